"""OBJ frames read by the fast path (tvmedit.engine.capture.objfast) give what trimesh gives.

Every layout is written to a real file and read both ways: through ``read_mesh`` (the fast
path where it applies) and through trimesh alone (``readers.read_trimesh``), at each detail a
caller asks for; the layouts the fast path leaves to trimesh must still read the same.
"""

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


#: Layouts left to trimesh, each made from the fast path's own textured or plain frame.
OTHER = {
    "quads": ("positions", lambda t: t + b"f 1 2 3 4\n"),
    "negative indices": ("positions", lambda t: t + b"f -1 -2 -3\n"),
    "normals only": ("positions", lambda t: t.replace(b"f 1 ", b"vn 0 0 1\nf 1//1 ", 1)),
    "a polyline": ("positions", lambda t: t + b"l 1 2\n"),
    "a comment among the vertices": ("positions", lambda t: t.replace(b"\nv ", b"\n# note\nv ", 2)),
    "texture indices apart": ("textured", lambda t: t.replace(b"f 1/1 ", b"f 1/2 ", 1)),
    "two materials": ("textured", lambda t: t.replace(b"\nf ", b"\nusemtl other\nf ", 1)),
    "windows line ends": ("colours", lambda t: t.replace(b"\n", b"\r\n")),
}


@pytest.mark.parametrize("case", sorted(OTHER))
def test_other_layouts_are_read_by_trimesh_as_before(tmp_path, case):
    layout, change = OTHER[case]
    path = _exported(tmp_path, layout)
    path.write_bytes(change(path.read_bytes()))
    if case == "windows line ends":
        assert objfast.read_obj(path) is not None     # the same frame, read the fast way
    else:
        assert objfast.read_obj(path) is None
    try:
        expected = readers.read_trimesh(path)
    except Exception as error:   # trimesh refuses it: so does read_mesh, in the same words
        with pytest.raises(type(error)):
            readers.read_mesh(path)
        return
    assert np.array_equal(readers.read_mesh(path).faces, expected.faces)
    _same(path)
