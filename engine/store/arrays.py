"""The stored meshes' flat arrays, written as frames stream in and read back memory-mapped.

Every stored frame's vertices, colours, normals and faces lie one after another in flat
arrays (:data:`MESH_ARRAYS`), with ``frames.npy`` giving each frame's ranges and
``frame_keys.npy`` its sequence and frame (after a rebuild that added frames, in those and
the parts beside them, ``part1_*.npy`` ..., read as one: :func:`parts`, :class:`PartedArray`);
textured frames add ``uvs.npy`` and their texels (:mod:`tvmedit.engine.store.layout` lists
every file of a library). Flat arrays plus ranges
(as Motion-Matching's database keeps its frames) let the player stream without parsing:
:class:`MeshWriter` appends frames to growing ``.npy`` files whose lengths are known only at
the end (:class:`NpyStream`), and the readers here check the arrays' shapes against each
other before anything is drawn from them.
"""

from pathlib import Path

import numpy as np

from .layout import damaged, load_array

__all__ = ["MESH_ARRAYS", "NpyStream", "MeshWriter", "Spooled", "spool", "PartedArray", "parts", "mesh_arrays", "frame_offsets", "frame_keys",
           "texture_arrays"]

#: The flat per-vertex and per-face arrays of the stored meshes: name, dtype, width.
MESH_ARRAYS = (("positions", np.float32, 3), ("colours", np.uint8, 3), ("normals", np.float32, 3),
               ("faces", np.uint32, 3))


class NpyStream:
    """An ``.npy`` file of rows appended in pieces, whose length is known only at the end.

    The header is written last, into a fixed 128 bytes reserved at the start (numpy's own
    header for a 2-D array is that long), so the rows go straight to disk and are never
    copied.
    """

    HEADER = 128

    def __init__(self, path, dtype, width):
        self.path, self.dtype, self.width, self.rows = path, np.dtype(dtype), width, 0
        self.handle = open(path, "wb")
        self.handle.write(b"\0" * self.HEADER)

    def append(self, array):
        array = np.ascontiguousarray(array, dtype=self.dtype)
        self.handle.write(memoryview(array).cast("B"))
        self.rows += len(array)

    def copy_rows(self, path, start, stop):
        """Append rows ``start:stop`` of the ``.npy`` file ``path`` (same dtype and width) byte for
        byte, in the kernel where it can (``os.copy_file_range``), never through numpy."""
        start, stop = int(start), int(stop)
        source = np.load(path, mmap_mode="r")
        if source.dtype != self.dtype or source.shape[1:] != (self.width,) or not 0 <= start <= stop <= len(source):
            raise ValueError(f"{path} does not hold rows {start}:{stop} of {self.dtype} x {self.width}")
        size = self.dtype.itemsize * self.width
        self.copy_bytes(path, source.offset + start * size, (stop - start) * size)

    def copy_bytes(self, path, offset, length):
        """Append ``length`` bytes of file ``path`` from ``offset`` on, whole rows of this
        stream's dtype and width, in the kernel where it can (``os.copy_file_range``)."""
        import os

        size = self.dtype.itemsize * self.width
        if length % size:
            raise ValueError(f"{length} bytes of {path} are not whole rows of {self.dtype} x {self.width}")
        self.handle.flush()
        left = length
        with open(path, "rb") as handle:
            while left:
                try:
                    done = os.copy_file_range(handle.fileno(), self.handle.fileno(), left, offset)
                except (AttributeError, OSError):
                    handle.seek(offset)
                    done = os.write(self.handle.fileno(), handle.read(min(left, 1 << 26)))
                if not done:
                    raise ValueError(f"{path} ends before byte {offset + left}")
                offset, left = offset + done, left - done
        self.handle.seek(0, os.SEEK_END)
        self.rows += length // size

    def close(self):
        header = {"descr": np.lib.format.dtype_to_descr(self.dtype), "fortran_order": False,
                  "shape": (self.rows, self.width)}
        text = repr(header).encode("latin1")
        length = self.HEADER - 10
        if len(text) + 1 > length:
            raise ValueError(f"npy header too long for {self.path}")
        self.handle.seek(0)
        self.handle.write(b"\x93NUMPY\x01\x00" + length.to_bytes(2, "little")
                          + text + b" " * (length - len(text) - 1) + b"\n")
        self.handle.close()


def _bounds(positions):
    """``(low, high)`` corners of a frame's positions (N, 3)."""
    rows = np.ascontiguousarray(np.asarray(positions).T)  # reduced as rows: 20x faster than by axis 0
    return rows.min(axis=1), rows.max(axis=1)


class _Rows:
    """``rows`` rows of an array that lie as ``nbytes`` raw bytes from ``offset`` in file ``path``."""

    def __init__(self, path, offset, nbytes, rows):
        self.path, self.offset, self.nbytes, self.rows = path, offset, nbytes, rows

    def __len__(self):
        return self.rows


class Spooled:
    """A frame's mesh written by a worker process into a spool file (:func:`spool`).

    ``parts`` gives ``(offset, bytes, rows)`` of its positions, colours, normals and faces in
    file ``path``; ``bounds`` its positions' corners; ``uv`` and ``texture`` travel as they are
    (None for an untextured frame).
    """

    def __init__(self, path, parts, bounds, uv, texture):
        self.path, self.parts, self.bounds, self.uv, self.texture = path, parts, bounds, uv, texture


def spool(path, meshes):
    """Write ``meshes`` ``(positions, colours, faces, normals, uv, texture)`` as raw bytes to file
    ``path`` and return a :class:`Spooled` for each, for :meth:`MeshWriter.add_spooled`.

    A worker process that hands a frame's arrays back pickles them, and the builder unpickles
    and writes them: about 1 ms a frame of 17,000 vertices, a third of what reading the frame
    costs. Written to a file beside the library instead, they reach the library's arrays by
    ``os.copy_file_range``, which copies in the kernel (page cache to page cache).
    """
    spooled = []
    with open(path, "wb") as handle:
        for positions, colours, faces, normals, uv, texture in meshes:
            parts = []
            for array, (_, dtype, _) in zip((positions, colours, normals, faces), MESH_ARRAYS):
                array = np.ascontiguousarray(array, dtype=dtype)
                parts.append((handle.tell(), array.nbytes, len(array)))
                handle.write(memoryview(array).cast("B"))
            spooled.append(Spooled(str(path), parts, _bounds(positions), uv, texture))
    return spooled


class MeshWriter:
    """Streams stored frames into the flat mesh arrays of folder ``folder``; use as a context.

    ``bounds`` and ``max_counts`` (for the manifest) are known once every frame is added.
    With ``prefix="blend_"`` it writes the in-between frames' arrays (no frame keys).
    """

    def __init__(self, folder, prefix=""):
        folder = Path(folder)
        self._folder, self._prefix = folder, prefix
        self._arrays = {name: NpyStream(folder / f"{prefix}{name}.npy", dtype, width)
                        for name, dtype, width in MESH_ARRAYS}
        # Texture arrays are opened at the first textured frame: untextured libraries have none.
        self._uvs = self._texels = None
        self._texture_rows = []
        self._offsets = NpyStream(folder / f"{prefix}frames.npy", np.int64, 4)
        self._keys = None if prefix == "blend_" else NpyStream(folder / f"{prefix}frame_keys.npy", np.int64, 2)
        self._low, self._high = np.full(3, np.inf), np.full(3, -np.inf)
        self._starts = [0, 0]
        self.frames = 0
        self.max_counts = (0, 0)

    def add(self, sequence_index, frame, positions, colours, faces, normals, uv=None, texture=None,
            texture_row=None, bounds=None):
        """Append frame ``frame`` of the ``sequence_index``-th sequence, with its texture
        coordinates (N, 2) and texture image (H, W, 3) uint8 (or ``texture_row``, one stored
        already) when it is textured. An array may be :class:`_Rows` of a spool file (then
        ``bounds``, the positions' ``(low, high)``, comes with it)."""
        for name, array in (("positions", positions), ("colours", colours), ("normals", normals),
                            ("faces", faces)):
            if isinstance(array, _Rows):
                self._arrays[name].copy_bytes(array.path, array.offset, array.nbytes)
            else:
                self._arrays[name].append(array)
        v0, f0 = self._starts
        if uv is not None and (texture is not None or (texture_row is not None and texture_row[1])):
            if self._uvs is None:
                self._uvs = NpyStream(self._folder / f"{self._prefix}uvs.npy", np.float32, 2)
                for start in range(0, v0, 1 << 20):
                    self._uvs.append(np.zeros((min(1 << 20, v0 - start), 2), np.float32))
            self._uvs.append(uv)
            if texture_row is None:
                self._texels = self._texels or NpyStream(self._folder / "textures.npy", np.uint8, 3)
                texture_row = [self._texels.rows, texture.shape[0], texture.shape[1]]
                self._texels.append(np.asarray(texture).reshape(-1, 3))
            self._texture_rows.append([int(x) for x in texture_row])
        else:
            if self._uvs is not None:
                self._uvs.append(np.zeros((len(positions), 2), np.float32))
            self._texture_rows.append([0, 0, 0])
        self._offsets.append(np.array([[v0, len(positions), f0, len(faces)]]))
        if self._keys is not None:
            self._keys.append(np.array([[sequence_index, frame]]))
        self._starts = [v0 + len(positions), f0 + len(faces)]
        self.max_counts = (max(self.max_counts[0], len(positions)), max(self.max_counts[1], len(faces)))
        low, high = _bounds(positions) if bounds is None else bounds
        np.minimum(self._low, low, out=self._low)
        np.maximum(self._high, high, out=self._high)
        self.frames += 1

    def add_spooled(self, sequence_index, frame, spooled):
        """Append frame ``frame`` of the ``sequence_index``-th sequence from a :class:`Spooled`
        file a worker wrote (:func:`spool`): its arrays copied in the kernel, never unpickled."""
        positions, colours, normals, faces = (_Rows(spooled.path, *part) for part in spooled.parts)
        self.add(sequence_index, frame, positions, colours, faces, normals, spooled.uv, spooled.texture,
                 bounds=spooled.bounds)

    def copy_frames(self, library, rows, keys):
        """Append the stored frames ``rows`` (consecutive rows, untextured) of ``library`` (an
        :class:`tvmedit.engine.store.library.Library`) as frames ``keys`` (``(sequence index, frame)``), byte for
        byte. Their bounds are taken as the library's (its corners over all its frames)."""
        part, first = part_of(library.path, rows[0])
        offsets = np.asarray(load_array(library.path, f"{part}frames.npy"))[rows[0] - first:rows[-1] - first + 1]
        if len(offsets) != len(rows) or len(keys) != len(rows):
            raise ValueError("copy_frames takes consecutive rows of one part, one key each")
        (v0, f0), (v1, f1) = offsets[0, [0, 2]].tolist(), (offsets[-1, [0, 2]] + offsets[-1, [1, 3]]).tolist()
        for name, _, _ in MESH_ARRAYS:
            self._arrays[name].copy_rows(Path(library.path) / f"{part}{name}.npy",
                                         *((f0, f1) if name == "faces" else (v0, v1)))
        if self._uvs is not None:
            self._uvs.append(np.zeros((v1 - v0, 2), np.float32))
        self._texture_rows += [[0, 0, 0]] * len(rows)
        moved = offsets - np.array([v0 - self._starts[0], 0, f0 - self._starts[1], 0])
        self._offsets.append(moved)
        self._keys.append(np.asarray(keys, np.int64).reshape(-1, 2))
        self._starts = [self._starts[0] + int(v1 - v0), self._starts[1] + int(f1 - f0)]
        self.max_counts = (max(self.max_counts[0], int(offsets[:, 1].max())),
                           max(self.max_counts[1], int(offsets[:, 3].max())))
        low, high = library.bounds()
        np.minimum(self._low, low, out=self._low)
        np.maximum(self._high, high, out=self._high)
        self.frames += len(rows)

    @property
    def bounds(self):
        """``(low, high)`` corners over every frame added (zeros when none)."""
        if not self.frames:
            return [0.0] * 3, [0.0] * 3
        return self._low.tolist(), self._high.tolist()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        for stream in (*self._arrays.values(), self._offsets, self._keys, self._uvs, self._texels):
            if stream is not None:
                stream.close()
        if self._uvs is not None:
            np.save(self._folder / f"{self._prefix}texture_frames.npy",
                    np.array(self._texture_rows, np.int64).reshape(-1, 3))


def part_rows(path):
    """``(prefix, first row, frames)`` of each part (:func:`parts`) of the stored frames."""
    rows, first = [], 0
    for part in parts(path):
        count = len(load_array(path, f"{part}frames.npy"))
        rows.append((part, first, count))
        first += count
    return rows


def part_of(path, row):
    """``(prefix, first row)`` of the part (:func:`parts`) that holds stored frame ``row``."""
    for part, first, count in part_rows(path):
        if row < first + count:
            return part, first
    raise IndexError(f"no stored frame {row} in {path}")


def parts(path):
    """The prefixes of the stored frames' parts in the library folder ``path``: ``""`` (the
    frames a build stored) and ``"part1_"``, ``"part2_"`` ... (the frames a rebuild added
    beside them, :mod:`tvmedit.engine.store.meshfiles`), in storage order."""
    found = [""]
    while (Path(path) / f"part{len(found)}_frames.npy").exists():
        found.append(f"part{len(found)}_")
    return found


class PartedArray:
    """The rows of several parts' arrays read as one: ``len``, ``shape``, ``dtype`` and slices
    that lie within one part (a frame's rows never straddle two), each a view of its part."""

    def __init__(self, pieces):
        self.pieces = pieces
        self.starts = np.cumsum([0] + [len(piece) for piece in pieces])
        self.dtype, self.ndim = pieces[0].dtype, pieces[0].ndim
        self.shape = (int(self.starts[-1]), *pieces[0].shape[1:])

    def __len__(self):
        return self.shape[0]

    def __getitem__(self, rows):
        start, stop, step = rows.indices(len(self)) if isinstance(rows, slice) else (None, None, None)
        if step != 1:
            raise TypeError("a parted array is read in slices of rows")
        k = min(int(np.searchsorted(self.starts, start, side="right")) - 1, len(self.pieces) - 1)
        if stop > self.starts[k + 1]:
            raise IndexError(f"rows {start}:{stop} straddle two parts")
        return self.pieces[k][start - self.starts[k]:stop - self.starts[k]]


def _part_arrays(path, prefix):
    arrays = {name: load_array(path, f"{prefix}{name}.npy") for name, _, _ in MESH_ARRAYS}
    for name, dtype, width in MESH_ARRAYS:
        array = arrays[name]
        if array.ndim != 2 or array.shape[1] != width or array.dtype != dtype:
            raise damaged(path, ValueError(f"{prefix}{name}.npy holds {array.dtype} {array.shape}"))
    if not len(arrays["positions"]) == len(arrays["colours"]) == len(arrays["normals"]):
        raise damaged(path, ValueError("the vertex arrays differ in length"))
    return arrays


def mesh_arrays(path, prefix=""):
    """The flat mesh arrays of :data:`MESH_ARRAYS` (``prefix="blend_"``: of the in-between
    frames), memory-mapped, their shapes checked; the stored frames' parts (:func:`parts`)
    read as one (:class:`PartedArray`)."""
    prefixes = parts(path) if prefix == "" else [prefix]
    if len(prefixes) == 1:
        return _part_arrays(path, prefix)
    pieces = [_part_arrays(path, part) for part in prefixes]
    return {name: PartedArray([piece[name] for piece in pieces]) for name, _, _ in MESH_ARRAYS}


def frame_offsets(path, arrays, prefix=""):
    """``frames.npy`` as an (n, 4) int64 array, every frame's range inside the mesh arrays
    (the parts' ranges one after another, as :func:`mesh_arrays` reads them)."""
    pieces = ([dict(zip(arrays, part)) for part in zip(*(array.pieces for array in arrays.values()))]
              if isinstance(arrays["positions"], PartedArray) else [arrays])
    prefixes = parts(path) if len(pieces) > 1 else [prefix]
    tables, vertices, faces = [], 0, 0
    for part, piece in zip(prefixes, pieces):
        offsets = np.asarray(load_array(path, f"{part}frames.npy"))
        ok = offsets.ndim == 2 and offsets.shape[1] == 4 and offsets.dtype == np.int64
        if ok and len(offsets):
            v0, nv, f0, nf = offsets.T
            ok = bool((offsets >= 0).all() and (v0 + nv <= len(piece["positions"])).all()
                      and (f0 + nf <= len(piece["faces"])).all())
        if not ok:
            raise damaged(path, ValueError(f"{part}frames.npy does not match the mesh arrays"))
        tables.append(offsets + np.array([vertices, 0, faces, 0]) if len(offsets) else offsets)
        vertices, faces = vertices + len(piece["positions"]), faces + len(piece["faces"])
    return tables[0] if len(tables) == 1 else np.concatenate(tables)


def frame_keys(path, frames, sequences):
    """``frame_keys.npy`` (and its parts') as an (n, 2) int64 array of (sequence index, frame),
    checked."""
    keys = [np.asarray(load_array(path, f"{part}frame_keys.npy")) for part in parts(path)]
    # Parts of another shape cannot be joined: the check below then refuses them.
    keys = np.concatenate(keys) if all(k.ndim == 2 and k.shape[1:] == (2,) for k in keys) else np.zeros((0, 0))
    ok = keys.ndim == 2 and keys.shape == (frames, 2) and keys.dtype == np.int64
    if not ok or (len(keys) and not ((keys[:, 0] >= 0) & (keys[:, 0] < sequences) & (keys[:, 1] >= 0)).all()):
        raise damaged(path, ValueError("frame_keys.npy does not match frames.npy and the sequences"))
    return keys


def texture_arrays(path, vertices, frames, prefix=""):
    """``(uvs (V, 2), texels (T, 3), rows (n, 3))`` memory-mapped, every frame's texels inside."""
    uvs, texels = load_array(path, f"{prefix}uvs.npy"), load_array(path, "textures.npy")
    rows = np.asarray(load_array(path, f"{prefix}texture_frames.npy"))
    ok = (uvs.shape == (vertices, 2) and texels.ndim == 2 and texels.shape[1] == 3
          and rows.shape == (frames, 3) and rows.dtype == np.int64)
    if ok and len(rows):
        start, height, width = rows.T
        ok = bool((rows >= 0).all() and (start + height * width <= len(texels)).all())
    if not ok:
        raise damaged(path, ValueError("the texture arrays do not match the meshes"))
    return uvs, texels, rows
