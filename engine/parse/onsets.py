"""Where a change of exercise starts: boundaries placed between whole periods, then moved to the onset.

Two rules of the ``energy`` parser (:mod:`tvmedit.engine.parse.structure`) place each boundary
the novelty gave:

* **Whole periods on each side** (:func:`settle`). The two-block novelty
  (:func:`tvmedit.engine.parse.atoms.novelty`) compares blocks of ``novelty_window`` seconds
  whatever the tempo, so a block holds a period and a part of one, and its peak moves with
  the phase at which the blocks cut the cycles. Once the clusters and their periods are
  known, each boundary moves, by up to ``refine_reach`` seconds and never nearer a neighbour
  than ``min_cluster``, to where the energy distance between the frames before and after it
  is largest, each block a whole number of its own cluster's periods (at least two; the
  window itself where a cluster shows no period).
* **Both views** (``settle_free``). The parser's rows are turned back by a heading tracked
  in whole bins, which can be a bin or a few off just after a change of exercise; such an
  offset spreads the energy distance broad and its top wanders. The heading-free rows
  (:func:`tvmedit.engine.parse.heading.azimuth_spectrum`) cannot be put off by a heading but
  cannot tell a pose from its mirror image, so neither is read alone: each view's distances
  over the reach (negative ones as none) are scaled to their largest, and the boundary goes
  where the sum is largest, which lies at the sharper of the two tops.
* **The onset of a slow transition** (:func:`onset`). The novelty peaks where the pose
  distribution changes most, in the middle of a slow transition, a second or two after the
  old exercise stopped. Each boundary moves back, by up to ``onset_reach`` seconds, to where
  the motion left the old exercise's poses: the first frame from which every later frame up
  to the boundary is farther from the old cluster's frames than they are from each other.
  Where the frames it would leave behind are only the old poses turned
  (:func:`turned_away`), the onset is read on the heading-free rows too and the later one
  taken, so a turn shortly before a change does not pull the boundary back to it.
"""

import numpy as np

from .atoms import block_means
from ..features import distance_matrix

__all__ = ["onset", "settle", "energy_distance", "turned_away", "TURN_DEGREES", "TURN_EXPLAINS"]

#: Least turn, in degrees, for which :func:`turned_away` holds: two azimuth bins at the
#: features' default 5 degrees: a slow turn counts too, not only one faster than the heading
#: tracker follows (:data:`tvmedit.engine.parse.heading.MOST`).
TURN_DEGREES = 10.0

#: Greatest ratio of the turned frames' distance to the old poses, turned back, to their
#: distance unturned, for :func:`turned_away`: a true turn, undone, brings the frames well
#: nearer the old poses, while a change of exercise that only looks turned barely does.
TURN_EXPLAINS = 0.8


def energy_distance(D, split):
    """Energy distance between rows [0, split) and [split, n) of a frame-distance matrix.

    2 mean d(X, Y) - mean d(X, X') - mean d(Y, Y') with the within-block means over distinct
    pairs (the statistic of :func:`tvmedit.engine.parse.atoms.novelty`, for blocks of any two lengths).

    Parameters
    ----------
    D : (n, n) array
        Frame distances (:func:`tvmedit.engine.features.distance_matrix`) of the two blocks in order.
    split : int
        Rows in the first block; each block needs two rows at least (else -inf).

    Examples
    --------
    >>> v = np.r_[np.zeros((3, 1)), np.ones((2, 1))]
    >>> float(energy_distance(distance_matrix(v), 3))
    2.0
    """
    n = len(D)
    if split < 2 or n - split < 2:
        return -np.inf
    x, y = D[:split, :split], D[split:, split:]
    return (2.0 * D[:split, split:].mean() - x.sum() / (split * (split - 1))
            - y.sum() / ((n - split) * (n - split - 1)))


def settle(vectors, clusters, periods, fps, window=4.0, reach=1.5, min_gap=2.0, other=None, use_other=(),
           other_weight=1.0):
    """Cluster starts moved to where whole periods before and after differ most.

    Where ``other`` rows are given, a boundary not in ``use_other`` reads both views: each
    view's energy distances over the boundary's reach (negative ones taken as none) are
    scaled to their largest, and the boundary goes where their sum is largest, ``other``'s
    weighed by ``other_weight``. Where one view tops sharply and the other broadly, that is
    at the sharp top; a view in which no place in reach differs counts for nothing. A
    boundary in ``use_other`` reads ``other`` alone.

    Parameters
    ----------
    vectors : (T, D) array
    clusters : list of (start, end), inclusive, covering the sequence in order
    periods : list of int or None, each cluster's period in frames (None: it shows none)
    fps : float
    window : float, seconds each block spans at least, rounded to whole periods (two at least)
    reach : float, seconds a boundary may move either way
    min_gap : float, least seconds between a moved boundary and its neighbours (or the ends)
    other : (T, D') array, optional: the heading-free rows of the same frames, read alone for
        the starts of ``clusters[i]``, i in ``use_other``, beside ``vectors`` for the others
    use_other : collection of int
    other_weight : float, weight of ``other``'s scaled distances (0: ``vectors`` alone)

    Returns
    -------
    list of int: the clusters' first frames (0 first), in order.

    Examples
    --------
    >>> t = np.arange(120)
    >>> v = np.where((t < 64)[:, None], [[0.0, 1.0]], [[1.0, 0.0]]) * (1 + 0.1 * np.sin(t))[:, None]
    >>> settle(v, [(0, 59), (60, 119)], [None, None], 10)
    [0, 64]

    A view in which the change looks slow (a stand-in for a heading tracked a bin or a few
    off: a ramp over 2.4 s, topping at frame 71) read with one in which it is sharp: either
    way round, the boundary goes to the sharp top.

    >>> ramp = np.clip((t - 58) / 24.0, 0, 1)[:, None]
    >>> slow = (1 - ramp) * [[0.0, 1.0]] + ramp * [[1.0, 0.0]]
    >>> settle(slow, [(0, 59), (60, 119)], [None, None], 10)
    [0, 71]
    >>> settle(slow, [(0, 59), (60, 119)], [None, None], 10, other=v)
    [0, 64]
    >>> settle(v, [(0, 59), (60, 119)], [None, None], 10, other=slow)
    [0, 64]
    """
    v = np.asarray(vectors, dtype=np.float64)
    step, rows, alt = _views(v, other, use_other, other_weight, fps)
    f, n = fps / step, len(rows)
    block = lambda P: _whole_periods(P, window, f, step)  # noqa: E731

    old = [cs for cs, _ in clusters] + [len(v)]
    out = [0]
    gap, k = max(1, int(round(min_gap * f))), int(round(reach * f))
    for i in range(1, len(clusters)):
        b, prev, nxt = old[i] // step, out[-1] // step, old[i + 1] // step
        lo, hi = _reach(b, prev, nxt, gap, k)
        before, after = block(periods[i - 1]), block(periods[i])
        a0, a1 = max(0, lo - before), min(n, hi + after)
        if hi < lo:
            out.append(old[i])
            continue
        span = (a0, a1, lo, hi, before, after)
        score = _settle_score(rows, alt if i in use_other else None, alt, other_weight, span)
        score = np.where(np.isnan(score), -np.inf, score)
        if not np.isfinite(score).any():
            out.append(old[i])
            continue
        at = lo + int(np.argmax(score))
        out.append(old[i] if at == b else min(len(v) - 1, at * step))
    return out


def _views(v, other, use_other, other_weight, fps):
    """The step to about 10 fps, and the parser's rows and ``other``'s (None where unread) at it."""
    step = max(1, int(round(fps / 10.0)))      # about 10 fps, as the novelty is computed
    rows = block_means(v, step)
    alt = (block_means(np.asarray(other, dtype=np.float64), step)
           if other is not None and (use_other or other_weight > 0) else None)
    return step, rows, alt


def _reach(b, prev, nxt, gap, k):
    """Rows lo..hi a boundary at row ``b`` may move to: within ``k`` of it, and never nearer
    the boundaries ``prev`` and ``nxt`` than ``gap``, nor nearer than it already is."""
    lo = max(prev + max(1, min(gap, b - prev)), b - k)
    hi = min(nxt - max(1, min(gap, nxt - b)), b + k)
    return lo, hi


def _period_profile(view, a0, a1, lo, hi, before, after):
    """Energy distance of whole periods before and after each place t in lo..hi."""
    D = distance_matrix(view[a0:a1])
    out = np.empty(hi - lo + 1)
    for t in range(lo, hi + 1):
        i0, i1 = max(a0, t - before) - a0, min(a1, t + after) - a0
        out[t - lo] = energy_distance(D[i0:i1, i0:i1], t - a0 - i0)
    return out


def _whole_periods(P, window, f, step):
    """Rows a block spans: ``window`` seconds rounded to whole periods P (frames), two at least."""
    if P is None:
        return max(2, int(round(window * f)))
    P = P / step
    return max(2, int(round(P * max(2, round(window * f / P)))))


def _settle_score(rows, only, alt, other_weight, span):
    """The profile a boundary is placed on: ``only``'s alone where given, else ``rows``',
    beside ``alt``'s with ``other_weight`` (both views)."""
    if only is not None:
        return _period_profile(only, *span)
    score = _period_profile(rows, *span)
    if alt is not None and other_weight > 0:
        # Both views (above): each scaled to its largest in reach, then summed; the
        # places where a view differs less than not at all count as no difference.
        views = [(1.0, score), (other_weight, _period_profile(alt, *span))]
        tops = [np.nanmax(s, initial=0.0) for _, s in views]
        if any(top > 0 for top in tops):
            score = sum(w * np.clip(s, 0, None) / top for (w, s), top in zip(views, tops) if top > 0)
    return score


def onset(vectors, start, peak, fps, reach=3.0, reference=10.0):
    """The frame where the motion leaves cluster [start, peak) on its way to ``peak``.

    Parameters
    ----------
    vectors : (T, D) array
        Feature vectors (frame distance: Euclidean distance of rows, eq. (2)).
    start : int
        First frame of the cluster before the boundary.
    peak : int
        The boundary found at the novelty peak.
    fps : float
    reach : float
        Seconds before ``peak`` within which the onset is looked for.
    reference : float
        Seconds of the old cluster, ending ``reach`` before the peak, whose poses stand for it.

    Returns
    -------
    int, in [peak - reach, peak]; ``peak`` when the frames before it still look like the old
    cluster, or when the old cluster is too short to tell.

    Examples
    --------
    >>> t = np.arange(80)
    >>> cyc = np.stack([np.sin(2 * np.pi * t / 8), np.cos(2 * np.pi * t / 8)], axis=1)
    >>> v = np.where((t < 50)[:, None], cyc, 3.0 + (t[:, None] - 50) * 0.0)
    >>> v[40:50] = cyc[40:50] + np.linspace(0, 3, 10)[:, None]   # a slow change from frame 40
    >>> onset(v, 0, 50, 10)
    41
    """
    v = np.asarray(vectors, dtype=np.float64)
    k = int(round(reach * fps))
    lo = max(start, peak - k)
    # The reference poses at about 10 fps are enough, and keep this linear in the frame rate.
    step = max(1, int(round(fps / 10.0)))
    ref = v[max(start, lo - int(round(reference * fps))): lo][::-1][::step][::-1]
    if len(ref) < max(4, int(round(1.0 * fps / step))):
        return int(peak)
    # How far the old cluster's poses lie from their nearest others (half a second apart at
    # least, so a pose is not matched with itself a frame later).
    D = distance_matrix(ref)
    gap = max(1, int(round(0.5 * fps / step)))
    idx = np.arange(len(ref))
    D[np.abs(idx[:, None] - idx[None, :]) < gap] = np.inf
    spread = np.nanpercentile(np.where(np.isfinite(D.min(axis=1)), D.min(axis=1), np.nan), 90)
    if not np.isfinite(spread):
        return int(peak)
    away = distance_matrix(v[lo: peak + 1], ref).min(axis=1) > spread
    t = len(away) - 1
    while t > 0 and away[t - 1]:
        t -= 1
    return int(lo + t) if away[-1] else int(peak)


def turned_away(rows, theta, start, left, peak, fps, reference=10.0):
    """Whether frames [left, peak] are the poses of cluster [start, left) turned about the vertical.

    Each of those frames (at about 10 fps) is matched with the ``reference`` seconds of the
    old cluster before ``left`` turned by every whole number of azimuth bins; the turn that
    brings it nearest is its angle. See the module docstring, *The onset of a slow transition*.

    Parameters
    ----------
    rows : (T, D) array
        Feature rows, their azimuth histograms smoothed.
    theta : slice
        The azimuth histogram's columns.
    start, left, peak : int
        The old cluster's first frame, the frame :func:`onset` would take, the boundary.
    fps : float
    reference : float
        Seconds of the old cluster whose poses stand for it.

    Returns
    -------
    bool

    Examples
    --------
    >>> j, t = np.arange(72), np.arange(120)
    >>> pose = lambda c: np.exp(-0.5 * (((j - c + 36) % 72 - 36) / 3.0) ** 2)
    >>> old = np.array([pose(10 + 4 * np.sin(2 * np.pi * k / 12)) for k in t])
    >>> angle = np.clip(t - 100, 0, 10) * 2                  # frame 100 on: 1 s turn, 20 bins
    >>> rows = np.array([np.roll(r, int(a)) for r, a in zip(old, angle)])
    >>> turned_away(rows, slice(0, 72), 0, 100, 119, 10)
    True
    >>> new = rows.copy(); new[100:] = [pose(50)] * 20          # a new pose from frame 100
    >>> turned_away(new, slice(0, 72), 0, 100, 119, 10)
    False
    >>> half = np.clip(t - 100, 0, 10) * 3.6                  # about: 180 degrees, either way
    >>> [turned_away(np.array([np.roll(r, int(s * a)) for r, a in zip(old, half)]), slice(0, 72), 0, 100, 119, 10)
    ...  for s in (1, -1)]
    [True, True]
    >>> flip = old.copy(); flip[100:] = [np.roll(old[k], 36) for k in range(100, 120)]
    >>> turned_away(flip, slice(0, 72), 0, 100, 119, 10)    # 180 degrees at once: no turn seen
    False
    """
    r = np.asarray(rows, dtype=np.float64)
    step = max(1, int(round(fps / 10.0)))
    ref = r[max(start, left - int(round(reference * fps))): left][::-1][::step][::-1]
    stretch = r[left: peak + 1: step]
    if len(ref) < 2 or len(stretch) < 3:
        return False
    n = stretch[:, theta].shape[1]
    dist = np.empty((n, len(stretch)))
    turned = stretch.copy()
    for s in range(n):
        turned[:, theta] = np.roll(stretch[:, theta], s, axis=1)
        dist[s] = distance_matrix(turned, ref).min(axis=1)
    # Angles in degrees, -180 to 180, of the turn that brings each frame nearest; the last
    # third's about its circular mean (a turn of about 180 degrees reads +175 and -175).
    best = np.argmin(dist, axis=0)
    angle = ((best + n // 2) % n - n // 2) * 360.0 / n
    last = slice(len(stretch) - max(1, len(stretch) // 3), None)
    mean = np.degrees(np.angle(np.exp(1j * np.radians(angle[last])).mean()))
    end = float((mean + np.median((angle[last] - mean + 180) % 360 - 180) + 180) % 360 - 180)
    tol = max(15.0, abs(end) / 4)
    # Near 180 degrees the turn may have gone either way round: half of either will do.
    ends = [end] + ([end - 360.0 * np.sign(end)] if 360 - 2 * abs(end) <= 2 * tol else [])
    halfway = any((np.abs((angle - e / 2 + 180) % 360 - 180) <= tol).any() for e in ends)
    explains = np.median(dist.min(axis=0)[last]) <= TURN_EXPLAINS * np.median(dist[0][last])
    return bool(abs(end) >= TURN_DEGREES and halfway and explains)
