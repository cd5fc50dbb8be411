"""Loading TVM frames: formats, colours, natural order, and one-sentence errors."""

import json
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import trimesh

from tvmedit.engine.errors import InputError
from tvmedit.engine.capture.load import (NEUTRAL_COLOUR, SkippedFramesWarning, UnsupportedFilesWarning, frame_paths,
                         load_sequence, open_sequence, read_frame)


def _mesh(subdivisions=1, colour=(200, 30, 40), shift=0.0):
    mesh = trimesh.creation.icosphere(subdivisions)
    mesh.vertices += shift
    colours = np.tile(np.array(colour + (255,), np.uint8), (len(mesh.vertices), 1))
    colours[::3, :3] = (10, 220, 90)  # not uniform, so a lost colour channel shows
    mesh.visual.vertex_colors = colours
    return mesh


def _write_coff(path, mesh):
    lines = ["COFF", f"{len(mesh.vertices)} {len(mesh.faces)} 0"]
    colours = mesh.visual.vertex_colors
    lines += [f"{float(x)!r} {float(y)!r} {float(z)!r} {r} {g} {b} 255" for (x, y, z), (r, g, b, _) in zip(mesh.vertices, colours)]
    lines += [f"3 {a} {b} {c}" for a, b, c in mesh.faces]
    path.write_text("\n".join(lines) + "\n")


@pytest.mark.parametrize("name, export", [
    ("binary.ply", lambda m, p: m.export(p)),
    ("ascii.ply", lambda m, p: m.export(p, encoding="ascii")),
    ("frame.obj", lambda m, p: m.export(p)),
    ("frame.off", lambda m, p: _write_coff(p, m)),
])
def test_every_format_round_trips_positions_and_colours(tmp_path, name, export):
    mesh = _mesh()
    path = tmp_path / name
    export(mesh, path)
    frame = read_frame(path)
    np.testing.assert_allclose(frame.positions, mesh.vertices, atol=1e-6)
    np.testing.assert_array_equal(frame.colours, mesh.visual.vertex_colors[:, :3])
    np.testing.assert_array_equal(frame.faces, mesh.faces)
    assert frame.positions.dtype == np.float32 and frame.colours.dtype == np.uint8
    assert frame.faces.dtype == np.uint32


def test_frame_without_colours_gets_the_neutral_colour(tmp_path):
    trimesh.creation.box().export(tmp_path / "plain.off")
    frame = read_frame(tmp_path / "plain.off")
    assert (frame.colours == NEUTRAL_COLOUR).all()


def test_frames_come_in_natural_order_and_vary_in_size(tmp_path):
    for index in (10, 2, 1, 33):
        _mesh(subdivisions=1 + index % 3, shift=index).export(tmp_path / f"f{index}.ply")
    (tmp_path / "truth.json").write_text("{}")
    assert [p.name for p in frame_paths(tmp_path)] == ["f1.ply", "f2.ply", "f10.ply", "f33.ply"]
    sequence = load_sequence(tmp_path)
    assert sequence.name == tmp_path.name and sequence.fps == 10
    assert [round(float(f.positions[:, 0].mean())) for f in sequence.frames] == [1, 2, 10, 33]
    assert len({len(f) for f in sequence.frames}) > 1


def test_glob_and_sequence_json(tmp_path):
    for index in range(3):
        _mesh(shift=index).export(tmp_path / f"take_{index}.ply")
    _mesh().export(tmp_path / "other.obj")
    (tmp_path / "sequence.json").write_text(json.dumps({"fps": 25}))
    sequence = open_sequence(str(tmp_path / "take_*.ply"))
    assert len(sequence) == 3 and sequence.fps == 25
    assert open_sequence(tmp_path, fps=30).fps == 30


def _bad_inputs(tmp_path):
    good = _mesh()
    good.export(tmp_path / "good.ply")
    data = (tmp_path / "good.ply").read_bytes()
    (tmp_path / "truncated.ply").write_bytes(data[: len(data) // 2])
    (tmp_path / "notmesh.ply").write_bytes(b"hello, I am not a mesh")
    (tmp_path / "novertices.off").write_text("OFF\n0 0 0\n")
    (tmp_path / "nan.obj").write_text("v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n")
    (tmp_path / "frame.stl").write_text("solid x\nendsolid x\n")


@pytest.mark.parametrize("name, words", [
    ("truncated.ply", "truncated"),
    ("notmesh.ply", "not a readable mesh"),
    ("novertices.off", "has no vertices"),
    ("nan.obj", "NaN or infinite"),
    ("frame.stl", "unsupported extension '.stl'"),
])
def test_each_bad_frame_has_its_sentence(tmp_path, name, words):
    _bad_inputs(tmp_path)
    with pytest.raises(InputError) as caught:
        read_frame(tmp_path / name)
    message = str(caught.value)
    assert name in message and words in message
    assert message.count(". ") == 0 and message.endswith(".")  # one sentence


def test_missing_and_empty_folders(tmp_path):
    with pytest.raises(InputError, match="does not exist"):
        open_sequence(tmp_path / "nowhere")
    (tmp_path / "empty").mkdir()
    with pytest.raises(InputError, match="is empty"):
        open_sequence(tmp_path / "empty")
    (tmp_path / "stl").mkdir()
    (tmp_path / "stl" / "f1.stl").write_text("solid\nendsolid\n")
    with pytest.raises(InputError, match="unsupported extension"):
        open_sequence(tmp_path / "stl")


def test_a_bad_frame_stops_the_load_unless_skipped(tmp_path):
    for index in range(4):
        _mesh(shift=index).export(tmp_path / f"f{index}.ply")
    (tmp_path / "f2.ply").write_bytes((tmp_path / "f2.ply").read_bytes()[:200])
    with pytest.raises(InputError, match="f2.ply"):
        load_sequence(tmp_path)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sequence = load_sequence(tmp_path, skip_bad_frames=True)
    assert [p.name for p in sequence.paths] == ["f0.ply", "f1.ply", "f3.ply"]
    assert any(issubclass(w.category, SkippedFramesWarning) and "f2.ply" in str(w.message) for w in caught)


def test_check_command_prints_one_sentence_and_no_traceback(tmp_path):
    _bad_inputs(tmp_path)
    bad = tmp_path / "bad"
    bad.mkdir()
    (tmp_path / "truncated.ply").rename(bad / "f1.ply")
    before = sorted(p.name for p in tmp_path.rglob("*"))
    result = subprocess.run([sys.executable, "-m", "tvmedit", "check", str(bad)], capture_output=True, text=True)
    assert result.returncode == 2
    assert result.stderr.startswith("error: frame ") and "f1.ply" in result.stderr
    assert "Traceback" not in result.stderr and result.stderr.count("\n") == 1
    assert sorted(p.name for p in tmp_path.rglob("*")) == before  # nothing left behind


def test_check_command_skips_with_a_warning(tmp_path):
    for index in range(3):
        _mesh(subdivisions=1 + index, shift=index).export(tmp_path / f"f{index}.ply")
    (tmp_path / "f1.ply").write_bytes(b"ply\nbroken")
    result = subprocess.run([sys.executable, "-m", "tvmedit", "check", str(tmp_path), "--skip-bad-frames"],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert "warning: skipped 1 bad frame(s): f1.ply" in result.stderr
    assert "2 frames at 10 fps" in result.stdout


@pytest.mark.parametrize("meta, words", [
    ({"name": 7}, "gives the sequence name 7, but a name must be a non-empty string"),
    ({"name": ["walk"]}, r'gives the sequence name \["walk"\], but a name must be'),
    ({"fps": "abc"}, "must be a number above 0 and at most 1000, not 'abc'"),
    ({"fps": True}, "must be a number above 0 and at most 1000, not True"),
    ({"fps": -5}, "must be a number above 0 and at most 1000, not -5"),
])
def test_sequence_json_values_are_checked(tmp_path, meta, words):
    _mesh().export(tmp_path / "f0.ply")
    (tmp_path / "sequence.json").write_text(json.dumps(meta))
    with pytest.raises(InputError, match=words):
        open_sequence(tmp_path)
    assert open_sequence(tmp_path, name="walk", fps=12).name == "walk"


def test_sequence_json_names_the_sequence(tmp_path):
    _mesh().export(tmp_path / "f0.ply")
    (tmp_path / "sequence.json").write_text(json.dumps({"name": "walk", "fps": 25}))
    sequence = open_sequence(tmp_path)
    assert (sequence.name, sequence.fps) == ("walk", 25)


def test_a_file_of_another_format_among_the_frames_is_reported(tmp_path):
    for index in range(4):
        _mesh(shift=index).export(tmp_path / f"frame_{index:05d}.ply")
    _mesh().export(tmp_path / "frame_00004.stl")
    for name in ("notes.md", "take.txt", "sequence.json", "material.mtl"):
        (tmp_path / name).write_text("{}")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        paths = frame_paths(tmp_path)
    assert len(paths) == 4
    assert [w.category for w in caught] == [UnsupportedFilesWarning]
    message = str(caught[0].message)
    assert "left out 1 file(s) with an unsupported extension (frame_00004.stl)" in message
    assert not any(name in message for name in ("notes.md", "take.txt", "sequence.json", "material.mtl"))

    (tmp_path / "frame_00004.stl").unlink()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert len(frame_paths(tmp_path)) == 4


@pytest.mark.parametrize("kind, scale", [("float", 1.0), ("ushort", 65535.0), ("uchar", 255.0)])
def test_binary_ply_colours_of_any_type_are_kept(tmp_path, kind, scale):
    from tvmedit.engine.capture.plyfast import read_ply

    dtypes = {"float": "<f4", "ushort": "<u2", "uchar": "u1"}
    rgb = np.array([[1.0, 0.0, 0.0], [0.0, 0.5, 0.0], [0.0, 0.0, 1.0]])
    vertex = np.empty(3, dtype=[("p", "<f4", 3), ("c", dtypes[kind], 3)])
    vertex["p"], vertex["c"] = np.eye(3), rgb if kind == "float" else np.rint(rgb * scale)
    face = np.empty(1, dtype=[("n", "u1"), ("i", "<i4", 3)])
    face["n"], face["i"] = 3, [0, 1, 2]
    header = ("ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
              "property float x\nproperty float y\nproperty float z\n"
              + "".join(f"property {kind} {c}\n" for c in ("red", "green", "blue"))
              + "element face 1\nproperty list uchar int vertex_indices\nend_header\n")
    path = tmp_path / "f.ply"
    path.write_bytes(header.encode() + vertex.tobytes() + face.tobytes())
    assert (read_ply(path) is None) == (kind == "float")  # trimesh scales float colours
    colours = read_frame(path).colours
    np.testing.assert_allclose(colours, np.rint(rgb * 255), atol=1)


def test_a_rate_nothing_states_is_said_to_be_assumed(tmp_path):
    from tvmedit.engine.capture.load import open_sequence

    for index in range(3):
        _mesh(shift=index).export(tmp_path / f"f{index}.ply")
    assert open_sequence(str(tmp_path)).rate_from == "assumed"
    result = subprocess.run([sys.executable, "-m", "tvmedit", "check", str(tmp_path)], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert "10 fps was assumed; set it with --fps" in result.stdout
    (tmp_path / "sequence.json").write_text(json.dumps({"fps": 30}))
    assert open_sequence(str(tmp_path)).rate_from == "sequence.json"
    result = subprocess.run([sys.executable, "-m", "tvmedit", "check", str(tmp_path)], capture_output=True, text=True)
    assert "assumed" not in result.stdout and "30 fps" in result.stdout and "sequence.json's" in result.stdout
    assert open_sequence(str(tmp_path), fps=12).rate_from == "given"


def test_frames_one_folder_down_are_read_from_the_top_folder(tmp_path):
    from tvmedit.engine.capture.load import open_sequence

    top = tmp_path / "take"
    (top / "geometry").mkdir(parents=True)
    (top / "textures").mkdir()
    (top / "sound.mp3").write_bytes(b"ID3")
    for index in range(3):
        _mesh(shift=index).export(top / "geometry" / f"f{index}.ply")
    sequence = open_sequence(str(top))
    assert [p.name for p in map(Path, sequence.paths)] == ["f0.ply", "f1.ply", "f2.ply"]
    assert sequence.name == "take"
    (top / "other").mkdir()
    _mesh().export(top / "other" / "g0.ply")
    with pytest.raises(InputError, match="holds frames in 2 subfolders"):
        open_sequence(str(top))


def _player_export(tmp_path, textures):
    """A web player's layout: three frames in ``talk/geometry_draco/``, beside an (empty)
    texture folder named ``textures``."""
    top = tmp_path / "talk"
    (top / "geometry_draco").mkdir(parents=True)
    (top / textures).mkdir()
    for index in range(3):
        _mesh(shift=index).export(top / "geometry_draco" / f"f{index}.ply")
    return top


def test_a_rate_a_folder_name_states_is_taken_and_said(tmp_path):
    from tvmedit.engine.capture.load import open_sequence

    top = _player_export(tmp_path, "texture_ktx2-fps30-1k_baseColor_default")
    sequence = open_sequence(str(top))
    assert sequence.fps == 30 and sequence.rate_from == "folder name 'texture_ktx2-fps30-1k_baseColor_default'"
    result = subprocess.run([sys.executable, "-m", "tvmedit", "check", str(top)], capture_output=True, text=True)
    assert "3 frames at 30 fps" in result.stdout and "folder name" in result.stdout, result.stdout
    assert open_sequence(str(top), fps=10).fps == 10


def test_a_uvol_manifest_gives_the_rate_and_an_lfs_pointer_is_named(tmp_path):
    # A web player's export: geometry_draco/ beside textures and a *.uvol.json manifest; cloned
    # without `git lfs pull`, the manifest is a pointer file.
    from tvmedit.engine.capture.load import open_sequence

    top = _player_export(tmp_path, "texture_ktx2-fps25-1k")
    manifest = top / "talk.uvol.json"
    manifest.write_text(json.dumps({"version": "2", "geometry": {"targets": {"draco_high": {"frameRate": 30}}}}))
    sequence = open_sequence(str(top))
    assert sequence.fps == 30 and sequence.rate_from == "uvol manifest 'talk.uvol.json'"
    result = subprocess.run([sys.executable, "-m", "tvmedit", "check", str(top)], capture_output=True, text=True)
    assert "3 frames at 30 fps" in result.stdout and "uvol manifest" in result.stdout, result.stdout
    manifest.write_text("version https://git-lfs.github.com/spec/v1\noid sha256:0123\nsize 2048\n")
    with pytest.warns(UserWarning, match=r"talk\.uvol\.json cannot be read .*Git LFS pointer.*git lfs pull"):
        sequence = open_sequence(str(top))
    assert sequence.fps == 25          # the rate the texture folder's name states, said so
