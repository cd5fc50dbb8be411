"""Writing frames the way captures come: Draco with a JPG texture, OBJ with MTL, binary glTF.

Each writer is the twin of a reader of :mod:`tvmedit.engine.capture.readers` and writes what
that reader reads back: positions, triangles, and either per-vertex colours or texture
coordinates with their image (OpenGL's convention for ``uv``: v = 0 at the image's bottom row;
the image with row 0 at the top). :data:`WRITERS` maps a format name to its writer.

Compression is chosen to stay inside a capture's own noise. Draco quantises positions on a
grid of 2^``QUANTIZATION_BITS`` steps over the frame's extent: 14 bits put a 2 m person on
0.12 mm steps, far under the millimetres a depth camera resolves, and texture coordinates on
2^12 steps, a quarter texel of a 1024-pixel atlas. JPG textures at quality 92 keep print
legible (the scvv exporter's own textures are JPG). OBJ and glTF are written losslessly
(trimesh writes both; a texture array is written or embedded as PNG). A texture that is still
the capture's own image file is copied (or embedded) as it is, never decoded and encoded
again (:data:`TAKES`).
"""

import io
import os
import shutil
from pathlib import Path

import numpy as np

__all__ = ["WRITERS", "SUFFIXES", "TAKES", "prepare", "write_frame", "write_draco", "write_obj", "write_glb", "write_image",
           "QUANTIZATION_BITS", "UV_BITS", "COMPRESSION_LEVEL", "JPG_QUALITY"]

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
    """Import what the writer of ``fmt`` uses (DracoPy, trimesh, Pillow: tenths of a second),
    so that worker processes forked afterwards start with it."""
    import PIL.Image  # noqa: F401

    if fmt in ("scvv", "drc"):
        import DracoPy  # noqa: F401
    else:
        import trimesh.exchange.gltf  # noqa: F401
        import trimesh.exchange.obj  # noqa: F401


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


def write_draco(path, positions, faces, colours=None, uv=None):
    """One frame as a Draco mesh (``.drc``/``.draco``); its texture is written by the caller
    (:func:`write_frame` puts it beside, as scvv does). Returns the path."""
    import DracoPy

    data = DracoPy.encode(np.asarray(positions, dtype=np.float32), faces=np.asarray(faces, dtype=np.uint32),
                          quantization_bits=QUANTIZATION_BITS, compression_level=COMPRESSION_LEVEL,
                          colors=None if colours is None else np.asarray(colours, dtype=np.uint8),
                          tex_coord=None if uv is None else np.asarray(uv, dtype=np.float64),
                          tex_coord_quantization_bits=UV_BITS if uv is not None else None)
    Path(path).write_bytes(data)
    return Path(path)


def _trimesh(positions, faces, colours=None, uv=None, image=None):
    """A trimesh of one frame: textured where ``uv`` is given (``image`` an array, a Pillow
    image, or None for the caller to name the image), else vertex-coloured."""
    import trimesh
    from PIL import Image

    if uv is not None:
        if image is not None and not isinstance(image, Image.Image):
            image = Image.fromarray(np.asarray(image, dtype=np.uint8))
        visual = trimesh.visual.TextureVisuals(uv=np.asarray(uv, dtype=np.float64), image=image)
    else:
        visual = trimesh.visual.ColorVisuals(vertex_colors=None if colours is None else np.asarray(colours))
    return trimesh.Trimesh(np.asarray(positions, dtype=np.float64), np.asarray(faces), visual=visual, process=False)


def _is_file(image):
    return isinstance(image, (str, os.PathLike))


def _obj_texture(stem, image):
    """The name of an OBJ frame's texture beside it: the image file's own suffix where it is
    copied, ``.png`` where an array is written."""
    return f"{stem}{Path(image).suffix.lower() if _is_file(image) else '.png'}"


def _encoded(image_file):
    """A Pillow image of ``image_file`` that saves as the file's own bytes. trimesh's glTF
    writer embeds an image by saving it; a JPG would be decoded and encoded again (at quality
    75), a PNG compressed again, for the same pixels."""
    from PIL import Image

    data = Path(image_file).read_bytes()
    picture = Image.open(io.BytesIO(data))
    picture.save = lambda fp, *args, **kwargs: fp.write(data)
    return picture


def write_obj(path, positions, faces, colours=None, uv=None, image=None):
    """One frame as OBJ: with a texture, ``path`` plus an MTL and the image of the same stem
    beside it (``image`` an array, written as PNG, or an image file, copied as it is); with
    colours, ``v x y z r g b`` lines. Returns the OBJ's path."""
    from trimesh.exchange.obj import export_obj

    path = Path(path)
    textured = uv is not None and image is not None
    copied = textured and _is_file(image)
    mesh = _trimesh(positions, faces, colours, uv if textured else None, None if copied else image)
    text, files = export_obj(mesh, include_texture=textured, include_color=not textured,
                             return_texture=True, mtl_name=f"{path.stem}.mtl")
    path.write_text(text)
    texture = _obj_texture(path.stem, image)
    for name, blob in files.items():
        if name.endswith(".png"):   # trimesh's image (a placeholder where the file is copied)
            if not copied:
                (path.parent / texture).write_bytes(blob)
        else:
            (path.parent / name).write_bytes(blob)
    if copied:
        shutil.copyfile(image, path.parent / texture)
    if textured:
        mtl = path.parent / f"{path.stem}.mtl"
        lines = [f"map_Kd {texture}" if line.startswith("map_Kd") else line
                 for line in mtl.read_text().splitlines()]
        mtl.write_text("\n".join(lines) + "\n")
    return path


def write_glb(path, positions, faces, colours=None, uv=None, image=None):
    """One frame as a binary glTF (``.glb``) holding its texture (``image`` an array, embedded
    as PNG, or a JPG or PNG file, embedded as it is) or its colours. Returns the path."""
    path = Path(path)
    textured = uv is not None and image is not None
    picture = _encoded(image) if textured and _is_file(image) else image
    mesh = _trimesh(positions, faces, colours, uv if textured else None, picture if textured else None)
    path.write_bytes(mesh.export(file_type="glb"))
    return path


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
