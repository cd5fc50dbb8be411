"""KTX2 textures as web volumetric players ship them: Basis Universal, several frames to a file.

A web player's export (UVOL 2, and the layouts derived from it) keeps one Draco mesh a frame in
``geometry_draco/`` and the textures beside it in a folder such as
``texture_ktx2-fps30-1k_baseColor_default/``: KTX2 files (Khronos KTX 2.0) holding Basis
Universal video textures (``basisu -ktx2 -tex_type video``), each an array of layers, one a
frame, a few frames to a file (the encoder's batch size). Frame ``i`` of the geometry shows
layer ``i`` counted over the files in name order (:func:`layer_of`; the reader of the frames,
:func:`tvmedit.engine.capture.readers.texture_for`, counts ``i``); a file's layer count is its
header's ``layerCount`` (bytes 32-35; 0 means one).

Decoding: Basis Universal (ETC1S and UASTC, supercompressed or not) is transcoded by the
``alktx2`` package, a binding of Binomial's own ``basisu`` transcoder that ships wheels for
CPython 3.11-3.13 on x86-64 Linux; libktx's binding (``pyktx``) needs the C library built and
installed by hand, and no other maintained Python decoder reads Basis. It is an optional
dependency (``pip install 'tvmedit[ktx2]'``): without it a KTX2 texture is one sentence saying
so. The decoder gives RGBA rows in the order stored.

Which way up: a KTX2 file may say how its rows run (the ``KTXorientation`` key, ``"ru"``: from
the bottom up; ``"rd"``: from the top down). Where it does not, its rows are taken to run up,
as the uvol encoder stores them (``basisu -y_flip``, which writes no such key) and as OpenGL
and WebGL upload a compressed texture: the first row stored is the one at v = 0. Either way
:func:`read_layer` returns the image with row 0 at the top, as every other reader does. (The
surface cannot tell: flipping an image keeps neighbouring texels neighbours, so a texture read
upside down is as smooth across the mesh's edges as one read the right way up.)
"""

import struct
from functools import lru_cache
from pathlib import Path
from typing import NamedTuple

import numpy as np

from ..errors import InputError, TvmError

__all__ = ["KtxLayer", "layer_count", "texture_folder", "layer_of", "read_layer", "rows_run_up", "IDENTIFIER"]

#: The first twelve bytes of every KTX 2.0 file.
IDENTIFIER = b"\xabKTX 20\xbb\r\n\x1a\n"


class KtxLayer(NamedTuple):
    """Layer ``layer`` of the KTX2 file ``path``: one frame's texture."""

    path: Path
    layer: int

    @property
    def suffix(self):
        return ".ktx2"

    def __str__(self):
        return f"{self.path} (layer {self.layer})"


def layer_count(path):
    """The frames (array layers) of KTX2 file ``path``; InputError where it is not KTX2.

    >>> import tempfile, os
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = os.path.join(folder, "t.ktx2")
    ...     _ = open(path, "wb").write(IDENTIFIER + struct.pack("<9I", 0, 1, 64, 32, 0, 5, 1, 1, 1))
    ...     layer_count(path)
    5
    """
    with open(path, "rb") as handle:
        head = handle.read(48)
    if head.startswith(b"version https://git-lfs"):
        raise InputError(f"texture {path} is a Git LFS pointer, not the texture; fetch it with `git lfs pull` "
                         "in the clone the capture came from.")
    if len(head) < 48 or head[:12] != IDENTIFIER:
        raise InputError(f"texture {path} is not a KTX2 file (its first bytes are not KTX 2.0's identifier); "
                         "export the textures again or move the file out of the folder.")
    return max(1, struct.unpack("<I", head[32:36])[0])


def texture_folder(frames_folder):
    """The folder of KTX2 textures of a folder of mesh frames, or None: the frames folder itself
    where it holds ``.ktx2`` files, else one of its siblings that does, a base colour's first
    where there are several (a player ships normal or roughness maps too)."""
    frames_folder = Path(frames_folder)
    stamps = tuple(_mtime(p) for p in (frames_folder, frames_folder.parent))
    return _texture_folder(str(frames_folder), stamps)


def _mtime(path):
    try:
        return path.stat().st_mtime_ns
    except OSError:
        return None


@lru_cache(maxsize=64)
def _texture_folder(frames_folder, _stamps):
    frames_folder = Path(frames_folder)
    if any(frames_folder.glob("*.ktx2")):
        return frames_folder
    siblings = sorted(p for p in frames_folder.parent.iterdir()
                      if p.is_dir() and p != frames_folder and any(p.glob("*.ktx2")))
    colour = [p for p in siblings if "basecolor" in p.name.lower() or "albedo" in p.name.lower()]
    return (colour or siblings or [None])[0]


@lru_cache(maxsize=16)
def _layers(folder, order, _stamp):
    """``[(file, layer), ...]``: every frame's texture over a folder's KTX2 files, in ``order``."""
    table = []
    for path in sorted(Path(folder).glob("*.ktx2"), key=order):
        table += [(path, layer) for layer in range(layer_count(path))]
    return table


def layer_of(folder, index, order=None):
    """The :class:`KtxLayer` of frame ``index`` (counted from 0) over the KTX2 files of ``folder``
    in ``order`` (a sort key of paths; default: by name), or None past the last layer."""
    folder = Path(folder)
    stamp = tuple((p.name, p.stat().st_mtime_ns) for p in sorted(folder.glob("*.ktx2")))
    table = _layers(str(folder), order or (lambda path: path.name), stamp)
    return KtxLayer(*table[index]) if 0 <= index < len(table) else None


@lru_cache(maxsize=4)
def _file_bytes(path, _stamp):
    return Path(path).read_bytes()


def rows_run_up(data):
    """Whether the KTX2 file ``data`` stores its rows from the bottom up: its ``KTXorientation``
    says so (``"ru"``) or it says nothing (the uvol encoder's convention, see the module).

    >>> kvd = b"KTXorientation\\0rd\\0"
    >>> head = IDENTIFIER + bytes(44) + struct.pack("<2I", 80, len(kvd) + 4)
    >>> rows_run_up(head + bytes(80 - len(head)) + struct.pack("<I", len(kvd)) + kvd), rows_run_up(head)
    (False, True)
    """
    if len(data) < 64:
        return True
    at, size = struct.unpack("<2I", data[56:64])
    values, end = data[at:at + size], 0
    while end + 4 <= len(values):
        length = struct.unpack("<I", values[end:end + 4])[0]
        key, _, value = values[end + 4:end + 4 + length].partition(b"\0")
        if key == b"KTXorientation":
            return value[1:2] != b"d"
        end += 4 + length + (-length % 4)
    return True


def read_layer(texture):
    """(H, W, 3) uint8 RGB of a :class:`KtxLayer`, row 0 at the top (:func:`rows_run_up`)."""
    import io

    from PIL import Image

    try:
        import alktx2
    except ImportError:
        raise TvmError(f"{texture.path} is a KTX2 (Basis Universal) texture, which needs the alktx2 package; "
                       "install it with: pip install 'tvmedit[ktx2]'.") from None
    path = Path(texture.path)
    data = _file_bytes(str(path), path.stat().st_mtime_ns)
    try:
        picture, _ = alktx2.decode_ktx2_to_bytes(data, format="tga", layer=int(texture.layer))
    except Exception as error:  # the binding raises RuntimeError and ValueError alike
        raise InputError(f"texture {texture} cannot be decoded as Basis Universal KTX2 ({error}); export the "
                         "textures again.") from None
    with Image.open(io.BytesIO(picture)) as image:
        rgb = np.asarray(image.convert("RGB"))
    return np.ascontiguousarray(rgb[::-1]) if rows_run_up(data) else rgb
