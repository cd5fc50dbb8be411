"""The synthetic capture actor: frames as a capture studio makes them, and a truth that matches."""

import json
import subprocess
import sys

import numpy as np
import pytest
import trimesh

from tvmedit.engine.lab import synth
from tvmedit.engine.errors import InputError
from interrupt import default_sigint


def _frame(folder, k):
    return trimesh.load(folder / f"frame_{k:05d}.ply", process=False)


def _truth(folder):
    return json.loads((folder / "truth.json").read_text())


@pytest.fixture(scope="module")
def gym_vertices(synth_gym):
    return [np.asarray(_frame(synth_gym, k).vertices) for k in range(_truth(synth_gym)["frames"])]


def _descriptor(vertices, centre):
    """Histograms of vertex (r, theta, phi) about a centre, as the analysis uses."""
    q = vertices - centre
    r = np.linalg.norm(q, axis=1)
    theta = np.arccos(np.clip(q[:, 2] / r, -1, 1))
    phi = np.arctan2(q[:, 1], q[:, 0])
    hist = [np.histogram(r, 32, (0, 1.2))[0], np.histogram(theta, 32, (0, np.pi))[0],
            np.histogram(phi, 32, (-np.pi, np.pi))[0]]
    return np.concatenate(hist) / len(vertices)


def _dominant_lag(x):
    """Lag (frames, interpolated) of the first local maximum of the autocorrelation that comes
    within 80 % of the highest one (a multiple of the period can score as high)."""
    x = x - x.mean(axis=0)
    n = len(x)
    acf = np.array([(x[:n - lag] * x[lag:]).sum() / (n - lag) for lag in range(n)])
    acf /= acf[0]
    peaks = [lag for lag in range(2, int(0.6 * n)) if acf[lag - 1] < acf[lag] >= acf[lag + 1]]
    best = next(lag for lag in peaks if acf[lag] >= 0.8 * max(acf[peaks]))
    y0, y1, y2 = acf[best - 1:best + 2]
    return best + 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2)


def test_vertex_count_and_connectivity_change_every_frame(synth_walk):
    truth = _truth(synth_walk)
    meshes = [_frame(synth_walk, k) for k in range(5)]
    counts = [len(m.vertices) for m in meshes]
    assert counts == truth["vertex_counts"][:5]
    assert len(set(truth["vertex_counts"])) > truth["frames"] // 2
    assert not np.array_equal(meshes[0].faces[:100], meshes[1].faces[:100])
    assert 12000 < np.mean(truth["vertex_counts"]) < 20000


def test_actor_stands_on_the_floor_and_is_a_closed_surface(synth_walk):
    for k in (0, 33, 66):
        mesh = _frame(synth_walk, k)
        (_, _, bottom), (_, _, top) = mesh.bounds
        assert abs(bottom) < 0.02
        assert 1.6 < top < 1.8
        assert mesh.is_watertight and mesh.volume > 0.04   # outward normals, about 60 litres


def test_truth_agrees_with_the_frames_written(synth_gym):
    truth = _truth(synth_gym)
    n = truth["frames"]
    assert n >= 300 and truth["fps"] == 10          # six motions, three cycles each
    assert len(list(synth_gym.glob("frame_*.ply"))) == n
    assert len(truth["labels"]) == len(truth["vertex_counts"]) == n
    segments = truth["segments"]
    assert [s["label"] for s in segments] == PRESET_GYM
    assert segments[0]["start"] == 0 and segments[-1]["end"] == n - 1
    for before, after in zip(segments, segments[1:]):
        assert after["start"] == before["end"] + 1
    for s in segments:
        assert set(truth["labels"][s["start"]:s["end"] + 1]) == {s["label"]}
    periods = [h["period_s"] for h in truth["periods_hint"]]
    assert min(periods) < 0.9 and max(periods) > 2.3
    assert len(_frame(synth_gym, n - 1).vertices) == truth["vertex_counts"][-1]


PRESET_GYM = ["walk", "run", "jumping-jacks", "arm-circles", "squats", "side-bends"]


def test_each_motion_repeats_at_the_period_in_truth(synth_gym, gym_vertices):
    truth = _truth(synth_gym)
    centre = gym_vertices[0].mean(axis=0)
    descriptors = np.array([_descriptor(v, centre) for v in gym_vertices])
    blend = round(synth.TRANSITION_S * truth["fps"])
    for hint in truth["periods_hint"]:
        start = hint["start"] + (blend if hint["start"] else 0)
        lag = _dominant_lag(descriptors[start:hint["end"] + 1])
        assert lag == pytest.approx(hint["period_frames"], rel=0.1), hint["label"]


def test_motions_differ_in_shape_not_only_in_timing(synth_gym, gym_vertices):
    truth = _truth(synth_gym)
    centre = gym_vertices[0].mean(axis=0)
    descriptors = np.array([_descriptor(v, centre) for v in gym_vertices])
    labels = np.array(truth["labels"])
    means = np.array([descriptors[labels == name].mean(axis=0) for name in PRESET_GYM])
    gaps = np.linalg.norm(means[:, None] - means[None], axis=2)
    spread = np.mean([np.linalg.norm(descriptors[labels == name] - means[i], axis=1).mean()
                      for i, name in enumerate(PRESET_GYM)])
    assert gaps[~np.eye(len(PRESET_GYM), dtype=bool)].min() > 0.5 * spread


def test_shoes_skin_shirt_and_trousers_are_coloured(synth_walk):
    mesh = _frame(synth_walk, 10)
    colours = np.asarray(mesh.visual.vertex_colors)[:, :3].astype(float)
    nearest = np.argmin(np.linalg.norm(colours[:, None] - synth.PALETTE[None], axis=2), axis=1)
    share = np.bincount(nearest, minlength=len(synth.PALETTE)) / len(nearest)
    for name in ("skin", "hair", "shirt", "trousers", "shoes"):
        assert share[synth.MATERIALS.index(name)] > 0.01, name
    shoes = nearest == synth.MATERIALS.index("shoes")
    assert mesh.vertices[shoes, 2].max() < 0.2


def test_one_seed_gives_identical_files_for_any_number_of_workers(tmp_path):
    options = dict(motions=["jumping-jacks"], cycles=1, fps=4, vertices=3000, progress=False)
    one = synth.generate(tmp_path / "one", workers=1, **options)
    two = synth.generate(tmp_path / "two", workers=2, **options)
    synth.generate(tmp_path / "other", seed=1, workers=2, **options)
    assert one == two and one["frames"] >= 4
    for k in range(one["frames"]):
        name = f"frame_{k:05d}.ply"
        assert (tmp_path / "one" / name).read_bytes() == (tmp_path / "two" / name).read_bytes()
        assert (tmp_path / "one" / name).read_bytes() != (tmp_path / "other" / name).read_bytes()
    assert (tmp_path / "one" / "truth.json").read_bytes() == (tmp_path / "two" / "truth.json").read_bytes()


def test_a_non_empty_folder_needs_overwrite(tmp_path):
    (tmp_path / "notes.txt").write_text("mine")
    with pytest.raises(InputError, match=r"not empty; pass overwrite=True") as error:
        synth.generate(tmp_path, motions=["squats"], cycles=1, fps=2, vertices=2000, progress=False)
    assert str(error.value).count(". ") == 0 and "\n" not in str(error.value)
    cli = subprocess.run([sys.executable, "-m", "tvmedit", "synth", "--motions", "squats", "--cycles", "1",
                          "--fps", "2", "--vertices", "2000", "--out", str(tmp_path), "-q"],
                         capture_output=True, text=True)
    assert cli.returncode == 2
    assert cli.stderr.startswith("error: ") and cli.stderr.count("\n") == 1
    assert not (tmp_path / "truth.json").exists()
    truth = synth.generate(tmp_path, motions=["squats"], cycles=1, fps=2, vertices=2000,
                           overwrite=True, progress=False)
    assert (tmp_path / "truth.json").exists() and (tmp_path / "notes.txt").exists()
    assert len(list(tmp_path.glob("frame_*.ply"))) == truth["frames"]


def test_unknown_motion_names_the_choices(tmp_path):
    with pytest.raises(InputError, match="Unknown motion 'yoga'; choose from walk, run"):
        synth.generate(tmp_path, motions=["walk", "yoga"], progress=False)
    assert not any(tmp_path.iterdir())


def test_cli_help_runs():
    result = subprocess.run([sys.executable, "-m", "tvmedit", "synth", "--help"],
                            capture_output=True, text=True)
    assert result.returncode == 0
    for option in ("--preset", "--motions", "--cycles", "--rest", "--turns", "--vertices", "--workers", "--overwrite"):
        assert option in result.stdout


def test_ctrl_c_is_reported_once_by_the_parent(tmp_path):
    import os
    import signal
    import time

    out = tmp_path / "walk"
    process = subprocess.Popen([sys.executable, "-m", "tvmedit", "synth", "--preset", "walk", "--out", str(out),
                                "--workers", "2", "--vertices", "16000", "-q"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               start_new_session=True, preexec_fn=default_sigint)
    deadline = time.monotonic() + 60
    # The take is written beside its name (.walk.tmp-PID) and renamed into place at the end.
    while not list(tmp_path.glob(".walk.*/frame_*.ply")) and time.monotonic() < deadline and process.poll() is None:
        time.sleep(0.05)
    assert process.poll() is None, "synth ended before it could be interrupted"
    os.killpg(process.pid, signal.SIGINT)  # what Ctrl-C does: the whole foreground group
    _, err = process.communicate(timeout=60)
    assert process.returncode == 130
    assert err == "interrupted\n"
    assert list(tmp_path.iterdir()) == []


def test_pauses_between_repetitions_hold_the_pose_and_count_in_the_period():
    # rest: the actor pauses after each repetition, in the pose the repetition ended in; a
    # period runs from one repetition's start to the next, pause included.
    kw = dict(motions=["squats"], cycles=6, fps=10, seed=4)
    poses0, _, _, periods0 = synth.plan(**kw)
    poses, labels, _, periods = synth.plan(rest=1.5, **kw)
    # no rest: the timeline as before pauses existed (figures of the plan made then)
    assert (len(poses0), round(float(poses0.sum()), 4)) == (132, 804.5255)
    gym = synth.plan("gym", seed=3)[0]
    assert (len(gym), round(float(gym.sum()), 4), round(float(np.abs(gym).sum()), 4)) == (653, 3036.276, 3317.3317)
    added = np.array(periods[0]) - np.array(periods0[0])
    assert np.all(added >= 0) and np.all(added <= 1.5) and added.sum() > 2.0, added
    assert len(poses) == pytest.approx(len(poses0) + 10 * added.sum(), abs=2)
    # a pause: frames that do not move, all in the pose a squat starts and ends in
    still = np.flatnonzero(np.abs(np.diff(poses, axis=0)).max(axis=1) < 1e-9)
    assert len(still) >= 10 * added.sum() - 12
    assert np.allclose(poses[still], poses[0], atol=0.2)
    with pytest.raises(ValueError, match="rest"):
        synth.plan(rest=-1, **kw)


def test_a_turn_over_half_a_circle_is_refused_before_any_write(tmp_path):
    with pytest.raises(ValueError, match="turns=200"):
        synth.generate(tmp_path / "t", motions=["squats"], cycles=1, turns=200, vertices=2000, progress=False)
    assert not (tmp_path / "t").exists()


def test_a_take_that_pauses_is_made_from_the_command_line(tmp_path):
    # tvmedit synth --rest: the actor pauses after each squat; truth.json's periods count the
    # pauses and record the setting, and a bad value is one sentence with nothing written.
    args = [sys.executable, "-m", "tvmedit", "synth", "--motions", "squats", "--cycles", "3", "--fps", "4",
            "--vertices", "2000", "--seed", "5", "-q"]
    plain = subprocess.run(args + ["--out", str(tmp_path / "plain")], capture_output=True, text=True)
    paused = subprocess.run(args + ["--rest", "1.5", "--out", str(tmp_path / "paused")], capture_output=True,
                            text=True)
    assert plain.returncode == paused.returncode == 0, paused.stderr
    a, b = _truth(tmp_path / "plain"), _truth(tmp_path / "paused")
    assert b["generator"]["rest_s"] == 1.5 and a["generator"]["rest_s"] == 0.0
    assert b["frames"] > a["frames"] and len(list((tmp_path / "paused").glob("frame_*.ply"))) == b["frames"]
    assert b["periods_hint"][0]["period_s"] > a["periods_hint"][0]["period_s"]
    bad = subprocess.run(args + ["--rest", "-1", "--out", str(tmp_path / "bad")], capture_output=True, text=True)
    assert bad.returncode != 0 and "rest" in bad.stderr and bad.stderr.count("\n") == 1, bad.stderr
    assert not (tmp_path / "bad").exists()


def _right_hand_height(pose):
    # Height of the right hand's tip (the last "hand" capsule is the right one).
    hand = [p for p in synth.primitives(pose) if p[-1] == "hand"][-1]
    return float(hand[2][2])


def test_one_off_movements_go_somewhere_else_each_time_and_start_standing():
    # pick-up and reach-up stand for putting things on the floor and taking them off a shelf:
    # each repetition turns the body another way and lasts another time (spread 4: much more
    # than an exercise's repetitions), reaches the floor or above the head, and starts and
    # ends standing, so repetitions join without a jump.
    for name, low in (("pick-up", True), ("reach-up", False)):
        poses, labels, _, periods = synth.plan(motions=[name, "squats"], cycles=[8, 8], fps=20, seed=6)
        mine = poses[np.array(labels) == name]
        yaw = mine[:, synth.POSE.index("yaw")]
        starts = np.concatenate([[0], np.round(np.cumsum(periods[0])[:-1] * 20).astype(int)])
        extreme = [yaw[a: b][np.argmax(np.abs(yaw[a: b]))] for a, b in zip(starts, list(starts[1:]) + [len(yaw)])]
        assert np.ptp(extreme) > 0.5, extreme   # turned between about -0.8 and 0.8 rad
        spread = lambda p: np.std(p) / np.mean(p)  # noqa: E731
        assert spread(periods[0]) > 2 * spread(periods[1]), periods
        standing = synth.MOTIONS[name].pose(0.0, 1.0)   # whatever the repetition's amplitude
        assert np.abs(mine[starts] - standing).max() < 0.05
        for a in (0.5, 0.8, 1.2, 1.5):
            assert np.allclose(synth.MOTIONS[name].pose(0.0, a), standing)
            assert np.allclose(synth.MOTIONS[name].pose(1 - 1e-9, a), standing, atol=1e-6)
        heights = [_right_hand_height(p) for p in mine]
        assert (min(heights) < 0.5) if low else (max(heights) > 1.9), (min(heights), max(heights))


def test_a_take_made_at_another_rate_is_built_at_that_rate(tmp_path):
    # PLY frames carry no frame rate: tvmedit synth writes it beside them (sequence.json),
    # where tvmedit build reads it, so a 5 fps take is not read as 10 fps (its periods and
    # playback twice too fast); an overwrite replaces it with the rest of the take.
    from tvmedit.engine.capture.load import open_sequence
    out = tmp_path / "slow"
    synth.generate(out, motions=["squats"], cycles=1, fps=5, vertices=1500, workers=1, progress=False)
    assert open_sequence(out).fps == 5
    synth.generate(out, motions=["squats"], cycles=1, fps=8, vertices=1500, workers=1, progress=False,
                   overwrite=True)
    assert open_sequence(out).fps == 8 and json.loads((out / "sequence.json").read_text()) == {"fps": 8}


def _hand(pose, side):
    # The tip of the left ("l") or right ("r") hand: the "hand" capsules come left, then right.
    hands = [p for p in synth.primitives(pose) if p[-1] == "hand"]
    return hands[0 if side == "l" else 1][2]


def test_boxing_toe_touches_and_twists_go_left_then_right():
    # The CMU mocap6 exercises the other motions lack, each done with one side and then the
    # other within a cycle: a jab with the left fist then the right (the fist comes forward,
    # -y, at a quarter and three quarters of the cycle), the right hand to the floor by the
    # left foot then the left hand by the right foot, and the trunk turned one way then the other.
    box = synth.MOTIONS["box"].pose
    guard = _hand(box(0.0, 1.0), "l")[1]
    assert _hand(box(0.25, 1.0), "l")[1] < guard - 0.3 and _hand(box(0.75, 1.0), "r")[1] < guard - 0.3
    assert _hand(box(0.25, 1.0), "r")[1] > _hand(box(0.25, 1.0), "l")[1] + 0.3   # the other fist stays back
    touch = synth.MOTIONS["toe-touch"].pose
    standing = min(_hand(touch(0.0, 1.0), s)[2] for s in "lr")
    assert min(_hand(touch(0.25, 1.0), s)[2] for s in "lr") < standing - 0.3
    assert min(_hand(touch(0.75, 1.0), s)[2] for s in "lr") < standing - 0.3
    yaw = synth.POSE.index("yaw")
    twist = [synth.MOTIONS["twist"].pose(p, 1.0)[yaw] for p in (0.25, 0.75)]
    assert twist[0] > 0.5 and twist[1] < -0.5, twist
    for name in ("box", "toe-touch", "twist"):   # a cycle ends where the next one starts
        assert np.allclose(synth.MOTIONS[name].pose(0.0, 1.0), synth.MOTIONS[name].pose(1 - 1e-9, 1.0), atol=1e-6)


def _toe_tip(pose, side):
    # The tip of the left ("l") or right ("r") foot: the "foot" capsules come left, then right.
    feet = [p for p in synth.primitives(pose) if p[-1] == "foot"]
    return feet[0 if side == "l" else 1][2]


def test_a_kick_is_the_left_leg_out_in_front_and_a_hop_leaves_the_floor():
    # HDM05's kickLFront and hopBothLegs, done as its single-repetition clips are: the left foot
    # comes up in front (-y) to about hip height while the right stays where it stands, then the
    # actor stands in guard; a hop takes both feet off the floor, and both land again. No
    # other motion moves the body by one foot ("plant"), so their frames are as they were.
    kick, hop = synth.MOTIONS["kick"].pose, synth.MOTIONS["hop"].pose
    standing = _toe_tip(kick(0.0, 1.0), "l")
    out = _toe_tip(kick(0.3, 1.0), "l")
    assert out[1] < standing[1] - 0.6 and out[2] > 0.6, out
    support = [_toe_tip(kick(phase, 1.0), "r") for phase in (0.0, 0.15, 0.3, 0.45)]
    assert np.allclose(support, support[0], atol=0.01)                # the foot stood on stays put
    assert np.allclose(kick(0.8, 1.0), kick(0.0, 1.0))           # in guard between kicks
    floor = min(_toe_tip(hop(0.0, 1.0), s)[2] for s in "lr")
    up = min(_toe_tip(hop(0.42, 1.0), s)[2] for s in "lr")
    assert up > floor + 0.1, up
    assert max(_toe_tip(hop(0.72, 1.0), s)[2] for s in "lr") < floor + 0.03      # landed, in a crouch
    plant = synth.POSE.index("plant")
    assert not synth.plan("gym")[0][:, plant].any()
    assert all(m.pose(phase, 1.0)[plant] == 0 for name, m in synth.MOTIONS.items() if name != "kick"
               for phase in np.linspace(0, 1, 9, endpoint=False))
    for name in ("kick", "hop"):   # a cycle ends where the next one starts
        assert np.allclose(synth.MOTIONS[name].pose(0.0, 1.0), synth.MOTIONS[name].pose(1 - 1e-9, 1.0), atol=1e-6)


def test_side_reaches_toe_touches_with_both_hands_and_up_downs():
    # The other mocap6 exercises, as the fresh batch "mocap6-rest" uses them: a side reach has
    # the left hand out to the left (+x) and up, then the right hand out to the right, each
    # while the other stays in; a toe touch with both hands brings both down, then both over
    # the head; an up-down crouches with the hands low, then jumps with both feet off the
    # floor and both hands over the head.
    reach = synth.MOTIONS["side-reach"].pose
    assert _hand(reach(0.25, 1.0), "l")[0] > _hand(reach(0.0, 1.0), "l")[0] + 0.5
    assert _hand(reach(0.75, 1.0), "r")[0] < _hand(reach(0.0, 1.0), "r")[0] - 0.5
    assert abs(_hand(reach(0.25, 1.0), "r")[0]) < 0.4 and abs(_hand(reach(0.75, 1.0), "l")[0]) < 0.4
    both = synth.MOTIONS["toe-touch-both"].pose
    standing = _hand(both(0.0, 1.0), "l")[2]
    assert all(_hand(both(0.3, 1.0), s)[2] < standing - 0.3 for s in "lr")
    assert all(_hand(both(0.75, 1.0), s)[2] > 1.8 for s in "lr")
    up_down = synth.MOTIONS["up-down"].pose
    floor = min(_toe_tip(up_down(0.0, 1.0), s)[2] for s in "lr")
    assert all(_hand(up_down(0.25, 1.0), s)[2] < standing - 0.3 for s in "lr")
    assert min(_toe_tip(up_down(0.58, 1.0), s)[2] for s in "lr") > floor + 0.1
    assert all(_hand(up_down(0.58, 1.0), s)[2] > 1.8 for s in "lr")
    for name in ("side-reach", "toe-touch-both", "up-down"):   # a cycle ends where the next one starts
        assert np.allclose(synth.MOTIONS[name].pose(0.0, 1.0), synth.MOTIONS[name].pose(1 - 1e-9, 1.0), atol=1e-6)


def test_a_turning_actor_turns_on_its_feet(tmp_path):
    # tvmedit synth --turns: the actor turns to face another way now and then while touching
    # its toes. People turn on their feet: the feet (the lowest vertices) stay on their spot
    # through every turn. Turned about each frame's own centre, which moves 0.1-0.2 m with the
    # pose, they slid by up to 0.4 m (synth VERSION 2), and the development suite's turning
    # takes had that artefact.
    from tvmedit.engine.capture.load import open_sequence, read_frame
    out = tmp_path / "turning"
    synth.generate(out, motions=["toe-touch"], cycles=4, turns=180.0, vertices=3000, seed=2, progress=False)
    sequence = open_sequence(str(out))
    feet, centres = [], []
    for path in sequence.paths:
        v = read_frame(path, sequence.orientation, "geometry").positions
        feet.append(v[v[:, 2] < v[:, 2].min() + 0.08, :2].mean(axis=0))
        centres.append(v[:, :2].mean(axis=0))
    feet, centres = np.array(feet), np.array(centres)
    heading = synth.turn_headings(len(feet), 10.0, 180.0, seed=2)
    assert np.ptp(heading) > np.radians(90)                         # it does turn
    assert np.ptp(np.linalg.norm(centres - centres[0], axis=1)) > 0.15   # and bends
    slid = np.linalg.norm(feet - feet[0], axis=1).max()
    assert slid < 0.12, slid        # the ankles stay put; the toes, 0.1 m in front of them, turn


def test_an_interrupted_synth_leaves_nothing_and_a_rerun_makes_the_take(tmp_path):
    """Ctrl-C after the fifth frame: neither the take's folder nor a temporary one is left."""
    import signal

    from interrupt import run_signalled

    out = tmp_path / "take"
    args = ["synth", "--motions", "squats", "--cycles", "2", "--fps", "5", "--vertices", "1500",
            "--workers", "1", "--out", out, "-q"]
    result = run_signalled(args, at="tvmedit.engine.lab.synth:write_ply", after=5, signum=signal.SIGINT)
    assert result.returncode != 0 and "Traceback" not in result.stderr, result.stderr
    assert list(tmp_path.iterdir()) == []
    again = subprocess.run([sys.executable, "-m", "tvmedit", *map(str, args)], capture_output=True, text=True)
    assert again.returncode == 0, again.stderr
    assert (out / "truth.json").exists() and len(list(out.glob("frame_*.ply"))) == json.loads(
        (out / "truth.json").read_text())["frames"]
