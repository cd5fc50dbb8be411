"""Synthetic capture actor: a procedural human whose frames are made as a capture studio makes them.

A smooth implicit body (ellipsoids and tapered capsules joined by a polynomial smooth-min) is
posed by cyclic procedural motions. Each frame's surface is reconstructed on its own, with
marching cubes on a voxel grid that has a random sub-voxel offset per frame, so the vertex
count and the connectivity change every frame, as in the paper's TVM (Xu, Yamasaki, Aizawa
2009, sec. 1). Vertices carry a little Gaussian noise and the colour of their garment.

Conventions: Z up, metres, feet on z = 0, subject about 1.70 m tall, facing -Y; the actor
moves on the spot (walking and running as on a treadmill), so a histogram of vertex positions
about the first frame's centroid sees only the motion.

Boxing, toe touches, twists, knee raises, side bends and side reaches go left then right within
a cycle, as the CMU mocap6 exercises of those names do; toe touches with both hands and up-downs
(a deep crouch, then a jump with the arms overhead), mocap6's other two, once a cycle. Kicks (front kicks
with the left leg, standing in guard between them) and hops on both feet are done as HDM05's
single-repetition clips of those names are.

Timeline: each motion is repeated for a number of cycles whose period and amplitude jitter a
little from cycle to cycle (a lot for the one-off movements, putting something on the floor
and reaching up, whose repetitions each go somewhere else) (and, with :func:`plan`'s ``rest``, a pause may follow each
cycle, as people pause between repetitions); between two motions a transition of
``TRANSITION_S`` blends the last pose of one into the first pose of the next. Transition
frames are labelled with the motion they lead *into*, so each segment of ``truth.json``
starts where the actor starts to change exercise. The random state of the timeline depends
only on the seed, and that of a frame (grid offset, vertex and colour noise) only on the seed
and the frame index, so any number of workers writes byte-identical files.

>>> sorted(MOTIONS)[:7]
['arm-circles', 'box', 'hop', 'jumping-jacks', 'kick', 'knee-raises', 'pick-up']
>>> sorted(MOTIONS)[7:]
['reach-up', 'run', 'side-bends', 'side-reach', 'squats', 'toe-touch', 'toe-touch-both', 'twist', 'up-down', 'walk']
>>> PRESETS["gym"]["motions"][0], PRESETS["walk"]["motions"]
('walk', ['walk'])
"""

import json
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .. import safewrite
from ..errors import InputError
from ..capture.load import SIDECAR, sidecar_json
from ..store.parallel import Workers, default_workers
from ..checks import number, whole
from ..capture.plyfast import write_ply

#: Most cycles of one motion a take may have (a cycle is a few seconds of frames).
MAX_CYCLES = 1000
VERSION = 3                 # bump when the output for given options changes (3: turns on the feet)
TRANSITION_S = 0.8          # blend between two motions, seconds
NOISE_M = 0.002             # Gaussian vertex noise, metres
PERIOD_JITTER = 0.04        # relative standard deviation of a cycle's period
AMPLITUDE_JITTER = 0.06     # relative standard deviation of a cycle's amplitude
SPREAD_PERIOD = 0.35        # largest relative change of a one-off movement's period (Motion.spread)
SPREAD_AMPLITUDE = 0.5      # largest change of a one-off movement's amplitude
# Voxel size that gives about 16,000 vertices per frame for this body (measured on the
# gym preset); the vertex count grows with the inverse square of the voxel size.
VOXEL_AT_16K = 0.0122


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


# Axes of the rest pose: forward (the subject faces -Y), the subject's left, and up.
F, L, U = np.array([0.0, -1.0, 0.0]), np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0])
SKIN, HAIR, SHIRT, TROUSERS, SHOES = range(5)
PALETTE = np.array([[222, 170, 138], [62, 42, 30], [40, 92, 170], [48, 52, 68], [236, 236, 232]],
                   dtype=float)
MATERIALS = ["skin", "hair", "shirt", "trousers", "shoes"]
BLEND = 0.03                # smooth-min radius, metres


def _rot(axis, angle):
    c, s = np.cos(angle), np.sin(angle)
    i, j = {"x": (1, 2), "y": (2, 0), "z": (0, 1)}[axis]
    r = np.eye(3)
    r[i, i] = r[j, j] = c
    r[j, i], r[i, j] = s, -s
    return r


def _limb(side_axis, fwd, up, flex, abd):
    """Unit direction of a limb that hangs down, swung out by abd and forward by flex, and the
    unit direction perpendicular to it in the swing plane (forward when hanging)."""
    d = np.cos(abd) * (-np.cos(flex) * up + np.sin(flex) * fwd) + np.sin(abd) * side_axis
    n = np.sin(flex) * up + np.cos(flex) * fwd
    return d, n


def primitives(pose, build=1.0):
    """Primitives of the posed body, feet resting on z = 0 (plus the pose's jump lift).

    ``build`` scales the radii of the trunk and limbs (0.8 slim, 1.3 heavy).

    Returns a list of tuples ``("cap", a, b, ra, rb, part)`` (tapered capsule from a to b)
    and ``("ell", centre, axes (3, 3) columns, radii (3,), part)``; part names the body
    part, which decides the colour.
    """
    p = dict(zip(POSE, pose))
    trunk = _rot("z", p["yaw"]) @ _rot("y", p["roll"]) @ _rot("x", p["pitch"])
    pelvis = _rot("z", 0.4 * p["yaw"])
    tf, tl, tu = trunk @ F, trunk @ L, trunk @ U
    prims = []
    root = np.zeros(3)
    prims.append(("ell", root + 0.02 * U, pelvis, np.array([0.165, 0.11, 0.11]), "pelvis"))
    prims.append(("ell", root + tu * 0.17, trunk, np.array([0.145, 0.10, 0.13]), "belly"))
    prims.append(("ell", root + tu * 0.36 - tf * 0.005, trunk, np.array([0.175, 0.11, 0.15]), "chest"))
    neck = root + tu * 0.49
    head = neck + tu * 0.16 + tf * 0.015
    prims.append(("cap", neck, neck + tu * 0.10, 0.052, 0.048, "neck"))
    prims.append(("ell", head, trunk, np.array([0.078, 0.095, 0.106]), "head"))
    shoulder = {}
    for s, side in ((1.0, "l"), (-1.0, "r")):
        shoulder[side] = root + tu * 0.46 + tl * (0.175 * s)
    prims.append(("cap", shoulder["l"], shoulder["r"], 0.058, 0.058, "girdle"))
    feet = []
    for s, side in ((1.0, "l"), (-1.0, "r")):
        arm, n = _limb(tl * s, tf, tu, p["sh_flex_" + side], p["sh_abd_" + side])
        elbow = shoulder[side] + 0.29 * arm
        e = p["elbow_" + side]
        fore = np.cos(e) * arm + np.sin(e) * n
        wrist = elbow + 0.25 * fore
        prims.append(("cap", shoulder[side], elbow, 0.05, 0.04, "upperarm"))
        prims.append(("cap", elbow, wrist, 0.038, 0.03, "forearm"))
        prims.append(("cap", wrist + 0.02 * fore, wrist + 0.1 * fore, 0.034, 0.03, "hand"))
        pf, pl = pelvis @ F, pelvis @ L
        hip = root + pl * (0.09 * s) - 0.06 * U
        thigh, n = _limb(pl * s, pf, U, p["hip_flex_" + side], p["hip_abd_" + side])
        knee = hip + 0.42 * thigh
        k = p["knee_" + side]
        shin = np.cos(k) * thigh - np.sin(k) * n
        ankle = knee + 0.41 * shin
        prims.append(("cap", hip, knee, 0.085, 0.055, "thigh"))
        prims.append(("cap", knee, ankle, 0.052, 0.038, "shin"))
        toe = p["toe_" + side]
        foot = np.cos(toe) * pf - np.sin(toe) * U
        heel = ankle - 0.045 * pf - 0.035 * U
        tip = ankle + 0.16 * foot - 0.025 * U
        prims.append(("cap", heel, tip, 0.042, 0.036, "foot"))
        feet += [heel, tip, ankle]
    # Feet rest on the floor, centred under the body (or the right foot, as "plant" says),
    # unless the actor jumps.
    feet = np.array(feet)
    sole = min(feet[0::3, 2].min() - 0.042, feet[1::3, 2].min() - 0.036)
    shift = np.array([-feet[2::3, 0].mean(), -feet[2::3, 1].mean(), p["lift"] - sole])
    if p["plant"]:
        # Where the body's centre would be were the left foot the right one's mirror image:
        # the right ankle moved onto the pelvis's mid-plane.
        side = pelvis @ L
        right = feet[5] - (feet[5] @ side) * side
        shift[:2] = (1 - p["plant"]) * shift[:2] - p["plant"] * right[:2]
    moved = []
    for prim in prims:
        if prim[0] == "cap":
            moved.append(("cap", prim[1] + shift, prim[2] + shift, prim[3] * build, prim[4] * build, prim[5]))
        else:
            moved.append(("ell", prim[1] + shift, prim[2], prim[3] * build, prim[4]))
    return moved


def _part_material(part, local, t):
    """Material of vertices nearest one primitive (local coords for the head, t for arms)."""
    if part == "head":
        hair = (local[:, 2] > 0.015) | ((local[:, 1] > 0.02) & (local[:, 2] > -0.045))
        return np.where(hair, HAIR, SKIN)
    if part == "upperarm":
        return np.where(t < 0.5, SHIRT, SKIN)
    return {"pelvis": TROUSERS, "belly": SHIRT, "chest": SHIRT, "neck": SKIN, "girdle": SHIRT,
            "forearm": SKIN, "hand": SKIN, "thigh": TROUSERS, "shin": TROUSERS, "foot": SHOES}[part]


def _distance(prim, x, y, z):
    """Signed distance of one primitive (negative inside) and, for capsules, the position t
    along the axis; x, y, z broadcast (grid axes or flat vertex coordinates)."""
    if prim[0] == "cap":
        _, a, b, ra, rb, _ = prim
        ba = b - a
        qx, qy, qz = x - a[0], y - a[1], z - a[2]
        t = np.clip((qx * ba[0] + qy * ba[1] + qz * ba[2]) / (ba @ ba + 1e-12), 0.0, 1.0)
        d = np.sqrt((qx - t * ba[0]) ** 2 + (qy - t * ba[1]) ** 2 + (qz - t * ba[2]) ** 2)
        return d - (ra + (rb - ra) * t), t
    _, c, axes, r, _ = prim
    qx, qy, qz = x - c[0], y - c[1], z - c[2]
    k0 = k1 = 0.0
    for i in range(3):
        q = qx * axes[0, i] + qy * axes[1, i] + qz * axes[2, i]
        k0 = k0 + (q / r[i]) ** 2
        k1 = k1 + (q / r[i] ** 2) ** 2
    k0 = np.sqrt(k0)
    return k0 * (k0 - 1.0) / (np.sqrt(k1) + 1e-9), None


def _bounds(prim):
    if prim[0] == "cap":
        _, a, b, ra, rb, _ = prim
        r = max(ra, rb)
        return np.minimum(a, b) - r, np.maximum(a, b) + r
    _, c, axes, r, _ = prim
    half = np.sqrt(((axes * r) ** 2).sum(axis=1))
    return c - half, c + half


def _field(prims, h, origin, shape):
    """Smooth-min of all primitives on the grid ``origin + h * index``; each primitive is
    evaluated only inside its own bounding box (grown by the blend radius)."""
    field = np.full(shape, 1.0, dtype=np.float32)
    k = np.float32(BLEND)
    for prim in prims:
        lo, hi = _bounds(prim)
        i0 = np.maximum(np.floor((lo - BLEND - origin) / h).astype(int), 0)
        i1 = np.minimum(np.ceil((hi + BLEND - origin) / h).astype(int) + 1, shape)
        axes = [(origin[i] + h * np.arange(i0[i], i1[i])).astype(np.float32) for i in range(3)]
        d, _ = _distance(prim, axes[0][:, None, None], axes[1][None, :, None], axes[2][None, None, :])
        sub = field[i0[0]:i1[0], i0[1]:i1[1], i0[2]:i1[2]]
        w = np.clip(0.5 + (sub - d) / (2 * k), 0.0, 1.0)
        sub[...] = sub + w * (d - sub) - k * w * (1.0 - w)
    return field


def make_frame(pose, voxel, rng, build=1.0, noise=NOISE_M):
    """One reconstructed frame of the actor in the given pose (``build``: see :func:`primitives`;
    ``noise``: standard deviation of the vertex noise, metres).

    Returns ``vertices (V, 3) float32``, ``faces (F, 3) int32`` (outward winding) and
    ``colours (V, 3) uint8``.
    """
    from skimage.measure import marching_cubes

    prims = primitives(pose, build)
    boxes = np.array([_bounds(p) for p in prims])
    lo, hi = boxes[:, 0].min(axis=0) - 2 * voxel, boxes[:, 1].max(axis=0) + 2 * voxel
    origin = lo - rng.uniform(0.0, voxel, 3)
    shape = tuple(np.ceil((hi - origin) / voxel).astype(int) + 1)
    field = _field(prims, voxel, origin, shape)
    verts, faces, _, _ = marching_cubes(field, 0.0, spacing=(voxel,) * 3,
                                        gradient_direction="descent", allow_degenerate=False)
    verts = verts + origin + rng.normal(0.0, noise, verts.shape)
    colours = _colours(prims, verts, rng)
    return verts.astype(np.float32), faces.astype(np.int32), colours


def turn_headings(n, fps, turns, seed=0):
    """The heading (radians) of an actor who turns to face another way now and then.

    Every 5-10 s at random the actor turns by 1/2 to 1 times ``turns`` degrees to either side,
    over 1 s (smoothly), as people do between repetitions; 0 at every frame where ``turns`` is
    0. ``n`` frames at ``fps``; the turns' own random numbers (from ``seed``) leave every
    other draw of a take as it was.

    >>> h = np.degrees(turn_headings(300, 10.0, 90.0, seed=1))
    >>> float(h[0]), bool(np.abs(np.diff(h)).max() > 5), bool(np.abs(np.diff(h)[:40]).max() == 0)
    (0.0, True, True)
    """
    t = np.arange(n) / fps
    heading = np.zeros(n)
    if not turns or n == 0:
        return heading
    rng = np.random.default_rng(seed + 2000)
    at = rng.uniform(5.0, 10.0)
    while at < t[-1]:
        angle = np.radians(turns) * rng.uniform(0.5, 1.0) * rng.choice([-1.0, 1.0])
        x = np.clip(t - at, 0.0, 1.0)
        heading = heading + angle * x * x * (3 - 2 * x)
        at += 1.0 + rng.uniform(5.0, 10.0)
    return heading


def turned_about(verts, angle, at=(0.0, 0.0)):
    """Vertices (Z up) turned by ``angle`` radians about the vertical through ``at`` (x, y).

    ``at`` is the spot the person turns on: people turn on their feet. Until VERSION 3 each
    frame turned about its own centre, which moves with the pose (0.1-0.2 m as the actor bends
    to touch its toes): the feet slid by up to twice that in a turn of 180 degrees, and a
    turned left-right exercise lost its mirror symmetry about any fixed point.

    >>> v = np.array([[0.2, 0.0, 1.0], [0.0, 0.0, 0.0]])          # a hand out front, a foot
    >>> np.round(turned_about(v, np.pi), 6).tolist()              # the foot stays where it was
    [[-0.2, 0.0, 1.0], [0.0, 0.0, 0.0]]
    """
    centre = np.array([at[0], at[1], 0.0])
    return (np.asarray(verts) - centre) @ _rot("z", angle).T + centre


def _colours(prims, verts, rng):
    """Garment colour of the nearest primitive, with a little brightness and hue noise."""
    x, y, z = verts.T
    dist = np.empty((len(prims), len(verts)))
    ts = []
    for i, prim in enumerate(prims):
        dist[i], t = _distance(prim, x, y, z)
        ts.append(t)
    nearest = dist.argmin(axis=0)
    material = np.empty(len(verts), dtype=int)
    for i, prim in enumerate(prims):
        sel = nearest == i
        if not sel.any():
            continue
        part = prim[-1]
        local = (verts[sel] - prim[1]) @ prim[2] if prim[0] == "ell" else None
        t = ts[i][sel] if ts[i] is not None else None
        material[sel] = _part_material(part, local, t)
    colour = PALETTE[material] * rng.uniform(0.92, 1.06, (len(verts), 1))
    colour += rng.normal(0.0, 3.0, colour.shape)
    return np.clip(np.rint(colour), 0, 255).astype(np.uint8)


def _frame_job(job):
    out, index, pose, voxel, seed, heading = job
    rng = np.random.default_rng(np.random.SeedSequence([seed, 1, index]))
    verts, faces, colours = make_frame(pose, voxel, rng)
    if heading:
        verts = turned_about(verts, heading).astype(np.float32)     # the actor stands at x = y = 0
    write_ply(Path(out) / f"frame_{index:05d}.ply", verts, faces, colours)
    return index, len(verts)


def _write_frames(jobs, workers, progress, name):
    """Run the frame jobs on worker processes (:class:`tvmedit.engine.store.parallel.Workers`); vertex counts."""
    from tqdm import tqdm

    counts = [0] * len(jobs)
    with Workers(min(workers or default_workers(), len(jobs))) as pool, \
            tqdm(total=len(jobs), unit="frame", desc=f"synth {name}", disable=not progress) as bar:
        for index, count in pool.map(_frame_job, jobs):
            counts[index] = count
            bar.update()
    return counts


def _segments(labels):
    segments, start = [], 0
    for i in range(1, len(labels) + 1):
        if i == len(labels) or labels[i] != labels[start]:
            segments.append({"start": start, "end": i - 1, "label": labels[start]})
            start = i
    return segments


def _acf_at(poses, lag):
    """Normalised autocorrelation of a pose sequence (T, len(POSE)) at an integer lag; angles
    enter as cosine and sine, so a full turn (arm circles) counts as no change, and the lift
    and "plant" (the last column) as they are."""
    x = np.hstack([poses[:, :1], np.cos(poses[:, 1:-1]), np.sin(poses[:, 1:-1]), poses[:, -1:]])
    x = x - x.mean(axis=0)
    if lag < 1 or lag >= len(x):
        return None
    den = (x * x).sum()
    return float((x[:-lag] * x[lag:]).sum() / den * len(x) / (len(x) - lag)) if den > 0 else None


def plan(preset="gym", motions=None, cycles=None, fps=10, seed=0, periods_s=None,
         transition=TRANSITION_S, still=0.0, jitter=1.0, rest=0.0):
    """Pose and label of every frame, without reconstructing any surface.

    Returns ``(poses, labels, motions, periods)``: poses ``(N, len(POSE)) float``, one label
    per frame, the motion names in order, and each motion's cycle periods in seconds.
    ``cycles`` is one count for every motion or a list of one per motion; ``periods_s``
    (one mean period per motion, seconds), ``transition`` (seconds of blend between two
    motions), ``still`` (seconds standing at rest within each transition), ``jitter``
    (scale of the cycle-to-cycle spread) and ``rest`` (longest pause after each cycle,
    seconds; its periods then count the pauses) vary the timeline (see :func:`_timeline`).

    >>> poses, labels, motions, periods = plan("walk")
    >>> poses.shape[1] == len(POSE), labels[0], len(periods[0])
    (True, 'walk', 9)
    """
    if preset not in PRESETS:
        raise InputError(f"Unknown preset '{preset}'; choose one of {', '.join(PRESETS)}.")
    motions = list(PRESETS[preset]["motions"] if motions is None else motions)
    unknown = [m for m in motions if m not in MOTIONS]
    if unknown or not motions:
        raise InputError(f"Unknown motion '{unknown[0] if unknown else ''}'; "
                         f"choose from {', '.join(MOTIONS)}.")
    each = cycles if isinstance(cycles, (list, tuple)) else [cycles] * len(motions)
    counts = [whole("cycles", c, at_least=1, at_most=MAX_CYCLES) if c is not None
              else PRESETS[preset]["cycles"].get(m, MOTIONS[m].cycles) for c, m in zip(each, motions)]
    periods_s = None if periods_s is None else [number("periods_s", x, above=0.05, at_most=60) for x in periods_s]
    if len(each) != len(motions) or (periods_s is not None and len(periods_s) != len(motions)):
        raise InputError(f"cycles and periods_s take one value for each of the {len(motions)} motions.")
    fps = number("fps", fps, above=0, at_most=120)
    whole("seed", seed, at_least=0, at_most=2 ** 32 - 1)
    transition = number("transition", transition, above=0, at_most=60)
    still = number("still", still, at_least=0, at_most=600)
    jitter = number("jitter", jitter, at_least=0, at_most=5)
    rest = number("rest", rest, at_least=0, at_most=60)
    pieces, periods, total = _timeline(motions, counts, seed, periods_s, transition, still, jitter, rest)
    n = max(1, int(round(total * fps)))
    poses, labels = [], []
    for k in range(n):
        pose, m = _pose_at(pieces, motions, min(k / fps, total))
        poses.append(pose)
        labels.append(motions[m])
    return np.array(poses), labels, motions, periods


def voxel_size(vertices):
    """Grid spacing (metres) that gives about ``vertices`` vertices per frame."""
    return VOXEL_AT_16K * np.sqrt(16000.0 / vertices)


def _prepare(out, overwrite):
    """Make ``out`` ready for a take: new, empty, or (with ``overwrite``) a take of ours.

    Only the files a previous ``generate`` wrote (listed in its marker, or for a take made
    before the marker: ``truth.json`` by ``tvmedit synth`` and its frames) are removed;
    anything else in the folder stays, and frames nobody can vouch for are refused.
    """
    out = Path(out)
    safewrite.refuse_inside(out)
    if out.exists() and not out.is_dir():
        raise InputError(f"Output path {out} is a file, not a folder.")
    if out.exists() and any(out.iterdir()):
        if not overwrite:
            raise InputError(f"Output folder {out} is not empty; pass overwrite=True to replace it.")
        ours = _ours(out)
        theirs = sorted(p.name for p in out.glob("frame_*.ply") if p.name not in ours)
        if theirs:
            raise InputError(f"Output folder {out} holds frames tvmedit did not write "
                             f"({theirs[0]}...), so they are not replaced; choose another folder.")
        # truth.json goes first, so an interrupted run leaves a folder marked incomplete.
        for name in sorted(ours, key=lambda n: n != "truth.json"):
            (out / name).unlink(missing_ok=True)
    out.mkdir(parents=True, exist_ok=True)
    return out


def _ours(out):
    """Names of the files a previous take wrote into ``out``."""
    if safewrite.owner(out) == "take":
        return set(safewrite.marked_files(out)) | {safewrite.MARKER}
    try:
        tool = json.loads((out / "truth.json").read_text())["generator"]["tool"]
    except (OSError, ValueError, KeyError, TypeError):
        return set()
    return {"truth.json", *(p.name for p in out.glob("frame_*.ply"))} if tool == "tvmedit synth" else set()


def generate(out, preset="gym", motions=None, cycles=None, fps=10, vertices=16000, seed=0,
             workers=None, overwrite=False, progress=True, rest=0.0, turns=0.0):
    """Write a synthetic TVM take into folder ``out`` and return its truth (``truth.json``).

    ``out/frame_00000.ply, ...`` are binary PLY frames; ``sequence.json`` gives their frame
    rate (``{"fps": fps}``, which :func:`tvmedit.engine.capture.load.open_sequence` reads); ``truth.json``
    (written last, by rename) holds fps, frames, per-frame labels, segments
    ``{start, end (inclusive), label}``, ``periods_hint`` (the true mean period of each
    segment), ``vertex_counts`` and the generator settings. ``motions`` (names from
    :data:`MOTIONS`) and ``cycles`` override the preset; ``rest`` (seconds) pauses the actor
    after each cycle for up to that long, at random, and the periods then count the pauses
    (:func:`plan`); ``turns`` (degrees) turns the actor to face another way every 5-10 s
    (:func:`turn_headings`). Files are identical for any number of ``workers`` (default: all
    cores).
    """
    vertices = whole("vertices", vertices, at_least=1000, at_most=1_000_000)
    turns = number("turns", turns, at_least=0, at_most=180, hint=" degrees")
    if workers is not None:
        workers = whole("workers", workers, at_least=1, at_most=1024)
    poses, labels, motions, periods = plan(preset, motions, cycles, fps, seed, rest=rest)
    out = _prepare(out, overwrite)
    voxel = float(voxel_size(vertices))
    headings = turn_headings(len(poses), fps, turns, seed)
    jobs = [(str(out), k, pose, voxel, seed, float(h)) for k, (pose, h) in enumerate(zip(poses, headings))]
    counts = _write_frames(jobs, workers, progress, out.name)
    segments = _segments(labels)
    hints = []
    for seg in segments:
        per = periods[motions.index(seg["label"])]
        period_s = float(np.mean(per))
        lag = int(round(period_s * fps))
        acf = _acf_at(poses[seg["start"]:seg["end"] + 1], lag)
        hints.append({**seg, "period_s": round(period_s, 4), "period_frames": round(period_s * fps, 3),
                      "acf_peak": None if acf is None else round(acf, 3)})
    truth = {
        "source": PRESETS[preset]["source"] if motions == PRESETS[preset]["motions"]
        else f"tvmedit synth ({', '.join(motions)})",
        "fps": fps,
        "frames": len(jobs),
        "labels": labels,
        "segments": segments,
        "periods_hint": hints,
        "periods_hint_note": "true mean period of the segment's cycles (the actor's timeline); "
                             "acf_peak is the pose autocorrelation at that lag",
        "transitions": f"the {TRANSITION_S} s blend between two motions is labelled with the "
                       "motion it leads into",
        "coordinates": "Z up, metres, feet on z = 0; subject faces -Y and moves on the spot"
                       + (f", turning to face another way every 5-10 s (by {turns / 2:g}-{turns:g} degrees)"
                          if turns else ""),
        "vertex_counts": counts,
        "generator": {"tool": "tvmedit synth", "version": VERSION, "preset": preset,
                      "motions": motions, "cycles": cycles, "seed": seed, "vertices": vertices,
                      "voxel_m": round(voxel, 6), "noise_m": NOISE_M,
                      "transition_s": TRANSITION_S, "rest_s": rest, "turns_deg": turns, "cycle_periods_s": [
                          [round(p, 4) for p in per] for per in periods]},
    }
    # The frame rate beside the frames, where `tvmedit build` reads it (PLY frames carry none).
    safewrite.write_text(out / SIDECAR, sidecar_json(fps))
    safewrite.write_text(out / "truth.json", json.dumps(truth, indent=1))
    safewrite.mark(out, "take", files=["truth.json", SIDECAR,
                                    *(f"frame_{k:05d}.ply" for k in range(len(jobs)))])
    return truth
