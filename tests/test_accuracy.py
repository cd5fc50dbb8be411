"""Motion-structure accuracy on real motion (CMU takes turned into meshes), default parameters.

Targets, per take: cluster-boundary precision and recall >= 0.9 (one-to-one matching, within
1 s of a true exercise start), and the median texton length within 15 % of the true period
for >= 90 % of the detected clusters. A 30 fps variant guards that the defaults, given in
seconds, are not fitted to 10 fps. Features are cached next to the generated frames
(``tvmedit.engine.lab.evaluate.sequence_features``), so a rerun costs seconds. One HDM05 take of the
development suite guards the sub-multiple step of ``tvmedit.engine.parse.periods``, another the rhythm rule
(``tvmedit.engine.parse.rhythm``), a third the comb rule (textons cut at one repetition where the period read
spans two).
"""

import numpy as np
import pytest

from conftest import CACHE, mocap_take, needs_hdm05, needs_mocap
from tvmedit.engine.lab.evaluate import score_take
from tvmedit.engine.parse.structure import StructureParams

pytestmark = pytest.mark.slow


def scores(folder, params=None, frame="body"):
    result = score_take(folder, params, cache_dir=CACHE.parent / "features", frame=frame)
    return result.precision, result.recall, result.texton_accuracy, result.structure


_OWN = object()


def take_score(take, params=None, centred=_OWN):
    """A development-suite take (tvmedit.engine.lab.devsuite.Take) parsed and scored against its truth;
    ``centred``: other rows about each frame's own centre than the take's (None: none)."""
    from tvmedit.engine.lab.evaluate import score
    from tvmedit.engine.parse.structure import parse
    rows = take.centred if centred is _OWN else centred
    return score(parse(take.vectors, take.fps, params, theta=take.theta, centred=rows), take.truth, take.fps)


#: The boundaries and the onset rule as they are without the partition: boundaries at the novelty's
#: peaks (no partition, tvmedit.engine.parse.partition) and taken back up to 2 s to the onset. The tests
#: that show what a rule of the peaks does without it read the takes so; with the partition
#: some of those failures no longer arise (each test also checks the defaults).
PEAKS = dict(partition=0.0, onset_reach=2.0)


def _steady_turn_change_found(name):
    """CMU 13_29 turning steadily (fresh batch "steady-turns"): its change from arm circles to
    one-hand toe touches (16.0 s) has a boundary within 1 s; returns (cluster starts, change)."""
    needs_mocap()
    from tvmedit.engine.lab import fresh
    take = fresh.take("steady-turns", name)
    change = take.truth["segments"][3]["start"] / take.fps
    assert abs(change - 16.0) < 0.05
    found = starts_of(take)
    assert any(abs(b - change) <= 1.0 for b in found), found
    return found, change


def starts_of(take, **params):
    """Where a development-suite take's clusters after the first start, in seconds, parsed with
    ``params`` over the defaults."""
    from tvmedit.engine.parse.structure import parse
    s = parse(take.vectors, take.fps, StructureParams(**params), theta=take.theta, centred=take.centred)
    return [cs / take.fps for cs, _ in s.clusters[1:]]


# The whole takes, a 30 fps capture of each (time-like parameters are in seconds), and a
# slimmer body: in 13_29 at build 0.8 the toe-touch cluster ends 9 frames early and holds a
# single 41-frame left-right cycle, whose half period must not be taken for the period.
CASES = {"13_30": ("13_30", {}), "13_29": ("13_29", {}),
         "13_30-fps30": ("13_30", {"fps": 30}), "13_29-fps30": ("13_29", {"fps": 30}),
         "13_30-build0.8": ("13_30", {"build": 0.8}), "13_29-build0.8": ("13_29", {"build": 0.8})}


def assert_meets_targets(folder):
    precision, recall, textons, s = scores(folder)
    assert precision >= 0.9 and recall >= 0.9, (precision, recall, s.clusters)
    assert textons >= 0.9, textons


@pytest.mark.parametrize("case", list(CASES))
def test_default_parse_meets_the_targets(case):
    take, options = CASES[case]
    assert_meets_targets(mocap_take(take, **options))


def test_synthetic_gym_meets_the_targets(synth_gym):
    assert_meets_targets(synth_gym)


def test_paper_method_runs_and_covers_the_take(take_13_30):
    # The printed procedure is kept for comparison; it is not expected to meet the targets.
    *_, s = scores(take_13_30, StructureParams(method="paper"))
    assert s.clusters[0][0] == 0 and s.clusters[-1][1] == len(s.curve) - 1
    assert len(s.textons) >= 2


def test_hops_stitched_from_single_clips_get_one_hop_textons(devsuite):
    # HDM05 actor bk, five exercises stitched from single-repetition clips (a take of the
    # development suite). Consecutive hops differ a little, so the lag profile's clearest
    # valley lies at two hops (17 frames); the sub-multiple test takes the one-hop valley.
    from tvmedit.engine.lab.evaluate import load_truth, texton_length_accuracy
    needs_hdm05()
    actor, plan, seed, options = devsuite.HDM_SOURCES[3]
    folder = devsuite.hdm_source(actor, plan, seed, **options)
    rows = texton_length_accuracy(scores(folder)[3], load_truth(folder), details=True)[1]
    hops = [r for r in rows if r[1] == 4]   # the last block: hopping on both legs
    assert hops and hops[0][4], rows


def test_kicks_dipping_at_one_and_a_half_periods_get_one_kick_textons(devsuite):
    # HDM05 actor bd (a take of the development suite): six front kicks from 19.9 s, 1.64 s a
    # kick on average. Consecutive kicks differ, so the lag profile's clearest valley lies at
    # two kicks, and the one-kick valley is too shallow for the sub-multiple test; but the
    # profile dips at one and a half times that lag too, which a period of two kicks would not
    # show (the comb rule, tvmedit.engine.parse.periods): the textons are one kick long. No boundary moves.
    from tvmedit.engine.lab.evaluate import load_truth, texton_length_accuracy
    needs_hdm05()
    actor, plan, seed, options = devsuite.HDM_SOURCES[0]
    assert plan.split(",")[3] == "kickLFront1Reps:6"
    folder = devsuite.hdm_source(actor, plan, seed, **options)
    truth = load_truth(folder)
    with_step = scores(folder)[3]
    kicks = lambda s: [r for r in texton_length_accuracy(s, truth, details=True)[1] if r[1] == 3]  # noqa: E731
    (_, _, median, period, right), = kicks(with_step)
    assert right and abs(median - period) <= 0.15 * period, kicks(with_step)


def test_a_weak_peak_where_the_period_changes_is_a_boundary(devsuite):
    # HDM05 actor bk (a take of the development suite): reaching up (1.79 s a repetition)
    # then hops (0.79 s) from 15.9 s. At pace weight 1, the novelty takes the
    # novelty's peak there for a turn, and a weaker peak beside it stays under the threshold;
    # the period step reads 1.8 s before it and 0.8 s after (tvmedit.engine.parse.rhythm): the boundary is
    # found, and no false one comes with it. At the weight 2 the novelty finds it by itself.
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


def test_a_half_period_whose_third_multiple_is_no_valley_is_doubled(devsuite):
    # CMU 13_30 played 1.4x (a take of the development suite): the first exercise's lag
    # profile dips at 12 frames and, nearly as deep, at 23 (its true period, 22.6 frames),
    # and the mirror test does not flag 12 as half a left-right cycle. A period repeats, so
    # the profile must dip near 36 too; it does not, and the texton is two halves long.
    needs_mocap()
    take = devsuite.cmu_take("13_30@1.4x")
    rows = take_score(take).texton_rows
    first = [r for r in rows if r[1] == 1][0]   # (cluster, true segment, median, period, right)
    assert first[4] and first[2] > 0.85 * first[3], rows


def test_a_short_first_exercise_is_found_near_the_take_start(devsuite):
    # CMU 13_30 played 1.4x opens with a 1.3 s exercise: its boundary's novelty peak, twice
    # the threshold, lies within 1.5 s of the start, where weaker peaks are not trusted
    # (tvmedit.engine.parse.boundaries.STRONG_EDGE); it is taken, within 1 s of the labelled start.
    from tvmedit.engine.parse.structure import parse
    needs_mocap()
    take = devsuite.cmu_take("13_30@1.4x")
    starts = [cs for cs, _ in parse(take.vectors, take.fps, theta=take.theta, centred=take.centred).clusters]
    assert abs(starts[1] - take.truth["segments"][1]["start"]) <= take.fps, starts


def test_exercises_of_alike_poses_are_told_apart_by_their_pace(devsuite):
    # CMU 13_29 played 0.7x (a take of the development suite): on the poses alone the
    # boundary from twists to arm circles came 1.4 s early (13.0 s for 14.4 s: a false start
    # and a miss). With each bin's pace of change beside it (tvmedit.engine.parse.boundaries.pace) every
    # boundary is found within 1 s and none is false.
    from tvmedit.engine.parse.structure import StructureParams
    needs_mocap()
    take = devsuite.cmu_take("13_29@0.7x")
    # On the rows as they are (not whitened, tvmedit.engine.parse.boundaries.whiten), as when the pace came in.
    raw = dict(novelty_components=0, onset_reach=2.0)   # threshold 0.05 then, and the onset's reach
    found = {pace: take_score(take, StructureParams(novelty_pace=pace, **raw)) for pace in (1.0, 0.0)}
    assert (found[1.0].precision, found[1.0].recall) == (1.0, 1.0), found[1.0].matches
    assert found[0.0].recall < 1.0   # the poses alone miss it
    result = take_score(take)
    assert (result.precision, result.recall) == (1.0, 1.0), result.matches   # and the defaults find it


def test_a_person_turning_while_exercising_is_not_split_at_the_turn(devsuite):
    # The development suite's "turn-sway" take: the synthetic actor's heading sways slowly
    # over +/- 90 degrees while it wanders and exercises. The azimuth histograms shift with
    # the heading and the novelty peaked inside side bends (false boundaries). Read as they
    # stand (heading_window=0), compared whichever way the body faces
    # (tvmedit.engine.parse.heading.azimuth_spectrum) that peak vanishes and is vetoed
    # (StructureParams.turn_ratio), while every true boundary stays; read turned back by the
    # tracked heading (tvmedit.engine.parse.heading, the default) there is no such peak to veto. (Without
    # the heading followed, at pace weight 1: at weight 2 the rows read as
    # they stand make one false boundary more.)
    from tvmedit.engine.parse.structure import StructureParams
    take = devsuite.synth_take("synth-drift", "turn-sway", dict(devsuite.SYNTH["synth-drift"])["turn-sway"])
    vetoed = take_score(take, StructureParams(turn_ratio=0.4, heading_window=0, novelty_pace=1.0))
    assert (vetoed.precision, vetoed.recall) == (1.0, 1.0), vetoed.matches
    followed = take_score(take, StructureParams(turn_ratio=0.0))
    assert (followed.precision, followed.recall) == (1.0, 1.0), followed.matches
    # and, turned back, its side bends get textons of a whole period (left and right)
    default = take_score(take)
    assert default.texton_accuracy == 1.0, default.texton_rows


def test_a_change_just_after_a_turn_is_found_where_it_is(devsuite):
    # The development suite's "turns" take: the synthetic actor turns to face another way
    # every 5-10 s; the first turn (5.4-6.4 s, 76 degrees) comes 2.7 s before jumping jacks
    # give way to side bends (8.1 s). While the actor's feet slid as it turned (synth VERSION
    # 2), the turn's novelty peak hid the change on its slope (tvmedit.engine.parse.boundaries, *Boundaries
    # behind a turn*). Turning on its feet, it makes no peak of its own; the change's peak
    # lies at 8.1 s, and settling the boundary between whole periods moved it back onto the
    # turn (6.6 s), where the jumping jacks, seen turned, look left behind. Those frames are
    # the old poses turned (tvmedit.engine.parse.onsets.turned_away), so it is settled on the heading-free
    # rows (the turned-away test). Without the turn veto there are no heading-free rows to read.
    from tvmedit.engine.lab.evaluate import score
    from tvmedit.engine.parse.structure import parse
    take = devsuite.synth_take("synth-drift", "turns", dict(devsuite.SYNTH["synth-drift"])["turns"])
    change = take.truth["segments"][1]["start"] / take.fps
    assert abs(change - 8.1) < 0.05
    found = starts_of(take)
    assert any(abs(b - change) <= 1.0 for b in found), found
    assert not any(5.0 <= b <= 7.0 for b in found), found          # nothing at the turn
    # The other take that turns so (15 fps, turns of 60-120 degrees) is parsed right too (with
    # the turn veto; boundaries behind a turn changes nothing there).
    other = devsuite.synth_take("synth-drift", "turns-15fps", dict(devsuite.SYNTH["synth-drift"])["turns-15fps"])
    result = score(parse(other.vectors, other.fps, theta=other.theta), other.truth, other.fps)
    assert (result.precision, result.recall) == (1.0, 1.0), result.matches


def test_a_change_of_exercise_after_a_turn_is_not_taken_back_to_the_turn(devsuite):
    # Fresh batch "step23", take spin-a (tvmedit.engine.lab.fresh): the actor turns on its spot
    # (9.6-10.6 s, 139 degrees) while doing squats, and circles its arms from 11.1 s. The turn's
    # peak and the change's merge, so no turn is vetoed; the boundary settles at 11.5 s, and
    # the onset step took it back to 9.6 s, where the squats, seen turned, looked left
    # behind (a false start and a miss). Those frames are the old poses turned
    # (tvmedit.engine.parse.onsets.turned_away), so the onset is read on the heading-free rows: 11.1 s.
    from tvmedit.engine.lab import fresh

    from tvmedit.engine.parse.structure import parse
    take = fresh.take("step23", "spin-a")
    change = take.truth["segments"][1]["start"] / take.fps
    assert abs(change - 11.1) < 0.05 and take.truth["segments"][1]["label"] == "arm-circles"
    starts = [cs / take.fps for cs, _ in parse(take.vectors, take.fps, theta=take.theta,
                                                centred=take.centred).clusters[1:]]
    assert any(abs(b - change) <= 1.0 for b in starts), starts
    assert not any(9.0 <= b <= 10.0 for b in starts), starts       # nothing at the turn's start


def test_a_change_whose_novelty_peaks_twice_is_not_taken_early(devsuite):
    # CMU 13_29 turning steadily 4 degrees a second the other way (fresh batch "steady-turns"):
    # the change from arm circles to slow one-hand toe touches (16.0 s) peaks twice, at 15.4 and 15.7 s,
    # the later top a little higher. The earlier-twin rule (twin_peak 0.9, no longer the default)
    # took 15.4 s, and the later rules that place a boundary, searching about
    # it, took it back to 14.5 s: 1.5 s early, a miss and a false start. From the higher
    # peak they place it at 15.2 s; settling on both views places it right from either.
    _steady_turn_change_found("13_29-turn-m4")


def test_the_boundaries_placed_wrong_are_the_least_sure(devsuite):
    # CMU 13_29 turning 6 degrees a second the other way, swaying 30 degrees about that (fresh
    # batch "review-3"): the onset step takes two changes (16.0 s and 31.7 s) back 1.2-1.4 s,
    # off their novelty peaks, and both are missed. `tvmedit info` lists the least sure
    # boundaries first: the ones placed wrong must lead the list, below every right one. Read
    # where a boundary lies, the novelty ranked those two first and fourth of five (0.21 and
    # 0.38 against 0.29-0.56); read at its peak and discounted by the move (tvmedit.engine.parse.confidence),
    # first and second (0.02 and 0.10 against 0.21-0.26).
    from tvmedit.engine.lab.evaluate import score
    from tvmedit.engine.parse.structure import parse
    needs_mocap()
    from tvmedit.engine.lab import fresh
    take = fresh.take("review-3", "13_29-turn-m6")
    s = parse(take.vectors, take.fps, theta=take.theta, centred=take.centred)
    result = score(s, take.truth, take.fps)
    found = {d for d, _ in result.matches}
    sure = dict(zip((cs for cs, _ in s.clusters[1:]), s.boundary_confidence[1:]))
    wrong = [sure[cs] for cs in sure if cs not in found]
    right = [sure[cs] for cs in sure if cs in found]
    assert wrong and right, (s.clusters, result.matches)
    assert max(wrong) < min(right), sure


def test_an_exercise_done_swaying_gets_textons_of_a_whole_cycle(devsuite):
    # CMU 13_30 with the person swaying up to 90 degrees back and forth (a take of the
    # development suite): its second exercise (twists, 3.16 s a cycle, left then right) once read half
    # cycles. The mirror test compares the rows about each frame's own centre against one
    # reflection plane; those rows turn with the person, so they are read turned back by their
    # own slow heading, as the parser's rows are (tvmedit.engine.parse.periods, *A person who turns*).
    take = devsuite.cmu_take("13_30-turn")
    rows = take_score(take).texton_rows
    second = [r for r in rows if r[1] == 1][0]  # (cluster, true segment, median, period, right)
    assert abs(second[3] / take.fps - 3.16) < 0.1, rows                 # the twists' true cycle
    assert abs(second[2] / take.fps - 3.16) < 0.15 * 3.16 and second[4], rows


def test_walking_across_sudden_turns_gets_textons_of_a_whole_stride(devsuite):
    # Fresh batch "step23", take spin-c-rests: the actor walks 13.2-28.5 s (1.45 s a stride,
    # left then right) and turns 90 degrees at 16 s and 124 degrees at 22-23 s, each over 1 s,
    # faster than the slow heading follows. One reflection plane for the whole cluster fits
    # neither heading, and the texton was a third of a stride (0.6 s); the plane is now chosen
    # anew every two lags (tvmedit.engine.parse.periods.mirror_ratio).
    from tvmedit.engine.lab import fresh

    from tvmedit.engine.parse.structure import parse
    take = fresh.take("step23", "spin-c-rests")
    assert take.truth["segments"][1]["label"] == "walk"
    structure = parse(take.vectors, take.fps, theta=take.theta, centred=take.centred)
    k, cluster = min(enumerate(structure.clusters), key=lambda c: abs(c[1][0] / take.fps - 13.2))
    assert abs(cluster[0] / take.fps - 13.2) < 1.0 and abs(cluster[1] / take.fps - 28.5) < 1.0, structure.clusters
    stride = float(np.median([len(t) for t in structure.textons_of(k)])) / take.fps
    assert abs(stride - 1.45) < 0.15 * 1.45, stride


def test_toe_touches_done_across_a_turn_get_textons_of_a_whole_cycle(devsuite):
    # Fresh batch "step23", take spin-c-rests: four toe touches (left then right, 3.3 s a
    # cycle with its rest), in which the actor turns 147 degrees on its feet (10.3-11.3 s),
    # a spot a little off the first frame's centre, the features' origin. Every reflection the
    # mirror test tries is about a plane through that origin; the turned body's own plane no
    # longer passes through it, so the test read half cycles (1.6 s). About each frame's own
    # centre (Features.centred) the halves are mirror images, and the cycle is whole
    # (tvmedit.engine.parse.periods, *About the body's own centre*).
    from tvmedit.engine.lab import fresh

    from tvmedit.engine.parse.structure import parse, textons_for
    take = fresh.take("step23", "spin-c-rests")
    assert take.truth["segments"][0]["label"] == "toe-touch"
    structure = parse(take.vectors, take.fps, theta=take.theta, centred=take.centred)
    cluster = structure.clusters[0]
    assert abs(cluster[1] / take.fps - 13.2) < 1.0, cluster
    parsed = [t.end - t.start + 1 for t in structure.textons_of(0)]
    assert abs(float(np.median(parsed)) / take.fps - 3.3) < 0.4, parsed     # the parser's own textons

    def cycle(centred):
        found = textons_for(take.vectors, [cluster], take.fps, theta=take.theta, centred=centred)
        return float(np.median([t.end - t.start + 1 for t in found])) / take.fps

    assert abs(cycle(take.centred) - 3.3) < 0.4, cycle(take.centred)
    assert abs(cycle(None) - 1.6) < 0.3, cycle(None)


def test_the_turns_the_parser_vetoed_are_where_the_actor_turned(devsuite):
    # tvmedit.engine.parse.structure.vetoed_turns, which the report marks: on the "turns" take, the turn of
    # 14.5-15.5 s (the later two lie at boundaries and are no veto's; the first, 5.4-6.4 s,
    # has made no novelty peak of its own since the actor turns on its feet, synth VERSION 3);
    # none on a take of the actor facing one way.
    from tvmedit.engine.parse.structure import vetoed_turns
    take = devsuite.synth_take("synth-drift", "turns", dict(devsuite.SYNTH["synth-drift"])["turns"])
    seen = [f / take.fps for f in vetoed_turns(take.vectors, None, take.theta, take.fps, take.centred)]
    assert any(14.5 <= s <= 16.0 for s in seen) and all(5.4 <= s <= 6.9 or 14.5 <= s <= 16.0 for s in seen), seen
    still = devsuite.synth_take("synth", "slim-fast", dict(devsuite.SYNTH["synth"])["slim-fast"])
    assert vetoed_turns(still.vectors, None, still.theta, still.fps) == []


def test_marching_jogging_and_high_knees_in_place_are_told_apart(devsuite):
    # The development suite's "warm-up" take: marching (1.2 s), jogging (0.7 s) and high
    # knees (1.4 s, left then right) in place, then jumping jacks: alike poses at another
    # tempo. With the defaults all are found. On novelty rows not whitened
    # (StructureParams.novelty_components 0) the change from jogging to high knees looked
    # like a turn on the heading-free rows about the first frame's centre and was vetoed;
    # on those about each frame's own centre (Features.centred, centred features) it is found. (At the
    # pace weight 1: at 2 the pace tells that change from a turn either way.)
    from tvmedit.engine.parse.structure import StructureParams
    take = devsuite.synth_take("synth", "warm-up", dict(devsuite.SYNTH["synth"])["warm-up"])
    found = take_score(take)
    assert (found.precision, found.recall, found.texton_accuracy) == (1.0, 1.0, 1.0), found.matches
    plain = StructureParams(novelty_components=0, novelty_threshold=0.05, novelty_pace=1.0)
    about = {centred is not None: take_score(take, plain, centred).recall for centred in (None, take.centred)}
    assert about == {False: 2 / 3, True: 1.0}, about


def test_a_take_in_the_body_frame_is_parsed_on_smoothed_azimuth_histograms(devsuite):
    # The development suite's "wander" take (the synthetic actor wandering up to 0.8 m), with
    # features in the body's own frame as build computes them: its front lies a fraction of
    # a 5 degree azimuth bin off the bins' edges, and on hard-edged histograms its last
    # boundary landed 1.3 s late (a false start and a miss). Read smoothed (tvmedit.engine.parse.heading),
    # every boundary is found within 1 s and none is false.
    from tvmedit.engine.lab.evaluate import score
    from tvmedit.engine.parse.structure import parse
    assert devsuite.FRAME == "body"
    take = devsuite.synth_take("synth-drift", "wander", dict(devsuite.SYNTH["synth-drift"])["wander"])
    structure = parse(take.vectors, take.fps, theta=take.theta, centred=take.centred)
    result = score(structure, take.truth, take.fps)
    assert (result.precision, result.recall) == (1.0, 1.0), structure.clusters


def test_a_real_take_done_turning_reads_as_if_facing_one_way(devsuite):
    # CMU 13_29 turning 6 degrees a second (devsuite.CMU_TURNS: its meshes rotated about
    # where the person stands, then taken in their own body frame): read as its histograms
    # stand, the turn makes novelty peaks inside exercises (boundaries more than there are
    # changes) and textons of the wrong length. Turned back by the tracked heading
    # (tvmedit.engine.parse.heading, StructureParams.heading_window) there are as many boundaries as changes
    # and every texton is right. One of its five changes (16.0 s) was taken 1.1 s early at its
    # onset once the take turned on the person's feet (synth VERSION 3; README, *The turning
    # takes' feet*), over frames that are the old toe touches turned 25 degrees, read about
    # each frame's own centre (which the tracker does not turn back): the turned-away test took turns under
    # 30 degrees for none without the slow-turn rule (tvmedit.engine.parse.onsets, *A slow turn counts too*). A second one
    # (22.5 s) was merged away in favour of a split 2.5 s into the toe touches, without the short-side rule
    # (tvmedit.engine.parse.rhythm, *A side too short to tell*).
    from tvmedit.engine.parse.structure import StructureParams
    take = devsuite.cmu_take("13_29-turn")
    # Read turned back by the followed heading, the turn is no change of pose (on the novelty's
    # peaks too, with the shoulder rule off: as many boundaries as changes).
    followed = take_score(take, StructureParams(heading_window=4.0, shoulder=0.0, **PEAKS))
    changes = len(take.truth["segments"]) - 1
    assert followed.detected == changes and followed.texton_accuracy == 1.0, (followed.matches, followed.texton_rows)
    assert (followed.precision, followed.recall) == (1.0, 1.0), followed.matches
    default = take_score(take)
    assert (default.precision, default.recall) == (1.0, 1.0), default.matches


def test_repetitions_with_pauses_get_textons_of_a_whole_repetition(devsuite):
    # The development suite's "rests-long-20fps" take: the synthetic actor pauses up to
    # 1.5 s after each repetition. Measured on every frame, the lag profile's clearest valley
    # was the movement alone (squats: textons of 2.2 s where a repetition and its pause last
    # 3.0 s) and knee raises got half periods; measured on the frames that move
    # (tvmedit.engine.parse.pauses, StructureParams.pause_share), each texton is a repetition with its pause.
    from tvmedit.engine.parse.structure import StructureParams
    take = devsuite.synth_take("synth", "rests-long-20fps", dict(devsuite.SYNTH["synth"])["rests-long-20fps"])
    found = {share: take_score(take, StructureParams(pause_share=share)) for share in (0.1, 0.0)}
    right = {share: sum(ok for *_, ok in found[share].texton_rows) for share in found}
    assert right[0.1] >= right[0.0] + 2, found[0.1].texton_rows
    squats = [row for row in found[0.1].texton_rows if abs(row[3] / take.fps - 3.01) < 0.05]   # frames
    assert squats and squats[0][-1], found[0.1].texton_rows


def test_a_shoulder_of_a_strong_novelty_peak_is_no_boundary(devsuite):
    # The same pausing take: the novelty of the change into knee raises falls away slowly,
    # and a bump on its flank 2 s later (from the pauses) made a false boundary inside the
    # knee raises; it is that peak's shoulder (StructureParams.shoulder) and no boundary now.
    # (At pace weight 1, 1; at 2 that bump stays under the threshold.)
    from tvmedit.engine.parse.structure import StructureParams
    take = devsuite.synth_take("synth", "rests-long-20fps", dict(devsuite.SYNTH["synth"])["rests-long-20fps"])
    # (A rule of the novelty's peaks: read on them, as without the partition.)
    peaks = take_score(take, StructureParams(shoulder=0.2, novelty_pace=1.0, **PEAKS))
    default = take_score(take)
    assert (default.precision, default.recall) == (1.0, 1.0), default.matches   # the defaults
    assert (peaks.precision, peaks.recall) == (1.0, 1.0), peaks.matches
    # The suite's take of one-off movements at 15 fps, whose change from picking things up
    # into side bends (37.7 s) peaks at 38.4 s with a shoulder 2.9 s before it (0.91 against
    # the threshold 0.9); taken for a boundary (35.5 s), it was settled to 36.9 s and taken
    # back to its onset at 36.2 s: 1.5 s early (on the novelty's peaks, the defaults until
    # the partition). With the partition, the defaults since, the change is found too.
    name = "one-offs-irregular-15fps"
    take = devsuite.synth_take("synth", name, dict(devsuite.SYNTH["synth"])[name])
    default = take_score(take)
    assert (default.precision, default.recall) == (1.0, 1.0), default.matches
    peaks = take_score(take, StructureParams(shoulder=0.2, **PEAKS))
    assert (peaks.precision, peaks.recall) == (1.0, 1.0), peaks.matches


def test_two_short_exercises_that_repeat_are_not_joined_as_a_weak_split(devsuite):
    # CMU 13_30 played 1.4x (a take of the development suite): two alike exercises of about
    # two periods each (1.7 s; 3.5 s and 3.0 s long) meet at 8.5 s under a weak novelty peak
    # (confidence 0.22 where the weak-split rule reads it, at the boundary). Each holds one whole texton, as
    # the stretches of one-off movements whose weak splits the weak-split rule undoes do, but both show a
    # period: the boundary stays.
    from tvmedit.engine.parse.boundaries import novelty_curve
    from tvmedit.engine.parse.confidence import boundary_confidences
    from tvmedit.engine.lab.evaluate import score
    from tvmedit.engine.parse.structure import parse, parser_view
    needs_mocap()
    take = devsuite.cmu_take("13_30@1.4x")
    s = parse(take.vectors, take.fps, theta=take.theta, centred=take.centred)
    result = score(s, take.truth, take.fps)
    assert (result.precision, result.recall) == (1.0, 1.0), result.matches
    at = [i for i, (cs, _) in enumerate(s.clusters) if abs(cs / take.fps - 8.5) <= 1.0]
    # the confidence the weak-split rule reads: the novelty at the boundary (not the one reported, which
    # reads it at the peak and discounts a move, tvmedit.engine.parse.confidence)
    p = StructureParams()
    curve, step = novelty_curve(parser_view(take.vectors, p, take.theta, take.fps), take.fps, p)
    weak = boundary_confidences(curve, step, s.clusters, p.novelty_threshold)
    assert at and weak[at[0]] < p.weak_boundary, (s.clusters, weak)
    # what makes it a case for the weak-split rule: at most one whole texton on either side
    assert all(len(s.textons_of(k)) <= 1 for k in (at[0] - 1, at[0])), [s.textons_of(k) for k in (at[0] - 1, at[0])]


def test_a_change_in_a_turning_take_is_settled_on_both_views(devsuite):
    # Settling on both views (tvmedit.engine.parse.onsets, *Both views*). Settling places each boundary
    # between whole periods of its two clusters; on the rows turned back by the tracked
    # heading, which follows a steady turn only in whole bins a second and leaves offsets at a
    # change of exercise, the energy distance lay broad before the change and its top
    # wandered early. CMU 13_29 turning 7 degrees a second (fresh batch "steady-turns"): the
    # change from arm circles to one-hand toe touches (16.0 s) was settled to 14.9 s, a miss
    # and a false start; the heading-free rows, which cannot be a bin off, top at 16.3 s.
    found, change = _steady_turn_change_found("13_29-turn-7")
    assert not any(change - 2.0 <= b < change - 1.0 for b in found), found


def test_a_change_after_a_spin_is_settled_on_both_views(devsuite):
    # Fresh batch "step23", take spin-b-15fps: the synthetic actor, turning to face another
    # way every 5-10 s, changes from jumping jacks to knee raises at 7.9 s. On the rows turned
    # back by the heading the whole periods either side differ most at 6.8 s (within 10 % of
    # that over 6.5-7.9 s), on the heading-free rows at 8.1 s; the boundary was placed 1.3 s
    # early (6.6 s).
    from tvmedit.engine.lab import fresh
    take = fresh.take("step23", "spin-b-15fps")
    change = take.truth["segments"][1]["start"] / take.fps
    assert abs(change - 7.9) < 0.1 and take.truth["segments"][1]["label"] == "knee-raises"
    found = starts_of(take)
    assert any(abs(b - change) <= 1.0 for b in found), found
