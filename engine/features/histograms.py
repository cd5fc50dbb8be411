"""A frame's spherical-coordinate histograms, section 3, eq. (1).

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
The cluster thresholds of :mod:`tvmedit.engine.parse.structure` were calibrated at these
defaults (``benchmarks/bin_sizes.py`` compares others), so another bin size wants them
recalibrated too.
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..checks import number

#: Most angular bins (theta or phi) and radial bins a histogram may have: each is a column
#: of every frame's feature vector.
MAX_ANGLE_BINS = 3600
MAX_R_BINS = 100_000

__all__ = ["BinSizes", "spherical", "frame_histograms", "MAX_ANGLE_BINS", "MAX_R_BINS"]


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


def _radii(x, y, z, r, tmp):
    """r = sqrt(x^2 + y^2 + z^2) into ``r``, ``tmp`` as scratch (no allocation)."""
    np.multiply(x, x, out=r)
    np.multiply(y, y, out=tmp)
    r += tmp
    np.multiply(z, z, out=tmp)
    r += tmp
    np.sqrt(r, out=r)


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
    there.

    Parameters
    ----------
    positions : (N, 3) array_like, the frame's vertex positions, N >= 1
    origin : (3,) array_like, the sequence's origin
    bins : BinSizes

    Returns
    -------
    h_r (J_r,), h_theta (bins.n_theta,), h_phi (bins.n_phi,) : float64

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

    _radii(x, y, z, r, tmp)
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
