"""Boundaries where the rhythm changes: weak novelty peaks confirmed by a change of period.

Step 1b of the ``energy`` parser (:mod:`tvmedit.engine.parse.structure`). The novelty (step 1,
:mod:`tvmedit.engine.parse.boundaries`) sees where the pose distribution changes. Two exercises of alike
poses at another tempo change it little, and their peak stays under the threshold: of the
nine boundaries the development suite's HDM05 takes missed, five lay under such a peak
(0.69-0.89 against the threshold 0.9): elbow to knee then kicks, squats then arm circles,
reaching up then hops, putting something on the floor then squats, sneaking then kicks. A lower threshold
finds them but adds false boundaries where poses vary a little (thresholds 0.6-0.8 were
tried among the cross-validation's settings in step 20's work and no fold chose them).

What such a boundary has that a fluctuation inside an exercise has not is a second cue: the
rhythm changes. So a local maximum of the novelty under the threshold but at least
:data:`FLOOR` of it, not a turn (the turn veto of step 1), and ``min_cluster`` or more from
its cluster's ends, splits the cluster when the periods (:func:`tvmedit.engine.parse.periods.cluster_period`)
of the frames before and after it (at most :data:`LOCAL` times ``max_period`` on each side)
differ by ``rhythm_ratio`` (1.5) or more. A ratio within :data:`WHOLE` of a whole number is
no evidence: the period step's known failure is a multiple of the true period (a take's knee
raises with long pauses between them read 3.15 s on one side and 1.05 s on the other, one
motion). Peaks are taken strongest first, each in the cluster it lies in by then.

**A side too short to tell** (step 26). The period step's lag profile runs to
:data:`tvmedit.engine.parse.periods.LONGEST` (0.8) of the frames it is given
(:func:`tvmedit.engine.parse.periods.longest_lag`; only its mirror test's doubling reads further), so on a
side shorter than the other side's period over 0.8 it could not have found that period: the
shorter period it reads is no evidence that the tempo changed, only of what fits in it
(often a half period). Such a peak splits nothing. The cost: a true change of tempo that
close to a cluster's end (within 1.25 times the longer period) is no longer found by this
step. On the development suite, CMU 13_29 turning 6 degrees a second had a weak peak 2.5 s
into a block of one-hand toe touches (period 2.8 s): the 2.4 s before it read 1.3 s, the
block after it 2.9 s, and the split it made was kept while the true boundary 3 s earlier
was merged away as the weaker; with the rule, that boundary is found and the false one goes
(that take finds 4 of its 5 changes, not 3, with one false boundary, not 2; every other
suite take is unchanged). On the eleven fresh batches there were then (52 takes,
``benchmarks/fresh.py``), one of them (``steady-turns``) made for this step before it was
tried, nothing changes.

The periods are the period step's as it reads them, not the true tempos: at the five
boundaries it reads 1.5 / 3.3 s (true 1.32 / 1.64 s: the kicks read at two repetitions),
1.5 / 1.0 s (true 1.50 / 1.04), 1.8 / 0.8 s (1.79 / 0.79), 2.3 / 1.5 s (2.62 / 1.45) and
2.5 / 1.6 s (2.52 / 1.78). Three of the five true ratios are under 1.5 (1.24, 1.44, 1.41),
so the step finds them partly through the period step's own errors. The ratio's reach on
the suite: 1.4 and 1.5 find the same five; 1.3 adds a false boundary; 1.6 to 2 find two.
Nor is the period measured as step 2 measures a cluster's (on the frames that move where
repetitions pause): measured so, the step found fewer HDM05 boundaries and added false ones
(pooled 0.964 / 0.970 / 0.906 against 0.982 / 0.976 / 0.914). Step 1's suppression of
peaks near stronger ones is not carried over, on purpose: reaching up then hops (1.8 / 0.8 s)
peaks over the threshold where the turn veto takes the peak for a turn, and only the weak
peak beside it, with the change of period, finds that boundary.

Measured with ``benchmarks/accuracy.py`` (body axes; precision / recall / texton length):
the pooled figures of the 46 takes then in the suite 0.981 / 0.945 / 0.912 -> 0.982 / 0.976
/ 0.914, hdm05 0.95 / 0.86 / 0.77 -> 0.95 / 0.94 / 0.79 (five boundaries more, no false
one), every other group unchanged; in tvmedit's axes one hdm05 boundary more, and held out
there 0.934 / 0.945 / 0.869 -> 0.928 / 0.939 / 0.878 (the hdm05 fold as before; with step 21
on the rest, the cmu and synth folds pick threshold 1.0 and period tolerance 0.3, and find
between them one right boundary fewer; the synth-drift fold goes without step 21). Four
HDM05 takes made for this check and never looked at before (``benchmarks/fresh.py``): 1.00 /
0.94 / 0.89 -> 1.00 / 1.00 / 0.90 (the one missed boundary found); the three of step 18
unchanged. Leave one group out cannot choose it for the hdm05 fold: no other group changes
with it, and among equals the step left out is taken (README, *How well it parses real
motion*).
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
        ``novelty_threshold``, ``min_cluster``, ``turn_ratio`` and the period step's are used.
    clusters : list of (start, end)
        Inclusive frame ranges covering the sequence (step 1's).
    n, step
        The novelty curve and its frame step (:func:`tvmedit.engine.parse.boundaries.novelty_curve`).
    turn_free : array like ``n``, optional
        The heading-free novelty of step 1's turn veto: a peak under which it stays below
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
