"""Motion structure parsing (eq. (5)-(8)) on feature vectors built by hand.

The vectors stand in for histogram rows: a sum of sinusoids per dimension, with the period
and the mean pose changing at known frames, scaled like normalised histograms (distances of
a few tenths).
"""

import json

import numpy as np
import pytest

from tvmedit.engine.parse.structure import Structure, StructureParams, atom_window, parse

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


def test_an_empty_sequence_or_a_rate_of_zero_is_refused():
    with pytest.raises(ValueError, match="shape"):
        parse(np.zeros((0, 3)), fps=10)
    with pytest.raises(ValueError, match="frame rate"):
        parse(np.zeros((5, 3)), fps=0)
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
    # 53 frames of a 42-frame left-right cycle between two other exercises (a toe touch cut
    # short by its boundaries): 2L = 42 is the lag profile's last lag, where a valley has no
    # far side. The theta columns still say that 21 is only half a period.
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
    # slow cycles part-way, and its peak splits in two; with ``twin_peak`` 0.9 the earlier top
    # is taken, early. Placed between whole periods of each side (refine_reach), the boundary
    # is the frame where the motion changes. With the twin rule left out (the default) the
    # higher top is right already.
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
    settled = parse(v, 10, StructureParams(twin_peak=0.9, **raw))
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
    # Over 100 degrees between the first and last windows as it stands; turned back, what
    # turn is left is at most a quarter of that.
    raw, left = (np.degrees(np.ptp(heading_track(rows, theta, 10))) for rows in (turning, b))
    assert raw > 100 and left <= 0.25 * raw, (raw, left)
    assert np.array_equal(a, parser_view(still, StructureParams(heading_window=0), theta, 10))   # no turn: as is
    with pytest.raises(ValueError, match="frame rate"):
        parser_view(still, p, theta)


def test_a_weak_split_is_undone_only_where_one_side_does_not_repeat():
    # tvmedit.engine.parse.joins.merge_weak: a weak boundary between two clusters of at most one
    # texton each goes when one side shows no period, and stays between two short stretches
    # that both repeat (two alike exercises), as it stays wherever the boundary is not weak.
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
    # tvmedit.engine.parse.joins.absorb_transitions, on stretches that show no period (one-off
    # movements): a short one joins the long one after it (it leads into it); a short one at
    # the take's end, after a long one, leads into nothing and stays, so a take whose only
    # change is near its end keeps it.
    from tvmedit.engine.parse.periods import PeriodReader
    from tvmedit.engine.parse.joins import absorb_transitions
    v = np.random.default_rng(0).random((200, 3))
    period = PeriodReader(v, 10, atom_window(10), StructureParams(min_periodicity=1.0))   # no period anywhere
    none = lambda cs, ce, P: 0  # noqa: E731
    into, periods = absorb_transitions(period, [(0, 79), (80, 99), (100, 199)], none)
    assert into == [(0, 79), (80, 199)] and periods == [None, None]
    end, _ = absorb_transitions(period, [(0, 179), (180, 199)], none)
    assert end == [(0, 179), (180, 199)]
