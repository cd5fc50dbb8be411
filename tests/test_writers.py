"""Frames written as captures come read back as they were written."""

import numpy as np
import pytest
from scipy.spatial import cKDTree

from tvmedit.engine.capture.readers import read_mesh
from tvmedit.engine.capture.writers import QUANTIZATION_BITS, write_frame


def textured_square(n=12):
    """An n x n grid over a 2 m square with a checker texture: a frame with uv and image."""
    u, v = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    positions = np.column_stack([u.ravel() * 2, v.ravel() * 2, np.sin(u.ravel() * 3)]).astype(np.float32)
    faces = []
    for i in range(n - 1):
        for j in range(n - 1):
            a = i * n + j
            faces += [[a, a + 1, a + n], [a + 1, a + n + 1, a + n]]
    image = np.zeros((64, 64, 3), np.uint8)
    image[::2, ::2] = (250, 40, 40)
    image[1::2, 1::2] = (40, 40, 250)
    uv = np.column_stack([u.ravel(), v.ravel()]).astype(np.float32)
    return positions, np.array(faces), uv, image


@pytest.mark.parametrize("fmt", ["scvv", "obj", "glb"])
def test_a_textured_frame_reads_back_with_its_texture(tmp_path, fmt):
    positions, faces, uv, image = textured_square()
    mesh_name, _ = write_frame(fmt, tmp_path, "frame_00000", positions, faces, uv=uv, image=image)
    back = read_mesh(tmp_path / mesh_name)
    assert len(back.faces) == len(faces)
    # Every written vertex is within the quantisation step of one read back.
    step = np.ptp(positions, axis=0).max() / 2 ** QUANTIZATION_BITS
    assert cKDTree(back.vertices).query(positions)[0].max() <= step
    assert back.uv is not None and back.texture is not None
    assert back.texture.shape == image.shape
    if fmt != "scvv":   # JPG is lossy; PNG and glTF's embedded image are not
        assert np.array_equal(back.texture, image)
    if fmt == "glb":    # vertices in their order, each with its own texture coordinates
        np.testing.assert_allclose(back.vertices, positions, atol=1e-6)
        np.testing.assert_allclose(back.uv, uv, atol=1e-6)


@pytest.mark.parametrize("fmt", ["obj", "glb"])
def test_a_vertex_coloured_frame_keeps_its_colours(tmp_path, fmt):
    positions, faces, _, _ = textured_square()
    colours = np.tile(np.array([[200, 100, 50]], np.uint8), (len(positions), 1))
    mesh_name, texture = write_frame(fmt, tmp_path, "f", positions, faces, colours=colours)
    back = read_mesh(tmp_path / mesh_name)
    assert texture is None and back.colours is not None
    assert np.abs(back.colours.astype(int) - colours).max() <= 1


@pytest.mark.parametrize("fmt", ["scvv", "obj", "glb"])
def test_a_texture_given_as_its_file_goes_out_byte_for_byte(tmp_path, fmt):
    # An in-between frame shows the capture's own JPG: copied beside the frame (scvv, OBJ) or
    # embedded (glTF) as it is, never decoded and encoded again.
    from PIL import Image

    positions, faces, uv, image = textured_square()
    jpg = tmp_path / "capture.jpg"
    Image.fromarray(image).save(jpg, quality=90)
    out = tmp_path / "out"
    out.mkdir()
    mesh_name, texture = write_frame(fmt, out, "frame_00000", positions, faces, uv=uv, image=jpg)
    if fmt == "glb":
        assert texture is None and jpg.read_bytes() in (out / mesh_name).read_bytes()
    else:
        assert texture == "frame_00000.jpg" and (out / texture).read_bytes() == jpg.read_bytes()
    back = read_mesh(out / mesh_name)
    assert back.uv is not None and np.array_equal(back.texture, np.asarray(Image.open(jpg).convert("RGB")))


@pytest.mark.parametrize("fmt", ["obj", "glb"])
def test_rgba_colours_are_written_as_their_rgb(tmp_path, fmt):
    positions, faces, _, _ = textured_square()
    colours = np.tile(np.array([[200, 100, 50, 128]], np.uint8), (len(positions), 1))
    mesh_name, _ = write_frame(fmt, tmp_path, "f", positions, faces, colours=colours)
    assert np.abs(read_mesh(tmp_path / mesh_name).colours.astype(int) - colours[:, :3]).max() <= 1


def test_a_frame_without_triangles_is_refused_as_glb_not_written_invalid(tmp_path):
    positions, _, _, _ = textured_square()
    with pytest.raises(ValueError, match="a frame without triangles cannot be written as GLB"):
        write_frame("glb", tmp_path, "f", positions, np.zeros((0, 3), np.int64))
    assert not (tmp_path / "f.glb").exists()


def _as_percent(head, rows, decimals, twice=None):
    """The lines :func:`tvmedit.engine.capture.writers._text` must write, by Python's ``%``."""
    spec = "%d" if decimals == 0 and rows.dtype.kind in "iu" else f"%.{decimals}f"
    values = rows.tolist() if spec == "%d" else rows.astype(np.float64).tolist()
    field = spec + (f"{twice}{spec}" if twice else "")
    return b"".join((head.decode() + " ".join(field % ((v, v) if twice else v) for v in row) + "\n").encode()
                    for row in values)


@pytest.mark.parametrize("seed", range(4))
def test_obj_numbers_are_written_as_python_writes_them(seed):
    # The OBJ writer looks digits up in tables rather than formatting each number: any digit
    # it got wrong would move a vertex in every mesh tool that reads the export.
    from tvmedit.engine.capture.writers import _LARGEST, _text

    rng = np.random.default_rng(seed)
    scales = rng.choice([1e-9, 1e-4, 0.5, 1.0, 3.0, 1e3], size=(400, 3))
    floats = (rng.normal(size=(400, 3)) * scales).astype(np.float32)
    floats[:7, 0] = [-0.0, 0.0, 0.999999999, -0.0000000049, _LARGEST - 0.5, 0.99999999, 1e-8]
    large = floats * 1000                        # whole parts past the digit tables: written by %
    inexact = floats.astype(np.float64) + 1e-13  # not float32 values: written by % too
    for rows in (floats, floats.astype(np.float64), floats[:, :1], floats[:0], large, inexact):
        for decimals in (0, 3, 6, 8):
            assert _text(b"v ", rows, decimals) == _as_percent(b"v ", rows, decimals), (rows.dtype, decimals)
    assert np.abs(floats).max() < _LARGEST <= np.abs(large).max()
    for dtype in (np.int32, np.int64, np.uint32):
        faces = rng.integers(1, 40000, size=(300, 3)).astype(dtype)
        faces[:5, 0] = [0, 1, 9, 10, _LARGEST - 1]
        for rows in (faces, faces * 300):   # the second past the tables
            assert _text(b"f ", rows, 0, "/") == _as_percent(b"f ", rows, 0, "/")
            assert _text(b"f ", rows, 0) == _as_percent(b"f ", rows, 0)
    negative = rng.integers(-10 ** 6, 10 ** 6, size=(50, 2))
    assert _text(b"l ", negative, 0) == _as_percent(b"l ", negative, 0)
    extremes = [np.array([[-128, 127]], np.int8), np.array([[0, 2 ** 64 - 1]], np.uint64),
                np.array([[-2 ** 63, 5]], np.int64), np.array([[3, -7]], np.int16)]
    for rows in extremes:
        assert _text(b"l ", rows, 0) == _as_percent(b"l ", rows, 0), rows.dtype
        assert _text(b"v ", rows, 2) == _as_percent(b"v ", rows.astype(np.float64), 2), rows.dtype


def test_integer_positions_are_written_as_numbers(tmp_path):
    import trimesh

    from tvmedit.engine.capture.writers import write_obj

    path = write_obj(tmp_path / "f.obj", np.eye(3, dtype=np.int32), [[0, 1, 2]])
    assert path.read_text().startswith("v 1.00000000 0.00000000 0.00000000\n")
    assert np.array_equal(trimesh.load(path, process=False).vertices, np.eye(3))
