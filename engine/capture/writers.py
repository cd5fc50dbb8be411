"""Writing frames the way captures come: Draco with a JPG texture, OBJ with MTL, binary glTF.

Each writer is the twin of a reader of :mod:`tvmedit.engine.capture.readers` and writes what
that reader reads back: positions, triangles, and either per-vertex colours or texture
coordinates with their image (OpenGL's convention for ``uv``: v = 0 at the image's bottom row;
the image with row 0 at the top). :data:`WRITERS` maps a format name to its writer.

Compression is chosen to stay inside a capture's own noise. Draco quantises positions on a
grid of 2^``QUANTIZATION_BITS`` steps over the frame's extent: 14 bits put a 2 m person on
0.12 mm steps, far under the millimetres a depth camera resolves, and texture coordinates on
2^12 steps, a quarter texel of a 1024-pixel atlas. JPG textures at quality 92 keep print
legible (the scvv exporter's own textures are JPG). OBJ and glTF are written losslessly, by
this module rather than trimesh's exporters, which took three to ten times as long for the
same file (:func:`write_obj`, :func:`write_glb`); trimesh reads them back. A texture array
is written or embedded as PNG. A texture that is still
the capture's own image file is copied (or embedded) as it is, never decoded and encoded
again (:data:`TAKES`).
"""

import io
import os
import shutil
from pathlib import Path

import numpy as np

__all__ = ["WRITERS", "SUFFIXES", "TAKES", "prepare", "write_frame", "encode_draco", "write_draco", "write_obj",
           "write_glb", "write_image", "QUANTIZATION_BITS", "UV_BITS", "COMPRESSION_LEVEL", "JPG_QUALITY"]

#: Draco position quantisation (bits per axis over the frame's extent).
QUANTIZATION_BITS = 14
#: Draco texture-coordinate quantisation.
UV_BITS = 12
#: Draco's encoder speed against size (0-10): 3 encodes twice as fast as 7 for a few percent
#: more bytes on a capture's frames.
COMPRESSION_LEVEL = 3
#: Quality of JPG textures.
JPG_QUALITY = 92


def prepare(fmt):
    """Import what the writer of ``fmt`` uses (DracoPy, Pillow: tenths of a second),
    so that worker processes forked afterwards start with it."""
    import PIL.Image  # noqa: F401

    if fmt in ("scvv", "drc"):
        import DracoPy  # noqa: F401


def write_image(path, image, quality=JPG_QUALITY):
    """Write an (H, W, 3) uint8 image as JPG or PNG, by ``path``'s suffix."""
    from PIL import Image

    path = Path(path)
    picture = Image.fromarray(np.ascontiguousarray(image, dtype=np.uint8))
    if path.suffix.lower() in (".jpg", ".jpeg"):
        picture.save(path, quality=quality, subsampling=0)
    else:
        picture.save(path)
    return path


def encode_draco(positions, faces, colours=None, uv=None):
    """One frame's Draco bytes, at :data:`QUANTIZATION_BITS`, :data:`UV_BITS` and
    :data:`COMPRESSION_LEVEL` (what :func:`write_draco` writes)."""
    import DracoPy

    return DracoPy.encode(np.asarray(positions, dtype=np.float32), faces=np.asarray(faces, dtype=np.uint32),
                          quantization_bits=QUANTIZATION_BITS, compression_level=COMPRESSION_LEVEL,
                          colors=None if colours is None else np.asarray(colours, dtype=np.uint8),
                          tex_coord=None if uv is None else np.asarray(uv, dtype=np.float64),
                          tex_coord_quantization_bits=UV_BITS if uv is not None else None)


def write_draco(path, positions, faces, colours=None, uv=None):
    """One frame as a Draco mesh (``.drc``/``.draco``); its texture is written by the caller
    (:func:`write_frame` puts it beside, as scvv does). Returns the path."""
    Path(path).write_bytes(encode_draco(positions, faces, colours, uv))
    return Path(path)


def _is_file(image):
    return isinstance(image, (str, os.PathLike))


def _obj_texture(stem, image):
    """The name of an OBJ frame's texture beside it: the image file's own suffix where it is
    copied, ``.png`` where an array is written."""
    return f"{stem}{Path(image).suffix.lower() if _is_file(image) else '.png'}"


def write_obj(path, positions, faces, colours=None, uv=None, image=None):
    """One frame as OBJ: with a texture, ``path`` plus an MTL and the image of the same stem
    beside it (``image`` an array, written as PNG, or an image file, copied as it is); with
    colours, ``v x y z r g b`` lines (0-1). Returns the OBJ's path.

    The text is trimesh's, byte for byte (8 decimals), looked up by numpy a whole block of
    lines at a time (:func:`_text`): 5.6 ms for a 12,000-vertex textured frame of the scvv
    card, where making the digits one by one took 11 ms, Python's ``%`` 31 ms and trimesh's
    exporter 71 ms. Faces index ``v`` and ``vt`` alike (one texture coordinate a vertex)."""
    path = Path(path)
    positions = np.asarray(positions).reshape(-1, 3)
    faces = np.asarray(faces, dtype=np.int64).reshape(-1, 3) + 1
    textured = uv is not None and image is not None
    if textured:
        texture = _obj_texture(path.stem, image)
        head = f"mtllib {path.stem}.mtl\nusemtl material_0\n".encode()
        body = [_text(b"v ", positions, 8), _text(b"vt ", np.asarray(uv), 8), _text(b"f ", faces, 0, "/")]
        (path.parent / f"{path.stem}.mtl").write_text(
            "newmtl material_0\nKa 1.0 1.0 1.0\nKd 1.0 1.0 1.0\nKs 0.0 0.0 0.0\nillum 1\n"
            f"map_Kd {texture}\n")
        if _is_file(image):
            shutil.copyfile(image, path.parent / texture)
        else:
            write_image(path.parent / texture, image)
    else:
        head = b""
        if colours is not None:
            rows = np.hstack([positions.astype(np.float64), np.asarray(colours, np.float64)[:, :3] / 255.0])
            body = [_text(b"v ", rows, 8)]
        else:
            body = [_text(b"v ", positions, 8)]
        body.append(_text(b"f ", faces, 0))
    with open(path, "wb") as out:
        out.write(head)
        for block in body:
            out.write(block)
    return path


def _text(head, rows, decimals, twice=None):
    """The lines ``head v1 v2 ...`` of every row of ``rows``, each value as Python's
    ``"%.{decimals}f"`` writes it (``"%d"`` with none), as bytes; with ``twice``, each value
    written twice joined by it (OBJ's ``f 1/1 2/2 3/3``).

    Every line is laid out at one width in a character matrix (:func:`_tokens`), NUL where a
    shorter number leaves room, and the NULs are dropped at once by ``bytearray.translate``
    (one pass in C; a boolean mask took three times as long). The digits are those of
    ``rint(|v| * 10**decimals)``, which is the decimal rounding itself when that product is
    exact: for every float32 value at up to 12 decimals and every integer below 2**53 (what a
    frame holds). Other values, and whole parts from :data:`_LARGEST` up, are formatted by ``%``.

    >>> _text(b"v ", np.array([[1.5, -0.0, 12.25]]), 2), _text(b"f ", np.array([[1, 20, 300]]), 0, "/")
    (b'v 1.50 -0.00 12.25\\n', b'f 1/1 20/20 300/300\\n')
    """
    given = np.asarray(rows)
    if given.dtype.kind in "iu" and decimals:
        given = given.astype(np.float64)    # integers with decimals: written as the floats they are
    if given.dtype.kind not in "iu":
        given = given if given.dtype == np.float32 else given.astype(np.float64)
        # 10**d times a float32 is exact in a float64 up to d = 12 (24 + 28 bits of 5**12).
        exact = given.size and decimals <= 12 and float(np.abs(given).max()) * 10.0 ** decimals < 2.0 ** 53 and (
            given.dtype == np.float32 or decimals == 0 and np.array_equal(given, np.rint(given))
            or np.array_equal(given, given.astype(np.float32)))
        if not exact:
            given = None
    tokens = None if given is None or not given.size else _tokens(given, decimals)
    if tokens is None:
        values = np.asarray(rows)
        spec = "%d" if decimals == 0 and values.dtype.kind in "iu" else f"%.{decimals}f"
        values = values if spec == "%d" else values.astype(np.float64)
        line = head.decode() + " ".join([spec + (f"{twice}{spec}" if twice else "")] * values.shape[1]) + "\n"
        return ((line * len(values)) % tuple(np.repeat(values, 2 if twice else 1, axis=1).ravel().tolist())).encode()
    count, columns, size = tokens.shape
    field = (2 if twice else 1) * (size + 1)
    buffer = bytearray(count * (len(head) + columns * field))
    chars = np.frombuffer(buffer, np.uint8).reshape(count, -1)
    chars[:, :len(head)] = np.frombuffer(head, np.uint8)
    fields = chars[:, len(head):].reshape(count, columns, field)
    fields[:, :, :size] = tokens
    if twice:
        fields[:, :, size] = ord(twice)
        fields[:, :, size + 1:-1] = tokens
    fields[:, :, -1] = ord(" ")
    fields[:, -1, -1] = ord("\n")
    return bytes(buffer.translate(None, b"\0"))


#: Whole parts from here up are written by ``%``: the digit table stops below it (8 MB).
_LARGEST = 1 << 20
_DIGITS = {}


def _digit_tables(count):
    """``(whole, four)``: ``whole[i]``, a uint64 holding ``"%d" % i`` right-aligned in 8
    bytes with NULs before it, for ``i < count`` at least; ``four[i]``, a uint32 holding
    ``"%04d" % i`` for ``i < 10000``. Made once a process (and again for a larger count)."""
    whole = _DIGITS.get("whole")
    if whole is None or len(whole) < count:
        size = 1 << max(10, (count - 1).bit_length())
        values = np.arange(size, dtype=np.int64)
        table, rest = np.zeros((size, 8), np.uint8), values.copy()
        for k in range(8):
            digit = (48 + rest % 10).astype(np.uint8)
            table[:, 7 - k] = np.where(values >= 10 ** k, digit, 0) if k else digit
            rest //= 10
        _DIGITS["whole"] = whole = table.view(np.uint64).reshape(-1)
    if "four" not in _DIGITS:
        values = np.arange(10000)
        four = np.stack([48 + values // 10 ** k % 10 for k in (3, 2, 1, 0)], axis=1).astype(np.uint8)
        _DIGITS["four"] = four.view(np.uint32).reshape(-1)
    return whole, _DIGITS["four"]


def _tokens(given, decimals):
    """(N, C, W) uint8: the text of each value of (N, C) ``given`` (integers, or floats whose
    decimal rounding is exact, see :func:`_text`), right-aligned, NUL where nothing is written
    (a positive value's sign, leading zeros); None where a whole part reaches :data:`_LARGEST`.

    Looked up, not computed digit by digit: a whole part in one 8-byte gather, the decimals
    four digits a gather."""
    if given.dtype.kind in "iu":
        if int(given.max()) >= _LARGEST or int(given.min()) <= -_LARGEST:
            return None     # compared before any cast: no int8 -128 or uint64 wraps round
        values = given.astype(np.int64)
        negative, whole, fraction = values < 0, np.abs(values), None
    else:
        negative = np.signbit(given)   # "-0.00" for -0.0, as % writes it
        scaled = np.rint(np.abs(given.astype(np.float64)) * 10.0 ** decimals).astype(np.int64)
        whole, fraction = np.divmod(scaled, 10 ** decimals) if decimals else (scaled, None)
    top = int(whole.max())
    if top >= _LARGEST:
        return None
    wholes, fours = _digit_tables(top + 1)
    width, (count, columns) = len(str(top)), given.shape
    size = 1 + width + (1 + decimals if decimals else 0)
    out = np.empty((count, columns, size), np.uint8)
    out[:, :, 0] = np.where(negative, np.uint8(ord("-")), np.uint8(0))
    out[:, :, 1:1 + width] = wholes[whole].view(np.uint8).reshape(count, columns, 8)[:, :, 8 - width:]
    if decimals:
        out[:, :, 1 + width] = ord(".")
        chunks = -(-decimals // 4)
        digits = np.empty((count, columns, chunks), np.uint32)
        for i in range(chunks):
            digits[:, :, i] = fours[fraction // 10 ** (4 * (chunks - 1 - i)) % 10000]
        out[:, :, 2 + width:] = digits.view(np.uint8).reshape(count, columns, 4 * chunks)[:, :, -decimals:]
    return out


def write_glb(path, positions, faces, colours=None, uv=None, image=None):
    """One frame as a binary glTF (``.glb``) holding its texture (``image`` an array, embedded
    as PNG, or a JPG or PNG file, embedded as it is) or its colours. Returns the path.

    The file is laid out here, not by trimesh's exporter: one mesh of one triangle primitive
    (POSITION, TEXCOORD_0 or COLOR_0, 32-bit indices), its material and image, in a JSON chunk
    and a binary chunk (glTF 2.0, section "GLB File Format Specification"). trimesh builds a
    scene, hashes its arrays and re-reads the image for the same bytes, four times as long for
    a 12,000-vertex frame of the scvv card. The Khronos validator finds no error in it, and
    trimesh and tvmedit's reader read it back. A frame without triangles is refused: glTF has
    no empty accessor."""
    import json
    import struct

    positions = np.ascontiguousarray(positions, dtype="<f4").reshape(-1, 3)
    parts, views, accessors = [], [], []   # parts: the binary chunk's pieces, written as they are

    def add(data, target=None, **accessor):
        data = memoryview(data).cast("B") if isinstance(data, np.ndarray) else data
        offset = sum(len(part) + -len(part) % 4 for part in parts)
        parts.append(data)
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(data),
                      **({"target": target} if target else {})})
        if accessor:
            accessors.append({"bufferView": len(views) - 1, **accessor})
        return len(accessors) - 1 if accessor else len(views) - 1

    count = len(positions)
    if not count or not len(faces):
        raise ValueError(f"{path}: a frame without triangles cannot be written as GLB")
    flat = positions.reshape(-1)    # each axis reduced as a strided row: (N, 3) by axis 0 is twenty times slower
    low, high = [flat[k::3].min() for k in range(3)], [flat[k::3].max() for k in range(3)]
    attributes = {"POSITION": add(positions, 34962, componentType=5126, count=count, type="VEC3",
                                  min=[float(v) for v in low], max=[float(v) for v in high])}
    primitive = {"attributes": attributes, "mode": 4}
    gltf = {"asset": {"version": "2.0", "generator": "tvmedit"}, "scene": 0, "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0}], "meshes": [{"primitives": [primitive]}]}
    textured = uv is not None and image is not None
    if textured:
        flipped = np.array(uv, dtype="<f4").reshape(-1, 2)
        flipped[:, 1] = 1.0 - flipped[:, 1]     # glTF's v runs down the image
        attributes["TEXCOORD_0"] = add(flipped, 34962,
                                       componentType=5126, count=count, type="VEC2")
    elif colours is not None:
        rgba = np.full((count, 4), 255, np.uint8)
        rgba[:, :3] = np.asarray(colours, dtype=np.uint8)[:, :3]
        attributes["COLOR_0"] = add(rgba, 34962, componentType=5121, normalized=True, count=count,
                                    type="VEC4")
    indices = np.ascontiguousarray(faces).reshape(-1)
    # Indices are never negative: a frame's int32 faces are their uint32 bytes as they are.
    indices = indices.view("<u4") if indices.dtype == np.dtype("<i4") else indices.astype("<u4")
    primitive["indices"] = add(indices, 34963, componentType=5125, count=len(indices), type="SCALAR")
    if textured:
        data, mime = _image_bytes(image)
        gltf.update(images=[{"bufferView": add(data), "mimeType": mime}], samplers=[{}],
                    textures=[{"sampler": 0, "source": 0}],
                    materials=[{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0}}])
        primitive["material"] = 0
    binary = sum(len(part) + -len(part) % 4 for part in parts)
    gltf.update(bufferViews=views, accessors=accessors, buffers=[{"byteLength": binary}])
    text = json.dumps(gltf, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    total = 12 + 8 + len(text) + 8 + binary
    path = Path(path)
    pieces = [struct.pack("<III", 0x46546C67, 2, total), struct.pack("<II", len(text), 0x4E4F534A), text,
              struct.pack("<II", binary, 0x004E4942)]
    for part in parts:     # each piece padded to 4 bytes, as its view's offset says
        pieces += [part, b"\0" * (-len(part) % 4)]
    _write_pieces(path, pieces)
    return path


def _write_pieces(path, pieces):
    """Write the byte strings ``pieces`` one after another as the file ``path``: gathered by
    the kernel in one call where it can (``os.writev``), not copied into a buffer first."""
    with open(path, "wb", buffering=0) as out:
        if not hasattr(os, "writev"):
            for piece in pieces:
                out.write(piece)
            return
        pieces = [piece for piece in pieces if len(piece)]
        while pieces:
            written = os.writev(out.fileno(), pieces[:1024])
            while pieces and written >= len(pieces[0]):
                written -= len(pieces.pop(0))
            if written:     # a short write: the rest of that piece goes next
                pieces[0] = memoryview(pieces[0])[written:]


def _image_bytes(image):
    """``(bytes, MIME type)`` of a texture to embed: a JPG or PNG file as it is, an array as PNG."""
    if _is_file(image):
        data = Path(image).read_bytes()
        return data, "image/png" if data[:8] == b"\x89PNG\r\n\x1a\n" else "image/jpeg"
    from PIL import Image

    buffer = io.BytesIO()
    Image.fromarray(np.ascontiguousarray(image, dtype=np.uint8)).save(buffer, format="PNG")
    return buffer.getvalue(), "image/png"


#: format -> (frame suffix, writer, texture suffix beside the frame or None).
WRITERS = {
    "scvv": (".draco", write_draco, ".jpg"),
    "drc": (".drc", write_draco, ".jpg"),
    "obj": (".obj", write_obj, None),
    "glb": (".glb", write_glb, None),
}
SUFFIXES = {name: suffix for name, (suffix, _, _) in WRITERS.items()}
#: format -> the image files a frame's texture is copied or embedded from as they are: JPG for
#: scvv (as depth-camera apps write it), JPG or PNG for OBJ and glTF (what their readers and
#: glTF's core image types take).
TAKES = {"scvv": (".jpg", ".jpeg"), "drc": (".jpg", ".jpeg"), "obj": (".jpg", ".jpeg", ".png"),
         "glb": (".jpg", ".jpeg", ".png")}


def write_frame(fmt, folder, stem, positions, faces, colours=None, uv=None, image=None):
    """Write one frame in format ``fmt`` into ``folder`` as ``stem`` plus the format's suffix;
    returns ``(mesh file name, texture file name or None)``.

    ``image`` is the texture: an (H, W, 3) array, or an image file holding it already (a
    capture's own JPG). A file in a form the format takes (:data:`TAKES`) is copied or
    embedded as it is: the same pixels, no second loss, and a hundred times faster than an
    encoder; any other is read and encoded."""
    suffix, writer, texture_suffix = WRITERS[fmt]
    folder = Path(folder)
    textured = uv is not None and image is not None
    if textured and _is_file(image) and Path(image).suffix.lower() not in TAKES[fmt]:
        from .readers import read_image

        image = read_image(image)
    if texture_suffix is None:
        writer(folder / f"{stem}{suffix}", positions, faces, colours, uv if textured else None,
               image if textured else None)
        if not (textured and fmt == "obj"):
            return f"{stem}{suffix}", None
        return f"{stem}{suffix}", _obj_texture(stem, image)
    writer(folder / f"{stem}{suffix}", positions, faces, colours, uv if textured else None)
    if not textured:
        return f"{stem}{suffix}", None
    if _is_file(image):
        texture = f"{stem}{Path(image).suffix.lower()}"
        shutil.copyfile(image, folder / texture)
        return f"{stem}{suffix}", texture
    write_image(folder / f"{stem}{texture_suffix}", image)
    return f"{stem}{suffix}", f"{stem}{texture_suffix}"
