"""Exported edits: PLY for vertex-coloured libraries, formats refused by name, and where an
export may be written again."""

import json

import pytest

from tvmedit import Library
from tvmedit.engine.errors import OutputError, ParameterError
from tvmedit.engine.graph.export import default_format, export_edit


def test_a_vertex_coloured_library_exports_ply_frames_and_no_format_key(small_library, tmp_path):
    library = Library.open(small_library)
    assert default_format(library) == "ply"
    names = [node.name for node in library.nodes[:2]]
    record = export_edit(library.edit(names), tmp_path / "out")
    files = sorted(p.name for p in (tmp_path / "out").iterdir() if not p.name.startswith("."))
    assert files == sorted([f["file"] for f in record["frames"]] + ["edit.json", "sequence.json"])
    assert all(name.endswith(".ply") for name in files if name.startswith("frame_"))
    assert "format" not in json.loads((tmp_path / "out" / "edit.json").read_text())


def test_an_unknown_format_is_refused_before_anything_is_written(small_library, tmp_path):
    library = Library.open(small_library)
    edit = library.edit([node.name for node in library.nodes[:2]])
    with pytest.raises(ParameterError, match="not one of ply, scvv, obj, glb"):
        export_edit(edit, tmp_path / "out", fmt="usd")
    assert not (tmp_path / "out").exists()


def test_an_export_is_replaced_only_with_force_and_a_plain_folder_never(small_library, tmp_path):
    library = Library.open(small_library)
    edit = library.edit([node.name for node in library.nodes[:2]])
    export_edit(edit, tmp_path / "out")
    with pytest.raises(OutputError, match="already exists; pass force=True"):
        export_edit(edit, tmp_path / "out")
    record = export_edit(edit, tmp_path / "out", force=True)
    assert json.loads((tmp_path / "out" / "edit.json").read_text())["frames"] == record["frames"]
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "notes.txt").write_text("keep me")
    with pytest.raises(OutputError, match="not replaced"):
        export_edit(edit, tmp_path / "mine", force=True)
    assert (tmp_path / "mine" / "notes.txt").read_text() == "keep me"


def test_frames_of_sequences_turned_apart_go_out_in_the_one_frame_the_export_states(tmp_path):
    """Two takes of one walk, the second stated to face +x: an OBJ export through a motion of
    each writes every frame in the first sequence's coordinates, the ones its sequence.json
    states, so each reads back where the library shows it."""
    import numpy as np

    from conftest import synth_take
    from tvmedit import engine
    from tvmedit.engine.capture.load import iter_frames, open_sequence

    walk = synth_take("walk")
    side = tmp_path / "side"
    side.mkdir()
    for path in sorted(walk.glob("frame_*.ply")):
        (side / path.name).symlink_to(path)
    (side / "sequence.json").write_text('{"fps": 10, "front": "+x"}')
    library = engine.build([("walk", walk), ("side", side)], tmp_path / "two.tvmlib", workers=1, cache=False,
                           smooth=False, blend_frames=0)
    assert library.orientation("side").front == "+x" and library.orientation("walk").front == "-y"
    first, second = (next(n for n in library.nodes if n.sequence == name) for name in ("walk", "side"))
    record = export_edit(library.edit([first.name, second.name], durations=[1.3]), tmp_path / "out", fmt="obj")
    back = open_sequence(tmp_path / "out")
    assert back.orientation.front == "-y"
    frames = dict(iter_frames(back.paths, orientation=back.orientation))
    sequences = set()
    for entry in record["frames"]:
        sequences.add(entry["sequence"])
        shown = np.asarray(library.frame_mesh((entry["sequence"], entry["frame"]))[0])
        assert np.abs(frames[tmp_path / "out" / entry["file"]].positions - shown).max() < 1e-4
    assert sequences == {"walk", "side"}
