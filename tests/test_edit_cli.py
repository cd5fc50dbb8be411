"""Edits from the command line and from Python: path, export, and the example scripts."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from tvmedit import Library, NoPath
from tvmedit.engine.capture.load import load_sequence
from interrupt import reachable_pair as _reachable_pair
from interrupt import refused, tvmedit

ROOT = Path(__file__).resolve().parents[1]

def _unreachable_pair(library):
    for a in library.nodes:
        for b in library.nodes:
            if a.id != b.id:
                try:
                    library.edit([a.id, b.id])
                except NoPath:
                    return a, b
    return None

def test_path_json_is_the_edit_with_info_ids(small_library):
    library = Library.open(small_library)
    a, b, edit = _reachable_pair(library)
    result = tvmedit("path", small_library, a.name, b.name, "--json")
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    info_ids = {node["id"] for node in library.info()["nodes"]}
    assert [leg["path"] for leg in data["legs"]] == [list(leg.path) for leg in edit.legs]
    assert set(data["legs"][0]) >= {"from", "to", "path", "cost", "edges"}
    assert data["legs"][0]["from"] == a.id and data["legs"][0]["to"] == b.id
    assert {entry["node"] for entry in data["schedule"]} <= info_ids
    assert [(e["sequence"], e["frame"]) for e in data["schedule"]] == [(e.sequence, e.frame) for e in edit.schedule]

def test_path_prints_legs_and_schedule(small_library):
    library = Library.open(small_library)
    a, b, edit = _reachable_pair(library)
    result = tvmedit("path", small_library, a.id, b.id, "--loops", "2")
    assert result.returncode == 0, result.stderr
    assert f"{a.name} -> {b.name}:" in result.stdout
    assert f"schedule: {len(library.edit([a.id, b.id], loops=2).schedule)} frames" in result.stdout

def test_unknown_motion_lists_the_known_names(small_library):
    library = Library.open(small_library)
    result = tvmedit("path", small_library, library.nodes[0].name, "no-such-motion")
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert "no-such-motion" in result.stderr
    assert all(node.name in result.stderr for node in library.nodes)

def test_every_pair_is_reachable_by_default(small_library):
    assert _unreachable_pair(Library.open(small_library)) is None

def test_unreachable_pair_exits_3_naming_the_mu_that_connects(paper_library):
    library = Library.open(paper_library)
    pair = _unreachable_pair(library)
    assert pair is not None, "the paper's graph of the gym take should cut a motion off (issue 12)"
    a, b = pair
    result = tvmedit("path", paper_library, a.name, b.name)
    assert result.returncode == 3
    assert a.name in result.stderr and b.name in result.stderr and "mu" in result.stderr
    assert result.stderr.count("\n") == 1

def test_forbid_is_repeatable_and_forbidden_motions_are_never_used(small_library, capsys):
    # Every pair through the command's own entry, in this process: a child process a pair
    # spent 33 s starting Python 30 times. The other tests here run the command as a child.
    from tvmedit.cli import main

    library = Library.open(small_library)
    names = [n.name for n in library.nodes]
    checked = 0
    for a in names:
        for b in names:
            if a == b or refused(library, a, b):
                continue
            checked += 1
            others = [n for n in names if n not in (a, b)]
            status = main(["path", str(small_library), a, b, "--json", "--forbid", *others[:1],
                           "--forbid", *others[1:]])
            out, err = capsys.readouterr()
            if status == 0:
                path = json.loads(out)["legs"][0]["path"]
                assert path == [library.node(a).id, library.node(b).id]
            else:
                assert status == 3 and "forbidden" in err
    assert checked

def test_export_round_trip_frames_colours_and_edit_json(small_library, tmp_path):
    library = Library.open(small_library)
    a, b, edit = _reachable_pair(library)
    out = tmp_path / "edited"
    result = tvmedit("export", small_library, a.name, b.name, "-o", out, "-q")
    assert result.returncode == 0, result.stderr
    record = json.loads((out / "edit.json").read_text())
    assert [(f["sequence"], f["frame"]) for f in record["frames"]] == [(e.sequence, e.frame) for e in edit.schedule]
    assert [(t["from"], t["to"]) for t in record["transitions"]] == [(t.source, t.target) for t in edit.transitions]
    assert all(t["weight"] > 0 for t in record["transitions"])
    exported = load_sequence(out)
    assert len(exported.frames) == len(edit.schedule)
    for entry, frame in zip(edit.schedule[::7], exported.frames[::7]):
        positions, colours, faces, _ = library.frame_mesh((entry.sequence, entry.frame))
        np.testing.assert_array_equal(frame.positions, positions)
        np.testing.assert_array_equal(frame.colours, colours)
        np.testing.assert_array_equal(frame.faces, faces)
    again = tvmedit("export", small_library, a.name, b.name, "-o", out, "-q")
    assert again.returncode == 2 and "--force" in again.stderr

@pytest.mark.parametrize("script", ["there_and_back.py", "tour.py", "forbidden.py"])
def test_example_scripts_run(small_library, tmp_path, script):
    result = subprocess.run([sys.executable, str(ROOT / "examples" / script), str(small_library)],
                            capture_output=True, text=True, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip()
    if script == "there_and_back.py":
        import imageio.v2 as iio2
        frames = int(result.stdout.split(" frames;")[0].split()[-1])
        with iio2.get_reader(tmp_path / "there_and_back.mp4") as reader:
            assert reader.count_frames() == frames
    if script == "tour.py":
        tour = result.stdout.splitlines()[0].removeprefix("tour: ").split(" -> ")
        assert len(tour) >= 2
        assert len(load_sequence(tmp_path / "tour").frames) == int(result.stdout.split("exported ")[1].split()[0])

def test_export_force_replaces_only_a_previous_export(small_library, tmp_path):
    library = Library.open(small_library)
    a, b, edit = _reachable_pair(library)
    out = tmp_path / "edited"
    assert tvmedit("export", small_library, a.name, b.name, "-o", out, "-q").returncode == 0
    again = tvmedit("export", small_library, a.name, b.name, "-o", out, "-q", "--force")
    assert again.returncode == 0, again.stderr
    assert len(list(out.glob("frame_*.ply"))) == len(edit.schedule)
    assert not list(tmp_path.glob(".edited.*"))
    # A file the user put into the export is theirs: --force refuses rather than delete it.
    (out / "frame_99999.ply").write_bytes((out / "frame_00000.ply").read_bytes())
    refused = tvmedit("export", small_library, a.name, b.name, "-o", out, "-q", "--force")
    assert refused.returncode == 2 and "frame_99999.ply, which tvmedit did not write" in refused.stderr
    assert (out / "frame_99999.ply").exists()
    (out / "frame_99999.ply").unlink()

    capture = tmp_path / "capture"
    capture.mkdir()
    (capture / "frame_00000.ply").write_bytes((out / "frame_00000.ply").read_bytes())
    (capture / "notes.md").write_text("take 3: the good one")
    for target, cwd in ((capture, None), (".", capture), ("..", capture)):
        result = tvmedit("export", small_library, a.name, b.name, "-o", target, "-q", "--force", cwd=cwd)
        assert result.returncode == 2 and "Traceback" not in result.stderr
        assert result.stderr.startswith("error: ") and result.stderr.count("\n") == 1
        assert (capture / "notes.md").read_text() == "take 3: the good one"
        assert (capture / "frame_00000.ply").exists() and out.exists()
    # The current folder is refused even when it is a previous export.
    result = tvmedit("export", small_library, a.name, b.name, "-o", ".", "-q", "--force", cwd=out)
    assert result.returncode == 2 and "current folder" in result.stderr
    assert (out / "edit.json").exists()

def test_edit_json_traces_each_frame_to_its_capture_file(small_library, tmp_path):
    library = Library.open(small_library)
    a, b, edit = _reachable_pair(library)
    out = tmp_path / "edited"
    assert tvmedit("export", small_library, a.name, b.name, "-o", out, "-q").returncode == 0
    record = json.loads((out / "edit.json").read_text())
    manifest = json.loads((small_library / "manifest.json").read_text())
    files = {s["name"]: [row[0] for row in s["files"]] for s in manifest["sequences"]}
    for frame in record["frames"]:
        assert frame["source_file"] == files[frame["sequence"]][frame["frame"]]
        assert Path(frame["source_file"]).is_file()
        assert frame["source_file"] != frame["file"]
