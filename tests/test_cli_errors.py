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


def test_an_output_below_a_file_names_the_file(small_library, tmp_path):
    (tmp_path / "notes.txt").write_text("mine")
    for command in (["render", small_library, "0", "1", "-o", tmp_path / "notes.txt" / "out.mp4"],
                    ["export", small_library, "0", "1", "-o", tmp_path / "notes.txt" / "edit"]):
        result = tvmedit(*command)
        assert result.returncode == 2 and "notes.txt is a file, not a folder" in result.stderr, result.stderr
        assert "Errno" not in result.stderr and (tmp_path / "notes.txt").read_text() == "mine"


def test_a_string_where_a_list_is_expected_is_refused_naming_the_type(small_library):
    from tvmedit.engine.errors import ParameterError

    library = Library.open(small_library)
    for call, says in ((lambda: library.edit("01"), "keys='01' should be a list"),
                       (lambda: library.edit([0, 1], durations="57"), "durations='57' should be a list"),
                       (lambda: library.wander(5, only="gym/01"), "only='gym/01' should be a list")):
        with pytest.raises(ParameterError, match=says):
            call()


def test_a_name_is_one_printable_line(small_library, tmp_path):
    import shutil

    copy = tmp_path / "copy.tvmlib"
    shutil.copytree(small_library, copy)
    for name in ("new\nname", "esc\x1b[31mred"):
        result = tvmedit("rename", copy, "0", name)
        assert result.returncode == 2 and "one line of printable characters" in result.stderr, result.stderr
    assert Library.open(copy).nodes[0].name == Library.open(small_library).nodes[0].name


def test_a_deeply_nested_corrections_file_is_one_sentence(small_library, tmp_path):
    deep = tmp_path / "deep.json"
    deep.write_text("[" * 100000 + "]" * 100000)
    result = tvmedit("correct", small_library, deep, "-o", tmp_path / "out.tvmlib")
    assert result.returncode == 2 and "deep.json is not valid JSON" in result.stderr
    assert "Traceback" not in result.stderr and not (tmp_path / "out.tvmlib").exists()


@pytest.mark.parametrize("command", ["play", "inspect"])
def test_seconds_must_be_a_positive_number(small_library, command):
    result = tvmedit(command, small_library, "--seconds", "nan")
    assert result.returncode == 2 and "--seconds" in result.stderr and "not 'nan'" in result.stderr


def test_a_long_path_says_a_looping_texton_once_with_its_count(small_library):
    result = tvmedit("path", small_library, "0", "1", "--loops", "3000")
    assert result.returncode == 0, result.stderr
    assert max(map(len, result.stdout.splitlines())) < 200 and "(x" in result.stdout
