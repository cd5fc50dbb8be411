"""Ctrl-C or SIGTERM at a random time of every command that writes: the outcome is the old
state or the complete new one, never part of a new one; no worker left, no traceback.

Each example runs the command in a child process, as a user does, and signals its process
group (what a terminal's Ctrl-C does) after a time drawn over the length of an uninterrupted
run of the same command, so interrupts land while Python starts, while frames are read or
written, and while the result is put in place (a signal that lands while Python itself starts,
before tvmedit's first line, is Python's: it says so in its own words). Three examples a
command on every run (the same ones); ``TVMEDIT_INTERRUPT_EXAMPLES=N`` draws N new ones a
command, to hunt.
"""

import hashlib
import json
import os
import re
import shutil
import signal
import time
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from interrupt import reachable_pair, run_interrupted
from tvmedit import Library

pytestmark = pytest.mark.slow

EXAMPLES = int(os.environ.get("TVMEDIT_INTERRUPT_EXAMPLES", "0"))
SWEEP = settings(max_examples=EXAMPLES or 3, deadline=None, derandomize=not EXAMPLES, database=None,
                 suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
COMMANDS = ["synth", "build", "correct", "export", "export-obj", "export-scvv", "export-glb", "render", "report"]


@pytest.fixture(scope="module")
def world(tmp_path_factory, small_library):
    """The small library, twelve of its frames, a correction, an older take, and how long each
    command takes uninterrupted."""
    root = tmp_path_factory.mktemp("interrupt-world")
    library = Library.open(small_library)
    sequence = root / "seq"
    sequence.mkdir()
    for path in sorted(Path(library.sequences[0].paths[0]).parent.glob("frame_*.ply"))[:12]:
        shutil.copy2(path, sequence / path.name)
    fix = root / "fix.json"
    fix.write_text(json.dumps({"sequences": {library.sequences[0].name: {"drop": [library.nodes[-1].name]}}}))
    a, b, _ = reachable_pair(library)
    older = root / "older-take"
    run_interrupted(["synth", "--preset", "walk", "--vertices", "1500", "--seed", "1", "--out", older, "-q", "--workers", "2"])
    world = {"root": root, "library": Path(small_library), "sequence": sequence, "fix": fix, "a": a.id, "b": b.id,
             "older": older, "seconds": {}}
    for command in COMMANDS:
        place = tmp_path_factory.mktemp(f"whole-{command}")
        start = time.monotonic()
        result = run_interrupted(_argv(world, command, _prepare(world, command, place)))
        assert result.returncode == 0, result.stderr
        world["seconds"][command] = time.monotonic() - start
        world[f"whole-{command}"] = _state(command, place / "out")
        shutil.rmtree(place)    # only its digest is needed; the disk is not endless
    return world


def _prepare(world, command, place):
    """What ``command`` replaces, put at ``place / "out"`` (nothing where it writes anew)."""
    if command == "synth":
        shutil.copytree(world["older"], place / "out")
    elif command in ("build", "correct"):
        shutil.copytree(world["library"], place / "out")
    return place


def _argv(world, command, place):
    out = place / "out"
    return {"synth": ["synth", "--preset", "walk", "--vertices", "1500", "--out", out, "--overwrite", "-q",
                      "--workers", "2"],
            "build": ["build", world["sequence"], "-o", out, "--force", "-q", "--workers", "2", "--no-cache"],
            "correct": ["correct", out, world["fix"]],
            "export": ["export", world["library"], world["a"], world["b"], "-o", out, "-q"],
            # every frame encoded, on worker processes
            "export-obj": ["export", world["library"], world["a"], world["b"], "-o", out, "-q", "--format", "obj"],
            # every frame encoded, on threads
            "export-scvv": ["export", world["library"], world["a"], world["b"], "-o", out, "-q", "--format", "scvv"],
            "export-glb": ["export", world["library"], world["a"], world["b"], "-o", out, "-q", "--format", "glb"],
            "render": ["render", world["library"], world["a"], world["b"], "-o", out.with_suffix(".gif"), "--size",
                       "64x48", "-q"],
            "report": ["report", world["library"], "-o", out, "-q"]}[command]


def _state(command, out):
    """A digest of what a user finds at ``out``: its files' names and bytes ("nothing" where
    there is nothing). A library is checked whole and read back, without the build's timings."""
    if command == "render":
        out = out.with_suffix(".gif")
    if not out.exists():
        return "nothing"
    digest = hashlib.sha1()
    if command == "render":
        digest.update(out.read_bytes())
    elif command in ("build", "correct"):
        library = Library.open(out)
        library.verify()
        digest.update(repr((library.stored_frames(), [(n.start, n.end) for n in library.nodes],
                            sorted(library.graph.edges))).encode())
    else:
        for path in sorted(out.rglob("*")):
            if path.is_file():
                digest.update(str(path.relative_to(out)).encode() + path.read_bytes())
    return digest.hexdigest()


def _before_tvmedit(stderr):
    """Whether ``stderr`` is Python's own word on a signal that landed before tvmedit's first
    line: a fatal error in its start (init_import_site, init_sys_streams...), or Ctrl-C while
    ``python -m`` was still finding the module (a traceback of Python's frozen runpy and
    importlib frames alone, none of them running the module's code)."""
    if stderr.startswith("Fatal Python error: init_"):
        return True
    frames = re.findall(r'File "([^"]+)"', stderr)
    return (stderr.startswith("Traceback") and stderr.rstrip().endswith("KeyboardInterrupt") and bool(frames)
            and all(frame.startswith("<frozen ") for frame in frames) and "in _run_code" not in stderr)


@pytest.mark.parametrize("command", COMMANDS)
@SWEEP
@given(fraction=st.floats(0.0, 1.0), signum=st.sampled_from([signal.SIGINT, signal.SIGTERM]))
def test_an_interrupt_at_any_time_leaves_the_old_state_or_the_new(world, command, fraction, signum,
                                                                   tmp_path_factory):
    place = _prepare(world, command, tmp_path_factory.mktemp(command))
    old = _state(command, place / "out")
    result = run_interrupted(_argv(world, command, place), signum, after=fraction * world["seconds"][command])
    if _before_tvmedit(result.stderr):
        shutil.rmtree(place)
        return      # the signal landed in Python's own start, before any line of tvmedit ran
    assert "Traceback" not in result.stderr and "Exception" not in result.stderr, result.stderr
    # Before Python has set its handlers the signal ends the process itself (a shell shows 130 or 143).
    assert result.returncode in (0, 130, 128 + signal.SIGTERM, -signal.SIGINT, -signal.SIGTERM), result.stderr
    assert _state(command, place / "out") in (old, world[f"whole-{command}"])
    leftovers = [p.name for p in place.rglob(".*") if ".tmp-" in p.name or ".old-" in p.name]
    assert not leftovers, leftovers
    shutil.rmtree(place)    # a passing example's copy goes at once (a failing one's stays)
