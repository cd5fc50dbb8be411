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
