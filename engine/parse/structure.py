"""Hierarchical motion structure: atoms, textons and clusters, section 4, eq. (5)-(8).

A *motion atom* is a short window of frames centred on one frame; the *atom distance*
(eq. (5)) is a weighted sum of frame distances over two such windows. A *motion texton* is
one period of a cyclic motion, and a *motion cluster* a run of similar textons (one
exercise, say). :func:`parse` turns a sequence's feature vectors (rows of
:attr:`tvmedit.engine.features.Features.vectors`) into clusters and textons, by one of two
methods:

``method="paper"``
    Section 4 as printed: a texton starts at a local minimum of d_A(t, t_first) that has
    fallen far enough (``texton_contrast``, ``texton_drop``, at least ``min_texton`` s, this
    implementation's reading of "large enough"); after two textons their atoms are the
    reference range of eq. (7), and two successive atoms farther than ``beta`` from it
    (eq. (8)) start a new cluster.
``method="energy"`` (the default)
    The paper's quantities, decisions taken over whole stretches, because on real motion
    the printed procedure misses most exercise boundaries (eq. (8) runs only after two
    textons, and one threshold on nearest-atom distances fires inside a cluster at 10 fps
    phase offsets, or never). The rules, in order:

    1. *Rows*: azimuth histograms smoothed and turned back by the person's slow heading
       (:mod:`.heading`), so turning is not read as a change of pose.
    2. *Clusters* where the whole take changes (:mod:`.partition`, kernel change points on
       the novelty's rows, :mod:`.boundaries`), none where the person only turned, plus
       changes of rhythm under the threshold (:mod:`.rhythm`) and changes just behind a turn.
    3. *Textons* one period long (:mod:`.periods`: the lag profile's deepest valley, the
       mirror test for left-right exercises, pauses between repetitions in :mod:`.pauses`).
    4. *Transitions* join the exercise they lead into, and weak splits of one-off movements
       are undone (:mod:`.joins`).
    5. *Boundaries placed* between whole periods, then back at the onset of the change
       (:mod:`.onsets`); clusters left shorter than ``min_cluster`` join a neighbour.

    Each boundary and texton gets a confidence (:mod:`.confidence`).

The features' origin is the first frame's centroid, as in the paper, unless the person strays
over half a metre from it; then it follows the person. Near the sequence's ends the atom
window is cut and its weights rescaled, so a distance keeps its scale. Clusters are inclusive
frame ranges that cover the sequence; one with fewer than two textons is kept, and the
database decides what to do with it. Times are in seconds, so a 30 fps capture is parsed like
a 10 fps one.
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field

import numpy as np

from .atoms import (PAPER_FPS, atom_distance, atom_distances_to, atoms_along_lag,
                    atom_window, lag_profile, novelty)
from .heading import azimuth_smoothed, azimuth_spectrum
from .boundaries import novelty_boundaries, novelty_curve, spacing
from .confidence import MOVED_S, boundary_confidences, texton_confidence
from .heading import heading_track, turned
from .onsets import onset, settle, turned_away
from .params import StructureParams
from .pauses import moving_frames, with_pauses
from .periods import PeriodReader
from .rhythm import rhythm_splits
from .joins import absorb_transitions, join_short, merge_weak

__all__ = [
    "StructureParams",
    "Texton",
    "Structure",
    "parse",
    "textons_for",
    "texton_curve",
    "vetoed_turns",
    "parser_view",
    "followed_heading",
    "atom_window",
    "atom_distance",
    "atom_distances_to",
    "lag_profile",
    "novelty",
]


@dataclass
class Texton:
    """One motion texton: inclusive frame range, cluster index, d_T of eq. (6) and confidence
    (:func:`tvmedit.engine.parse.confidence.texton_confidence`; None: drawn by hand, or an older library)."""

    start: int
    end: int
    cluster: int
    distance: float
    confidence: float | None = None

    def __len__(self) -> int:
        return self.end - self.start + 1


def _number(value):
    return None if value is None else float(value)


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
    boundary_confidence : list of float
        One per cluster: how sure the parse is of the boundary that starts it, 0-1
        (:func:`tvmedit.engine.parse.confidence.boundary_confidences`; 1 for the first cluster).
    """

    clusters: list
    textons: list
    curve: np.ndarray
    fps: float = PAPER_FPS
    params: dict = field(default_factory=dict)
    boundary_confidence: list = field(default_factory=list)

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
                         "distance": float(t.distance), "confidence": _number(t.confidence)} for t in self.textons],
            "curve": [float(x) for x in self.curve],
            "boundary_confidence": [float(c) for c in self.boundary_confidence],
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
            textons=[Texton(int(t["start"]), int(t["end"]), int(t["cluster"]), float(t["distance"]),
                            _number(t.get("confidence"))) for t in data["textons"]],
            curve=np.asarray(data["curve"], dtype=np.float64),
            fps=float(data.get("fps", PAPER_FPS)),
            params=params,
            boundary_confidence=[float(c) for c in data.get("boundary_confidence", [])],
        )


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


def _cluster_textons(period, cs, ce, P, ci):
    # The textons of one cluster: whole periods of P (read by ``period``, a PeriodReader, where
    # None). Where its repetitions pause (tvmedit.engine.parse.pauses), the period and textons come from its
    # moving frames and each texton keeps the pause after it.
    v, w = period.rows, period.window
    moving = moving_frames(v, cs, ce, period.fps, period.params.pause_share)
    if moving is not None:
        sub = period.on(moving)
        moving_period = sub.one_repetition(0, len(moving) - 1, sub(0, len(moving) - 1, broad=True))
        found = _textons_by_period(sub.rows, 0, len(moving) - 1, moving_period, w, ci)
        if found:
            for t in with_pauses(found, moving, ce, moving_period):
                t.distance = atom_distance(v, t.end, t.start, w)
            return found
    if P is None:
        P = period(cs, ce, broad=True)
    return _textons_by_period(v, cs, ce, period.one_repetition(cs, ce, P), w, ci)


def _textons_of_clusters(period, clusters, periods=None):
    # Each cluster's period (given, or read by ``period``), then its textons.
    v, w = period.rows, period.window
    textons = []
    for ci, (cs, ce) in enumerate(clusters):
        P = periods[ci] if periods is not None else None
        textons.extend(_cluster_textons(period, cs, ce, P, ci))
    for t in textons:
        t.confidence = texton_confidence(v, t.start, t.end, w)
    return textons


def _heading_free(v, fps, p, theta, centred_rows=None):
    # The heading-free rows and their novelty, for the turn veto; (None, None) without one (it
    # needs the azimuth columns: theta None or empty, every peak counts). From the features
    # about each frame's own centre where given (_centred_rows): about an origin the person
    # stands away from, turning about their own axis changes even the heading-free rows.
    if not (p.turn_ratio > 0 and theta is not None and len(range(*theta.indices(v.shape[1]))) > 0):
        return None, None
    if centred_rows is not None:
        free = azimuth_spectrum(*centred_rows)
    else:
        free = azimuth_spectrum(v, theta)
    return free, novelty_curve(free, fps, p)[0]


def _centred_rows(centred, frames):
    # The features about each frame's own centre (Features.centred) as the parser reads them,
    # azimuth histograms smoothed, with their azimuth columns; None without them.
    if centred is None:
        return None
    if len(centred.vectors) != frames:
        raise ValueError(f"the centred features have {len(centred.vectors)} frames, the features {frames}")
    return azimuth_smoothed(centred.vectors, centred.theta_columns), centred.theta_columns


def _period_reader(v, fps, p, w, theta, centred_rows=None):
    # How every step reads a period: on the parser's rows, the mirror test also on the rows
    # about each frame's own centre where the azimuth columns are known (tvmedit.engine.parse.periods, *About
    # the body's own centre*), turned back by their own slow heading as the parser's rows are
    # (*A person who turns*).
    if theta is None:
        centred_rows = None
    elif centred_rows is not None:
        heading = _heading(centred_rows[0], p, centred_rows[1], fps)
        if heading is not None:
            centred_rows = (turned(centred_rows[0], centred_rows[1], -heading), centred_rows[1])
    return PeriodReader(v, fps, w, p, theta, centred_rows)


def _starting_at(starts, frames):
    # Clusters that start at ``starts`` (0 first, increasing) and cover frames 0..frames-1.
    return [(a, b - 1) for a, b in zip(starts, starts[1:] + [frames])]


def _parse_energy(v, fps, p, w, theta, n, step, centred=None):
    # The rows about each frame's own centre, smoothed once for the turn veto, the mirror test
    # and the test of frames only turned.
    centred_rows = _centred_rows(centred, len(v))
    free, turn_free = _heading_free(v, fps, p, theta, centred_rows)
    clusters, turns = novelty_boundaries(v, fps, p, n, step, turn_free)
    # Boundaries near a vetoed turn are placed (settle and onset) on the heading-free rows: on
    # the others the turn itself is the greatest change about them (tvmedit.engine.parse.boundaries).
    near_turn = lambda b: any(abs(b - t) <= p.novelty_window * fps for t in turns)  # noqa: E731
    period = _period_reader(v, fps, p, w, theta, centred_rows)
    # Weak peaks where the period changes (tvmedit.engine.parse.rhythm).
    clusters = rhythm_splits(period, clusters, n, step, turn_free)
    periods = None
    count = lambda cs, ce, P: len(_cluster_textons(period, cs, ce, P, 0))  # noqa: E731
    # Frames a boundary would move back over that are only the old poses turned,
    # read about each frame's own centre where given (a turn about the body's own axis only
    # shifts their azimuth histograms), else on the parser's view.
    turn_rows = (centred_rows or (v, theta)) if free is not None else None
    turned_back = lambda i, to, cs: (to < cs and turn_rows is not None  # noqa: E731
                                     and turned_away(*turn_rows, clusters[i - 1][0], to, cs, fps))
    if p.max_transition > 0:
        clusters, periods = absorb_transitions(period, clusters, count)
    if p.refine_reach > 0 and len(clusters) > 1:
        # Each boundary between whole periods of its two clusters (tvmedit.engine.parse.onsets); on
        # the heading-free rows near a turn, vetoed or one it would move back onto, elsewhere
        # on those rows and the parser's together (``settle_free``).
        periods = periods or [period(cs, ce) for cs, ce in clusters]
        near = {i for i, (cs, _) in enumerate(clusters) if i and near_turn(cs)}
        settled = lambda use: settle(v, clusters, periods, fps, p.novelty_window, p.refine_reach,  # noqa: E731
                                     p.min_cluster, other=free, use_other=use, other_weight=p.settle_free)
        starts = settled(near)
        back = {i for i, (cs, _) in enumerate(clusters) if i and i not in near and turned_back(i, starts[i], cs)}
        if back:
            starts = settled(near | back)
        if starts != [cs for cs, _ in clusters]:
            clusters = _starting_at(starts, len(v))
            periods = None
    if p.onset_reach > 0:
        # Each boundary moves back from its novelty peak to where the motion left the
        # old exercise (tvmedit.engine.parse.onsets), never onto the old cluster's first frame; read on the
        # heading-free rows near a turn, vetoed or left behind by the onset.
        def start_of(i, cs):
            first = clusters[i - 1][0]
            if near_turn(cs):
                return onset(free, first, cs, fps, reach=p.onset_reach)
            left = onset(v, first, cs, fps, reach=p.onset_reach)
            if turned_back(i, left, cs):
                return max(left, onset(free, first, cs, fps, reach=p.onset_reach))
            return left

        starts = [0] + [max(start_of(i, cs), clusters[i - 1][0] + 1) for i, (cs, _) in enumerate(clusters) if i]
        if starts != [cs for cs, _ in clusters]:
            clusters = _starting_at(starts, len(v))
            periods = None
    if p.partition > 0:
        # With the partition only: a cluster that settling and onsets left shorter than the
        # boundaries' least spacing joins a neighbour (tvmedit.engine.parse.joins).
        least = spacing(p, fps / step) * step
        joined = join_short(clusters, lambda cs: boundary_confidences(n, step, cs, p.novelty_threshold), least)
        if joined != clusters:
            clusters, periods = joined, None
    if p.weak_boundary > 0:
        clusters, periods = merge_weak(period, clusters, count,
                                       boundary_confidences(n, step, clusters, p.novelty_threshold), periods)
    return clusters, _textons_of_clusters(period, clusters, periods)


def textons_for(vectors, clusters, fps=PAPER_FPS, params: StructureParams | None = None, theta=None,
                centred=None) -> list:
    """The textons of given clusters, found as ``method="energy"`` finds them.

    For clusters drawn by hand (:mod:`tvmedit.engine.store.corrections`): each cluster's period from its
    lag profile, then whole periods from its most repeatable atom.

    Parameters
    ----------
    vectors : (T, D) array
        Rows of :attr:`tvmedit.engine.features.Features.vectors`.
    clusters : list of (start, end)
        Inclusive frame ranges; ``Texton.cluster`` indexes this list.
    fps, params, theta, centred
        As for :func:`parse` (the centred rows for the periods' mirror test, as the parser
        reads them).

    Returns
    -------
    list of Texton
    """
    p = params or StructureParams()
    v = parser_view(vectors, p, theta, fps)
    # Smoothed only where _period_reader passes them on to the mirror test (theta known).
    centred_rows = _centred_rows(centred, len(v)) if p.method == "energy" and theta is not None else None
    return _textons_of_clusters(_period_reader(v, fps, p, atom_window(fps, p.window_taps, p.window_fps), theta,
                                               centred_rows), clusters)


def texton_curve(vectors, clusters, textons, fps=PAPER_FPS, params: StructureParams | None = None, theta=None):
    """d_A(t, t_first) of every frame, Figure 4: :attr:`Structure.curve` for given clusters and textons.

    Returns
    -------
    (T,) float64
    """
    p = params or StructureParams()
    v = parser_view(vectors, p, theta, fps)
    return _curve(v, clusters, textons, atom_window(fps, p.window_taps, p.window_fps))


def parser_view(vectors, params=None, theta=None, fps=None):
    """The feature rows as the parser reads them: float64, and for method "energy" with the
    theta columns given, azimuth histograms smoothed (:func:`tvmedit.engine.parse.heading.azimuth_smoothed`)
    and turned back by the person's slow heading (:mod:`tvmedit.engine.parse.heading`,
    ``heading_window``; it needs ``fps``).

    Everything that decides or measures a structure (:func:`parse`, :func:`textons_for`,
    :func:`texton_curve`, :mod:`tvmedit.engine.store.corrections`) reads this view, so a texton's d_T and
    confidence are the same whether the parser or a correction made it.

    Returns
    -------
    (T, D) float64
    """
    p = params or StructureParams()
    if p.method == "energy" and theta is not None:
        v = azimuth_smoothed(vectors, theta)
        heading = _heading(v, p, theta, fps)
        return v if heading is None else turned(v, theta, -heading)
    return np.asarray(vectors, dtype=np.float64)


def _heading(smoothed, p, theta, fps):
    # The heading parser_view undoes (radians a frame), None where it follows none.
    if p.method != "energy" or theta is None or not p.heading_window > 0:
        return None
    if fps is None:
        raise ValueError("parser_view needs the frame rate (fps) to follow the heading")
    return heading_track(smoothed, theta, fps, p.heading_window)


def followed_heading(vectors, params=None, theta=None, fps=None):
    """The person's slow heading as the parser followed it (:mod:`tvmedit.engine.parse.heading`), degrees a
    frame, relative to the first window's; None where it follows none (method "paper",
    ``heading_window`` 0, no azimuth columns). For showing it (the report), not for parsing.

    >>> v = np.zeros((80, 76)); v[:, 4:] = 1.0
    >>> float(np.abs(followed_heading(v, theta=slice(4, 76), fps=10)).max())
    0.0
    >>> followed_heading(v, StructureParams(heading_window=0), slice(4, 76), 10) is None
    True
    """
    p = params or StructureParams()
    if theta is None:
        return None
    heading = _heading(azimuth_smoothed(vectors, theta), p, theta, fps)
    return None if heading is None else np.degrees(heading)


def vetoed_turns(vectors, params=None, theta=None, fps=None, centred=None):
    """Frames where the parser read the person turning and cut no boundary (the turn veto,
    :mod:`tvmedit.engine.parse.boundaries`), in order; [] where there is no veto (method "paper",
    ``turn_ratio`` 0, no azimuth columns). For showing them (the report), not for parsing.

    >>> v = np.zeros((80, 76)); v[:, 4:] = 1.0
    >>> vetoed_turns(v, theta=slice(4, 76), fps=10), vetoed_turns(v, StructureParams(turn_ratio=0), slice(4, 76), 10)
    ([], [])
    """
    p = params or StructureParams()
    v = np.asarray(vectors, dtype=np.float64)
    if p.method != "energy" or not p.turn_ratio > 0 or theta is None or fps is None or len(v) < 2:
        return []
    v = parser_view(v, p, theta, fps)
    n, step = novelty_curve(v, fps, p)
    turn_free = _heading_free(v, fps, p, theta, _centred_rows(centred, len(v)))[1]
    return [] if turn_free is None else novelty_boundaries(v, fps, p, n, step, turn_free)[1]


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


def parse(vectors, fps=PAPER_FPS, params: StructureParams | None = None, theta=None, centred=None) -> Structure:
    """Parse a sequence's motion structure (section 4) from its feature vectors.

    Parameters
    ----------
    vectors : (T, D) array
        Rows of :attr:`tvmedit.engine.features.Features.vectors`.
    fps : float
        Frame rate of the sequence.
    params : StructureParams, optional
    theta : slice, optional
        Columns of ``vectors`` that hold the azimuth (theta) histogram, i.e.
        :attr:`tvmedit.engine.features.Features.theta_columns`. With it, "energy" tells a half
        period of a left-right exercise from a whole one and a turn from a boundary.
    centred : tvmedit.engine.features.Features, optional
        The same frames' features about each frame's own centre
        (:attr:`tvmedit.engine.features.Features.centred`, where the origin stays put): the turn
        veto reads their heading-free rows, so a person turning about their own axis away
        from the origin is read as turning. Without them it reads ``vectors``'.

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
    v = parser_view(v, p, theta, fps)
    w = atom_window(fps, p.window_taps, p.window_fps)
    curve, step = novelty_curve(v, fps, p) if len(v) >= 2 else (np.zeros(1), 1)
    if len(v) < 2:
        clusters, textons = [(0, len(v) - 1)], []
    elif p.method == "paper":
        clusters, textons = _parse_paper(v, fps, p, w)
    else:
        clusters, textons = _parse_energy(v, fps, p, w, theta, curve, step, centred)
    params = asdict(p)
    params["window_taps"] = list(p.window_taps)
    for t in textons:
        if t.confidence is None:
            t.confidence = texton_confidence(v, t.start, t.end, w)
    # Each boundary's confidence: its novelty peak, discounted as the steps after the novelty
    # (energy only: whole periods, the onset) moved it off that peak (tvmedit.engine.parse.confidence).
    reach = int(round((p.refine_reach + p.onset_reach) * fps)) if p.method != "paper" else 0
    sure = boundary_confidences(curve, step, clusters, p.novelty_threshold, reach, MOVED_S * fps)
    return Structure(clusters, textons, _curve(v, clusters, textons, w), float(fps), params, sure)
