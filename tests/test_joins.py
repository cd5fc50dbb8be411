"""Clusters that are no exercise of their own (tvmedit.engine.parse.joins): hand-made clusters, a take."""

import numpy as np
import pytest

from conftest import needs_mocap
from tvmedit.engine.parse.joins import absorb_transitions, activity, join_short, merge_weak
from tvmedit.engine.parse.params import StructureParams


class Periods:
    """A stand-in for PeriodReader: the period of a stretch from a table, rows moving steadily."""

    def __init__(self, table, frames=100, fps=10, pace=1.0):
        self.table, self.fps, self.params = table, fps, StructureParams()
        self.rows = pace * np.arange(float(frames))[:, None]
        self.read = []

    def __call__(self, cs, ce):
        self.read.append((cs, ce))
        return self.table.get((cs, ce))


def repetitions(cs, ce, period):
    return (ce - cs + 1) // period


def test_activity_is_the_pace_of_change_over_half_a_second():
    rows = 3.0 * np.arange(20.0)[:, None]
    assert activity(rows, (0, 19), 10) == 15.0        # 5 frames a half second, 3 a frame
    assert activity(np.zeros((20, 4)), (0, 19), 10) == 0.0
    assert activity(rows, (0, 4), 10) == 0.0          # no longer than half a second


def test_a_short_stretch_without_period_joins_the_exercise_after_it():
    period = Periods({(0, 29): 10, (35, 94): 10, (30, 94): 10})
    clusters, periods = absorb_transitions(period, [(0, 29), (30, 34), (35, 94)], repetitions)
    assert clusters == [(0, 29), (30, 94)] and periods == [10, 10]
    assert (30, 94) in period.read                    # the joined cluster's period is read again


def test_a_transition_before_a_long_stretch_joins_it_even_without_period():
    # the stretch after it is longer than max_transition (4 s): an exercise of one-off movements
    period = Periods({(0, 29): 10})
    clusters, _ = absorb_transitions(period, [(0, 29), (30, 34), (35, 99)], repetitions)
    assert clusters == [(0, 29), (30, 99)]


def test_a_short_piece_at_the_end_joins_the_exercise_before_it():
    period = Periods({(0, 29): 10, (0, 34): 10})
    clusters, periods = absorb_transitions(period, [(0, 29), (30, 34)], repetitions)
    assert clusters == [(0, 34)] and periods == [10]


def test_a_short_piece_after_a_stretch_that_does_not_repeat_stays():
    period = Periods({})
    clusters, periods = absorb_transitions(period, [(0, 29), (30, 34)], repetitions)
    assert clusters == [(0, 29), (30, 34)] and periods == [None, None]


def test_a_short_exercise_that_repeats_and_moves_is_no_transition():
    period = Periods({(0, 29): 10, (30, 39): 5, (40, 99): 10})
    clusters, _ = absorb_transitions(period, [(0, 29), (30, 39), (40, 99)], repetitions)
    assert clusters == [(0, 29), (30, 39), (40, 99)]


def test_a_short_stretch_standing_still_is_a_transition_despite_a_period():
    # noise in a still stretch shows a period; it changes pose far slower than what follows
    period = Periods({(0, 29): 10, (30, 39): 5, (40, 99): 10, (30, 99): 10})
    period.rows[30:40] = 30.0
    clusters, _ = absorb_transitions(period, [(0, 29), (30, 39), (40, 99)], repetitions)
    assert clusters == [(0, 29), (30, 99)]


def test_a_weak_boundary_between_stretches_that_do_not_repeat_is_dropped():
    period = Periods({(20, 29): 10, (0, 29): 10})
    clusters, periods = merge_weak(period, [(0, 19), (20, 29)], repetitions, [1.0, 0.1])
    assert clusters == [(0, 29)] and periods == [10]


def test_a_weak_boundary_between_two_short_exercises_that_repeat_stays():
    period = Periods({(0, 19): 10, (20, 29): 10})
    clusters, periods = merge_weak(period, [(0, 19), (20, 29)], repetitions, [1.0, 0.1])
    assert clusters == [(0, 19), (20, 29)] and periods == [10, 10]


def test_a_boundary_at_the_weak_limit_or_beside_long_exercises_stays():
    period = Periods({(0, 59): 10})
    assert merge_weak(period, [(0, 19), (20, 29)], repetitions, [1.0, 0.25])[0] == [(0, 19), (20, 29)]
    # three repetitions before it: an exercise, not a one-off stretch
    assert merge_weak(period, [(0, 59), (60, 69)], repetitions, [1.0, 0.1])[0] == [(0, 59), (60, 69)]


def test_a_cluster_left_too_short_joins_across_its_weaker_boundary():
    weak_after = lambda cs: [1.0] + [0.2 if s == 15 else 0.5 for s, _ in cs[1:]]  # noqa: E731
    assert join_short([(0, 9), (10, 14), (15, 39)], weak_after, 20) == [(0, 9), (10, 39)]
    equal = lambda cs: [1.0] + [0.5] * (len(cs) - 1)  # noqa: E731
    assert join_short([(0, 9), (10, 14), (15, 39)], equal, 20) == [(0, 14), (15, 39)]


def test_short_first_and_last_clusters_stay_as_they_are():
    equal = lambda cs: [1.0] + [0.5] * (len(cs) - 1)  # noqa: E731
    assert join_short([(0, 4), (5, 39), (40, 44)], equal, 20) == [(0, 4), (5, 39), (40, 44)]


@pytest.mark.parser
@pytest.mark.slow
def test_two_short_exercises_that_repeat_are_not_joined_as_a_weak_split(devsuite):
    # CMU 13_30 played 1.4x: two alike exercises of about two periods each (1.7 s; 3.5 s and
    # 3.0 s long) meet at 8.5 s under a weak novelty peak. Each holds at most one whole texton,
    # as stretches of one-off movements do, but both show a period: the boundary stays.
    from tvmedit.engine.lab.evaluate import score
    from tvmedit.engine.parse.boundaries import novelty_curve
    from tvmedit.engine.parse.confidence import boundary_confidences
    from tvmedit.engine.parse.structure import parse, parser_view
    needs_mocap()
    take = devsuite.cmu_take("13_30@1.4x")
    s = parse(take.vectors, take.fps, theta=take.theta, centred=take.centred)
    result = score(s, take.truth, take.fps)
    assert (result.precision, result.recall) == (1.0, 1.0), result.matches
    at = [i for i, (cs, _) in enumerate(s.clusters) if abs(cs / take.fps - 8.5) <= 1.0]
    # the confidence merge_weak reads: the novelty at the boundary itself
    p = StructureParams()
    curve, step = novelty_curve(parser_view(take.vectors, p, take.theta, take.fps), take.fps, p)
    weak = boundary_confidences(curve, step, s.clusters, p.novelty_threshold)
    assert at and weak[at[0]] < p.weak_boundary, (s.clusters, weak)
    assert all(len(s.textons_of(k)) <= 1 for k in (at[0] - 1, at[0])), [s.textons_of(k) for k in (at[0] - 1, at[0])]
