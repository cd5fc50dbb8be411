"""Rhythm splits (tvmedit.engine.parse.rhythm): a weak novelty peak is a boundary where the
period changes, on takes of two tempos built by hand (10 fps)."""

import numpy as np
import pytest

from tvmedit.engine.parse.atoms import atom_window
from tvmedit.engine.parse.params import StructureParams
from tvmedit.engine.parse.periods import PeriodReader, cluster_period, longest_lag
from tvmedit.engine.parse.rhythm import FLOOR, rhythm_splits

P, W, T = StructureParams(), atom_window(10), np.arange(120)
WEAK = 0.8 * P.novelty_threshold


def two_tempos(at, second):
    """``at`` frames cycling once a second, then the rest at ``second`` frames a cycle."""
    phase = np.where(T < at, 2 * np.pi * T / 10, 2 * np.pi * (T - at) / second)
    return np.stack([np.sin(phase), np.cos(phase), 0.3 * np.sin(2 * phase)], axis=1)


def split(second, height=WEAK, at=60, params=P, turn_free=None, step=1, change=60):
    """The clusters of the whole take after the rhythm splits, one peak at frame ``at``."""
    n = np.zeros(120 // step)
    n[at // step] = height
    v = two_tempos(change, second)
    return rhythm_splits(PeriodReader(v, 10, W, params), [(0, 119)], n, step, turn_free)


@pytest.mark.parametrize("second", [13, 15, 20])
def test_each_side_reads_its_own_period(second):
    v = two_tempos(60, second)
    assert [cluster_period(v, a, b, 10, W, P)[0] for a, b in ((0, 59), (60, 119))] == [10, second]


def test_a_weak_peak_where_the_period_changes_by_half_is_a_boundary():
    assert split(15) == [(0, 59), (60, 119)]                  # 1.5: a boundary
    assert split(15, step=2) == [(0, 59), (60, 119)]          # the curve at 5 fps, frames at 10


def test_a_small_change_of_tempo_or_a_whole_multiple_splits_nothing():
    assert split(13) == [(0, 119)]                            # 1.3: the same exercise's tempo
    assert split(20) == [(0, 119)]                            # 2.0: a period read at two repetitions


def test_only_a_weak_peak_of_at_least_three_quarters_the_threshold_splits():
    assert split(15, height=0.95 * FLOOR * P.novelty_threshold) == [(0, 119)]
    # A peak over the threshold is the novelty's own boundary, not a rhythm split.
    assert split(15, height=P.novelty_threshold) == [(0, 119)]


def test_no_split_near_a_cluster_end_at_a_turn_or_with_the_rule_off():
    assert split(15, at=110) == [(0, 119)]                    # 1 s from the end: under min_cluster
    assert split(15, turn_free=np.zeros(120)) == [(0, 119)]   # the heading-free novelty stays flat: a turn
    assert split(15, turn_free=np.full(120, WEAK)) == [(0, 59), (60, 119)]
    assert split(15, params=StructureParams(rhythm_ratio=0)) == [(0, 119)]
    with pytest.raises(ValueError):
        StructureParams(rhythm_ratio=0.5)


def test_a_side_too_short_to_show_the_other_sides_period_splits_nothing():
    # The lag profile reaches only a share of its frames (tvmedit.engine.parse.periods.longest_lag):
    # a side shorter than the other side's period over that share could not have shown it, so
    # the shorter period it read is no evidence. The cost, asserted too: a true change of
    # tempo that near a cluster's end is not split here.
    for at, second in ((30, 25), (40, 25), (35, 28)):
        v = two_tempos(at, second)
        assert [cluster_period(v, a, b, 10, W, P)[0] for a, b in ((0, at - 1), (at, 119))] == [10, second]
    assert longest_lag(30) < 25 <= longest_lag(40)
    assert split(25, at=30, change=30) == [(0, 119)]                  # 3 s could not have shown 2.5 s
    assert split(25, at=40, change=40) == [(0, 39), (40, 119)]        # 4 s could: the tempo changed
    assert longest_lag(35) == 28
    assert split(28, at=35, change=35) == [(0, 34), (35, 119)]        # 3.5 s reaches 2.8 s, just
