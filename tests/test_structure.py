"""Motion structure parsing (eq. (5)-(8)) on feature vectors built by hand.

The vectors stand in for histogram rows: a sum of sinusoids per dimension, with the period
and the mean pose changing at known frames, scaled like normalised histograms (distances of
a few tenths).
"""

import json

import numpy as np
import pytest

from tvmedit.engine.parse.structure import (
    Structure,
    StructureParams,
    atom_distance,
    atom_distances_to,
    atom_window,
    lag_profile,
    parse,
)

DIM = 40


def cyclic_sequence(parts, fps=10, noise=0.003, seed=0):
    """Feature vectors made of cyclic parts: [(frames, period_frames), ...].

    Each part has its own random mean pose and its own two harmonics per dimension.
    Returns (vectors (T, DIM), list of true part starts).
    """
    rng = np.random.default_rng(seed)
    rows, starts, t0 = [], [], 0
    for frames, period in parts:
        mean = rng.random(DIM) * 0.06
        a1, a2 = rng.normal(size=(2, DIM)) * 0.02
        p1, p2 = rng.uniform(0, 2 * np.pi, size=(2, DIM))
        t = np.arange(frames)[:, None]
        phase = 2 * np.pi * t / period
        rows.append(mean + a1 * np.sin(phase + p1) + a2 * np.sin(2 * phase + p2))
        starts.append(t0)
        t0 += frames
    v = np.concatenate(rows) + rng.normal(scale=noise, size=(t0, DIM))
    return v, starts


def test_atom_window_keeps_its_span_and_total_across_frame_rates():
    assert atom_window(10).tolist() == [0.25, 0.5, 1.0, 0.5, 0.25]
    w30 = atom_window(30)
    assert len(w30) == 13 and w30[6] == w30.max()
    assert w30.sum() == pytest.approx(2.5)
    with pytest.raises(ValueError):
        StructureParams(window_taps=(1.0, 1.0))


def test_atom_distance_is_eq_5_and_renormalised_at_the_ends():
    v = np.array([[0.0], [1.0], [3.0], [6.0], [10.0], [15.0]])
    w = [0.25, 0.5, 1.0, 0.5, 0.25]
    # Inside: sum_k w(k) |v[2+k] - v[3+k]| = .25*1 + .5*2 + 1*3 + .5*4 + .25*5
    assert atom_distance(v, 2, 3, w) == pytest.approx(0.25 + 1 + 3 + 2 + 1.25)
    # At t1 = 0 only k = 0, 1, 2 exist (weights 1, .5, .25 of 2.5, rescaled to 2.5).
    expected = (1 * 1 + 0.5 * 2 + 0.25 * 3) / 1.75 * 2.5
    assert atom_distance(v, 0, 1, w) == pytest.approx(expected)
    np.testing.assert_allclose(atom_distances_to(v, 2, np.array([3, 2]), w), [7.5, 0.0])
    assert atom_distance(v, 1, 4, w) == pytest.approx(atom_distance(v, 4, 1, w))


def test_lag_profile_finds_the_period():
    v, _ = cyclic_sequence([(120, 17)])
    lags = np.arange(5, 30)  # up to 2P the multiple 34 would tie with 17
    assert lags[np.argmin(lag_profile(v, lags, atom_window(10)))] == 17


def test_energy_method_finds_boundaries_and_periods():
    parts = [(60, 10), (80, 24), (70, 14), (90, 30)]
    v, starts = cyclic_sequence(parts)
    s = parse(v, fps=10)
    found = [c[0] for c in s.clusters]
    assert len(found) == len(starts)
    assert all(abs(a - b) <= 2 for a, b in zip(found, starts))
    for ci, (_, period) in enumerate(parts):
        lengths = [len(t) for t in s.textons_of(ci)]
        assert len(lengths) >= 2
        assert abs(np.median(lengths) - period) <= 0.15 * period
    # Clusters cover the sequence; each texton lies inside its cluster.
    assert s.clusters[0][0] == 0 and s.clusters[-1][1] == len(v) - 1
    assert all(b[0] == a[1] + 1 for a, b in zip(s.clusters, s.clusters[1:]))
    for t in s.textons:
        cs, ce = s.clusters[t.cluster]
        assert cs <= t.start <= t.end <= ce
    assert s.curve.shape == (len(v),) and np.isfinite(s.curve).all()


def test_a_30fps_capture_parses_like_a_10fps_one():
    parts = [(60, 10), (80, 24), (70, 14)]
    v10, starts = cyclic_sequence(parts, noise=0.0)
    # The same motion sampled three times as often: repeat-interpolate each dimension.
    t10 = np.arange(len(v10))
    t30 = np.arange(3 * len(v10)) / 3
    v30 = np.stack([np.interp(t30, t10, v10[:, d]) for d in range(DIM)], axis=1)
    v30 += np.random.default_rng(3).normal(scale=0.003, size=v30.shape)
    s = parse(v30, fps=30)
    found = [c[0] for c in s.clusters]
    assert len(found) == len(starts)
    assert all(abs(a - 3 * b) <= 6 for a, b in zip(found, starts))
    for ci, (_, period) in enumerate(parts):
        lengths = [len(t) for t in s.textons_of(ci)]
        assert abs(np.median(lengths) - 3 * period) <= 0.15 * 3 * period


def test_still_sequence_with_noise_has_one_cluster_and_no_textons():
    rng = np.random.default_rng(0)
    v = 0.05 + rng.normal(scale=0.004, size=(150, DIM))
    for method in ("energy", "paper"):
        s = parse(v, fps=10, params=StructureParams(method=method))
        assert s.clusters == [(0, 149)], method
        assert s.textons == [], method


def test_paper_method_finds_textons_and_a_cluster_change():
    # Long clusters of strong cycles, so the printed procedure gets its two textons.
    v, starts = cyclic_sequence([(100, 12), (100, 20)], noise=0.001, seed=2)
    v[100:] += 0.3  # a clearly different pose distribution in the second cluster
    s = parse(v, fps=10, params=StructureParams(method="paper"))
    assert len(s.clusters) == 2 and abs(s.clusters[1][0] - 100) <= 3
    lengths = [len(t) for t in s.textons_of(0)]
    assert len(lengths) >= 3 and abs(np.median(lengths) - 12) <= 2


def test_json_round_trip():
    v, _ = cyclic_sequence([(60, 10), (60, 20)])
    s = parse(v, fps=10)
    text = json.dumps(s.to_json())
    back = Structure.from_json(text)
    assert back.clusters == s.clusters
    assert [(t.start, t.end, t.cluster) for t in back.textons] == [(t.start, t.end, t.cluster) for t in s.textons]
    np.testing.assert_allclose(back.curve, s.curve)
    assert back.texton_starts == s.texton_starts
    assert StructureParams(**back.params) == StructureParams()


def test_bad_input_is_refused():
    with pytest.raises(ValueError):
        parse(np.zeros((0, 3)), fps=10)
    with pytest.raises(ValueError):
        StructureParams(method="magic")


@pytest.mark.parametrize("method", ["energy", "paper"])
def test_any_sequence_length_parses_up_to_its_last_frame(method):
    # A cluster that runs to the last frame has no atom at u + P beyond it; every cut of a
    # sequence must still parse, with textons inside the sequence.
    vectors, _ = cyclic_sequence([(60, 9), (40, 12)])
    for length in range(75, 101):
        s = parse(vectors[:length], 10, StructureParams(method=method))
        assert s.clusters[-1][1] == length - 1
        assert all(0 <= t.start <= t.end < length for t in s.textons)


def left_right_part(frames, period, theta, seed=0, noise=0.003):
    """A left-right exercise: r and phi columns repeat every half period, theta every period.

    Left and right poses share their r and phi histograms; only the azimuth (theta)
    columns, mirrored, tell the two halves apart.
    """
    rng = np.random.default_rng(seed)
    mean = rng.random(DIM) * 0.06
    a1, a2 = rng.normal(size=(2, DIM)) * 0.02
    p1, p2 = rng.uniform(0, 2 * np.pi, size=(2, DIM))
    t = np.arange(frames)[:, None]
    half = 2 * np.pi * t / (period / 2)
    v = mean + a1 * np.sin(half + p1) + a2 * np.sin(2 * half + p2)
    v[:, theta] = mean[theta] + 2 * a1[theta] * np.sin(2 * np.pi * t / period + p1[theta])
    return v + rng.normal(scale=noise, size=v.shape)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_left_right_cluster_holding_one_period_gets_the_whole_period(seed):
    # 53 frames of a 42-frame left-right cycle between two other exercises (CMU 13_29's
    # toe touch cut short by its boundary): 2L = 42 is the lag profile's last lag, where a
    # valley has no far side. The theta columns still say that 21 is only half a period.
    theta = slice(30, 40)
    before, _ = cyclic_sequence([(80, 12)], seed=10 + seed)
    after, _ = cyclic_sequence([(80, 16)], seed=20 + seed)
    v = np.concatenate([before, left_right_part(53, 42, theta, seed), after])
    s = parse(v, fps=10, theta=theta)
    assert [c[0] for c in s.clusters] == [0, 80, 133]
    lengths = [len(t) for t in s.textons_of(1)]
    assert len(lengths) == 1 and abs(lengths[0] - 42) <= 0.15 * 42, lengths
    # Without the theta columns the half period is all there is to see.
    assert [len(t) for t in parse(v, fps=10).textons_of(1)][0] == 21


@pytest.mark.parametrize("min_cluster, novelty_window", [(6.5, 3.0), (8.0, 3.0), (2.5, 1.0)])
def test_a_long_shortest_cluster_still_finds_boundaries(min_cluster, novelty_window):
    # The novelty blocks are novelty_window long; asking each to hold half of min_cluster
    # must not switch boundary detection off when that is more than a block holds.
    vectors, starts = cyclic_sequence([(150, 12), (150, 9), (150, 15)])
    s = parse(vectors, 10, StructureParams(min_cluster=min_cluster, novelty_window=novelty_window))
    assert len(s.clusters) > 1


@pytest.mark.parametrize("slow, quick, change", [(45, 7, 110), (42, 10, 105)])
def test_a_slow_to_quick_boundary_lies_where_the_motion_changes(slow, quick, change):
    # Three slow cycles, then quick ones about other poses. The novelty's 4 s blocks cut the
    # slow cycles part-way, and its peak splits in two; the earlier-twin rule, as when the earlier-twin rule
    # came in, took the earlier top, 1.4 s early. Placed between whole
    # periods of each side (refine_reach), the boundary is the frame where the motion changes.
    # With the rule left out (the default) the higher top is right already.
    rng = np.random.default_rng(1)

    def cycles(n, period, centre, amp):
        phase = 2 * np.pi * np.arange(n) / period
        return np.stack([centre[0] + amp * np.sin(phase), centre[1] + amp * np.cos(phase),
                         centre[2] + 0.5 * amp * np.sin(2 * phase)], axis=1)

    v = np.vstack([cycles(change, slow, (0, 0, 0), 1.0), cycles(200 - change, quick, (0.8, 0.3, 0.2), 0.6)])
    v = v * 0.2 + rng.normal(0, 0.005, v.shape)
    # Three columns, not a histogram's hundreds: whitened, every axis would be kept and scaled
    # alike (tvmedit.engine.parse.boundaries.whiten), so the novelty compares the rows as they are here.
    raw = dict(novelty_components=0)   # threshold 0.05 then
    peaks = parse(v, 10, StructureParams(refine_reach=0, twin_peak=0.9, **raw)).clusters
    settled = parse(v, 10, StructureParams(twin_peak=0.9, **raw))
    assert len(peaks) == 2 and abs(peaks[1][0] - change) > 10, peaks
    assert len(settled.clusters) == 2 and abs(settled.clusters[1][0] - change) <= 1, settled.clusters
    assert [len(t) for t in settled.textons_of(1)][:3] == [quick] * 3
    default = parse(v, 10, StructureParams(refine_reach=0, **raw)).clusters   # the peak itself
    assert len(default) == 2 and abs(default[1][0] - change) <= 1, default


def _left_right(half, frames=120, bins=72):
    # Azimuth histograms of a left-then-right motion: frame u + half is frame u's mirror image.
    j = np.arange(bins)

    def bump(centre, width=2.0):
        d = (j - centre + bins / 2) % bins - bins / 2
        return np.exp(-0.5 * (d / width) ** 2)

    rows = []
    for u in range(frames):
        side = 1 if (u // half) % 2 == 0 else -1
        phase = (u % half) / half   # the limb travels out within each half
        rows.append(bump(side * (6 + 6 * phase)) + 0.7 * bump(side * 16) + bump(36))
    return np.array(rows)


def test_a_turning_person_reads_as_facing_one_way_given_the_rate():
    from tvmedit.engine.parse.heading import heading_track, turned
    from tvmedit.engine.parse.structure import parser_view
    rng = np.random.default_rng(0)
    still = np.hstack([rng.random((300, 4)), _left_right(half=8, frames=300)])
    theta = slice(4, 76)
    turning = turned(still, theta, np.radians(6.0) * np.arange(300) / 10)   # 6 degrees a second
    p = StructureParams()
    a, b = parser_view(still, p, theta, 10), parser_view(turning, p, theta, 10)
    # 156 degrees between the first and last windows as it stands; turned back, what turn is
    # left is under half a bin (2.5 degrees) a second, here 10 degrees in all
    raw, left = (np.degrees(np.ptp(heading_track(rows, theta, 10))) for rows in (turning, b))
    assert raw > 100 and left <= 0.25 * raw, (raw, left)
    assert np.array_equal(a, parser_view(still, StructureParams(heading_window=0), theta, 10))   # no turn: as is
    with pytest.raises(ValueError, match="frame rate"):
        parser_view(still, p, theta)


def test_a_weak_split_is_undone_only_where_one_side_does_not_repeat():
    # tvmedit.engine.parse.joins.merge_weak (the weak-split rule and the weak-split rule): a weak boundary
    # between two clusters of at most one texton each goes when one side shows no period, and
    # stays between two short stretches that both repeat (two alike exercises), as it stays
    # wherever the boundary is not weak.
    from tvmedit.engine.parse.periods import PeriodReader
    from tvmedit.engine.parse.joins import merge_weak
    v, _ = cyclic_sequence([(30, 12), (30, 12)])
    period = PeriodReader(v, 10, atom_window(10), StructureParams())
    one = lambda cs, ce, P: 1  # noqa: E731  (one whole texton in each)
    clusters = [(0, 29), (30, 59)]
    kept, _ = merge_weak(period, clusters, one, [1.0, 0.1], periods=[12, 12])
    joined, _ = merge_weak(period, clusters, one, [1.0, 0.1], periods=[None, 12])
    strong, _ = merge_weak(period, clusters, one, [1.0, 0.5], periods=[None, 12])
    assert kept == clusters and strong == clusters
    assert joined == [(0, 59)]


def test_a_transition_joins_what_it_leads_into_an_end_piece_stays():
    # tvmedit.engine.parse.joins.absorb_transitions (both a parser rule and a parser rule of the energy parser), on stretches
    # that show no period (one-off movements): a short one joins the long one after it (it
    # leads into it); a short one at the take's end, after a long one, leads into nothing and
    # stays (the real capture scvv-card lost its only change when it joined the one before).
    from tvmedit.engine.parse.periods import PeriodReader
    from tvmedit.engine.parse.joins import absorb_transitions
    v = np.random.default_rng(0).random((200, 3))
    period = PeriodReader(v, 10, atom_window(10), StructureParams(min_periodicity=1.0))   # no period anywhere
    none = lambda cs, ce, P: 0  # noqa: E731
    into, periods = absorb_transitions(period, [(0, 79), (80, 99), (100, 199)], none)
    assert into == [(0, 79), (80, 199)] and periods == [None, None]
    end, _ = absorb_transitions(period, [(0, 179), (180, 199)], none)
    assert end == [(0, 179), (180, 199)]


def test_a_weak_peak_splits_a_cluster_only_where_the_period_changes():
    # tvmedit.engine.parse.rhythm (the rhythm rule): a novelty peak under the threshold but at
    # least 3/4 of it is a boundary where the longer of the periods before and after it is
    # 1.5 times the shorter or more; not under 1.5, not at a whole multiple (the period
    # step's known failure), not for a peak under 3/4 of the threshold, not for a turn, not
    # within min_cluster of the cluster's ends, and not with the step off.
    from tvmedit.engine.parse.periods import PeriodReader, cluster_period
    from tvmedit.engine.parse.rhythm import FLOOR, rhythm_splits
    p, w, t = StructureParams(), atom_window(10), np.arange(120)
    weak = 0.8 * p.novelty_threshold

    def take(second):
        # 6 s cycling at a 1 s period, then 6 s at ``second`` frames (10 fps)
        phase = np.where(t < 60, 2 * np.pi * t / 10, 2 * np.pi * (t - 60) / second)
        return np.stack([np.sin(phase), np.cos(phase), 0.3 * np.sin(2 * phase)], axis=1)

    def split(second, height=weak, at=60, params=p, turn_free=None, step=1):
        n = np.zeros(120 // step)
        n[at // step] = height
        return rhythm_splits(PeriodReader(take(second), 10, w, params), [(0, 119)], n, step, turn_free)

    for second in (13, 15, 20):   # what the period step reads on either side is what is compared
        assert [cluster_period(take(second), a, b, 10, w, p)[0] for a, b in ((0, 59), (60, 119))] == [10, second]
    assert split(15) == [(0, 59), (60, 119)]                  # 1.5: a boundary
    assert split(15, step=2) == [(0, 59), (60, 119)]          # the curve at 5 fps, frames at 10
    assert split(13) == [(0, 119)]                            # 1.3: the same exercise's tempo
    assert split(20) == [(0, 119)]                            # 2.0: a period read at two repetitions
    assert split(15, height=0.95 * FLOOR * p.novelty_threshold) == [(0, 119)]
    assert split(15, height=p.novelty_threshold) == [(0, 119)]   # the novelty's boundaries's, not this step's
    assert split(15, at=110) == [(0, 119)]                    # 1 s from the end: under min_cluster
    assert split(15, turn_free=np.zeros(120)) == [(0, 119)]   # the heading-free novelty stays flat: a turn
    assert split(15, turn_free=np.full(120, weak)) == [(0, 59), (60, 119)]
    assert split(15, params=StructureParams(rhythm_ratio=0)) == [(0, 119)]
    with pytest.raises(ValueError):
        StructureParams(rhythm_ratio=0.5)


def test_a_side_too_short_to_show_the_other_sides_period_splits_nothing():
    # tvmedit.engine.parse.rhythm, the short-side rule: the period step's lag profile reaches 0.8 of its frames
    # (tvmedit.engine.parse.periods.longest_lag), so a side that read the shorter period but is shorter
    # than the other side's period over 0.8 is taken as no evidence that the tempo changed
    # (CMU 13_29 turning: 2.4 s of toe touches read at 1.3 s beside 2.9 s, and the split was
    # kept while the true boundary was merged away). The cost, asserted too: a true change of
    # tempo that near a cluster's end is not split here.
    from tvmedit.engine.parse.periods import PeriodReader, cluster_period, longest_lag
    from tvmedit.engine.parse.rhythm import rhythm_splits
    p, w, t = StructureParams(), atom_window(10), np.arange(120)

    def split(at, second=25):
        # ``at`` frames cycling at 1 s, then the rest at ``second`` frames (10 fps), a weak
        # peak between
        phase = np.where(t < at, 2 * np.pi * t / 10, 2 * np.pi * (t - at) / second)
        v = np.stack([np.sin(phase), np.cos(phase), 0.3 * np.sin(2 * phase)], axis=1)
        assert [cluster_period(v, a, b, 10, w, p)[0] for a, b in ((0, at - 1), (at, 119))] == [10, second]
        n = np.zeros(120)
        n[at] = 0.8 * p.novelty_threshold
        return rhythm_splits(PeriodReader(v, 10, w, p), [(0, 119)], n, 1)

    assert longest_lag(30) < 25 <= longest_lag(40)
    assert split(30) == [(0, 119)]                  # 3 s could not have shown 2.5 s
    assert split(40) == [(0, 39), (40, 119)]        # 4 s could: the tempo changed
    assert longest_lag(35) == 28
    assert split(35, second=28) == [(0, 34), (35, 119)]   # 3.5 s reaches 2.8 s, just
