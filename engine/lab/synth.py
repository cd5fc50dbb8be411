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
from pathlib import Path

import numpy as np

from .. import safewrite
from ..errors import InputError
from ..capture.load import SIDECAR, sidecar_json
from ..parallel import Workers, default_workers
from ..checks import number, whole
from ..capture.plyfast import write_ply
from .body import (MATERIALS, NOISE_M, PALETTE, make_frame, primitives, turn_headings,  # noqa: F401 (the actor's API)
                   turned_about)
from .exercises import MOTIONS, POSE, PRESETS, TRANSITION_S, Motion, _pose_at, _timeline  # noqa: F401

#: Most cycles of one motion a take may have (a cycle is a few seconds of frames).
MAX_CYCLES = 1000
VERSION = 3                 # bump when the output for given options changes (3: turns on the feet)
# Voxel size that gives about 16,000 vertices per frame for this body (measured on the
# gym preset); the vertex count grows with the inverse square of the voxel size.
VOXEL_AT_16K = 0.0122


def _frame_job(job):
    out, index, pose, voxel, seed, heading = job
    rng = np.random.default_rng(np.random.SeedSequence([seed, 1, index]))
    verts, faces, colours = make_frame(pose, voxel, rng)
    if heading:
        verts = turned_about(verts, heading).astype(np.float32)     # the actor stands at x = y = 0
    write_ply(Path(out) / f"frame_{index:05d}.ply", verts, faces, colours)
    return index, len(verts)


def _write_frames(jobs, workers, progress, name):
    """Run the frame jobs on worker processes (:class:`tvmedit.engine.parallel.Workers`); vertex counts."""
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
    Returns whether the take is written in place (True) or beside, then renamed into place.

    A folder holding nothing but a previous take is replaced whole, by rename, so that an
    interrupted run leaves the previous take as it was. Where the user's own files stand
    beside the take (or the folder is the current one), the take is written in place: only
    the files a previous ``generate`` wrote (listed in its marker, or for a take made before
    the marker: ``truth.json`` by ``tvmedit synth`` and its frames) are removed first, and
    frames nobody can vouch for are refused.
    """
    out = Path(out)
    safewrite.refuse_inside(out)
    if out.exists() and not out.is_dir():
        raise InputError(f"Output path {out} is a file, not a folder.")
    if not out.exists() or not any(out.iterdir()):
        return safewrite.holds_cwd(out)
    if not overwrite:
        raise InputError(f"Output folder {out} is not empty; pass overwrite=True to replace it.")
    ours = _ours(out)
    theirs = sorted(p.name for p in out.glob("frame_*.ply") if p.name not in ours)
    if theirs:
        raise InputError(f"Output folder {out} holds frames tvmedit did not write "
                         f"({theirs[0]}...), so they are not replaced; choose another folder.")
    if all(path.name in ours for path in out.iterdir()) and not safewrite.holds_cwd(out):
        return False
    # truth.json goes first, so an interrupted run leaves a folder marked incomplete.
    for name in sorted(ours, key=lambda n: n != "truth.json"):
        (out / name).unlink(missing_ok=True)
    return True


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
    out = Path(out)
    files = ["truth.json", SIDECAR, *(f"frame_{k:05d}.ply" for k in range(len(poses)))]
    if _prepare(out, overwrite):
        # Files of the user's stay beside the take: it is written in place, marked as ours
        # before the first frame, so that an interrupted run is still replaced by --overwrite.
        out.mkdir(parents=True, exist_ok=True)
        safewrite.mark(out, "take", files=files)
        return _write_take(out, out, poses, labels, motions, periods, preset, cycles, fps, vertices, seed,
                           workers, progress, rest, turns, files)
    # A take is written beside its name and renamed into place: an interrupted run leaves
    # nothing, or the previous take, never a folder of some of its frames.
    if out.is_dir() and not any(out.iterdir()):
        out.rmdir()
    with safewrite.replacing_folder(out) as folder:
        return _write_take(out, folder, poses, labels, motions, periods, preset, cycles, fps, vertices, seed,
                           workers, progress, rest, turns, files)


def _write_take(out, folder, poses, labels, motions, periods, preset, cycles, fps, vertices, seed, workers,
                progress, rest, turns, files):
    """Write the take's frames, ``sequence.json``, ``truth.json`` and marker into ``folder``
    (``out`` itself, or the temporary folder that becomes it); returns the truth."""
    voxel = float(voxel_size(vertices))
    headings = turn_headings(len(poses), fps, turns, seed)
    jobs = [(str(folder), k, pose, voxel, seed, float(h)) for k, (pose, h) in enumerate(zip(poses, headings))]
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
    safewrite.write_text(folder / SIDECAR, sidecar_json(fps))
    safewrite.write_text(folder / "truth.json", json.dumps(truth, indent=1))
    safewrite.mark(folder, "take", files=files)
    return truth
