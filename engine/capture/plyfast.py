"""A fast reader for the common case of TVM frames: binary little-endian PLY triangle meshes.

Reading thousands of frames is what a library build spends its time on, and a general mesh
reader pays for generality on every file. A capture system writes the same layout every
frame (``element vertex`` with float x, y, z and optional uchar red, green, blue;
``element face`` with ``property list uchar int vertex_indices``), which numpy reads in one
``np.frombuffer`` per element with a structured dtype. Anything else (ASCII or big-endian
files, float colours, polygons that are not all triangles, extra face
properties, other elements first) makes :func:`read_ply` return ``None`` so the caller falls
back to trimesh.

A file that announces more data than it holds, or less (a header that under-counts its
faces), raises ``ValueError`` naming the difference.
"""

from pathlib import Path

import numpy as np

__all__ = ["read_ply", "write_ply"]

# PLY scalar type names (both spellings) -> little-endian numpy codes.
_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
    "short": "<i2", "int16": "<i2", "ushort": "<u2", "uint16": "<u2",
    "int": "<i4", "int32": "<i4", "uint": "<u4", "uint32": "<u4",
    "float": "<f4", "float32": "<f4", "double": "<f8", "float64": "<f8",
}
_MAX_HEADER = 64 * 1024


def _header(data):
    """(elements, body offset) of a binary little-endian PLY, or None for any other layout.

    ``elements`` is a list of ``(name, count, properties)``; a property is
    ``(name, type)`` or ``(name, (count_type, item_type))`` for a list.
    """
    end = data.find(b"end_header", 0, _MAX_HEADER)
    if not data.startswith(b"ply") or end < 0:
        return None
    newline = data.find(b"\n", end)
    if newline < 0:
        return None
    lines = data[:end].decode("ascii", "replace").splitlines()
    elements, binary = [], False
    for line in lines[1:]:
        words = line.split()
        if not words or words[0] in ("comment", "obj_info"):
            continue
        if words[0] == "format":
            binary = len(words) > 1 and words[1] == "binary_little_endian"
        elif words[0] == "element" and len(words) == 3:
            elements.append((words[1], int(words[2]), []))
        elif words[0] == "property" and elements:
            if words[1] == "list" and len(words) == 5:
                if words[2] not in _TYPES or words[3] not in _TYPES:
                    return None
                elements[-1][2].append((words[4], (_TYPES[words[2]], _TYPES[words[3]])))
            elif len(words) == 3 and words[1] in _TYPES:
                elements[-1][2].append((words[2], _TYPES[words[1]]))
            else:
                return None
        else:
            return None
    return (elements, newline + 1) if binary else None


def read_ply(path):
    """(vertices, faces, colours or None) of a binary little-endian PLY, or None to fall back.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    vertices : (N, 3) float32
    faces : (M, 3) integer array, the index type of the file (int32 usually)
    colours : (N, 3) uint8, or None when the file has no red, green, blue; colours of a
        wider integer type (ushort) are scaled from its range to 0-255

    Returns None instead, for trimesh to read, when the layout is not the common one (see
    the module's docstring), float colours included.

    Examples
    --------
    >>> import tempfile, os
    >>> header = (b"ply\\nformat binary_little_endian 1.0\\nelement vertex 3\\n"
    ...           b"property float x\\nproperty float y\\nproperty float z\\n"
    ...           b"element face 1\\nproperty list uchar int vertex_indices\\nend_header\\n")
    >>> body = np.eye(3, dtype="<f4").tobytes() + bytes([3]) + np.arange(3, dtype="<i4").tobytes()
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     name = os.path.join(tmp, "f.ply")
    ...     _ = open(name, "wb").write(header + body)
    ...     v, f, c = read_ply(name)
    >>> v.shape, f.tolist(), c
    ((3, 3), [[0, 1, 2]], None)
    """
    data = Path(path).read_bytes()
    parsed = _header(data)
    if parsed is None:
        return None
    elements, offset = parsed
    if len(elements) < 2 or elements[0][0] != "vertex" or elements[1][0] != "face":
        return None
    (_, n_vertices, vertex_props), (_, n_faces, face_props) = elements[:2]
    if any(isinstance(kind, tuple) for _, kind in vertex_props):
        return None
    names = [name for name, _ in vertex_props]
    if not {"x", "y", "z"} <= set(names) or len(face_props) != 1:
        return None
    count_type, index_type = face_props[0][1] if isinstance(face_props[0][1], tuple) else (None, None)
    if count_type is None:
        return None
    vertex_dtype = np.dtype([(name, kind) for name, kind in vertex_props])
    face_dtype = np.dtype([("n", count_type), ("i", index_type, (3,))])
    need = offset + n_vertices * vertex_dtype.itemsize + n_faces * face_dtype.itemsize
    if len(data) < need:
        raise ValueError(f"the file holds {len(data)} bytes but its header announces {need}")
    if len(data) > need and len(elements) == 2:
        # An under-counted header would silently drop the rest of the mesh.
        raise ValueError(f"the file holds {len(data) - need} bytes more than its header announces "
                         f"({n_vertices} vertices, {n_faces} faces)")
    vertices = np.frombuffer(data, vertex_dtype, n_vertices, offset)
    faces = np.frombuffer(data, face_dtype, n_faces, offset + n_vertices * vertex_dtype.itemsize)
    if n_faces and not (faces["n"] == 3).all():
        return None
    positions = np.empty((n_vertices, 3), np.float32)
    for axis, name in enumerate("xyz"):
        positions[:, axis] = vertices[name]
    rgb = ("red", "green", "blue")
    colours = None
    if any(c in names for c in rgb):
        kinds = {vertex_dtype[c].kind for c in rgb if c in names}
        # Float colours (0-1) go to trimesh, which scales them; it would cut 16-bit ones to
        # their low byte, so integers are scaled from their type's range here.
        if not set(rgb) <= set(names) or kinds != {"u"} and kinds != {"i"}:
            return None
        colours = np.empty((n_vertices, 3), np.uint8)
        for axis, name in enumerate(rgb):
            channel = vertices[name]
            if channel.dtype != np.uint8:
                top = np.iinfo(channel.dtype).max
                channel = np.rint(np.clip(channel, 0, top) * (255.0 / top))
            colours[:, axis] = channel
    return positions, np.ascontiguousarray(faces["i"]), colours


def write_ply(path, verts, faces, colours):
    """Write a binary little-endian PLY in the layout :func:`read_ply` reads fastest.

    verts : (N, 3) float, faces : (M, 3) int, colours : (N, 3) uint8.
    Vertex float x, y, z and uchar red, green, blue; faces as ``list uchar int``.
    """
    vertex = np.empty(len(verts), dtype=[("p", "<f4", 3), ("c", "u1", 3)])
    vertex["p"], vertex["c"] = verts, colours
    face = np.empty(len(faces), dtype=[("n", "u1"), ("i", "<i4", 3)])
    face["n"], face["i"] = 3, faces
    header = ("ply\nformat binary_little_endian 1.0\ncomment tvmedit\n"
              f"element vertex {len(verts)}\nproperty float x\nproperty float y\nproperty float z\n"
              "property uchar red\nproperty uchar green\nproperty uchar blue\n"
              f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(vertex.tobytes())
        f.write(face.tobytes())
