"""A hostile user, sampled by hypothesis: random option values for every command, random byte
damage to frames and library files, signals at random moments.

The only outcomes allowed: success, or the package's one-sentence error with exit status 2 or
3 (argparse's usage error counts: exit 2, its own one line). Never a traceback, never a
temporary file or folder left behind, never a file of the user's removed or changed.

Commands run in this process (``tvmedit.cli.main``), so an example costs what the command
costs; signals need a child process and are sampled a few times only.
"""

import contextlib
import io
import json
import os
import shutil
import signal
from pathlib import Path

import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis.control import currently_in_test_context
from hypothesis import strategies as st

from tvmedit import Library
from interrupt import reachable_pair, run_signalled
from tvmedit.cli import main

pytestmark = pytest.mark.slow

#: Examples per sweep: the same ones on every run (about a minute in all), unless
#: TVMEDIT_HOSTILE_EXAMPLES asks for more, and new ones each time, to hunt.
EXAMPLES = int(os.environ.get("TVMEDIT_HOSTILE_EXAMPLES", "0"))
SWEEP = settings(max_examples=EXAMPLES or 60, deadline=None, derandomize=not EXAMPLES, database=None,
                 suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])

#: Values a careless or hostile user types for a number, a size or a name.
NUMBERS = ["0", "-1", "-5", "nan", "inf", "-inf", "1e-300", "1e300", "1e9", "abc", "", "0.5",
           "3", "1", "2.5", "1000000000"]
SIZES = ["0x0", "1x1", "1x100", "3x3", "x", "64", "-4x4", "64x48", "99999x2", "2x2"]
NAMES = ["", " ", "0", "99", "gym/01", "a/b", "ü", "x" * 300, "--force", "-1", "1e3"]


@pytest.fixture(scope="module")
def world(tmp_path_factory, small_library):
    """A copy of the small library, a short sequence of its frames, and user files beside them."""
    root = tmp_path_factory.mktemp("hostile")
    library = root / "gym.lib"
    shutil.copytree(small_library, library)
    frames = sorted(Path(Library.open(library).sequences[0].paths[0]).parent.glob("frame_*.ply"))
    sequence = root / "seq"
    sequence.mkdir()
    for path in frames[:12]:
        shutil.copy2(path, sequence / path.name)
    mine = root / "mine"
    mine.mkdir()
    (mine / "thesis.tex").write_text("chapter 1")
    (root / "notes.png").write_text("my notes")
    (root / "keep.mp4").write_bytes(b"\0\0\0\x18ftypisom" + b"mine" * 8)
    a, b, _ = reachable_pair(Library.open(library))
    return {"root": root, "library": library, "sequence": sequence, "a": str(a.id), "b": str(b.id)}


def _snapshot(root):
    """Every file of the user's (the inputs and their own files, not tvmedit's outputs) with its bytes."""
    return {p: p.read_bytes() for p in root.rglob("*") if p.is_file()
            and p.relative_to(root).parts[0] in ("seq", "mine", "notes.png", "keep.mp4")}


def run(argv):
    """``tvmedit ARGV`` in this process: (exit status, stderr)."""
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        try:
            status = main([str(a) for a in argv])
        except SystemExit as leave:
            status = leave.code
    if currently_in_test_context():  # the sweeps' statistics
        event(f"{argv[0]} exit {status}")
    return status, err.getvalue()


def assert_allowed(status, err, root, before):
    lines = [line for line in err.splitlines() if not line.startswith("warning: ")]
    assert "Traceback" not in err and "Exception ignored" not in err, err
    assert status in (0, 2, 3), (status, err)
    if status != 0:
        assert lines, "an error exit must say why"
        if lines[0].startswith("usage:"):
            assert ": error: " in lines[-1], err  # argparse: usage, then its own one line
        else:
            assert len(lines) == 1 and lines[0].startswith("error: ") and lines[0].endswith("."), err
    leftovers = [p for p in root.rglob(".*") if ".tmp-" in p.name or ".old-" in p.name]
    assert not leftovers, leftovers
    after = {p: p.read_bytes() for p in before if p.exists()}
    assert after == before, "a file of the user's was removed or changed"


def _options(pairs):
    """Options drawn from ``(flag, values)`` pairs: up to three, each with one value."""
    return st.lists(st.sampled_from(pairs), max_size=3, unique_by=lambda p: p[0]).flatmap(
        lambda chosen: st.tuples(*[st.sampled_from(values).map(lambda v, f=flag: [f, v])
                                   if values else st.just([flag]) for flag, values in chosen])
        if chosen else st.just(()))


def _outputs(world, suffix=""):
    root = world["root"]
    return st.sampled_from([root / f"out{suffix}", root / "mine", root / "notes.png", root / "keep.mp4",
                            world["library"] / f"inside{suffix}", world["sequence"] / f"o{suffix}",
                            root / "new" / "deep" / f"o{suffix}", root])


BUILD = [("--fps", NUMBERS), ("--bin-r", NUMBERS), ("--bin-theta", NUMBERS), ("--bin-phi", NUMBERS),
         ("--mu", NUMBERS), ("--workers", ["0", "1", "-3", "2", "100000", "x"]),
         ("--analysis-fps", NUMBERS), ("--min-cluster", NUMBERS), ("--novelty-window", NUMBERS),
         ("--min-texton", NUMBERS), ("--window-fps", NUMBERS), ("--period-tolerance", NUMBERS),
         ("--max-period", NUMBERS), ("--twin-peak", NUMBERS), ("--beta", NUMBERS),
         ("--max-transition", NUMBERS), ("--onset-reach", NUMBERS),
         ("--method", ["paper", "energy", "x", ""]), ("--window-taps", ["1", "nan", "-1", "0"]),
         ("--blend-frames", ["0", "1", "8", "9", "-1", "x", "1e9"])]


@SWEEP
@given(data=st.data())
def test_build_and_check_with_random_options(world, data):
    root = world["root"]
    out = data.draw(_outputs(world))
    options = [v for pair in data.draw(_options(BUILD)) for v in pair]
    flags = data.draw(st.lists(st.sampled_from(["--force", "--skip-bad-frames", "--no-cache"]),
                               unique=True, max_size=2))
    before = _snapshot(root)
    status, err = run(["build", world["sequence"], "-o", out, "-q", "--workers", "1", *flags, *options])
    assert_allowed(status, err, root, before)
    fps = [v for pair in data.draw(_options([("--fps", NUMBERS)])) for v in pair]
    assert_allowed(*run(["check", world["sequence"], *fps]), root, before)
    if status == 0 and out == root / "out":
        shutil.rmtree(out)


EDIT = [("--loops", NUMBERS), ("--forbid", NAMES), ("--strict", []),
        ("--durations", ["2,3", "0.1,0.2", "nan,1", "1", ",", "-1,2", "x", "30,", "0,0"]),
        ("--at", ["0,2,5", "1,2,3", "0,-1", "", "0,inf,2"]),
        ("--hold", ["gym/01=1", "x=1", "=", "gym/01=nan", "gym/02=1e9", "0=0.5"])]
RENDER = [("--size", SIZES), ("--fps", NUMBERS), ("--orbit", NUMBERS), ("--loops", ["1", "0", "x", "1e9"]),
          ("--camera", ["0,0,0", "nan,0,0", "1,2", "-90,10,-1", "1e300,0,0"]), ("--node", NAMES)]


@SWEEP
@given(data=st.data())
def test_edit_commands_with_random_options(world, data):
    root, library = world["root"], world["library"]
    keys = data.draw(st.lists(st.sampled_from([world["a"], world["b"], *NAMES]), min_size=2, max_size=3))
    before = _snapshot(root)
    command = data.draw(st.sampled_from(["path", "export", "render", "info", "rename"]))
    if command == "path":
        argv = ["path", library, *keys, *[v for p in data.draw(_options(EDIT)) for v in p]]
    elif command == "export":
        argv = ["export", library, *keys, "-o", data.draw(_outputs(world)), "-q",
                *[v for p in data.draw(_options(EDIT + [("--force", [])])) for v in p]]
    elif command == "render":
        suffix = data.draw(st.sampled_from([".gif", ".mp4", ".png", "", ".txt"]))
        argv = ["render", library, *keys, "-o", data.draw(_outputs(world, suffix)), "-q",
                "--size", "32x24", *[v for p in data.draw(_options(RENDER)) for v in p]]
        argv += data.draw(st.sampled_from([[], ["--force"]]))
    elif command == "info":
        argv = ["info", data.draw(st.sampled_from([library, world["sequence"], root / "mine", root / "x"]))]
    else:
        argv = ["rename", library, keys[0], data.draw(st.sampled_from(NAMES))]
    status, err = run(argv)
    assert_allowed(status, err, root, before)
    Library.open(library)  # whole, whatever the command did to it
    for made in (root / "out", root / "out.gif", root / "out.mp4", root / "new"):
        if made.is_dir():
            shutil.rmtree(made)
        elif made.exists():
            made.unlink()


FRAMES = [-5, 0, 3, 40, 120, 10 ** 9, 1.5, "x", None, [1, 2]]


@contextlib.contextmanager
def _without_display():
    """This process's environment without a display, as on the CI machine, for one command."""
    saved = {k: os.environ.pop(k) for k in ("DISPLAY", "WAYLAND_DISPLAY") if k in os.environ}
    try:
        yield
    finally:
        os.environ.update(saved)


def _corrections(frames=st.sampled_from(FRAMES)):
    """A corrections.json as a careless user writes one: any entry may be wrong."""
    ops = st.fixed_dictionaries({}, optional={"add": st.lists(frames, max_size=2),
                                             "remove": st.lists(frames, max_size=2),
                                             "move": st.lists(st.lists(frames, min_size=1, max_size=3), max_size=2)})
    entry = st.fixed_dictionaries({}, optional={"boundaries": ops, "textons": ops,
                                                "representatives": st.lists(frames, max_size=2),
                                                "drop": st.lists(st.sampled_from(NAMES), max_size=2),
                                                "colour": st.just("red")})
    return st.one_of(st.fixed_dictionaries({"sequences": st.dictionaries(st.sampled_from(["gym", "x", ""]), entry,
                                                                          max_size=2)}),
                     st.sampled_from([[], "gym", {"sequences": []}, {"x": 1}]))


@settings(SWEEP, max_examples=max(EXAMPLES // 3, 15))
@given(data=st.data())
def test_correct_and_inspect_with_random_input(world, data):
    root = world["root"]
    file = root / "corrections.json"
    if data.draw(st.booleans()):
        file.write_text(json.dumps(data.draw(_corrections())))
    else:
        file.write_bytes(data.draw(st.sampled_from([b"", b"{", b"\xff\xfe", b"null", b'{"sequences": {"gym": 5}}'])))
    before = _snapshot(root)
    assert_allowed(*run(["correct", world["library"], file, "-o", root / "out", "--force"]), root, before)
    # no display here: bad options are still said first, then the missing display, in one sentence
    options = [v for p in data.draw(_options([("--frame", NUMBERS), ("--sequence", ["gym", "x", ""]),
                                                ("--seconds", NUMBERS), ("--size", SIZES),
                                                ("--corrections", [file, root / "none.json"])])) for v in p]
    with _without_display():
        assert_allowed(*run(["inspect", world["library"], *options]), root, before)
    Library.open(world["library"])
    if (root / "out").exists():
        shutil.rmtree(root / "out")


SYNTH = [("--cycles", NUMBERS), ("--fps", NUMBERS), ("--vertices", ["0", "999", "2000", "1e9", "x", "-1"]),
         ("--seed", NUMBERS), ("--workers", ["0", "1", "-1", "x"]), ("--motions", ["squats", "", "yoga", ",,"]),
         ("--preset", ["walk", "gym", "x"])]


@settings(SWEEP, max_examples=max(EXAMPLES // 2, 20))
@given(data=st.data())
def test_synth_with_random_options(world, data):
    root = world["root"]
    options = dict(data.draw(_options(SYNTH)))
    # A short take unless the example asks otherwise: what matters is refusing bad values.
    base = {"--motions": "squats", "--cycles": "1", "--fps": "2", "--vertices": "2000", "--workers": "1"}
    if "--preset" in options:
        base.pop("--motions")
    argv = ["synth", "--out", data.draw(_outputs(world)), "-q",
            *[v for flag, value in {**base, **options}.items() for v in (flag, value)]]
    argv += data.draw(st.sampled_from([[], ["--overwrite"]]))
    before = _snapshot(root)
    assert_allowed(*run(argv), root, before)
    if (root / "out").exists():
        shutil.rmtree(root / "out")


def _library_files(library):
    """Every file of ``library``: the sweep damages any of them, the marker included."""
    return sorted(p.name for p in Path(library).iterdir() if p.is_file())


def _copy(tmp_path_factory, folder, name):
    """A fresh folder holding a copy of ``folder`` called ``name``: (root, copy)."""
    root = tmp_path_factory.mktemp("hostile-copy")
    shutil.copytree(folder, root / name)
    return root, root / name


def damage(data, path):
    """Truncate, overwrite bytes in place (same size) or append garbage to ``path``."""
    blob = bytearray(path.read_bytes()) if path.exists() else bytearray()
    how = data.draw(st.sampled_from(["truncate", "same-size", "append"]))
    if how == "truncate":
        blob = blob[:data.draw(st.integers(0, max(0, len(blob) - 1)))]
    elif how == "same-size" and blob:
        for _ in range(data.draw(st.integers(1, 8))):
            # Headers are where damage matters most: half the writes land in the first 256 bytes.
            end = data.draw(st.sampled_from([min(256, len(blob)), len(blob)]))
            blob[data.draw(st.integers(0, end - 1))] = data.draw(st.integers(0, 255))
    else:
        blob += data.draw(st.binary(min_size=1, max_size=64))
    path.write_bytes(bytes(blob))


@SWEEP
@given(data=st.data())
def test_damaged_library_files(world, data, tmp_path_factory):
    root, library = _copy(tmp_path_factory, world["library"], "gym.lib")
    damage(data, library / data.draw(st.sampled_from(_library_files(library))))
    argv = data.draw(st.sampled_from([
        ["info", library, "--json"], ["path", library, world["a"], world["b"]],
        ["export", library, world["a"], world["b"], "-o", root / "edit", "-q"],
        ["render", library, world["a"], world["b"], "-o", root / "edit.gif", "--size", "32x24", "-q"],
        ["rename", library, world["a"], "renamed"],
        ["build", world["sequence"], "-o", library, "--force", "-q", "--workers", "1"]]))
    status, err = run(argv)
    assert_allowed(status, err, root, {})


def test_the_advice_for_a_garbled_manifest_and_marker_is_taken(world, tmp_path_factory):
    # Both files a library is known by, garbled: the advice says build --force, and build
    # --force takes it (the folder holds nothing but the files a build writes).
    root, library = _copy(tmp_path_factory, world["library"], "gym.lib")
    (library / "manifest.json").write_text("garbage{")
    (library / ".tvmedit").write_bytes(b"\x00\xff not json")
    status, err = run(["info", library])
    assert status == 2 and "--force" in err
    status, err = run(["build", world["sequence"], "-o", library, "--force", "-q", "--workers", "1"])
    assert status == 0, err
    assert run(["info", library])[0] == 0


@SWEEP
@given(data=st.data())
def test_damaged_frames(world, data, tmp_path_factory):
    root, sequence = _copy(tmp_path_factory, world["sequence"], "seq")
    for _ in range(data.draw(st.integers(1, 2))):
        damage(data, data.draw(st.sampled_from(sorted(sequence.glob("*.ply")))))
    skip = data.draw(st.sampled_from([[], ["--skip-bad-frames"]]))
    before = _snapshot(root)
    assert_allowed(*run(["check", sequence, *skip]), root, before)
    # Without display-rate in-betweens (two thirds of a build of twelve frames): the damaged
    # frames reach them only through the stages before, which blend the same frames.
    status, err = run(["build", sequence, "-o", root / "lib", "-q", "--workers", "1", "--no-cache", "--no-smooth",
                       *skip])
    assert_allowed(status, err, root, before)
    assert status == 0 or not (root / "lib").exists()


#: Points inside the commands where a signal lands: (command, module:function, calls before it).
MOMENTS = [("build", "tvmedit.engine.store.featurecache:stat_list", 1), ("build", "tvmedit.engine.store.layout:link_meshes", 1),
           ("build", "tvmedit.engine.store.inbetweens:blend_library", 1),
           ("build", "tvmedit.engine.store.layout:write_manifest", 1), ("build", "tvmedit.engine.safewrite:mark", 1),
           ("export", "tvmedit.engine.graph.export:write_ply", 3), ("export", "tvmedit.engine.safewrite:mark", 1),
           ("render", "tvmedit.player.headless:_draw", 2), ("rename", "tvmedit.engine.safewrite:write_text", 1)]


@settings(SWEEP, max_examples=max(EXAMPLES // 10, 8))
@given(moment=st.sampled_from(MOMENTS), signum=st.sampled_from([signal.SIGINT, signal.SIGTERM]))
def test_signals_at_random_moments(world, moment, signum, tmp_path_factory):
    root, library = _copy(tmp_path_factory, world["library"], "gym.lib")
    command, at, after = moment
    argv = {"build": ["build", world["sequence"], "-o", library, "--force", "-q", "--workers", "1"],
            "export": ["export", library, world["a"], world["b"], "-o", root / "edit", "-q"],
            "render": ["render", library, world["a"], world["b"], "-o", root / "e.gif", "--size", "32x24", "-q"],
            "rename": ["rename", library, world["a"], "renamed"]}[command]
    result = run_signalled(argv, at=at, signum=signum, after=after,
                           env={**os.environ, "XDG_CACHE_HOME": str(root / "cache")})
    assert "Traceback" not in result.stderr, result.stderr
    assert result.returncode in (0, 130, 128 + signal.SIGTERM), result.stderr
    if result.returncode == 130:
        assert result.stderr.strip().splitlines()[-1] == "interrupted"
    leftovers = [p for p in root.rglob(".*") if ".tmp-" in p.name or ".old-" in p.name]
    assert not leftovers, leftovers
    Library.open(library)  # the library is whole: the old one or the new one
    assert not (root / "edit").exists() or (root / "edit" / "edit.json").exists()
