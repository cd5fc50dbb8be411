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
