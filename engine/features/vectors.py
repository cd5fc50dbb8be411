"""Feature vectors of whole sequences and the distance between frames, eq. (2)-(4).

A frame's three histograms (:mod:`.histograms`) are concatenated into one row
``[h_r, h_theta, h_phi]``, the r histograms zero-padded to the widest frame's (eq. (4)); the
frame distance of eq. (2), the square root of the three squared histogram distances of
eq. (3), is then the Euclidean distance between rows. :class:`Features` holds a sequence's
rows; :class:`FeatureAccumulator` builds them frame by frame. The origin is the centroid of
the first frame, as in the paper, unless the person strays more than :data:`FOLLOW_M` from
it over the take (:func:`moves_across`): then each frame is taken about where the person is
(:func:`frame_origin`), since an exercise done while drifting would otherwise change its
histograms all the time. :func:`centred_histograms` gives a frame's histograms about its own
centre, which the parser's turn veto reads.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Iterable

import numpy as np

from ..errors import InputError
from .histograms import BinSizes, frame_histograms

__all__ = ["Features", "FeatureAccumulator", "centred_histograms", "stored_rows", "CENTRED_VERTICES", "stacked",
           "features_of", "frame_origin", "moves_across", "FOLLOW_M", "SAMPLE_FRAMES", "follow_picks", "spread_indices",
           "frame_distance", "histogram_distance", "distance_matrix"]


@dataclass
class Features:
    """Per-frame histograms of one sequence, zero-padded to common widths (eq. (4)).

    Attributes
    ----------
    r : (T, J_r) float32
        r histograms; J_r is the widest frame's bin count, narrower frames end in zeros.
    theta : (T, J_theta) float32
    phi : (T, J_phi) float32
    origin : (3,) float64
        Centroid of the first frame, the origin of every frame's coordinates.
    bins : BinSizes
    centred : Features or None
        The same frames' histograms about each frame's own centre (:func:`centred_histograms`),
        where the origin stays put, else None (then they are these). A person
        turning about their own axis away from the origin changes these rows much less than
        those about the origin; the parser's turn veto reads them
        (:func:`tvmedit.engine.parse.structure.parse`). Not padded with the rows above.

    Examples
    --------
    >>> f = features_of([np.zeros((4, 3)), np.array([[0.0, 0, 0.05]] * 4)])
    >>> len(f), f.r.shape, f.vectors.shape
    (2, (2, 3), (2, 111))
    >>> f.pad_r(5).r.shape
    (2, 5)
    """

    r: np.ndarray
    theta: np.ndarray
    phi: np.ndarray
    origin: np.ndarray = field(default_factory=lambda: np.zeros(3))
    bins: BinSizes = field(default_factory=BinSizes)
    centred: "Features | None" = None

    def __len__(self) -> int:
        return int(self.r.shape[0])

    @property
    def vectors(self) -> np.ndarray:
        """(T, J_r + J_theta + J_phi) float32: rows whose Euclidean distance is eq. (2)."""
        return np.concatenate([self.r, self.theta, self.phi], axis=1)

    @property
    def theta_columns(self) -> slice:
        """Columns of :attr:`vectors` holding the theta histogram."""
        return slice(self.r.shape[1], self.r.shape[1] + self.theta.shape[1])

    def pad_r(self, width: int) -> "Features":
        """A copy whose r histograms are zero-padded to ``width`` bins (eq. (4)).

        Use the largest ``r.shape[1]`` of several sequences so their vectors compare.
        """
        if width < self.r.shape[1]:
            raise ValueError(f"cannot pad {self.r.shape[1]} r bins down to {width}")
        r = np.zeros((self.r.shape[0], width), dtype=np.float32)
        r[:, : self.r.shape[1]] = self.r
        return Features(r, self.theta, self.phi, self.origin, self.bins, self.centred)


#: A person whose centre strays further than this from where the take starts (metres,
#: horizontally, on :data:`SAMPLE_FRAMES` frames spread over the take) is followed by the
#: origin (:func:`frame_origin`); CMU subject 13 stays within 0.3 m over whole exercise takes.
FOLLOW_M = 0.5
#: Frames whose centres decide whether the origin follows (:func:`follow_picks`). A dozen
#: missed short excursions: an HDM05 take whose 4 s of jogging in a circle carry the person
#: 2.9 m away (a quarter of its frames beyond 0.5 m) showed none, kept the first frame's
#: origin and lost the jog's start. 48 reads are a few percent of a take's.
SAMPLE_FRAMES = 48


def follow_picks(n):
    """Indices of the (up to :data:`SAMPLE_FRAMES`) frames, spread over a take of ``n``,
    whose centres decide whether the origin follows the person (:func:`moves_across`).

    >>> follow_picks(5).tolist(), len(follow_picks(1000))
    ([0, 1, 2, 3, 4], 48)
    """
    return spread_indices(n, SAMPLE_FRAMES)


def spread_indices(n, count):
    """Up to ``count`` distinct indices spread evenly over ``n`` frames, both ends included.

    >>> spread_indices(10, 4).tolist(), spread_indices(3, 12).tolist(), spread_indices(0, 5).tolist()
    ([0, 3, 6, 9], [0, 1, 2], [])
    """
    return np.unique(np.linspace(0, n - 1, min(count, n)).round().astype(int)) if n > 0 else np.zeros(0, int)


def moves_across(centroids, limit=FOLLOW_M):
    """Whether the origin should follow the person: some centroid lies further than ``limit``
    from the first one horizontally.

    >>> moves_across([[0, 0, 1], [0.3, 0.2, 1]]), moves_across([[0, 0, 1], [0.6, 0, 1]])
    (False, True)
    """
    c = np.asarray(centroids, dtype=np.float64).reshape(-1, 3)
    return bool(len(c) > 1 and np.linalg.norm(c[:, :2] - c[0, :2], axis=1).max() > limit)


def frame_origin(positions, origin, follow):
    """The origin of one frame's coordinates (eq. (1)).

    The paper fixes it at the first frame's centroid (``follow`` False: ``origin``). A person
    who moves across the capture volume then drifts away from it, and every histogram changes
    with the position rather than the pose: an exercise done while drifting splits into many
    clusters. With ``follow``, the origin is the frame's own centroid horizontally and
    ``origin``'s height vertically, so it moves with the person. It is used only for a take
    whose person strays (:func:`moves_across`): about a moving origin the sideways shift of the
    body's centre that tells a left-right exercise's halves apart is lost.

    >>> frame_origin(np.array([[2.0, 1.0, 0.0], [4.0, 1.0, 2.0]]), np.zeros(3), True).tolist()
    [3.0, 1.0, 0.0]
    """
    if not follow:
        return origin
    # Summed as (3, N) rows: numpy reduces (N, 3) over axis 0 several times slower (the same
    # centre to the last bit or two; no histogram of the dev suite's frames changed with it).
    rows = np.ascontiguousarray(np.asarray(positions, dtype=np.float64).T)
    centre = rows.sum(axis=1) / len(rows[0])
    return np.array([centre[0], centre[1], origin[2]])


#: About this many vertices of a frame go into its histograms about its own centre
#: (:func:`centred_histograms`): every k-th in file order, which spreads them over the surface,
#: with k = vertices // CENTRED_VERTICES (so 4,000-8,000 of a larger frame, all of a smaller).
#: The turn veto compares blocks of frames of those rows, where sampling noise averages out;
#: all of a 17,000-vertex frame would double a build's feature pass.
CENTRED_VERTICES = 4000


def centred_histograms(positions, origin, bins: BinSizes = BinSizes()):
    """A frame's histograms about its own centre (:func:`frame_origin` with ``follow``): what
    :attr:`Features.centred` holds, from every k-th of its vertices (the centre too; see
    :data:`CENTRED_VERTICES`).

    >>> frame = np.column_stack([np.linspace(0.0, 0.3, 9000), np.zeros(9000), np.zeros(9000)])
    >>> h_r = centred_histograms(frame, np.zeros(3))[0]
    >>> len(h_r), float(h_r.sum())
    (8, 1.0)

    Of 8,000 vertices every second is taken: here those at the origin, not the others 1 m off.

    >>> frame = np.zeros((8000, 3)); frame[1::2, 0] = 1.0
    >>> len(centred_histograms(frame, np.zeros(3))[0])
    1
    """
    positions = np.asarray(positions)
    sample = positions[:: max(1, len(positions) // CENTRED_VERTICES)]
    return frame_histograms(sample, frame_origin(sample, origin, True), bins)


def stored_rows(positions, origin, bins: BinSizes = BinSizes(), follow=False):
    """What a build keeps of one frame: ``(own, centred)``, its histograms about the sequence's
    origin (:func:`frame_origin`) and about its own centre (:func:`centred_histograms`; None
    where the origin follows), as float32, the precision :class:`Features` stores.

    >>> own, centred = stored_rows(np.array([[0.0, 0, 0], [0.0, 0, 0.1]]), np.zeros(3))
    >>> [h.dtype.name for h in own], len(centred)
    (['float32', 'float32', 'float32'], 3)
    """
    positions = np.asarray(positions)
    own = frame_histograms(positions, frame_origin(positions, origin, follow), bins)
    centred = None if follow else tuple(h.astype(np.float32) for h in centred_histograms(positions, origin, bins))
    return tuple(h.astype(np.float32) for h in own), centred


class FeatureAccumulator:
    """Builds :class:`Features` one frame at a time, so no caller must hold every mesh.

    The first frame added fixes the origin (its centroid) for all later frames. With
    ``centred`` and an origin that does not ``follow``, each frame's histograms about its own
    centre are kept too (:attr:`Features.centred`).

    Examples
    --------
    >>> acc = FeatureAccumulator(BinSizes(), centred=True)
    >>> acc.add(np.array([[0.0, 0, 0], [0.0, 0, 0.1]]))
    >>> acc.add(np.array([[0.5, 0, 0], [0.5, 0, 0.1]]))
    >>> acc.origin.tolist()
    [0.0, 0.0, 0.05]
    >>> f = acc.result()
    >>> len(f), f.r[1].nonzero()[0].tolist(), f.centred.r[1].nonzero()[0].tolist()
    (2, [25], [2])
    """

    def __init__(self, bins: BinSizes | None = None, origin=None, follow=False, centred=False):
        self.bins = bins if bins is not None else BinSizes()
        self.origin = None if origin is None else np.asarray(origin, dtype=np.float64)
        self.follow = bool(follow)
        self.centred = bool(centred) and not self.follow
        self._rows: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
        self._centred_rows: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []

    def add(self, positions) -> None:
        """Append one frame's histograms; ``positions`` is (N, 3)."""
        positions = np.asarray(positions)
        if self.origin is None:
            if positions.ndim != 2 or positions.shape[0] == 0:
                raise InputError("the first frame has no vertices, so it gives no origin")
            self.origin = positions.mean(axis=0, dtype=np.float64)
        self._rows.append(frame_histograms(positions, frame_origin(positions, self.origin, self.follow), self.bins))
        if self.centred:
            self._centred_rows.append(centred_histograms(positions, self.origin, self.bins))

    def add_histograms(self, h_r, h_theta, h_phi, centred=None) -> None:
        """Append histograms computed elsewhere (e.g. by a worker with the same origin);
        ``centred``: the frame's ``(h_r, h_theta, h_phi)`` about its own centre, where kept."""
        self._rows.append((np.asarray(h_r), np.asarray(h_theta), np.asarray(h_phi)))
        if self.centred:
            if centred is None:
                raise ValueError("this accumulator keeps histograms about each frame's own centre: pass them")
            self._centred_rows.append(tuple(np.asarray(h) for h in centred))

    def __len__(self) -> int:
        return len(self._rows)

    def result(self) -> Features:
        """Stack the frames added so far into zero-padded arrays."""
        origin = self.origin if self.origin is not None else np.zeros(3)
        centred = stacked(self._centred_rows, origin, self.bins) if self.centred else None
        return stacked(self._rows, origin, self.bins, centred)


def stacked(rows, origin, bins: BinSizes, centred: Features | None = None) -> Features:
    """:class:`Features` of frames given as ``(h_r, h_theta, h_phi)`` rows, r zero-padded to the
    widest.

    >>> rows = [frame_histograms(np.array([[0.0, 0, z]]), np.zeros(3)) for z in (0.01, 0.03)]
    >>> stacked(rows, np.zeros(3), BinSizes()).r.tolist()
    [[1.0, 0.0], [0.0, 1.0]]
    """
    t = len(rows)
    width = max((len(row[0]) for row in rows), default=1)
    r = np.zeros((t, width), dtype=np.float32)
    theta = np.zeros((t, bins.n_theta), dtype=np.float32)
    phi = np.zeros((t, bins.n_phi), dtype=np.float32)
    for i, (h_r, h_t, h_p) in enumerate(rows):
        r[i, : len(h_r)] = h_r
        theta[i] = h_t
        phi[i] = h_p
    return Features(r, theta, phi, origin, bins, centred)


def features_of(frames: Iterable, bins: BinSizes | None = None) -> Features:
    """Features of a sequence given as an iterable of (N_t, 3) vertex arrays, in order.

    Examples
    --------
    >>> features_of([np.array([[0.0, 0, 0], [0.05, 0, 0]])]).r.tolist()  # both 2.5 cm out
    [[0.0, 1.0]]
    """
    acc = FeatureAccumulator(bins)
    for positions in frames:
        acc.add(positions)
    return acc.result()


def histogram_distance(h1, h2) -> float:
    """Distance between two histograms of one coordinate, eq. (3)-(4).

    The shorter histogram is zero-padded (eq. (4)): a frame that reaches less far out has
    no vertices in the outer r bins.

    Examples
    --------
    >>> histogram_distance([1.0], [0.0, 1.0])
    1.4142135623730951
    """
    h1 = np.asarray(h1, dtype=np.float64)
    h2 = np.asarray(h2, dtype=np.float64)
    width = max(len(h1), len(h2))
    return float(np.linalg.norm(np.pad(h1, (0, width - len(h1))) - np.pad(h2, (0, width - len(h2)))))


def frame_distance(a, b) -> float:
    """Frame distance eq. (2)-(4) between two feature vectors (rows of ``Features.vectors``).

    Both rows must share one layout: rows of one :class:`Features`, or of several padded to
    one r width with :meth:`Features.pad_r` (the builder does this for a library). Rows of
    different lengths are refused rather than padded at the end, which would misplace the
    zeros after the phi bins instead of after the r bins.

    Examples
    --------
    >>> frame_distance([0.5, 0.5, 0.0], [0.5, 0.0, 0.5])
    0.7071067811865476
    """
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    if a.shape != b.shape:
        raise ValueError(f"feature vectors of {a.shape[-1]} and {b.shape[-1]} values have different "
                         "r widths; pad them alike with Features.pad_r first")
    return float(np.sqrt(np.sum((a - b) ** 2)))


def distance_matrix(A, B=None) -> np.ndarray:
    """All frame distances between rows of ``A`` (n, D) and ``B`` (m, D): (n, m) float64.

    Uses |a|^2 + |b|^2 - 2 a.b in float64. Histogram rows have norms below about 1.7, so
    the cancellation error of a squared distance is about 1e-15 and the distance is exact to
    about 3e-8 near zero; negative round-off is clipped to 0, and when ``B`` is omitted
    (``A`` against itself) the diagonal is set to exactly 0.

    Examples
    --------
    >>> distance_matrix(np.array([[0.0, 0.0], [3.0, 4.0]])).tolist()
    [[0.0, 5.0], [5.0, 0.0]]
    """
    a = np.asarray(A, dtype=np.float64)
    same = B is None
    b = a if same else np.asarray(B, dtype=np.float64)
    sq = np.einsum("nd,nd->n", a, a)[:, None] + np.einsum("md,md->m", b, b)[None, :]
    sq -= 2.0 * (a @ b.T)
    np.maximum(sq, 0.0, out=sq)
    d = np.sqrt(sq, out=sq)
    if same:
        np.fill_diagonal(d, 0.0)
    return d
