"""Clusters that are no exercise of their own: transitions joined to an exercise, weak splits undone.

Steps 3, 5b and 6 of the ``energy`` parser (:mod:`tvmedit.engine.parse.structure`), on the clusters step 1
gives:

* **Transitions join the exercise they lead into** (:func:`absorb_transitions`). Standing
  still or a slow change of pose between two exercises is a stretch whose pose distribution
  differs from both neighbours, so novelty peaks on both of its sides and it became a cluster
  of its own (precision 0.50 on the development suite's take with 2 s of standing still). A
  cluster of at most ``max_transition`` seconds that shows no period, or changes pose at
  under :data:`STILL_RATIO` of the pace of its neighbour (standing still can show a period of
  noise), joins the next cluster when that one repeats or is too long to be a transition
  itself, else the previous one where that one repeats (at the end of the take, or where
  the next cluster is itself short and shows no period).
* **A transition into one-off movements joins them** (step 27 of ``docs/parsing.md``). An
  exercise of one-off movements (picking things up, reaching up, lying down and getting up:
  each repetition goes elsewhere or lasts another time) shows no period, and a transition
  into it joined the exercise *before* it: the synthetic actor twisting, then 2 s of changing
  pose with 0.5 s of standing still, then picking things up, had its boundary 2.7 s late, at
  the first pick-up (a fresh batch, ``benchmarks/fresh.py --batch few-reps``). A neighbour
  longer than ``max_transition`` is an exercise whether or not it repeats, so the transition
  now joins the next cluster when that one repeats or is that long. The previous cluster
  is joined, as before, only where it repeats: a short piece at the end of the take, after a
  long stretch that shows no period, is no transition into it, and may be a motion of its
  own (the real capture ``shared/data/scvv-card``, 6.4 s, has its one change 5 s in, at the
  novelty peak, with the last 1.4 s after it; joining that piece to the stretch before left
  the capture one motion, and no edit). No take of the development suite moves (held out
  0.945 / 0.934 / 0.906 as before); of the 14 fresh batches (66 takes) one take gains and
  none loses: few-reps 0.82 / 0.70 / 0.77 -> 0.88 / 0.75 / 0.77. In tvmedit's axes that take
  finds its change into the picking up but takes its next one (into running) 1.8 s late
  instead: the standing still, now inside the picking up, is among the old poses the onset
  step (:func:`tvmedit.engine.parse.onsets.onset`) compares with, and the start of the transition into
  running looks like it. Its count of errors is the same there. Held out in tvmedit's axes
  (768 settings) 0.934 / 0.934 / 0.894 -> 0.940 / 0.934 / 0.893: with the hdm05 fold's
  setting an HDM05 take's first 1.6 s, without period, joins the grabbing it leads into.
* **A weak boundary between two stretches that do not repeat is dropped**
  (:func:`merge_weak`). Between cyclic exercises novelty compares whole cycles, and a small
  peak still marks a change. An exercise whose repetitions are one-off movements (putting
  something on the floor, reaching up: the HDM05 takes) makes novelty fluctuate from one
  repetition to the next and split the exercise in two or three; on the suite when the
  step came in (docs/parsing.md, step 6) every boundary between two clusters of at most one texton
  with a confidence under 0.25 was wrong (5 of 5), and none of the right ones was that
  weak. Since then one right one is (docs/parsing.md, step 20), so one side at least must also show
  no period: two short stretches that both repeat are two exercises, however weak the peak
  between them (CMU 13_30 played 1.4x: two alike exercises of about two 1.7 s periods each,
  one whole texton each, confidence 0.23, were joined). On the 46 takes of the suite the
  step undoes three HDM05 splits, each with a side that shows no period.

* **Clusters the placing left too short** (step 5b, :func:`join_short`; step 36 of
  ``docs/parsing.md``). Boundaries are at least ``min_cluster`` apart when step 1 finds them;
  steps 4 and 5 then move each one on its own, and two can close in on a piece between them.
  With the partition's changes (:mod:`tvmedit.engine.parse.partition`) a slow transition can be a segment
  of its own, 2 s long with a change at each end, and after the placing 1.5 s of it stayed a
  cluster (CMU 13_29 played at 0.7x, between two exercises: a false boundary). An inner
  cluster shorter than step 1's spacing (``min_cluster``, in whole rows of the reduced
  sequence) now joins the neighbour across the weaker of its two boundaries
  (:mod:`tvmedit.engine.parse.confidence`, read at the boundary itself, as step 6 reads it). With the
  partition only: ``partition`` 0 parses as before step 36. The development suite gains that
  take (cmu 0.98 / 1.00 -> 1.00 / 1.00) and nothing else moves; the 26 fresh batches find one
  change fewer (548 -> 547 right boundaries, 579 -> 578 found: as many false ones).

``count(cs, ce, P)`` is the number of whole textons of period P in cluster [cs, ce] (the
parser's texton step, which measures a cluster whose repetitions pause on its moving frames:
:mod:`tvmedit.engine.parse.pauses`), passed in by :mod:`tvmedit.engine.parse.structure`.
"""

import numpy as np

__all__ = ["STILL_RATIO", "absorb_transitions", "merge_weak", "join_short", "activity"]

#: A short cluster that changes pose less than this fraction as fast as the exercise it leads
#: into is a transition even where noise shows a period in it (standing still).
STILL_RATIO = 0.5


def activity(v, cluster, fps):
    """How fast the pose changes in ``cluster``: mean frame distance over half a second.

    >>> activity(np.arange(10.0)[:, None], (0, 9), 2)
    1.0
    """
    cs, ce = cluster
    k = max(1, int(round(0.5 * fps)))
    if ce - cs + 1 <= k:
        return 0.0
    d = v[cs + k: ce + 1] - v[cs: ce + 1 - k]
    return float(np.sqrt(np.einsum("nd,nd->n", d, d)).mean())


def _join(period, clusters, periods, a, b):
    # Clusters a..b become one; its period is found again.
    merged = (clusters[a][0], clusters[b][1])
    clusters[a: b + 1] = [merged]
    periods[a: b + 1] = [period(*merged)]


def absorb_transitions(period, clusters, count):
    """Clusters with transitions joined (see the module docstring), and each one's period.

    ``period`` reads the take's periods (:class:`tvmedit.engine.parse.periods.PeriodReader`); its rows,
    rate and ``max_transition`` are used too.

    Returns
    -------
    clusters : list of (start, end)
    periods : list of int or None
    """
    v, fps, p = period.rows, period.fps, period.params
    clusters = list(clusters)
    periods = [period(cs, ce) for cs, ce in clusters]
    cyclic = lambda k: periods[k] is not None and count(*clusters[k], periods[k]) >= 1  # noqa: E731
    limit = p.max_transition * fps
    # What a transition leads into: the next cluster, where it repeats or is too long to be a
    # transition itself; else the previous one, where it repeats (step 27).
    lead = lambda k: clusters[k][1] - clusters[k][0] + 1 > limit or cyclic(k)  # noqa: E731
    i = 0
    while i < len(clusters) and len(clusters) > 1:
        cs, ce = clusters[i]
        j = i + 1 if i + 1 < len(clusters) and lead(i + 1) else i - 1 if i > 0 and cyclic(i - 1) else None
        still = j is not None and activity(v, clusters[i], fps) < STILL_RATIO * activity(v, clusters[j], fps)
        if ce - cs + 1 > limit or j is None or (cyclic(i) and not still):
            i += 1
            continue
        _join(period, clusters, periods, min(i, j), max(i, j))
        i = min(i, j)
    return clusters, periods


def merge_weak(period, clusters, count, confidence, periods=None):
    """Clusters with weak boundaries between non-repeating stretches dropped, and their periods.

    ``confidence`` holds each cluster's boundary confidence (:mod:`tvmedit.engine.parse.confidence`); a
    boundary under ``weak_boundary`` (of ``period.params``) between two clusters of at most one
    texton each, one of them at least showing no period, goes. ``period`` as for
    :func:`absorb_transitions`; ``periods``: the clusters' periods where already read.
    """
    p = period.params
    clusters, confidence = list(clusters), list(confidence)
    periods = list(periods) if periods is not None else [period(cs, ce) for cs, ce in clusters]
    few = lambda k: periods[k] is None or count(*clusters[k], periods[k]) <= 1  # noqa: E731
    i = 1
    while i < len(clusters):
        # At least one side shows no period: two short stretches that both repeat are two
        # exercises, however alike (CMU 13_30 at 1.4x, two of two periods each).
        aperiodic = periods[i - 1] is None or periods[i] is None
        if confidence[i] < p.weak_boundary and aperiodic and few(i - 1) and few(i):
            _join(period, clusters, periods, i - 1, i)
            del confidence[i]
            continue
        i += 1
    return clusters, periods


def join_short(clusters, confidence, least):
    """Clusters with every inner one shorter than ``least`` frames joined to a neighbour (step 5b).

    ``confidence(clusters)`` gives each cluster's boundary confidence (:mod:`tvmedit.engine.parse.confidence`);
    of a short cluster's two boundaries the weaker goes (the earlier of equal ones), and the
    confidences are read again. The first and last clusters stay as they are (a take may start
    or end with a short piece).

    >>> weak = lambda cs: [1.0] + [0.2 if s == 10 else 0.5 for s, _ in cs[1:]]
    >>> join_short([(0, 9), (10, 14), (15, 39)], weak, 20)
    [(0, 14), (15, 39)]
    """
    clusters = list(clusters)
    while True:
        short = [i for i in range(1, len(clusters) - 1) if clusters[i][1] - clusters[i][0] + 1 < least]
        if not short:
            return clusters
        i = short[0]
        conf = confidence(clusters)
        k = i if conf[i] <= conf[i + 1] else i + 1
        clusters[k - 1: k + 1] = [(clusters[k - 1][0], clusters[k][1])]
