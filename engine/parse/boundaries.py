"""Cluster boundaries from the novelty: step 1 of the ``energy`` parser (:mod:`tvmedit.engine.parse.structure`).

The novelty of a frame is the energy distance between the ``novelty_window`` seconds of
frames before it and after it (:func:`tvmedit.engine.parse.atoms.novelty`), on the sequence reduced to
about 10 fps. Until step 36 of ``docs/parsing.md`` its local maxima above
``novelty_threshold``, strongest first and at least ``min_cluster`` apart, were the
boundaries (``partition`` 0 still does that; the bullets below were measured so). Since then
the boundaries are the changes of the partition of the same rows that the take as a whole
supports (*Changes of the whole take*, the last bullet); the novelty still reads each of them
(the turn veto, the floor, the confidence) and finds the boundaries near the ends and behind
turns.

* **Pose and pace.** Each row compared (:func:`novelty_rows`, about 0.1 s of frames) is
  their mean histograms and, weighted by ``novelty_pace``, how fast each bin changes: its
  change over :data:`PACE_SECONDS` (0.1 s) whatever the frame rate (:func:`pace`). The
  histograms alone describe which poses a block holds, not how fast it moves through them:
  hops then elbow-to-knee, or grabbing high then hops (HDM05, the development suite), hold
  alike poses and their
  novelty peaked at 0.02-0.05, under the threshold, inside exercises' own ripple. With the
  pace beside them (weight 1: a bin's change per 0.1 s counts as much as the bin) the
  suite's pooled precision / recall / texton accuracy went 0.95 / 0.92 / 0.91 -> 0.97 /
  0.95 / 0.91 (hdm05 0.89 / 0.82 / 0.74 -> 0.92 / 0.88 / 0.75, cmu 0.98 / 0.95 / 1.00 ->
  1.00 / 0.98 / 1.00, synthetic groups unchanged at 1.00); weights 0.75-1.5 score alike,
  0.5 as without, 2 loses precision. The speed alone (one column, the norm of the change)
  scored a little less (0.96 / 0.95 / 0.91), and a time-delay embedding of the poses
  (frames t - k, t, t + k side by side) separated true from false peaks no better than the
  poses alone. (Figures on the rows as they were, before whitening.) Since the rows are
  whitened (below) the weight no longer scales a distance: it decides how many of the kept
  principal axes describe pace. At weight 1 pace made a tenth of them (4-18 % on the suite's
  takes), and HDM05 changes between alike poses at another tempo still peaked under the
  threshold; the weight is 2 since step 29 of ``docs/parsing.md`` (a third of the axes,
  14-41 %): three of the four folds of the cross-validation choose 2 over 1 and 3 (the
  fourth scores its training groups alike with 1 and 2). On the 87 fresh takes (17
  batches) five boundaries more are found and three false ones fewer; on the 14 batches not
  looked at to choose it, one more and two fewer, all on the batch made to check it: on the
  13 older ones it trades four changes for four (two HDM05 changes and two of CMU takes that
  turn found; one HDM05 change and three of takes that turn lost, placed 1.1-1.5 s off, as is
  one change of the turning take of ``tests/test_report.py``).
* **Rows whitened** (:func:`whiten`, ``novelty_components``). On the rows as they are, the
  frame distance is ruled by the few directions in which the body changes most (arms swung
  wide, the trunk's sway) and blurred by the hundreds of bins that only carry noise; two
  exercises that differ along a direction of little variance (elbow to knee then kicks, hops
  then elbow to knee, reaching up then squats: HDM05) met peaks of 0.02-0.045, inside other
  exercises' ripple. The rows are taken on the take's 10 principal axes of change, each
  divided by the square root of its variance plus the kept axes' mean variance: weak
  directions count about as much as strong ones, the noise left out not at all, and the
  threshold (0.9) is in units of the take's own spread. Peaks of the suite's novelty (greedy,
  2 s apart) told true from false at the best threshold of each: F1 0.818 -> 0.873 (misses 19
  -> 9 of 129, false peaks 30 -> 26; every group gained). With the parser's later steps, the
  suite's pooled precision / recall / texton accuracy 0.96 / 0.91 / 0.91 -> 0.98 / 0.95 /
  0.90 (cmu 1.00 / 0.98 / 1.00 -> 1.00 / 1.00 / 1.00, synth-drift precision 0.94 -> 1.00,
  hdm05 0.91 / 0.81 / 0.76 -> 0.94 / 0.88 / 0.76); leave one group out, with whitened or
  not among the settings (every fold chose it), 0.907 / 0.907 / 0.867 -> 0.953 / 0.953 /
  0.886; three fresh HDM05 takes, never looked at before, 0.75 / 0.69 / 0.67 -> 0.77 / 0.77 /
  0.62. 8-12 axes and floors of 0.5-2 times the mean score alike; the projection alone,
  undivided, gains half as much (F1 0.842); 15 axes or more let the noise back in (0.857;
  20 axes with a floor of 0.1: 0.800). Rows of a few columns (not histograms) keep every
  axis and lose their relative scale: compare them as they are (``novelty_components=0``).
* **Twin peaks** (left out since step 30 of docs/parsing.md: ``twin_peak`` 1). When a new
  motion begins with poses of the old one (standing before the first squat) the peak splits
  in two and the later top is the higher; an earlier local maximum within ``min_cluster`` and
  at least ``twin_peak`` as high was taken instead (0.9, from the parser's first version).
  The steps that came later and place each boundary (between whole periods, then at the
  onset of the change: tvmedit.engine.parse.onsets) search about the boundary they are given, and from the
  earlier top they took changes 1-2 s off, mostly early: a split peak at a change into slow toe touches
  (CMU 13_29 turning), two close peaks where a turn and a change meet. Left out, the fresh
  batches find six more changes and place six fewer boundaries falsely, none lost (the 17
  older batches 312 -> 316 of 349 changes; ``review-3``, made for it, 0.87 / 0.84 / 0.74 ->
  0.94 / 0.91 / 0.77); on the development suite one false HDM05 boundary goes and one HDM05
  cluster's texton length goes wrong, and held out is the same either way.
* **Shoulders.** A strong change's novelty may fall away slowly, and a bump on its flank
  ``min_cluster`` or more after the peak (the suite's synthetic actor pausing at random
  between knee raises, 2 s after the change into them) passed as a second boundary. A peak
  within twice ``min_cluster`` of a stronger one already taken that rises less than
  ``shoulder`` (0.2) of its height above the lowest novelty between them is that peak's
  shoulder. On the development suite only that false boundary went (pooled 0.974 / 0.936 /
  0.903 -> 0.980 / 0.936 / 0.907, body axes); 0.1 and 0.2 score alike, 0.3 loses an HDM05
  boundary's precision, 0.5 more.
* **Turns.** A person who turns while exercising shifts every azimuth histogram around
  the circle, and the blocks before and after differ although the motion does not. A peak
  is no boundary where the novelty of the same rows compared whichever way the body faces
  (:func:`tvmedit.engine.parse.heading.azimuth_spectrum`) stays under ``turn_ratio`` (0.4) of it within
  0.5 s. Found on the development suite's synthetic actor turning as it exercises (a slow
  random sway of +/- 90 degrees: two false boundaries inside its side bends) and in an
  HDM05 take's block of kicks (a false boundary where only the azimuth histograms changed:
  heading-free novelty 0.32 of the peak, on rows not yet whitened); no true boundary of the
  suite is lost. Each curve is whitened on its own rows' axes (so the heading-free one may
  now exceed the other): at true boundaries the ratio is 0.67 or more on the suite's real
  takes, at its false peaks from turning 0-0.23. A vetoed peak keeps the lower peaks within
  ``min_cluster`` of it (its shoulders) from becoming boundaries, and is never taken as
  another peak's earlier twin. Heading-free novelty alone
  lost CMU's twist boundaries (a twist differs from its neighbours mostly in which way the
  torso faces), so it only vetoes. Pooled precision 0.95 -> 0.97 on the suite with its
  turning takes.
* **Boundaries behind a turn** (step 22 of ``docs/parsing.md``). A person who turns to face
  another way a few seconds before they change exercise (the suite's synthetic actor
  turning by 45-120 degrees over 1 s every 5-10 s) makes a novelty peak far higher than
  the change's: the change lies on the turn's falling slope and is no local maximum, and
  vetoing the turn lost both. The heading-free novelty, which the turn hardly raises,
  peaks at the change (1.44 against the threshold 0.9, 2.4 s after the turn's peak).
  So, within ``novelty_window`` of a vetoed turn, the heading-free novelty's own local
  maxima over the threshold, ``min_cluster`` from every peak already taken or vetoed, are
  boundaries (:func:`_behind_turns`); and boundaries within ``novelty_window`` of a vetoed
  turn (:func:`novelty_boundaries`) are moved by steps 4 and 5 (:mod:`tvmedit.engine.parse.onsets`) on the
  heading-free rows, where the turn is no change of pose (on the rows as read, both moved
  the boundary back onto the turn). Heading-free rows everywhere lost a boundary of the
  wandering synthetic take and a CMU texton, so only near turns. On the development suite
  the step finds one boundary more (synth-drift 0.95 / 0.91 -> 0.96 / 0.96), and changes
  nothing in any other group; on three fresh synthetic takes with such turns, made before
  the step was tried on them (``benchmarks/fresh.py --batch step22``), 0.60 / 0.67 -> 0.80 /
  0.89 (two right boundaries more, two false ones fewer). Still wrong: a change of exercise
  2 s *before* a turn, where the novelty peak is no turn (the heading-free novelty stays
  over ``turn_ratio`` of it) and lies between the two, more than 1 s late.
* **Turns about the body's own axis** (step 23 of ``docs/parsing.md``). The heading-free
  novelty is blind to turns about the features' origin only. A person who stays near the
  first frame's centre keeps the origin there, and a body turning about its own axis a
  little off it changes even the heading-free rows (0.5-0.7 of the turn's novelty): turns
  of 90-180 degrees were not vetoed. So where the origin stays put the builder also keeps
  each frame's histograms about its own centre (:attr:`tvmedit.engine.features.Features.centred`,
  from 4,000-8,000 vertices of a larger frame: :data:`tvmedit.engine.features.CENTRED_VERTICES`),
  and the heading-free rows are taken from them (:func:`tvmedit.engine.parse.structure.parse`,
  ``centred``). The suite's figures do not move (no take of it turns so on its spot); five
  fresh takes made for the step (``benchmarks/fresh.py --batch step23``: the synthetic
  actor and CMU 13_29 and 13_30 turning by 60-180 degrees on their spot) 0.67 / 0.78 / 1.00
  -> 0.83 / 0.83 / 1.00; six more made after it, chosen for changes of exercise 1-2.5 s
  after a turn (``--batch after-turns``), 0.62 / 0.80 / 0.84 -> 0.76 / 0.76 / 0.77: half
  the false boundaries, one right one fewer, and one texton length more wrong (blocks of
  toe touches with rests, no longer cut at turns into pieces of one texton, read at half
  their period, as they are with no turn in them). Still wrong: changes of exercise 1-2.5 s
  after a turn (placed back on the turn, or kept away by a vetoed one). People who stray
  (every HDM05 take of the suite but one) have their origin followed
  already, and so no centred rows.
* **Ends of the take.** Within 0.75 ``min_cluster`` of either end a block is short and its
  novelty unreliable, so a peak there is taken only when it is at least :data:`STRONG_EDGE`
  times the threshold. Before that rule no boundary could lie there at all, and a first
  exercise of 1.3 s (CMU 13_30 played at 1.4x, the development suite) was lost; its peak is
  twice the threshold. On the suite (``benchmarks/accuracy.py``) pooled recall 0.95 -> 0.96
  in tvmedit's axes and 0.93 -> 0.94 in the body's, nothing else changed.
* **Changes of the whole take** (step 36 of ``docs/parsing.md``, ``partition``). A peak of
  the novelty says that 4 s differ from the 4 s after them; two exercises of alike poses
  (HDM05 kicks beside elbow to knee, throwing beside jogging) differ little within 4 s, and
  where one exercise (lying on the floor) holds much of the take's spread the others' changes
  peaked under the threshold too. The boundaries are now the changes of the partition of the
  whitened rows of least within-segment energy scatter plus ``partition`` (20) per change
  (:func:`tvmedit.engine.parse.partition.energy_partition`): the novelty's own statistic taken over whole
  segments, each at least ``min_cluster`` long. A change is read on the novelty's highest
  point within 0.5 s (:data:`PEAK_REACH_S`): no boundary where that stays under
  ``partition_floor`` (0.7) of the threshold (a slow exercise's long cycles cut into 2 s
  pieces: CMU 13_29 played at 0.7x), and the turn veto reads it as it reads a peak. The
  boundary stays at the change, not the peak. Near the ends, where a segment cannot be
  ``min_cluster`` long, a peak of :data:`STRONG_EDGE` times the threshold is a boundary as
  before (CMU 13_30 played at 1.4x) where no change of the partition lies within
  ``min_cluster`` of it. The partition cuts no nearer an end than that: a first or last
  exercise under 2 s long is cut at 2 s, up to 1 s off, and only steps 4 and 5 can move it
  to where it is (taking the peaks first cost the suite a change instead); behind a vetoed
  turn the heading-free novelty's peaks are, as before; shoulders and twin peaks have no meaning for a partition. Raw (no later
  step), over the suite and the 26 fresh batches (772 changes), the partition finds changes
  within 1 s at F1 0.862 (at penalty 24; 20, the default, was chosen with the later steps)
  where the peaks reach 0.809 at their best threshold. With the later
  steps (and ``onset_reach`` 1 s, since the changes already lie where the poses change) the
  fresh batches find 547 of 580 changes where they found 525, and place 31 boundaries falsely
  rather than 33; the suite 0.98 / 0.98 / 0.93 -> 0.99 / 0.98 / 0.94 (with step 5b of
  :mod:`tvmedit.engine.parse.structure`, :func:`tvmedit.engine.parse.joins.join_short`).
"""

import numpy as np

from .atoms import block_means, novelty
from .partition import MAX_SEGMENT_S, energy_partition

__all__ = ["novelty_rows", "novelty_curve", "novelty_clusters", "local_maxima", "turn_test", "spacing", "pace",
           "whiten", "STRONG_EDGE", "PACE_SECONDS", "WHITEN_FLOOR"]

#: A novelty peak this many times ``novelty_threshold`` is a boundary even within 0.75
#: ``min_cluster`` of the sequence's ends, where weaker peaks are not trusted. (On whitened rows
#: the 1.3 s first exercise of CMU 13_30 played 1.4x peaks at 2.02 times: a thin margin.)
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
    (LAPACK, threaded) took seconds instead of milliseconds on a machine whose other core was
    busy. On the development suite's rows the top 10 eigenvalues agree with the full
    solver's to 1e-4 after 8 iterations.

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
    """Least distance between step 1's boundaries, in rows of the novelty (``f`` a second):
    ``min_cluster``, in whole rows. Steps 1b and 5b keep to it too."""
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
    0.5 s (see the module docstring); without ``turn_free`` nothing is a turn. Steps 1 and 1b
    (:mod:`tvmedit.engine.parse.rhythm`) of the parser share it.

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
    # ``sep`` from every peak already claimed, strongest first, are boundaries (see *Boundaries
    # behind a turn* above).
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
    """Clusters cut at the novelty curve's peaks: step 1 of the ``energy`` parser.

    The clusters of :func:`novelty_boundaries`, without the turns.
    """
    return novelty_boundaries(vectors, fps, p, n, step, turn_free)[0]


def novelty_boundaries(vectors, fps, p, n, step, turn_free=None):
    """Clusters cut at the novelty curve's peaks (step 1 of the ``energy`` parser), and the turns.

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
        rows: *Boundaries behind a turn* above).

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
    # (left out by default since step 30), an earlier local maximum within ``sep`` and at
    # least ``twin_peak`` as high is taken instead (a peak split in two).
    # Near the ends a block is short and unreliable; an end cluster may be a little shorter.
    # A peak at least STRONG_EDGE times the threshold is a boundary there all the same: a
    # first exercise of 1.3 s (CMU 13_30 played at 1.4x) peaks at twice the threshold.
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
    # Step 1 since step 36 of docs/parsing.md: the changes of the kernel partition
    # (tvmedit.engine.parse.partition) of the novelty's rows, each read on the novelty's top within
    # PEAK_REACH_S of it: no boundary where that stays under ``partition_floor`` of the
    # threshold, a turn where the veto says so. Near the ends, where a segment may not be
    # ``min_cluster`` long, a novelty peak of STRONG_EDGE times the threshold, as before, if
    # no change is within ``min_cluster`` of it. (Taken first, such peaks cost the suite
    # CMU 13_30 turning's first change, 1.8 s in.)
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
    # Step 1 until step 36 (``partition`` 0): the novelty's local maxima over the threshold,
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
