"""Where the player gets its meshes: the ``MeshSource`` protocol and an in-memory implementation.

A time-varying mesh changes vertex count and topology every frame, so the player asks for one
frame at a time by key ``(sequence_name, frame_index)`` and receives flat arrays it can upload
as they are (the library hands out memory-mapped slices; nothing is parsed while playing).

The protocol, which the library implements and ``ArraySource`` shows in miniature:

``frame_mesh(key) -> (positions, colours, faces, normals)``
    positions : (N, 3) float32, metres, Z up
    colours   : (N, 3) uint8, sRGB
    faces     : (M, 3) uint32, indices into the N vertices
    normals   : (N, 3) float32 unit vertex normals, or None (the renderer then shades facets)
``bounds() -> ((xmin, ymin, zmin), (xmax, ymax, zmax))``
    over every stored frame, for framing the camera once for a whole video;
``max_counts() -> (max_vertices, max_faces)``
    over every stored frame, so the renderer sizes its GPU buffers once.
``frame_texture(key) -> (uv, image) or None``, optional
    uv : (N, 2) float32 texture coordinates of the frame's vertices (v = 0 at the bottom row)
    image : (H, W, 3) uint8 sRGB, the frame's texture, first row at the top
    for textured captures; the renderer draws it instead of the vertex colours
    (:func:`texture_of` decides by the shading asked for).

Normals are computed when frames are stored (here: at construction), never per displayed frame.
"""

from typing import Protocol

import numpy as np

from ..engine.capture.normals import vertex_normals  # the library computes them so at build time
from ..engine.errors import InputError


class MeshSource(Protocol):
    """Anything the renderer can play: see the module docstring for shapes and units."""

    def frame_mesh(self, key): ...

    def bounds(self): ...

    def max_counts(self): ...


SHADINGS = ("auto", "texture", "colour")
"""``auto``: a frame's texture where it has one, else its vertex colours; ``texture``: the
textures (a source without any is refused); ``colour``: the vertex colours."""


def check_shading(source, shading):
    """Refuse a shading the source cannot give: ``texture`` on a source without textures."""
    if shading not in SHADINGS:
        raise ValueError(f"shading should be one of {', '.join(SHADINGS)}, not {shading!r}")
    if shading == "texture" and not getattr(source, "textured", False):
        raise ValueError("this library has no textures (its frames were vertex-coloured); "
                         "draw its vertex colours (shading='colour')")


def texture_of(source, key, shading="auto"):
    """The ``(uv, image)`` to draw frame ``key`` with under ``shading``, or None for its vertex colours."""
    if shading == "colour" or not getattr(source, "textured", False):
        return None
    return source.frame_texture(key)


class ArraySource:
    """A ``MeshSource`` over frames held in memory.

    Parameters
    ----------
    frames : dict mapping key -> (positions (N, 3), colours (N, 3) uint8, faces (M, 3))
        Keys are ``(sequence_name, frame_index)``; arrays are converted once to the protocol's
        dtypes and normals are computed here.

    >>> p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
    >>> c = np.full((3, 3), 200, np.uint8)
    >>> source = ArraySource({("walk", 0): (p, c, [[0, 1, 2]])})
    >>> source.max_counts()
    (3, 1)
    >>> source.bounds()
    ((0.0, 0.0, 0.0), (1.0, 1.0, 0.0))
    """

    def __init__(self, frames):
        if not frames:
            raise InputError("ArraySource needs at least one frame")
        self._frames = {key: self._checked(key, *arrays) for key, arrays in frames.items()}
        lows = np.array([m[0].min(axis=0) for m in self._frames.values()])
        highs = np.array([m[0].max(axis=0) for m in self._frames.values()])
        self._bounds = (tuple(lows.min(axis=0).tolist()), tuple(highs.max(axis=0).tolist()))
        self._max_counts = (max(len(m[0]) for m in self._frames.values()),
                            max(len(m[2]) for m in self._frames.values()))

    def frame_mesh(self, key):
        try:
            return self._frames[key]
        except KeyError:
            raise InputError(f"frame {key!r} is not in this source") from None

    def bounds(self):
        return self._bounds

    def max_counts(self):
        return self._max_counts

    @staticmethod
    def _checked(key, positions, colours, faces):
        positions = np.ascontiguousarray(positions, dtype=np.float32)
        colours = np.asarray(colours)
        faces = np.asarray(faces)
        if positions.ndim != 2 or positions.shape[1] != 3 or len(positions) == 0:
            raise InputError(f"frame {key!r}: positions should be a non-empty (N, 3) array, got shape {positions.shape}")
        if not np.isfinite(positions).all():
            raise InputError(f"frame {key!r}: positions contain NaN or infinite values")
        if colours.shape != positions.shape:
            raise InputError(f"frame {key!r}: colours should be ({len(positions)}, 3) like the positions, got shape {colours.shape}")
        if colours.dtype != np.uint8:
            if colours.min() < 0 or colours.max() > 255:
                raise InputError(f"frame {key!r}: colours should be uint8 sRGB values in 0..255")
            colours = colours.astype(np.uint8)
        if faces.ndim != 2 or faces.shape[1] != 3:
            raise InputError(f"frame {key!r}: faces should be an (M, 3) array, got shape {faces.shape}")
        if len(faces) and (faces.min() < 0 or faces.max() >= len(positions)):
            raise InputError(f"frame {key!r}: faces index vertices outside 0..{len(positions) - 1}")
        faces = np.ascontiguousarray(faces, dtype=np.uint32)
        colours = np.ascontiguousarray(colours)
        return positions, colours, faces, vertex_normals(positions, faces)
