"""Motion atoms (tvmedit.engine.parse.atoms): the atom window and distance of eq. (5), the lag
profile, the two-block novelty and block means, on rows small enough to check by hand."""

import numpy as np
import pytest

from test_structure import cyclic_sequence
from tvmedit.engine.parse.atoms import (atom_distance, atom_distances_to, atom_window, atoms_along_lag,
                                        block_means, lag_profile, novelty)
from tvmedit.engine.parse.params import StructureParams


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


def test_atoms_along_a_lag_are_the_atom_distances_one_by_one():
    v = np.random.default_rng(0).random((30, 4))
    w = atom_window(10)
    along = atoms_along_lag(v, 7, w)
    assert len(along) == 30 - 7
    np.testing.assert_allclose(along, [atom_distance(v, u, u + 7, w) for u in range(23)])


def test_lag_profile_finds_the_period():
    v, _ = cyclic_sequence([(120, 17)])
    lags = np.arange(5, 30)  # up to 2P the multiple 34 would tie with 17
    assert lags[np.argmin(lag_profile(v, lags, atom_window(10)))] == 17


def test_novelty_peaks_where_the_poses_change_and_is_zero_inside():
    v = np.r_[np.zeros((30, 2)), np.ones((30, 2))]
    n = novelty(v, 10)
    assert int(np.argmax(n)) == 30
    assert n[:20].max() == pytest.approx(0.0) and n[41:].max() == pytest.approx(0.0)
    # Blocks shorter than min_block at the ends are not judged.
    assert not novelty(v, 10, min_block=10)[:10].any()


def test_block_means_pad_the_last_block_with_the_last_frame():
    assert block_means(np.arange(6.0)[:, None], 3).ravel().tolist() == [1.0, 4.0]
    assert block_means(np.arange(4.0)[:, None], 3).ravel().tolist() == [1.0, 3.0]
    v = np.random.default_rng(1).random((5, 2))
    assert np.array_equal(block_means(v, 1), v)
