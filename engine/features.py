"""Feature vectors and frame distance: spherical-coordinate histograms, eq. (1)-(4).

A frame of a time-varying mesh (TVM) has its own vertices and connectivity, so frames are
compared through statistics rather than correspondences. Each vertex is written in spherical
coordinates about one origin per sequence (the centroid of its first frame), and a frame is
summarised by three histograms, of r, theta and phi. The bin *sizes* are shared by every
frame of every sequence in a library; the number of r bins follows each frame's largest r,
so histograms of different frames may differ in length and the shorter one is zero-padded
(eq. (4)).

Each histogram is divided by the frame's vertex count. Reconstruction gives every frame a
different number of vertices (16,000 to 17,600 on the same body in the mocap test data, and
more for a bigger subject), and raw counts would turn that into a distance between two
frames of the same pose. Normalised, a histogram is the fraction of the surface samples
falling in each bin, which depends on the pose alone.

The frame distance (eq. (2)) is the square root of the sum of the three squared histogram
distances (eq. (3)); that is exactly the Euclidean distance between the concatenations
``[h_r, h_theta, h_phi]`` once the r histograms share a padded width. :class:`Features`
therefore stores one zero-padded row per frame and every distance below is a plain
Euclidean distance between rows.

How the default bin sizes were chosen: 2 cm and 5 degrees give about 100 r bins (a
standing adult reaches about 1.2 m from its centroid, more with raised arms), 72 theta bins
and 36 phi bins, so a feature vector has some 200 entries, and a 2 cm shell of a limb still
holds tens of the ~17,000 vertices of a reconstructed frame (3 mm surface noise stays well
inside one bin). With these defaults the structure parser meets its accuracy targets on the
mocap test takes and all their variants (``benchmarks/accuracy.py``); other sizes were not
swept, and the cluster thresholds of :mod:`engine.structure` are calibrated for these.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Iterable

import numpy as np

from .errors import InputError

__all__ = [
    "BinSizes",
    "Features",
    "FeatureAccumulator",
    "frame_histograms",
    "spherical",
    "features_of",
    "frame_distance",
    "pair_distances",
    "distance_matrix",
]


@dataclass(frozen=True)
class BinSizes:
    """Histogram bin sizes shared by all frames of all sequences of a library (section 3).

    Parameters
    ----------
    r : float
        Radial bin size in metres.
    theta : float
        Azimuth bin size in radians (theta spans (-pi, pi]).
    phi : float
        Polar bin size in radians (phi spans [0, pi], 0 pointing up along +Z).

    Examples
    --------
    >>> BinSizes().r
    0.02
    >>> round(math.degrees(BinSizes().theta), 6)
    5.0
    >>> BinSizes(r=0.03).n_theta, BinSizes().n_phi
    (72, 36)
    """

    r: float = 0.02
    theta: float = math.radians(5.0)
    phi: float = math.radians(5.0)

    def __post_init__(self):
        for name in ("r", "theta", "phi"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise InputError(f"bin size {name}={value!r} must be a positive finite number")

    @property
    def n_theta(self) -> int:
        """Number of theta bins covering (-pi, pi]."""
        return max(1, math.ceil(2.0 * math.pi / self.theta - 1e-9))

    @property
    def n_phi(self) -> int:
        """Number of phi bins covering [0, pi]."""
        return max(1, math.ceil(math.pi / self.phi - 1e-9))

    def to_json(self) -> dict:
        """Plain dict ``{"r": ..., "theta": ..., "phi": ...}``."""
        return {"r": self.r, "theta": self.theta, "phi": self.phi}


def spherical(positions, origin):
    """Spherical coordinates of vertices about ``origin``, eq. (1), Z vertical.

    theta = sign(y) * arccos(x / sqrt(x^2 + y^2)) and phi = arccos(z / r). Two conventions
    make this total and NaN-free: sign(0) is taken as +1, so a point on the negative x axis
    has theta = +pi and theta lies in (-pi, pi]; where x = y = 0 theta is 0, and where r = 0
    phi is 0. They are computed as ``arctan2(y, x)`` and ``arctan2(sqrt(x^2+y^2), z)``, which
    equal the arccos forms (with those conventions) and need no division.

    Parameters
    ----------
    positions : (N, 3) array_like
        Vertex positions in metres.
    origin : (3,) array_like
        The sequence's origin (centroid of its first frame).

    Returns
    -------
    r, theta, phi : (N,) float64

    Examples
    --------
    >>> r, theta, phi = spherical([[1, 0, 0], [-1, 0, 0], [0, -1, 0], [0, 0, 0]], [0, 0, 0])
    >>> theta.round(4).tolist(), phi.round(4).tolist()
    ([0.0, 3.1416, -1.5708, 0.0], [1.5708, 1.5708, 1.5708, 0.0])
    """
    p = np.asarray(positions, dtype=np.float64) - np.asarray(origin, dtype=np.float64)
    x, y, z = p[:, 0], p[:, 1], p[:, 2]
    rxy = np.hypot(x, y)
    r = np.hypot(rxy, z)
    # Adding +0.0 turns -0.0 into +0.0, so y = -0 counts as sign +1 like y = 0 (theta = +pi).
    theta = np.arctan2(y + 0.0, x)
    phi = np.arctan2(rxy, z)
    return r, theta, phi


def frame_histograms(positions, origin, bins: BinSizes = BinSizes()):
    """The three normalised histograms of one frame (section 3, eq. (1)).

    Bin j of r covers [j * bins.r, (j+1) * bins.r); there are floor(max r / bins.r) + 1 of
    them, so their number depends on the frame. theta bins start at -pi and phi bins at 0;
    the value pi itself falls in the last bin. Each histogram sums to 1 (see the module
    docstring for why).

    Parameters
    ----------
    positions : (N, 3) array_like
        Vertex positions of the frame, N >= 1.
    origin : (3,) array_like
        The sequence's origin.
    bins : BinSizes

    Returns
    -------
    h_r : (J_r,) float64
    h_theta : (bins.n_theta,) float64
    h_phi : (bins.n_phi,) float64

    Examples
    --------
    >>> h_r, h_t, h_p = frame_histograms([[0.01, 0, 0], [0, 0, 0.05]], [0, 0, 0])
    >>> h_r.tolist()
    [0.5, 0.0, 0.5]
    >>> float(h_t.sum()), float(h_p[0]), float(h_p[18])
    (1.0, 0.5, 0.5)
    """
    positions = np.asarray(positions)
    if positions.ndim != 2 or positions.shape[1] != 3:
        raise InputError(f"vertex positions must have shape (N, 3), got {positions.shape}")
    n = positions.shape[0]
    if n == 0:
        raise InputError("a frame has no vertices, so it has no histograms")
    r, theta, phi = spherical(positions, origin)
    if not np.isfinite(r).all():
        raise InputError("a frame has NaN or infinite vertex positions")
    n_theta, n_phi = bins.n_theta, bins.n_phi
    ir = (r / bins.r).astype(np.intp)
    it = np.minimum(((theta + np.pi) / bins.theta).astype(np.intp), n_theta - 1)
    ip = np.minimum((phi / bins.phi).astype(np.intp), n_phi - 1)
    # theta = -pi cannot occur with the sign(0) = +1 convention, but rounding in the
    # division may still give -1 for values a hair above -pi.
    np.maximum(it, 0, out=it)
    scale = 1.0 / n
    h_r = np.bincount(ir) * scale
    h_theta = np.bincount(it, minlength=n_theta) * scale
    h_phi = np.bincount(ip, minlength=n_phi) * scale
    return h_r, h_theta, h_phi


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
        return Features(r, self.theta, self.phi, self.origin, self.bins)


class FeatureAccumulator:
    """Builds :class:`Features` one frame at a time, so no caller must hold every mesh.

    The first frame added fixes the origin (its centroid) for all later frames.

    Examples
    --------
    >>> acc = FeatureAccumulator(BinSizes())
    >>> acc.add(np.array([[0.0, 0, 0], [0.0, 0, 0.1]]))
    >>> acc.origin.tolist()
    [0.0, 0.0, 0.05]
    >>> len(acc.result())
    1
    """

    def __init__(self, bins: BinSizes | None = None, origin=None):
        self.bins = bins if bins is not None else BinSizes()
        self.origin = None if origin is None else np.asarray(origin, dtype=np.float64)
        self._rows: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []

    def add(self, positions) -> None:
        """Append one frame's histograms; ``positions`` is (N, 3)."""
        positions = np.asarray(positions)
        if self.origin is None:
            if positions.ndim != 2 or positions.shape[0] == 0:
                raise InputError("the first frame has no vertices, so it gives no origin")
            self.origin = positions.mean(axis=0, dtype=np.float64)
        self._rows.append(frame_histograms(positions, self.origin, self.bins))

    def add_histograms(self, h_r, h_theta, h_phi) -> None:
        """Append histograms computed elsewhere (e.g. by a worker with the same origin)."""
        self._rows.append((np.asarray(h_r), np.asarray(h_theta), np.asarray(h_phi)))

    def __len__(self) -> int:
        return len(self._rows)

    def result(self) -> Features:
        """Stack the frames added so far into zero-padded arrays."""
        t = len(self._rows)
        width = max((len(row[0]) for row in self._rows), default=1)
        r = np.zeros((t, width), dtype=np.float32)
        theta = np.zeros((t, self.bins.n_theta), dtype=np.float32)
        phi = np.zeros((t, self.bins.n_phi), dtype=np.float32)
        for i, (h_r, h_t, h_p) in enumerate(self._rows):
            r[i, : len(h_r)] = h_r
            theta[i] = h_t
            phi[i] = h_p
        origin = self.origin if self.origin is not None else np.zeros(3)
        return Features(r, theta, phi, origin, self.bins)


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


def frame_distance(a, b) -> float:
    """Frame distance eq. (2)-(4) between two feature vectors (rows of ``Features.vectors``).

    Vectors of different lengths are compared as if the shorter were zero-padded; this is
    only right when the extra entries are r bins, i.e. for vectors of one library whose
    r widths were padded alike, or for single histograms.

    Examples
    --------
    >>> frame_distance([0.5, 0.5, 0.0], [0.5, 0.0, 0.5])
    0.7071067811865476
    >>> frame_distance([1.0], [0.0, 1.0])
    1.4142135623730951
    """
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    if a.shape[-1] != b.shape[-1]:
        width = max(a.shape[-1], b.shape[-1])
        a = np.pad(a, (0, width - a.shape[-1]))
        b = np.pad(b, (0, width - b.shape[-1]))
    return float(np.sqrt(np.sum((a - b) ** 2)))


def pair_distances(vectors, i, j) -> np.ndarray:
    """Frame distances between rows ``i`` and ``j`` of ``vectors`` (broadcast index arrays).

    Parameters
    ----------
    vectors : (T, D) array
    i, j : int arrays of broadcastable shapes S

    Returns
    -------
    (S) float64

    Examples
    --------
    >>> v = np.array([[0.0, 0.0], [3.0, 4.0], [0.0, 1.0]])
    >>> pair_distances(v, np.array([0, 0, 1]), np.array([1, 2, 1])).tolist()
    [5.0, 1.0, 0.0]
    """
    v = np.asarray(vectors)
    diff = v[np.asarray(i)].astype(np.float64) - v[np.asarray(j)]
    return np.sqrt(np.einsum("...d,...d->...", diff, diff))


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
