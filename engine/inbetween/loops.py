"""Closing a motion's loop: the wrap from a texton's last frame back to its first, without a pop.

Section 8 plays a texton as a cycle: after its last frame ``end`` comes its first, ``start``.
The texton is one period of a repeated motion found on the features (eq. (5)-(9)), so ``end``
and ``start`` are close poses; but the period is a whole number of frames and no two
repetitions are the same, so the wrap can jump (the symmetric mean Chamfer distance of
:func:`tvmedit.engine.inbetween.blend.chamfer`) once per cycle, and a looping motion is where
an edit spends most of its time.

Method: a cross-fade with the neighbouring repetition, as loops of captured motion are
closed. The frame before ``start`` in the capture, ``start - 1``, is the previous repetition's
last frame and follows into ``start`` by a natural step; so the texton's last ``k`` frames,
``end - m`` for ``m = k - 1 .. 0``, are each warped a growing share ``(k - m) / k`` of the way
onto the surface of the previous repetition's frame of the same phase, ``start - 1 - m``
(:func:`tvmedit.engine.inbetween.fit.align`), and the last one lies on ``start - 1``. Where
the texton is the first of its cluster, the next repetition is used instead, at the other
end: its first ``k`` frames, ``start + m``, are warped onto ``end + 1 + m`` by ``(k - m) / k``,
so ``end`` leads into them as into ``end + 1`` (:func:`plan`, :func:`window`).

What counts as a pop is a step beyond both the library's natural step and the capture's own
step at the same phase (:func:`paces`): a fast motion steps more than the natural step between
every pair of captured frames, and more at some phases than at others, so each step of the
path through the window is held to what the capture steps at its phase, in the texton and in
the repetition the window is warped onto (the larger), not to what it steps at the wrap.
``k`` is the fewest (1 to :data:`MAX_CLOSING`, at most a third of the texton and as many as
the cluster holds beyond it) whose steps around the wrap all stay at or below that, else the
one with the smallest largest step; 0 where the wrap is already no larger, or where no
closing makes the largest step smaller than the wrap's, by that measure and in metres
(:func:`close_loop`).

Every frame stays one captured frame's own mesh, colours and motion, moved; none is left out
and none added, so a schedule's length, the play length rule, edits of a given length
(:mod:`tvmedit.engine.graph.timing`) and the player's counts are unchanged. The warped frames
are shown only where a visit plays the whole window and wraps next to it (:func:`closing`): a
visit that leaves the texton inside the window, or enters inside it, shows the captured
frames, so transitions (whose in-between frames start from captured frames) are as they were.
"""

__all__ = ["MAX_CLOSING", "closing", "closed_at", "plan", "window", "close_loop", "reach", "phase_pairs", "paces"]

#: Most texton frames a loop's closing warps.
MAX_CLOSING = 4


def plan(start, end, cluster):
    """Where texton ``start..end`` of a cluster ``(first, last)`` frames is closed, and how far.

    Returns
    -------
    (str, int)
        ``"end"`` (the last frames are warped onto the previous repetition's) or ``"start"``
        (the first onto the next one's), and the most frames that may be warped (0: the
        loop is not closed).

    >>> plan(20, 31, (0, 60)), plan(0, 11, (0, 60)), plan(0, 11, (0, 11))
    (('end', 4), ('start', 4), ('end', 0))
    """
    most = min(MAX_CLOSING, (end - start + 1) // 3)
    before, after = start - cluster[0], cluster[1] - end
    if before >= min(most, after):
        return "end", min(most, before)
    return "start", min(most, after)


def window(start, end, at, count):
    """Texton frames the closing warps, in play order, and the frame each is warped onto.

    >>> window(20, 31, "end", 2), window(20, 31, "start", 2)
    (([30, 31], [18, 19]), ([20, 21], [32, 33]))
    """
    if at == "end":
        return list(range(end - count + 1, end + 1)), list(range(start - count, start))
    return list(range(start, start + count)), list(range(end + 1, end + 1 + count))


def closing(frames, start, end, count, at="end", rests=False):
    """Which frames of one visit of a texton are replaced by its loop's closing frames.

    Parameters
    ----------
    frames : list of int
        The texton frames a visit shows, in order (cyclic from its entry frame).
    start, end : int
        The texton.
    count : int
        Frames the texton's closing warps (``k``; 0: none).
    at : {"end", "start"}
        Which end of the texton they are (:func:`plan`).
    rests : bool
        The visit goes on after ``frames`` (the player resting in its last motion).

    Returns
    -------
    list of int or None
        Per frame, the index of the closing frame shown instead (0 .. count - 1, in play
        order), or None: a frame is replaced where the visit shows the whole window and
        wraps right after it (``at="end"``) or right before it (``at="start"``).

    >>> closing([10, 11, 12, 13, 10, 11, 12, 13], 10, 13, 2)
    [None, None, 0, 1, None, None, None, None]
    >>> closing([12, 13, 10, 11, 12, 13], 10, 13, 2, rests=True)
    [None, None, None, None, 0, 1]
    >>> closing([12, 13, 10, 11, 12, 13], 10, 13, 2, at="start")
    [None, None, 0, 1, None, None]
    """
    return [closed_at(i, frame, start, end, count, at, None if rests else len(frames) - i)
            for i, frame in enumerate(frames)]


def closed_at(shown, frame, start, end, count, at, left):
    """The index of the closing frame shown instead of texton frame ``frame``, or None: the one
    rule :func:`closing` and the realtime playhead (:class:`tvmedit.engine.playback.Playhead`) apply.

    ``shown`` frames of the visit came before it; ``left`` are still to show, this one
    included (None: the visit goes on). The frame is replaced where the visit shows the whole
    window (its first frame comes after the visit's entry) and wraps right after the window
    (``at="end"``) or has wrapped right before it (``at="start"``).

    >>> closed_at(2, 12, 10, 13, 2, "end", 6), closed_at(2, 12, 10, 13, 2, "end", 2)
    (0, None)
    """
    index = frame - (end - count + 1 if at == "end" else start)
    if not (count and 0 <= index < count and shown > index):
        return None
    if left is not None and left < count - index + (at == "end"):
        return None
    return index


def close_loop(meshes, start, end, at, limit, natural, tail=None, room=None):
    """The closing frames of one texton's loop (:func:`plan` gives ``at`` and ``limit``).

    Parameters
    ----------
    meshes : callable
        ``meshes(frame)``: ``(positions, colours, faces)`` of a frame of the sequence (:func:`window`).
    start, end, at, limit : int, int, {"end", "start"}, int
        The texton, where it is closed, and the most frames to warp.
    room : (int, int) or None
        The first and last frames of the texton's cluster (:func:`reach`).
    natural, tail : float, float or None
        The library's natural step and its 99th percentile
        (:func:`tvmedit.engine.inbetween.blend.chamfer_and_tail`), which a closing's steps keep
        within (or the capture's own at each step's phase, :func:`paces`).

    Returns
    -------
    tvmedit.engine.inbetween.blend.BlendRun
        ``count = len(run)`` warped frames in play order (``side`` is the frame's index; none
        where the wrap is at most the larger of ``natural`` and the capture's own step there
        (:func:`paces`), or where no closing lowers its
        largest step below the wrap's); ``jump`` is the wrap's own step (``end`` to
        ``start``), ``steps`` those from the last captured frame before the window (or ``end``)
        through the window to ``start`` (or the first captured frame after it).
    """
    import numpy as np

    from .blend import BlendRun, chamfer_and_tail
    from .fit import kdtree
    from ..capture.normals import vertex_normals

    cache = {}
    first, last = reach(start, end, at, limit, room)

    def mesh(frame):  # each frame read once, with its k-d tree built once
        if frame not in cache:
            positions, colours, faces = meshes(frame)
            positions = np.asarray(positions)
            cache[frame] = (positions, colours, faces, kdtree(positions))
        return cache[frame]

    def step(a, b):
        return chamfer_and_tail(a[0], b[0], a[3], b[3], stride=4)

    jump, jump_tail = step(mesh(end), mesh(start))
    if natural <= 0 or limit <= 0:
        return BlendRun([], [jump], jump)
    goals = _phase_goals(lambda f, g: step(mesh(f), mesh(g)), natural, tail, start, end, at,
                         lambda frame: first <= frame <= last)
    # A step's size against its goal, by its mean and (given the library's) its tail.
    size = (lambda m, t, g: max(m / g[0], t / g[1])) if tail else (lambda m, t, g: m / g[0])
    wrap_size = size(jump, jump_tail, goals(0)[0])
    if wrap_size <= 1.0:
        return BlendRun([], [jump], jump)
    fields, best, best_sizes = {}, None, None
    for count in range(1, limit + 1):
        frames, run = _warped_window(mesh, fields, start, end, at, count)
        ends = (frames[0] - 1, start) if at == "end" else (end, frames[-1] + 1)
        points = [mesh(ends[0]), *run, mesh(ends[1])]
        figures, sizes, goal = [(0.0, 0.0)] * (len(points) - 1), [0.0] * (len(points) - 1), goals(count)
        stop = None if best is None else 0.95 * max(best_sizes)
        # The step at the wrap first: a count that would not help is told by it alone.
        for i in sorted(range(len(sizes)), reverse=at == "end"):
            figures[i] = step(points[i], points[i + 1])
            sizes[i] = size(*figures[i], goal[i])
            if stop is not None and sizes[i] >= stop:
                break
        if stop is not None and max(sizes) >= stop:
            break  # more frames would not help
        if max(m for m, _ in figures) >= 0.95 * jump:
            continue  # a step not clearly less far than the wrap (a jump moved to a faster phase is still one)
        best = BlendRun([(p, c, f, None, i) for i, (p, c, f, _) in enumerate(run)], [m for m, _ in figures], jump)
        best_sizes = sizes
        if max(sizes) <= 1.0:
            break
    if best is None or max(best_sizes) >= wrap_size:  # the warps' own residual outweighs the wrap: keep the cut
        return BlendRun([], [jump], jump)
    best.frames = [(p, c, f, vertex_normals(p, f), i) for p, c, f, _, i in best.frames]
    return best


def _phase_goals(step, natural, tail, start, end, at, has):
    """``goals(count)``: per step of the path through a closing of ``count`` frames, the larger
    of the natural step (and ``tail``) and the capture's own step at its phase (:func:`paces`),
    ``(mean, 99th percentile)``; each captured step measured once by ``step(f, g)``."""
    captured = {}

    def measured(f, g):
        if (f, g) not in captured:
            captured[f, g] = step(f, g)
        return captured[f, g]

    return lambda count: [(max(natural, m), max(tail or 0.0, t))
                          for m, t in paces(measured, start, end, at, count, has)]


def _warped_window(mesh, fields, start, end, at, count):
    """The texton frames a closing of ``count`` warps (:func:`window`) and the frames it shows
    instead, in play order: each moved its share of the way onto the neighbouring repetition's
    frame of its phase, ``(positions, colours, faces, k-d tree)``. ``mesh(frame)`` gives a
    frame's ``(positions, colours, faces, tree)``; ``fields`` keeps each frame's alignment
    (:func:`tvmedit.engine.inbetween.fit.align`) for the next count."""
    import numpy as np

    from .fit import align, kdtree

    frames, targets = window(start, end, at, count)
    run = []
    for index, (frame, target) in enumerate(zip(frames, targets)):
        if frame not in fields:
            fields[frame] = align(mesh(frame)[0], mesh(target)[0])
        share = (index + 1) / count if at == "end" else (count - index) / count
        positions, colours, faces, _ = mesh(frame)
        positions = (np.asarray(positions, np.float32) + np.float32(share) * fields[frame]).astype(np.float32)
        run.append((positions, np.asarray(colours, np.uint8), np.asarray(faces, np.uint32), kdtree(positions)))
    return frames, run


def reach(start, end, at, limit, room=None):
    """The frames a closing of at most ``limit`` frames looks at, ``(first, last)``: the texton,
    the frames its window may be warped onto (:func:`window`), and, where the cluster's frames
    ``room`` ``(first, last)`` hold it, the frame the capture shows after the texton's last
    (closed at its end) or before its first (at its start), all of them stored by a build. The
    capture's own steps a closing is held to (:func:`paces`) are those within them, so a
    library keeping every frame closes its loops as one keeping only its motions' does.

    Why the frame across the wrap: the wrap replaces the capture's step from ``end`` to
    ``end + 1`` (and from ``start - 1`` to ``start``); that step is the capture's own pace at the
    wrap's phase, the first thing a wrap is to be held to. Without it, a fast motion whose
    other pair at that phase is slower (13_30's motion 01: 2.0 natural steps from its last
    frame to the next, 1.73 into its first) reads as a pop where it is not one.

    >>> reach(20, 31, "end", 4), reach(20, 31, "start", 4), reach(20, 31, "end", 4, (10, 40))
    ((16, 31), (20, 35), (16, 32))
    """
    first, last = (start - limit, end) if at == "end" else (start, end + limit)
    if room is not None and at == "end" and end + 1 <= room[1]:
        last = end + 1
    if room is not None and at == "start" and start - 1 >= room[0]:
        first = start - 1
    return first, last


def phase_pairs(start, end, at, count):
    """The captured steps at the phase of each step a wrap closed by ``count`` frames shows.

    The path runs from the captured frame before the window, through its ``count`` warped
    frames, to the captured frame after it (``count + 1`` steps; with 0, the wrap itself,
    ``end`` to ``start``). At each step's phase the capture steps twice, once in the texton,
    ``q`` to ``q + 1``, and once in the neighbouring repetition the window is warped onto, a
    period (``end + 1 - start`` frames) away: the pairs of frames of both, per step.

    >>> phase_pairs(20, 31, "end", 2)
    [[(29, 30), (17, 18)], [(30, 31), (18, 19)], [(31, 32), (19, 20)]]
    >>> phase_pairs(20, 31, "start", 1)
    [[(19, 20), (31, 32)], [(20, 21), (32, 33)]]
    """
    period = end + 1 - start
    if at == "end":
        return [[(q, q + 1), (q - period, q + 1 - period)] for q in range(end - count, end + 1)]
    return [[(q, q + 1), (q + period, q + 1 + period)] for q in range(start - 1, start + count)]


def paces(step, start, end, at, count, has):
    """The capture's own step at the phase of each step of a closed wrap's path
    (:func:`phase_pairs`): ``(mean, 99th percentile)`` per step, the larger of the two captured
    steps there whose frames ``has(frame)`` (at least one pair of each step's always is, where
    ``has`` holds the :func:`reach` of a closing; (0, 0) where none is). ``step(f, g)``
    measures the step from frame ``f`` to frame ``g``.

    A fast motion steps more than the library's natural step in every frame, and more at some
    phases than at others: a closing frame pops only where it steps more than the capture does
    at its own phase, not more than at the wrap's.

    >>> paces(lambda f, g: (f / 10, f / 5), 20, 31, "start", 1, lambda f: f < 33)
    [(3.1, 6.2), (2.0, 4.0)]
    """
    out = []
    for pairs in phase_pairs(start, end, at, count):
        found = [step(f, g) for f, g in pairs if has(f) and has(g)] or [(0.0, 0.0)]
        out.append((max(m for m, _ in found), max(t for _, t in found)))
    return out
