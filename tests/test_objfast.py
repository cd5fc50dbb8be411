"""OBJ frames read by the fast path (tvmedit.engine.capture.objfast) give what trimesh gives.

Every layout is written to a real file and read both ways: through ``read_mesh`` (the fast
path where it applies) and through trimesh alone (``readers.read_trimesh``), at each detail a
caller asks for; the frames the fast path leaves to trimesh must still read the same.
"""

import re
from pathlib import Path

import numpy as np
import pytest
import trimesh
from PIL import Image

from tvmedit.engine.capture import objfast, readers
from tvmedit.engine.capture.writers import write_obj


def _mesh(seed=0):
    sphere = trimesh.creation.icosphere(subdivisions=2)
    rng = np.random.default_rng(seed)
    return (sphere.vertices * (1 + 0.1 * rng.random((len(sphere.vertices), 1))), sphere.faces,
            rng.integers(0, 256, (len(sphere.vertices), 3)).astype(np.uint8), rng.random((len(sphere.vertices), 2)))


def _exported(folder, layout):
    """A frame of ``layout`` in ``folder``: as tvmedit's exporter or trimesh's writes it."""
    positions, faces, colours, uv = _mesh()
    image = np.zeros((16, 32, 3), np.uint8)
    image[:, 16:] = (20, 40, 230)
    path = Path(folder) / "frame.obj"
    if layout == "positions":
        write_obj(path, positions, faces)
    elif layout == "colours":
        write_obj(path, positions, faces, colours=colours)
    elif layout == "textured":
        write_obj(path, positions, faces, uv=uv, image=image)
    else:
        mesh = trimesh.Trimesh(positions, faces, process=False)
        if layout == "trimesh-textured":     # with normals: f a/a/a b/b/b c/c/c
            mesh.visual = trimesh.visual.TextureVisuals(uv=uv, image=Image.fromarray(image))
        else:
            mesh.visual.vertex_colors = colours
        mesh.export(path)
    return path


def _same(path):
    for detail in readers.DETAILS:
        fast, slow = readers.read_mesh(path, detail), readers.read_trimesh(path, detail)
        for name in ("vertices", "faces", "colours", "uv", "texture", "texture_path"):
            a, b = getattr(fast, name), getattr(slow, name)
            assert (a is None) == (b is None), (detail, name)
            if isinstance(a, np.ndarray):
                assert a.dtype == np.asarray(b).dtype and np.array_equal(a, b), (detail, name)
            else:
                assert a == b, (detail, name)


@pytest.mark.parametrize("layout", ["positions", "colours", "textured", "trimesh-textured", "trimesh-colours"])
def test_exported_frames_take_the_fast_path_and_read_as_trimesh_reads_them(tmp_path, layout):
    path = _exported(tmp_path, layout)
    fast = objfast.read_obj(path)
    assert fast is not None
    assert len(fast[0]) == 162 and len(fast[1]) == 320
    assert (fast[2] is not None) == layout.endswith("colours") and (fast[3] is not None) == layout.endswith("textured")
    _same(path)


#: Frames changed from the fast path's own: still read the fast way, as trimesh reads them.
FAST = {
    "windows line ends": ("colours", lambda t: t.replace(b"\n", b"\r\n")),
    "colours on a textured frame": ("textured", lambda t: re.sub(rb"(?m)^(v .*)$", rb"\1 0.25 0.5 0.75", t)),
    "blank lines": ("textured", lambda t: t.replace(b"\nvt ", b"\n\nvt ", 1) + b"\n\n"),
}

#: Frames changed from the fast path's own that it leaves to trimesh.
OTHER = {
    "quads": ("positions", lambda t: t + b"f 1 2 3 4\n"),
    "a quad among the triangles": ("positions", lambda t: t.replace(b"\nf ", b"\nf 1 2 3 4\nf ", 1)),
    "negative indices": ("positions", lambda t: t + b"f -1 -2 -3\n"),
    "normals only": ("positions", lambda t: t.replace(b"f 1 ", b"vn 0 0 1\nf 1//1 ", 1)),
    "a polyline": ("positions", lambda t: t + b"l 1 2\n"),
    "a comment among the vertices": ("positions", lambda t: t.replace(b"\nv ", b"\n# note\nv ", 2)),
    "tabs after the keywords": ("textured", lambda t: t.replace(b"\nvt ", b"\nvt\t")),
    "texture indices apart": ("textured", lambda t: t.replace(b"f 1/1 ", b"f 1/2 ", 1)),
    "two materials": ("textured", lambda t: t.replace(b"\nf ", b"\nusemtl other\nf ", 1)),
    "mtllib in a comment": ("textured", lambda t: b"# mtllib is read below\n" + t),
    "map_Kd with options": ("textured", None),
}


def _changed(tmp_path, layout, change):
    path = _exported(tmp_path, layout)
    if change is None:      # the material file's texture line, with an option before the image
        mtl = path.with_suffix(".mtl")
        mtl.write_bytes(mtl.read_bytes().replace(b"map_Kd ", b"map_Kd -s 1 1 1 "))
    else:
        path.write_bytes(change(path.read_bytes()))
    return path


@pytest.mark.parametrize("case", sorted(FAST))
def test_frames_changed_in_ways_trimesh_reads_the_same_still_take_the_fast_path(tmp_path, case):
    path = _changed(tmp_path, *FAST[case])
    assert objfast.read_obj(path) is not None
    _same(path)


@pytest.mark.parametrize("case", sorted(OTHER))
def test_other_layouts_are_read_by_trimesh_as_before(tmp_path, case):
    path = _changed(tmp_path, *OTHER[case])
    assert objfast.read_obj(path) is None
    try:
        expected = readers.read_trimesh(path)
    except Exception as error:   # trimesh refuses it: so does read_mesh, in the same words
        with pytest.raises(type(error)):
            readers.read_mesh(path)
        return
    assert np.array_equal(readers.read_mesh(path).faces, expected.faces)
    _same(path)


def test_a_texture_pillow_cannot_read_is_left_to_trimesh(tmp_path):
    path = _exported(tmp_path, "textured")
    path.with_suffix(".png").write_bytes(b"not an image")
    assert objfast.read_obj(path) is not None      # laid out as the fast path reads it ...
    _same(path)                                    # ... but the image is trimesh's to judge
