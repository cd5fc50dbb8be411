"""The in-between frames of a whole library: the build stage that makes and stores them.

:mod:`tvmedit.engine.inbetween.blend` makes one transition's run from two frames; this stage does it for every
edge of the motion graph of a library being written (and closes every motion's loop,
:mod:`tvmedit.engine.inbetween.loops`): it measures the library's natural step on its texton frames, copies
from the library being replaced every run that would come out the same, makes the others on
the workers, and stores them in flat arrays beside the texton frames (``blend_*.npy``,
``blends.json``, written through :class:`tvmedit.engine.store.arrays.MeshWriter`).
"""

import contextlib
import os

import numpy as np

from ..inbetween.blend import FIT, blend, frame_count, natural_step, side, texton_steps
from ..inbetween.loops import close_loop, plan, reach, window

__all__ = ["blend_library", "instant_library", "join", "join_library", "mapping", "NATURAL_PAIRS"]

#: Consecutive texton frame pairs a build measures the natural step on, at most (spread
#: evenly over the textons): the median of 240 is as good as of all, and a 60 fps take
#: stores a thousand pairs.
NATURAL_PAIRS = 240


def _meshes(folder, ids, names=("positions", "colours", "faces")):
    """The arrays ``names`` of the meshes ``ids`` of the library being written in ``folder``
    (its meshes are written, the rest perhaps not yet), a tuple per mesh: ``id`` is a stored
    frame's row, or ``-1 - k`` for its ``k``-th in-between frame."""
    meshes, tables = [], {}
    for mesh_id in ids:
        prefix = "blend_" if mesh_id < 0 else ""
        if prefix not in tables:
            tables[prefix] = _opened(folder, prefix)
        arrays, offsets = tables[prefix]
        v0, nv, f0, nf = offsets[-1 - mesh_id if mesh_id < 0 else mesh_id].tolist()
        meshes.append(tuple(np.asarray(arrays[name][f0:f0 + nf] if name == "faces" else arrays[name][v0:v0 + nv])
                            for name in names))
    return meshes


#: This process's memory maps of the library being written: ``(folder, prefix) -> (signature,
#: (arrays, offsets))``, of one folder at a time.
_OPENED = {}


@contextlib.contextmanager
def mapping():
    """The stages in which this process keeps the library being written mapped
    (:func:`_opened`): its maps are let go at the end, so that no file of a library built,
    or of one left half-written, stays mapped (and its disk space held) after the build."""
    try:
        yield
    finally:
        _OPENED.clear()


def _opened(folder, prefix):
    """``(arrays, offsets)`` of the meshes stored in ``folder`` (``prefix="blend_"``: its
    in-between frames), mapped once a process and again only where a ``frames.npy`` changed.

    A task that reads a few meshes used to map every array and parse its header again: 15 %
    of measuring the natural step of a 60 fps take (1,175 maps for 235 pairs)."""
    from .arrays import frame_offsets, mesh_arrays

    with os.scandir(folder) as entries:
        signature = tuple(sorted((entry.name, entry.inode(), entry.stat().st_size, entry.stat().st_mtime_ns)
                                 for entry in entries if entry.name.endswith("frames.npy")))
    known = _OPENED.get((str(folder), prefix))
    if known is None or known[0] != signature:
        if any(key[0] != str(folder) for key in _OPENED):
            _OPENED.clear()     # one library at a time
        arrays = mesh_arrays(folder, prefix)
        known = _OPENED[str(folder), prefix] = (signature, (arrays, frame_offsets(folder, arrays, prefix)))
    return known[1]


def _rows(folder, names):
    """``{(sequence, frame): row}`` of the frames stored in the library being written in
    ``folder`` (``names``: the sequences in manifest order, as ``frame_keys.npy`` indexes them)."""
    from .arrays import frame_keys

    count = len(_opened(folder, "")[1])
    return {(names[s], f): row for row, (s, f) in enumerate(frame_keys(folder, count, len(names)).tolist())}


def _steps_task(task):
    """Steps between consecutive texton frames of the library being written:
    ``(folder, [[row, next row, ...], ...])`` -> list of ``(step, tail)``, the steps of each run
    of rows one after another (as :func:`texton_steps` with tails; a frame's k-d tree serves
    both its pairs)."""
    folder, runs = task
    return [step for run in runs for step in texton_steps([mesh[0] for mesh in _meshes(folder, run)], tails=True)]


def _runs(pairs):
    """``pairs`` of ``(sequence, frame)`` (each the first frame of a pair) grouped into runs of
    consecutive frames: lists of ``(sequence, frame)`` one frame longer than their pairs."""
    runs = []
    for sequence, frame in pairs:
        if runs and runs[-1][-1] == (sequence, frame):
            runs[-1].append((sequence, frame + 1))
        else:
            runs.append([(sequence, frame), (sequence, frame + 1)])
    return runs


def _natural(folder, rows, graph, pool, known):
    """The natural step of the library being written and its 99th percentile (medians over at
    most :data:`NATURAL_PAIRS` pairs of consecutive texton frames spread evenly over them), and
    ``{(sequence, frame): (step, tail)}`` of those pairs. A pair in ``known`` (the library being replaced measured it, on
    the same frame files) is not measured again: a correction of a few motions measures only
    the pairs of their new textons, not the 240 of every texton (1.3 s of the 2,033-frame gym's
    correction on one core, before)."""
    pairs = [(data["sequence"], f) for _, data in sorted(graph.nodes(data=True))
             for f in range(data["start"], data["end"])]
    pairs = pairs[::max(1, -(-len(pairs) // NATURAL_PAIRS))]
    todo = [p for p in pairs if p not in known]
    chunks = [[]]
    for run in _runs(todo):
        for k in range(0, len(run) - 1, 8):  # pieces of 8 pairs, tasks of 16 pairs at most
            if sum(len(r) - 1 for r in chunks[-1]) + len(run[k:k + 9]) - 1 > 16:
                chunks.append([])
            chunks[-1].append(run[k:k + 9])
    chunks = [chunk for chunk in chunks if chunk]
    tasks = ((str(folder), [[rows[q] for q in run] for run in chunk]) for chunk in chunks)
    measured = dict(zip(todo, (step for steps in pool.map(_steps_task, tasks) for step in steps)))
    steps = {p: tuple(known[p]) if p in known else tuple(measured[p]) for p in pairs}
    return (natural_step([[mean for mean, _ in steps.values()]]), natural_step([[tail for _, tail in steps.values()]]),
            steps)


def join(graph, nodes, vectors, meshes, rates=None):
    """Make each transition of ``graph`` at the pair of frames whose poses are nearest among
    those eq. (10) all but ties (:mod:`tvmedit.engine.inbetween.pairs`): its edge's
    ``exit_frame`` and ``entry_frame`` move there (and the complete graph's ``transitions``, which
    a library stores); its weight stays. ``vectors`` are each sequence's feature vectors, as the
    graph was built on; ``meshes(keys)`` gives ``(positions, colours)`` of frames ``(sequence,
    frame)``; ``rates`` each sequence's frame rate (candidates a tenth of a second apart,
    :func:`tvmedit.engine.inbetween.pairs.stride`; every frame where not given). Returns how many moved."""
    from ..features.vectors import distance_matrix
    from ..graph.motiongraph import entry_range, exit_range
    from ..inbetween.pairs import best_join, candidates, pose_distance, pose_points, stride

    poses, moved = {}, 0
    for u, v, data in sorted(graph.edges(data=True)):
        a, b = nodes[u], nodes[v]
        (x0, x1), (e0, e1) = exit_range(a), entry_range(b)
        va, vb = vectors[a.sequence][x0:x1 + 1], vectors[b.sequence][e0:e1 + 1]
        strides = tuple(stride((rates or {}).get(n.sequence, 10.0)) for n in (a, b))
        pairs = candidates(distance_matrix(np.concatenate([va, vb]))[:len(va), len(va):],
                           (data["exit_frame"] - x0, data["entry_frame"] - e0), strides=strides)
        keys = [key for i, j in pairs for key in ((a.sequence, x0 + i), (b.sequence, e0 + j)) if key not in poses]
        keys = list(dict.fromkeys(keys))
        for key, (positions, colours) in zip(keys, meshes(keys)):
            poses[key] = pose_points(positions, colours)
        best = best_join(pairs, lambda i, j: pose_distance(poses[a.sequence, x0 + i], poses[b.sequence, e0 + j]))
        if best != pairs[0]:
            data["exit_frame"], data["entry_frame"] = x0 + best[0], e0 + best[1]
            graph.graph["transitions"][u, v] = (x0 + best[0], e0 + best[1])
            moved += 1
    return moved


def join_library(folder, names, graph, nodes, vectors, count, rates=None):
    """:func:`join` on the library being written in ``folder`` (every frame of a texton is stored
    there), a build's stage before the in-between frames; none moves where ``count`` is 0 (the
    paper's cut, where eq. (10) makes it). Returns how many moved."""
    if count == 0:
        return 0
    rows = _rows(folder, names)
    return join(graph, nodes, vectors,
                lambda keys: _meshes(folder, [rows[key] for key in keys], ("positions", "colours")), rates)


def _blend_task(task):
    """One edge's run, ``("edge", folder, exit row, entry row, natural, count, tail)``, or one
    texton's loop closing, ``("wrap", folder, {frame: row}, (start, end, at, limit, room), natural,
    tail)`` (the rows of the frames its closing looks at, :func:`_loops`) ->
    ``(frames, steps, jump, cpu seconds, fit)`` (as :class:`BlendRun` has them)."""
    import time

    started = time.process_time()
    if task[0] == "edge":
        _, folder, exit_row, entry_row, natural, count, tail = task
        run = blend(*_meshes(folder, (exit_row, entry_row)), natural, count, tail=tail)
    else:
        _, folder, rows, (start, end, at, limit, room), natural, tail = task
        run = close_loop(lambda frame: _meshes(folder, (rows[frame],))[0], start, end, at, limit, natural, tail,
                         room)
    return run.frames, run.steps, run.jump, time.process_time() - started, run.fit


def _loops(graph, count, rooms, across=True):
    """``(node, (sequence, start, end), (at, limit, room), (first, last))`` of every texton whose
    loop may be closed (:mod:`tvmedit.engine.inbetween.loops`): cycles, not one-shots, with
    ``room = rooms[node]`` the first and last frames of its cluster (None without ``across``:
    the closing does not look at the frame across the wrap), and the frames its closing looks
    at (:func:`tvmedit.engine.inbetween.loops.reach`); none where ``count`` is 0 (the paper's cut)."""
    if count == 0:
        return []
    loops = []
    for node, data in sorted(graph.nodes(data=True)):
        room = tuple(rooms.get(node, (data["start"], data["end"])))
        at, limit = plan(data["start"], data["end"], room)
        if data.get("kind") != "once" and limit > 0:
            room = room if across else None
            loops.append((node, (data["sequence"], data["start"], data["end"]), (at, limit, room),
                          reach(data["start"], data["end"], at, limit, room)))
    return loops


def loop_frames(graph, count, rooms, across=True):
    """``(sequence, frame)`` of the neighbouring repetitions' frames that closing the loops of
    ``graph``'s textons warps onto (a build stores them with the texton frames)."""
    frames = set()
    for _, (seq, _, _), _, (first, last) in _loops(graph, count, rooms, across):
        frames.update((seq, f) for f in range(first, last + 1))
    return frames


def _tasks(folder, edges, loops, rows, natural, count, reuse, tail=None):
    """The runs to make (not copied from the library being replaced): edges, then loop closings."""
    fresh = [(a, b) for _, _, a, b in edges if (a, b) not in reuse]
    tasks = [("edge", str(folder), rows[a], rows[b], natural, count, tail) for a, b in fresh]
    tasks += [("wrap", str(folder), {f: rows[seq, f] for f in range(first, last + 1) if (seq, f) in rows},
               (start, end, at, limit, room), natural, tail)
              for _, (seq, start, end), (at, limit, room), (first, last) in loops
              if ("wrap", seq, start, end, at, limit, (first, last)) not in reuse]
    return tasks


def _store_run(writer, frames, sources, textures, offsets):
    """Append one run's frames to ``writer``, each with the texture of the stored frame it was
    warped from (``sources``: their rows)."""
    for index, ((positions, colours, faces, normals, _), source) in enumerate(zip(frames, sources)):
        uv, texture_row = (None, None) if textures is None else (
            textures[0][offsets[source][0]:offsets[source][0] + offsets[source][1]], textures[2][source])
        writer.add(-1, index, positions, colours, faces, normals, uv=uv, texture_row=texture_row)


def blend_library(folder, names, graph, count, keys, pool, bar=None, old=None, keep_natural=False, rooms=None,
                  across=True):
    """Make and store the in-between frames of every edge of ``graph`` and the closing frames
    of every texton's loop (:mod:`tvmedit.engine.inbetween.loops`; a build's stage after the meshes):
    ``blend_*.npy`` in ``folder`` (see :mod:`tvmedit.engine.store.layout`).

    Parameters
    ----------
    folder : Path, the library being written; its texton frames are stored
    names : list of str, the sequences in manifest order (``frame_keys.npy`` indexes them)
    graph : networkx.DiGraph, the final motion graph (nodes with ``sequence``, ``start``,
        ``end``; edges with ``exit_frame`` and ``entry_frame``)
    count : int or None, in-between frames per transition (None: as many as each needs)
    keys : dict, ``sequence -> feature key`` (the frame files it was read from)
    pool : tvmedit.engine.parallel.Workers: tasks of 16 pairs of texton frames, then one per edge
    bar : callable or None, ``bar(total, desc, unit=...)`` makes a progress bar, advanced once per edge
    old : tvmedit.engine.store.library.Library or None, the library being replaced: a run it holds
        for the same frames of the same files, natural step and count is copied, not made again.
    rooms : dict, ``node -> (first, last)`` frame of its cluster, where closing its loop may look
    across : bool, closings look at the frame across the wrap (:func:`tvmedit.engine.inbetween.loops.reach`);
        False in a rebuild of a library whose closings did not (``blends.json``'s ``across``)
    keep_natural : bool, keep ``old``'s natural step (a rebuild from corrections by hand: the
        capture's pace is what it was; only the runs of the transitions it changed are made anew)

    Returns
    -------
    dict: ``data`` (``blends.json``), ``frames`` (in-between frames stored), ``seconds`` (CPU seconds
    of the runs), ``made`` (runs made, not copied), ``bounds`` and ``max_counts``.
    """
    from .arrays import MeshWriter

    arrays, offsets = _opened(folder, "")
    offsets = offsets.tolist()
    rows = _rows(folder, names)
    data = _old_data(old, keys)
    known = {(row[0], row[1]): (row[2], row[3]) for row in data.get("pair_steps", []) if len(row) == 4}
    if keep_natural and data.get("natural_step", 0) > 0:
        natural, tail, measured = float(data["natural_step"]), data.get("natural_tail"), known
    else:
        natural, tail, measured = _natural(folder, rows, graph, pool, known)
    textures = _textures(folder, len(arrays["positions"]), len(offsets))
    reuse = _old_runs(data, natural, count, tail)
    edges = [(u, v, (graph.nodes[u]["sequence"], d["exit_frame"]), (graph.nodes[v]["sequence"], d["entry_frame"]))
             for u, v, d in sorted(graph.edges(data=True))]
    loops = _loops(graph, count, rooms or {}, across)
    tasks = _tasks(folder, edges, loops, rows, natural, count, reuse, tail)
    plans = {u: (limit, span) for u, _, (_, limit, _), span in loops}
    made = pool.map(_blend_task, tasks)
    progress = bar(len(edges) + len(loops), "blends", unit="run") if bar is not None else None
    records, closings, seconds = [], [], 0.0
    jobs = [(u, v, a, b) for u, v, a, b in edges] + [(u, u, at, texton) for u, texton, (at, _, _), _ in loops]
    try:
        with MeshWriter(folder, prefix="blend_") as writer:
            for u, v, a, b in jobs:
                wrap = u == v
                key = ("wrap", *b, a, *plans[u]) if wrap else (a, b)
                frames, steps, jump, cpu, fit = _copied(old, reuse[key], wrap) if key in reuse else next(made)
                if wrap:  # a loop's closing: the texton frames it warps, in play order
                    seq, at, warped = b[0], a, window(b[1], b[2], a, len(frames))[0]
                    a, b = (seq, b[2]), (seq, b[1])  # the wrap itself, end -> start
                first = writer.frames
                sources = [rows[seq, warped[index]] if wrap else rows[(a, b)[frame[4]]]
                           for index, frame in enumerate(frames)]
                _store_run(writer, frames, sources, textures, offsets)
                record = {"from": u, "to": v, "first": first, "count": len(frames), "jump": jump,
                          "steps": steps, "exit": list(a), "entry": list(b), **fit,
                          **({"at": at, "limit": plans[u][0], "reach": [int(f) for f in plans[u][1]],
                              "texton": [seq, graph.nodes[u]["start"], graph.nodes[u]["end"]]} if wrap else {})}
                (records if u != v else closings).append(record)
                seconds += cpu
                if progress is not None:
                    progress.update()
    finally:
        if progress is not None:
            progress.close()
    data = {"fit": FIT, "natural_step": natural, "natural_tail": tail, "blend_frames": count, "feature_keys": keys,
            "across": across, "edges": records, "wraps": closings,
            "pair_steps": [[name, frame, *step] for (name, frame), step in measured.items()]}
    return {"data": data, "frames": writer.frames, "seconds": seconds, "made": len(tasks),
            "bounds": writer.bounds, "max_counts": writer.max_counts}


def _textures(folder, vertices, frames):
    """The texton frames' ``(uvs, texels, rows)`` (memory-mapped), or None when untextured."""
    from pathlib import Path

    from .arrays import texture_arrays

    return texture_arrays(folder, vertices, frames) if (Path(folder) / "uvs.npy").exists() else None


def _old_data(old, keys):
    """What ``old``'s ``blends.json`` holds about the sequences read from the same frame files
    (``keys``: sequence -> feature key) as the library being written: its ``edges`` between
    such sequences and its measured ``pair_steps`` of them; ``{}`` when there is nothing."""
    from ..errors import TvmError

    try:
        data = old.blend_data() if old is not None else {}
    except TvmError:  # a damaged library being replaced lends nothing
        return {}
    if not data:
        return {}
    same = {name for name, key in data.get("feature_keys", {}).items() if keys.get(name) == key}
    return dict(data, edges=[e for e in data["edges"] if e["exit"][0] in same and e["entry"][0] in same],
                wraps=[w for w in data.get("wraps", []) if w["entry"][0] in same],
                pair_steps=[row for row in data.get("pair_steps", []) if row[0] in same])


def _old_runs(data, natural, count, tail=None):
    """``{(exit, entry): (first row, count, jump, steps)}`` of the runs of the old library's
    ``data`` (:func:`_old_data`) that a new build would make the same: same count option, and
    a run :func:`blend` gives again at this natural step (:func:`_same_run`; a correction that
    changes the motions changes the natural step a little, and should not make every run again)."""
    if not data or data.get("blend_frames") != count or (count is None and data.get("natural_tail") != tail):
        return {}
    # A transition made by another fit (blend.FIT) is made again; a loop's closing is fitted by position alone.
    runs = {(tuple(e["exit"]), tuple(e["entry"])): (e["first"], e["count"], e["jump"], e["steps"],
                                                    {k: e[k] for k in ("colour", "chosen_at") if k in e})
            for e in data["edges"] if data.get("fit", 1) == FIT and (
                count is not None or _same_run(e, data["natural_step"], natural))}
    if data["natural_step"] == natural:  # a loop's closing is kept at the same natural step only
        # The same texton closed at the same end and as far: a correction that moves its
        # cluster's edge may change where it is closed, and then it is closed anew.
        # A closing recorded before closings looked across the wrap has the reach without it.
        runs.update({("wrap", *w["texton"], w["at"], w["limit"],
                      tuple(w["reach"]) if "reach" in w else reach(*w["texton"][1:], w["at"], w["limit"])):
                     (w["first"], w["count"], w["jump"], w["steps"], {})
                     for w in data.get("wraps", []) if "limit" in w})
    return runs


def _same_run(run, was, natural):
    """Whether :func:`blend` at ``natural`` returns the stored ``run`` (a ``blends.json`` edge,
    made at natural step ``was`` with no count given): its fields and warps depend on the two
    frames and on the fit it chose on its first count alone, so it does when its first guess of
    the count is this run's, the fit was chosen on that count and the run's steps already stay
    within ``natural``, or when it was and stays a plain cut."""
    if natural == was:
        return True
    if run["count"] == 0:
        return run["jump"] <= natural
    return (run["jump"] > natural and max(frame_count(run["jump"], natural), 1) == run["count"]
            and run.get("chosen_at") == run["count"] and max(run["steps"]) <= natural)


def _copied(old, run, wrap=False):
    """A run of ``old`` as :func:`_blend_task` returns one (no CPU time spent)."""
    first, count, jump, steps, fit = run
    frames = []
    for index in range(count):
        positions, colours, faces, normals = old.blend_row(first + index)
        frames.append((np.array(positions), np.array(colours), np.array(faces), np.array(normals),
                       index if wrap else side(index, count)))
    return frames, steps, jump, 0.0, fit


def _field_task(task):
    """The fields of a few display steps: ``(folder, [(from id, to id), ...])`` -> list of
    float16 (N, 3) (:func:`tvmedit.engine.inbetween.instants.step_field`); a mesh read once."""
    from ..inbetween.instants import step_field

    folder, pairs = task
    ids = list(dict.fromkeys(i for pair in pairs for i in pair))
    meshes = dict(zip(ids, _meshes(folder, ids, ("positions", "normals", "faces"))))
    fields = []
    for a, b in pairs:
        field = _same_mesh_field(meshes[a], meshes[b])
        fields.append(field if field is not None else step_field(meshes[a][0], *meshes[b][:2], a_normals=meshes[a][1]))
    return fields


def _same_mesh_field(a, b):
    """Where ``b`` is ``a``'s own mesh moved (two in-between frames warped from one captured
    frame, or a captured frame and its warp), the exact field ``b - a``: no fit; else None."""
    if len(a[0]) != len(b[0]) or len(a[2]) != len(b[2]) or not np.array_equal(a[2], b[2]):
        return None
    return (np.asarray(b[0], np.float32) - np.asarray(a[0], np.float32)).astype(np.float16)


#: Display steps a worker's task fits, at most (a few frames' fits: scheduling stays cheap
#: and every core busy to the end).
FIELDS_PER_TASK = 6


def instant_library(folder, names, graph, blends, count, pool, bar=None, old=None, keys=None, rates=None):
    """Make and store the field of every step a schedule of the library shows
    (:mod:`tvmedit.engine.inbetween.instants`), a build's stage after the in-between frames:
    ``instant_pairs.npy`` (per step: from mesh id, to mesh id, first row, rows) and
    ``instant_fields.npy`` (float16, a row per vertex of each step's first mesh).

    ``blends`` is what ``blends.json`` holds (:func:`blend_library`'s ``data``); with ``count``
    0 (the paper's cut) the cut itself gets no field. A step the library being replaced
    (``old``) holds between the same meshes (:func:`_shows`: stored frames read from the same
    frame files, ``keys``: sequence -> feature key, or in-between frames of the same run) is
    copied, not fitted again: a correction by hand fits only the steps of the textons and
    transitions it changed. A step of a sequence whose rate (``rates``: sequence
    -> fps) is :data:`tvmedit.engine.inbetween.instants.FIELDS_BELOW_FPS` or more gets none.
    Returns ``{"pairs"`` (fields stored), ``"steps"``
    (steps looked at), ``"made"`` (steps fitted), ``"seconds"}``.
    """
    import time

    from .arrays import NpyStream
    from ..inbetween.instants import FIELDS_BELOW_FPS, display_pairs

    started = time.perf_counter()
    rows = _rows(folder, names)
    frames = {row: key for key, row in rows.items()}
    nodes = [(d["sequence"], d["start"], d["end"]) for _, d in sorted(graph.nodes(data=True))]
    edges = [e for e in blends["edges"] if count != 0 or e["count"]]
    pairs = display_pairs(nodes, edges, blends.get("wraps", []), lambda seq, frame: rows[seq, frame])
    shows = _shows(frames, blends)
    fast = {name for name, fps in (rates or {}).items() if fps >= FIELDS_BELOW_FPS}
    pairs = [pair for pair in pairs if not _sequences_of(shows[pair[0]]) & fast]
    kept = _old_fields(old, keys or {})
    copied = {(a, b): kept[shows[a], shows[b]] for a, b in pairs if (shows.get(a), shows.get(b)) in kept}
    todo = [pair for pair in pairs if pair not in copied]
    chunks = [todo[k:k + FIELDS_PER_TASK] for k in range(0, len(todo), FIELDS_PER_TASK)]
    progress = bar(len(pairs), "in-betweens", unit="step") if bar is not None else None
    table, stream = [], NpyStream(folder / "instant_fields.npy", np.float16, 3)
    try:
        made = (field for fields in pool.map(_field_task, ((str(folder), chunk) for chunk in chunks))
                for field in fields)
        for a, b in pairs:
            field = np.asarray(copied[a, b]) if (a, b) in copied else next(made)
            if field is not None:   # None: the step is shown as captured (instants.helps)
                table.append((a, b, stream.rows, len(field)))
                stream.append(field)
            if progress is not None:
                progress.update()
    finally:
        stream.close()
        if progress is not None:
            progress.close()
    np.save(folder / "instant_pairs.npy", np.array(table, np.int64).reshape(-1, 4))
    return {"pairs": len(table), "steps": len(pairs), "made": len(todo), "seconds": time.perf_counter() - started}


def _shows(frames, blends):
    """``{mesh id: what it shows}``: a stored frame's ``("frame", sequence, frame)``; an in-between
    frame's run and place in it, ``("edge", exit, entry, count, k, fit, colour)`` or ``("wrap",
    texton, at, count, k)``. A run's frames follow from its two ends (or its texton), its count,
    the fit that made a transition's (:data:`tvmedit.engine.inbetween.blend.FIT`, and whether
    it kept the fit by colour) and the frames' files alone, so two libraries' mesh ids that
    show the same are the same mesh."""
    shows = {row: ("frame", *key) for row, key in frames.items()}
    fit = blends.get("fit", 1)
    for edge in blends.get("edges", []):
        for k in range(edge["count"]):
            shows[-1 - (edge["first"] + k)] = ("edge", tuple(edge["exit"]), tuple(edge["entry"]), edge["count"], k,
                                               fit, edge.get("colour"))
    for wrap in blends.get("wraps", []):
        for k in range(wrap["count"]):
            shows[-1 - (wrap["first"] + k)] = ("wrap", tuple(wrap["texton"]), wrap["at"], wrap["count"], k)
    return shows


def _sequences_of(shown):
    """The sequences whose frames a mesh id's :func:`_shows` entry is made from."""
    if shown[0] == "edge":
        return {shown[1][0], shown[2][0]}
    return {shown[1][0]} if shown[0] == "wrap" else {shown[1]}


def _old_fields(old, keys):
    """``{(shows, shows): field}`` (:func:`_shows`) of the steps ``old`` holds, stored and
    in-between frames alike, for sequences read from the same frame files as the library being
    written (``keys``); {} when there is none or it cannot be read."""
    from ..errors import TvmError

    try:
        if old is None or not old.smooth:
            return {}
        same = {r["name"] for r in old.manifest["sequences"] if keys.get(r["name"]) == r.get("feature_key")}
        shows = _shows(dict(enumerate(old.stored_frames())), old.blend_data())
        table, fields = old._instants
    except (TvmError, KeyError, ValueError):   # a damaged library being replaced lends nothing
        return {}
    return {(shows[a], shows[b]): fields[first:first + size] for (a, b), (first, size) in table.items()
            if a in shows and b in shows and _sequences_of(shows[a]) | _sequences_of(shows[b]) <= same}
