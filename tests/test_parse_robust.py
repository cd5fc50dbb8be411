"""The parser on takes it was not tuned on: a person drifting across the volume, standing still
between exercises, a left-then-right exercise; and the confidence a user sees per boundary and
texton (``tvmedit info``). The synthetic actor's frames are reconstructed in memory and turned
into features the way the builder does (the origin follows a person who strays)."""

import json
import subprocess
import sys

import numpy as np
import pytest

from tvmedit.engine.lab import synth
from tvmedit.engine.lab.evaluate import score
from tvmedit.engine.features import FeatureAccumulator, follow_picks, moves_across
from tvmedit.engine.parse.structure import Structure, parse


def _take(drift=(0.0, 0.0), vertices=6000, **plan):
    """(vectors, theta columns, truth) of a synthetic take, its actor moving by ``drift`` m/s."""
    poses, labels, motions, periods = synth.plan(**plan)
    fps = float(plan.get("fps", 10))
    rng = np.random.default_rng(0)
    frames = [synth.make_frame(pose, float(synth.voxel_size(vertices)), rng)[0] + np.array([*drift, 0.0]) * k / fps
              for k, pose in enumerate(poses)]
    picks = follow_picks(len(frames))
    acc = FeatureAccumulator(follow=moves_across([frames[k].mean(axis=0) for k in picks]))
    for verts in frames:
        acc.add(verts)
    f = acc.result()
    starts = [0] + [k for k in range(1, len(labels)) if labels[k] != labels[k - 1]]
    ends = starts[1:] + [len(labels)]
    per = {m: float(np.mean(p)) * fps for m, p in zip(motions, periods)}
    truth = {"fps": fps, "segments": [{"start": a, "end": b - 1} for a, b in zip(starts, ends)],
             "periods_hint": [{"period_frames": per[labels[a]]} for a in starts]}
    return f.vectors, f.theta_columns, truth, acc.follow


@pytest.fixture(scope="module")
def drifting():
    return _take(drift=(0.04, 0.0), motions=["jumping-jacks", "squats", "knee-raises"], cycles=[8, 4, 5], seed=3)


def test_a_person_drifting_across_the_volume_gets_a_cluster_per_exercise(drifting):
    vectors, theta, truth, follows = drifting
    assert follows, "a person 1.5 m away from the start is followed by the origin"
    result = score(parse(vectors, truth["fps"], theta=theta), truth)
    assert (result.precision, result.recall) == (1.0, 1.0), result.matches
    assert result.texton_accuracy == 1.0


def test_a_short_excursion_is_enough_for_the_origin_to_follow():
    # Two seconds of jogging 2.5 m away and back in a 30 s take, as a take may jog in a
    # circle among its exercises: the frames sampled for following must catch it.
    poses, _, _, _ = synth.plan(motions=["jumping-jacks", "squats"], cycles=[16, 10], seed=4)
    rng = np.random.default_rng(0)
    away = lambda k: 2.5 * np.sin(np.pi * (k - 140) / 20) if 140 <= k < 160 else 0.0  # noqa: E731
    frames = [synth.make_frame(pose, float(synth.voxel_size(3000)), rng)[0] + [away(k), 0.0, 0.0]
              for k, pose in enumerate(poses[:300])]
    centres = [frames[k].mean(axis=0) for k in follow_picks(len(frames))]
    assert moves_across(centres), "the excursion was not among the frames sampled"
    steady = [frames[k].mean(axis=0) - [away(k), 0.0, 0.0] for k in follow_picks(len(frames))]
    assert not moves_across(steady), "a person exercising on one spot is not followed"


def test_standing_still_between_exercises_joins_the_next_one():
    vectors, theta, truth, _ = _take(motions=["jumping-jacks", "side-bends", "squats"], cycles=[8, 4, 4],
                                     transition=1.0, still=2.0, seed=5)
    s = parse(vectors, truth["fps"], theta=theta)
    result = score(s, truth)
    assert len(s.clusters) == 3 and (result.precision, result.recall) == (1.0, 1.0), s.clusters
    # Side bends go left then right: a texton is the whole cycle, not one side.
    assert result.texton_accuracy == 1.0


def test_a_transition_into_one_off_movements_joins_them():
    # Twisting, then 2 s of changing pose with 0.5 s standing still, then picking things up
    # (one-offs: no period), at 10 fps and on its spot. The transition joins the pick-ups, so
    # the boundary lies where they begin, not where the twists end.
    vectors, theta, truth, _ = _take(motions=["walk", "twist", "pick-up", "run"], cycles=[4, 3, 3, 5],
                                     transition=2.0, still=0.5, jitter=2.0, seed=182)
    s = parse(vectors, truth["fps"], theta=theta)
    pick_up = truth["segments"][2]["start"]
    nearest = min(abs(start - pick_up) for start, _ in s.clusters)
    assert nearest <= truth["fps"], (s.clusters, truth["segments"])     # within 1 s, as the scorer counts


def test_every_boundary_and_texton_has_a_confidence_that_survives_json(drifting):
    vectors, theta, truth, _ = drifting
    s = parse(vectors, truth["fps"], theta=theta)
    assert len(s.boundary_confidence) == len(s.clusters) and s.boundary_confidence[0] == 1.0
    assert all(0.0 < c <= 1.0 for c in s.boundary_confidence)
    assert all(0.0 <= t.confidence <= 1.0 for t in s.textons)
    # Clean synthetic cycles return to their first pose: most textons are sure.
    assert np.median([t.confidence for t in s.textons]) > 0.5
    again = Structure.from_json(json.dumps(s.to_json()))
    assert again.boundary_confidence == s.boundary_confidence
    assert [t.confidence for t in again.textons] == [t.confidence for t in s.textons]


def test_info_shows_the_confidence_of_each_boundary_and_texton(small_library):
    run = subprocess.run([sys.executable, "-m", "tvmedit", "info", str(small_library), "--json"],
                         capture_output=True, text=True, check=True)
    sequence = json.loads(run.stdout)["sequences"][0]
    assert sequence["clusters"][0]["confidence"] == 1.0
    assert all(0 <= c["confidence"] <= 1 for c in sequence["clusters"])
    assert all(0 <= t["confidence"] <= 1 for t in sequence["textons"])
    text = subprocess.run([sys.executable, "-m", "tvmedit", "info", str(small_library)],
                          capture_output=True, text=True, check=True).stdout
    assert "least sure (confidence 0-1): " in text


def test_a_boundary_after_a_slow_transition_is_where_the_old_one_stopped():
    # 3 s from the last squat to the first run: the novelty peaks more than 1 s into the
    # change; the boundary moves back to where the squats stopped.
    vectors, theta, truth, _ = _take(motions=["squats", "run"], cycles=[4, 10], transition=3.0, seed=7)
    s = parse(vectors, truth["fps"], theta=theta)
    result = score(s, truth)
    assert (result.precision, result.recall) == (1.0, 1.0), (s.clusters, truth["segments"])
    assert abs(s.clusters[1][0] - truth["segments"][1]["start"]) <= 4
