"""Cluster boundaries from the novelty: where the take changes exercise.

The novelty of a frame is the energy distance between the ``novelty_window`` seconds of
frames before it and after it (:func:`tvmedit.engine.parse.atoms.novelty`), on the sequence
reduced to about 10 fps: 2 E|X - Y| - E|X - X'| - E|Y - Y'| over frame distances, a
checkerboard kernel along the diagonal of the frame-distance matrix. It is near zero inside
an exercise whatever its phase (both blocks hold whole cycles of the same poses) and peaks
where the pose distribution changes. The rules it is read by:

* **Pose and pace** (:func:`novelty_rows`, :func:`pace`). Each row is a block's mean
  histograms and, weighted by ``novelty_pace``, how fast each bin changes over
  :data:`PACE_SECONDS`: exercises of alike poses at another tempo differ only in pace.
* **Rows whitened** (:func:`whiten`, ``novelty_components``). Rows are compared on the take's
  principal axes of change, each scaled to its spread (plus :data:`WHITEN_FLOOR`), so that
  two exercises that differ along a direction of little variance still stand out;
  ``novelty_threshold`` is in units of that spread.
* **Changes of the whole take** (``partition``, :mod:`tvmedit.engine.parse.partition`). The
  boundaries are the changes of the partition of the rows of least within-segment energy
  scatter plus a penalty per change: exercises of alike poses differ little within a few
  seconds but clearly over whole segments. Each change is read on the novelty's top within
  :data:`PEAK_REACH_S`; none where that stays under ``partition_floor`` of the threshold.
  With ``partition`` 0 the boundaries are the novelty's local maxima over the threshold,
  strongest first, at least ``min_cluster`` apart (:func:`spacing`), a peak's ``shoulder``
  (a bump on a stronger peak's flank) and, with ``twin_peak`` under 1, the later of two
  near-equal peaks left out.
* **Turns** (:func:`turn_test`). A person who turns shifts every azimuth histogram; a peak
  under which the novelty of the heading-free rows
  (:func:`tvmedit.engine.parse.heading.azimuth_spectrum`) stays below ``turn_ratio`` of it is a
  turn, not a boundary. Within ``novelty_window`` of such a turn, the heading-free novelty's
  own peaks over the threshold are the boundaries: a change just after a turn lies on the
  turn's slope, with no peak of its own. About an origin the person stands away from,
  turning about their own axis changes even the heading-free rows, so they are taken about
  each frame's own centre where the features hold it.
* **Ends of the take.** Within 0.75 ``min_cluster`` of either end a block is short and
  unreliable: only a peak of :data:`STRONG_EDGE` times the threshold is a boundary there.
"""
import numpy as np

from .atoms import block_means, novelty
from .partition import MAX_SEGMENT_S, energy_partition

__all__ = ["novelty_rows", "novelty_curve", "novelty_clusters", "local_maxima", "turn_test", "spacing", "pace",
           "whiten", "STRONG_EDGE", "PACE_SECONDS", "WHITEN_FLOOR"]

#: A novelty peak this many times ``novelty_threshold`` is a boundary even within 0.75
#: ``min_cluster`` of the sequence's ends, where weaker peaks are not trusted: a short first
#: or last exercise has only a short block to show it, and only a clear change is believed.
STRONG_EDGE = 2.0

#: The pace beside each novelty row is a bin's change over this many seconds, whatever the
#: rate the sequence is reduced to.
PACE_SECONDS = 0.1

#: :func:`whiten` adds this fraction of the kept components' mean variance to each one's.
WHITEN_FLOOR = 1.0

#: A change of the partition (``partition``) is read on the novelty's highest point within
#: this many seconds of it: the turn veto and ``partition_floor`` look there.
PEAK_REACH_S = 0.5


def pace(rows):
    """How fast each column changes: |row t+1 - row t-1| / 2 (one-sided at the ends).

    Parameters
    ----------
    rows : (T, D) array, T >= 2
        Successive rows (the block means of :func:`novelty_rows`).

    Returns
    -------
    (T, D) float64

    >>> pace(np.array([[0.0], [1.0], [3.0], [3.0]])).ravel().tolist()
    [1.0, 1.5, 1.0, 0.0]
    """
    r = np.asarray(rows, dtype=np.float64)
    d = np.empty_like(r)
    d[1:-1] = (r[2:] - r[:-2]) / 2.0
    d[0], d[-1] = r[1] - r[0], r[-1] - r[-2]
    return np.abs(d)


def novelty_rows(vectors, fps, p):
    """The rows the novelty compares: the sequence reduced to about ``p.analysis_fps`` (block
    means of ``step`` frames), each beside its :func:`pace` per :data:`PACE_SECONDS` weighted
    by ``p.novelty_pace`` (left out when that is 0), then whitened on ``p.novelty_components``
    principal axes (:func:`whiten`; not when that is 0).

    Returns
    -------
    rows : (ceil(T / step), C) float64
        C: min(novelty_components, D', rows - 1) whitened, else D' (D, or 2D with the pace).
    step : int
        Frames per block mean.
    """
    step = max(1, int(round(fps / p.analysis_fps)))
    v = block_means(vectors, step)
    if p.novelty_pace > 0 and len(v) > 1:
        # pace() is per row and rows are step / fps s apart: a 15 or 25 fps take reduced to
        # 7.5 or 12.5 rows a second weighs its pace as a 10 fps one does.
        v = np.hstack([v, (p.novelty_pace * PACE_SECONDS * fps / step) * pace(v)])
    if p.novelty_components > 0:
        v = whiten(v, p.novelty_components)
    return v, step


def whiten(rows, components, floor=WHITEN_FLOOR):
    """Rows on their ``components`` principal axes, each divided by its spread (plus a floor).

    Coordinates along the take's own principal directions of change, each scaled by
    1 / sqrt(variance + floor * mean variance of those kept): a direction in which little
    changes (the legs while the arms swing) counts as much as one in which much does, and
    the many directions of noise left out count not at all. At most rows - 1 axes are kept;
    a single row, or rows holding a NaN or infinity, come back as they are, and rows that do
    not change come back centred (zeros).
    """
    x = np.asarray(rows, dtype=np.float64)
    k = min(int(components), x.shape[1], len(x) - 1)
    if k < 1 or not np.isfinite(x).all():
        return x
    x = x - x.mean(axis=0)
    # Principal coordinates from the smaller of x x' and x' x.
    gram = len(x) <= x.shape[1]
    sq, vectors = _leading_eigen(x @ x.T if gram else x.T @ x, k)
    scores = vectors * np.sqrt(sq) if gram else x @ vectors
    var = sq / len(x)
    if not var.mean() > 0:
        return x
    return scores / np.sqrt(var + floor * var.mean())


def _leading_eigen(m, k, iterations=10, extra=6):
    """The ``k`` largest eigenvalues (>= 0) of a symmetric positive semi-definite ``m`` and
    their eigenvectors, by subspace iteration from a fixed start (the same answer every run).

    Ten products with ``m`` and thin QRs: a full symmetric eigensolver or SVD of a take's rows
    (LAPACK, threaded) is far slower where other work shares the cores, and a take's spectrum
    falls fast enough that a few iterations give its leading axes.

    >>> m = np.diag([5.0, 3.0, 1.0, 0.5])
    >>> values, vectors = _leading_eigen(m, 2)
    >>> values.round(6).tolist(), np.abs(vectors).round(6).tolist()
    ([5.0, 3.0], [[1.0, 0.0], [0.0, 1.0], [0.0, 0.0], [0.0, 0.0]])
    """
    q = np.random.default_rng(0).standard_normal((len(m), min(len(m), k + extra)))
    for _ in range(iterations):
        q, _ = np.linalg.qr(m @ q)
    values, small = np.linalg.eigh(q.T @ m @ q)
    order = np.argsort(values)[::-1][:k]
    return np.maximum(values[order], 0.0), q @ small[:, order]


def novelty_curve(vectors, fps, p):
    """The two-block novelty of :func:`novelty_rows`, and the step.

    Parameters
    ----------
    vectors : (T, D) array
    fps : float
    p : tvmedit.engine.parse.structure.StructureParams

    Returns
    -------
    n : (ceil(T / step),) float64
        :func:`tvmedit.engine.parse.atoms.novelty` of the rows, ``p.novelty_window`` s blocks.
    step : int
        Frames per block mean.
    """
    v, step = novelty_rows(vectors, fps, p)
    f = fps / step
    block = max(3, int(round(p.novelty_window * f)))
    # A block shorter than half the shortest cluster says too little, but never ask for more
    # than the block holds: novelty() would then skip every frame and find no boundary.
    return novelty(v, block, min_block=min(block, max(3, int(round(0.5 * p.min_cluster * f))))), step


def spacing(p, f):
    """Least distance between boundaries, in rows of the novelty (``f`` a second):
    ``min_cluster``, in whole rows. Rhythm splits and joined short clusters keep to it too."""
    return max(2, int(round(p.min_cluster * f)))


def _shoulder(n, t, claimed, reach, share):
    # A peak that rises less than ``share`` of its height above the lowest novelty between it
    # and a stronger peak already taken (within ``reach``) is that peak's shoulder.
    for q in claimed:
        if abs(t - q) <= reach:
            a, b = sorted((q, t))
            if n[t] - n[a:b + 1].min() < share * n[t]:
                return True
    return False


def local_maxima(n):
    """Where curve ``n`` is a local maximum (at least its neighbours; never its ends).

    >>> local_maxima(np.array([1.0, 2.0, 2.0, 0.0, 1.0])).tolist()
    [False, True, True, False, False]
    """
    peak = np.zeros(len(n), dtype=bool)
    peak[1:-1] = (n[1:-1] >= n[:-2]) & (n[1:-1] >= n[2:])
    return peak


def turn_test(n, turn_free, ratio, f):
    """Whether peak t of novelty ``n`` (sampled at ``f`` per second) is a turn: a predicate.

    A turn's peak has the heading-free novelty ``turn_free`` stay under ``ratio`` of it within
    0.5 s (see the module docstring); without ``turn_free`` nothing is a turn. The novelty's
    boundaries and the rhythm splits (:mod:`tvmedit.engine.parse.rhythm`) share it.

    >>> turned = turn_test(np.array([0.0, 1.0, 0.0]), np.array([0.0, 0.2, 0.0]), 0.4, 2)
    >>> turned(1), turn_test(np.ones(3), None, 0.4, 2)(1)
    (True, False)
    """
    if turn_free is None:
        return lambda t: False
    reach = max(1, int(round(0.5 * f)))
    return lambda t: bool(turn_free[max(0, t - reach): t + reach + 1].max() < ratio * n[t])


def _behind_turns(turn_free, turns, claimed, threshold, sep, reach, near_end):
    # A change of exercise within a turn's blocks can be no peak of n: the turn's far higher
    # novelty hides it on its slope. The heading-free novelty, which the turn hardly moves,
    # peaks there: its local maxima over the threshold, within ``reach`` of a turn and
    # ``sep`` from every peak already claimed, strongest first, are boundaries (see *Turns* in
    # the module docstring).
    is_peak = local_maxima(turn_free)
    out = []
    for u in np.argsort(-turn_free, kind="stable"):
        u = int(u)
        if turn_free[u] < threshold:
            break
        if (not is_peak[u] or near_end(u) or not any(abs(u - t) <= reach for t in turns)
                or any(abs(u - q) < sep for q in claimed)):
            continue
        out.append(u)
        claimed.append(u)
    return out


def novelty_clusters(vectors, fps, p, n, step, turn_free=None):
    """Clusters cut where the novelty says the take changes (the ``energy`` parser).

    The clusters of :func:`novelty_boundaries`, without the turns.
    """
    return novelty_boundaries(vectors, fps, p, n, step, turn_free)[0]


def novelty_boundaries(vectors, fps, p, n, step, turn_free=None):
    """Clusters cut where the novelty says the take changes (the ``energy`` parser), and the turns.

    Parameters
    ----------
    vectors : (T, D) array
    fps : float
    p : tvmedit.engine.parse.structure.StructureParams
        ``novelty_threshold``, ``min_cluster``, ``turn_ratio``, ``partition`` and
        ``partition_floor`` (with ``novelty_components`` and what :func:`novelty_rows` reads),
        and for the novelty's peaks ``twin_peak`` and ``shoulder``, are used.
    n, step
        From :func:`novelty_curve`.
    turn_free : array like ``n``, optional
        The novelty of the same rows compared whichever way the body faces
        (:func:`tvmedit.engine.parse.heading.azimuth_spectrum`); a peak of ``n`` under which it stays below
        ``p.turn_ratio`` of the peak within 0.5 s is a turn, not a boundary; the turn keeps
        its lower shoulders, and an earlier twin peak that is itself a turn, from becoming
        boundaries. Within ``p.novelty_window`` of a turn its own peaks over the threshold
        are boundaries (a change of exercise the turn hid).

    Returns
    -------
    clusters : list of (start, end)
        Inclusive frame ranges covering the sequence.
    turns : list of int
        Frames of the peaks vetoed as turns (boundaries near them are placed on heading-free
        rows: *Turns* in the module docstring).

    Examples
    --------
    A turn at frame 60 (novelty 0.3, heading-free novelty 0.05) hides a change 2.4 s later
    that only the heading-free novelty shows:

    >>> from tvmedit.engine.parse.structure import StructureParams
    >>> x = np.arange(200)
    >>> n = 0.3 * np.exp(-0.5 * ((x - 60) / 10.0) ** 2)
    >>> free = np.maximum(0.05 * np.exp(-0.5 * ((x - 60) / 2.0) ** 2), 0.15 * np.exp(-0.5 * ((x - 84) / 2.0) ** 2))
    >>> p = StructureParams(novelty_threshold=0.05, novelty_components=0)
    >>> novelty_boundaries(np.zeros((400, 1)), 20.0, p, n, 2, free)
    ([(0, 167), (168, 399)], [120])
    """
    T = len(vectors)
    f = fps / step
    sep = spacing(p, f)
    # Non-maximum suppression over local maxima only (a broad peak's shoulder is not a
    # second boundary): strongest first, none closer than ``sep``. With ``twin_peak`` under 1
    # (left out by default), an earlier local maximum within ``sep`` and at least
    # ``twin_peak`` as high is taken instead (a peak split in two).
    # Near the ends a block is short and unreliable; an end cluster may be a little shorter.
    # A peak at least STRONG_EDGE times the threshold is a boundary there all the same.
    edge = max(2, int(round(0.75 * sep)))
    near_end = lambda t: t < edge or len(n) - t < edge  # noqa: E731
    is_peak = local_maxima(n)
    turned = turn_test(n, turn_free, p.turn_ratio, f)
    if p.partition > 0 and p.novelty_components > 0:
        bounds, claimed, turns = _partition_boundaries(vectors, fps, p, n, f, sep, is_peak, near_end, turned)
    else:
        bounds, claimed, turns = _peak_boundaries(p, n, f, sep, edge, is_peak, near_end, turned)
    if turns:
        bounds += _behind_turns(turn_free, turns, claimed, p.novelty_threshold, sep, int(round(p.novelty_window * f)),
                                near_end)
    bounds.sort()
    starts = [0] + [min(T - 1, t * step) for t in bounds]
    starts = sorted(set(starts))
    return [(s, e - 1) for s, e in zip(starts, starts[1:] + [T])], [min(T - 1, t * step) for t in sorted(turns)]


def _partition_boundaries(vectors, fps, p, n, f, sep, is_peak, near_end, turned):
    # The changes of the kernel partition (tvmedit.engine.parse.partition) of the novelty's
    # rows, each read on the novelty's top within PEAK_REACH_S of it: no boundary where that
    # stays under ``partition_floor`` of the threshold, a turn where the veto says so. Near the
    # ends, where a segment may not be ``min_cluster`` long, a novelty peak of STRONG_EDGE
    # times the threshold, if no change is within ``min_cluster`` of it: taken after the
    # partition's changes, so that such a peak never crowds out a change the partition found.
    bounds, claimed, turns = [], [], []

    def take(t, at):
        # The novelty's top t is a turn (claimed, no boundary) or a boundary placed at ``at``;
        # both keep others ``sep`` away.
        claimed.append(t)
        if turned(t):
            turns.append(t)
            return
        bounds.append(at)
        if at != t:
            claimed.append(at)

    rows, _ = novelty_rows(vectors, fps, p)
    reach = max(1, int(round(PEAK_REACH_S * f)))
    for c in energy_partition(rows, p.partition, sep, int(round(MAX_SEGMENT_S * f))):
        lo, hi = max(0, c - reach), min(len(n), c + reach + 1)
        t = lo + int(np.argmax(n[lo:hi]))
        if n[t] >= p.partition_floor * p.novelty_threshold:
            take(t, c)
    for t in np.argsort(-n, kind="stable"):
        t = int(t)
        if n[t] < STRONG_EDGE * p.novelty_threshold:
            break
        if is_peak[t] and near_end(t) and not any(abs(t - q) < sep for q in claimed):
            take(t, t)
    return bounds, claimed, turns


def _peak_boundaries(p, n, f, sep, edge, is_peak, near_end, turned):
    # With ``partition`` 0: the novelty's local maxima over the threshold,
    # strongest first (see the module docstring).
    bounds, claimed, turns = [], [], []
    for t in np.argsort(-n, kind="stable"):
        t = int(t)
        if n[t] < p.novelty_threshold:
            break
        if not is_peak[t] or (near_end(t) and n[t] < STRONG_EDGE * p.novelty_threshold):
            continue
        if any(abs(t - q) < sep for q in claimed):
            continue
        if p.shoulder > 0 and _shoulder(n, t, claimed, 2 * sep, p.shoulder):
            continue
        if turned(t):
            # A turn's lower shoulders are the same turn: the vetoed peak keeps them away.
            claimed.append(t)
            turns.append(t)
            continue
        early = [u for u in range(max(edge, t - sep + 1), t)
                 if is_peak[u] and n[u] >= p.twin_peak * n[t] and not turned(u)
                 and all(abs(u - q) >= sep for q in claimed)] if p.twin_peak < 1 else []
        bounds.append(early[0] if early else t)
        # Both the peak and the boundary chosen for it keep others ``sep`` away.
        claimed += [t, bounds[-1]]
    return bounds, claimed, turns
