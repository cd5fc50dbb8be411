"""Clusters that are no exercise of their own: transitions joined to an exercise, weak splits undone.

Rules of the ``energy`` parser (:mod:`tvmedit.engine.parse.structure`) applied to the clusters
its boundaries give:

* **Transitions join the exercise they lead into** (:func:`absorb_transitions`). Standing
  still or a slow change of pose between two exercises differs from both neighbours, so the
  novelty peaks on both of its sides. A cluster of at most ``max_transition`` seconds that
  shows no period, or changes pose at under :data:`STILL_RATIO` of its neighbour's pace
  (standing still can show a period of noise), joins the next cluster when that one repeats
  or is longer than ``max_transition`` (an exercise of one-off movements shows no period),
  else the previous one where that one repeats. A short piece at the end of a take after a
  stretch that does not repeat stays a motion of its own.
* **A weak boundary between two stretches that do not repeat is dropped**
  (:func:`merge_weak`). An exercise of one-off movements (putting something on the floor,
  reaching up) makes the novelty fluctuate from one repetition to the next; a boundary of
  confidence under ``weak_boundary`` between two clusters of at most one texton each, one of
  them at least showing no period, is dropped.
* **Clusters the placing left too short** (:func:`join_short`, with ``partition`` only).
  Settling and onsets move each boundary on its own; an inner cluster they leave shorter
  than the boundaries' least spacing joins the neighbour across its weaker boundary.
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
    # transition itself; else the previous one, where it repeats.
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
        # exercises, however alike.
        aperiodic = periods[i - 1] is None or periods[i] is None
        if confidence[i] < p.weak_boundary and aperiodic and few(i - 1) and few(i):
            _join(period, clusters, periods, i - 1, i)
            del confidence[i]
            continue
        i += 1
    return clusters, periods


def join_short(clusters, confidence, least):
    """Clusters with every inner one shorter than ``least`` frames joined to a neighbour.

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
