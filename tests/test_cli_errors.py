"""What the command line does when things go wrong: a signal, a closed pipe, a bad path, -q."""

import signal
import subprocess
import sys

import pytest

from tvmedit import Library
from interrupt import reachable_pair as _reachable_pair
from interrupt import run_signalled, tvmedit


def _pair(library):
    a, b, _ = _reachable_pair(library)
    return a.name, b.name


def test_sigterm_during_export_leaves_nothing_behind(small_library, tmp_path):
    a, b = _pair(Library.open(small_library))
    out = tmp_path / "edited"
    # SIGTERM arrives after the fifth frame file is written.
    result = run_signalled(["export", small_library, a, b, "--loops", "3", "-o", out, "-q"],
                           at="tvmedit.engine.graph.export:write_ply", after=5, signum=signal.SIGTERM)
    assert result.returncode == 128 + signal.SIGTERM, result.stderr
    assert "Traceback" not in result.stderr
    assert list(tmp_path.iterdir()) == []  # neither the export nor its temporary folder


def test_a_closed_pipe_is_not_an_error(small_library):
    a, b = _pair(Library.open(small_library))
    result = subprocess.run(f"{sys.executable} -m tvmedit path {small_library} {a} {b} --loops 300 | head -c 20",
                            shell=True, capture_output=True, text=True)
    assert "Traceback" not in result.stderr and "BrokenPipe" not in result.stderr


def test_an_unusable_output_path_is_one_sentence(small_library, tmp_path):
    a, b = _pair(Library.open(small_library))
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    result = tvmedit("export", small_library, a, b, "-o", blocker / "edited")
    assert result.returncode == 2 and result.stderr.startswith("error: ")
    assert "Traceback" not in result.stderr and result.stderr.count("\n") == 1


@pytest.mark.parametrize("option", [["--loops", "0"], ["--fps", "0"], ["--camera", "nan,0,0"],
                                    ["--size", "40000x40000"], ["--orbit", "inf"]])
def test_bad_numbers_are_refused_before_any_work(small_library, tmp_path, option):
    result = tvmedit("render", small_library, "0", "1", "-o", tmp_path / "out.mp4", *option)
    assert result.returncode == 2 and option[0] in result.stderr and "Traceback" not in result.stderr
    assert list(tmp_path.iterdir()) == []


def test_quiet_build_still_warns_about_skipped_frames(synth_walk, tmp_path):
    frames = tmp_path / "walk"
    frames.mkdir()
    for path in sorted(synth_walk.glob("frame_*.ply"))[:40]:
        (frames / path.name).symlink_to(path)
    (frames / "frame_00041.ply").write_bytes(b"ply\ntruncated")
    result = tvmedit("build", frames, "-o", tmp_path / "walk.tvmlib", "--skip-bad-frames", "-q",
                     "--workers", "1", "--no-cache")
    assert result.returncode == 0, result.stderr
    assert "skipped 1 bad frame" in result.stderr and "frame_00041.ply" in result.stderr
    assert "built" not in result.stderr  # the summary is what -q leaves out
