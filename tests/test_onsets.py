"""Placing a boundary (tvmedit.engine.parse.onsets): between whole periods, on one view or both,
back to the onset of a slow change, and the test of frames only turned, on rows built by hand
at 10 fps."""

import numpy as np
import pytest

from tvmedit.engine.features import distance_matrix
from tvmedit.engine.parse.onsets import energy_distance, onset, settle, turned_away

t = np.arange(120)
# Two poses, the change at frame 64, a little wobble so no two frames are alike.
SHARP = np.where((t < 64)[:, None], [[0.0, 1.0]], [[1.0, 0.0]]) * (1 + 0.1 * np.sin(t))[:, None]
# The same change as a ramp over 2.4 s, whose energy distance tops at frame 71.
RAMP = np.clip((t - 58) / 24.0, 0, 1)[:, None]
SLOW = (1 - RAMP) * [[0.0, 1.0]] + RAMP * [[1.0, 0.0]]
TWO = [(0, 59), (60, 119)]
NONE = [None, None]


def test_energy_distance_of_two_blocks_by_hand():
    two_poses = distance_matrix(np.r_[np.zeros((3, 1)), np.ones((2, 1))])
    assert energy_distance(two_poses, 3) == pytest.approx(2.0)
    still = distance_matrix(np.zeros((5, 1)))
    assert energy_distance(still, 2) == 0.0
    assert energy_distance(still, 1) == -np.inf            # a block of one frame says nothing


def test_a_boundary_moves_to_where_the_poses_change():
    assert settle(SHARP, TWO, NONE, 10) == [0, 64]
    assert settle(SHARP, TWO, NONE, 10, reach=0) == [0, 60]
    assert settle(SHARP, TWO, NONE, 10, reach=0.3) == [0, 63]    # no farther than its reach


def test_a_boundary_never_moves_nearer_a_close_neighbour():
    assert settle(SHARP, [(0, 59), (60, 69), (70, 119)], [None] * 3, 10) == [0, 60, 70]


def test_both_views_place_a_boundary_at_the_sharper_top():
    assert settle(SLOW, TWO, NONE, 10) == [0, 71]
    assert settle(SLOW, TWO, NONE, 10, other=SHARP) == [0, 64]
    assert settle(SHARP, TWO, NONE, 10, other=SLOW) == [0, 64]
    assert settle(SHARP, TWO, NONE, 10, other=SLOW, other_weight=0) == [0, 64]   # one view only


def test_a_boundary_named_in_use_other_reads_the_other_view_alone():
    assert settle(SHARP, TWO, NONE, 10, other=SLOW, use_other={1}) == [0, 71]


def cycling_then_change():
    """Eight-frame cycles, a slow change from frame 40, a new pose from frame 50."""
    cyc = np.stack([np.sin(2 * np.pi * t[:80] / 8), np.cos(2 * np.pi * t[:80] / 8)], axis=1)
    v = np.where((t[:80] < 50)[:, None], cyc, 3.0)
    v[40:50] = cyc[40:50] + np.linspace(0, 3, 10)[:, None]
    return v, cyc


def test_the_onset_is_where_the_motion_left_the_old_poses():
    v, _ = cycling_then_change()
    assert onset(v, 0, 50, 10) == 41
    assert onset(v, 0, 50, 10, reach=0.5) == 45                    # looked for within reach only


def test_no_onset_without_a_change_or_without_enough_old_cluster():
    v, cyc = cycling_then_change()
    assert onset(cyc, 0, 50, 10) == 50                            # still the old cycles: the peak
    assert onset(v, 40, 50, 10) == 50                             # no old poses to compare with


def test_frames_turned_away_are_told_from_a_new_pose():
    # An azimuth histogram of 72 bins whose bump swings a little every 1.2 s; from frame 100
    # the person turns 20 bins (100 degrees) in 1 s.
    j = np.arange(72)
    pose = lambda c: np.exp(-0.5 * (((j - c + 36) % 72 - 36) / 3.0) ** 2)  # noqa: E731
    old = np.array([pose(10 + 4 * np.sin(2 * np.pi * k / 12)) for k in t])
    angle = np.clip(t - 100, 0, 10) * 2
    rows = np.array([np.roll(r, int(a)) for r, a in zip(old, angle)])
    assert turned_away(rows, slice(0, 72), 0, 100, 119, 10)
    new = rows.copy()
    new[100:] = [pose(50)] * 20
    assert not turned_away(new, slice(0, 72), 0, 100, 119, 10)
    assert not turned_away(old, slice(0, 72), 0, 100, 119, 10)   # no turn at all
