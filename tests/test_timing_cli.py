"""Edits of a given length from the command line: --durations, --at, --hold, --strict."""

import itertools
import json
import warnings

import imageio.v2 as iio2
import pytest

from tvmedit import Library
from interrupt import tvmedit


def _keys_that_fit(library, durations):
    """Three key motions whose legs some schedule makes last ``durations`` (no warning)."""
    for a, b, c in itertools.permutations(library.nodes, 3):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            try:
                library.edit([a.id, b.id, c.id], durations=durations)
            except UserWarning:
                continue
        return [a.name, b.name, c.name]
    pytest.skip(f"no three motions of the test library make legs of {durations} s")


def test_durations_place_the_key_motions_in_the_export_and_the_video(small_library, tmp_path, ctx):
    library = Library.open(small_library)
    assert library.sequences[0].fps == 10
    keys = _keys_that_fit(library, [5, 7])
    result = tvmedit("export", small_library, *keys, "--durations", "5,7", "-o", tmp_path / "out", "-q")
    assert result.returncode == 0, result.stderr
    assert "warning" not in result.stderr
    record = json.loads((tmp_path / "out" / "edit.json").read_text())
    second, third = record["key_starts"][1:]
    assert abs(second - 50) <= 1 and abs(third - 120) <= 1
    ids = [library.node(key).id for key in keys]
    frames = record["frames"]
    # The key motion begins there: its frame, after the motion before or the in-between
    # frames of the transition into it (tvmedit.engine.inbetween.blend).
    for start, key, before in ((second, ids[1], ids[0]), (third, ids[2], ids[1])):
        assert frames[start]["node"] == key and "blend" not in frames[start]
        assert frames[start - 1]["node"] != key or "blend" in frames[start - 1]
    assert [leg["asked_s"] for leg in record["legs"]] == [5, 7]
    assert [round(leg["achieved_s"] * 10) for leg in record["legs"]] == [second, third - second]

    video = tmp_path / "out.mp4"
    result = tvmedit("render", small_library, *keys, "--durations", "5,7", "-o", video, "--size", "96x72", "-q")
    assert result.returncode == 0, result.stderr
    with iio2.get_reader(video) as reader:
        assert reader.count_frames() == len(frames)


def test_an_impossible_duration_warns_once_and_strict_exits_3(small_library):
    library = Library.open(small_library)
    keys = _keys_that_fit(library, [5, 7])
    shortest = library.edit(keys).legs[0].frames / 10
    result = tvmedit("path", small_library, *keys, "--durations", "0.1,12", "--json")
    assert result.returncode == 0, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("warning: leg 1 ")
    assert "0.1 s" in lines[0] and f"{shortest:g} s" in lines[0] and keys[0] in lines[0]
    legs = json.loads(result.stdout)["legs"]
    assert legs[0]["asked_s"] == 0.1 and legs[0]["achieved_s"] == pytest.approx(shortest)

    strict = tvmedit("path", small_library, *keys, "--durations", "0.1,12", "--strict")
    assert strict.returncode == 3 and strict.stdout == ""
    assert strict.stderr.count("\n") == 1 and strict.stderr.startswith("error: leg 1 ")
    assert "Traceback" not in strict.stderr


def test_a_missed_leg_after_a_hold_is_named_as_the_user_numbers_it(small_library):
    keys = _keys_that_fit(Library.open(small_library), [5, 7])[:2]
    result = tvmedit("path", small_library, *keys, "--durations", "1.1", "--hold", f"{keys[0]}=1")
    lines = result.stderr.strip().splitlines()
    assert result.returncode == 0 and len(lines) == 1, result.stderr
    # one leg asked for 1.1 s, a hold of 1 s in it: leg 1, not "leg 2"
    assert lines[0].startswith("warning: leg 1 ") and "after its hold (1.1 s in all)" in lines[0]


def test_at_is_durations_from_zero_and_a_hold_loops_the_motion(small_library):
    library = Library.open(small_library)
    keys = _keys_that_fit(library, [5, 7])
    by_durations = tvmedit("path", small_library, *keys, "--durations", "5,7", "--json")
    by_times = tvmedit("path", small_library, *keys, "--at", "0,5,12", "--json")
    assert by_durations.returncode == by_times.returncode == 0
    assert json.loads(by_durations.stdout)["schedule"] == json.loads(by_times.stdout)["schedule"]
    # An empty item leaves its leg as short as it plays; the next leg's time counts from its end.
    free = json.loads(tvmedit("path", small_library, *keys, "--durations", ",7", "--json").stdout)
    assert free["key_starts"][1] == library.edit(keys).starts[1] and free["legs"][0]["asked_s"] is None
    assert free["legs"][1]["asked_s"] == 7 and free["legs"][1]["goal_frames"] == 70

    # A hold of whole cycles leaves the motion where it was: the leg after it is made as before.
    motion = library.node(keys[1])
    cycles = 3 * (motion.end - motion.start + 1)
    held = tvmedit("path", small_library, *keys, "--at", f"0,5,{12 + cycles / 10:g}",
                   "--hold", f"{keys[1]}={cycles / 10:g}", "--json")
    assert held.returncode == 0 and held.stderr == ""
    data = json.loads(held.stdout)
    starts = data["key_starts"]
    assert abs(starts[1] - 50) <= 1 and starts[2] - starts[1] == cycles and abs(starts[3] - 120 - cycles) <= 1
    hold = data["legs"][1]
    assert hold["path"] == [motion.id] and hold["frames"] == cycles
    assert {e["node"] for e in data["schedule"][starts[1]:starts[2]]} == {motion.id}


@pytest.mark.parametrize("options, says", [
    (["--durations", "5"], "--durations has 1 value"),
    (["--at", "1,5,12"], "--at starts at 1"),
    (["--at", "0,5,3"], "--at goes back in time"),
    (["--durations", "5,-1"], "--durations"),
    (["--durations", "5,nan"], "--durations"),
    (["--hold", "nosuch=2"], "--hold nosuch"),
    (["--hold", "3"], "--hold"),
    (["--durations", "5,7", "--at", "0,5,12"], "not allowed with"),
])
def test_bad_lengths_are_refused_at_the_door(small_library, options, says):
    keys = [node.name for node in Library.open(small_library).nodes[:3]]
    result = tvmedit("path", small_library, *keys, *options)
    assert result.returncode == 2 and says in result.stderr and "Traceback" not in result.stderr


def test_the_shot_list_example_exports_what_it_prints(small_library, tmp_path):
    import subprocess
    import sys

    from conftest import ROOT

    result = subprocess.run([sys.executable, str(ROOT / "examples" / "shot_list.py"), str(small_library)],
                            capture_output=True, text=True, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    starts = json.loads(result.stdout.split("begin at frames ")[1].split(";")[0])
    record = json.loads((tmp_path / "shot_list" / "edit.json").read_text())
    assert record["key_starts"] == starts and len(starts) == 4
    assert starts[3] - starts[2] == 30                    # the 3 s hold of the last motion
    assert abs(starts[2] - 140) <= 1 or "note: leg" in result.stdout
