"""The kernel change-point partition (tvmedit.engine.parse.partition) and its use for the parser's boundaries."""

import itertools

import numpy as np
import pytest

from conftest import needs_mocap
from tvmedit.engine.parse.partition import energy_partition
from tvmedit.engine.parse.structure import StructureParams, parse


def _cost(x, starts, penalty):
    # The criterion of tvmedit.engine.parse.partition, written out: each segment's sum over
    # ordered pairs of distances divided by its length, plus the penalty per change.
    d = np.linalg.norm(x[:, None] - x[None], axis=2)
    bounds = [0, *starts, len(x)]
    return sum(d[a:b, a:b].sum() / (b - a) for a, b in zip(bounds, bounds[1:])) + penalty * len(starts)


@pytest.mark.parametrize("seed", range(12))
def test_the_partition_is_the_cheapest_of_all(seed):
    # Every partition with segments of min_len to max_len rows, tried one by one: none costs
    # less than the one found (a dynamic program that skipped a start, misread a segment's
    # scatter or let a segment run past max_len would be beaten or caught here).
    rng = np.random.default_rng(seed)
    T, m = int(rng.integers(8, 13)), int(rng.integers(1, 3))
    top = int(rng.integers(2 * m, T + 1)) if seed % 2 else None
    x = rng.normal(size=(T, 3))
    x[T // 2:] += rng.normal(size=3) * 1.5
    penalty = float(rng.uniform(0.5, 4.0))
    fits = lambda c: all(m <= b - a <= (top or T) for a, b in zip([0, *c], [*c, T]))  # noqa: E731
    found = energy_partition(x, penalty, m, top)
    best = min((list(c) for k in range(T // m) for c in itertools.combinations(range(m, T - m + 1), k) if fits(c)),
               key=lambda c: _cost(x, c, penalty))
    assert fits(found), found
    assert _cost(x, found, penalty) <= _cost(x, best, penalty) + 1e-9, (found, best)


def test_a_change_between_two_cyclic_exercises_is_found_where_it_is():
    # Two exercises, each cycling through its own poses (period 4 and 5 rows), over noise: one
    # change, at the row where the second starts; a penalty no change pays for gives none.
    rng = np.random.default_rng(0)
    t = np.arange(120)
    a = np.stack([np.sin(2 * np.pi * t[:70] / 4), np.cos(2 * np.pi * t[:70] / 4), np.zeros(70)], axis=1)
    b = np.stack([np.zeros(50), np.sin(2 * np.pi * t[70:] / 5), 1 + np.cos(2 * np.pi * t[70:] / 5)], axis=1)
    x = np.vstack([a, b]) + rng.normal(scale=0.1, size=(120, 3))
    assert energy_partition(x, 10.0, 20) == [70]
    assert energy_partition(x, 1e6, 20) == []


@pytest.mark.parser
def test_up_downs_after_squats_are_told_apart(devsuite):
    # The synthetic actor's squats, then up-downs (a squat, then standing up with the arms
    # raised): alike poses, whose novelty within 4 s stays under the threshold. Over whole
    # segments the two differ, and the partition finds the change within 1 s (every other
    # change of the take too).
    from tvmedit.engine.lab import fresh
    from tvmedit.engine.lab.evaluate import score
    take = fresh.take("mocap6-rest", "m6-c-20fps")
    change = take.truth["segments"][1]["start"]
    assert [s["label"] for s in take.truth["segments"][:2]] == ["squats", "up-down"]

    def starts(params):
        return [cs for cs, _ in parse(take.vectors, take.fps, params, theta=take.theta, centred=take.centred).clusters]

    near = lambda found: any(abs(s - change) <= take.fps for s in found)  # noqa: E731
    assert near(starts(StructureParams())), starts(StructureParams())
    result = score(parse(take.vectors, take.fps, theta=take.theta, centred=take.centred), take.truth, take.fps)
    assert (result.precision, result.recall) == (1.0, 1.0), result.matches


@pytest.mark.parser
def test_a_slow_exercise_is_not_cut_where_the_novelty_stays_low(devsuite):
    # CMU 13_29 played 0.7x: the last exercises' cycles are a few seconds long, and within one
    # cycle the poses change more than between pieces of it, so the partition alone would cut
    # them into min_cluster pieces. Read on the novelty (``partition_floor``), which stays low
    # there, those cuts are no boundaries; a slow transition left short joins its neighbour.
    # Every change is found within 1 s and none is false.
    from tvmedit.engine.lab.evaluate import score
    needs_mocap()
    take = devsuite.cmu_take("13_29@0.7x")

    def result(params):
        s = parse(take.vectors, take.fps, params, theta=take.theta, centred=take.centred)
        return score(s, take.truth, take.fps)

    found = result(StructureParams())
    assert (found.precision, found.recall) == (1.0, 1.0), found.matches
