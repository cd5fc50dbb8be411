"""The parse of whole takes, real (CMU and HDM05 captures) and synthetic, with default parameters.

Targets, per take: cluster-boundary precision and recall >= 0.9 (one-to-one matching, within
1 s of a true exercise start), and the median texton length within 15 % of the true period
for >= 90 % of the detected clusters. A 20 fps capture of each CMU take guards that the
defaults, given in seconds, are not fitted to 10 fps. Features are cached next to the generated
frames (``tvmedit.engine.lab.evaluate.sequence_features``), so a rerun costs seconds.

The tests after the targets show changes of exercise found where they are on takes that make
it hard (turns, alike poses, twin novelty peaks), where several of the parser's modules place
a boundary together. A rule of one module, seen on a whole take, is tested in that module's
file (``test_periods``, ``test_pauses``, ``test_heading``, ``test_joins``, ``test_confidence``).

Those tests, the 20 fps targets and the slimmer body's parse takes made for them alone (most
of them the development suite's, :mod:`tvmedit.engine.lab.devsuite`), which cost minutes to
make: marked ``parser``, they run with ``make test-parser``, not ``make test``. ``make test``
holds the targets on the two CMU takes at 10 fps and on the synthetic gym.
"""

import pytest

from conftest import CACHE, mocap_take, needs_hdm05, needs_mocap
from tvmedit.engine.lab.evaluate import score, score_take
from tvmedit.engine.parse.structure import StructureParams, parse

pytestmark = pytest.mark.slow


def scores(folder, params=None, frame="body"):
    result = score_take(folder, params, cache_dir=CACHE.parent / "features", frame=frame)
    return result.precision, result.recall, result.texton_accuracy, result.structure


def take_score(take, params=None, centred=...):
    """A development-suite take (tvmedit.engine.lab.devsuite.Take) parsed and scored against its truth;
    ``centred``: other rows about each frame's own centre than the take's (None: none)."""
    rows = take.centred if centred is ... else centred
    return score(parse(take.vectors, take.fps, params, theta=take.theta, centred=rows), take.truth, take.fps)


def starts_of(take, **params):
    """Where a development-suite take's clusters after the first start, in seconds, parsed with
    ``params`` over the defaults."""
    s = parse(take.vectors, take.fps, StructureParams(**params), theta=take.theta, centred=take.centred)
    return [cs / take.fps for cs, _ in s.clusters[1:]]


#: Boundaries at the novelty's peaks (no partition, tvmedit.engine.parse.partition), taken back up
#: to 2 s to the onset: a rule of the peaks (the shoulder rule) is seen at work on them.
PEAKS = dict(partition=0.0, onset_reach=2.0)


def _steady_turn_change_found(name):
    """CMU 13_29 turning steadily (a lab take): its change from arm circles to
    one-hand toe touches (16.0 s) has a boundary within 1 s; returns (cluster starts, change)."""
    needs_mocap()
    from tvmedit.engine.lab import fresh
    take = fresh.take("steady-turns", name)
    change = take.truth["segments"][3]["start"] / take.fps
    assert abs(change - 16.0) < 0.05
    found = starts_of(take)
    assert any(abs(b - change) <= 1.0 for b in found), found
    return found, change


# The whole takes, a 20 fps capture of each (time-like parameters are in seconds), and a
# slimmer body: in 13_29 at build 0.8 the toe-touch cluster holds a single left-right cycle,
# whose half period must not be taken for the period. The 20 fps captures are the
# development suite's own (its CMU sources, made once for the tests that play them at other
# speeds), so the rate is guarded without turning a take into meshes once more.
CASES = {"13_30": ("13_30", {}), "13_29": ("13_29", {}),
         "13_30-fps20": ("13_30", {"fps": 20}), "13_29-fps20": ("13_29", {"fps": 20}),
         "13_30-build0.8": ("13_30", {"build": 0.8}), "13_29-build0.8": ("13_29", {"build": 0.8})}


def assert_meets_targets(folder):
    precision, recall, textons, s = scores(folder)
    assert precision >= 0.9 and recall >= 0.9, (precision, recall, s.clusters)
    assert textons >= 0.9, textons


@pytest.mark.parametrize("case", [pytest.param(case, marks=[pytest.mark.parser] if "-" in case else [])
                                  for case in CASES])
def test_default_parse_meets_the_targets(case, devsuite):
    take, options = CASES[case]
    if "fps" in options:
        needs_mocap()
        folder = devsuite.cmu_source(take, **options)      # the suite's folder: fps 20, no other option
    else:
        folder = mocap_take(take, **options)
    assert_meets_targets(folder)


def test_synthetic_gym_meets_the_targets(synth_gym):
    assert_meets_targets(synth_gym)


def test_paper_method_runs_and_covers_the_take(take_13_30):
    # The printed procedure is kept for comparison; it is not expected to meet the targets.
    *_, s = scores(take_13_30, StructureParams(method="paper"))
    assert s.clusters[0][0] == 0 and s.clusters[-1][1] == len(s.curve) - 1
    assert len(s.textons) >= 2


@pytest.mark.parser
def test_a_weak_peak_where_the_period_changes_is_a_boundary(devsuite):
    # HDM05 actor bk: reaching up (1.79 s a repetition), then hops (0.79 s) from 15.9 s. The
    # novelty's peak at the change is weak, but the period read before it (1.8 s) and after it
    # (0.8 s) differ (tvmedit.engine.parse.rhythm): the boundary is found, and no false one.
    from tvmedit.engine.lab.evaluate import load_truth
    needs_hdm05()
    actor, plan, seed, options = devsuite.HDM_SOURCES[9]
    assert plan.startswith("squat1Reps:6,grabHighR:4,hopBothLegs1hops:8")
    folder = devsuite.hdm_source(actor, plan, seed, **options)
    truth = load_truth(folder)
    hops = truth["segments"][2]["start"]
    near = lambda s: [cs for cs, _ in s.clusters if abs(cs - hops) <= truth["fps"]]  # noqa: E731
    precision, _, _, s = scores(folder)
    assert precision == 1.0 and near(s), s.clusters


@pytest.mark.parser
def test_a_short_first_exercise_is_found_near_the_take_start(devsuite):
    # CMU 13_30 played 1.4x opens with a 1.3 s exercise: its boundary's novelty peak, twice
    # the threshold, lies within 1.5 s of the start, where weaker peaks are not trusted
    # (tvmedit.engine.parse.boundaries.STRONG_EDGE); it is taken, within 1 s of the labelled start.
    needs_mocap()
    take = devsuite.cmu_take("13_30@1.4x")
    starts = [cs for cs, _ in parse(take.vectors, take.fps, theta=take.theta, centred=take.centred).clusters]
    assert abs(starts[1] - take.truth["segments"][1]["start"]) <= take.fps, starts


@pytest.mark.parser
def test_exercises_of_alike_poses_are_told_apart_by_their_pace(devsuite):
    # CMU 13_29 played 0.7x: twists give way to arm circles (14.4 s) in alike poses. With each
    # bin's pace of change beside it (tvmedit.engine.parse.boundaries.pace), every boundary is
    # found within 1 s and none is false: on rows not whitened (the novelty threshold and
    # onset reach that go with them), and with the defaults.
    needs_mocap()
    take = devsuite.cmu_take("13_29@0.7x")
    raw = dict(novelty_components=0, onset_reach=2.0)
    paced = take_score(take, StructureParams(novelty_pace=1.0, **raw))
    assert (paced.precision, paced.recall) == (1.0, 1.0), paced.matches
    result = take_score(take)
    assert (result.precision, result.recall) == (1.0, 1.0), result.matches


@pytest.mark.parser
def test_a_person_turning_while_exercising_is_not_split_at_the_turn(devsuite):
    # The suite's "turn-sway" take: the synthetic actor's heading sways slowly over +/- 90
    # degrees while it wanders and exercises, and every azimuth histogram shifts with it.
    # Read as they stand (heading_window=0), a turn's novelty peak vanishes when the rows are
    # compared whichever way the body faces (tvmedit.engine.parse.heading.azimuth_spectrum)
    # and is vetoed (StructureParams.turn_ratio); read turned back by the tracked heading
    # (the default) there is no such peak. Either way every true boundary is found, none false.
    take = devsuite.take("synth-drift", "turn-sway")
    vetoed = take_score(take, StructureParams(turn_ratio=0.4, heading_window=0, novelty_pace=1.0))
    assert (vetoed.precision, vetoed.recall) == (1.0, 1.0), vetoed.matches
    followed = take_score(take, StructureParams(turn_ratio=0.0))
    assert (followed.precision, followed.recall) == (1.0, 1.0), followed.matches
    # and, turned back, its side bends get textons of a whole period (left and right)
    default = take_score(take)
    assert default.texton_accuracy == 1.0, default.texton_rows


@pytest.mark.parser
def test_a_change_just_after_a_turn_is_found_where_it_is(devsuite):
    # The suite's "turns" take: the synthetic actor turns to face another way every 5-10 s;
    # the first turn (5.4-6.4 s, 76 degrees) comes 2.7 s before jumping jacks give way to side
    # bends (8.1 s). Settled between whole periods on the rows turned back, the boundary would
    # fall on the turn, where the jumping jacks, seen turned, look left behind; those frames
    # are the old poses turned (tvmedit.engine.parse.onsets.turned_away), so it is settled on
    # the heading-free rows, at the change.
    take = devsuite.take("synth-drift", "turns")
    change = take.truth["segments"][1]["start"] / take.fps
    assert abs(change - 8.1) < 0.05
    found = starts_of(take)
    assert any(abs(b - change) <= 1.0 for b in found), found
    assert not any(5.0 <= b <= 7.0 for b in found), found          # nothing at the turn
    # The other take that turns so (15 fps, turns of 60-120 degrees) is parsed right too.
    other = devsuite.take("synth-drift", "turns-15fps")
    result = score(parse(other.vectors, other.fps, theta=other.theta), other.truth, other.fps)
    assert (result.precision, result.recall) == (1.0, 1.0), result.matches


@pytest.mark.parser
def test_a_change_of_exercise_after_a_turn_is_not_taken_back_to_the_turn(devsuite):
    # Lab take spin-a (tvmedit.engine.lab.fresh): the actor turns on its spot (9.6-10.6 s,
    # 139 degrees) while doing squats, and circles its arms from 11.1 s. The turn's peak and
    # the change's merge, so no turn is vetoed. The frames of the turn are the old poses
    # turned (tvmedit.engine.parse.onsets.turned_away), so the onset is read on the
    # heading-free rows: at the change, not at the turn's start.
    from tvmedit.engine.lab import fresh
    take = fresh.take("step23", "spin-a")
    change = take.truth["segments"][1]["start"] / take.fps
    assert abs(change - 11.1) < 0.05 and take.truth["segments"][1]["label"] == "arm-circles"
    starts = [cs / take.fps for cs, _ in parse(take.vectors, take.fps, theta=take.theta,
                                                centred=take.centred).clusters[1:]]
    assert any(abs(b - change) <= 1.0 for b in starts), starts
    assert not any(9.0 <= b <= 10.0 for b in starts), starts       # nothing at the turn's start


@pytest.mark.parser
def test_a_change_whose_novelty_peaks_twice_is_not_taken_early(devsuite):
    # CMU 13_29 turning steadily 4 degrees a second the other way: the change from arm circles
    # to slow one-hand toe touches (16.0 s) peaks twice, at 15.4 and 15.7 s, the later top a
    # little higher. The boundary is placed from the higher peak and settled on both views:
    # within 1 s of the change.
    _steady_turn_change_found("13_29-turn-m4")


@pytest.mark.parser
def test_the_turns_the_parser_vetoed_are_where_the_actor_turned(devsuite):
    # tvmedit.engine.parse.structure.vetoed_turns, which the report marks: on the "turns" take,
    # the turn of 14.5-15.5 s (the later two lie at boundaries and are no veto's; the first,
    # 5.4-6.4 s, on the actor's feet, makes little novelty of its own); none on a take of the
    # actor facing one way.
    from tvmedit.engine.parse.structure import vetoed_turns
    take = devsuite.take("synth-drift", "turns")
    seen = [f / take.fps for f in vetoed_turns(take.vectors, None, take.theta, take.fps, take.centred)]
    assert any(14.5 <= s <= 16.0 for s in seen) and all(5.4 <= s <= 6.9 or 14.5 <= s <= 16.0 for s in seen), seen
    still = devsuite.take("synth", "slim-fast")
    assert vetoed_turns(still.vectors, None, still.theta, still.fps) == []


@pytest.mark.parser
def test_marching_jogging_and_high_knees_in_place_are_told_apart(devsuite):
    # The suite's "warm-up" take: marching (1.2 s), jogging (0.7 s) and high knees (1.4 s, left
    # then right) in place, then jumping jacks: alike poses at another tempo. With the defaults
    # every change is found and every texton is right. On novelty rows not whitened
    # (StructureParams.novelty_components 0), the turn veto reads the heading-free rows about
    # each frame's own centre (Features.centred), where the change from jogging to high knees
    # is no turn, and every change is found too.
    take = devsuite.take("synth", "warm-up")
    found = take_score(take)
    assert (found.precision, found.recall, found.texton_accuracy) == (1.0, 1.0, 1.0), found.matches
    plain = StructureParams(novelty_components=0, novelty_threshold=0.05, novelty_pace=1.0)
    centred = take_score(take, plain, take.centred)
    assert centred.recall == 1.0, centred.matches


@pytest.mark.parser
def test_a_shoulder_of_a_strong_novelty_peak_is_no_boundary(devsuite):
    # The suite's "rests-long-20fps" take (the actor pauses after each repetition): the
    # novelty of the change into knee raises falls away slowly, with a bump on its flank 2 s
    # later from the pauses. That bump is the peak's shoulder (StructureParams.shoulder) and
    # no boundary, read on the novelty's peaks as with the defaults.
    take = devsuite.take("synth", "rests-long-20fps")
    peaks = take_score(take, StructureParams(shoulder=0.2, novelty_pace=1.0, **PEAKS))
    default = take_score(take)
    assert (default.precision, default.recall) == (1.0, 1.0), default.matches
    assert (peaks.precision, peaks.recall) == (1.0, 1.0), peaks.matches
    # The suite's take of one-off movements at 15 fps: its change from picking things up into
    # side bends (37.7 s) peaks at 38.4 s with a shoulder 2.9 s before it, just over the
    # threshold; the shoulder is no boundary, and the change is found, either way.
    take = devsuite.take("synth", "one-offs-irregular-15fps")
    default = take_score(take)
    assert (default.precision, default.recall) == (1.0, 1.0), default.matches
    peaks = take_score(take, StructureParams(shoulder=0.2, **PEAKS))
    assert (peaks.precision, peaks.recall) == (1.0, 1.0), peaks.matches


@pytest.mark.parser
def test_a_change_in_a_turning_take_is_settled_on_both_views(devsuite):
    # Settling on both views (tvmedit.engine.parse.onsets, *Both views*) places each boundary
    # between whole periods of its two clusters. The rows turned back by the tracked heading
    # follow a steady turn only in whole bins and keep offsets at a change of exercise, so
    # the energy distance lies broad before the change; the heading-free rows, which cannot
    # be a bin off, top at the change. CMU 13_29 turning 7 degrees a second: the change from
    # arm circles to one-hand toe touches (16.0 s) is found, with no boundary 1-2 s before it.
    found, change = _steady_turn_change_found("13_29-turn-7")
    assert not any(change - 2.0 <= b < change - 1.0 for b in found), found


@pytest.mark.parser
def test_a_change_after_a_spin_is_settled_on_both_views(devsuite):
    # Lab take spin-b-15fps: the synthetic actor, turning to face another way every 5-10 s,
    # changes from jumping jacks to knee raises at 7.9 s. On the rows turned back by the
    # heading the whole periods either side differ most 1.1 s early, on the heading-free rows
    # at the change: the boundary is found within 1 s of it.
    from tvmedit.engine.lab import fresh
    take = fresh.take("step23", "spin-b-15fps")
    change = take.truth["segments"][1]["start"] / take.fps
    assert abs(change - 7.9) < 0.1 and take.truth["segments"][1]["label"] == "knee-raises"
    found = starts_of(take)
    assert any(abs(b - change) <= 1.0 for b in found), found
