"""The offline builder: TVM sequences in, a library directory out (sections 3-6 in one pass).

:func:`build` is one pass, stage by stage:

1. **Features** (section 3). Every frame file is read once and summarised by its three
   histograms about its sequence's origin (the centroid of the first frame). This is the
   build's cost, so it runs on worker processes or a dask cluster in chunks of frames
   (:mod:`tvmedit.engine.parallel`), and its result is kept in the feature cache
   (:mod:`tvmedit.engine.store.featurecache`) and in the library: a rebuild with other parsing or pruning
   parameters reuses it, from the library being replaced or from the cache.
2. **Structure** (section 4), **database** (section 5, eq. (9)) and **graph** (section 6):
   cheap, on the feature vectors of all sequences padded to one r width (eq. (4)).
3. **Meshes.** Only the frames of database textons can ever be played, so only they are
   stored; which ones is known only now, and those files are read a second time and
   streamed to flat arrays on disk with their vertex normals, never all held in memory.
4. **Blends.** For every edge of the final graph, in-between frames from the exit frame to
   the entry frame (:mod:`tvmedit.engine.inbetween.blend`), one task per edge on the same workers, in flat
   arrays of their own beside the texton frames'. A rebuild with other blend options keeps
   the features and the texton frames, and copies the runs that come out the same.
5. **Write** the rest of the library; its format is owned by :mod:`tvmedit.engine.store.layout`.

Everything is written into a temporary folder beside the target and renamed into place at
the end (:mod:`tvmedit.engine.safewrite`): an interrupted build leaves the previous library (or none),
never half of one.
"""

import contextlib
import dataclasses
import sys
import time
import warnings
from pathlib import Path
from typing import NamedTuple

import numpy as np

from .. import safewrite
from . import featurecache
from . import layout
from . import meshfiles
from ..inbetween.blend import preload
from . import capturecopy
from .inbetweens import blend_library, instant_library, join_library, loop_frames, mapping
from .inputs import check_kept, check_target, kept_corrections, open_inputs, open_old, pass_on
from ..errors import InputError, summarise
from ..features import FeatureAccumulator, Features, follow_picks, moves_across, stored_rows
from ..capture.load import read_frame, resolved
from ..parallel import Workers
from .advice import more_motions
from .settings import Settings

__all__ = ["build", "derive", "report_of", "library_features", "Settings"]

#: Frames per feature task: large enough to amortise a task's overhead, small enough to
#: keep every worker busy on short sequences.
FEATURE_CHUNK = 32


# Worker tasks stay at module level so that processes and dask can pickle them.
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

    A row is ``((h_r, h_theta, h_phi), centred)`` as float32 (what :class:`Features` stores;
    ``centred`` the same about the frame's own centre, None where the origin follows), or the
    reason the frame was skipped.
    """
    paths, origin, bins, skip_bad_frames, orientation, follow = task
    rows, read_s, compute_s = [], 0.0, 0.0
    for path in paths:
        t0 = time.perf_counter()
        frame, reason = _read(path, skip_bad_frames, orientation, "geometry")
        if frame is None:
            rows.append(reason)
            continue
        t1 = time.perf_counter()
        rows.append(stored_rows(frame.positions, origin, bins, follow))
        read_s += t1 - t0
        compute_s += time.perf_counter() - t1
    return rows, read_s, compute_s


class _Run:
    """What a build keeps track of as it goes: messages, progress bars and timings."""

    def __init__(self, progress, log):
        self.log = log
        self.say = log or (lambda message: None)
        self.progress = progress
        self.timing = {"read": 0.0, "compute": 0.0}
        self.stages = {}
        self.read_frames = 0
        self.started = time.perf_counter()
        self.blends = self.instants = None
        self.names_from = None      # the library whose names given by hand carry over, if not ``old``
        self.old_whole = False      # every file of the library being replaced was found as written

    def stage(self, name, fn, *args):
        """Run one stage and record how long it took."""
        t0 = time.perf_counter()
        result = fn(*args)
        self.stages[name] = time.perf_counter() - t0
        return result

    def bar(self, total, desc, unit="frame"):
        """A tqdm bar on stderr, or one that shows nothing (also where there is nothing to do:
        "blends: 0run" would stay in a log)."""
        if not self.progress or not total:
            return _NoBar()
        from tqdm import tqdm

        return tqdm(total=total, desc=desc, unit=unit, file=sys.stderr, leave=False,
                    dynamic_ncols=True)

    def add_times(self, read_s, compute_s):
        self.timing["read"] += read_s
        self.timing["compute"] += compute_s


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


def origin_follows(paths, orientation=None, first=None):
    """Whether the feature origin follows the person in the take of ``paths`` (eq. (1)).

    :data:`tvmedit.engine.features.SAMPLE_FRAMES` frames spread over the take are read (``first``:
    the first frame's positions, when already read) and :func:`tvmedit.engine.features.moves_across`
    decides; unreadable frames are left out of the sample.
    """
    picks = follow_picks(len(paths))
    centroids = []
    for k in picks:
        if k == 0 and first is not None:
            centroids.append(np.asarray(first).mean(axis=0))
            continue
        frame, _ = _read(paths[k], True, orientation, "geometry")
        if frame is not None:
            centroids.append(frame.positions.mean(axis=0))
    return moves_across(centroids)


def _compute_features(sequence, bins, skip_bad_frames, pool, bar, run):
    paths = list(sequence.paths)
    orientation = sequence.orientation.for_features()   # in the body's own frame where asked
    skipped, first = [], None
    # The origin is the centroid of the first usable frame; everything else waits on it.
    for k, path in enumerate(paths):
        t0 = time.perf_counter()
        frame, reason = _read(path, skip_bad_frames, orientation, "geometry")
        if frame is None:
            skipped.append((str(path), reason))
            bar.update()
            continue
        run.add_times(time.perf_counter() - t0, 0.0)
        first = k
        break
    if first is None:
        raise InputError(f"no usable frames in sequence {sequence.name!r}: all {len(paths)} were bad.")
    t0 = time.perf_counter()
    follow = origin_follows(paths[first:], orientation, frame.positions)
    accumulator = FeatureAccumulator(bins, follow=follow, centred=True)
    accumulator.add(frame.positions)
    run.add_times(0.0, time.perf_counter() - t0)
    bar.update()
    real = resolved(paths)
    kept = [real[first]]
    rest = paths[first + 1:]
    chunks = [rest[i:i + FEATURE_CHUNK] for i in range(0, len(rest), FEATURE_CHUNK)]
    tasks = ((chunk, accumulator.origin, bins, skip_bad_frames, orientation, follow) for chunk in chunks)
    for k, (chunk, (rows, read_s, compute_s)) in enumerate(zip(chunks, pool.map(_feature_task, tasks))):
        for index, (path, row) in enumerate(zip(chunk, rows), start=first + 1 + k * FEATURE_CHUNK):
            if isinstance(row, str):
                skipped.append((str(path), row))
            else:
                accumulator.add_histograms(*row[0], centred=row[1])
                kept.append(real[index])
        run.add_times(read_s, compute_s)
        bar.update(len(chunk))
    return accumulator.result(), kept, skipped


def _sequence_features(sequence, bins, skip_bad_frames, pool, old, cache, run):
    """The features of one sequence: from the library being replaced, the cache, or computed."""
    stats = featurecache.stat_list(sequence.paths)
    key = featurecache.key(stats, bins, skip_bad_frames, sequence.orientation.for_features(), sequence.orientation)
    entry = library_features(old, key, bins) or (_from_cache(key, bins) if cache else None)
    if entry is None:
        bar = run.bar(len(sequence.paths), f"features {sequence.name}")
        try:
            features, kept, skipped = _compute_features(sequence, bins, skip_bad_frames, pool, bar, run)
        finally:
            bar.close()
        entry = _SequenceFeatures(features, kept, skipped, key)
        if cache:
            featurecache.write(key, features, {"paths": kept, "skipped": skipped})
    else:
        where = "the library being replaced" if entry.source == "library" else "the cache"
        run.say(f"features of {sequence.name}: reused from {where} ({len(entry.features)} frames)")
    if entry.skipped:
        run.say(f"{sequence.name}: skipped {len(entry.skipped)} bad frame(s): "
                + summarise([Path(p).name for p, _ in entry.skipped], noun="frames", separator="; "))
    entry.stats = {row[0]: row for row in stats}
    return entry


def _from_cache(key, bins):
    found = featurecache.read(key, bins)
    if found is None:
        return None
    features, meta = found
    return _SequenceFeatures(features, meta["paths"], [tuple(s) for s in meta["skipped"]], key, "cache")


def library_features(old, key, bins):
    """Features of the sequence with feature key ``key`` in library ``old`` (with its frame
    files and skipped frames, as the feature pass gives them), or None."""
    if old is None:
        return None
    for record in old.manifest["sequences"]:
        if record.get("feature_key") == key:
            f = old.features(record["name"])
            width = record["r_bins"]
            c = f.centred
            centred = None if c is None else Features(np.array(c.r), np.array(c.theta), np.array(c.phi), c.origin, bins)
            features = Features(np.array(f.r[:, :width]), np.array(f.theta), np.array(f.phi),
                                np.array(record["origin"], dtype=np.float64), bins, centred)
            paths = [row[0] for row in record["files"]]
            skipped = [tuple(s) for s in record.get("skipped", [])]
            return _SequenceFeatures(features, paths, skipped, key, "library")
    return None


#: What the cheap stages make: automatic parses, corrected structures, database, graph.
_Analysis = NamedTuple("_Analysis", [("parses", dict), ("structures", dict), ("nodes", list),
                                     ("graph", object), ("corrections", object)])


def _motion_graph(sequences, padded, params, mu, run, corrections, parses=None, connect="auto"):
    """Parse every sequence (section 4; unless ``parses`` are given), apply the corrections by
    hand (:mod:`tvmedit.engine.store.corrections`), then build the database (section 5) and graph (section 6)."""
    from ..parse import structure as structure_module
    from .corrections import apply_database, apply_structures
    from ..graph.database import advice, build_database
    from ..graph.motiongraph import build_graph, nodes_of

    vectors = {seq.name: f.vectors for seq, f in zip(sequences, padded)}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        # The theta columns tell a one-leg-then-the-other cycle from its half (see
        # tvmedit.engine.parse.structure): left and right poses share their r and phi histograms.
        if parses is None:
            parses = run.stage("structure", lambda: {
                seq.name: structure_module.parse(vectors[seq.name], seq.fps, params, theta=f.theta_columns,
                                                 centred=f.centred)
                for seq, f in zip(sequences, padded)})
        t0 = time.perf_counter()
        thetas = {seq.name: f.theta_columns for seq, f in zip(sequences, padded)}
        structures = apply_structures(parses, vectors, corrections, thetas, lambda m: run.say(f"warning: {m}"),
                                      {seq.name: f.centred for seq, f in zip(sequences, padded)})
        nodes = apply_database(build_database(structures), structures, corrections)
        graph = build_graph(nodes, vectors, mu=mu, connect=connect)
        run.stages["graph"] = time.perf_counter() - t0
    pass_on(caught, run.log)
    nodes = nodes_of(graph)
    if advice(nodes):
        better = more_motions(sequences, padded, vectors, params) if not corrections else None
        run.say(f"warning: {advice(nodes, better)}")
    return _Analysis(parses, structures, nodes, graph, corrections)


def _write_library(tmp, old, sequences, computed, padded, settings, analysis, meshes, run):
    """Everything but the meshes: features, structure, database, graph, names, manifest last."""
    layout.write_json(tmp / "blends.json", run.blends["data"])
    bins = settings.bins
    structures, nodes, graph = analysis.structures, analysis.nodes, analysis.graph
    centred_rows, centred_width = layout.write_features(tmp, padded)
    layout.write_json(tmp / "structure.json", {name: s.to_json() for name, s in structures.items()})
    if analysis.corrections:
        layout.write_corrections(tmp, analysis.corrections.to_json(),
                                    {name: s.to_json() for name, s in analysis.parses.items()})
    layout.write_json(tmp / "database.json", nodes)
    layout.write_json(tmp / "graph.json", layout.graph_to_json(graph))
    kept = _carry_names(run.names_from or old, nodes, tmp)
    if kept:
        run.say(f"kept {len(kept)} motion name(s) given in the library being replaced")
        for i, name in kept.items():
            graph.nodes[int(i)]["name"] = name
    layout.write_graphml(graph, tmp / "graph.graphml")
    records, row = [], 0
    for seq, entry, centred in zip(sequences, computed, centred_rows):
        n = len(entry.features)
        files = [entry.stats.get(path, [path, None, None]) for path in entry.paths]
        records.append(layout.sequence_record(seq.name, seq.fps, (row, row + n), entry.features,
                                                 entry.key, files, entry.skipped, seq.format,
                                                 seq.orientation.to_json(), centred))
        row += n
    width = padded[0].r.shape[1] if padded else 0
    layout.write_manifest(tmp, layout.manifest(
        records,
        params={"bins": bins.to_json(), "structure": settings.params, "mu": settings.mu,
                "skip_bad_frames": settings.skip_bad_frames, "connect": settings.connect,
                "blend_frames": settings.blend_frames, "keep_frames": settings.keep_frames,
                "smooth": settings.smooth},
        feature_columns={"r": width, "theta": bins.n_theta, "phi": bins.n_phi, "centred_r": centred_width},
        counts={"frames": row, "nodes": len(nodes), "edges": graph.number_of_edges(),
                "stored_frames": meshes.frames, "blend_frames": run.blends["frames"],
                "display_steps": run.instants["pairs"] if run.instants else 0},
        bounds=_union(meshes.bounds, run.blends["bounds"] if run.blends["frames"] else meshes.bounds),
        max_counts=np.maximum(meshes.max_counts, run.blends["max_counts"]).tolist()), old=old)


def _union(a, b):
    """The box ``(low, high)`` around the boxes ``a`` and ``b``."""
    return np.minimum(a[0], b[0]).tolist(), np.maximum(a[1], b[1]).tolist()


def build(inputs, out, *, fps=None, bins=None, structure=None, mu=None, skip_bad_frames=False,
          progress=False, workers=None, dask=None, force=False, cache=True, log=None, up=None,
          units=None, mirror=None, front=None, body_frame=True, connect="auto", corrections=None, blend_frames=None,
          keep_frames="motions", smooth=True, open_library=None):
    """Write a library from TVM sequences and return its report (``engine.build``, that is
    :func:`tvmedit.engine.store.library.build`, returns it opened).

    Parameters
    ----------
    inputs : list
        Sequence folders, quoted globs, or ``(name, source)`` pairs (see :func:`expand_inputs`).
        A sequence is named after its folder unless named here.
    out : str or Path
        The library directory to write.
    fps : float or None, every sequence's rate (default: its ``sequence.json``, else 10)
    bins : BinSizes or None, histogram bin sizes (section 3)
    structure : StructureParams or dict or None, parsing parameters (a dict overrides defaults)
    mu : float or None, pruning parameter of eq. (14)
    skip_bad_frames : bool, leave out frames that cannot be read instead of stopping
    connect : {"auto", "off"}
        ``"auto"`` adds the fewest, lightest complete-graph edges that let every motion reach
        every other (:mod:`tvmedit.engine.graph.connect`); ``"off"`` keeps the graph eq. (14) prunes.
    progress : bool, tqdm bars on stderr
    workers : int or None, local worker processes (None: all cores, 1: this process only)
    dask : str or None, a dask.distributed scheduler address or ``"local"``
    force : bool, replace an existing library
    cache : bool
        Look up and store features in the feature cache (:mod:`tvmedit.engine.store.featurecache`); the
        library being replaced is always consulted.
    log : callable or None, called with one-line messages (features reused, stages)
    up, units, mirror, front : str, str, bool, str or None
        The frame of reference of every sequence (``"+y"``, ``"mm"``, True, ``"-z"``: the way the
        subject faces); what is not given is found per sequence (:mod:`tvmedit.engine.capture.orientation`).
    body_frame : bool
        Compute features in the body's own frame (:func:`tvmedit.engine.capture.orientation.feature_frame`),
        the default, so a take parses alike however it is turned; False: in tvmedit's axes.
    corrections : Corrections, dict, str, Path or None
        Corrections by hand applied on top of the parse (:mod:`tvmedit.engine.store.corrections`), or the
        file holding them; None keeps those of the library being replaced, if any; False
        builds from the automatic parse alone.
    blend_frames : int or None
        In-between frames at every transition (:mod:`tvmedit.engine.inbetween.blend`), 0 to
        ``tvmedit.engine.inbetween.blend.MAX_FRAMES``; None (default): as many as keep every step at or below
        the natural step; 0 keeps the paper's cut.
    keep_frames : {"motions", "all"}
        Store the frames of the database motions only (default), or every frame of every
        sequence (``tvmedit.engine.store.settings.KEEP_FRAMES``): a larger library whose corrections by hand
        never read a frame file, even with the capture folder gone.
    smooth : bool, make the display-rate in-betweens (:mod:`tvmedit.engine.inbetween.instants`)
    open_library : callable or None
        Opens the library being replaced (``Library.open``), to reuse its features, corrections
        and meshes (no array of a damaged one, :func:`_sound`); None: nothing is reused from it.

    Returns
    -------
    dict, the report: counts, reused sequences and timings (:func:`report_of`)
    """
    from .corrections import Corrections

    run = _Run(progress, log)
    out = Path(out).absolute()
    settings = Settings.of(bins, structure, mu, skip_bad_frames, connect, blend_frames, keep_frames, smooth)
    given = None if corrections is None else Corrections.coerce(corrections or None)
    old = open_old(out, open_library)
    frame = {"up": up, "units": units, "mirror": mirror, "front": front, "body_frame": bool(body_frame)}
    sequences = open_inputs(inputs, fps, log, frame, old)
    out.parent.mkdir(parents=True, exist_ok=True)
    safewrite.clean_stale(out)
    check_target(out, force, sequences)
    reused, recheck = _sound(old, run), lambda target: check_target(target, force, sequences)  # noqa: E731
    corrections = given if given is not None else kept_corrections(old, sequences, run)
    with safewrite.replacing_folder(out, recheck=recheck, kind="library") as tmp:
        with Workers(workers, dask) as pool, _started(pool):
            computed = run.stage("features", lambda: [
                _sequence_features(seq, settings.bins, settings.skip_bad_frames, pool, reused, cache, run)
                for seq in sequences])
            if given is None and corrections:
                check_kept(corrections, sequences, computed)
            derived = derive(tmp, reused, sequences, computed, settings, corrections, pool=pool, run=run)
    return report_of(derived)


@contextlib.contextmanager
def _started(pool):
    """Start the build's worker processes with scipy imported (each would import it for its
    first in-between run), then import networkx (the motion graph's) on a thread while they
    compute the features: this process only waits for them then, and imported it after them.

    The thread starts once the workers are forked: a fork must never see a thread that holds
    an import's lock (a local pool forks all its workers at once). Only a library outside
    tvmedit is imported there, so no import of ours can wait on it in a cycle."""
    import threading

    preload()
    pool.start()

    def imports():
        try:
            import networkx  # noqa: F401
        except ImportError:
            pass    # said where it is needed

    threading.Thread(target=imports, name="tvmedit-imports", daemon=True).start()
    yield pool


def _sound(old, run):
    """``old``, the library being replaced, where its files hold the bytes its build wrote;
    None (and a note) where some do not: a build from the capture then reuses none of its
    arrays; its corrections by hand, its front and the names given to its motions are still
    kept (``run.names_from``).

    A build reuses the old library's features, meshes and in-between frames, and keeps the
    checksums of the files it links (:func:`tvmedit.engine.store.layout.write_manifest`): from
    a damaged library it would carry the damage over, and the build that ``check`` advises
    for a damaged library would not repair it. Its files are read once more for this: a
    fraction of a second for a 60 fps take's, where the build reads every frame file (a build
    that reads none, every feature cached and every frame stored, pays it in full)."""
    run.names_from = old
    bad = layout.verify(old.path, old.manifest) if old is not None else []
    run.old_whole = old is not None and not bad
    if bad:
        run.say(f"note: the library being replaced is damaged ({', '.join(bad)}); nothing is reused from it"
                + ("; its corrections by hand are kept as they read: look them over (tvmedit correct --help)"
                   if "corrections.json" in bad else ""))
        return None
    return old


#: What :func:`derive` made, for :func:`report_of` to report.
Derived = NamedTuple("Derived", [(name, object) for name in
                                 ("run", "sequences", "computed", "padded", "analysis", "meshes", "pool")])


def derive(tmp, old, sequences, computed, settings, corrections, *, pool, run=None, log=None, parses=None,
           keep_natural=False):
    """The stages after the features, written into the library folder ``tmp``.

    Structure (unless ``parses``, the automatic parse of every sequence, are given),
    corrections, database, graph, stored meshes (copied from ``old`` where it stores them
    from the same frame files, else read) and the library's other files. ``sequences`` need
    ``name``, ``fps``, ``format``, ``orientation`` and ``paths``; ``computed`` are their
    features as :func:`library_features` gives them; ``settings`` a :class:`Settings`.
    :func:`build` and :func:`tvmedit.engine.store.rebuild.rebuild` both go through here; a rebuild keeps
    ``old``'s natural step (``keep_natural``, see :func:`tvmedit.engine.store.inbetweens.blend_library`).

    Returns
    -------
    Derived
    """
    run = run or _Run(False, log)
    corrections.check_sequences({seq.name: len(entry.features) for seq, entry in zip(sequences, computed)})
    width = max(entry.features.r.shape[1] for entry in computed)
    padded = [entry.features.pad_r(width) for entry in computed]
    analysis = _motion_graph(sequences, padded, settings.params, settings.mu, run, corrections, parses,
                             settings.connect)
    rooms = {node.id: analysis.structures[node.sequence].clusters[node.cluster] for node in analysis.nodes}
    across = not keep_natural or _across(old)
    needed = _needed(sequences, computed, analysis, settings, rooms, across)
    meshes = run.stage("meshes", meshfiles.write, tmp, needed, pool, run, old, meshfiles.reusable(old, computed))
    with mapping():     # the library's meshes, mapped in this process until the in-betweens are made
        run.stage("joins", join_library, tmp, [s.name for s in sequences], analysis.graph, analysis.nodes,
                  {s.name: f.vectors for s, f in zip(sequences, padded)}, settings.blend_frames,
                  {s.name: s.fps for s in sequences})
        run.blends = run.stage("blends", blend_library, tmp, [s.name for s in sequences], analysis.graph,
                               settings.blend_frames, {s.name: e.key for s, e in zip(sequences, computed)},
                               pool, run.bar, old, keep_natural, rooms, across)
        if capturecopy.applies(sequences) and run.blends["frames"]:   # in-between frames as an export writes them
            run.stage("draco", capturecopy.encode_blends, tmp, sequences[0].orientation)
        run.instants = run.stage("in-betweens", instant_library, tmp, [s.name for s in sequences], analysis.graph,
                                 run.blends["data"], settings.blend_frames, pool, run.bar, old,
                                 {s.name: e.key for s, e in zip(sequences, computed)},
                                 {s.name: s.fps for s in sequences}) if settings.smooth else None
    run.stage("write", _write_library, tmp, old, sequences, computed, padded, settings, analysis, meshes, run)
    return Derived(run, sequences, computed, padded, analysis, meshes, pool)


def _across(old):
    """Whether ``old``'s loop closings looked at the frame across each wrap (and it stores those
    frames): a rebuild of a library made before they did, which reads no frame file, keeps
    its closings as they were."""
    from ..errors import TvmError

    try:
        return bool(old is not None and old.blend_data().get("across"))
    except TvmError:
        return False


def _needed(sequences, computed, analysis, settings, rooms, across=True):
    """The frames a library stores, ``(sequence index, frame, path, orientation)``: every frame
    (``keep_frames="all"``), else those of the database motions and of the neighbouring
    repetitions their loops are closed onto (:mod:`tvmedit.engine.inbetween.loops`)."""
    index = {seq.name: k for k, seq in enumerate(sequences)}
    if settings.keep_frames == "all":
        needed = [(s, frame) for s, entry in enumerate(computed) for frame in range(len(entry.features))]
    else:
        frames = {(node.sequence, frame) for node in analysis.nodes for frame in range(node.start, node.end + 1)}
        frames |= loop_frames(analysis.graph, settings.blend_frames, rooms, across)
        needed = sorted((index[name], frame) for name, frame in frames)
    return [(s, frame, computed[s].paths[frame], sequences[s].orientation) for s, frame in needed]


def report_of(derived):
    """What :func:`derive` did: counts, reuse and timings (``Library.report``)."""
    run, sequences, computed, padded, analysis, meshes, pool = derived
    return {
        "sequences": len(sequences),
        "frames": sum(len(f) for f in padded),
        "clusters": sum(len(s.clusters) for s in analysis.structures.values()),
        "nodes": len(analysis.nodes),
        "edges": analysis.graph.number_of_edges(),
        "added": analysis.graph.graph["connect"]["added"],
        "stored_frames": meshes.frames,
        "blend_frames": run.blends["frames"],
        "blend_seconds": run.blends["seconds"],
        "blend_made": run.blends["made"],
        "display_steps": run.instants["pairs"] if run.instants else 0,
        "display_made": run.instants["made"] if run.instants else 0,
        "read_frames": run.read_frames,
        "corrected": sorted(name for name, c in analysis.corrections.sequences.items() if c),
        "reused": {seq.name: entry.source for seq, entry in zip(sequences, computed)
                   if entry.source != "computed"},
        "seconds": time.perf_counter() - run.started,
        "stages": run.stages,
        "read_seconds": run.timing["read"],
        "compute_seconds": run.timing["compute"],
        "workers": pool.kind if pool.kind != "processes" else f"{pool.workers} processes",
    }


def _carry_names(old, nodes, tmp):
    """Names given with ``rename`` survive a rebuild where the same texton is still a motion."""
    if old is None:
        return {}
    given = layout.read_names(old.path)
    given = {(n.sequence, n.start, n.end): given[str(n.id)] for n in old.nodes if str(n.id) in given}
    taken = {n.name for n in nodes}
    names = {}
    for node in nodes:
        name = given.get((node.sequence, node.start, node.end))
        if name and name not in taken:
            names[str(node.id)] = name
            taken.add(name)
    if names:
        layout.write_json(tmp / "names.json", names)
    return names
