"""tvmedit.engine.parse.periods: the mirror test where the person turns between repetitions."""

import numpy as np

from tvmedit.engine.parse.heading import turned
from tvmedit.engine.parse.periods import mirror_ratio

BINS = 72


def _with_turns(cycle, headings):
    # Three cycles at each heading (in bins), one after another: a person who turns to face
    # another way now and then, more suddenly than a slow heading can follow.
    return np.vstack([turned(np.tile(cycle, (3, 1)), slice(0, BINS), 2 * np.pi * h / BINS) for h in headings])


def test_a_left_then_right_exercise_stays_mirrored_across_turns():
    # Four poses of one side, then their mirror images: lag 4 is half a cycle. The person
    # turns five times, each turn moving the plane the halves are mirrored about. One plane
    # for the whole stretch read 0.81 here (no half cycle: the texton would be half an
    # exercise's cycle); the plane chosen again every two lags reads the halves as mirrored.
    half = np.random.default_rng(0).random((4, BINS))
    cycle = np.vstack([half, half[:, (10 - np.arange(BINS)) % BINS]])
    headings = (0, 17, 40, 9, 55, 28)
    assert mirror_ratio(_with_turns(cycle, headings), 4, slice(0, BINS)) < 0.5


def test_a_symmetric_exercise_is_not_read_as_mirrored_across_turns(devsuite):
    # The plane may be chosen too freely: the development suite's synthetic take that turns
    # ("turns", synth-drift) opens with jumping jacks (1.0 s a cycle, symmetric), during which
    # the actor turns. A plane chosen anew every lag is free enough to pass one cycle off as the
    # mirror image of the one before, and the texton read two cycles (2.0 s); chosen every
    # two lags (three without the two-lag mirror plane), it stays one cycle.
    from tvmedit.engine.parse.structure import parse
    take = devsuite.take("synth-drift", "turns")
    assert take.truth["segments"][0]["label"] == "jumping-jacks"
    structure = parse(take.vectors, take.fps, theta=take.theta, centred=take.centred)
    texton = float(np.median([len(t) for t in structure.textons_of(0)])) / take.fps
    assert abs(texton - 1.0) < 0.15, texton


def _texton_and_period(name, segment, label):
    # The median texton of the cluster that holds the middle of a true segment of a take of the
    # fresh batch "mocap6-rest", and that segment's true period, in seconds.
    from tvmedit.engine.lab import fresh
    from tvmedit.engine.parse.structure import parse
    take = fresh.take("mocap6-rest", name)
    true = take.truth["segments"][segment]
    assert true["label"] == label
    structure = parse(take.vectors, take.fps, theta=take.theta, centred=take.centred)
    middle = (true["start"] + true["end"]) // 2
    ci = next(i for i, (cs, ce) in enumerate(structure.clusters) if cs <= middle <= ce)
    texton = float(np.median([len(t) for t in structure.textons_of(ci)])) / take.fps
    return texton, take.truth["periods_hint"][segment]["period_s"]


def test_slow_side_bends_are_not_cut_into_a_third_of_a_half_cycle(devsuite):
    # Fresh batch "mocap6-rest", take m6-h-slow: the synthetic actor's side bends at 3.2 s a
    # cycle, left then right, after a 2 s transition. The lag profile's most prominent valley
    # is the cycle (3.3 s); the shortest-lag rule takes the half cycle (1.6 s), which barely
    # dips below the profile's level, and the sub-multiple test then took a shallow dent at
    # 0.5 s, as deep as 0.7 of that little dip: textons of 0.5 s. A sub-multiple must dip 0.7
    # as deep as the most prominent valley, so the half cycle stays and the mirror test doubles it.
    texton, period = _texton_and_period("m6-h-slow", 1, "side-bends")
    assert abs(texton - period) <= 0.15 * period, (texton, period)


def test_toe_touches_across_two_turns_get_textons_of_a_whole_cycle(devsuite):
    # Fresh batch "mocap6-rest", take m6-f-turns: the synthetic actor's one-hand toe touches
    # (2.96 s a cycle, left then right), during which it turns to face another way twice, by
    # 30-60 degrees over a second. With the reflection plane chosen every three lags a turn
    # lay inside each stretch, the mirror ratio over the cluster was 0.81 against 0.8, and the
    # textons were half a cycle (1.5 s); every two lags, a whole one.
    texton, period = _texton_and_period("m6-f-turns", 2, "toe-touch")
    assert abs(texton - period) <= 0.15 * period, (texton, period)
