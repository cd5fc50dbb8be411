"""Histograms and frame distance (eq. (1)-(4)) against values worked out by hand."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from tvmedit.engine.errors import InputError, ParameterError
from tvmedit.engine.features import (
    BinSizes,
    FeatureAccumulator,
    distance_matrix,
    features_of,
    frame_distance,
    frame_histograms,
    histogram_distance,
    spherical,
)

BINS = BinSizes(r=0.1, theta=math.radians(90), phi=math.radians(45))


def test_spherical_matches_eq_1_including_axes():
    pts = np.array([[1, 1, 0], [-1, 0, 1], [0, -2, 0], [0, 0, -3], [0, 0, 0], [1, -1, -math.sqrt(2)]], float)
    r, theta, phi = spherical(pts, [0, 0, 0])
    np.testing.assert_allclose(r, [math.sqrt(2), math.sqrt(2), 2, 3, 0, 2])
    # sign(y) * arccos(x / sqrt(x^2 + y^2)), with sign(0) = +1 and theta = 0 on the z axis.
    np.testing.assert_allclose(theta, [math.pi / 4, math.pi, -math.pi / 2, 0, 0, -math.pi / 4])
    np.testing.assert_allclose(phi, [math.pi / 2, math.pi / 4, math.pi / 2, math.pi, 0, 3 * math.pi / 4])


def test_negative_zero_y_counts_as_positive_sign():
    _, theta, _ = spherical([[-1.0, -0.0, 0.0]], [0, 0, 0])
    assert theta[0] == pytest.approx(math.pi)


def test_histograms_by_hand():
    # Origin (0, 0, 0); four points.
    pts = np.array([
        [0.05, 0.0, 0.0],    # r 0.05 -> r bin 0; theta 0 -> bin 2; phi pi/2 -> bin 2
        [0.0, 0.15, 0.0],    # r 0.15 -> 1; theta pi/2 -> 3; phi pi/2 -> 2
        [0.0, 0.0, 0.25],    # r 0.25 -> 2; theta 0 (on the axis) -> 2; phi 0 -> 0
        [-0.3, -0.01, 0.0],  # r ~0.30 -> 3; theta ~ -pi -> 0; phi pi/2 -> 2
    ])
    h_r, h_t, h_p = frame_histograms(pts, [0, 0, 0], BINS)
    assert h_r.tolist() == [0.25, 0.25, 0.25, 0.25]
    assert h_t.tolist() == [0.25, 0.0, 0.5, 0.25]
    assert h_p.tolist() == [0.25, 0.0, 0.75, 0.0]
    assert h_r.dtype == np.float64


def test_theta_pi_falls_in_last_bin_and_r_bins_follow_max_r():
    h_r, h_t, _ = frame_histograms([[-0.5, 0.0, 0.0]], [0, 0, 0], BINS)
    assert h_t.tolist() == [0.0, 0.0, 0.0, 1.0]
    assert len(h_r) == 6 and h_r[5] == 1.0


def test_frame_distance_zero_pads_the_shorter_r_histogram():
    # Frame a: one point at r 0.05 (one r bin). Frame b: points at r 0.05 and 0.25 (three).
    fa = features_of([np.array([[0.05, 0, 0]])], BINS)
    acc = FeatureAccumulator(BINS, origin=[0, 0, 0])
    acc.add([[0.05, 0, 0]])
    acc.add([[0.05, 0, 0], [0.0, 0.0, 0.25]])
    f = acc.result()
    assert fa.r.shape == (1, 1) and f.r.shape == (2, 3)
    assert f.r.tolist() == [[1.0, 0.0, 0.0], [0.5, 0.0, 0.5]]
    # r: (1 - .5)^2 + (0 - .5)^2 with a's missing third bin read as 0 (eq. (4)); theta: all
    # points at theta 0 (bin 2), no difference; phi: a all in bin 2, b half in bin 0, half in 2.
    expected = math.sqrt((0.25 + 0.25) + 0.0 + (0.25 + 0.25))
    v = f.vectors
    assert frame_distance(v[0], v[1]) == pytest.approx(expected)
    # The same through the per-histogram form of eq. (2)-(3) with unequal lengths.
    ha = frame_histograms([[0.05, 0, 0]], [0, 0, 0], BINS)
    hb = frame_histograms([[0.05, 0, 0], [0.0, 0.0, 0.25]], [0, 0, 0], BINS)
    by_parts = math.sqrt(sum(histogram_distance(x, y) ** 2 for x, y in zip(ha, hb)))
    assert by_parts == pytest.approx(expected)


def test_origin_is_first_frame_centroid_for_every_frame():
    acc = FeatureAccumulator(BINS)
    acc.add([[0.0, 0, 0], [0.2, 0, 0]])  # centroid (0.1, 0, 0)
    acc.add([[0.45, 0, 0]])              # r 0.35 from that origin -> r bin 3
    f = acc.result()
    np.testing.assert_allclose(f.origin, [0.1, 0, 0])
    assert f.r[1].tolist() == [0, 0, 0, 1]


def test_pad_r_keeps_distances():
    f = features_of([np.random.default_rng(0).normal(size=(50, 3)) * s for s in (0.1, 0.3)], BinSizes())
    g = f.pad_r(f.r.shape[1] + 7)
    assert g.vectors.shape[1] == f.vectors.shape[1] + 7
    assert frame_distance(*g.vectors) == pytest.approx(frame_distance(*f.vectors))


def test_distance_matrix_agrees_with_frame_distance():
    rng = np.random.default_rng(1)
    v = rng.random((6, 40)).astype(np.float32)
    m = distance_matrix(v)
    for a in range(6):
        for b in range(6):
            assert m[a, b] == pytest.approx(frame_distance(v[a], v[b]), abs=1e-6)
    np.testing.assert_allclose(distance_matrix(v[:2], v[3:]), m[:2, 3:], atol=1e-6)
    assert np.all(np.diag(m) == 0)


def test_degenerate_points_give_no_nan():
    pts = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 0.3], [0.0, 0.0, -0.3]])
    for h in frame_histograms(pts, [0, 0, 0], BinSizes()):
        assert np.isfinite(h).all() and h.sum() == pytest.approx(1.0)


def test_bad_frames_are_named_errors():
    with pytest.raises(InputError):
        frame_histograms(np.zeros((0, 3)), [0, 0, 0])
    with pytest.raises(InputError):
        frame_histograms(np.array([[np.nan, 0, 0]]), [0, 0, 0])
    with pytest.raises(ParameterError, match=r"r=0 is out of range"):
        BinSizes(r=0)
    with pytest.raises(ParameterError, match=r"at most 3600 bins"):
        BinSizes(phi=1e-300)  # once a hang: 3e300 bins
    with pytest.raises(InputError, match=r"needs 5e\+28 radial bins of 0.02; at most 100000"):
        frame_histograms(np.array([[1e27, 0, 0]]), [0, 0, 0])


frames = arrays(np.float64, st.tuples(st.integers(1, 60), st.just(3)),
                elements=st.floats(-1.0, 1.0, allow_nan=False))


@settings(max_examples=60, deadline=None)
@given(frames, frames, st.randoms(use_true_random=False))
def test_distance_properties(a, b, rnd):
    origin = np.array([0.01, -0.02, 0.03])
    bins = BinSizes()

    def vec(p):
        # Every frame padded to the widest r histogram any frame here can have, so that rows
        # of separate accumulators share one layout (eq. (4)).
        acc = FeatureAccumulator(bins, origin=origin)
        acc.add(p)
        return acc.result().pad_r(200).vectors[0].astype(np.float64)

    va, vb = vec(a), vec(b)
    assert frame_distance(va, vb) == pytest.approx(frame_distance(vb, va))
    assert frame_distance(va, va) == 0.0
    order = list(range(len(a)))
    rnd.shuffle(order)
    assert frame_distance(vec(a[order]), vb) == pytest.approx(frame_distance(va, vb), abs=1e-6)
    # Duplicating every vertex changes counts, not fractions: the distance stays.
    assert frame_distance(vec(np.vstack([a, a])), vb) == pytest.approx(frame_distance(va, vb), abs=1e-6)


def reference_bins(points, origin, bins):
    """Bins straight from the definition: floor(value / bin size) of :func:`spherical`'s values."""
    r, theta, phi = spherical(points, origin)
    values = (r / bins.r, (theta + np.pi) / bins.theta, phi / bins.phi)
    index = [np.floor(v).astype(int) for v in values]
    index[1] = np.clip(index[1], 0, bins.n_theta - 1)
    index[2] = np.clip(index[2], 0, bins.n_phi - 1)
    # How far each value lies from the nearest bin edge, in bins.
    margin = np.min([np.abs(v - np.round(v)) for v in values], axis=0)
    return index, margin


def bins_of_each_point(points, origin, bins):
    found = []
    for p in points:
        hists = frame_histograms(p[None], origin, bins)
        found.append([int(np.flatnonzero(h)[0]) for h in hists])
    return np.array(found).T


@pytest.mark.parametrize("bins", [
    BinSizes(),
    BINS,
    BinSizes(r=0.03, theta=math.radians(7), phi=math.radians(13)),  # partial last bins
    BinSizes(theta=math.radians(0.1), phi=math.radians(0.1)),        # phi falls back to search
])
def test_every_vertex_lands_in_the_bin_of_its_spherical_coordinates(bins):
    rng = np.random.default_rng(7)
    points = np.vstack([rng.normal(size=(1500, 3)) * 0.4, rng.normal(size=(300, 3)) * 1e-3,
                        rng.normal(size=(200, 3)) * 5]).astype(np.float32)
    origin = np.array([0.013, -0.2, 0.9])
    expected, margin = reference_bins(points, origin, bins)
    away = margin > 1e-9
    assert away.sum() > 1900
    np.testing.assert_array_equal(bins_of_each_point(points, origin, bins)[:, away],
                                  np.array(expected)[:, away])


def test_axis_and_diagonal_vertices_fall_in_the_bin_they_start():
    bins = BinSizes(r=1.0, theta=math.radians(45), phi=math.radians(45))
    pts = np.array([[1, 0, 0], [1, 1, 0], [0, 1, 0], [-1, 1, 0], [-1, 0, 0], [-1, -1, 0],
                    [0, -1, 0], [1, -1, 0], [0, 0, 0], [-1, -0.0, 0], [0, 0, 1], [0, 0, -1], [1, 0, 1]])
    theta, phi = bins_of_each_point(pts, [0, 0, 0], bins)[1:]
    # theta bins start at -180 + 45 k degrees; theta = 180 (negative x axis) is in the last.
    assert theta.tolist() == [4, 5, 6, 7, 7, 1, 2, 3, 4, 7, 4, 4, 4]
    # phi bins start at 45 k degrees; phi = 0 at the origin, 180 in the last bin.
    assert phi.tolist() == [2, 2, 2, 2, 2, 2, 2, 2, 0, 2, 0, 3, 1]


def test_edge_count_table_matches_searchsorted_on_and_beside_every_edge():
    from tvmedit.engine.features.histograms import _EdgeCount, _edge_counters

    rng = np.random.default_rng(3)
    theta, phi = _edge_counters(BinSizes(theta=math.radians(7), phi=math.radians(13)))
    edges = np.sort(rng.uniform(-1, 1, 40))
    for counter, lo, hi in [(theta, -2.0, 2.0), (phi, -1.0, 1.0), (_EdgeCount(edges, -1.0, 1.0), -1.0, 1.0)]:
        assert not counter.searched
        e = counter.edges
        u = np.concatenate([e, np.nextafter(e, -np.inf), np.nextafter(e, np.inf), [lo, hi, 0.0, -0.0],
                            rng.uniform(lo, hi, 5000)])
        n = len(u)
        out, tmp, cell, mask = np.empty(n, np.intp), np.empty(n), np.empty(n, np.intp), np.empty(n, bool)
        for inclusive, side in [(True, "right"), (False, "left")]:
            counter.count(u, out, tmp, cell, mask, inclusive)
            np.testing.assert_array_equal(out, np.searchsorted(e, u, side=side))


def test_frames_of_any_size_in_any_order_and_thread_agree():
    from concurrent.futures import ThreadPoolExecutor

    rng = np.random.default_rng(5)
    frames = [rng.normal(size=(n, 3)) * 0.3 for n in (10, 20000, 3, 5000, 20001, 1)]
    origin = [0.0, 0.1, 0.0]
    first = [frame_histograms(f, origin) for f in frames]
    with ThreadPoolExecutor(4) as pool:
        again = list(pool.map(lambda f: frame_histograms(f, origin), frames * 8))
    for k, hists in enumerate(again):
        for a, b in zip(first[k % len(frames)], hists):
            np.testing.assert_array_equal(a, b)
    for f, hists in zip(frames, first):
        expected, margin = reference_bins(f, origin, BinSizes())
        assert margin.min() > 1e-9
        for h, e in zip(hists, expected):
            np.testing.assert_array_equal(np.round(h * len(f)), np.bincount(e, minlength=len(h)))


def test_rows_of_different_r_widths_are_refused_not_misaligned():
    # Padding a whole row at its end would put the zeros after the phi bins (eq. (4) pads
    # the r histogram); rows must share a layout first.
    def one_frame(points):
        acc = FeatureAccumulator(BINS, origin=[0, 0, 0])
        acc.add(points)
        return acc.result()

    short = one_frame([[0.05, 0, 0]])                      # r bins [1]
    long = one_frame([[0.05, 0, 0], [0.0, 0.0, 0.25]])     # r bins [.5, 0, .5]
    with pytest.raises(ValueError, match="pad_r"):
        frame_distance(short.vectors[0], long.vectors[0])
    width = long.r.shape[1]
    # r: .5^2 + .5^2; theta: no difference; phi: half the points moved from bin 2 to bin 0.
    assert frame_distance(short.pad_r(width).vectors[0], long.vectors[0]) == pytest.approx(1.0)
