"""A fast reader for the common case of OBJ frames: one mesh of triangles, as exporters write it.

A capture exported as OBJ (tvmedit's own ``export --format obj`` among them) writes every
frame the same way: a block of ``v`` lines (``x y z``, or ``x y z r g b`` with vertex
colours), a block of ``vt`` lines indexed like the vertices, one material with its texture
(``mtllib``, ``usemtl``, ``map_Kd``, beside the frame) and a block of triangles ``f a b c``
or ``f a/a b/b c/c``. trimesh reads any OBJ, but pays for it on every frame: it splits the
text into a Python string per line and checks each one (110 ms for a 12,000-vertex textured
frame of the scvv card, texture colours included); here numpy finds where each kind of line
starts and ends and parses each block at once, with the number parser trimesh uses
(``np.fromstring``), so the arrays are the same (45 ms; most of it that parser). As trimesh
does, a textured frame takes its colours from its texture, not from its ``v`` lines.

:func:`read_obj` gives ``None`` for anything else: lines it does not know (``l``, ``p``,
curves, indented lines, a tab after a keyword), a block broken by other lines, a face line
with more or fewer corners than the first, polygons that are not triangles, negative or
``v//vn`` indices, texture or normal indices that differ from the vertex ones, vertices no
triangle uses in a textured frame, ``mtllib`` or ``usemtl`` more than once (comments
included: trimesh looks for the words anywhere), a material file or image in another folder,
options before the image, a material without its texture, texture coordinates without a
material (trimesh then makes a coloured material of its own), a line continued with a
backslash. The caller then reads the file through trimesh, which handles all of these, as it
does a texture image Pillow cannot read (:func:`tvmedit.engine.capture.readers.read_obj_file`).
"""

import warnings
from pathlib import Path

import numpy as np

__all__ = ["read_obj", "check_textures"]

#: Keywords of the lines the fast path passes over (besides ``v``, ``vt``, ``vn`` and ``f``).
_OTHER = {b"#", b"mtllib", b"usemtl", b"o", b"g", b"s"}
#: Most such lines a frame may have: a header's worth, looked at one by one.
_MOST_OTHER = 256


def read_obj(path, data=None):
    """``(vertices (N, 3) float64, faces (M, 3) int64, colours (N, 3) uint8 or None, uv (N, 2)
    float32 or None, texture image path or None)`` of an OBJ frame of the common layout (see
    the module docstring), or None for any other. ``data``: the file's bytes, where the caller
    has read them.

    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     frame = Path(folder) / "f.obj"
    ...     _ = frame.write_text("# a triangle\\nv 0 0 0\\nv 1 0 0\\nv 0 1 0\\nf 1 2 3\\n")
    ...     v, f, colours, uv, image = read_obj(frame)
    >>> v.tolist(), f.tolist(), colours, uv, image
    ([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], [[0, 1, 2]], None, None, None)
    """
    path = Path(path)
    data = path.read_bytes() if data is None else data
    if b"\r" in data:
        data = data.replace(b"\r\n", b"\n")
    if b"\\\n" in data:
        return None
    blocks = _lines(data)
    if blocks is None or "v" not in blocks or "f" not in blocks:
        return None
    vertices = _floats(data, blocks["v"])
    faces = _faces(data, blocks["f"])
    if vertices is None or faces is None or vertices.shape[1] < 3:
        return None
    faces, corners = faces
    colours = _colours(vertices[:, 3:6]) if vertices.shape[1] >= 6 else None
    vertices = vertices[:, :3]
    if len(faces) and (faces.min() < 0 or faces.max() >= len(vertices)):
        return None
    if any(k is not None and not np.array_equal(k, faces) for k in corners):
        return None
    if corners[0] is None:      # no texture coordinates: a material would give a colour instead
        plain = b"mtllib" not in data and b"usemtl" not in data and "vt" not in blocks
        return (vertices, faces, colours, None, None) if plain else None
    uv = _floats(data, blocks["vt"]) if "vt" in blocks else None
    if (uv is None or uv.shape[1] < 2 or len(uv) != len(vertices)
            or np.bincount(faces.ravel(), minlength=len(vertices)).min() == 0):
        return None
    image = _texture(path.parent, data)
    if image is None:
        return None
    # Textured, trimesh keeps no vertex colours: they come from the texture.
    return vertices, faces, None, uv[:, :2].astype(np.float32), image


def _lines(data):
    """``{kind: (first byte, end byte, lines)}`` for ``v``, ``vt``, ``vn`` and ``f`` lines,
    each kind one unbroken run of lines; None where a kind is broken up, or a line is none of
    these nor of :data:`_OTHER`."""
    raw = np.frombuffer(data, np.uint8)
    newline = np.flatnonzero(raw == 10)
    starts = np.concatenate([[0], newline + 1])
    ends = np.concatenate([newline, [len(raw)]])
    starts, ends = starts[starts < ends], ends[starts < ends]
    padded = np.concatenate([raw, np.zeros(3, np.uint8)])
    first, second, third = padded[starts], padded[starts + 1], padded[starts + 2]
    kinds = np.zeros(len(starts), np.int8)     # trimesh finds "v ", "vt ", "vn ", "f ": a space, not a tab
    kinds[(first == ord("v")) & (second == ord(" "))] = 1
    kinds[(first == ord("v")) & (second == ord("t")) & (third == ord(" "))] = 2
    kinds[(first == ord("v")) & (second == ord("n")) & (third == ord(" "))] = 3
    kinds[(first == ord("f")) & (second == ord(" "))] = 4
    rest = np.flatnonzero(kinds == 0)
    if len(rest) > _MOST_OTHER:
        return None
    for index in rest:
        words = data[starts[index]:ends[index]].split()
        if words and words[0] not in _OTHER and not words[0].startswith(b"#"):
            return None
        if words and words[0] in (b"usemtl", b"o", b"g") and len(kinds) and index > np.argmax(kinds == 4):
            return None     # a material or object begun among the faces: trimesh groups them
    blocks = {}
    for code, name in ((1, "v"), (2, "vt"), (3, "vn"), (4, "f")):
        where = np.flatnonzero(kinds == code)
        if not len(where):
            continue
        if where[-1] - where[0] + 1 != len(where):
            return None
        blocks[name] = (int(starts[where[0]]), int(ends[where[-1]]), len(where))
    return blocks


def _numbers(text, dtype):
    """Every number of ``text`` (whitespace between), or None where something is not one."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            return np.fromstring(text, sep=" ", dtype=dtype)
        except (ValueError, DeprecationWarning):
            return None


def _floats(data, block):
    """The ``(lines, columns)`` float64 values of a block of ``v`` or ``vt`` lines, as many on
    each line as on its first; None otherwise."""
    begin, end, count = block
    stop = data.find(b"\n", begin, end)
    head = data[begin:stop if stop >= 0 else end].split()
    text = data[begin:end]
    columns = len(head) - 1    # (as trimesh, which checks the first line's count and the total)
    if columns < 1:
        return None
    values = _numbers(text.replace(head[0], b" "), np.float64)
    if values is None or len(values) != count * columns:
        return None
    return values.reshape(count, columns)


def _each_line_holds(text, count, words):
    """Whether each of the ``count`` lines of ``text`` that hold anything holds ``words``
    words (blank lines aside), as trimesh asks of faces before it reads them as one array: a
    quad among triangles would shift every corner after it (1 ms for 24,000 faces)."""
    raw = np.frombuffer(text, np.uint8)
    blank = raw <= ord(" ")     # (any other control character is no number: the block is refused)
    begins = ~blank
    begins[1:] &= blank[:-1]
    starts = np.concatenate([[0], np.flatnonzero(raw == ord("\n")) + 1])
    per_line = np.add.reduceat(begins, starts[starts < len(raw)], dtype=np.int32)
    held = per_line[per_line > 0]
    return len(held) == count and bool((held == words).all())


def _faces(data, block):
    """``(faces (M, 3) int64, [texture indices or None, normal indices or None])``, 0-based,
    of a block of triangles; None for other polygons, negative or ``v//vn`` indices."""
    begin, end, count = block
    text = data[begin:end]
    if b"-" in text or b"//" in text:
        return None
    head = text[:text.find(b"\n")] if b"\n" in text else text
    fields = head.count(b"/") // 3 + 1
    if len(head.split()) != 4 or fields > 3 or head.count(b"/") % 3 or not _each_line_holds(text, count, 4):
        return None
    values = _numbers(text.replace(b"f", b" ").replace(b"/", b" "), np.int64)
    if values is None or len(values) != count * 3 * fields:
        return None
    values = values.reshape(count, 3, fields) - 1
    corners = [np.ascontiguousarray(values[:, :, k]) if k < fields else None for k in (1, 2)]
    return np.ascontiguousarray(values[:, :, 0]), corners


def _colours(values):
    """Vertex colours as trimesh makes them from an OBJ's ``r g b`` (0-1 floats, or 0-255)."""
    from trimesh.visual.color import to_rgba

    return np.asarray(to_rgba(values))[:, :3]


def _texture(folder, data):
    """The image file of the frame's one material (``map_Kd``) where trimesh finds the same:
    one ``mtllib`` and one ``usemtl`` line (the words nowhere else, comments included: trimesh
    looks for them anywhere), the material file and the image beside the frame, the image
    ``map_Kd``'s one argument; else None."""
    if data.count(b"mtllib") != 1 or data.count(b"usemtl") != 1:
        return None
    libraries, materials = _named(data, b"mtllib "), _named(data, b"usemtl ")
    if len(libraries) != 1 or len(materials) != 1 or _in_folder(libraries[0]):
        return None
    mtl, material = folder / libraries[0].decode("utf-8", "replace"), materials[0]
    if not mtl.is_file():
        return None
    name, image = None, None
    for line in mtl.read_bytes().splitlines():
        words = line.split(None, 1)
        key = words[0].lower() if words else b""
        if key == b"newmtl":
            name = words[1].strip() if len(words) > 1 else None
        elif key == b"map_kd" and name == material:
            if image is not None or len(words) < 2 or len(words[1].split()) != 1:
                return None     # options before the image, or a second one: left to trimesh
            image = words[1].strip()
    if image is None or _in_folder(image):
        return None
    path = folder / image.decode("utf-8", "replace")
    return path if path.is_file() else None


def _in_folder(name):
    return b"/" in name or b"\\" in name


def check_textures(path, data=None):
    """The texture images an OBJ's material files name must be there: trimesh leaves a missing
    one out without a word, and the frame would draw white where the capture had its colours.
    Raises ``ValueError`` naming what is missing. ``data``: the file's bytes, where the caller
    has read them."""
    path = Path(path)
    for name in _named(path.read_bytes() if data is None else data, b"mtllib "):
        name = name.decode("utf-8", "replace")
        mtl = path.parent / name
        if not mtl.is_file():
            raise ValueError(f"its material file {name} is missing; put it beside the frame or remove the "
                             "mtllib line")
        for line in mtl.read_text(errors="replace").splitlines():
            words = line.split()
            if words and words[0].lower() in ("map_kd", "map_ka") and len(words) > 1:
                image = mtl.parent / words[-1]
                if not image.is_file():
                    raise ValueError(f"its material file {name} names the texture {words[-1]}, which is missing; "
                                     "put it beside the frame")


def _named(data, key):
    """What follows ``key`` on each line it begins (stripped, where anything does), found by
    ``bytes.find``: a regular expression anchored at every line took 19 ms on a 1.5 MB frame.

    >>> _named(b"# x\\nmtllib a.mtl\\nv 0 0 0\\nmtllib  b c.mtl \\r\\nusemtl m\\n", b"mtllib ")
    [b'a.mtl', b'b c.mtl']
    """
    names, at = [], data.find(key)
    while at >= 0:
        end = data.find(b"\n", at)
        if at == 0 or data[at - 1:at] == b"\n":
            name = data[at + len(key):end if end >= 0 else len(data)].strip()
            if name:
                names.append(name)
        at = data.find(key, at + 1)
    return names
