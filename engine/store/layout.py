"""The library's on-disk format, written and read in this one place.

A library is a directory written by :func:`tvmedit.build` and opened by
:class:`tvmedit.engine.store.library.Library`; nothing in it is parsed while playing. Its files:

``manifest.json``
    format version, tvmedit version, build parameters, and per sequence its name, fps,
    frame count, rows in ``features.npy`` (and ``features_centred.npy``), r width, origin,
    feature cache key, frame files
    (resolved path, size, mtime_ns) and skipped frames; the size of every file below (checked
    on open), the bounds of the stored meshes and their largest vertex and face counts.
``features.npy``
    (T, D) float32: one feature vector per frame of every sequence in order (eq. (1)-(4)),
    r histograms zero-padded to the library's widest, then theta, then phi.
``features_centred.npy``
    only where the origin of some sequence stays put: its frames' histograms about each
    frame's own centre (:attr:`tvmedit.engine.features.Features.centred`, which the parser's turn veto
    reads), as ``features.npy``, sequence after sequence, r padded to the widest of them
    (``feature_columns.centred_r`` in the manifest); the manifest gives a sequence's
    ``centred_rows`` and ``centred_r_bins``. A library without it
    (built before) opens as before: its sequences have no centred features.
``structure.json``
    per sequence, its parsed structure (section 4): clusters, textons, the atom-distance curve.
``database.json``
    the motion database (section 5): nodes with id, default name, sequence, inclusive frame
    range, cluster, texton distance and intensity.
``graph.json``
    the complete graph's weights ``[[i, j, w], ...]`` (eq. (12)), transition frames
    ``[[i, j, exit, entry], ...]`` (eq. (10), frames within each node's sequence) and mu; the
    pruned graph (eq. (14)) is rebuilt from them on open.
``graph.graphml``
    the pruned graph for other tools (``networkx.read_graphml(path, node_type=int)``).
``positions.npy``, ``colours.npy``, ``normals.npy``
    (V, 3) float32, uint8, float32: vertices of every stored frame, one after another.
``faces.npy``
    (F, 3) uint32, indices local to each frame.
``frames.npy``
    (n, 4) int64 per stored frame: vertex start, vertex count, face start, face count.
``frame_keys.npy``
    (n, 2) int64 per stored frame: sequence index (manifest order) and frame number.
``blend_*.npy``, ``blends.json``
    the in-between frames (:mod:`tvmedit.engine.inbetween.blend`) as the frames above (no keys; texture rows into
    ``textures.npy``), run after run; per graph edge ``{"from", "to", "first", "count", "jump",
    "steps", "exit", "entry"}`` (first row, Chamfer of the cut and of each step in metres, exit
    and entry ``[sequence, frame]``); ``wraps`` likewise per closed loop (:mod:`tvmedit.engine.inbetween.loops`:
    from = to, exit the end, entry the start, ``at``, ``texton``); ``natural_step``, ``blend_frames``,
    ``feature_keys``, ``pair_steps`` (``[sequence, frame, step]`` the natural step is the median of).
``uvs.npy``, ``textures.npy``, ``texture_frames.npy``
    only where some stored frame is textured: (V, 2) float32 texture coordinates beside
    ``positions`` (zeros for untextured frames); the texture images' RGB texels one frame
    after another, (P, 3) uint8, each image's rows top first; (n, 3) int64 per stored frame:
    first texel, height, width (0, 0, 0 for an untextured frame).
``names.json``
    optional; node names given with ``tvmedit rename`` (``{"id": "name"}``).
``corrections.json``, ``parse.json``
    only where the parse was corrected by hand (:mod:`tvmedit.engine.store.corrections`): the corrections,
    and the automatic parse they were applied to (as ``structure.json``, which then holds the
    corrected one).

Only the frames of database textons are stored (after a correction by hand, possibly
some more: :mod:`tvmedit.engine.store.meshfiles` keeps a library's arrays rather than copy them), and
the in-between frames of the transitions. Every array opens with
``np.load(..., mmap_mode="r")``, so opening reads only the small JSON files.
"""

import dataclasses
import json
import time
from pathlib import Path

import numpy as np

from .. import safewrite
from ..errors import LibraryError, build_call, not_a_library

__all__ = ["FORMAT", "CHECKED_FILES", "MESH_ARRAYS", "NpyStream", "MeshWriter", "write_json",
           "graph_to_json", "read_graph", "write_graphml", "sequence_record", "manifest",
           "write_manifest", "read_manifest", "legacy_foreign", "load_array", "read_json",
           "read_names", "write_names", "tvmedit_version", "write_corrections", "read_corrections",
           "read_parse", "link_meshes", "read_blends", "write_features", "read_features"]

#: On-disk format version; a library of another version must be rebuilt.
FORMAT = 2

#: Files whose sizes the manifest records and :func:`read_manifest` checks.
CHECKED_FILES = ("features.npy", "features_centred.npy", "structure.json", "database.json", "graph.json",
                 "positions.npy",
                 "colours.npy", "normals.npy", "faces.npy", "frames.npy", "frame_keys.npy",
                 "uvs.npy", "textures.npy", "texture_frames.npy", "corrections.json", "parse.json",
                 "blends.json", "blend_positions.npy", "blend_colours.npy", "blend_normals.npy",
                 "blend_faces.npy", "blend_frames.npy", "blend_uvs.npy", "blend_texture_frames.npy")

#: The flat per-vertex and per-face arrays of the stored meshes: name, dtype, width.
MESH_ARRAYS = (("positions", np.float32, 3), ("colours", np.uint8, 3), ("normals", np.float32, 3),
               ("faces", np.uint32, 3))


def tvmedit_version():
    """The installed tvmedit's version, recorded in every manifest."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("tvmedit")
    except PackageNotFoundError:  # running from a source tree that was never installed
        return "0.0.0+unknown"


# --- writing ------------------------------------------------------------------------------

def _json_default(value):
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.floating):
        return float(value)
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, tuple):
        return list(value)
    if dataclasses.is_dataclass(value):
        return dataclasses.asdict(value)
    raise TypeError(f"cannot store {type(value).__name__} in JSON")


def write_json(path, data):
    """Write ``data`` compactly (numpy scalars and arrays, tuples and dataclasses allowed)."""
    Path(path).write_text(json.dumps(data, default=_json_default, separators=(",", ":")))


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
        import os

        start, stop = int(start), int(stop)
        source = np.load(path, mmap_mode="r")
        if source.dtype != self.dtype or source.shape[1:] != (self.width,) or not 0 <= start <= stop <= len(source):
            raise ValueError(f"{path} does not hold rows {start}:{stop} of {self.dtype} x {self.width}")
        size = self.dtype.itemsize * self.width
        offset, left = source.offset + start * size, (stop - start) * size
        self.handle.flush()
        with open(path, "rb") as handle:
            while left:
                try:
                    done = os.copy_file_range(handle.fileno(), self.handle.fileno(), left, offset)
                except (AttributeError, OSError):
                    handle.seek(offset)
                    done = os.write(self.handle.fileno(), handle.read(min(left, 1 << 26)))
                if not done:
                    raise ValueError(f"{path} ends before row {stop}")
                offset, left = offset + done, left - done
        self.handle.seek(0, os.SEEK_END)
        self.rows += stop - start

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
        self._keys = None if prefix else NpyStream(folder / "frame_keys.npy", np.int64, 2)
        self._low, self._high = np.full(3, np.inf), np.full(3, -np.inf)
        self._starts = [0, 0]
        self.frames = 0
        self.max_counts = (0, 0)

    def add(self, sequence_index, frame, positions, colours, faces, normals, uv=None, texture=None,
            texture_row=None):
        """Append frame ``frame`` of the ``sequence_index``-th sequence, with its texture
        coordinates (N, 2) and texture image (H, W, 3) uint8 (or ``texture_row``, one stored
        already) when it is textured."""
        for name, array in (("positions", positions), ("colours", colours), ("normals", normals),
                            ("faces", faces)):
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
        np.minimum(self._low, positions.min(axis=0), out=self._low)
        np.maximum(self._high, positions.max(axis=0), out=self._high)
        self.frames += 1

    def copy_frames(self, library, rows, keys):
        """Append the stored frames ``rows`` (consecutive rows, untextured) of ``library`` (an
        :class:`tvmedit.engine.store.library.Library`) as frames ``keys`` (``(sequence index, frame)``), byte for
        byte. Their bounds are taken as the library's (its corners over all its frames)."""
        offsets = frame_offsets(library.path, mesh_arrays(library.path))[rows[0]:rows[-1] + 1]
        if len(offsets) != len(rows) or len(keys) != len(rows):
            raise ValueError("copy_frames takes consecutive rows, one key each")
        (v0, f0), (v1, f1) = offsets[0, [0, 2]].tolist(), (offsets[-1, [0, 2]] + offsets[-1, [1, 3]]).tolist()
        for name, _, _ in MESH_ARRAYS:
            self._arrays[name].copy_rows(Path(library.path) / f"{name}.npy", *((f0, f1) if name == "faces" else (v0, v1)))
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


#: The files of the stored meshes (:class:`MeshWriter` writes them).
MESH_FILES = ("positions.npy", "colours.npy", "normals.npy", "faces.npy", "frames.npy", "frame_keys.npy",
              "uvs.npy", "textures.npy", "texture_frames.npy")


def link_meshes(library, folder):
    """Give ``folder`` the stored meshes of ``library`` (a :class:`tvmedit.engine.store.library.Library`) as
    they are: hard links, copies where links cannot be made. Nothing in a library is changed in
    place, so the two may share them. Returns what :class:`MeshWriter` would: an object with
    ``frames``, ``bounds`` and ``max_counts``."""
    import os
    import shutil
    from types import SimpleNamespace

    for name in MESH_FILES:
        source = Path(library.path) / name
        if name in library.manifest.get("files", {}):
            try:
                os.link(source, Path(folder) / name)
            except OSError:
                shutil.copyfile(source, Path(folder) / name)
    return SimpleNamespace(frames=int(library.manifest["counts"]["stored_frames"]),
                           bounds=library.manifest["bounds"], max_counts=library.manifest["max_counts"])


def graph_to_json(graph):
    """What ``graph.json`` holds: the complete graph's weights, transition frames and mu; and,
    for a reader other than tvmedit (which derives them again), the edges added to connect
    the graph and why."""
    unpruned = graph.graph["unpruned"]
    transitions = graph.graph["transitions"]
    return {
        "mu": graph.graph["mu"],
        "connect": graph.graph.get("connect"),
        "added": [[int(i), int(j)] for i, j, added in sorted(graph.edges(data="added")) if added],
        "unpruned": [[int(i), int(j), float(w)] for (i, j), w in sorted(unpruned.items())],
        "transitions": [[int(i), int(j), int(a), int(b)] for (i, j), (a, b) in sorted(transitions.items())],
    }


def write_graphml(graph, path):
    """Export the pruned graph as GraphML (only mu among the graph attributes), atomically."""
    import networkx as nx

    plain = nx.DiGraph(mu=float(graph.graph["mu"]))
    for i, data in graph.nodes(data=True):
        plain.add_node(i, **{k: v for k, v in data.items() if v is not None})
    plain.add_edges_from(graph.edges(data=True))
    with safewrite.replacing_file(path) as tmp:
        nx.write_graphml(plain, tmp)


def write_corrections(folder, corrections, parses):
    """Write ``corrections.json`` (as :meth:`tvmedit.engine.store.corrections.Corrections.to_json` gives it)
    and ``parse.json`` (the automatic parse, per sequence as ``Structure.to_json``)."""
    write_json(Path(folder) / "corrections.json", corrections)
    write_json(Path(folder) / "parse.json", parses)


def read_corrections(path):
    """The corrections stored in the library at ``path`` as a dict, or None when it has none."""
    return read_json(path, "corrections.json") if (Path(path) / "corrections.json").exists() else None


def read_parse(path):
    """The automatic parse stored beside corrections (``{name: Structure JSON}``), or None."""
    return read_json(path, "parse.json") if (Path(path) / "parse.json").exists() else None


def write_features(folder, features):
    """Write ``features.npy`` from the :class:`tvmedit.engine.features.Features` of every sequence, in
    order (r padded to one width), and ``features_centred.npy`` from their ``centred`` ones
    where any has them; returns each sequence's rows in ``features_centred.npy`` (None where
    it has none) and their r width, for :func:`sequence_record` and :func:`manifest`."""
    folder = Path(folder)
    vectors = np.concatenate([f.vectors for f in features]) if features else np.zeros((0, 0), np.float32)
    np.save(folder / "features.npy", np.ascontiguousarray(vectors, dtype=np.float32))
    kept = [f.centred for f in features if f.centred is not None]
    rows, at = [], 0
    for f in features:
        rows.append(None if f.centred is None else (at, at + len(f.centred)))
        at += 0 if f.centred is None else len(f.centred)
    if not kept:
        return rows, 0
    width = max(c.r.shape[1] for c in kept)
    np.save(folder / "features_centred.npy",
            np.ascontiguousarray(np.concatenate([c.pad_r(width).vectors for c in kept]), dtype=np.float32))
    return rows, width


def read_features(manifest, record, bins, rows, centred_rows):
    """The :class:`tvmedit.engine.features.Features` of the sequence of manifest ``record``, r at the
    library's width, with its centred features where it has them (r at their own width).
    ``rows``: ``features.npy`` memory-mapped (:func:`load_array`); ``centred_rows``: a callable
    giving ``features_centred.npy`` so, called only where the record has rows in it."""
    from ..features import Features

    columns = manifest["feature_columns"]
    w_r, w_t = columns["r"], columns["theta"]
    origin = np.array(record["origin"], dtype=np.float64)

    def split(array, start, stop, width, own, centred=None):
        block = array[start:stop]
        return Features(block[:, :own], block[:, width:width + w_t], block[:, width + w_t:], origin, bins, centred)

    centred = None
    if record.get("centred_rows") is not None:
        centred = split(centred_rows(), *record["centred_rows"], columns["centred_r"], record["centred_r_bins"])
    return split(rows, *record["rows"], w_r, w_r, centred)


def sequence_record(name, fps, rows, features, feature_key, files, skipped, format=None,
                    orientation=None, centred_rows=None):
    """One sequence's entry in the manifest; ``features`` are its own (unpadded) ones; ``format``
    names its reader, ``orientation`` (JSON) the map into tvmedit's frame it was read with;
    ``centred_rows`` its rows in ``features_centred.npy`` (:func:`write_features`)."""
    extra = {} if format is None else {"format": format}
    if orientation is not None:
        extra["orientation"] = orientation
    if centred_rows is not None:
        extra["centred_rows"] = list(centred_rows)
        extra["centred_r_bins"] = int(features.centred.r.shape[1])
    return {
        "name": name,
        "fps": fps,
        "frames": rows[1] - rows[0],
        "rows": list(rows),
        "r_bins": int(features.r.shape[1]),
        "origin": [float(x) for x in features.origin],
        "feature_key": feature_key,
        "files": files,
        "skipped": [list(s) for s in skipped],
        **extra,
    }


def manifest(records, params, feature_columns, counts, bounds, max_counts):
    """The manifest's contents but for the file sizes (added by :func:`write_manifest`)."""
    return {
        "format": FORMAT,
        "tvmedit": tvmedit_version(),
        "created": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "params": json.loads(json.dumps(params, default=_json_default)),
        "feature_columns": feature_columns,
        "sequences": records,
        "counts": counts,
        "bounds": [list(bounds[0]), list(bounds[1])],
        "max_counts": list(max_counts),
    }


def write_manifest(folder, data):
    """Record the sizes of the :data:`CHECKED_FILES` in ``folder`` and write ``manifest.json`` last."""
    folder = Path(folder)
    data = dict(data, files={path.name: path.stat().st_size for path in sorted(folder.iterdir())
                             if path.name in CHECKED_FILES})
    write_json(folder / "manifest.json", data)


# --- reading ------------------------------------------------------------------------------

def _rebuild_hint(path):
    return f"rebuild it with {build_call(None, path, force=True)}"


#: Every file a library may hold besides the marker.
LIBRARY_FILES = (*CHECKED_FILES, "manifest.json", "graph.graphml", "names.json")


def legacy_foreign(path):
    """For a library built before the ownership marker: the files in it that a build did not write.

    None when ``path`` is not such a library (see :func:`tvmedit.engine.safewrite.check_target`).
    """
    names = sorted(str(p.relative_to(path)) for p in Path(path).rglob("*"))
    if safewrite.owner(path) != "library":
        # A manifest too damaged to read: still a library when it holds nothing but library files.
        whole = {"manifest.json", "features.npy", "database.json"} <= set(names)
        return [] if whole and set(names) <= set(LIBRARY_FILES) else None
    return [name for name in names if name not in LIBRARY_FILES]


def read_manifest(path):
    """The manifest of the library at ``path``, its format and file sizes checked.

    Raises
    ------
    LibraryError
        When ``path`` is not a library, is of another format version, or misses or
        has a truncated file; the message says how to rebuild it.
    """
    path = Path(path)
    manifest_path = path / "manifest.json"
    if not manifest_path.is_file():
        leftovers = sorted(path.parent.glob(f".{path.name}.old-*"))
        if leftovers and not path.exists():
            raise LibraryError(f"no library at {path}, but an interrupted build left the previous "
                               f"one at {leftovers[0]}; rename it back to {path.name}.")
        if path.is_dir():
            from ..capture.load import holds_frames  # only here: opening a library reads no mesh code

            raise LibraryError(not_a_library(path, holds_frames(path)))
        raise LibraryError(f"no library at {path}; build one with {build_call(None, path)}.")
    try:
        data = json.loads(manifest_path.read_text())
    except (OSError, ValueError) as error:
        raise LibraryError(f"library {path} has an unreadable manifest.json ({error}); "
                           f"{_rebuild_hint(path)}.") from None
    version = data.get("format") if isinstance(data, dict) else None
    if version != FORMAT:
        shown = "no format version" if version is None else f"format version {version!r}"
        shown += f" (a {type(version).__name__}, not a number)" if version is not None and not isinstance(version, int) else ""
        raise LibraryError(f"library {path} has {shown} but this tvmedit reads version "
                           f"{FORMAT!r}; {_rebuild_hint(path)}.")
    for name, size in data.get("files", {}).items():
        try:
            actual = (path / name).stat().st_size
        except OSError:
            raise LibraryError(f"library {path} is incomplete: {name} is missing; "
                               f"{_rebuild_hint(path)}.") from None
        if actual != size:
            raise LibraryError(f"library {path} is damaged: {name} has {actual} bytes where "
                               f"{size} were written (truncated or changed); {_rebuild_hint(path)}.")
    return data


def damaged(path, error):
    """The LibraryError for a library whose files cannot be read as the format says."""
    return LibraryError(f"library {path} cannot be read ({type(error).__name__}: {error}); "
                        f"{_rebuild_hint(path)}.")


def read_json(path, name):
    """The JSON file ``name`` of the library at ``path``; LibraryError when it is not JSON."""
    try:
        return json.loads((Path(path) / name).read_text())
    except (OSError, ValueError) as error:
        raise damaged(path, error) from None


def load_array(path, name):
    """Array file ``name`` of the library at ``path``, memory-mapped."""
    try:
        return np.load(Path(path) / name, mmap_mode="r")
    except Exception as error:  # noqa: BLE001 - a damaged header fails in numpy's parser in many ways
        detail = str(error).strip().splitlines()[0] if str(error).strip() else type(error).__name__
        raise LibraryError(f"library {path} has an unreadable {name} ({detail}); "
                           f"{_rebuild_hint(path)}.") from None


def mesh_arrays(path, prefix=""):
    """The flat mesh arrays of :data:`MESH_ARRAYS` (``prefix="blend_"``: of the in-between
    frames), memory-mapped, their shapes checked."""
    arrays = {name: load_array(path, f"{prefix}{name}.npy") for name, _, _ in MESH_ARRAYS}
    for name, dtype, width in MESH_ARRAYS:
        array = arrays[name]
        if array.ndim != 2 or array.shape[1] != width or array.dtype != dtype:
            raise damaged(path, ValueError(f"{name}.npy holds {array.dtype} {array.shape}"))
    if not len(arrays["positions"]) == len(arrays["colours"]) == len(arrays["normals"]):
        raise damaged(path, ValueError("the vertex arrays differ in length"))
    return arrays


def frame_offsets(path, arrays, prefix=""):
    """``frames.npy`` as an (n, 4) int64 array, every frame's range inside the mesh arrays."""
    offsets = np.asarray(load_array(path, f"{prefix}frames.npy"))
    vertices, faces = len(arrays["positions"]), len(arrays["faces"])
    ok = offsets.ndim == 2 and offsets.shape[1] == 4 and offsets.dtype == np.int64
    if ok and len(offsets):
        v0, nv, f0, nf = offsets.T
        ok = bool((offsets >= 0).all() and (v0 + nv <= vertices).all() and (f0 + nf <= faces).all())
    if not ok:
        raise damaged(path, ValueError(f"{prefix}frames.npy does not match the mesh arrays"))
    return offsets


def frame_keys(path, frames, sequences):
    """``frame_keys.npy`` as an (n, 2) int64 array of (sequence index, frame), checked."""
    keys = np.asarray(load_array(path, "frame_keys.npy"))
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


def read_graph(path):
    """``(unpruned, transitions, mu)`` from ``graph.json``: ``{(i, j): w}``, ``{(i, j): (exit, entry)}``."""
    data = read_json(path, "graph.json")
    unpruned = {(i, j): w for i, j, w in data["unpruned"]}
    transitions = {(i, j): (a, b) for i, j, a, b in data["transitions"]}
    return unpruned, transitions, float(data["mu"])


def read_blends(path, frames):
    """``(natural_step, {(from, to): (first row, count)}, data)`` from ``blends.json``, checked
    against the ``frames`` rows of ``blend_frames.npy``."""
    data = read_json(path, "blends.json")
    try:
        runs = {(int(e["from"]), int(e["to"])): (int(e["first"]), int(e["count"]))
                for e in [*data["edges"], *data.get("wraps", [])]}
        natural = float(data["natural_step"])
    except (KeyError, TypeError, ValueError) as error:
        raise damaged(path, error) from None
    if any(first < 0 or count < 0 or first + count > frames for first, count in runs.values()):
        raise damaged(path, ValueError("blends.json names rows beyond blend_frames.npy"))
    return natural, runs, data


def read_names(path):
    """The names given with ``rename`` (``{"id": "name"}``), checked; ``{}`` when none."""
    names_path = Path(path) / "names.json"
    if not names_path.exists():
        return {}
    try:
        names = json.loads(names_path.read_text())
    except ValueError as error:
        raise LibraryError(f"{names_path} is not valid JSON ({error}); fix it or delete it "
                           "to go back to the default names.") from None
    _check_names(names_path, names)
    return names


def write_names(path, names):
    """Store ``names`` (``{"id": "name"}``) in ``names.json`` atomically."""
    target = Path(path) / "names.json"
    try:
        safewrite.write_text(target, json.dumps(names, indent=1, sort_keys=True))
        safewrite.note_written(path, "names.json")
    except OSError as error:
        raise LibraryError(f"cannot write {target} ({error.strerror}); "
                           "check that the library is writable.") from None


def _check_names(names_path, names):
    """``names.json`` is edited by hand at times: it must map ids to names, as rename writes it."""
    if not isinstance(names, dict):
        shown = json.dumps(names)
        shown = shown if len(shown) <= 40 else shown[:37] + "..."
        raise LibraryError(f"{names_path} must hold a JSON object of motion names such as "
                           f"{{\"3\": \"squats\"}}, not {shown}; fix it or delete it "
                           "to go back to the default names.")
    for key, name in names.items():
        if not key.strip().isdigit() or not isinstance(name, str) or not name.strip() or name.strip().isdigit():
            raise LibraryError(f"{names_path} maps {key!r} to {name!r}, but it must map motion ids to "
                               "names with at least one non-digit, such as {\"3\": \"squats\"}; "
                               "fix it or delete it to go back to the default names.")


def check_unique(path, nodes):
    """Names applied from ``names.json`` must not give two motions one name."""
    seen = {}
    for node in nodes:
        if node.name in seen:
            raise LibraryError(f"{Path(path) / 'names.json'} gives motions {seen[node.name]} and "
                               f"{node.id} the same name {node.name!r}; fix it or delete it to go "
                               "back to the default names.")
        seen[node.name] = node.id
