"""The development suite's takes as data: feature rows computed once and cached, and their truth.

A take of the suite (:mod:`tvmedit.engine.lab.devsuite`) is its feature rows (about 10 a second),
its azimuth columns, its rate and its truth (segments and periods), which
:func:`tvmedit.engine.lab.evaluate.score` reads. Rows of frames written to disk are read once and
cached under ``.cache/devsuite`` (keyed by the frames and the code that reads them); the axes
they are computed in (:data:`FRAME`) and how each frame's origin is placed (:data:`ORIGIN`) are
chosen by environment variables, as the builder's options would choose them.
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..safewrite import exclusive, replacing_file
from ..store.featurecache import code_version
from ..features import follow_picks
from ..capture.orientation import feature_frame, sample_indices
from .body import turned_about

ROOT = Path(__file__).resolve().parents[2]


SHARED = Path(os.environ.get("TVMEDIT_SHARED", ROOT.parent / "shared"))


CACHE = Path(os.environ.get("TVMEDIT_TEST_CACHE", ROOT / ".cache" / "testdata")).parent / "devsuite"


STITCH = SHARED / "tools" / "hdm05_stitch.py"


GROUPS = ("synth", "synth-drift", "cmu", "hdm05")


@dataclass
class Take:
    """One labelled take of the suite.

    Attributes
    ----------
    group, name : str
    vectors : (T, D) float64
        Feature rows (:attr:`tvmedit.engine.features.Features.vectors`).
    theta : slice
        Columns of the azimuth histogram.
    fps : float
    truth : dict
        ``fps``, ``segments`` (inclusive frame ranges with labels) and ``periods_hint``
        (``period_frames`` per segment, None where unknown), as in ``truth.json``.
    centred : Rows or None
        The rows about each frame's own centre (:attr:`tvmedit.engine.features.Features.centred`),
        where the origin stays put; ``parse(..., centred=take.centred)``.
    """

    group: str
    name: str
    vectors: np.ndarray
    theta: slice
    fps: float
    truth: dict
    centred: "Rows | None" = None


@dataclass
class Rows:
    """Feature rows and their azimuth columns: what :func:`tvmedit.engine.parse.structure.parse` reads of
    :class:`tvmedit.engine.features.Features`."""

    vectors: np.ndarray
    theta_columns: slice

    def at(self, idx):
        return Rows(self.vectors[idx], self.theta_columns)

    def mirrored(self):
        return Rows(mirror_theta(self.vectors, self.theta_columns), self.theta_columns)


def _at(rows, idx):
    return None if rows is None else rows.at(idx)


def _store(path, f):
    """Cache features ``f`` (with their centred rows, where kept) at ``path``; what
    :func:`_cached` reads back."""
    path.parent.mkdir(parents=True, exist_ok=True)
    c = f.centred
    extra = {} if c is None else {"centred": c.vectors, "centred_theta": [c.theta_columns.start, c.theta_columns.stop]}
    with replacing_file(path) as tmp:
        np.savez(tmp, vectors=f.vectors, theta=[f.theta_columns.start, f.theta_columns.stop], **extra)
    return _cached(path)


def _features_once(path, compute):
    """``(vectors, theta, centred)`` cached at ``path``, computed (``compute()``, features)
    and stored the first time; one process computes them while any other that needs them
    waits (the tests run in several)."""
    found = _cached(path)
    if found is None:
        with exclusive(path):
            found = _cached(path) or _store(path, compute())
    return found


def _cached(path):
    """``(vectors, theta, centred Rows or None)`` cached at ``path``, or None."""
    if not path.exists():
        return None
    with np.load(path) as z:
        centred = Rows(z["centred"], slice(*z["centred_theta"])) if "centred" in z else None
        return z["vectors"], slice(*z["theta"]), centred


def _key(*parts):
    return hashlib.sha1(json.dumps(parts, sort_keys=True, default=str).encode()).hexdigest()[:12]


def _run(cmd):
    subprocess.run([sys.executable, *map(str, cmd)], check=True, stdout=subprocess.DEVNULL)


#: How each frame's origin is placed: "auto" (the engine's rule: it follows a person who
#: strays, :func:`tvmedit.engine.store.builder.origin_follows`), "first" (the paper: the first frame's
#: centroid for every frame) or "follow" (always; see :func:`tvmedit.engine.features.frame_origin`).
ORIGIN = os.environ.get("TVMEDIT_DEV_ORIGIN", "auto")


def _accumulator(centroids):
    from ..features import FeatureAccumulator, moves_across

    follow = moves_across(centroids) if ORIGIN == "auto" else ORIGIN == "follow"
    return FeatureAccumulator(follow=follow, centred=True)


#: The axes features are computed in: "body" (the body's own over the take,
#: :func:`tvmedit.engine.capture.orientation.feature_frame`, as ``build`` does by default) or "stored"
#: (tvmedit's, as ``build --no-body-frame`` does); ``TVMEDIT_DEV_FRAME=stored python
#: benchmarks/accuracy.py`` scores that.
FRAME = os.environ.get("TVMEDIT_DEV_FRAME", "body")


@functools.cache
def _prefix():
    # How the origin and axes are placed, and the version of the code that reads frames and
    # makes histograms (tvmedit.engine.store.featurecache.code_version): features it changed are made anew.
    axes = "" if FRAME == "stored" else f"{FRAME}-"
    return f"{ORIGIN}-{axes}{code_version()}-"


def _body(n, frame_at):
    """The body's own frame of a take of ``n`` frames (``frame_at(k)``: the positions of frame
    k) where FRAME is "body", else the identity."""
    if FRAME != "body":
        return np.eye(3)
    return feature_frame([frame_at(k) for k in sample_indices(n)])[0]


def _frames_features(folder, start=0, stop=None):
    """Features of frames [start, stop) of a folder, about their own first frame (and in their
    own body frame where FRAME is "body"), as if they were a take of their own (cached)."""
    from dataclasses import replace

    from ..capture.load import iter_frames, open_sequence, read_frame

    sequence = open_sequence(str(folder))
    stop = len(sequence.paths) if stop is None else stop
    path = CACHE / "features" / f"{_prefix()}{folder.name}-{start}-{stop}.npz"

    def compute():
        from ..store.builder import origin_follows

        paths = sequence.paths[start:stop]
        body = _body(len(paths), lambda k: read_frame(paths[k], sequence.orientation, "geometry").positions)
        body = tuple(map(tuple, body.tolist()))
        orientation = replace(sequence.orientation, features=body).for_features()
        follows = origin_follows(paths, orientation)
        acc = _accumulator([[0, 0, 0], [1, 0, 0]] if follows else [])
        for _, frame in iter_frames(paths, orientation=orientation, detail="geometry"):
            acc.add(frame.positions)
        return acc.result()
    return _features_once(path, compute)


def _turned_features(folder, frames, heading):
    """Features of the folder's ``frames`` with the body turned by ``heading`` (radians, one a
    frame) about the vertical through where the person stands (the mean of their centre over
    the 4 s about each frame: people turn on their feet, :func:`tvmedit.engine.lab.synth.turned_about`),
    the meshes themselves rotated, then taken as the builder takes a capture: its own body
    frame, its own origin (cached)."""
    from ..capture.load import open_sequence, read_frame

    heading = np.asarray(heading, dtype=np.float64)
    key = _key([int(i) for i in frames], np.round(heading, 6).tolist(), "on the feet")
    path = CACHE / "features" / f"{_prefix()}{folder.name}-turned-{key}.npz"

    def compute():
        sequence = open_sequence(str(folder))
        # Each frame read once: the spots, the body frame, the origin and the histograms all need it.
        positions = [read_frame(sequence.paths[int(i)], sequence.orientation, "geometry").positions for i in frames]
        centres = np.array([p.mean(axis=0)[:2] for p in positions])
        half = min(len(frames) // 2, 20)                       # 2 s either side at 10 fps
        spots = np.array([centres[max(0, k - half): k + half + 1].mean(axis=0) for k in range(len(frames))])

        def frame_at(k):
            return turned_about(positions[k], heading[k], spots[k])

        body = _body(len(frames), frame_at)
        acc = _accumulator([frame_at(k).mean(axis=0) @ body.T for k in follow_picks(len(frames))])
        for k in range(len(frames)):
            acc.add(frame_at(k) @ body.T)
        return acc.result()
    return _features_once(path, compute)


def truth_of(labels, periods_s, fps):
    """truth dict from one label and one true period (seconds, NaN: none) per frame."""
    segments, hints, start = [], [], 0
    for i in range(1, len(labels) + 1):
        if i == len(labels) or labels[i] != labels[start]:
            period = float(np.nanmedian(periods_s[start:i])) if np.isfinite(periods_s[start:i]).any() else None
            segments.append({"start": start, "end": i - 1, "label": labels[start]})
            hints.append(None if period is None else {"period_frames": period * fps, "period_s": period})
            start = i
    return {"fps": fps, "segments": segments, "periods_hint": hints}


def _frame_truth(truth):
    """(segment number per frame, true period in seconds per frame) of a truth.json."""
    n = truth["frames"] if "frames" in truth else truth["segments"][-1]["end"] + 1
    seg = np.zeros(n, dtype=int)
    per = np.full(n, np.nan)
    for i, (s, h) in enumerate(zip(truth["segments"], truth["periods_hint"])):
        seg[s["start"]: s["end"] + 1] = i
        if h and h.get("period_frames"):
            per[s["start"]: s["end"] + 1] = h["period_frames"] / truth["fps"]
    return seg, per


def mirror_theta(vectors, theta):
    """Feature rows of the mirror image (x -> -x): azimuth bin j becomes bin n/2 - 1 - j."""
    out = vectors.copy()
    n = theta.stop - theta.start
    out[:, theta] = vectors[:, theta][:, (n // 2 - 1 - np.arange(n)) % n]
    return out
