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


def test_a_vertex_coloured_draco_capture_keeps_colours_on_its_in_between_frames(synth_gym, tmp_path):
    # Draco frames with vertex colours and no texture: the in-between frames the build keeps as
    # Draco carry their colours, byte for byte as an export of a library without them encodes.
    import json
    import shutil

    import DracoPy
    import numpy as np
    import trimesh

    from tvmedit import Library, build
    from tvmedit.engine.graph.export import export_edit

    take = synth_gym
    frames = tmp_path / "draco"
    frames.mkdir()
    for path in sorted(take.glob("*.ply")):
        mesh = trimesh.load(path, process=False)
        (frames / f"{path.stem}.drc").write_bytes(DracoPy.encode(
            np.asarray(mesh.vertices, np.float32), faces=np.asarray(mesh.faces, np.uint32),
            colors=np.asarray(mesh.visual.vertex_colors, np.uint8)[:, :3], quantization_bits=14))
    (frames / "sequence.json").write_text('{"fps": 10}')
    library = build([frames], tmp_path / "draco.tvmlib", cache=False, smooth=False)   # transitions' frames only
    edit = library.edit(list(range(len(library.nodes))))
    moved = [k for k, entry in enumerate(edit.schedule) if entry.blend is not None]
    assert moved and library.capture_bytes(edit.schedule[moved[0]].key)
    older = tmp_path / "older.tvmlib"   # the same library as built before it kept them
    shutil.copytree(library.path, older)
    manifest = json.loads((older / "manifest.json").read_text())
    for name in ("blend_draco.npy", "blend_draco_frames.npy"):
        (older / name).unlink()
        manifest["files"].pop(name), manifest["checksums"].pop(name)
    (older / "manifest.json").write_text(json.dumps(manifest))
    kept = export_edit(edit, tmp_path / "kept", fmt="scvv")
    made = export_edit(Library.open(older).edit(list(edit.keys)), tmp_path / "made", fmt="scvv")
    names = [frame["file"] for frame in kept["frames"]]
    assert all((tmp_path / "kept" / name).read_bytes() == (tmp_path / "made" / name).read_bytes() for name in names)
    decoded = DracoPy.decode((tmp_path / "kept" / names[moved[0]]).read_bytes())
    assert decoded.colors is not None and len(decoded.colors) == len(decoded.points)
