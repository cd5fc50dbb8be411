"""The synthetic actor's exercises: a pose for every phase of a cycle, and a take's timeline.

A pose is a small vector (:data:`POSE`): a jump's lift, joint angles and which foot the body
stands on. Each motion of :data:`MOTIONS` maps a cycle's phase (0 to 1) and an amplitude to a
pose. Boxing, toe touches, twists, knee raises, side bends and side reaches go left then right
within a cycle, as the CMU mocap6 exercises of those names do; toe touches with both hands and
up-downs once a cycle; kicks and hops as HDM05's single-repetition clips do. A take's timeline
(:func:`_timeline`) repeats each motion for a number of cycles whose period and amplitude
jitter a little (a lot for the one-off movements), with a transition of :data:`TRANSITION_S`
blending one motion's last pose into the next one's first.
"""

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

TRANSITION_S = 0.8          # blend between two motions, seconds
PERIOD_JITTER = 0.04        # relative standard deviation of a cycle's period
AMPLITUDE_JITTER = 0.06     # relative standard deviation of a cycle's amplitude
SPREAD_PERIOD = 0.35        # largest relative change of a one-off movement's period (Motion.spread)
SPREAD_AMPLITUDE = 0.5      # largest change of a one-off movement's amplitude


# A pose is a small vector: jump lift (metres), joint angles (radians), named below, and
# "plant": 0 stands the body centred between its feet, 1 places it by the right foot alone (a
# kick with the left leg: the foot the actor stands on stays put, whatever the left leg does;
# with the legs alike, as in a kick's guard, both place the body alike, so nothing slides as
# the actor moves into or out of kicking).
POSE = ["lift", "pitch", "roll", "yaw",
        "hip_flex_l", "hip_abd_l", "knee_l", "toe_l", "sh_flex_l", "sh_abd_l", "elbow_l",
        "hip_flex_r", "hip_abd_r", "knee_r", "toe_r", "sh_flex_r", "sh_abd_r", "elbow_r", "plant"]
_IX = {name: i for i, name in enumerate(POSE)}


def _pose(**values):
    """Pose vector from keyword values; arms hang slightly away from the body by default."""
    p = np.zeros(len(POSE))
    p[_IX["sh_abd_l"]] = p[_IX["sh_abd_r"]] = 0.15
    p[_IX["elbow_l"]] = p[_IX["elbow_r"]] = 0.15
    p[_IX["hip_abd_l"]] = p[_IX["hip_abd_r"]] = 0.04
    for name, value in values.items():
        p[_IX[name]] = value
    return p


# Each motion maps a phase in [0, 1) of one full cycle and an amplitude (about 1) to a pose.
# Phase 0 is the pose a cycle starts and ends in. The actor is a little asymmetric (left arm
# swings more, bends go deeper to the left), as people are, so a full cycle is never two
# mirror-image halves that a vertex histogram could not tell apart.

def _walk(phase, a):
    th = 2 * np.pi * phase
    swing_l, swing_r = max(0.0, np.cos(th)) ** 1.5, max(0.0, -np.cos(th)) ** 1.5
    return _pose(hip_flex_l=0.38 * a * np.sin(th), hip_flex_r=-0.38 * a * np.sin(th),
                 knee_l=0.08 + 0.65 * a * swing_l, knee_r=0.08 + 0.65 * a * swing_r,
                 toe_l=0.25 * swing_l, toe_r=0.25 * swing_r,
                 sh_flex_l=-0.40 * a * np.sin(th), sh_flex_r=0.28 * a * np.sin(th),
                 elbow_l=0.3 + 0.2 * max(0.0, -np.sin(th)), elbow_r=0.3 + 0.2 * max(0.0, np.sin(th)),
                 yaw=0.07 * a * np.sin(th), pitch=0.04, roll=0.03 * np.cos(th))


def _run(phase, a):
    th = 2 * np.pi * phase
    swing_l, swing_r = max(0.0, np.cos(th)), max(0.0, -np.cos(th))
    return _pose(hip_flex_l=-0.15 + 0.75 * a * max(-0.45, np.sin(th + 0.4)),
                 hip_flex_r=-0.15 + 0.75 * a * max(-0.45, -np.sin(th + 0.4)),
                 knee_l=0.3 + 1.3 * a * swing_l, knee_r=0.3 + 1.3 * a * swing_r,
                 toe_l=0.35, toe_r=0.35,
                 sh_flex_l=-0.5 * a * np.sin(th), sh_flex_r=0.38 * a * np.sin(th),
                 elbow_l=1.55, elbow_r=1.45, sh_abd_l=0.25, sh_abd_r=0.2,
                 lift=0.06 * a * np.sin(th) ** 2, pitch=0.15, yaw=0.1 * a * np.sin(th))


def _jumping_jacks(phase, a):
    th = 2 * np.pi * phase
    open_ = (1 - np.cos(th)) / 2
    return _pose(hip_abd_l=0.05 + 0.32 * a * open_, hip_abd_r=0.05 + 0.30 * a * open_,
                 sh_abd_l=0.15 + 2.75 * a * open_, sh_abd_r=0.15 + 2.6 * a * open_,
                 elbow_l=0.1 + 0.15 * open_, elbow_r=0.1 + 0.2 * open_,
                 knee_l=0.15 * open_, knee_r=0.15 * open_,
                 toe_l=0.3 * abs(np.sin(th)), toe_r=0.3 * abs(np.sin(th)),
                 lift=0.08 * a * abs(np.sin(th)))


def _arm_circles(phase, a):
    # Both arms sweep one big circle: down, forward, overhead, back, down.
    th = 2 * np.pi * phase
    return _pose(sh_flex_l=th, sh_flex_r=th - 0.25 * np.sin(th),
                 sh_abd_l=0.35 + 0.15 * a * np.sin(th / 2) ** 2, sh_abd_r=0.3 + 0.1 * a * np.sin(th / 2) ** 2,
                 elbow_l=0.05, elbow_r=0.1,
                 pitch=-0.06 * a * np.sin(th), knee_l=0.1 + 0.1 * np.sin(th) ** 2,
                 knee_r=0.1 + 0.1 * np.sin(th) ** 2, hip_flex_l=0.05, hip_flex_r=0.05,
                 hip_abd_l=0.1, hip_abd_r=0.1)


def _squats(phase, a):
    # Going down takes 60 % of the cycle, coming up 40 %.
    u = phase / 0.6 if phase < 0.6 else 1 + (phase - 0.6) / 0.4
    depth = a * (1 - np.cos(np.pi * u)) / 2
    return _pose(knee_l=1.95 * depth, knee_r=1.95 * depth,
                 hip_flex_l=1.45 * depth, hip_flex_r=1.45 * depth,
                 hip_abd_l=0.14, hip_abd_r=0.14, pitch=0.5 * depth,
                 sh_flex_l=1.5 * depth + 0.1, sh_flex_r=1.4 * depth + 0.1,
                 sh_abd_l=0.15, sh_abd_r=0.15, elbow_l=0.1, elbow_r=0.1)


def _side_bends(phase, a):
    # Bend to the left with the right arm overhead, then to the right with the left arm up.
    th = 2 * np.pi * phase
    left, right = max(0.0, np.sin(th)), max(0.0, -np.sin(th))
    return _pose(roll=a * (0.55 * left - 0.45 * right),
                 sh_abd_r=0.15 + 2.75 * a * left, sh_abd_l=0.15 + 2.65 * a * right,
                 elbow_r=0.15 + 0.5 * left, elbow_l=0.15 + 0.5 * right,
                 sh_flex_l=0.1 * left, sh_flex_r=0.1 * right,
                 hip_abd_l=0.16, hip_abd_r=0.16)


def _knee_raises(phase, a):
    # The left knee comes up to the right elbow, then the right knee to the left elbow.
    th = 2 * np.pi * phase
    left, right = max(0.0, np.sin(th)), max(0.0, -np.sin(th))
    return _pose(hip_flex_l=1.5 * a * left, knee_l=1.7 * a * left, hip_flex_r=1.4 * a * right,
                 knee_r=1.6 * a * right, yaw=0.35 * a * (left - right), pitch=0.2 * (left + right),
                 sh_flex_l=0.6 + 0.3 * right, sh_flex_r=0.6 + 0.3 * left, elbow_l=1.9, elbow_r=1.9)


def _box(phase, a):
    # Boxing: a jab with the left fist, back to the guard, then one with the right; the
    # trunk turns into each punch and the knees stay bent.
    th = 2 * np.pi * phase
    left, right = max(0.0, np.sin(th)) ** 1.5, max(0.0, -np.sin(th)) ** 1.5
    return _pose(sh_flex_l=0.75 + 0.8 * a * left, sh_flex_r=0.7 + 0.75 * a * right,
                 elbow_l=2.2 - 2.0 * a * left, elbow_r=2.25 - 1.9 * a * right,
                 sh_abd_l=0.25 - 0.1 * left, sh_abd_r=0.25 - 0.1 * right,
                 yaw=0.35 * a * (right - 0.9 * left), pitch=0.12, knee_l=0.3, knee_r=0.3,
                 hip_flex_l=0.2, hip_flex_r=0.12, hip_abd_l=0.12, hip_abd_r=0.12)


def _toe_touch(phase, a):
    # Bend down and touch the left foot with the right hand, up, then the right foot with the
    # left hand; the other arm swings up behind.
    th = 2 * np.pi * phase
    left, right = max(0.0, np.sin(th)), max(0.0, -np.sin(th))
    return _pose(pitch=1.45 * a * (left + 0.95 * right), yaw=0.45 * a * (left - right),
                 sh_flex_r=0.15 + 1.25 * left, sh_flex_l=0.15 + 1.2 * right,
                 sh_abd_l=0.15 + 1.6 * a * left, sh_abd_r=0.15 + 1.5 * a * right,
                 elbow_l=0.15, elbow_r=0.15, hip_abd_l=0.3, hip_abd_r=0.3,
                 knee_l=0.1 * (left + right), knee_r=0.1 * (left + right))


def _twist(phase, a):
    # The trunk turns left and right over still hips, arms held out, elbows a little bent.
    th = 2 * np.pi * phase
    return _pose(yaw=a * (0.75 * np.sin(th) - 0.05 * np.sin(th) ** 2), sh_abd_l=1.45, sh_abd_r=1.4,
                 elbow_l=0.35 + 0.1 * max(0.0, np.sin(th)), elbow_r=0.35 + 0.1 * max(0.0, -np.sin(th)),
                 sh_flex_l=0.15, sh_flex_r=0.2, hip_abd_l=0.16, hip_abd_r=0.16)


def _kick(phase, a):
    # A front kick with the left leg from a guard, as HDM05's kickLFront clips are done: the
    # knee comes up, the leg snaps out straight and back, the foot comes down, and the actor
    # stands in guard for the rest of the cycle (0.4 of it) before the next kick.
    s = min(phase / 0.6, 1.0)
    lift, snap = np.sin(np.pi * s) ** 2, np.sin(np.pi * s) ** 8
    return _pose(plant=1.0, hip_flex_l=1.5 * a * lift, knee_l=1.6 * lift - 1.5 * min(a, 1.05) * snap, toe_l=0.4 * snap,
                 knee_r=0.15 * lift, hip_flex_r=-0.05 * lift, pitch=-0.12 * lift, yaw=0.1 * lift,
                 sh_flex_l=0.55, sh_flex_r=0.5 + 0.15 * lift, elbow_l=1.9, elbow_r=1.95,
                 sh_abd_l=0.25, sh_abd_r=0.2 + 0.1 * lift)


def _hop(phase, a):
    # A hop on both feet, as HDM05's hopBothLegs clips are: down into a crouch, up off the floor
    # with the arms swung forward, down into a crouch again, and up to standing.
    crouch = (np.sin(np.pi * phase / 0.3) ** 2 if phase < 0.3 else 0.0) + \
        (np.sin(np.pi * (phase - 0.55) / 0.35) ** 2 if 0.55 <= phase < 0.9 else 0.0)
    air = np.sin(np.pi * (phase - 0.25) / 0.35) if 0.25 <= phase < 0.6 else 0.0
    return _pose(knee_l=0.1 + 1.0 * a * crouch, knee_r=0.1 + 0.95 * a * crouch,
                 hip_flex_l=0.7 * a * crouch, hip_flex_r=0.7 * a * crouch, pitch=0.3 * a * crouch,
                 lift=0.16 * a * air, toe_l=0.5 * air, toe_r=0.5 * air,
                 sh_flex_l=0.2 + 1.1 * air - 0.4 * crouch, sh_flex_r=0.2 + 0.95 * air - 0.4 * crouch,
                 elbow_l=0.3, elbow_r=0.3)


def _side_reach(phase, a):
    # Reach out to the left: lean left with the left arm stretched out to the side at shoulder
    # height, the left knee bent (that foot lifts a little: the actor stands on the straight
    # leg) and the right hand in front of the hip; back to standing, then the same to the
    # right (mocap6's SideReach). The same arm leads as the body leans, where a side bend
    # lifts the other arm overhead.
    th = 2 * np.pi * phase
    left, right = max(0.0, np.sin(th)), max(0.0, -np.sin(th))
    return _pose(roll=a * (0.38 * left - 0.32 * right),
                 sh_abd_l=0.15 + 1.85 * a * left, sh_abd_r=0.15 + 1.75 * a * right,
                 sh_flex_l=0.25 * left, sh_flex_r=0.25 * right,
                 elbow_l=0.15 + 0.9 * right, elbow_r=0.15 + 0.9 * left,
                 knee_l=0.1 + 0.6 * a * left, knee_r=0.1 + 0.55 * a * right,
                 hip_flex_l=0.3 * a * left, hip_flex_r=0.3 * a * right,
                 hip_abd_l=0.22 + 0.12 * left, hip_abd_r=0.22 + 0.12 * right)


def _toe_touch_both(phase, a):
    # Bend forward, both hands down to the shins (as deep as toe-touch's one hand goes), come
    # up on the toes with both arms overhead, arms back down (mocap6's ToeTouchTwoHands): one
    # symmetric cycle, where toe-touch reaches each hand to the other foot in turn.
    down = np.sin(np.pi * phase / 0.6) ** 2 if phase < 0.6 else 0.0
    up = np.sin(np.pi * (phase - 0.5) / 0.5) ** 2 if phase >= 0.5 else 0.0
    return _pose(pitch=1.4 * a * down - 0.12 * up, knee_l=0.15 * down, knee_r=0.15 * down,
                 sh_flex_l=0.15 + 1.2 * down + 2.6 * a * up, sh_flex_r=0.15 + 1.15 * down + 2.5 * a * up,
                 sh_abd_l=0.15 + 0.2 * up, sh_abd_r=0.15 + 0.2 * up, elbow_l=0.12, elbow_r=0.12,
                 hip_abd_l=0.12, hip_abd_r=0.12, toe_l=0.25 * up, toe_r=0.25 * up)


def _up_down(phase, a):
    # Down into a deep crouch with the hands low in front of the knees, then up in a jump with
    # both arms thrown overhead, land, give a little at the knees and stand (mocap6's UpDown):
    # a hop's course, deeper and slower, with the arms up.
    crouch = np.sin(np.pi * phase / 0.5) ** 2 if phase < 0.5 else 0.0
    crouch += 0.4 * np.sin(np.pi * (phase - 0.72) / 0.28) ** 2 if phase >= 0.72 else 0.0
    air = np.sin(np.pi * (phase - 0.42) / 0.32) if 0.42 <= phase < 0.74 else 0.0
    return _pose(knee_l=0.1 + 1.9 * a * crouch, knee_r=0.1 + 1.85 * a * crouch,
                 hip_flex_l=1.5 * a * crouch, hip_flex_r=1.5 * a * crouch, pitch=0.6 * a * crouch,
                 lift=0.2 * a * air, toe_l=0.6 * air, toe_r=0.6 * air,
                 sh_flex_l=0.1 + 1.1 * crouch + 2.7 * air, sh_flex_r=0.1 + 1.05 * crouch + 2.6 * air,
                 sh_abd_l=0.15 + 0.25 * air, sh_abd_r=0.15 + 0.25 * air, elbow_l=0.2, elbow_r=0.2,
                 hip_abd_l=0.1, hip_abd_r=0.1)


def _ease(phase, up, top):
    # 0 -> 1 over [0, up), 1 over [up, top), 1 -> 0 over [top, 1): a one-off movement's course.
    if phase < up:
        return (1 - np.cos(np.pi * phase / up)) / 2
    if phase < top:
        return 1.0
    return (1 + np.cos(np.pi * (phase - top) / (1 - top))) / 2


# One-off movements: each repetition goes somewhere else, as a person putting things on the
# floor or taking them off a shelf does (HDM05's depositFloorR and grabHighR clips). The
# amplitude, spread wide for these (Motion.spread), sets how far round the body turns, how it
# leans and how deep or high it reaches; the cycle starts and ends standing, whatever it is.

def _pick_up(phase, a):
    # Bend down and put something on the floor with the right hand, a moment there, back up.
    d, side = _ease(phase, 0.45, 0.6), a - 1
    return _pose(pitch=(1.25 + 0.3 * side) * d, yaw=1.6 * side * d, roll=(0.5 * side - 0.2) * d,
                 hip_flex_l=0.8 * d, hip_flex_r=0.8 * d, knee_l=(1.1 + 0.5 * side) * d,
                 knee_r=(1.1 - 0.3 * side) * d, hip_abd_l=0.08, hip_abd_r=0.08,
                 sh_flex_r=0.1 + 1.5 * d, sh_abd_r=0.15 + 0.2 * d, elbow_r=0.15,
                 sh_flex_l=0.1 + 0.35 * d, elbow_l=0.15 + 0.5 * d)


def _reach_up(phase, a):
    # Reach up high with the right hand, rising on the toes, a moment there, back down.
    r, side = _ease(phase, 0.4, 0.55), a - 1
    return _pose(sh_flex_r=0.15 + (2.5 + 0.4 * side) * r, sh_abd_r=0.15 + 0.6 * max(0.0, side) * r,
                 elbow_r=0.15 + 0.8 * r * (1 - r), yaw=1.4 * side * r, roll=-0.45 * side * r,
                 pitch=-0.1 * r, toe_l=(0.25 + 0.4 * side) * r, toe_r=(0.3 + 0.4 * side) * r,
                 sh_abd_l=0.15 + 0.3 * r, elbow_l=0.15 + 0.3 * r)


@dataclass(frozen=True)
class Motion:
    """A repeated motion: pose function of (phase, amplitude), mean period and default cycles.

    ``spread`` scales the cycle-to-cycle spread of its period and amplitude: 1 for exercises,
    wider for one-off movements, whose repetitions differ (see :func:`_timeline`).
    """

    pose: Callable[[float, float], np.ndarray]
    period_s: float
    cycles: int
    spread: float = 1.0


MOTIONS = {
    "walk": Motion(_walk, 1.1, 9),
    "run": Motion(_run, 0.8, 12),
    "jumping-jacks": Motion(_jumping_jacks, 1.0, 10),
    "arm-circles": Motion(_arm_circles, 1.5, 7),
    "squats": Motion(_squats, 2.2, 5),
    "side-bends": Motion(_side_bends, 2.5, 4),
    "knee-raises": Motion(_knee_raises, 1.8, 5),
    "pick-up": Motion(_pick_up, 2.4, 4, spread=4.0),
    "reach-up": Motion(_reach_up, 2.0, 4, spread=4.0),
    "box": Motion(_box, 1.0, 8),
    "toe-touch": Motion(_toe_touch, 3.0, 4),
    "twist": Motion(_twist, 2.0, 5),
    "kick": Motion(_kick, 1.4, 6),
    "hop": Motion(_hop, 0.9, 8),
    "side-reach": Motion(_side_reach, 2.4, 4),
    "toe-touch-both": Motion(_toe_touch_both, 2.6, 4),
    "up-down": Motion(_up_down, 1.8, 6),
}

PRESETS = {
    "walk": {"motions": ["walk"], "cycles": {"walk": 9},
             "source": "tvmedit synth walk (procedural actor, like the paper's Walk)"},
    "gym": {"motions": ["walk", "run", "jumping-jacks", "arm-circles", "squats", "side-bends"],
            "cycles": {}, "source": "tvmedit synth gym (procedural actor, like the paper's BroadGym)"},
}


def _timeline(motions, counts, seed, periods_s=None, transition=TRANSITION_S, still=0.0, jitter=1.0,
              rest=0.0):
    """Pieces ``(kind, motion_index, t0, duration, amp0, amp1)`` back to back, the cycle
    periods (seconds) of each motion, and the total duration. kind is "cycle", "transition"
    (into ``motion_index``), "still" (standing at rest before ``motion_index``) or "hold"
    (a pause after a cycle, in the pose it ended in); amp0 and amp1 are the amplitudes at
    the start and end of a cycle, so the amplitude changes smoothly from one cycle to the
    next. ``periods_s`` overrides each motion's mean period, ``jitter`` scales the
    cycle-to-cycle spread of period and amplitude (times the motion's ``spread``, within
    :data:`SPREAD_PERIOD` and :data:`SPREAD_AMPLITUDE`, for one-off movements), ``still``
    seconds of standing at rest split each transition in two halves (into the rest pose and
    out), and each cycle is followed by a pause of ``rest`` times a uniform random fraction,
    as people pause between repetitions (a cycle's period then counts its pause: the time
    from one repetition's start to the next)."""
    rng = np.random.default_rng(np.random.SeedSequence([seed, 0]))
    # Pauses draw from a generator of their own, so a take without them is as before.
    pauses = np.random.default_rng(np.random.SeedSequence([seed, 1]))
    pieces, periods, t = [], [], 0.0
    for m, (name, n) in enumerate(zip(motions, counts)):
        mean = MOTIONS[name].period_s if periods_s is None else periods_s[m]
        dev = jitter * np.clip(rng.normal(0, PERIOD_JITTER, n), -0.1, 0.1)
        adev = jitter * np.clip(rng.normal(0, AMPLITUDE_JITTER, n + 1), -0.15, 0.15)
        spread = MOTIONS[name].spread
        if spread != 1:
            dev = np.clip(spread * dev, -SPREAD_PERIOD, SPREAD_PERIOD)
            adev = np.clip(spread * adev, -SPREAD_AMPLITUDE, SPREAD_AMPLITUDE)
        per, amp = mean * (1 + dev), 1 + adev
        if m > 0:
            steps = [("transition", transition)] if still <= 0 else [
                ("transition", transition / 2), ("still", still), ("transition", transition / 2)]
            for kind, dur in steps:
                pieces.append((kind, m, t, dur, 0.0, 0.0))
                t += dur
        hold = rest * pauses.random(n) if rest > 0 else np.zeros(n)
        for i in range(n):
            pieces.append(("cycle", m, t, float(per[i]), float(amp[i]), float(amp[i + 1])))
            t += float(per[i])
            if hold[i] > 0:
                pieces.append(("hold", m, t, float(hold[i]), float(amp[i + 1]), float(amp[i + 1])))
                t += float(hold[i])
        periods.append([float(p) for p in per + hold])
    return pieces, periods, t


def _piece_pose(pieces, motions, j, end):
    """Pose at the start (``end`` False) or end of a cycle, hold or still piece ``j``."""
    kind, m, _, _, amp0, amp1 = pieces[j]
    return _pose() if kind == "still" else MOTIONS[motions[m]].pose(0.0, amp1 if end else amp0)


def _pose_at(pieces, motions, t):
    """Pose vector at time t (seconds) and the index of the motion it belongs to."""
    for j, (kind, m, t0, dur, amp0, amp1) in enumerate(pieces):
        if t < t0 + dur or j == len(pieces) - 1:
            u = min(max((t - t0) / max(dur, 1e-9), 0.0), 1.0)
            if kind == "cycle":
                return MOTIONS[motions[m]].pose(u % 1.0, amp0 + (amp1 - amp0) * u), m
            if kind in ("still", "hold"):
                return _piece_pose(pieces, motions, j, False), m
            before = _piece_pose(pieces, motions, j - 1, True)
            after = _piece_pose(pieces, motions, j + 1, False)
            w = u * u * (3 - 2 * u)
            return (1 - w) * before + w * after, m
    raise AssertionError("empty timeline")
