"""Which way a person faces (tvmedit.engine.parse.heading): turns followed and undone, where
nothing is followed, and the azimuth histograms smoothed or made turn-free for the parser."""

import numpy as np
import pytest

from conftest import needs_mocap
from tvmedit.engine.parse.heading import azimuth_smoothed, azimuth_spectrum, heading_track, turned

BINS = 72
THETA = slice(3, 3 + BINS)


def _take(seconds=30.0, fps=10.0, turn=0.0, seed=0):
    # Rows of 3 other columns and a 72-bin azimuth histogram of a motion that repeats every
    # 1.2 s, turning ``turn`` degrees a second.
    rng = np.random.default_rng(seed)
    t = np.arange(int(seconds * fps)) / fps
    j = np.arange(BINS)

    def bump(centre, width):
        d = (j - centre + BINS / 2) % BINS - BINS / 2
        return np.exp(-0.5 * (d / width) ** 2)

    theta = np.array([bump(12 + 3 * np.sin(2 * np.pi * x / 1.2), 3.0) + 0.5 * bump(40, 6.0) for x in t])
    rows = np.hstack([rng.random((len(t), 3)), theta])
    return turned(rows, THETA, np.radians(turn) * t)


@pytest.mark.parametrize("fps", [10.0, 25.0, 29.97])
def test_a_steady_turn_is_followed_at_any_frame_rate(fps):
    rows = _take(fps=fps, turn=10.0)
    h = np.degrees(heading_track(rows, THETA, fps))
    t = np.arange(len(rows)) / fps
    inner = (t > 3) & (t < 27)
    slope = np.polyfit(t[inner], h[inner], 1)[0]
    assert 7.5 <= slope <= 12.5, slope          # whole bins a second: 10 degrees within half a bin
    left = np.degrees(heading_track(turned(rows, THETA, -np.radians(h)), THETA, fps))
    assert np.ptp(left) <= 10.0                  # turned back, it faces one way


def test_no_turn_is_left_exactly_as_it_is():
    rows = _take(turn=0.0)
    assert not heading_track(rows, THETA, 10.0).any()


@pytest.mark.parametrize("rows, theta", [
    (_take(seconds=4.5), THETA),                 # shorter than a window and a hop
    (_take(turn=10.0)[:, :40], slice(3, 40)),     # 37 bins of ~10 degrees: followed (below)
    (_take(turn=10.0)[:, :23], slice(3, 23)),     # 20 bins of 18 degrees: too coarse
    (_take(turn=10.0), slice(3, 3)),              # no azimuth columns
])
def test_where_there_is_nothing_to_follow_the_heading_is_zero(rows, theta):
    h = heading_track(rows, theta, 10.0)
    assert h.shape == (len(rows),)
    n = theta.stop - theta.start
    assert h.any() == (n == 37)


def test_a_frame_that_is_not_finite_does_not_stop_the_heading():
    rows = _take(turn=10.0)
    rows[100] = np.nan
    h = np.degrees(heading_track(rows, THETA, 10.0))
    assert np.isfinite(h).all() and h[250] - h[150] > 70    # 100 degrees over those 10 s


def test_a_turned_body_has_the_same_azimuth_spectrum():
    rows = _take(seconds=2.0)
    spun = turned(rows, THETA, np.radians(35.0))
    a, b = azimuth_spectrum(rows, THETA), azimuth_spectrum(spun, THETA)
    assert a.shape == (len(rows), 3 + BINS // 2 + 1)
    assert np.allclose(a, azimuth_spectrum(turned(rows, THETA, 2 * np.pi * 7 / BINS), THETA))   # whole bins
    assert np.abs(a - b).max() < 0.1 * np.abs(a).max()                                      # a fraction of one
    # never farther apart than the rows themselves (Parseval)
    assert np.linalg.norm(a[0] - a[10]) <= np.linalg.norm(rows[0] - rows[10]) + 1e-12


def test_smoothed_azimuth_histograms_keep_each_row_total_and_other_columns():
    rows = _take(seconds=2.0)
    smooth = azimuth_smoothed(rows, THETA)
    assert np.array_equal(smooth[:, :3], rows[:, :3])
    assert np.allclose(smooth[:, THETA].sum(axis=1), rows[:, THETA].sum(axis=1))


def _scored(take, params=None):
    from tvmedit.engine.lab.evaluate import score
    from tvmedit.engine.parse.structure import parse
    structure = parse(take.vectors, take.fps, params, theta=take.theta, centred=take.centred)
    return structure, score(structure, take.truth, take.fps)


@pytest.mark.parser
@pytest.mark.slow
def test_a_take_in_the_body_frame_is_parsed_on_smoothed_azimuth_histograms(devsuite):
    # The suite's "wander" take (the synthetic actor wandering up to 0.8 m), with features in
    # the body's own frame as build computes them: its front lies a fraction of a 5 degree
    # azimuth bin off the bins' edges. Read smoothed, every boundary is found within 1 s and
    # none is false.
    assert devsuite.FRAME == "body"
    take = devsuite.take("synth-drift", "wander")
    structure, result = _scored(take)
    assert (result.precision, result.recall) == (1.0, 1.0), structure.clusters


@pytest.mark.parser
@pytest.mark.slow
def test_a_real_take_done_turning_reads_as_if_facing_one_way(devsuite):
    # CMU 13_29 turning 6 degrees a second (its meshes rotated about where the person stands,
    # then taken in their own body frame). Turned back by the tracked heading
    # (StructureParams.heading_window), the turn is no change of pose: on the novelty's peaks
    # with the shoulder rule off there are as many boundaries as changes and every texton is
    # right; with the defaults every change is found and none is false.
    from tvmedit.engine.parse.structure import StructureParams
    needs_mocap()
    take = devsuite.cmu_take("13_29-turn")
    peaks = StructureParams(heading_window=4.0, shoulder=0.0, partition=0.0, onset_reach=2.0)
    _, followed = _scored(take, peaks)
    changes = len(take.truth["segments"]) - 1
    assert followed.detected == changes and followed.texton_accuracy == 1.0, (followed.matches, followed.texton_rows)
    assert (followed.precision, followed.recall) == (1.0, 1.0), followed.matches
    _, default = _scored(take)
    assert (default.precision, default.recall) == (1.0, 1.0), default.matches
