"""Periods of motion clusters: the lag profile's valleys, and a half period told from a whole one.

A cluster's period is the lag L whose mean atom distance mean_u d_A(u, u + L) (eq. (5),
:func:`tvmedit.engine.parse.atoms.lag_profile`) dips deepest below the profile's level, taking the
shortest lag nearly as deep (a multiple of the period is a valley too). The rules that move
L by a factor of two or three:

* **Half periods of left-then-right exercises** (:func:`mirror_ratio`). Knee raises, side
  bends or one-hand toe touches repeat at half their period only approximately: the second
  half is the first one's mirror image, with the same r and phi histograms and a reflected
  azimuth (theta) histogram, so the profile dips as deep at L/2 as at L. The mirror test
  reflects frame u + L's theta histogram about the best vertical plane (a bin-aligned
  reflection j -> c - j); when the reflection is much nearer frame u than the frame itself,
  L is half a cycle and 2L is taken.
* **About the body's own centre.** The halves are mirror images about the body's own
  sagittal plane, which passes through the features' origin only while the person stands on
  it; where the features about each frame's own centre are kept (``Features.centred``), the
  test reads those too and takes the smaller ratio.
* **A person who turns.** Those rows are read turned back by their own slow heading
  (:mod:`tvmedit.engine.parse.heading`), and the plane is chosen anew every :data:`WINDOW`
  lags (a cycle of a left-then-right exercise): a turn between repetitions is faster than
  the heading follows. A plane chosen every lag is too free (symmetric exercises read as
  mirrored); a cluster shorter than five lags keeps one plane.
* **Double periods of alternating repetitions** (:func:`_submultiple`, ``submultiple``).
  Where consecutive repetitions differ a little, the deepest valley lies at two repetitions;
  L gives way to L/3 or L/2 while the profile's dip there (within :data:`JITTER` of it) is
  at least ``submultiple`` of the larger of L's dip and that of the profile's most prominent
  valley (0.7 of a slight dip is no evidence).
* **Half periods whose third multiple is no valley.** A period repeats, so the profile dips
  below its median near every multiple of it; where L has a valley at 2L but none around 3L,
  L was half a period the mirror test missed, and 2L is taken.
* **Two repetitions in one texton** (:func:`one_repetition`, ``comb``). Where the period P
  read spans two repetitions a and b that differ, the one-repetition valleys lie near P/2
  and 3P/2 (a and a + P); where the profile dips below its level at both, and at P/2 at
  least ``comb`` as deep as at P, textons are cut at P/2, unless P/2 is half a cycle of a
  left-then-right exercise.
"""

from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from .atoms import lag_profile

if TYPE_CHECKING:
    from .params import StructureParams

__all__ = ["cluster_period", "one_repetition", "PeriodReader", "mirror_ratio", "longest_lag", "MIRROR_RATIO", "LONGEST"]

#: A lag whose mirrored frames are at most this fraction as far as the frames themselves is
#: half a cycle of a left-then-right exercise. Half cycles of such exercises read well under
#: 1; half periods of symmetric exercises (jumping jacks, squats, arm circles) read about 1,
#: and whole periods above 1.
MIRROR_RATIO = 0.8

#: The mirror test's reflection plane is chosen anew every this many lags (a person who turns
#: between repetitions turns the plane); 1 is too free: symmetric exercises read as mirrored.
WINDOW = 2

#: Share of a stretch's length that its lag profile runs to (:func:`longest_lag`): the
#: longest period its valleys can show directly. Only the mirror test's doubling (2L for a
#: half period L) reads a longer one.
LONGEST = 0.8

#: Fractions of the chosen lag tried by the sub-multiple test, most parts first.
SUBMULTIPLES = (3, 2)

#: How far (fraction of the lag) one repetition's valley may lie from L/k when L spans k
#: repetitions: consecutive repetitions differ in length (tempo jitter), so the valleys of
#: one repetition lie a little off the exact fractions of L.
JITTER = 0.15

#: Reach of a valley's depth, as a fraction of its lag, where a 0.3 s reach finds no period.
BROAD_REACH = 0.25


def mirror_ratio(seg, lag, theta):
    """How much closer frame u + lag comes to frame u when mirrored, over a segment.

    mean_u |t_u - R t_(u+lag)| / mean_u |t_u - t_(u+lag)| on the azimuth (theta) histograms
    t, where R reflects the histogram about a vertical plane: bin j goes to bin (c - j) mod n.
    The plane is the one that gives the smallest sum over each stretch of :data:`WINDOW`
    lags' worth of pairs (WINDOW x lag pairs; the remainder joins the last stretch, which
    holds up to just under twice that), chosen for each stretch on its own: a person who turns between
    repetitions turns the plane. A segment shorter than 2 WINDOW + 1 lags has one plane. The
    r and phi histograms are left out: a pose and its mirror image share them.

    Parameters
    ----------
    seg : (N, D) array
        Feature vectors of the segment, N > lag.
    lag : int
    theta : slice
        Columns of the azimuth histogram.

    Returns
    -------
    float; under 1 when frame u + lag is nearer the mirror image of frame u than frame u
    itself (about 1 for a symmetric motion, above 1 at a whole period).

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> a = rng.random((1, 8)); b = a[:, [1, 0, 7, 6, 5, 4, 3, 2]]   # b: a reflected
    >>> seg = np.vstack([a, b] * 4)
    >>> round(mirror_ratio(seg, 1, slice(0, 8)), 6)
    0.0
    """
    seg = np.asarray(seg, dtype=np.float64)[:, theta]
    a, b = seg[:-lag], seg[lag:]
    plain = np.sqrt(((a - b) ** 2).sum(axis=1)).sum()
    if plain <= 0:
        return 1.0
    n = a.shape[1]
    j = np.arange(n)
    norms = (a ** 2).sum(axis=1) + (b ** 2).sum(axis=1)
    dist = np.stack([np.sqrt(np.maximum(norms - 2 * (a * b[:, (c - j) % n]).sum(axis=1), 0)) for c in range(n)])
    span = max(1, int(WINDOW * lag))
    cuts = list(range(0, len(a), span))
    if len(cuts) > 1 and len(a) - cuts[-1] < span:
        cuts.pop()
    best = sum(dist[:, s: e].sum(axis=1).min() for s, e in zip(cuts, cuts[1:] + [len(a)]))
    return float(best / plain)


def _moving_average(v, width):
    # Centred running mean along time, the ends padded by repeating the first/last frame.
    half = width // 2
    padded = np.concatenate([np.repeat(v[:1], half, axis=0), v, np.repeat(v[-1:], half, axis=0)])
    c = np.concatenate([np.zeros((1, v.shape[1])), np.cumsum(padded, axis=0)])
    return (c[2 * half + 1:] - c[: len(v)]) / (2 * half + 1)


def _valleys(prof, lags, h, reach):
    """Interior local minima of a lag profile with depth > 0, and each one's depth (dict).

    A valley's depth is the lower of the highest profile values within max(h, reach * lag)
    lags before and after it, less its own value.
    """
    cand, prom = [], {}
    for i in range(1, len(lags) - 1):
        if prof[i] <= prof[i - 1] and prof[i] <= prof[i + 1]:
            k = max(h, int(round(reach * lags[i])))
            depth = min(prof[max(0, i - k): i].max(), prof[i + 1: i + 1 + k].max()) - prof[i]
            if depth > 0:
                cand.append(i)
                prom[i] = depth
    return cand, prom


def _lowest_valley(cand, lags, prof, target, reach):
    # The lowest of the candidate valleys (indices into lags) within ``reach`` lags of
    # ``target``, or None.
    near = [i for i in cand if abs(lags[i] - target) <= reach]
    return min(near, key=lambda i: prof[i]) if near else None


def _submultiple(chosen, cand, lags, prof, level, ratio, clearest=0.0):
    """The shortest sub-multiple of the chosen lag whose valley is nearly as low (index into lags).

    A valley at L/3 or L/2 (:data:`SUBMULTIPLES`) whose dip below the profile's level (its
    median) is at least ``ratio`` times the dip at L means the motion already repeats there;
    L is two or three repetitions that differ a little (clips of one repetition stitched back
    to back alternate in heading or side, so the profile's clearest valley lies at two clips).
    Applied while it holds (L/4, L/6, ...). The valley is looked for within
    :data:`JITTER` of L/parts: repetitions differ in length, so the one-repetition valley
    under a two-repetition one is seldom at exactly half its lag. The mirror test still
    doubles a half period of a left-then-right exercise afterwards.

    ``clearest`` is the dip at the profile's most prominent valley. Where the shortest-lag
    rule has already taken a lag shorter than that valley (a half cycle of a left-then-right
    exercise), the dip at L can be slight, and the first sub-multiple must dip at least
    ``ratio`` times the larger of the two (see the module docstring, *Double periods of
    alternating repetitions*); each further sub-multiple, from one already taken, asks
    ``ratio`` of that one's dip alone.

    >>> lags = np.arange(4, 50)
    >>> def dips(**at):   # a flat profile at level 1 with valleys (index into lags) of these dips
    ...     prof = np.ones(len(lags))
    ...     for lag, dip in at.items():
    ...         prof[int(lag[1:]) - 4] = 1 - dip
    ...     return [int(lag[1:]) - 4 for lag in at], prof
    >>> cand, prof = dips(L40=1.0, L20=0.75, L10=0.6)      # alternating repetitions: 40 -> 20 -> 10
    >>> int(lags[_submultiple(36, cand, lags, prof, 1.0, 0.7, clearest=1.0)])
    10
    >>> cand, prof = dips(L33=0.5, L16=0.05, L5=0.04)      # a half cycle that barely dips, at 16
    >>> before = _submultiple(12, cand, lags, prof, 1.0, 0.7)         # against L's slight dip alone
    >>> int(lags[before]), int(lags[_submultiple(12, cand, lags, prof, 1.0, 0.7, clearest=0.5)])
    (5, 16)
    """
    if not ratio:
        return chosen
    while level > prof[chosen]:
        for parts in SUBMULTIPLES:
            target = lags[chosen] / parts
            k = _lowest_valley(cand, lags, prof, target, max(1.0, JITTER * target))
            if k is not None and level - prof[k] >= ratio * max(level - prof[chosen], clearest):
                chosen, clearest = k, 0.0      # from here on, against this sub-multiple's own dip
                break
        else:
            return chosen
    return chosen


def longest_lag(length):
    """The longest lag, in frames, whose valley a stretch of ``length`` frames can show.

    >>> longest_lag(30), longest_lag(35)
    (24, 28)
    """
    return int(length * LONGEST)


def cluster_period(v, cs, ce, fps, w, p, theta=None, broad=False, mirror=None, profile=None):
    """Period of the cluster [cs, ce] (frames) from its lag profile, and how clear it is.

    Parameters
    ----------
    v : (T, D) array
        Feature vectors of the whole sequence.
    cs, ce : int
        The cluster's first and last frame.
    fps : float
    w : (2K + 1,) array
        Atom window (eq. (5)).
    p : tvmedit.engine.parse.structure.StructureParams
    theta : slice, optional
        The azimuth histogram's columns (the half-period tests).
    broad : bool
        Where the 0.3 s reach finds no clear valley, try a reach of ``BROAD_REACH`` of each
        lag (the textons of a cluster already decided on; not for telling transitions).
    mirror : ((T, D') array, slice), optional
        Other rows of the same frames and their azimuth columns, whose halves the mirror test
        also tries (the features about each frame's own centre: see the module docstring,
        *About the body's own centre*).
    profile : callable, optional
        ``profile(cs, ce, lo, top)``: the lag profile as :func:`_profile` reads it, from a
        cache (:class:`PeriodReader`); else read here.

    Returns
    -------
    period : int or None
        None when the cluster is too short or shows no clear period.
    depth : float
        The chosen valley's prominence over the profile's median (0 without a period): how
        far below its usual level the mean atom distance dips at the period.
    """
    length = ce - cs + 1
    lo = _first_lag(p, fps)
    hi = min(int(round(p.max_period * fps)), longest_lag(length))
    if hi <= lo + 1:
        return None, 0.0
    # The profile runs on to the longest lag (past ``max_period``) so that the half-period
    # test below can look at 2L and 3L.
    top = longest_lag(length)
    lags, prof = profile(cs, ce, lo, top) if profile else _profile(v, cs, ce, fps, w, lo, top)
    found = _clearest_valley(prof, lags, fps, hi, p, broad)
    if found is None:
        return None, 0.0
    cand, prom, periods, best = found
    level = float(np.median(prof))
    # A multiple of the period is a valley too, often as deep: take the shortest lag that
    # is nearly as prominent as the most prominent one.
    chosen = min((i for i in periods if prom[i] >= (1 - p.period_tolerance) * prom[best]), key=lambda i: lags[i])
    chosen = _submultiple(chosen, cand, lags, prof, level, p.submultiple, clearest=level - prof[best])
    depth = float(prom[chosen] / max(float(np.median(prof)), 1e-12))
    L = _whole_cycle(v, cs, ce, int(lags[chosen]), lags, prof, cand, chosen, top, theta, mirror)
    return L, depth


def _clearest_valley(prof, lags, fps, hi, p, broad):
    """``(candidates, prominences, candidates up to lag hi, the most prominent)`` of the lag
    profile, or None where no valley is a clear dent in its level."""
    # Candidate periods are interior local minima; a valley's prominence is measured against
    # the highest profile values within +/- h lags on each side (0.3 s). A slow exercise's
    # valley is broader than that, and a 0.3 s reach sees only its floor: where that finds
    # no clear valley, a reach of a quarter of each lag is tried.
    level = float(np.median(prof))
    h = _valley_lags(fps)
    for reach in ((0.0, BROAD_REACH) if broad else (0.0,)):
        cand, prom = _valleys(prof, lags, h, reach)
        periods = [i for i in cand if lags[i] <= hi]
        if not periods:
            continue
        best = max(periods, key=lambda i: prom[i])
        # Noise alone makes shallow valleys; a cyclic motion's valley is a clear dent in
        # the profile's level.
        if prom[best] >= p.min_periodicity * level:
            return cand, prom, periods, best
    return None


def _whole_cycle(v, cs, ce, L, lags, prof, cand, chosen, top, theta, mirror):
    """L, or the lag near 2L where L is half a cycle (the mirror test and the 3L rules)."""
    length = ce - cs + 1
    level = float(np.median(prof))

    # A half period (one side then the other) can pass the prominence test: left and right
    # poses have the same r and phi histograms and differ in theta only.
    def valley_near(target):
        return _lowest_valley(cand, lags, prof, target, max(1.0, 0.1 * target))

    k2 = valley_near(2 * L)
    # In a cluster that holds only one whole cycle of a left-right exercise, 2L lies at the
    # profile's end, where a valley has no far side and is no candidate. A profile still
    # falling into its last lag, within reach of 2L, stands for that valley.
    last = len(lags) - 1
    if k2 is None and abs(lags[last] - 2 * L) <= max(1.0, 0.1 * 2 * L) and prof[last] < prof[last - 1]:
        k2 = last
    if theta is not None and 2 * L < length and _mirrored(v, cs, ce, L, theta, mirror) < MIRROR_RATIO:
        return int(lags[k2]) if k2 is not None else 2 * L
    # Without the azimuth columns: 2L when the profile is lower there and 3L is visible and
    # no valley (a true period's 3L is one). With them the mirror test above and the 3L-dip
    # test below decide.
    if theta is None and k2 is not None and prof[k2] < prof[chosen]:
        if 3 * L <= top and valley_near(3 * L) is None:
            L = int(lags[k2])
    elif theta is not None and k2 is not None and 3 * L <= top and not _dips_at(prof, lags, 3 * L, level):
        # A period repeats: the profile dips below its level at every multiple of it. Where
        # it dips at 2L but not near 3L, L was half a period (see the module docstring).
        L = int(lags[k2])
    return L


def _first_lag(p, fps):
    # The shortest lag a period may have: a texton of ``p.min_texton`` seconds.
    return max(2, int(round(p.min_texton * fps)))


def _valley_lags(fps):
    # A valley's depth is measured against the profile within 0.3 s (this many lags) of it.
    return max(2, int(round(0.3 * fps)))


def _profile(v, cs, ce, fps, w, lo, top):
    # Lags lo..top and the mean atom distance at each over frames [cs, ce].
    seg = v[cs: ce + 1]
    # The subject drifts away from the fixed origin, which makes every histogram change
    # slowly; removing a 2 s running mean keeps the cycles and drops that trend, which
    # otherwise makes long lags look like better periods than the true one.
    seg = seg - _moving_average(seg, max(3, int(round(2.0 * fps)) | 1))
    lags = np.arange(lo, top + 1)
    return lags, lag_profile(seg, lags, w)


def one_repetition(v, cs, ce, P, fps, w, p, theta=None, mirror=None, profile=None):
    """The texton length of cluster [cs, ce] whose period was read as ``P``: P, or about P/2
    where P spans two repetitions (see the module docstring, *Two repetitions in one texton*).

    P/2 is taken where the lag profile dips below its level (median) both near P/2 and near
    3P/2 (within :data:`JITTER`), the dip near P/2 is at least ``p.comb`` of the dip at P, and
    P/2 is not half a cycle of a left-then-right exercise (:func:`mirror_ratio` at least
    :data:`MIRROR_RATIO`). ``profile`` as for :func:`cluster_period`, whose profile of the
    same frames this is.

    >>> from tvmedit.engine.parse.structure import StructureParams, atom_window
    >>> t = np.arange(120)
    >>> v = np.stack([np.sin(2 * np.pi * t / 10), np.cos(2 * np.pi * t / 10)], axis=1)
    >>> v[::20] += 0.3                          # every second repetition a little different
    >>> w, p = atom_window(10), StructureParams()
    >>> one_repetition(v, 0, 119, 20, 10, w, p), one_repetition(v, 0, 119, 20, 10, w, StructureParams(comb=0))
    (10, 20)
    """
    if not p.comb or P is None or P < 2:
        return P
    top = longest_lag(ce - cs + 1)
    lo = _first_lag(p, fps)
    # Two repetitions a and b (P = a + b) put the one-repetition valleys at a and a + P (or b,
    # b + P): each as far from P/2 and 3P/2 as the other, so both are looked for within the
    # same JITTER of P/2.
    reach = max(1.0, JITTER * P / 2)
    if 1.5 * P + reach > top or P / 2 - reach < lo:
        return P
    lags, prof = profile(cs, ce, lo, top) if profile else _profile(v, cs, ce, fps, w, lo, top)
    level = float(np.median(prof))
    cand, _ = _valleys(prof, lags, _valley_lags(fps), 0.0)

    half, odd = (_lowest_valley(cand, lags, prof, target, reach) for target in (P / 2, 1.5 * P))
    whole = float(prof[int(P) - lo])
    if half is None or odd is None or not (prof[half] < level and prof[odd] < level and whole < level):
        return P
    if level - prof[half] < p.comb * (level - whole):
        return P
    if theta is not None and _mirrored(v, cs, ce, int(lags[half]), theta, mirror) < MIRROR_RATIO:
        return P
    return int(lags[half])


def _mirrored(v, cs, ce, L, theta, mirror=None):
    # The mirror test's ratio on the rows, or on the other rows where they show it clearer.
    ratio = mirror_ratio(v[cs: ce + 1], L, theta)
    if mirror is not None:
        ratio = min(ratio, mirror_ratio(mirror[0][cs: ce + 1], L, mirror[1]))
    return ratio


def _dips_at(prof, lags, target, level):
    """Whether the lag profile falls below its level within ``max(1, 0.1 * target)`` of target."""
    near = np.abs(lags - target) <= max(1.0, 0.1 * target)
    return bool(near.any() and prof[near].min() < level)


@dataclass(frozen=True, eq=False)
class PeriodReader:
    """The period of any stretch of one take, as the parser reads it: :func:`cluster_period`
    with everything but the stretch given once.

    Its fields are :func:`cluster_period`'s arguments of the same meaning: ``rows`` (``v``, the
    parser's rows: :func:`tvmedit.engine.parse.structure.parser_view`), ``fps``, ``window`` (``w``),
    ``params`` (``p``), ``theta`` and ``mirror``.

    Examples
    --------
    >>> from tvmedit.engine.parse.structure import StructureParams, atom_window
    >>> t = np.arange(100)
    >>> v = np.stack([np.sin(2 * np.pi * t / 10), np.cos(2 * np.pi * t / 10)], axis=1)
    >>> period = PeriodReader(v, 10, atom_window(10), StructureParams())
    >>> period(0, 99), period.on(np.arange(0, 100, 2))(0, 49)
    (10, 5)
    """

    rows: np.ndarray
    fps: float
    window: np.ndarray
    params: "StructureParams"
    theta: slice | None = None
    mirror: tuple | None = None
    # Lag profiles read so far, by (cs, ce, lo, top): one_repetition reads the profile
    # cluster_period read for the same cluster, and the rules that join and split clusters
    # read many clusters' periods more than once. Each reader (and each on()) starts empty.
    _profiles: dict = field(default_factory=dict, init=False, repr=False)

    def __call__(self, cs, ce, broad=False):
        """The period of frames [cs, ce] in frames, or None (:func:`cluster_period`)."""
        return cluster_period(self.rows, cs, ce, self.fps, self.window, self.params, self.theta, broad,
                              self.mirror, self._profile)[0]

    def one_repetition(self, cs, ce, P):
        """``P`` or about half of it, as the textons of frames [cs, ce] are cut (:func:`one_repetition`)."""
        return one_repetition(self.rows, cs, ce, P, self.fps, self.window, self.params, self.theta, self.mirror,
                              self._profile)

    def _profile(self, cs, ce, lo, top):
        key = (cs, ce, lo, top)
        if key not in self._profiles:
            self._profiles[key] = _profile(self.rows, cs, ce, self.fps, self.window, lo, top)
        return self._profiles[key]

    def on(self, frames):
        """The same reader on the given frames only (a cluster's moving frames: :mod:`tvmedit.engine.parse.pauses`)."""
        mirror = None if self.mirror is None else (self.mirror[0][frames], self.mirror[1])
        return replace(self, rows=self.rows[frames], mirror=mirror)
