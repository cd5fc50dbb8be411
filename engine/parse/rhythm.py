"""Boundaries where the rhythm changes: weak novelty peaks confirmed by a change of period.

The novelty (:mod:`tvmedit.engine.parse.boundaries`) sees where the pose distribution changes.
Two exercises of alike poses at another tempo change it little, and their peak stays under
the threshold; a lower threshold finds them but adds false boundaries where poses vary a
little. What such a boundary has that a fluctuation inside an exercise has not is a second
cue: the rhythm changes.

So a local maximum of the novelty under the threshold but at least :data:`FLOOR` of it, not
a turn, and ``min_cluster`` or more from its cluster's ends, splits the cluster when the
periods (:func:`tvmedit.engine.parse.periods.cluster_period`) of the frames before and after it
(at most :data:`LOCAL` times ``max_period`` on each side) differ by ``rhythm_ratio`` or more.
A ratio within :data:`WHOLE` of a whole number is no evidence: the period rule's known
failure is a multiple of the true period. Peaks are taken strongest first, each in the
cluster it lies in by then.

**A side too short to tell.** The lag profile runs to :data:`tvmedit.engine.parse.periods.LONGEST`
of the frames it is given (:func:`tvmedit.engine.parse.periods.longest_lag`), so on a side
shorter than the other side's period over that share it could not have found that period: a
shorter period read there is no evidence that the tempo changed, and the peak splits nothing.
A true change of tempo that close to a cluster's end is then left to the other rules.
"""

import numpy as np

from .boundaries import local_maxima, spacing, turn_test
from .periods import longest_lag

__all__ = ["rhythm_splits", "FLOOR", "WHOLE", "LOCAL"]

#: Least novelty peak, as a share of the threshold, that a change of period may confirm.
FLOOR = 0.75
#: A period ratio within this share of a whole number (2, 3, ...) confirms nothing.
WHOLE = 0.05
#: Each side's period is measured on at most this many times ``max_period`` next to the peak.
LOCAL = 3.0


def rhythm_splits(period, clusters, n, step, turn_free=None):
    """Clusters split where a weak novelty peak and a change of period coincide.

    Parameters
    ----------
    period : tvmedit.engine.parse.periods.PeriodReader
        The take's periods; of its parameters ``rhythm_ratio`` (0: no split),
        ``novelty_threshold``, ``min_cluster``, ``turn_ratio`` and the period rule's are used.
    clusters : list of (start, end)
        Inclusive frame ranges covering the sequence (the novelty's boundaries).
    n, step
        The novelty curve and its frame step (:func:`tvmedit.engine.parse.boundaries.novelty_curve`).
    turn_free : array like ``n``, optional
        The heading-free novelty of the turn veto: a peak under which it stays below
        ``turn_ratio`` of the peak within 0.5 s is a turn and splits nothing.

    Returns
    -------
    list of (start, end), in order, covering the sequence.

    Examples
    --------
    Six seconds cycling once a second, then six at 1.5 s, under a weak peak (0.8 against the
    threshold 0.9):

    >>> t = np.arange(120)
    >>> phase = np.where(t < 60, 2 * np.pi * t / 10, 2 * np.pi * (t - 60) / 15)
    >>> v = np.stack([np.sin(phase), np.cos(phase)], axis=1)
    >>> n = np.zeros(120); n[60] = 0.8
    >>> from tvmedit.engine.parse.periods import PeriodReader
    >>> from tvmedit.engine.parse.structure import StructureParams, atom_window
    >>> rhythm_splits(PeriodReader(v, 10, atom_window(10), StructureParams()), [(0, 119)], n, 1)
    [(0, 59), (60, 119)]
    """
    p, fps = period.params, period.fps
    if p.rhythm_ratio <= 0:
        return list(clusters)
    f = fps / step
    sep = spacing(p, f) * step
    peak, turned = local_maxima(n), turn_test(n, turn_free, p.turn_ratio, f)
    low = FLOOR * p.novelty_threshold
    local = int(round(LOCAL * p.max_period * fps))
    out = list(clusters)
    for t in np.argsort(-n, kind="stable"):
        t = int(t)
        if n[t] < low:
            break
        if not peak[t] or n[t] >= p.novelty_threshold:
            continue
        if turned(t):
            continue
        b = t * step
        k = next(i for i, (cs, ce) in enumerate(out) if cs <= b <= ce)
        cs, ce = out[k]
        if b - cs < sep or ce + 1 - b < sep:
            continue
        # Each side's period on at most LOCAL times max_period next to the peak: the
        # tempo there is what changes, and a long cluster costs no more.
        first, last = max(cs, b - local), min(ce, b + local - 1)
        before, after = period(first, b - 1), period(b, last)
        if not before or not after:
            continue
        # The side that read the shorter period must be long enough for its lag profile to
        # reach the longer one: else it only showed what fits in it (*A side too short to tell*).
        short = b - first if before < after else last + 1 - b
        if max(before, after) > longest_lag(short):
            continue
        ratio = max(before, after) / min(before, after)
        if ratio >= p.rhythm_ratio and abs(ratio - round(ratio)) > WHOLE * ratio:
            out[k:k + 1] = [(cs, b - 1), (b, ce)]
    return out
