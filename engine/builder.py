"""The offline builder: TVM sequences in, a library directory out (sections 3-6 in one pass).

The pipeline, per library:

1. **Features** (section 3). Every frame file is read once and summarised by its three
   histograms about its sequence's origin (the centroid of the first frame). This is the
   build's cost, so it runs on worker processes or a dask cluster in chunks of frames, and
   its result is cached per sequence, keyed by the frame files (paths, sizes, mtimes), the
   bin sizes and the feature code: a rebuild with other parsing or pruning parameters
   reuses it, from the library being replaced or from ``$XDG_CACHE_HOME/tvmedit``.
2. **Structure** (section 4), **database** (section 5, eq. (9)) and **graph** (section 6):
   cheap, on the feature vectors of all sequences padded to one r width (eq. (4)).
3. **Meshes.** Only the frames of database textons can ever be played, so only they are
   stored; which ones is known only now, and those files are read a second time and
   streamed to flat arrays on disk with their vertex normals, never all held in memory.

Everything is written into ``.LIB.tmp-<pid>`` beside the target and renamed into place at the
end: an interrupted build leaves the previous library (or none), never half of one. The
on-disk format is described in :mod:`engine.library`.
"""

import dataclasses
import glob as _glob
import hashlib
import json
import math
import os
import shutil
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from . import library as _library
from .errors import InputError, LibraryError, TvmError
from .features import BinSizes, FeatureAccumulator, Features, frame_histograms
from .load import open_sequence, read_frame
from .normals import vertex_normals
from .parallel import Workers

__all__ = ["build", "cache_dir", "expand_inputs"]

#: Frames per feature task: large enough to amortise a task's overhead, small enough to
#: keep every worker busy on short sequences.
FEATURE_CHUNK = 32
#: Frames per mesh task; each frame is about 1 MB on its way back, so chunks stay small.
MESH_CHUNK = 4


def cache_dir():
    """Where features are cached between builds: ``$XDG_CACHE_HOME/tvmedit`` (``~/.cache/tvmedit``)."""
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "tvmedit"


def _feature_code_version():
    # The cache depends on how frames are read and histograms computed; hashing the modules
    # that do it invalidates every cached feature when that code changes, with nothing to bump.
    digest = hashlib.sha1()
    for module in ("load.py", "plyfast.py", "readers.py", "orientation.py", "features.py"):
        digest.update(Path(__file__).with_name(module).read_bytes())
    return digest.hexdigest()[:12]


def expand_inputs(inputs):
    """``(name or None, source)`` for every sequence that ``inputs`` names.

    An input is a folder, a quoted glob of frame files (one sequence), a glob of folders
    (one sequence per folder), or a ``(name, source)`` pair. A glob that matches frame
    files is left to the loader, which orders them.

    >>> expand_inputs([("walk", "captures/a"), "captures/b"])
    [('walk', 'captures/a'), (None, 'captures/b')]
    """
    expanded = []
    for item in inputs:
        name, source = item if isinstance(item, tuple) else (None, item)
        text = str(source)
        if any(ch in text for ch in "*?[") and not Path(text).exists():
            matches = sorted(_glob.glob(text.rstrip("/\\")))
            folders = [m for m in matches if os.path.isdir(m)]
            if folders and len(folders) == len(matches):
                if name is not None and len(folders) > 1:
                    raise InputError(f"{text} matches {len(folders)} sequence folders, so it cannot "
                                     f"take the one name {name!r}; name each folder separately.")
                expanded += [(name, folder) for folder in folders]
                continue
        expanded.append((name, source))
    return expanded


def _stat_list(paths):
    rows = []
    for path in paths:
        try:
            stat = os.stat(path)
        except OSError as error:
            raise InputError(f"frame {path} cannot be read ({error.strerror}); check the input.") from None
        rows.append([str(Path(path).resolve()), stat.st_size, stat.st_mtime_ns])
    return rows


def _feature_key(stats, bins, skip_bad_frames, orientation=None):
    frame = [] if orientation is None or orientation.is_identity else [orientation.matrix, orientation.scale]
    blob = json.dumps([stats, bins.to_json(), _feature_code_version(), bool(skip_bad_frames)] + frame)
    return hashlib.sha1(blob.encode()).hexdigest()[:20]


# --- worker tasks: module-level so that processes and dask can run them -----------------

def _read(path, skip_bad_frames, orientation=None, detail="full"):
    """``(frame, None)``, or ``(None, reason)`` for a bad frame when skipping; raises otherwise."""
    try:
        return read_frame(path, orientation, detail), None
    except InputError as error:
        if not skip_bad_frames:
            raise
        return None, str(error)


def _feature_task(task):
    """Histograms of a chunk of frames: ``(rows, read_s, compute_s)``.

    A row is ``(h_r, h_theta, h_phi)`` as float32 (what :class:`Features` stores), or the
    reason the frame was skipped.
    """
    paths, origin, bins, skip_bad_frames, orientation = task
    rows, read_s, compute_s = [], 0.0, 0.0
    for path in paths:
        t0 = time.perf_counter()
        frame, reason = _read(path, skip_bad_frames, orientation, "geometry")
        if frame is None:
            rows.append(reason)
            continue
        t1 = time.perf_counter()
        rows.append(tuple(h.astype(np.float32) for h in frame_histograms(frame.positions, origin, bins)))
        read_s += t1 - t0
        compute_s += time.perf_counter() - t1
    return rows, read_s, compute_s


def _mesh_task(paths):
    """Meshes of a chunk of ``(path, orientation)`` with their normals: ``(meshes, read_s, compute_s)``."""
    meshes, read_s, compute_s = [], 0.0, 0.0
    for path, orientation in paths:
        t0 = time.perf_counter()
        frame = read_frame(path, orientation)
        t1 = time.perf_counter()
        normals = vertex_normals(frame.positions, frame.faces)
        meshes.append((frame.positions, frame.colours, frame.faces, normals))
        read_s += t1 - t0
        compute_s += time.perf_counter() - t1
    return meshes, read_s, compute_s


# --- features, with their cache ----------------------------------------------------------

class _Progress:
    """tqdm bars on stderr, or nothing."""

    def __init__(self, enabled):
        self.enabled = enabled

    def bar(self, total, desc, unit="frame"):
        if not self.enabled:
            return _NoBar()
        from tqdm import tqdm

        return tqdm(total=total, desc=desc, unit=unit, file=sys.stderr, leave=False,
                    dynamic_ncols=True)


class _NoBar:
    def update(self, n=1):
        pass

    def close(self):
        pass


@dataclasses.dataclass
class _SequenceFeatures:
    """What the feature pass learns about one sequence (and what the cache holds)."""

    features: Features
    paths: list          # kept frame files, resolved
    skipped: list        # [(path, reason)]
    key: str
    source: str = "computed"   # or "library" / "cache"
    stats: dict = dataclasses.field(default_factory=dict)   # resolved path -> [path, size, mtime_ns]


def _compute_features(sequence, bins, skip_bad_frames, pool, bar, timing):
    paths = list(sequence.paths)
    skipped, first = [], None
    # The origin is the centroid of the first usable frame; everything else waits on it.
    for k, path in enumerate(paths):
        t0 = time.perf_counter()
        frame, reason = _read(path, skip_bad_frames, sequence.orientation, "geometry")
        if frame is None:
            skipped.append((str(path), reason))
            bar.update()
            continue
        timing["read"] += time.perf_counter() - t0
        first = k
        break
    if first is None:
        raise InputError(f"no usable frames in sequence {sequence.name!r}: all {len(paths)} were bad.")
    t0 = time.perf_counter()
    accumulator = FeatureAccumulator(bins)
    accumulator.add(frame.positions)
    timing["compute"] += time.perf_counter() - t0
    bar.update()
    kept = [str(Path(paths[first]).resolve())]
    rest = paths[first + 1:]
    chunks = [rest[i:i + FEATURE_CHUNK] for i in range(0, len(rest), FEATURE_CHUNK)]
    tasks = ((chunk, accumulator.origin, bins, skip_bad_frames, sequence.orientation) for chunk in chunks)
    for chunk, (rows, read_s, compute_s) in zip(chunks, pool.map(_feature_task, tasks)):
        for path, row in zip(chunk, rows):
            if isinstance(row, str):
                skipped.append((str(path), row))
            else:
                accumulator.add_histograms(*row)
                kept.append(str(Path(path).resolve()))
        timing["read"] += read_s
        timing["compute"] += compute_s
        bar.update(len(chunk))
    return accumulator.result(), kept, skipped


def _cache_file(key):
    return cache_dir() / "features" / f"{key}.npz"


def _from_cache(key, bins):
    path = _cache_file(key)
    try:
        with np.load(path, allow_pickle=False) as data:
            meta = json.loads(str(data["meta"]))
            features = Features(data["r"], data["theta"], data["phi"], data["origin"], bins)
    except (OSError, ValueError, KeyError):
        return None
    return _SequenceFeatures(features, meta["paths"], [tuple(s) for s in meta["skipped"]], key, "cache")


def _to_cache(entry):
    path = _cache_file(entry.key)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
        meta = json.dumps({"paths": entry.paths, "skipped": entry.skipped})
        with open(tmp, "wb") as handle:
            f = entry.features
            np.savez(handle, r=f.r, theta=f.theta, phi=f.phi, origin=f.origin, meta=np.array(meta))
        os.replace(tmp, path)
    except OSError:
        pass  # a cache that cannot be written only costs time on the next build


def _from_library(old, key, bins):
    """Features of the sequence with this key in the library being replaced, or None."""
    if old is None:
        return None
    for record in old.manifest["sequences"]:
        if record.get("feature_key") == key:
            f = old.features(record["name"])
            width = record["r_bins"]
            features = Features(np.array(f.r[:, :width]), np.array(f.theta), np.array(f.phi),
                                np.array(record["origin"], dtype=np.float64), bins)
            paths = [row[0] for row in record["files"]]
            skipped = [tuple(s) for s in record.get("skipped", [])]
            return _SequenceFeatures(features, paths, skipped, key, "library")
    return None


# --- mesh arrays, streamed ----------------------------------------------------------------

class _NpyStream:
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


def _write_meshes(tmp, needed, pool, bar, timing):
    """Stream the needed frames to the flat mesh arrays; returns (keys, bounds, max_counts)."""
    streams = {name: _NpyStream(tmp / f"{name}.npy", dtype, 3) for name, dtype in
               (("positions", np.float32), ("colours", np.uint8), ("normals", np.float32),
                ("faces", np.uint32))}
    offsets = _NpyStream(tmp / "frames.npy", np.int64, 4)
    keys = _NpyStream(tmp / "frame_keys.npy", np.int64, 2)
    low, high = np.full(3, np.inf), np.full(3, -np.inf)
    max_v = max_f = vertex_start = face_start = 0
    if not needed:
        low, high = np.zeros(3), np.zeros(3)
    try:
        chunks = [needed[i:i + MESH_CHUNK] for i in range(0, len(needed), MESH_CHUNK)]
        tasks = ([(path, orientation) for _, _, path, orientation in chunk] for chunk in chunks)
        for chunk, (meshes, read_s, compute_s) in zip(chunks, pool.map(_mesh_task, tasks, window=2 * pool.workers + 2)):
            for (seq_index, frame, _, _), (positions, colours, faces, normals) in zip(chunk, meshes):
                streams["positions"].append(positions)
                streams["colours"].append(colours)
                streams["normals"].append(normals)
                streams["faces"].append(faces)
                offsets.append(np.array([[vertex_start, len(positions), face_start, len(faces)]]))
                keys.append(np.array([[seq_index, frame]]))
                vertex_start += len(positions)
                face_start += len(faces)
                max_v, max_f = max(max_v, len(positions)), max(max_f, len(faces))
                np.minimum(low, positions.min(axis=0), out=low)
                np.maximum(high, positions.max(axis=0), out=high)
            timing["read"] += read_s
            timing["compute"] += compute_s
            bar.update(len(chunk))
    finally:
        for stream in (*streams.values(), offsets, keys):
            stream.close()
    return (low.tolist(), high.tolist()), (max_v, max_f)


# --- the build ----------------------------------------------------------------------------

def _structure_module():
    from . import structure

    return structure


def _graph_module():
    from . import graph

    return graph


def _json_default(value):
    if isinstance(value, (np.integer,)):
        return int(value)
    if isinstance(value, (np.floating,)):
        return float(value)
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, tuple):
        return list(value)
    raise TypeError(f"cannot store {type(value).__name__} in JSON")


def _write_json(path, data):
    Path(path).write_text(json.dumps(data, default=_json_default, separators=(",", ":")))


def _sibling(out, tag):
    return out.parent / f".{out.name}.{tag}-{os.getpid()}"


def _clean_stale(out):
    """Remove what killed builds left beside ``out``; put back a library caught mid-swap."""
    for path in out.parent.glob(f".{_glob.escape(out.name)}.*-*"):
        tag, _, pid = path.name.rpartition("-")
        if not pid.isdigit() or not tag.endswith((".tmp", ".old")) or _alive(int(pid)):
            continue
        if tag.endswith(".old") and not out.exists():
            os.replace(path, out)  # killed between the two renames: the old library is whole
        else:
            shutil.rmtree(path, ignore_errors=True)


def _alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _is_library(out):
    """Whether ``out`` holds a tvmedit library's manifest (what ``--force`` may replace)."""
    try:
        manifest = json.loads((out / "manifest.json").read_text())
    except (OSError, ValueError):
        return False
    return isinstance(manifest, dict) and "format" in manifest and "tvmedit" in manifest


def _check_target(out, force):
    if out.is_file():
        raise LibraryError(f"{out} is a file; give a directory name for the library.")
    if out.exists():
        is_library = _is_library(out)
        if not is_library and any(out.iterdir()):
            raise LibraryError(f"{out} exists and is not a tvmedit library (no tvmedit manifest.json), "
                               "so it is not replaced; choose another -o or remove it yourself.")
        if is_library and not force:
            raise LibraryError(f"library {out} already exists; add --force to replace it.")
        here = Path.cwd().resolve()
        if is_library and (out.resolve() == here or out.resolve() in here.parents):
            raise LibraryError(f"library {out} is the current folder or holds it, so it is not "
                               "replaced; run the build from outside it.")


def _open_old(out):
    """The library being replaced, to reuse its features; None if it cannot be read."""
    if not (out / "manifest.json").exists():
        return None
    try:
        return _library.Library.open(out)
    except TvmError:
        return None


def _swap_in(tmp, out):
    if out.exists():
        old = _sibling(out, "old")
        os.replace(out, old)
        os.replace(tmp, out)
        shutil.rmtree(old, ignore_errors=True)
    else:
        os.replace(tmp, out)


def build(inputs, out, *, fps=None, bins=None, structure=None, mu=None, skip_bad_frames=False,
          progress=False, workers=None, dask=None, force=False, cache=True, log=None, up=None,
          units=None, mirror=None):
    """Build a library from TVM sequences and return it opened.

    Parameters
    ----------
    inputs : list
        Sequence folders, quoted globs, or ``(name, source)`` pairs (see :func:`expand_inputs`).
        A sequence is named after its folder unless named here.
    out : str or Path
        The library directory to write.
    fps : float or None
        Frame rate of every sequence; default: each one's ``sequence.json``, else 10.
    bins : BinSizes or None
        Histogram bin sizes (section 3); default ``BinSizes()``.
    structure : StructureParams or dict or None
        Parsing parameters (section 4); a dict overrides fields of the defaults.
    mu : float or None
        Pruning parameter of eq. (14); default ``engine.graph.MU``.
    skip_bad_frames : bool
        Leave out frames that cannot be read instead of stopping.
    progress : bool
        tqdm bars on stderr.
    workers : int or None
        Local worker processes for reading frames; None = all cores, 1 = this process only.
    dask : str or None
        A dask.distributed scheduler address, or ``"local"``; overrides local processes.
    force : bool
        Replace an existing library.
    cache : bool
        Look up and store features in :func:`cache_dir` (the library being replaced is
        always consulted).
    log : callable or None
        Called with one-line messages (features reused, stages).
    up, units, mirror : str, str, bool or None
        The frame of reference of every sequence (``"+y"``, ``"mm"``, True); what is not
        given is detected per sequence (:func:`engine.orientation.detect`).

    Returns
    -------
    Library
        With ``report``: a dict of counts, reused sequences and timings.
    """
    started = time.perf_counter()
    say = log or (lambda message: None)
    out = Path(out).absolute()
    graph_module, structure_module = _graph_module(), _structure_module()
    bins = bins if bins is not None else BinSizes()
    params = _structure_params(structure_module, structure)
    mu = graph_module.MU if mu is None else _check_mu(mu)

    expanded = expand_inputs(inputs)
    if not expanded:
        raise InputError("no input sequences given; name at least one sequence folder.")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sequences = [open_sequence(source, name=name, fps=fps, up=up, units=units, mirror=mirror)
                     for name, source in expanded]
    _pass_on(caught, log)
    seen = {}
    for (_, source), sequence in zip(expanded, sequences):
        if sequence.name in seen:
            raise InputError(f"{seen[sequence.name]} and {source} are both named {sequence.name!r}; "
                             "name them apart with NAME=PATH.")
        seen[sequence.name] = source

    out.parent.mkdir(parents=True, exist_ok=True)
    _clean_stale(out)
    _check_target(out, force)
    old = _open_old(out)
    tmp = _sibling(out, "tmp")
    progress_bars = _Progress(progress)
    timing = {"read": 0.0, "compute": 0.0}
    stages = {}
    try:
        tmp.mkdir()
        with Workers(workers, dask) as pool:
            t0 = time.perf_counter()
            computed = []
            for sequence in sequences:
                stats = _stat_list(sequence.paths)
                key = _feature_key(stats, bins, skip_bad_frames, sequence.orientation)
                entry = _from_library(old, key, bins) or (_from_cache(key, bins) if cache else None)
                if entry is None:
                    bar = progress_bars.bar(len(sequence.paths), f"features {sequence.name}")
                    try:
                        features, kept, skipped = _compute_features(
                            sequence, bins, skip_bad_frames, pool, bar, timing)
                    finally:
                        bar.close()
                    entry = _SequenceFeatures(features, kept, skipped, key)
                    if cache:
                        _to_cache(entry)
                else:
                    where = "the library being replaced" if entry.source == "library" else "the cache"
                    say(f"features of {sequence.name}: reused from {where} ({len(entry.features)} frames)")
                if entry.skipped:
                    say(f"{sequence.name}: skipped {len(entry.skipped)} bad frame(s): "
                        + "; ".join(f"{Path(p).name}" for p, _ in entry.skipped))
                entry.stats = {row[0]: row for row in stats}
                computed.append(entry)
            stages["features"] = time.perf_counter() - t0

            t0 = time.perf_counter()
            width = max(entry.features.r.shape[1] for entry in computed)
            padded = [entry.features.pad_r(width) for entry in computed]
            vectors = {seq.name: f.vectors for seq, f in zip(sequences, padded)}
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                # The theta columns tell a one-leg-then-the-other cycle from its half (see
                # engine.structure): left and right poses share their r and phi histograms.
                structures = {seq.name: structure_module.parse(vectors[seq.name], seq.fps, params,
                                                               theta=f.theta_columns)
                              for seq, f in zip(sequences, padded)}
                stages["structure"] = time.perf_counter() - t0

                t0 = time.perf_counter()
                from .database import build_database

                nodes = build_database(structures)
                G = graph_module.build_graph(nodes, vectors, mu=mu)
                nodes = graph_module.nodes_of(G)
                stages["graph"] = time.perf_counter() - t0
            _pass_on(caught, log)
            from .database import advice

            if advice(nodes):
                say(f"warning: {advice(nodes)}")

            t0 = time.perf_counter()
            index = {seq.name: k for k, seq in enumerate(sequences)}
            needed = sorted({(index[node.sequence], frame)
                             for node in nodes for frame in range(node.start, node.end + 1)})
            needed = [(s, frame, computed[s].paths[frame], sequences[s].orientation) for s, frame in needed]
            bar = progress_bars.bar(len(needed), "meshes")
            try:
                bounds, max_counts = _write_meshes(tmp, needed, pool, bar, timing)
            finally:
                bar.close()
            stages["meshes"] = time.perf_counter() - t0

        t0 = time.perf_counter()
        features_all = np.concatenate([f.vectors for f in padded]) if padded else np.zeros((0, 0), np.float32)
        np.save(tmp / "features.npy", np.ascontiguousarray(features_all, dtype=np.float32))
        _write_json(tmp / "structure.json", {name: s.to_json() for name, s in structures.items()})
        _write_json(tmp / "database.json", [dataclasses.asdict(node) for node in nodes])
        _write_json(tmp / "graph.json", _library.graph_to_json(G))
        kept = _carry_names(old, nodes, tmp)
        if kept:
            say(f"kept {len(kept)} motion name(s) given in the library being replaced")
            for i, name in kept.items():
                G.nodes[int(i)]["name"] = name
        _library.write_graphml(G, tmp / "graph.graphml")
        manifest = _manifest(sequences, computed, padded, bins, params, mu, skip_bad_frames,
                             nodes, G, bounds, max_counts, len(needed))
        manifest["files"] = {path.name: path.stat().st_size for path in sorted(tmp.iterdir())
                             if path.name in _library.CHECKED_FILES}
        _write_json(tmp / "manifest.json", manifest)
        stages["write"] = time.perf_counter() - t0
        if out.exists():
            _check_target(out, force)
        _swap_in(tmp, out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    library = _library.Library.open(out)
    library.report = {
        "sequences": len(sequences),
        "frames": sum(len(f) for f in padded),
        "clusters": sum(len(s.clusters) for s in structures.values()),
        "nodes": len(nodes),
        "edges": G.number_of_edges(),
        "stored_frames": len(needed),
        "reused": {seq.name: entry.source for seq, entry in zip(sequences, computed)
                   if entry.source != "computed"},
        "seconds": time.perf_counter() - started,
        "stages": stages,
        "read_seconds": timing["read"],
        "compute_seconds": timing["compute"],
        "workers": pool.kind if pool.kind != "processes" else f"{pool.workers} processes",
    }
    return library


def _pass_on(caught, log):
    """Warnings caught during the build go to ``log`` as ``warning: ...`` lines, if given."""
    for warning in caught:
        if log is None:
            warnings.warn(warning.message, warning.category, stacklevel=3)
        else:
            log(f"warning: {warning.message}")


def _check_mu(mu):
    """``mu`` as a float, or one sentence: JSON (manifest, graph) cannot hold inf or NaN.

    >>> _check_mu("inf")
    Traceback (most recent call last):
    ...
    engine.errors.InputError: mu must be a finite number above 0 (the default is 0.9), not 'inf'.
    """
    from .graph import MU

    try:
        value = float(mu)
    except (TypeError, ValueError):
        value = None
    if value is None or not math.isfinite(value) or value <= 0:
        raise InputError(f"mu must be a finite number above 0 (the default is {MU:g}), not {str(mu)!r}.")
    return value


def _carry_names(old, nodes, tmp):
    """Names given with ``rename`` survive a rebuild where the same texton is still a motion."""
    if old is None:
        return {}
    defaults = {n.id: n.name for n in old._read_nodes(renamed=False)}
    given = {(n.sequence, n.start, n.end): n.name for n in old.nodes if n.name != defaults[n.id]}
    taken = {n.name for n in nodes}
    names = {}
    for node in nodes:
        name = given.get((node.sequence, node.start, node.end))
        if name and name not in taken:
            names[str(node.id)] = name
            taken.add(name)
    if names:
        _write_json(tmp / "names.json", names)
    return names


def _structure_params(module, structure):
    if structure is None:
        return module.StructureParams()
    if isinstance(structure, dict):
        try:
            return module.StructureParams(**structure)
        except (TypeError, ValueError) as error:
            raise InputError(f"bad structure parameters: {error}.") from None
    return structure


def _manifest(sequences, computed, padded, bins, params, mu, skip_bad_frames, nodes, G,
              bounds, max_counts, stored):
    from tvmedit import __version__

    records, row = [], 0
    for seq, entry, features in zip(sequences, computed, padded):
        n = len(features)
        records.append({
            "name": seq.name,
            "fps": seq.fps,
            "frames": n,
            "rows": [row, row + n],
            "r_bins": int(entry.features.r.shape[1]),
            "origin": [float(x) for x in entry.features.origin],
            "feature_key": entry.key,
            "files": [entry.stats.get(path, [path, None, None]) for path in entry.paths],
            "skipped": [list(s) for s in entry.skipped],
            "format": seq.format,
            "orientation": seq.orientation.to_json(),
        })
        row += n
    width = padded[0].r.shape[1] if padded else 0
    return {
        "format": _library.FORMAT,
        "tvmedit": __version__,
        "created": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "params": {
            "bins": bins.to_json(),
            "structure": _params_json(params),
            "mu": mu,
            "skip_bad_frames": bool(skip_bad_frames),
        },
        "feature_columns": {"r": width, "theta": bins.n_theta, "phi": bins.n_phi},
        "sequences": records,
        "counts": {"frames": row, "nodes": len(nodes), "edges": G.number_of_edges(),
                   "stored_frames": stored},
        "bounds": [list(bounds[0]), list(bounds[1])],
        "max_counts": list(max_counts),
    }


def _params_json(params):
    if dataclasses.is_dataclass(params):
        return json.loads(json.dumps(dataclasses.asdict(params), default=_json_default))
    if hasattr(params, "to_json"):
        return params.to_json()
    return dict(vars(params))
