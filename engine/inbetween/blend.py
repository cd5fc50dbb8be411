"""In-between frames for a transition between frames of different topology.

An edit jumps from the exit frame of one texton to the entry frame of the next (eq. (10)).
The two are separate reconstructions (other vertices, other triangles) of similar but not
equal poses, so without help every transition is a visible pop, a step far larger than one
frame's motion (the symmetric mean Chamfer distance between displayed frames, :func:`chamfer`).
The paper names motion blending at costly transitions as its future work; this module does it
offline, at build time, and the library stores the frames it makes beside the texton frames.

Method: surface alignment, as Prada et al. (2016) blend meshes without correspondence. A
smooth, non-rigid displacement field carries the outgoing frame ``a`` onto the incoming
surface ``b`` (:func:`.fit.align`), and another carries ``b`` back onto ``a``'s half-way warp
(:func:`fields_of`). The in-between frame at time ``t`` (``0 < t < 1``) is ``a`` warped by
``t`` times the first field while ``t < 1/2``, and ``b`` warped back by ``2 (1 - t)`` times the
second from then on: the cut falls in the middle, where the two meet. Every in-between frame is therefore one captured frame's own
mesh with its own colours (and texture), moved smoothly: its area is that of a real frame,
and it is never two people at once, as a blend of two surfaces would be.

The fields are fitted by :mod:`.fit` (non-rigid ICP, by position, or by position and colour).
:func:`blend` fits each run by colour first, and where that run steps far less evenly than the
cut allows (:data:`UNEVEN`), by position too, and keeps the run whose largest steps are the
smaller (:func:`_largest`, on the run's first count of frames). 13_30's transitions then step at most
0.87x the natural step by colour, and the forearms travel whole (looked at); what is left is
milder: on an HDM05 transition the neck's skin is stretched into the shirt for two frames.

How many in-between frames: enough that no displayed step (vertex Chamfer) exceeds the
*natural step*, the median step between consecutive frames inside the database textons
(:func:`frame_count`), at most :data:`MAX_FRAMES`; the caller may fix the count instead
(``blend_frames``; 0 keeps the paper's cut).
"""

import numpy as np

from ..capture.normals import vertex_normals
from .fit import Carrier, align, coloured_points, kdtree

__all__ = ["MAX_FRAMES", "UNEVEN", "FIT", "matched_both_ways", "preload", "chamfer",
           "chamfer_and_tail", "texton_steps", "natural_step", "surface_area", "BlendRun", "blend",
           "fields_of", "frame_count", "side", "check_count"]

#: Most in-between frames one transition gets.
MAX_FRAMES = 8
#: How much farther than the cut's 99th percentile shared evenly over the run (the cut's over the
#: count plus one) a run fitted by colour may step and be kept without a fit by position
#: (:func:`blend`): the fit by position itself steps 0.87-1.44x that (median 1.05x) on 73
#: transitions of eight libraries (the scvv card's two aside, 2.7x and 4.7x).
UNEVEN = 1.2
#: The version of the fit that makes a transition's run, recorded in a library's ``blends.json``:
#: 1 by position alone; 3 by position and by position and colour, the smaller kept on the run's
#: first count, which fit and on what count recorded with each run (2 recorded neither; never
#: released); 4 as 3, but by position only where the run fitted by colour steps far less evenly
#: than the cut allows (:data:`UNEVEN`, :func:`blend`). A rebuild copies transitions of the
#: library it replaces only where this version made them.
FIT = 4


def preload():
    """Import what making runs needs (scipy's k-d tree and sparse matrices) in this process,
    so that worker processes forked after it have it: a rebuild's pool starts for a handful
    of runs, and each worker would otherwise import scipy on its own."""
    import scipy.sparse  # noqa: F401
    import scipy.spatial  # noqa: F401


def chamfer(a, b, tree_a=None, tree_b=None, stride=1):
    """Symmetric mean Chamfer distance between two point sets (metres if they are).

    The mean distance from each point of ``a`` to its nearest point of ``b``, and from ``b``
    to ``a``, averaged.

    Parameters
    ----------
    a, b : (N, 3), (M, 3) float
    tree_a, tree_b : cKDTree, optional
        Prebuilt trees of ``a`` and ``b``.
    stride : int
        Average over every ``stride``-th point only (each still measured against every point
        of the other set): a cheaper estimate of the same mean.

    Returns
    -------
    float

    >>> a = np.zeros((1, 3)); b = np.array([[0.0, 0.0, 0.5]])
    >>> chamfer(a, b)
    0.5
    """
    return chamfer_and_tail(a, b, tree_a, tree_b, stride)[0]


def chamfer_and_tail(a, b, tree_a=None, tree_b=None, stride=1):
    """:func:`chamfer`, and the 99th percentile of the same distances both ways: the few
    hundred vertices of a hand or a forearm that move far while the mean stays small.

    >>> a = np.zeros((1, 3)); b = np.array([[0.0, 0.0, 0.5]])
    >>> chamfer_and_tail(a, b)
    (0.5, 0.5)
    """
    tree_a = kdtree(a) if tree_a is None else tree_a
    tree_b = kdtree(b) if tree_b is None else tree_b
    a_part, b_part = np.asarray(a)[::stride], np.asarray(b)[::stride]
    ab, ba = tree_b.query(a_part)[0], tree_a.query(b_part)[0]
    return 0.5 * float(ab.mean() + ba.mean()), float(np.percentile(np.concatenate([ab, ba]), 99))


def texton_steps(frames, tails=False):
    """Chamfer distances between consecutive frames of one texton (every 4th vertex averaged).

    Parameters
    ----------
    frames : list of (N_k, 3) float
        Vertex positions of the texton's frames in play order.
    tails : bool
        Give each step as ``(chamfer, 99th percentile)`` (:func:`chamfer_and_tail`).

    Returns
    -------
    list of float
        ``len(frames) - 1`` steps; their median over every texton of a library is its
        *natural step* (:func:`natural_step`).
    """
    trees = [kdtree(np.asarray(p)) for p in frames]
    steps = [chamfer_and_tail(frames[k], frames[k + 1], trees[k], trees[k + 1], stride=4)
             for k in range(len(frames) - 1)]
    return steps if tails else [mean for mean, _ in steps]


def natural_step(steps):
    """The median of the steps inside the database textons (metres); 0 when there are none.

    >>> natural_step([[0.01, 0.03], [0.02]])
    0.02
    """
    flat = [s for texton in steps for s in texton]
    return float(np.median(flat)) if flat else 0.0


def surface_area(positions, faces):
    """Total area of a triangle mesh: positions (N, 3), faces (M, 3) -> float.

    >>> surface_area(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float), np.array([[0, 1, 2]]))
    0.5
    """
    p = np.asarray(positions, dtype=np.float64)
    f = np.asarray(faces, dtype=np.intp)
    cross = np.cross(p[f[:, 1]] - p[f[:, 0]], p[f[:, 2]] - p[f[:, 0]])
    return float(0.5 * np.sqrt(np.einsum("ij,ij->i", cross, cross)).sum())


def matched_both_ways(a, b):
    """The 99th percentile of the distances from each point ``a[0]`` to the nearest point of
    ``b`` (its k-d tree ``b[1]``), and from ``b[0]`` to ``a`` (``a[1]``): the figure of
    :func:`tvmedit.engine.inbetween.instants.matched_tail`, for points of
    :func:`.fit.coloured_points` and trees already made.

    >>> p = np.zeros((3, 6)); q = p + [0.0, 0.0, 0.1, 0.0, 0.0, 0.0]
    >>> round(matched_both_ways((p, kdtree(p)), (q, kdtree(q))), 3)
    0.1
    """
    d = np.concatenate([b[1].query(a[0])[0], a[1].query(b[0])[0]])
    return float(np.percentile(d, 99))


class BlendRun:
    """The in-between frames of one transition and the steps they make.

    Attributes
    ----------
    frames : list of tuple
        ``(positions (N, 3) float32, colours (N, 3) uint8, faces (M, 3) uint32, normals (N, 3)
        float32, side)`` per in-between frame, in play order; ``side`` is 0 for a frame warped
        from the outgoing frame, 1 from the incoming one.
    steps : list of float
        Chamfer distance of every displayed step from the exit frame to the entry frame
        (``len(frames) + 1`` of them, every 4th vertex averaged as in :func:`texton_steps`).
    jump : float
        Chamfer distance of the cut itself (exit frame to entry frame).
    fit : dict
        A blended transition's ``{"colour", "chosen_at"}``: whether :func:`blend` kept the fit
        by colour, and on what count it chose; ``{}`` for a cut or a loop's closing. With the
        two frames and the count it says what the run's frames are (``blends.json`` keeps it).
    """

    def __init__(self, frames, steps, jump, fit=None):
        self.frames, self.steps, self.jump, self.fit = frames, steps, jump, fit or {}

    def __len__(self):
        return len(self.frames)


def _warp(mesh, field, amount, side):
    """``(positions, colours, faces, side)`` of ``mesh`` moved by ``amount`` times ``field`` (V, 3)."""
    positions = (np.asarray(mesh[0], np.float32) + np.float32(amount) * field).astype(np.float32)
    return positions, np.asarray(mesh[1], np.uint8), np.asarray(mesh[2], np.uint32), side


def _finished(run):
    """``run`` with every in-between frame's vertex normals, computed once it is chosen."""
    run.frames = [(p, c, f, vertex_normals(p, f), s) for p, c, f, s in run.frames]
    return run


def side(index, count):
    """Which frame the ``index``-th (0-based) of ``count`` in-between frames is warped from:
    0 the outgoing (exit) frame, 1 the incoming (entry) frame. Its time is
    ``t = (index + 1) / (count + 1)``; the cut is at ``t = 1/2``.

    >>> [side(i, 3) for i in range(3)], [side(i, 2) for i in range(2)]
    ([0, 1, 1], [0, 1])
    """
    return 0 if 2 * (index + 1) < count + 1 else 1


def _run(outgoing, incoming, fields, count):
    """The ``count`` in-between frames at times ``k / (count + 1)``, cut at the middle: the
    outgoing frame moved ``t`` of the way by ``fields[0]``, then the incoming frame moved back
    by ``2 (1 - t)`` times ``fields[1]``, which lays it on the outgoing frame's half-way warp."""
    frames = []
    for index in range(count):
        t = (index + 1) / (count + 1)
        if side(index, count) == 0:
            frames.append(_warp(outgoing, fields[0], t, 0))
        else:
            frames.append(_warp(incoming, fields[1], 2.0 * (1.0 - t), 1))
    return frames


def fields_of(a, b, seed=0, colours=None, carriers=None):
    """The two fields of a run from ``a`` to ``b``: ``a`` laid onto ``b``, and ``b`` laid onto
    the half-way surface ``a + field / 2``, not onto ``a``.

    Two fields fitted apart (``a`` onto ``b``, ``b`` onto ``a``) disagree where the fit is
    poor, and the run switches from one to the other in its middle: there a forearm the fits
    carried differently jumps, a few hundred vertices moving far while the mean step stays
    small. Fitting the second onto the first one's middle makes the two warps meet where the
    run switches, to the residual of one fit between surfaces half as far apart.

    ``colours``, ``(a's, b's)`` uint8, match points by colour as well (:func:`.fit.align`);
    ``carriers``, ``a``'s and ``b``'s nodes (:class:`tvmedit.engine.inbetween.fit.Carrier`), where
    another fit made them."""
    carriers = carriers or (None, None)
    forward = align(a, b, seed, colours=colours, carrier=carriers[0])
    return forward, align(b, a + 0.5 * forward, seed, colours=None if colours is None else colours[::-1],
                          carrier=carriers[1])


def _steps(ends, frames, stop=None):
    """Chamfer steps from the exit frame through ``frames`` to the entry frame, and their
    99th percentiles; ``ends`` holds ``(points, tree)`` of the exit and entry frames (built
    once per transition). With ``stop``, None as soon as one step reaches it: the middle step,
    where the run switches from one frame's warp to the other's and the fields' residual
    shows, is measured first, so a count that would not help is told by one step rather than
    all (the same answer, sooner)."""
    points = [ends[0][0], *(f[0] for f in frames), ends[1][0]]
    trees = {0: ends[0][1], len(points) - 1: ends[1][1]}
    steps, tails = [0.0] * (len(points) - 1), [0.0] * (len(points) - 1)
    for i in sorted(range(len(steps)), key=lambda i: abs(2 * i + 1 - len(steps))):
        for k in (i, i + 1):
            if k not in trees:
                trees[k] = kdtree(points[k])
        steps[i], tails[i] = chamfer_and_tail(points[i], points[i + 1], trees[i], trees[i + 1], stride=4)
        if stop is not None and steps[i] >= stop:
            return None
    return steps, tails


def check_count(count):
    """``count`` in-between frames per transition as given (None: as each needs), checked.

    >>> check_count(None), check_count(3.0)
    (None, 3)
    """
    if count is None:
        return None
    from ..checks import whole

    return whole("blend_frames", count, at_least=0, at_most=MAX_FRAMES,
                 hint=" (None: as many as each transition needs)")


def frame_count(jump, natural):
    """In-between frames that bring a cut of Chamfer ``jump`` down to steps of ``natural``.

    >>> frame_count(0.05, 0.02), frame_count(0.01, 0.02), frame_count(1.0, 0.02)
    (2, 0, 8)
    """
    if natural <= 0:
        return 0
    return int(np.clip(np.ceil(jump / natural) - 1, 0, MAX_FRAMES))


def blend(outgoing, incoming, natural, count=None, seed=0, tail=None):
    """In-between frames from the exit frame ``outgoing`` to the entry frame ``incoming``.

    Parameters
    ----------
    outgoing, incoming : tuple
        ``(positions (N, 3), colours (N, 3) uint8, faces (M, 3))`` of the two frames.
    natural : float
        The natural step (metres): the largest step the run should make.
    count : int or None
        In-between frames to make; None: the fewest (up to :data:`MAX_FRAMES`) whose steps
        all stay at or below ``natural``; 0 makes none (the paper's cut).
    seed : int
        Seed of :func:`.fit.align`'s sampling.
    tail : float or None
        The natural step's 99th percentile (:func:`chamfer_and_tail`): with no ``count``
        given, the run also takes frames until no step's 99th percentile exceeds it, so that
        no limb jumps where the mean stays small.

    Returns
    -------
    BlendRun
        Made with the fields fitted by position and colour (:func:`fields_of`), or by
        position alone where that gives the smaller largest steps (:func:`_largest`) on a run
        of the first count of frames; its ``fit`` says which and on what count.

    The fit by position is made only where the run fitted by colour has a step whose 99th
    percentile exceeds :data:`UNEVEN` times the cut's shared evenly over the run: where the fit
    by colour steps as evenly as the fit by position does, the fit by position could be kept
    only for a smaller colour-matched step, and the second fit costs as much as the first. Of 75
    transitions (CMU 13_29 at 10 and 60 fps, 13_30, the gym, three HDM05 takes, a 20 fps take),
    this skips the fit by position on 59; on 8 of them the product would have kept it, by 5-19 %,
    their colour-matched steps within 8 % either way. Blending costs half as much.
    """
    a, b = np.asarray(outgoing[0]), np.asarray(incoming[0])
    ends = ((a, kdtree(a)), (b, kdtree(b)))
    jump, cut_tail = chamfer_and_tail(a, b, ends[0][1], ends[1][1], stride=4)
    if count == 0 or (count is None and jump <= natural and (tail is None or cut_tail <= tail)):
        return BlendRun([], [jump], jump)
    n = max(frame_count(jump, natural), 1) if count is None else count
    carriers = (Carrier(a, seed), Carrier(b, seed))

    def made(colour):
        fields = fields_of(a, b, seed, (outgoing[1], incoming[1]) if colour else None, carriers)
        frames = _run(outgoing, incoming, fields, n)
        return colour, fields, frames, _steps(ends, frames)

    chosen = made(True)
    if max(chosen[3][1]) > UNEVEN * cut_tail / (n + 1):   # steps less evenly than the fit by position would
        looks = [coloured_points(*mesh[:2]) for mesh in (outgoing, incoming)]
        looks = [(p, kdtree(p)) for p in looks]
        chosen = min((chosen, made(False)), key=lambda run: np.prod(_largest(looks, run[2], run[3][1])))
    colour, fields, frames, measured = chosen
    run = _counted(outgoing, incoming, ends, fields, jump, natural, count, tail, n, (frames, measured))
    run.fit = {"colour": colour, "chosen_at": n}
    return _finished(run)


def _counted(outgoing, incoming, ends, fields, jump, natural, count, tail, n, first):
    """The run of :func:`blend` made with ``fields``: ``count`` frames, or (None) the fewest
    from ``n`` on that keep every step within ``natural`` and ``tail``; ``first`` holds the
    frames of ``n`` and their steps (:func:`_steps`), already made."""
    previous = None
    frames, measured = first
    while True:
        if measured is None:
            return previous  # the cut's own residual dominates: more frames would not help
        run = BlendRun(frames, measured[0], jump)
        within = max(measured[0]) <= natural and (tail is None or max(measured[1]) <= tail)
        if count is not None or within or n >= MAX_FRAMES:
            return run
        previous, n = run, n + 1
        frames = _run(outgoing, incoming, fields, n)
        measured = _steps(ends, frames, 0.95 * max(previous.steps))


def _largest(ends, frames, tails):
    """The largest step of a run of ``frames`` (its steps' 99th percentiles ``tails``) by the 99th
    percentile of the vertices' distances to the other frame, ``(by position alone, by
    position and colour)`` (:func:`.fit.coloured_points`, every 4th vertex both ways): a run whose
    limb jumps along the body moves vertices far by the second; one whose fit sheared a
    textured surface (colours matched to like colours of a print nearby) by the first.
    :func:`blend` keeps the fit whose run of its first count of frames has the smaller two by
    their product, so that each counts by its ratio whatever its units: a fit by colour that
    halves the second and leaves the first as it was is kept (CMU 13_30), one that lowers the
    second by 1 % and raises the first by 70 % is not (the scvv card). ``ends`` holds the two
    ends' coloured points and k-d trees, made once for both fits."""
    points = [ends[0][0], *(coloured_points(*mesh[:2]) for mesh in frames), ends[1][0]]
    trees = [ends[0][1], *(kdtree(p) for p in points[1:-1]), ends[1][1]]
    matched = [matched_both_ways((points[k][::4], trees[k]), (points[k + 1][::4], trees[k + 1]))
               for k in range(len(points) - 1)]
    return max(tails), max(matched)
