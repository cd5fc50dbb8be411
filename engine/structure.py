"""Hierarchical motion structure: atoms, textons and clusters, section 4, eq. (5)-(8).

A *motion atom* is a short window of frames centred on one frame; the *atom distance*
(eq. (5)) is a weighted sum of frame distances over two such windows. A *motion texton* is
one period of a cyclic motion, and a *motion cluster* a run of similar textons (one
exercise, say). :func:`parse` turns a sequence's feature vectors (rows of
:attr:`engine.features.Features.vectors`) into clusters and textons.

Two methods are provided.

``method="paper"``
    The procedure of section 4 as printed. Atoms are visited in order; a texton starts at a
    local minimum of d_A(t, t_first) (t_first: the current texton's first atom) once the
    curve has fallen by at least ``texton_contrast`` of its maximum since t_first and by
    ``texton_drop`` in absolute terms (noise makes shallow minima). The paper leaves
    "large enough" open; these two thresholds, and a shortest texton of ``min_texton``
    seconds, are this implementation's reading of it. After two textons of a cluster, its
    atoms from the first to the last one of the previous texton form the reference range
    of eq. (7), and two successive atoms farther than ``beta`` from every reference atom
    (eq. (8)) start a new cluster.

``method="energy"`` (the default)
    Measured on real motion (CMU takes turned into meshes), the printed procedure misses
    most exercise boundaries: its eq. (8) test runs only after two textons were found, a
    cluster that starts on a transitional pose never closes its first texton, and a single
    threshold on nearest-atom distances either fires within a cluster (10 fps phase offsets
    put the best earlier match 0.15-0.4 away on normalised histograms) or never. This
    method keeps the paper's quantities and changes how the decisions are taken:

    1. **Clusters by novelty.** On a copy of the sequence reduced to about 10 fps (block
       means of frames), a two-block statistic is evaluated at every frame t: the energy
       distance between the frames of the ``novelty_window`` seconds before t and after t,
       2 E|X - Y| - E|X - X'| - E|Y - Y'| on frame distances, i.e. a checkerboard kernel
       along the diagonal of the frame-distance matrix with its within-block diagonals
       left out. It is near zero inside an exercise whatever its phase (both blocks hold
       whole cycles of the same poses) and peaks where the pose distribution changes.
       Local maxima above ``novelty_threshold`` and at least ``min_cluster`` seconds apart
       are boundaries (of two close peaks of nearly equal height, the earlier one).
    2. **Textons by period.** In each cluster the period P is the lag with the deepest
       mean atom distance mean_u d_A(u, u + L) (self-similarity), taking the shortest lag
       whose depth is within ``period_tolerance`` of the deepest, unless doubling it is
       nearly as deep (an exercise done left then right, or down then up, repeats at
       half its period only approximately: with the theta columns given, 2L is taken when
       the azimuth histogram alone shows no valley at L, as left and right poses share
       their r and phi histograms; in a cluster holding a single cycle, 2L is the
       profile's last lag, which stands for the valley when the profile falls into it).
       Textons then start at the most repeatable atom of the first period (the smallest
       d_A(u, u + P)) and each next one at the minimum of d_A(t, t_first) within
       P +/- 25 %, as in the paper. Partial periods at the cluster's ends are not textons.

Within K frames of either end of the sequence, the atom window is cut at the end and the
remaining weights are rescaled to the full window's total, so an atom distance keeps its
scale (the frames that would be needed do not exist).

Clusters are inclusive frame ranges that cover the sequence. A cluster with fewer than two
textons (a non-cyclic stretch, or an exercise shorter than two periods) is kept, with its
zero or one texton; the motion database decides what to do with it.

Time-like parameters are in seconds so that a 30 fps capture is parsed like a 10 fps one:
the atom window keeps its 0.5 s span (its taps are resampled), and periods and minimum
lengths scale with the frame rate.
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field, fields

import numpy as np

from .atoms import (PAPER_FPS, PAPER_TAPS, atom_distance, atom_distances_to, atoms_along_lag,
                    atom_window, lag_profile, novelty)
from .errors import ParameterError
from .params import MAX_FPS, number

__all__ = [
    "StructureParams",
    "Texton",
    "Structure",
    "parse",
    "textons_for",
    "texton_curve",
    "atom_window",
    "atom_distance",
    "atom_distances_to",
    "lag_profile",
    "novelty",
]


#: Longest atom window (eq. (5)), seconds, and most taps it may have.
MAX_WINDOW_S = 10.0
MAX_TAPS = 101


def _param(default, **limits):
    """A numeric field of :class:`StructureParams` with its range (see :func:`engine.params.number`)."""
    return field(default=default, metadata={"limits": limits})


@dataclass(frozen=True)
class StructureParams:
    """Parameters of :func:`parse`; times in seconds.

    Attributes
    ----------
    method : {"energy", "paper"}
        "energy" (default): novelty-based clusters and period-based textons; "paper": the
        sequential procedure of section 4 as printed (see the module docstring).
    window_taps : tuple of float
        Atom window of eq. (5) at ``window_fps``; an odd number >= 3 of taps. The default is
        the paper's 5-tap window {0.25, 0.5, 1, 0.5, 0.25} at 10 fps (0.5 s).
    window_fps : float
        Frame rate at which ``window_taps`` are given; at other rates the window is
        resampled to the same time span.
    beta : float
        Eq. (8) threshold on the smallest atom distance to the current cluster ("paper").
        The paper's 0.07 belongs to its histogram scale (on our normalised 2 cm / 5 degree
        histograms it fires inside every exercise); 0.3 (with ``texton_contrast`` 0.2) gave
        the best boundary scores of a grid (beta 0.07-0.6, contrast 0.2-0.5) on the base
        takes 13_29 and 13_30, and is still far from usable (``benchmarks/accuracy.py``).
    texton_contrast : float
        "paper": a local minimum of d_A(t, t_first) starts a texton only when it lies below
        the maximum since t_first by this fraction of that maximum.
    texton_drop : float
        "paper": and by at least this much in absolute terms (atom-distance units), which
        is what rejects the minima of a still, noisy sequence.
    min_texton : float
        Shortest texton (and shortest period searched), seconds.
    max_period : float
        Longest period searched ("energy"), seconds.
    min_periodicity : float
        "energy": a cluster has textons only when its deepest lag-profile valley is at
        least this fraction of the profile's median deep (still sequences have none).
    period_tolerance : float
        "energy": a shorter lag is preferred when its depth is within this fraction of the
        deepest (depth: how far below the profile's median the mean atom distance falls).
    novelty_window : float
        "energy": length of each of the two blocks compared, seconds.
    novelty_threshold : float
        "energy": smallest energy-distance peak that counts as a cluster boundary (same
        units as frame distances).
    min_cluster : float
        "energy": least distance between boundaries, seconds; the first and last cluster
        may be down to 3/4 of it.
    twin_peak : float
        "energy": an earlier novelty peak within ``min_cluster`` of a stronger one and at
        least this fraction of its height is the boundary instead.
    analysis_fps : float
        "energy": rate to which the sequence is reduced for cluster detection.
    """

    method: str = "energy"
    window_taps: tuple = PAPER_TAPS
    window_fps: float = _param(PAPER_FPS, above=0, at_most=MAX_FPS)
    beta: float = _param(0.3, at_least=0)
    texton_contrast: float = _param(0.2, at_least=0, at_most=1)
    texton_drop: float = _param(0.05, at_least=0)
    min_texton: float = _param(0.4, above=0, at_most=600)
    max_period: float = _param(5.0, above=0, at_most=600)
    min_periodicity: float = _param(0.05, at_least=0, at_most=1)
    period_tolerance: float = _param(0.3, at_least=0, at_most=1)
    novelty_window: float = _param(3.0, above=0, at_most=3600)
    novelty_threshold: float = _param(0.05, at_least=0)
    min_cluster: float = _param(2.0, above=0, at_most=3600)
    twin_peak: float = _param(0.9, at_least=0, at_most=1)
    analysis_fps: float = _param(10.0, above=0, at_most=MAX_FPS)

    def __post_init__(self):
        if self.method not in ("energy", "paper"):
            raise ParameterError(f"method={self.method!r} is not a structure method; use 'energy' or 'paper'.")
        for f in fields(self):
            if "limits" in f.metadata:
                object.__setattr__(self, f.name, number(f.name, getattr(self, f.name), **f.metadata["limits"]))
        taps = tuple(number("window_taps", tap, at_least=0) for tap in self.window_taps)
        if not 3 <= len(taps) <= MAX_TAPS or len(taps) % 2 == 0 or not sum(taps) > 0:
            raise ParameterError(f"window_taps has {len(taps)} taps summing to {sum(taps):g}; the atom "
                                 f"window needs an odd number from 3 to {MAX_TAPS} of them, not all 0.")
        object.__setattr__(self, "window_taps", taps)
        if (len(taps) - 1) / self.window_fps > MAX_WINDOW_S:
            raise ParameterError(f"window_fps={self.window_fps:g} makes the atom window "
                                 f"{(len(taps) - 1) / self.window_fps:g} s long; it may span at most "
                                 f"{MAX_WINDOW_S:g} s.")
        if self.max_period <= self.min_texton:
            raise ParameterError(f"max_period={self.max_period:g} must be above "
                                 f"min_texton={self.min_texton:g}.")


@dataclass
class Texton:
    """One motion texton: inclusive frame range, its cluster's index, and d_T of eq. (6)."""

    start: int
    end: int
    cluster: int
    distance: float

    def __len__(self) -> int:
        return self.end - self.start + 1


@dataclass
class Structure:
    """Parsed motion structure of one sequence (plain data).

    Attributes
    ----------
    clusters : list of (start, end)
        Inclusive frame ranges, in order, covering every frame.
    textons : list of Texton
        In order; each lies inside its cluster. Clusters may have zero or one texton.
    curve : (T,) float64
        d_A(t, t_first): atom distance from each frame to the first atom of its texton
        (of its cluster where it lies in no texton), as in the paper's Figure 4.
    fps : float
    params : dict
        The :class:`StructureParams` used, as a dict.
    """

    clusters: list
    textons: list
    curve: np.ndarray
    fps: float = PAPER_FPS
    params: dict = field(default_factory=dict)

    @property
    def texton_starts(self) -> list:
        """First frame of every texton."""
        return [t.start for t in self.textons]

    def textons_of(self, cluster: int) -> list:
        """The textons of one cluster."""
        return [t for t in self.textons if t.cluster == cluster]

    def to_json(self) -> dict:
        """Plain lists and dicts (``json.dumps`` works on the result)."""
        return {
            "fps": self.fps,
            "params": dict(self.params),
            "clusters": [[int(s), int(e)] for s, e in self.clusters],
            "textons": [{"start": int(t.start), "end": int(t.end), "cluster": int(t.cluster),
                         "distance": float(t.distance)} for t in self.textons],
            "curve": [float(x) for x in self.curve],
        }

    @classmethod
    def from_json(cls, data) -> "Structure":
        """Inverse of :meth:`to_json` (accepts the dict or its JSON text)."""
        if isinstance(data, str):
            data = json.loads(data)
        params = dict(data.get("params", {}))
        if "window_taps" in params:
            params["window_taps"] = tuple(params["window_taps"])
        return cls(
            clusters=[(int(s), int(e)) for s, e in data["clusters"]],
            textons=[Texton(int(t["start"]), int(t["end"]), int(t["cluster"]), float(t["distance"]))
                     for t in data["textons"]],
            curve=np.asarray(data["curve"], dtype=np.float64),
            fps=float(data.get("fps", PAPER_FPS)),
            params=params,
        )


def _reduce(vectors, step):
    # Block means of ``step`` frames: a 10 fps view of a faster capture.
    v = np.asarray(vectors, dtype=np.float64)
    if step == 1:
        return v
    T = len(v)
    n = -(-T // step)
    padded = np.concatenate([v, np.repeat(v[-1:], n * step - T, axis=0)])
    return padded.reshape(n, step, -1).mean(axis=1)


def _energy_clusters(vectors, fps, p: StructureParams):
    T = len(vectors)
    step = max(1, int(round(fps / p.analysis_fps)))
    v = _reduce(vectors, step)
    f = fps / step
    block = max(3, int(round(p.novelty_window * f)))
    sep = max(2, int(round(p.min_cluster * f)))
    # A block shorter than half the shortest cluster says too little, but never ask for more
    # than the block holds: novelty() would then skip every frame and find no boundary.
    n = novelty(v, block, min_block=min(block, max(3, int(round(0.5 * p.min_cluster * f)))))
    # Non-maximum suppression over local maxima only (a broad peak's shoulder is not a
    # second boundary): strongest first, none closer than ``sep``. When a new motion begins
    # with poses of the old one (standing before the first squat) the peak splits in two
    # and the later top is the higher; an earlier local maximum within ``sep`` and at least
    # ``twin_peak`` as high is taken instead.
    # Near the ends one block is short and its statistic unreliable; a first or last
    # cluster may still be a little shorter than ``min_cluster``.
    edge = max(2, int(round(0.75 * sep)))
    is_peak = np.zeros(len(n), dtype=bool)
    is_peak[1:-1] = (n[1:-1] >= n[:-2]) & (n[1:-1] >= n[2:])
    bounds, claimed = [], []
    for t in np.argsort(-n, kind="stable"):
        t = int(t)
        if n[t] < p.novelty_threshold:
            break
        if not is_peak[t] or t < edge or len(v) - t < edge:
            continue
        if any(abs(t - q) < sep for q in claimed):
            continue
        early = [u for u in range(max(edge, t - sep + 1), t)
                 if is_peak[u] and n[u] >= p.twin_peak * n[t] and all(abs(u - q) >= sep for q in claimed)]
        bounds.append(early[0] if early else t)
        # Both the peak and the boundary chosen for it keep others ``sep`` away.
        claimed += [t, bounds[-1]]
    bounds.sort()
    starts = [0] + [min(T - 1, t * step) for t in bounds]
    starts = sorted(set(starts))
    return [(s, e - 1) for s, e in zip(starts, starts[1:] + [T])]


def _moving_average(v, width):
    # Centred running mean along time, the ends padded by repeating the first/last frame.
    half = width // 2
    padded = np.concatenate([np.repeat(v[:1], half, axis=0), v, np.repeat(v[-1:], half, axis=0)])
    c = np.concatenate([np.zeros((1, v.shape[1])), np.cumsum(padded, axis=0)])
    return (c[2 * half + 1:] - c[: len(v)]) / (2 * half + 1)


def _period(v, cs, ce, fps, w, p: StructureParams, theta=None):
    # Period of the cluster [cs, ce] from its lag profile; None when too short to tell.
    length = ce - cs + 1
    lo = max(2, int(round(p.min_texton * fps)))
    hi = min(int(round(p.max_period * fps)), int(length * 0.8))
    if hi <= lo + 1:
        return None
    # The profile runs on to 0.8 of the cluster (past ``max_period``) so that the half-period
    # test below can look at 2L and 3L.
    top = max(hi, int(length * 0.8))
    seg = v[cs: ce + 1]
    # The subject drifts away from the fixed origin, which makes every histogram change
    # slowly; removing a 2 s running mean keeps the cycles and drops that trend, which
    # otherwise makes long lags look like better periods than the true one.
    seg = seg - _moving_average(seg, max(3, int(round(2.0 * fps)) | 1))
    lags = np.arange(lo, top + 1)
    prof = lag_profile(seg, lags, w)
    # Candidate periods are interior local minima; a valley's prominence is measured against
    # the highest profile values within +/- h lags on each side.
    h = max(2, int(round(0.3 * fps)))
    cand, prom = [], {}
    for i in range(1, len(lags) - 1):
        if prof[i] <= prof[i - 1] and prof[i] <= prof[i + 1]:
            left = prof[max(0, i - h): i].max()
            right = prof[i + 1: i + 1 + h].max()
            depth = min(left, right) - prof[i]
            if depth > 0:
                cand.append(i)
                prom[i] = depth
    if not cand:
        return None
    periods = [i for i in cand if lags[i] <= hi]
    if not periods:
        return None
    best = max(periods, key=lambda i: prom[i])
    # Noise alone makes shallow valleys; a cyclic motion's valley is a clear dent in the
    # profile's level.
    if prom[best] < p.min_periodicity * float(np.median(prof)):
        return None
    # A multiple of the period is a valley too, often as deep: take the shortest lag that
    # is nearly as prominent as the most prominent one.
    chosen = min((i for i in periods if prom[i] >= (1 - p.period_tolerance) * prom[best]), key=lambda i: lags[i])
    L = int(lags[chosen])
    # A half period (one side then the other) can pass that test: left and right poses
    # have the same r and phi histograms and differ in theta only. Prefer 2L when the
    # profile is lower there and either the azimuth histogram alone has no valley at L
    # (its relative depth under half the whole vector's) or, without that information, 3L
    # is visible and no valley (a true period's 3L is one).
    def valley_near(target):
        near = [i for i in cand if abs(lags[i] - target) <= max(1.0, 0.1 * target)]
        return min(near, key=lambda i: prof[i]) if near else None

    k2 = valley_near(2 * L)
    # In a cluster that holds only one whole cycle of a left-right exercise, 2L lies at the
    # profile's end, where a valley has no far side and is no candidate. A profile still
    # falling into its last lag, within reach of 2L, stands for that valley.
    last = len(lags) - 1
    if k2 is None and abs(lags[last] - 2 * L) <= max(1.0, 0.1 * 2 * L) and prof[last] < prof[last - 1]:
        k2 = last
    if k2 is not None and prof[k2] < prof[chosen]:
        k3 = valley_near(3 * L) if 3 * L <= top else None
        if theta is not None and k3 is None:
            t_prof = lag_profile(seg[:, theta], lags[[chosen]], w)[0]
            t_med = float(np.median(lag_profile(seg[:, theta], lags[:: max(1, len(lags) // 24)], w)))
            rel_theta = (t_med - t_prof) / t_med if t_med > 0 else 0.0
            rel_all = (float(np.median(prof)) - prof[chosen]) / float(np.median(prof))
            if rel_theta < 0.5 * rel_all:
                L = int(lags[k2])
        elif theta is None and k3 is None and 3 * L <= top:
            L = int(lags[k2])
    return L


def _textons_by_period(v, cs, ce, P, w, ci):
    # Whole periods only: from the most repeatable atom of the first period, each next
    # texton starts at the minimum of d_A(t, t_first) within P +/- 25 %; a period that does
    # not fit before the cluster's end is no texton.
    if P is None or ce - cs + 1 < P:
        return []
    # d_A(u, u + P) for every u at once (ends renormalised as everywhere); it exists for
    # u + P < T only, so a cluster that ends the sequence has one candidate fewer.
    along = atoms_along_lag(v, P, np.asarray(w, dtype=np.float64))
    starts = np.arange(cs, min(ce - P + 1, cs + P - 1, len(along) - 1) + 1)
    if len(starts) == 0:
        return []
    rep = along[starts]
    first = int(starts[int(np.argmin(rep))])
    lo, hi = max(1, int(math.ceil(0.75 * P))), int(math.floor(1.25 * P))
    out = []
    t0 = first
    while t0 + P <= ce + 1:
        cand = np.arange(t0 + lo, min(t0 + hi, ce + 1) + 1)
        d = atom_distances_to(v, t0, cand, w)
        # The next texton's first atom is a local minimum of d_A(t, t_first); when none lies
        # in the window (the cluster ends, or the curve only falls), one period on.
        inner = [i for i in range(1, len(cand) - 1) if d[i] <= d[i - 1] and d[i] <= d[i + 1]]
        nxt = int(cand[min(inner, key=lambda i: d[i])]) if inner else t0 + P
        out.append(Texton(t0, nxt - 1, ci, atom_distance(v, nxt - 1, t0, w)))
        t0 = nxt
    return out


def _textons_of_clusters(v, clusters, fps, p, w, theta=None):
    textons = []
    for ci, (cs, ce) in enumerate(clusters):
        P = _period(v, cs, ce, fps, w, p, theta)
        textons.extend(_textons_by_period(v, cs, ce, P, w, ci))
    return textons


def _parse_energy(v, fps, p, w, theta=None):
    clusters = _energy_clusters(v, fps, p)
    return clusters, _textons_of_clusters(v, clusters, fps, p, w, theta)


def textons_for(vectors, clusters, fps=PAPER_FPS, params: StructureParams | None = None, theta=None) -> list:
    """The textons of given clusters, found as step 2 of ``method="energy"`` finds them.

    For clusters drawn by hand (:mod:`engine.corrections`): each cluster's period from its
    lag profile, then whole periods from its most repeatable atom.

    Parameters
    ----------
    vectors : (T, D) array
        Rows of :attr:`engine.features.Features.vectors`.
    clusters : list of (start, end)
        Inclusive frame ranges; ``Texton.cluster`` indexes this list.
    fps, params, theta
        As for :func:`parse`.

    Returns
    -------
    list of Texton
    """
    p = params or StructureParams()
    v = np.asarray(vectors, dtype=np.float64)
    return _textons_of_clusters(v, clusters, fps, p, atom_window(fps, p.window_taps, p.window_fps), theta)


def texton_curve(vectors, clusters, textons, fps=PAPER_FPS, params: StructureParams | None = None):
    """d_A(t, t_first) of every frame, Figure 4: :attr:`Structure.curve` for given clusters and textons.

    Returns
    -------
    (T,) float64
    """
    p = params or StructureParams()
    v = np.asarray(vectors, dtype=np.float64)
    return _curve(v, clusters, textons, atom_window(fps, p.window_taps, p.window_fps))


def _parse_paper(v, fps, p, w):
    T = len(v)
    min_len = max(2, int(round(p.min_texton * fps)))
    clusters, textons = [], []
    c_start = 0
    t_first = 0
    n_textons = 0          # completed textons in the current cluster
    t_sup = None           # last atom of the previous texton (eq. (7))
    run_max = 0.0
    prev = [None, None]    # curve at t-2, t-1
    above = False          # d_min(t-1) > beta
    t = 1
    while t < T:
        d = atom_distance(v, t, t_first, w)
        new_cluster = False
        if n_textons >= 2 and t_sup is not None:
            ref = np.arange(c_start, t_sup + 1)
            dmin = float(np.min(atom_distances_to(v, t, ref, w)))
            if dmin > p.beta and above:
                new_cluster = True
            above = dmin > p.beta
        if new_cluster:
            # Eq. (8): atoms t-1 and t both unlike the cluster; the new one starts at t-1.
            start = t - 1
            clusters.append((c_start, start - 1))
            c_start = t_first = start
            n_textons, t_sup, above = 0, None, False
            prev = [None, atom_distance(v, t, t_first, w)]
            run_max = prev[1]
            t += 1
            continue
        a, b = prev
        if a is not None and b is not None and b < a and b <= d:
            m = t - 1
            drop = run_max - b
            if m - t_first >= min_len and drop >= p.texton_contrast * run_max and drop >= p.texton_drop:
                textons.append(Texton(t_first, m - 1, len(clusters), atom_distance(v, m - 1, t_first, w)))
                n_textons += 1
                t_sup = m - 1
                t_first = m
                d = atom_distance(v, t, t_first, w)
                prev = [None, d]
                run_max = d
                t += 1
                continue
        # The contrast test above saw the texton up to the candidate minimum only.
        run_max = max(run_max, d)
        prev = [b, d]
        t += 1
    clusters.append((c_start, T - 1))
    return clusters, textons


def _curve(v, clusters, textons, w):
    T = len(v)
    first = np.zeros(T, dtype=np.intp)
    for cs, ce in clusters:
        first[cs: ce + 1] = cs
    for t in textons:
        first[t.start: t.end + 1] = t.start
    curve = np.zeros(T)
    for f in np.unique(first):
        idx = np.nonzero(first == f)[0]
        curve[idx] = atom_distances_to(v, int(f), idx, w)
    return curve


def parse(vectors, fps=PAPER_FPS, params: StructureParams | None = None, theta=None) -> Structure:
    """Parse a sequence's motion structure (section 4) from its feature vectors.

    Parameters
    ----------
    vectors : (T, D) array
        Rows of :attr:`engine.features.Features.vectors`.
    fps : float
        Frame rate of the sequence.
    params : StructureParams, optional
    theta : slice, optional
        Columns of ``vectors`` that hold the azimuth (theta) histogram, i.e.
        :attr:`engine.features.Features.theta_columns`. With it, "energy" tells a half
        period of a left-right exercise from a whole one (see the module docstring).

    Returns
    -------
    Structure

    Examples
    --------
    >>> t = np.arange(200)
    >>> period = np.where(t < 100, 12, 20)
    >>> phase = np.cumsum(2 * np.pi / period)
    >>> v = np.stack([np.sin(phase), np.cos(phase), (t >= 100) * 6.0], axis=1) * 0.05
    >>> s = parse(v, fps=10)
    >>> s.clusters
    [(0, 99), (100, 199)]
    >>> [len(t) for t in s.textons_of(0)][:3]
    [12, 12, 12]
    """
    p = params or StructureParams()
    v = np.asarray(vectors, dtype=np.float64)
    if v.ndim != 2 or len(v) == 0:
        raise ValueError(f"feature vectors must have shape (T, D) with T >= 1, got {v.shape}")
    if not (fps > 0):
        raise ValueError(f"the frame rate must be positive, got {fps!r}")
    w = atom_window(fps, p.window_taps, p.window_fps)
    if len(v) < 2:
        clusters, textons = [(0, len(v) - 1)], []
    elif p.method == "paper":
        clusters, textons = _parse_paper(v, fps, p, w)
    else:
        clusters, textons = _parse_energy(v, fps, p, w, theta)
    params = asdict(p)
    params["window_taps"] = list(p.window_taps)
    return Structure(clusters, textons, _curve(v, clusters, textons, w), float(fps), params)
