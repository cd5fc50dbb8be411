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
(trimesh writes glTF; a texture is embedded as PNG).
"""

from pathlib import Path

import numpy as np

__all__ = ["WRITERS", "SUFFIXES", "write_frame", "write_draco", "write_obj", "write_glb", "write_image",
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
    import trimesh
    from PIL import Image

    if uv is not None and image is not None:
        visual = trimesh.visual.TextureVisuals(uv=np.asarray(uv, dtype=np.float64),
                                               image=Image.fromarray(np.asarray(image, dtype=np.uint8)))
    else:
        visual = trimesh.visual.ColorVisuals(vertex_colors=None if colours is None else np.asarray(colours))
    return trimesh.Trimesh(np.asarray(positions, dtype=np.float64), np.asarray(faces), visual=visual, process=False)


def write_obj(path, positions, faces, colours=None, uv=None, image=None):
    """One frame as OBJ: with a texture, ``path`` plus an MTL and a PNG of the same stem beside
    it; with colours, ``v x y z r g b`` lines. Returns the OBJ's path."""
    from trimesh.exchange.obj import export_obj

    path = Path(path)
    mesh = _trimesh(positions, faces, colours, uv, image)
    textured = uv is not None and image is not None
    text, files = export_obj(mesh, include_texture=textured, include_color=not textured,
                             return_texture=True, mtl_name=f"{path.stem}.mtl")
    path.write_text(text)
    for name, blob in files.items():
        if name.endswith(".png"):
            name = f"{path.stem}.png"
        (path.parent / name).write_bytes(blob)
    if textured:
        mtl = path.parent / f"{path.stem}.mtl"
        lines = [f"map_Kd {path.stem}.png" if line.startswith("map_Kd") else line
                 for line in mtl.read_text().splitlines()]
        mtl.write_text("\n".join(lines) + "\n")
    return path


def write_glb(path, positions, faces, colours=None, uv=None, image=None):
    """One frame as a binary glTF (``.glb``) holding its texture or colours. Returns the path."""
    path = Path(path)
    mesh = _trimesh(positions, faces, colours, uv, image)
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


def write_frame(fmt, folder, stem, positions, faces, colours=None, uv=None, image=None):
    """Write one frame in format ``fmt`` into ``folder`` as ``stem`` plus the format's suffix;
    returns ``(mesh file name, texture file name or None)``."""
    suffix, writer, texture_suffix = WRITERS[fmt]
    folder = Path(folder)
    textured = uv is not None and image is not None
    if texture_suffix is None:
        writer(folder / f"{stem}{suffix}", positions, faces, colours, uv if textured else None,
               image if textured else None)
        return f"{stem}{suffix}", (f"{stem}.png" if textured and fmt == "obj" else None)
    writer(folder / f"{stem}{suffix}", positions, faces, colours, uv if textured else None)
    if not textured:
        return f"{stem}{suffix}", None
    write_image(folder / f"{stem}{texture_suffix}", image)
    return f"{stem}{suffix}", f"{stem}{texture_suffix}"

