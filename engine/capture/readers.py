"""Reading captures as they come: one registry from file format to reader, and sequence manifests.

Every reader turns one frame file into plain arrays (:class:`MeshData`): vertices, triangles,
per-vertex colours when the file has them, and per-vertex texture coordinates with the
frame's texture image when it is textured. :data:`READERS` maps a file suffix to its reader;
:func:`register` adds one, so a new format is a function here, not a branch elsewhere.

Formats
-------
``ply``
    binary little-endian triangle meshes through :mod:`tvmedit.engine.capture.plyfast`, everything else
    (ASCII, other layouts) through trimesh.
``obj``
    one mesh of triangles as exporters write it (blocks of ``v``, ``vt`` and ``f`` lines, one
    material) through :mod:`tvmedit.engine.capture.objfast`, anything else through trimesh with
    ``process=False``; an ``.mtl`` beside it with a ``map_Kd`` texture gives texture
    coordinates and the image.
``off``
    parsed here, because trimesh drops the per-vertex colours of COFF.
``draco`` (``.drc``, ``.draco``)
    Google Draco through DracoPy; the frame's texture is the one its sequence manifest names,
    else the image beside it with the same name stem (``000855_frame.jpg``).
``gltf`` (``.gltf``, ``.glb``)
    through trimesh; base-colour textures and vertex colours are kept.

Sequence manifests
------------------
A folder may describe its own sequence. The Scandy Core Volumetric Video layout
(``scvv_animation.json`` or ``scvv.json``) lists per frame its ``mesh_path``, ``texture_path``
and ``delay_us``, the microseconds since the previous frame; :func:`read_manifest` returns
them as a :class:`Manifest` (frame files, texture files, capture times in seconds).

Colour from textures
--------------------
A textured frame without vertex colours gets them from its texture (:func:`texture_colours`):
each vertex takes the mean texel colour over its triangles, each triangle's mean read from a
box-filtered level of the texture as large as the triangle and weighted by its area in the
texture, so a vertex's colour is what its neighbourhood of the texture shows, not one noisy
texel.
"""

import os
import re
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..checks import json_value

__all__ = ["MeshData", "Manifest", "READERS", "register", "reader_for", "read_mesh", "read_image", "natural_key", "is_draco",
           "texture_colours", "read_manifest", "MANIFEST_NAMES", "IMAGE_SUFFIXES"]

#: File names of a sequence manifest, in the order they are looked for.
MANIFEST_NAMES = ("scvv_animation.json", "scvv.json")
#: Texture images tvmedit reads (Pillow decodes them).
IMAGE_SUFFIXES = (".jpg", ".jpeg", ".png", ".webp", ".bmp")


@dataclass
class MeshData:
    """One frame as a reader returns it: plain arrays, nothing checked yet.

    vertices : (N, 3) float
    faces : (M, 3) integer
    colours : (N, 3) uint8, or None when the file has no vertex colours
    uv : (N, 2) float32 texture coordinates (OpenGL convention: v = 0 at the image's bottom
        row), or None
    texture : (H, W, 3) uint8, the texture image with row 0 at the top, or None (also when
        textures were not asked for)
    texture_path : Path or None, where the texture came from (a file, or the mesh file itself
        when the texture is embedded)
    """

    vertices: np.ndarray
    faces: np.ndarray
    colours: np.ndarray = None
    uv: np.ndarray = None
    texture: np.ndarray = None
    texture_path: Path = None


#: suffix -> (format name, reader). A reader is ``reader(path, detail) -> MeshData`` where
#: ``detail`` says what the caller needs: ``"geometry"`` (vertices and faces: analysis, which
#: then never decodes a texture image), ``"colours"`` (and vertex colours, from the texture
#: where the frame has no others) or ``"full"`` (and texture coordinates with the image).
READERS = {}
DETAILS = ("geometry", "colours", "full")


def register(name, *suffixes):
    """Decorator: register ``reader(path, detail) -> MeshData`` for ``suffixes`` as format ``name``.

    >>> @register("xyz-demo", ".xyzdemo")
    ... def _read_demo(path, detail="full"):
    ...     return MeshData(np.zeros((3, 3)), np.array([[0, 1, 2]]))
    >>> reader_for("frame.XYZDEMO")[0]
    'xyz-demo'
    >>> del READERS[".xyzdemo"]
    """
    def decorate(function):
        for suffix in suffixes:
            READERS[suffix.lower()] = (name, function)
        return function
    return decorate


def reader_for(path):
    """``(format name, reader)`` for the suffix of ``path``, or None."""
    return READERS.get(Path(path).suffix.lower())


def read_mesh(path, detail="full"):
    """Read one frame file through the registry (``detail``: see :data:`READERS`).

    Raises ``ValueError`` for a suffix no reader is registered for.
    """
    entry = reader_for(path)
    if entry is None:
        raise ValueError(f"no reader for '{Path(path).suffix}' files")
    if detail not in DETAILS:
        raise ValueError(f"detail must be one of {DETAILS}, not {detail!r}")
    return entry[1](Path(path), detail)


def read_image(path):
    """(H, W, 3) uint8 RGB of an image file (or a KTX2 file's layer), row 0 at the top."""
    from PIL import Image

    from .ktx2 import KtxLayer, read_layer

    if isinstance(path, KtxLayer):
        return read_layer(path)
    with Image.open(path) as image:
        return np.asarray(image.convert("RGB") if image.mode != "RGB" else image)


# --- colour from a texture ----------------------------------------------------------------

def _pyramid(texture, depth):
    """The texture and its 2x2 box-filtered halvings (Pillow's ``reduce``), ``depth`` levels or
    down to one texel, each as (h, w) uint32 packed RGBX texels."""
    from PIL import Image

    image = Image.fromarray(np.ascontiguousarray(texture)).convert("RGBX")
    levels = [np.asarray(image).view(np.uint32)[..., 0]]
    while len(levels) <= depth and min(image.size) > 1:
        image = image.reduce(2)
        levels.append(np.asarray(image).view(np.uint32)[..., 0])
    return levels


def _texels(texture, uv):
    """The texels under texture coordinates ``uv`` (OpenGL convention, repeating): (K, 3)."""
    height, width = texture.shape[:2]
    x = ((uv[:, 0] - np.floor(uv[:, 0])) * width).astype(np.intp)
    y = ((np.ceil(uv[:, 1]) - uv[:, 1]) * height).astype(np.intp)
    np.clip(x, 0, width - 1, out=x)
    np.clip(y, 0, height - 1, out=y)
    return texture.reshape(-1, texture.shape[2])[y * width + x]


def texture_colours(uv, faces, texture):
    """Per-vertex colours from a texture, averaged over each vertex's triangles, not sampled
    at one point.

    Each triangle's mean colour is read from the level of the texture's box-filtered pyramid
    (a mipmap) whose texels are as large as the triangle is in the texture, under its centroid;
    a vertex takes the mean of its triangles', weighted by their areas in the texture. So a
    vertex shows what the texture shows around it, and texture noise or detail finer than the
    mesh averages out instead of turning into speckle. A vertex in no triangle takes the texel
    under it.

    Parameters
    ----------
    uv : (N, 2) float
        Texture coordinates, v = 0 at the bottom row.
    faces : (M, 3) int
    texture : (H, W, 3) uint8

    Returns
    -------
    (N, 3) uint8

    Examples
    --------
    A fine black and white checkerboard under two triangles: a point sample at any vertex
    would be black or white, the averages are grey.

    >>> texture = np.zeros((64, 64, 3), np.uint8)
    >>> texture[(np.indices((64, 64)).sum(axis=0) % 2) == 0] = 255
    >>> uv = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    >>> texture_colours(uv, np.array([[0, 1, 2], [0, 2, 3]]), texture)[:, 0].tolist()
    [128, 128, 128, 128]
    """
    uv = np.asarray(uv, dtype=np.float32)
    faces = np.asarray(faces, dtype=np.intp)
    n = len(uv)
    height, width = texture.shape[:2]
    # Corner coordinates as contiguous rows (3, M): column arithmetic on (M, 3, 2) views is
    # several times slower.
    corners = faces.T.copy()
    u, v = uv[:, 0][corners], uv[:, 1][corners]
    area = 0.5 * np.abs((u[1] - u[0]) * (v[2] - v[0]) - (v[1] - v[0]) * (u[2] - u[0]))
    cu = (u[0] + u[1] + u[2]) * np.float32(1.0 / 3.0)
    cv = (v[0] + v[1] + v[2]) * np.float32(1.0 / 3.0)
    # log2 of the side of a square of the triangle's area, in texels: the pyramid level whose
    # texels are about as large as the triangle.
    levels = np.floor(0.5 * np.log2(np.maximum(area * np.float32(width * height), 1.0))).astype(np.intp)
    pyramid = _pyramid(texture, int(levels.max(initial=0)))
    np.minimum(levels, len(pyramid) - 1, out=levels)
    # All levels in one flat array of packed RGBX texels, so every triangle's colour is one
    # gather of one word whatever its level.
    shapes = np.array([image.shape for image in pyramid], dtype=np.intp)
    starts = np.concatenate([[0], np.cumsum(shapes[:, 0] * shapes[:, 1])[:-1]])
    packed = np.concatenate([image.ravel() for image in pyramid])
    h, w = shapes[levels, 0], shapes[levels, 1]
    x = np.minimum(((cu - np.floor(cu)) * w).astype(np.intp), w - 1)
    y = np.minimum(((np.ceil(cv) - cv) * h).astype(np.intp), h - 1)
    np.maximum(x, 0, out=x)
    np.maximum(y, 0, out=y)
    texels = packed[starts[levels] + y * w + x].view(np.uint8).reshape(-1, 4)
    weights = area + np.float32((1e-3 * area.mean() if len(area) else 0.0) + 1e-12)
    total = np.zeros(n)
    sums = np.zeros((n, 3))
    weighted = [texels[:, channel] * weights for channel in range(3)]
    for corner in corners:
        total += np.bincount(corner, weights, minlength=n)
        for channel in range(3):
            sums[:, channel] += np.bincount(corner, weighted[channel], minlength=n)
    lonely = total == 0
    if lonely.any():
        sums[lonely] = _texels(np.asarray(texture), uv[lonely])
        total[lonely] = 1.0
    return np.clip(np.rint(sums / total[:, None]), 0, 255).astype(np.uint8)


def _coloured(mesh, detail):
    """Fill in vertex colours from the texture when the frame has a texture and no colours;
    drop what ``detail`` does not ask for."""
    if detail != "geometry" and mesh.colours is None and mesh.uv is not None and mesh.texture is not None:
        mesh.colours = texture_colours(mesh.uv, mesh.faces, mesh.texture)
    if detail != "full":
        mesh.texture = None
        mesh.uv = None
    return mesh


# --- the readers --------------------------------------------------------------------------

@register("ply", ".ply")
def read_ply_file(path, detail="full"):
    """PLY: the fast binary path of :mod:`tvmedit.engine.capture.plyfast`, else trimesh (also for a textured
    PLY, whose header names its image in a ``comment TextureFile`` line)."""
    from .plyfast import read_ply

    with open(path, "rb") as handle:
        head = handle.read(4096).split(b"end_header")[0]
    textured = b"TextureFile" in head
    if b"format ascii" in head:
        _check_ascii_counts(path)
    fast = None if textured else read_ply(path)
    if fast is not None:
        vertices, faces, colours = fast
        return MeshData(vertices, faces, colours)
    return read_trimesh(path, detail)


def _check_ascii_counts(path):
    """An ASCII PLY holds one line per vertex and per face, as many as its header declares:
    trimesh reads the counts the header gives and drops the rest, so a header that undercounts
    would lose faces without a word."""
    data = Path(path).read_bytes()
    head, _, body = data.partition(b"end_header")
    counts = [line.split() for line in head.decode("ascii", "replace").splitlines() if line.startswith("element ")]
    try:
        declared = {words[1]: int(words[2]) for words in counts if len(words) == 3}
    except ValueError:
        return  # trimesh says what is wrong with such a header
    lines = sum(1 for line in body.split(b"\n")[1:] if line.strip())
    if lines != sum(declared.values()):
        plural = {"vertex": "vertices"}
        shown = " and ".join(f"{n} {plural.get(name, name + 's') if n != 1 else name}" for name, n in declared.items())
        raise ValueError(f"its header declares {shown} ({sum(declared.values())} lines) but it holds {lines} "
                         "lines of data; fix the counts in its header")


@register("off", ".off")
def read_off(path, detail="full"):
    """OFF/COFF: a header line, counts, one vertex per line with optional RGB(A) as 0-255
    integers or 0-1 floats, then polygons (fan-triangulated).

    trimesh's OFF reader drops per-vertex colours (COFF), which TVM frames carry.
    """
    tokens_by_line = [line.split("#")[0].split() for line in Path(path).read_text().splitlines()]
    lines = [t for t in tokens_by_line if t]
    if not lines or not lines[0][0].upper().endswith("OFF"):
        raise ValueError("no OFF header")
    header = lines[0]
    rest = header[1:] if len(header) > 1 else None
    counts, body = (rest, lines[1:]) if rest else (lines[1], lines[2:])
    n_vertices, n_faces = int(counts[0]), int(counts[1])
    if len(body) < n_vertices + n_faces:
        raise ValueError(f"expected {n_vertices} vertices and {n_faces} faces, found {len(body)} lines")
    rows = body[:n_vertices]
    vertices = np.array([[float(v) for v in row[:3]] for row in rows], dtype=np.float64).reshape(-1, 3)
    colours = None
    if rows and all(len(row) >= 6 for row in rows):
        values = np.array([[float(v) for v in row[3:6]] for row in rows])
        colours = values * 255.0 if values.max(initial=0) <= 1.0 and any("." in v for v in rows[0][3:6]) else values
        colours = np.clip(np.rint(colours), 0, 255).astype(np.uint8)
    triangles = []
    for row in body[n_vertices:n_vertices + n_faces]:
        count = int(row[0])
        ids = [int(v) for v in row[1:1 + count]]
        triangles += [(ids[0], ids[k], ids[k + 1]) for k in range(1, count - 1)]
    return MeshData(vertices, np.array(triangles, dtype=np.int64).reshape(-1, 3), colours)


@register("obj", ".obj")
def read_obj_file(path, detail="full"):
    """OBJ: the fast path of :mod:`tvmedit.engine.capture.objfast` for a frame laid out as
    exporters write one, else trimesh; the texture a material names must be there."""
    from .objfast import check_textures, read_obj

    data = Path(path).read_bytes()
    check_textures(path, data)
    fast = read_obj(path, data)
    if fast is None:
        return read_trimesh(path, detail, checked=True)
    vertices, faces, colours, uv, image = fast
    mesh = MeshData(vertices, faces, colours)
    if image is not None:   # (the texture is decoded only where it is asked for, as trimesh's is not)
        from PIL import Image

        try:
            if detail == "geometry":
                with Image.open(image):     # its header: the texture itself is not asked for
                    pass
            else:
                mesh.uv, mesh.texture = uv, read_image(image)
        except (OSError, ValueError):   # an image Pillow cannot read: trimesh's way, a plain colour
            return read_trimesh(path, detail, checked=True)
        mesh.texture_path = Path(path)
    return _coloured(mesh, detail)


def read_trimesh(path, detail="full", checked=False):
    """Any format trimesh reads, as one mesh with its vertex order kept (``process=False``).

    Vertex colours are kept; a textured mesh (OBJ with MTL, glTF base colour) gives its
    texture coordinates and image. A scene of several meshes is concatenated.
    """
    import trimesh

    if Path(path).suffix.lower() == ".obj" and not checked:
        from .objfast import check_textures

        check_textures(path)
    loaded = trimesh.load(path, process=False, maintain_order=True)
    if isinstance(loaded, trimesh.Scene):
        meshes = [g for g in loaded.dump() if isinstance(g, trimesh.Trimesh)] if hasattr(loaded, "dump") else []
        if not meshes:
            return MeshData(np.empty((0, 3)), np.empty((0, 3), np.int64))
        mesh = meshes[0] if len(meshes) == 1 else trimesh.util.concatenate(meshes)
    else:
        mesh = loaded
    vertices = np.asarray(getattr(mesh, "vertices", np.empty((0, 3))), dtype=np.float64)
    faces = np.asarray(getattr(mesh, "faces", np.empty((0, 3))))
    data = MeshData(vertices, faces)
    visual = getattr(mesh, "visual", None)
    kind = getattr(visual, "kind", None)
    if kind == "vertex":
        data.colours = np.asarray(visual.vertex_colors)[:, :3]
    elif kind == "texture" and getattr(visual, "uv", None) is not None and len(visual.uv) == len(vertices):
        image = _material_image(visual.material)
        if image is not None:
            data.uv = np.asarray(visual.uv, dtype=np.float32)
            data.texture = image
            data.texture_path = Path(path)
        else:
            colour = _material_colour(visual.material)
            if colour is not None:
                data.colours = np.broadcast_to(colour, (len(vertices), 3))
    return _coloured(data, detail)


def _material_image(material):
    image = getattr(material, "image", None)
    if image is None:
        image = getattr(material, "baseColorTexture", None)
    if image is None:
        return None
    return np.asarray(image.convert("RGB"))


def _material_colour(material):
    colour = getattr(material, "main_color", None)
    if colour is None:
        return None
    return np.asarray(colour, dtype=np.uint8)[:3]


@register("gltf", ".gltf", ".glb")
def read_gltf(path, detail="full"):
    """glTF 2.0 (``.gltf`` with its buffers, or ``.glb``), through trimesh; Y is up (the
    format's convention, which :mod:`tvmedit.engine.capture.orientation` applies)."""
    return read_trimesh(path, detail)


@register("draco", ".drc", ".draco")
def read_draco(path, detail="full"):
    """A Draco-compressed triangle mesh (DracoPy), with its texture (see :func:`texture_for`)."""
    try:
        import DracoPy
    except ImportError:
        raise ValueError("reading Draco needs the DracoPy package (pip install DracoPy)") from None
    mesh = DracoPy.decode(Path(path).read_bytes())
    vertices = np.asarray(mesh.points, dtype=np.float32).reshape(-1, 3)
    faces = np.asarray(mesh.faces).reshape(-1, 3)
    colours = getattr(mesh, "colors", None)
    data = MeshData(vertices, faces)
    if colours is not None and len(colours) == len(vertices):
        data.colours = np.asarray(colours)[:, :3].astype(np.uint8)
    uv = getattr(mesh, "tex_coord", None)
    if uv is not None and len(uv) == len(vertices) and detail != "geometry":
        image_path = texture_for(path)
        if image_path is not None:
            data.uv = np.asarray(uv, dtype=np.float32)[:, :2]
            data.texture_path = image_path
            if detail == "full" or (detail == "colours" and data.colours is None):
                data.texture = read_image(image_path)
    return _coloured(data, detail)


def texture_for(mesh_path):
    """The texture image of a frame file: the one its folder's manifest names, else the image
    beside it with the same stem (``.jpg``, ``.jpeg``, ``.png``, ``.webp``, ``.bmp``), else its
    layer of the KTX2 textures a web player's export keeps beside the frames' folder
    (:class:`tvmedit.engine.capture.ktx2.KtxLayer`), else None."""
    mesh_path = Path(mesh_path)
    folder = mesh_path.parent
    manifest = _manifest_textures(str(folder), _mtime(folder))
    if manifest is not None:
        named = manifest.get(mesh_path.name)
        if named is not None:
            return folder / named
    for suffix in IMAGE_SUFFIXES:
        for candidate in (mesh_path.with_suffix(suffix), mesh_path.with_suffix(suffix.upper())):
            if candidate.is_file():
                return candidate
    return _ktx2_layer(mesh_path)


def natural_key(path):
    """Order by the last number in the file name, so ``f2`` comes before ``f10``.

    The name and stem are cut from the text as ``pathlib`` would give them, without making a
    ``Path`` (a sort of thousands of frames calls this for each).

    >>> sorted(["f10.ply", "f2.ply", "a/.f1"], key=natural_key)
    ['a/.f1', 'f2.ply', 'f10.ply']
    """
    name = os.path.basename(os.fspath(path).rstrip(os.sep))
    dot = name.rfind(".")
    numbers = re.findall(r"\d+", name[:dot] if 0 < dot < len(name) - 1 else name)
    return (int(numbers[-1]) if numbers else -1, name)


def _ktx2_layer(mesh_path):
    """The layer of the KTX2 textures beside a web player's frames that frame ``mesh_path``
    shows: its place among its folder's frames of its kind, in natural order."""
    from .ktx2 import layer_of, texture_folder

    folder = texture_folder(mesh_path.parent)
    if folder is None:
        return None
    names = _frame_names(str(mesh_path.parent), mesh_path.parent.stat().st_mtime_ns)
    return layer_of(folder, names.index(mesh_path.name), natural_key) if mesh_path.name in names else None


@lru_cache(maxsize=16)
def _frame_names(folder, _stamp):
    """The names of a folder's Draco frames (``.drc`` and ``.draco`` alike), in natural order."""
    return [p.name for p in sorted(Path(folder).iterdir(), key=natural_key) if is_draco(p)]


def is_draco(path):
    """Whether ``path`` is a frame file the Draco reader reads (``.drc``, ``.draco``)."""
    return (reader_for(path) or ("",))[0] == "draco"


def _mtime(folder):
    stamps = []
    for name in MANIFEST_NAMES:
        try:
            stamps.append((folder / name).stat().st_mtime_ns)
        except OSError:
            stamps.append(None)
    return tuple(stamps)


@lru_cache(maxsize=64)
def _manifest_textures(folder, _stamp):
    # Worker processes read a frame at a time; the manifest is parsed once per folder.
    try:
        manifest = read_manifest(Path(folder))
    except ValueError:
        return None
    if manifest is None:
        return None
    return {Path(mesh).name: Path(texture).name for mesh, texture in zip(manifest.meshes, manifest.textures)
            if texture is not None}


# --- sequence manifests --------------------------------------------------------------------

@dataclass
class Manifest:
    """A sequence as its manifest describes it.

    path : Path, the manifest file
    meshes : list of Path, frame files in playback order
    textures : list of (Path or None), each frame's texture image
    times : (T,) float64 seconds, each frame's capture time from the first (``delay_us``
        accumulated)
    format : str, ``"scvv"``
    """

    path: Path
    meshes: list
    textures: list
    times: np.ndarray
    format: str = "scvv"


def find_manifest(folder):
    """The manifest file in ``folder`` (see :data:`MANIFEST_NAMES`), or None."""
    folder = Path(folder)
    for name in MANIFEST_NAMES:
        if (folder / name).is_file():
            return folder / name
    return None


def read_manifest(source):
    """The :class:`Manifest` of a folder or manifest file, None where there is none.

    Raises ``ValueError`` with one sentence when the manifest is malformed.

    >>> import tempfile, json, os
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     frames = [{"mesh_path": f"{k}.drc", "texture_path": f"{k}.jpg", "delay_us": d}
    ...               for k, d in [(1, 0), (2, 66000), (3, 68000)]]
    ...     _ = open(os.path.join(tmp, "scvv.json"), "w").write(json.dumps({"frames": frames}))
    ...     m = read_manifest(tmp)
    >>> [p.name for p in m.meshes], m.times.round(3).tolist()
    (['1.drc', '2.drc', '3.drc'], [0.0, 0.066, 0.134])
    """
    source = Path(source)
    path = source if source.is_file() else find_manifest(source)
    if path is None:
        return None
    try:
        data = json_value(path.read_text())
    except (OSError, ValueError) as error:
        raise ValueError(f"{path} is not valid JSON ({error}); fix it or remove it") from None
    frames = data.get("frames") if isinstance(data, dict) else None
    if not isinstance(frames, list) or not frames:
        raise ValueError(f"{path} has no \"frames\" list; a scvv manifest lists each frame's "
                         "mesh_path, texture_path and delay_us")
    meshes, textures, delays = [], [], []
    for k, frame in enumerate(frames):
        if not isinstance(frame, dict) or not isinstance(frame.get("mesh_path"), str):
            raise ValueError(f"{path}: frame {k} has no mesh_path; every frame needs one")
        meshes.append(path.parent / frame["mesh_path"])
        texture = frame.get("texture_path")
        textures.append(path.parent / texture if isinstance(texture, str) and texture else None)
        delay = frame.get("delay_us", 0)
        if isinstance(delay, bool) or not isinstance(delay, (int, float)) or not np.isfinite(delay) or delay < 0:
            raise ValueError(f"{path}: frame {k} has delay_us {delay!r}; it must be a number of "
                             "microseconds, 0 or more")
        delays.append(float(delay))
    delays[0] = 0.0
    return Manifest(path, meshes, textures, np.cumsum(delays) / 1e6)
