"""In-between frames kept in the capture's own format, so that an export copies them too.

An edit of a Draco capture (an scvv card, a web player's export) goes out as Draco frames
(:mod:`tvmedit.engine.graph.export`). Its captured frames are copied as they came; its
in-between frames (a transition's run, a loop's closing) are the library's own meshes, and
each export would encode them again: 8 ms a frame, most of an export's time, for the same
bytes every time. A library whose every sequence was read from Draco frames, in the same
capture coordinates, therefore stores each in-between frame's Draco bytes, made anew by every
build and correction (a few milliseconds a frame, on threads) as
an export makes them (:func:`tvmedit.engine.capture.writers.encode_draco`, in the capture's
coordinates, :meth:`tvmedit.engine.capture.orientation.Orientation.undo`; texture coordinates
where the frame has a texture, else its vertex colours), and an export copies them like a
captured frame's file (with the JPG of the captured frame it moves):

``blend_draco.npy``
    uint8, the frames' Draco bytes one after another (one column);
``blend_draco_frames.npy``
    int64 ``[first byte, bytes]`` per in-between frame, in ``blend_frames.npy``'s order.

A library without them (another format, sequences in other coordinates, a build before
them) has its in-between frames encoded at export, as are frames moved by ``--fps``. The bytes cost a few percent of the
library (60 kB a card frame beside 1.2 MB of arrays) and, on threads (DracoPy lets go of the
GIL), about 5 ms a frame of the build.
"""

from functools import cached_property
from pathlib import Path

import numpy as np

from . import layout

__all__ = ["CaptureCopies", "DRACO_FORMATS", "applies", "encode_blends"]

#: Sequence formats (a manifest's ``format``) read from Draco frames.
DRACO_FORMATS = ("scvv", "draco")


def applies(sequences):
    """Whether a library of ``sequences`` (with ``format`` and ``orientation``) keeps its
    in-between frames as Draco bytes: every one read from Draco frames, in the same capture
    coordinates (so each in-between frame's are those of any export)."""
    from ..capture.orientation import Orientation

    first = sequences[0].orientation or Orientation() if sequences else None
    return bool(sequences) and all(seq.format in DRACO_FORMATS and first.same_coordinates(seq.orientation)
                                   for seq in sequences)


def _encode_task(task):
    """Draco bytes of one frame, as the export encodes it: texture coordinates where it has a
    texture, else its vertex colours."""
    from ..capture.writers import encode_draco

    positions, faces, colours, uv, orientation = task
    if orientation is not None:
        positions, faces = orientation.undo(positions, faces)
    return encode_draco(positions, faces, None if uv is not None else colours, uv)


def encode_blends(folder, orientation):
    """Store the Draco bytes of every in-between frame of the library being written in
    ``folder`` (its ``blend_*.npy`` written), in the capture coordinates of ``orientation``
    (None: the files' own). Returns the number of frames encoded."""
    from ..parallel import Workers
    from .arrays import NpyStream, frame_offsets, mesh_arrays, texture_arrays

    folder = Path(folder)
    meshes = mesh_arrays(folder, "blend_")
    offsets = frame_offsets(folder, meshes, "blend_").tolist()
    uvs, _, rows = (texture_arrays(folder, len(meshes["positions"]), len(offsets), "blend_")
                    if (folder / "blend_uvs.npy").exists() else (None, None, None))
    textured = [uvs is not None and rows[k][1] > 0 for k in range(len(offsets))]   # a texture's height
    tasks = ((np.asarray(meshes["positions"][v0:v0 + nv]), np.asarray(meshes["faces"][f0:f0 + nf]),
              np.asarray(meshes["colours"][v0:v0 + nv]), np.asarray(uvs[v0:v0 + nv]) if textured[k] else None,
              orientation)
             for k, (v0, nv, f0, nf) in enumerate(offsets))
    table, stream = [], NpyStream(folder / "blend_draco.npy", np.uint8, 1)
    try:
        with Workers(None, threads=True) as pool:
            for data in pool.map(_encode_task, tasks):
                table.append((stream.rows, len(data)))
                stream.append(np.frombuffer(data, np.uint8).reshape(-1, 1))
    finally:
        stream.close()
    np.save(folder / "blend_draco_frames.npy", np.array(table, np.int64).reshape(-1, 2))
    return len(table)


class CaptureCopies:
    """What a library adds for its in-between frames' Draco bytes (a mix-in of ``Library``,
    which provides ``path``, ``manifest``, ``_locate`` and ``_blend_arrays``)."""

    @cached_property
    @layout.reads_format
    def _draco(self):
        """``(bytes (B, 1) uint8, table (n, 2))`` memory-mapped, or None."""
        if "blend_draco_frames.npy" not in self.manifest.get("files", {}):
            return None
        data = layout.load_array(self.path, "blend_draco.npy")
        table = np.asarray(layout.load_array(self.path, "blend_draco_frames.npy"))
        frames = len(layout.load_array(self.path, "blend_frames.npy"))
        if data.ndim != 2 or data.shape[1] != 1 or data.dtype != np.uint8 or table.shape != (frames, 2) or (
                len(table) and ((table < 0).any() or int((table[:, 0] + table[:, 1]).max()) > len(data))):
            raise layout.damaged(self.path, ValueError("blend_draco_frames.npy does not match blend_draco.npy"))
        return data, table

    def capture_bytes(self, key):
        """The Draco bytes of in-between frame ``key`` as an export in the capture's format
        writes it (the capture's coordinates, :func:`encode_blends`), or None: a captured
        frame, or a library that keeps none."""
        sequence, frame, *blend = key
        if not blend or blend[0] is None or self._draco is None:
            return None
        _, _, row, _ = self._locate(key)
        data, table = self._draco
        first, size = table[row].tolist()
        return data[first:first + size].tobytes()
