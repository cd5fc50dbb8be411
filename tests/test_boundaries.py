"""The novelty's boundaries (tvmedit.engine.parse.boundaries) on novelty curves and rows built by hand.

Each case is a decision a user would see as a boundary placed or not: a turn taken for a
new exercise, a turn's shoulder or an earlier twin peak slipping through the veto, or the
same motion judged differently because the capture ran at another frame rate.
"""

import numpy as np
import pytest

from tvmedit.engine.parse.boundaries import novelty_clusters, novelty_rows
from tvmedit.engine.parse.structure import StructureParams

FPS = 10.0
T = 200   # 20 s at 10 fps: one novelty row a frame


def bump(centre, height, width=2.0):
    return height * np.exp(-0.5 * ((np.arange(T) - centre) / width) ** 2)


def starts(n, turn_free=None, **params):
    p = StructureParams(**{"novelty_threshold": 0.05, "novelty_components": 0, **params})   # the curves' scale
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
    # boundary is the change, not its twin (which would be taken were it no turn). The twin
    # rule is left out by default (twin_peak 1): there the higher peak is the boundary, turn
    # or no turn.
    n = np.maximum(bump(100, 0.1, 1.0), bump(108, 0.105, 1.0))
    turn_free = np.where(np.arange(T) < 106, 0.01, 0.1)
    assert starts(n, turn_free, twin_peak=0.9) == [108]
    assert starts(n, twin_peak=0.9) == [100]
    assert starts(n) == [108]


def test_a_change_on_a_turns_slope_is_found_by_the_heading_free_novelty():
    # A turn peaking at 6 s, far higher and broader than the change of exercise 2.4 s later,
    # which is no local maximum of the novelty; the heading-free novelty hardly rises at the
    # turn and peaks at the change.
    n = bump(60, 0.3, 10.0)
    assert not any(n[83:86] >= np.maximum(n[82:85], n[84:87]))   # no peak of n at the change
    turn_free = np.maximum(bump(60, 0.05), bump(84, 0.15))
    assert starts(n, turn_free) == [84]
    assert starts(n, turn_free, turn_ratio=0) == [60]              # no veto: the turn is the boundary
    # Only near a turn (within novelty_window) does the heading-free novelty find boundaries.
    assert starts(n, turn_free, novelty_window=2.0) == []
    # Not within min_cluster of the turn (the turn's own heading-free bump), nor at the
    # take's end, where a block is too short to trust.
    assert starts(n, np.maximum(bump(60, 0.05), bump(75, 0.15))) == []
    late = bump(165, 0.3, 10.0)
    assert starts(late, np.maximum(bump(165, 0.05), bump(192, 0.15))) == []


def test_the_shoulder_of_a_strong_peak_is_not_a_second_boundary():
    # A strong change at 10 s whose novelty falls away slowly, with a small bump on its
    # flank 2 s later (pauses between repetitions make such bumps): min_cluster apart, over
    # the threshold, but it rises only a little above the flank it stands on.
    n = np.maximum(bump(100, 0.25, 12.0), bump(120, 0.08, 1.5))
    assert starts(n) == [100]
    assert starts(n, shoulder=0) == [100, 120]                 # shoulder 0: every peak counts
    # Two changes with the novelty falling between them are both boundaries.
    apart = np.maximum(bump(100, 0.25, 2.0), bump(125, 0.1, 2.0))
    assert starts(apart) == [100, 125]


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


def test_exercises_differing_where_little_changes_are_told_apart():
    # Whitened (the default), the small change of pose counts as much as the wide swing and
    # the boundary is found within 1 s; on the rows as they are, its novelty stays far under
    # the threshold, inside the noise.
    from tvmedit.engine.parse.structure import parse
    v, change = alike_exercises()
    found = [cs for cs, _ in parse(v, FPS).clusters][1:]
    assert len(found) == 1 and abs(found[0] - change) <= FPS, found
    assert [cs for cs, _ in parse(v, FPS, StructureParams(novelty_components=0)).clusters] == [0]


def test_leading_axes_agree_with_a_full_eigensolver():
    # Subspace iteration (tvmedit.engine.parse.boundaries._leading_eigen) stands in for LAPACK's
    # threaded solvers; on a decaying spectrum like a take's it must find the same top axes.
    from tvmedit.engine.parse.boundaries import _leading_eigen
    rng = np.random.default_rng(3)
    basis, _ = np.linalg.qr(rng.normal(size=(80, 80)))
    m = basis @ np.diag(0.8 ** np.arange(80)) @ basis.T
    values, vectors = _leading_eigen(m, 10)
    exact_values, exact_vectors = np.linalg.eigh(m)
    assert np.allclose(values, exact_values[::-1][:10], rtol=1e-6)
    assert np.allclose(np.abs(np.sum(vectors * exact_vectors[:, ::-1][:, :10], axis=0)), 1.0, atol=1e-6)


def test_whitening_takes_few_rows_still_rows_and_bad_rows():
    from tvmedit.engine.parse.boundaries import whiten
    rng = np.random.default_rng(0)
    assert whiten(rng.normal(size=(3, 50)), 10).shape == (3, 2)          # at most rows - 1 axes
    assert not whiten(np.ones((20, 50)), 10).any()                       # no change: zeros
    bad = rng.normal(size=(20, 50))
    bad[4, 7] = np.nan
    assert np.array_equal(whiten(bad, 10), bad, equal_nan=True)          # left as it is
    rows = rng.normal(size=(200, 40)) * np.linspace(3, 0.01, 40)
    out = whiten(rows, 10)
    # Each kept axis scaled to about the same spread: variance / (variance + mean variance).
    assert out.shape == (200, 10) and np.all(out.var(axis=0) < 1) and out.var(axis=0).min() > 0.1

