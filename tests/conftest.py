"""Session-wide test data: generated once into a cache folder and reused.

Real motion comes from ``../shared`` (CMU takes turned into TVM by ``mocap2tvm.py``); where
that folder is absent, as on a user's machine, the tests that need it skip with a reason.
The cache lives in ``.cache/testdata`` (git-ignored), keyed by everything that shapes the
data, and a folder counts as complete only once its ``truth.json`` exists (both generators
write it last and atomically). ``make test`` runs the tests in several processes
(pytest-xdist): the first that needs a folder makes it while the others wait for it
(:func:`tvmedit.engine.safewrite.made_once`).
"""

import hashlib
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from tvmedit.engine.safewrite import made_once

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("TVMEDIT_SHARED", ROOT.parent / "shared"))
MOCAP2TVM = SHARED / "tools" / "mocap2tvm.py"
MOCAP_DATA = SHARED / "data" / "mocap6"
CACHE = Path(os.environ.get("TVMEDIT_TEST_CACHE", ROOT / ".cache" / "testdata"))


def _key(*parts):
    return hashlib.sha1(json.dumps(parts, sort_keys=True, default=str).encode()).hexdigest()[:12]


def needs_mocap():
    """Skip the calling test when the real-motion data of ``../shared`` is not there."""
    if not MOCAP2TVM.exists():
        pytest.skip(f"real-motion data not found at {SHARED} (set TVMEDIT_SHARED to the shared folder)")


def needs_hdm05():
    """Skip the calling test when the HDM05 clips of ``../shared`` are not there."""
    if not (SHARED / "data" / "hdm05").is_dir():
        pytest.skip(f"HDM05 data not found at {SHARED / 'data' / 'hdm05'} (set TVMEDIT_SHARED to the shared folder)")


def mocap_take(take, **options):
    """Folder of a CMU take turned into TVM (``mocap2tvm.py`` options as keyword arguments).

    Skips the calling test when ``../shared`` is not there.
    """
    needs_mocap()
    options = {"fps": 10, "seed": 0, **options}
    tool_hash = hashlib.sha1(MOCAP2TVM.read_bytes()).hexdigest()[:8]
    out = CACHE / f"mocap-{take}-{_key(take, options, tool_hash)}"
    cmd = [sys.executable, str(MOCAP2TVM), str(MOCAP_DATA / f"{take}.amc"), "--out", str(out),
           "--workers", "2", "--overwrite"]
    for name, value in options.items():
        flag = "--" + name.replace("_", "-")
        cmd += [flag] if value is True else [flag, str(value)]
    return made_once(out, "truth.json", lambda: subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL))


@pytest.fixture(scope="session")
def devsuite():
    """The parser's development suite, :mod:`tvmedit.engine.lab.devsuite` (its takes, sources and scorer)."""
    from tvmedit.engine.lab import devsuite

    return devsuite


@pytest.fixture(scope="session")
def take_13_30():
    """CMU 13_30 at 10 fps, whole take (205 frames, five exercises)."""
    return mocap_take("13_30")


def snippet_inputs(take):
    """Two sequences cut from one take: frames 0-59 and 100-159 (a build takes seconds)."""
    return [("gym", str(take / "frame_000[0-5]?.ply")), ("gym2", str(take / "frame_001[0-5]?.ply"))]


@pytest.fixture(scope="session")
def snippets_library(take_13_30, tmp_path_factory):
    """A library of :func:`snippet_inputs` of 13_30, built serially without the feature cache,
    once per test process (the store's tests share it; they must not modify it)."""
    import warnings

    from tvmedit import build

    with warnings.catch_warnings():  # short snippets rarely repeat a texton; the database says so
        warnings.filterwarnings("ignore", "no motion cluster repeats", UserWarning)
        return build(snippet_inputs(take_13_30), tmp_path_factory.mktemp("snippets") / "gym.lib", workers=1,
                     cache=False)


@pytest.fixture(scope="session")
def take_13_29():
    """CMU 13_29 at 10 fps, whole take (383 frames, six exercises)."""
    return mocap_take("13_29")


@pytest.fixture(scope="session")
def ctx():
    """The shared headless (EGL) OpenGL context; the test skips, saying why, where there is none."""
    from tvmedit.player.context import ContextError, shared_headless_context

    try:
        return shared_headless_context()
    except ContextError as error:
        pytest.skip(str(error))


def synth_take(preset, **options):
    """Folder of a take made by the synthetic actor (:func:`tvmedit.engine.lab.synth.generate` options)."""
    from tvmedit.engine.lab import synth

    options = {"fps": 10, "vertices": 16000, "seed": 0, **options}
    out = CACHE / f"synth-{preset}-{_key(preset, options, synth.VERSION)}"
    return made_once(out, "truth.json",
                lambda: synth.generate(out, preset=preset, workers=2, progress=False, overwrite=True, **options))


@pytest.fixture(scope="session")
def synth_walk():
    """Synthetic walk preset: about 100 frames at 10 fps, one motion, 16,000 vertices a frame."""
    return synth_take("walk")


@pytest.fixture(scope="session")
def synth_gym():
    """Synthetic gym preset at three cycles a motion and 4,000 vertices a frame: six exercises,
    313 frames at 10 fps (:func:`small_library`'s take). ``make demo``'s own take, the preset at
    its defaults (about 650 frames of 16,000 vertices), takes half a minute to make; the
    tests ask of the gym what either gives (truth, periods, the parse's targets, loops and
    transitions within a natural step)."""
    return synth_take("gym", cycles=3, vertices=4000)


def _engine_hash():
    digest = hashlib.sha1()
    for path in sorted((ROOT / "engine").rglob("*.py")):
        digest.update(path.read_bytes())
    return digest.hexdigest()[:10]


def built_library(name, take, **options):
    """A library of ``take`` (as sequence ``name``) built with ``engine.build`` options into the
    test cache, keyed by the take, the options and the engine's code. Tests must not modify it."""
    from tvmedit import engine

    out = CACHE / f"library-{name}-{take.name}-{_key(options)}-{_engine_hash()}"
    return made_once(out, "manifest.json", lambda: engine.build([(name, take)], out, workers=2, force=True, **options))


@pytest.fixture
def private_cache(tmp_path, monkeypatch):
    """Builds keep their feature cache in this test's own folder (``XDG_CACHE_HOME``): what one
    test caches never serves another, and a test of the cache sees only its own."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))


@pytest.fixture(scope="session")
def small_library(synth_gym):
    """A library of the synthetic actor: :func:`synth_gym`, the gym preset at three cycles a
    motion, 4,000 vertices.

    Built once into the test cache, keyed by the take and the engine's code. Tests must not
    modify it (copy it first, e.g. to rename motions).
    """
    from tvmedit import engine

    take = synth_gym
    out = CACHE / f"gym-library-{take.name}-{_engine_hash()}"
    return made_once(out, "manifest.json", lambda: engine.build([("gym", take)], out, workers=2, cache=False, force=True))


@pytest.fixture(scope="session")
def paper_library(small_library, synth_gym):
    """:func:`small_library` with the paper's graph (``connect="off"``): motions can be cut off."""
    from tvmedit import engine

    take = synth_gym
    out = CACHE / f"{small_library.name}-paper"
    return made_once(out, "manifest.json", lambda: engine.build([("gym", take)], out, workers=2, force=True, connect="off",
                                                                  smooth=False))
