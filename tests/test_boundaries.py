"""Step 1 of the energy parser (engine.boundaries) on novelty curves and rows built by hand.

Each case is a decision a user would see as a boundary placed or not: a turn taken for a
new exercise, a turn's shoulder or an earlier twin peak slipping through the veto, or the
same motion judged differently because the capture ran at another frame rate.
"""

import numpy as np
import pytest

from engine.boundaries import novelty_clusters, novelty_rows
from engine.structure import StructureParams

FPS = 10.0
T = 200   # 20 s at 10 fps: one novelty row a frame


def bump(centre, height, width=2.0):
    return height * np.exp(-0.5 * ((np.arange(T) - centre) / width) ** 2)


def starts(n, turn_free=None, **params):
    p = StructureParams(**{"novelty_threshold": 0.05, **params})   # the curves' scale
    return [cs for cs, _ in novelty_clusters(np.zeros((T, 3)), FPS, p, n, 1, turn_free)][1:]


def test_a_peak_whose_heading_free_novelty_stays_low_is_a_turn():
    n = bump(100, 0.2)
    assert starts(n) == [100]                                  # no veto information: a boundary
    assert starts(n, bump(100, 0.05)) == []                    # 0.05 < 0.4 x 0.2: a turn
    assert starts(n, bump(100, 0.1)) == [100]                  # the motion changed too
    assert starts(n, bump(100, 0.05), turn_ratio=0.2) == [100]  # 0.05 >= 0.2 x 0.2
    assert starts(n, bump(100, 0.05), turn_ratio=0) == [100]   # veto off
    # The heading-free novelty is looked for within 0.5 s of the peak, no further.
    assert starts(n, bump(104, 0.2, width=0.3)) == [100]
    assert starts(n, bump(107, 0.2, width=0.3)) == []


def test_a_turn_keeps_its_lower_shoulder_from_becoming_a_boundary():
    # A turn peaking at 10 s with a lower local maximum 0.8 s later; the heading-free novelty
    # (0.03) is under 0.4 of the turn's peak but not of the shoulder's (0.07).
    n = np.maximum(bump(100, 0.2), bump(108, 0.07))
    turn_free = np.full(T, 0.03)
    assert starts(n, turn_free) == []


def test_an_earlier_twin_peak_that_is_a_turn_is_not_taken_for_the_boundary():
    # A turn at 10 s, then 0.8 s later a slightly higher peak where the motion changes: the
    # boundary is the change, not its twin (which would be taken were it no turn).
    n = np.maximum(bump(100, 0.1, 1.0), bump(108, 0.105, 1.0))
    turn_free = np.where(np.arange(T) < 106, 0.01, 0.1)
    assert starts(n, turn_free) == [108]
    assert starts(n) == [100]


def circling(fps, seconds=12.0):
    # Feature rows of a motion that goes round the same poses every 3 s (slow enough that a
    # row's change over 0.1-0.15 s is nearly proportional to the time it spans).
    t = np.arange(int(seconds * fps)) / fps
    a = 2 * np.pi * t / 3.0
    return np.stack([np.cos(a), np.sin(a), 0.5 * np.cos(2 * a), 0.5 * np.sin(2 * a)], axis=1) * 0.1 + 0.3


@pytest.mark.parametrize("fps", [10.0, 15.0, 20.0, 25.0, 30.0])
def test_pace_is_a_change_over_a_tenth_of_a_second_whatever_the_frame_rate(fps):
    # The same motion captured at another rate must weigh its pace alike, or a 15 fps take
    # (reduced to 7.5 rows a second) would count pace a third more than a 10 fps one.
    raw = StructureParams(novelty_components=0)   # the rows before whitening
    rows, step = novelty_rows(circling(fps), fps, raw)
    reference, _ = novelty_rows(circling(10.0), 10.0, raw)
    pace, expected = rows[2:-2, 4:].mean(), reference[2:-2, 4:].mean()
    assert pace == pytest.approx(expected, rel=0.05), (fps, step)
    assert novelty_rows(circling(fps), fps, StructureParams(novelty_pace=0, novelty_components=0))[0].shape[1] == 4


def alike_exercises(seconds=24.0, fps=10.0, seed=0):
    # Two exercises of the same swing (columns 0-1) that differ only in a small, steady change
    # of pose (columns 2-5, 0.04) halfway, among 200 columns of noise: a leg held otherwise
    # while the arms do the same.
    rng = np.random.default_rng(seed)
    t = np.arange(int(seconds * fps)) / fps
    v = 0.3 + rng.normal(0.0, 0.006, (len(t), 200))
    v[:, 0] += 0.1 * np.sin(2 * np.pi * t / 1.5)
    v[:, 1] += 0.1 * np.cos(2 * np.pi * t / 1.5)
    v[t >= seconds / 2, 2:6] += 0.04
    return v, int(seconds / 2 * fps)


def test_exercises_that_differ_in_a_direction_of_little_change_are_told_apart():
    # Whitened (the default), the small change of pose counts as much as the wide swing and
    # the boundary is found within 1 s; on the rows as they are, its novelty stays far under
    # the threshold, inside the noise.
    from engine.structure import parse
    v, change = alike_exercises()
    found = [cs for cs, _ in parse(v, FPS).clusters][1:]
    assert len(found) == 1 and abs(found[0] - change) <= FPS, found
    assert [cs for cs, _ in parse(v, FPS, StructureParams(novelty_components=0, novelty_threshold=0.05)).clusters] == [0]
