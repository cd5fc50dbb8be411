"""The heading followed (tvmedit.engine.parse.heading): turns found and undone, and where nothing is followed."""

import numpy as np
import pytest

from tvmedit.engine.parse.heading import heading_track, turned

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
