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

How the default bin sizes were chosen: 2 cm and 5 degrees give some 50-65 r bins (a
standing adult reaches about 1 m from its centroid, more with raised arms and as the
subject drifts from the first frame's origin), 72 theta bins and 36 phi bins, so a feature
vector has about 170 entries, and a 2 cm shell of a limb still holds tens of the ~17,000
vertices of a reconstructed frame (3 mm surface noise stays well inside one bin).
``benchmarks/bin_sizes.py`` parses the real-motion takes 13_30 and 13_29
(as generated and at build 0.8) and the synthetic gym at r bins of 1, 2, 4 and 8 cm and
angle bins of 2.5, 5, 10 and 20 degrees. Only 2 cm / 5 degrees meets every target on all
five (precision, recall and texton accuracy 1.00 at their worst). Next best are 4 cm / 5
degrees (1.00 / 1.00 / 0.80) and 1 cm / 5 degrees (0.80 / 0.80 / 1.00). Coarser angles
lose texton lengths first (0.71 at 10 degrees, 0.56 at 20). The cluster thresholds of
:mod:`tvmedit.engine.parse.structure` were calibrated at these defaults, so another bin size also wants
them recalibrated.
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass, field
from typing import Iterable

import numpy as np

from .errors import InputError
from .checks import number

#: Most angular bins (theta or phi) and radial bins a histogram may have: each is a column
#: of every frame's feature vector.
MAX_ANGLE_BINS = 3600
MAX_R_BINS = 100_000

__all__ = [
    "BinSizes",
    "Features",
    "FeatureAccumulator",
    "frame_histograms",
    "centred_histograms",
    "CENTRED_VERTICES",
    "stacked",
    "spherical",
    "features_of",
    "frame_origin",
    "moves_across",
    "FOLLOW_M",
    "SAMPLE_FRAMES",
    "follow_picks",
    "spread_indices",
    "frame_distance",
    "histogram_distance",
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
        # Every angular bin is a histogram column of every frame: their number is bounded.
        for name, span in (("r", None), ("theta", 2 * math.pi), ("phi", math.pi)):
            value = getattr(self, name)
            least = span / MAX_ANGLE_BINS if span else None
            hint = f" (at most {MAX_ANGLE_BINS} bins over {span:.4g} rad)" if span else ""
            number(name, value, above=None if span else 0, at_least=least, at_most=span, hint=hint)

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
    them, so their number depends on the frame. theta bins start at -pi and phi bins at 0,
    each bin holding its lower edge; the value pi itself falls in the last bin. Each
    histogram sums to 1 (see the module docstring for why).

    Bins are found without trigonometry (see :class:`_EdgeCount`): r from
    sqrt(x^2 + y^2 + z^2), theta by comparing a pseudo-angle of (x, y) with those of the bin
    edges, phi by comparing z / r with the cosines of the edges, all in float64 about the
    float64 origin. What is guaranteed: every vertex lands in the bin that :func:`spherical`
    puts it in, except one within rounding of a bin edge (about 1e-16 relative for r and
    theta, 1e-16 / sin(phi) rad for phi: some 1e-15 rad with the default bins), which may
    fall on either side. Edges at multiples of 45 degrees of theta and at phi = 90 degrees
    are exact, so a vertex on an axis or a diagonal x = +-y belongs to the bin that starts
    there. On the mocap test takes (5,292 frames, 91 million vertices) no vertex lands in
    another bin than with ``arctan2`` on :func:`spherical`'s values.

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
    theta_edges, phi_edges = _edge_counters(bins)
    # Every step writes into per-thread buffers (see _scratch).
    xyz, r, tmp, index, cell, mask = _scratch(n)
    np.subtract(positions.T, np.asarray(origin, dtype=np.float64)[:, None], out=xyz)
    x, y, z = xyz
    # y = -0 becomes +0, so that sign(y) = +1 for it (theta = +pi on the negative x axis).
    np.add(y, 0.0, out=y)
    scale = 1.0 / n

    np.multiply(x, x, out=r)
    np.multiply(y, y, out=tmp)
    r += tmp
    np.multiply(z, z, out=tmp)
    r += tmp
    np.sqrt(r, out=r)
    if not math.isfinite(r.max()):
        raise InputError("a frame has NaN or infinite vertex positions")
    if r.max() / bins.r >= MAX_R_BINS:
        raise InputError(f"a frame reaches {r.max():.4g} from its sequence's origin, which needs "
                         f"{r.max() / bins.r:.3g} radial bins of {bins.r:g}; at most {MAX_R_BINS} "
                         "are allowed: use larger bins or check the frame's units.")
    np.divide(r, bins.r, out=tmp)
    np.copyto(index, tmp, casting="unsafe")
    h_r = np.bincount(index) * scale

    # phi >= k * bins.phi exactly when z / r <= cos(k * bins.phi), so the phi bin is the
    # number of edge cosines at or above z / r: n_phi - 1 minus those below it, which turns
    # into a reversed histogram. phi = 0 (z / r = 1) where r = 0.
    if r.min() > 0:
        np.divide(z, r, out=z)
    else:
        np.divide(z, r, out=z, where=r > 0)
        z[r == 0] = 1.0
    phi_edges.count(z, index, tmp, cell, mask, inclusive=False)
    h_phi = np.bincount(index, minlength=bins.n_phi)[::-1] * scale

    key = _theta_key(x, y, tmp, r)
    theta_edges.count(key, index, r, cell, mask, inclusive=True)
    h_theta = np.bincount(index, minlength=bins.n_theta) * scale
    return h_r, h_theta, h_phi


def _theta_key(x, y, out, tmp):
    """A pseudo-angle of (x, y), into ``out``: it grows with theta over (-pi, pi] like theta.

    sign(y) * (1 - x / (|x| + |y|)) runs through -2, -1, 0, 1, 2 at theta = -pi, -pi/2, 0,
    pi/2, pi (and through +-0.5, +-1.5 on the diagonals), is exact at those angles and
    needs one division; it is 0 where x = y = 0 (theta = 0). ``y`` must hold no -0.
    """
    d = np.abs(x, out=tmp)
    d += np.abs(y, out=out)
    np.subtract(d, x, out=out)
    if d.min() > 0:
        np.divide(out, d, out=out)
    else:
        np.divide(out, d, out=out, where=d > 0)
    return np.copysign(out, y, out=out)


def _theta_edge_key(angle):
    """:func:`_theta_key` of the direction at ``angle``, exact at multiples of 45 degrees."""
    eighths = angle / (math.pi / 4)
    if abs(eighths - round(eighths)) < 1e-9:
        return 0.5 * round(eighths)
    x, y = math.cos(angle), math.sin(angle)
    return math.copysign((abs(x) + abs(y) - x) / (abs(x) + abs(y)), y)


_COUNTERS: dict = {}


def _edge_counters(bins):
    """(theta, phi) :class:`_EdgeCount` of the interior bin edges, built once per bin sizes."""
    counters = _COUNTERS.get(bins)
    if counters is None:
        theta = [_theta_edge_key(-math.pi + k * bins.theta) for k in range(1, bins.n_theta)]
        phi = []
        for k in range(1, bins.n_phi):
            angle = k * bins.phi
            phi.append(0.0 if abs(angle / (math.pi / 2) - 1) < 1e-9 else math.cos(angle))
        counters = _COUNTERS[bins] = (_EdgeCount(theta, -2.0, 2.0), _EdgeCount(sorted(phi), -1.0, 1.0))
    return counters


class _EdgeCount:
    """How many of the sorted ``edges`` lie below a value, by table look-up, not search.

    ``count(u, ..., inclusive=True)`` equals ``np.searchsorted(edges, u, "right")`` (edges
    <= u) and ``inclusive=False`` equals ``"left"`` (edges < u), exactly, for every finite
    ``u``. The range [lo, hi] of the values is cut into cells a quarter of the narrowest gap
    between edges wide, so a cell holds at most one edge; the table gives, per cell, the
    number of edges below it and the edge inside it (or +inf), and one comparison with that
    edge finishes the count. Bins so fine that the table would be huge fall back to
    ``np.searchsorted``.
    """

    MAX_CELLS = 1 << 18

    def __init__(self, edges, lo, hi):
        self.edges = np.asarray(edges, dtype=np.float64)
        gaps = np.diff(self.edges)
        narrowest = gaps.min() if len(gaps) else hi - lo
        cells = max(1, math.ceil(4.0 * (hi - lo) / narrowest))
        self.searched = cells > self.MAX_CELLS
        if self.searched:
            return
        width = (hi - lo) / cells
        # Cell c holds values from lo + (c - 1) * width: one spare cell at each end, and
        # take(mode="clip") sends anything beyond them to the end cells, which still count
        # right. The 1e-9 margin dwarfs rounding in the cell index.
        self.scale, self.offset = 1.0 / width, 1.0 - lo / width
        lower = lo + (np.arange(cells + 2) - 1.0) * width - 1e-9 * width
        self.below = np.searchsorted(self.edges, lower, side="left")
        self.inside = np.append(self.edges, np.inf)[self.below]

    def count(self, u, out, tmp, cell, mask, inclusive):
        """Counts for the float64 values ``u`` into the intp array ``out``; the rest are scratch."""
        if self.searched:
            out[...] = np.searchsorted(self.edges, u, side="right" if inclusive else "left")
            return out
        np.multiply(u, self.scale, out=tmp)
        tmp += self.offset
        np.copyto(cell, tmp, casting="unsafe")
        self.below.take(cell, out=out, mode="clip")
        self.inside.take(cell, out=tmp, mode="clip")
        (np.less_equal if inclusive else np.less)(tmp, u, out=mask)
        out += mask
        return out


# Per-thread buffers: a frame's temporaries (~17,000 doubles each) are big enough that
# malloc hands them back to the system after each frame and the next frame faults the
# pages in again, which took longer than the arithmetic.
_WORKSPACE = threading.local()
# A frame with more vertices than this gets buffers that are not kept after it.
_KEEP_VERTICES = 1 << 20


def _scratch(n):
    """Views of per-thread buffers: xyz (3, n), two (n,) float64, two (n,) intp, (n,) bool."""
    held = getattr(_WORKSPACE, "buffers", None)
    if held is None or held[0].shape[1] < n:
        size = max(n, 1024)
        held = (np.empty((3, size)), np.empty((2, size)), np.empty((2, size), dtype=np.intp),
                np.empty(size, dtype=bool))
        if n <= _KEEP_VERTICES:
            _WORKSPACE.buffers = held
    xyz, f, i, m = held
    return xyz[:, :n], f[0, :n], f[1, :n], i[0, :n], i[1, :n], m[:n]


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
    centre = np.asarray(positions, dtype=np.float64).mean(axis=0)
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
