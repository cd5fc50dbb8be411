"""Scoring a parsed motion structure against labelled truth (``truth.json``).

Two figures are reported for a sequence whose true segments (one exercise each) and their
periods are known:

* **Boundary precision and recall.** The detected cluster starts (frame 0 left out, as it
  is not a decision) are matched one-to-one to the true segment starts (frame 0 left out).
  A pair matches when the two starts are at most ``tolerance_frames`` apart; among the
  admissible pairs, a maximum matching with the smallest total offset is taken, so a
  detection can explain at most one true start and vice versa. Precision is the matched
  fraction of detections, recall the matched fraction of true starts (both 1 when there is
  nothing to find and nothing was found).
* **Texton-length accuracy.** For each detected cluster that overlaps one true segment by
  more than half of the cluster's length and whose segment has a period (``periods_hint``),
  the median length of its textons is compared with that period; the figure is the
  fraction of such clusters within ``rel_tol`` (15 %) of it. A cluster without textons
  counts as a miss.
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

__all__ = [
    "TOLERANCE_S",
    "Score",
    "score",
    "score_take",
    "pool",
    "tolerance_frames",
    "boundary_scores",
    "texton_length_accuracy",
    "load_truth",
    "sequence_features",
]

#: Largest |detected - true| cluster start that counts as a hit, in seconds (rounded to
#: frames at the sequence's rate). Tests, benchmarks and the report all score with it.
TOLERANCE_S = 1.0


def tolerance_frames(fps):
    """:data:`TOLERANCE_S` in frames at ``fps``.

    >>> tolerance_frames(10), tolerance_frames(30)
    (10, 30)
    """
    return round(TOLERANCE_S * float(fps))


@dataclass
class Score:
    """How a parsed structure compares with ``truth.json`` (see the module docstring).

    ``texton_accuracy`` is NaN when no cluster can be scored, or when the structure is at
    another frame rate than the truth (its periods count frames at the truth's rate).
    ``structure``, ``parse_seconds`` and ``feature_columns`` are set by :func:`score_take`.
    """

    precision: float
    recall: float
    texton_accuracy: float
    matches: list
    tolerance_frames: int
    segments: list
    structure: object = field(default=None, repr=False)
    parse_seconds: float = 0.0
    feature_columns: int = 0
    detected: int = 0
    texton_rows: list = field(default_factory=list)


def _segments_at(truth, fps):
    # truth.json counts frames at its own rate; a library may hold the sequence at another.
    scale = float(fps) / float(truth.get("fps", fps) or fps)
    if abs(scale - 1.0) < 1e-9:
        return list(truth["segments"])
    return [{**seg, "start": int(round(seg["start"] * scale)), "end": int(round(seg["end"] * scale))}
            for seg in truth["segments"]]


def score(structure, truth, fps=None):
    """Score ``structure`` (parsed at ``fps``, default the truth's) against ``truth``.

    >>> from tvmedit.engine.parse.structure import Structure, Texton
    >>> s = Structure([(0, 9), (10, 19)], [Texton(0, 4, 0, 0.0), Texton(10, 14, 1, 0.0)], np.zeros(20))
    >>> truth = {"fps": 10, "segments": [{"start": 0, "end": 9}, {"start": 11, "end": 19}],
    ...          "periods_hint": [{"period_frames": 5}, {"period_frames": 5}]}
    >>> result = score(s, truth)
    >>> result.precision, result.recall, result.texton_accuracy, result.tolerance_frames
    (1.0, 1.0, 1.0, 10)
    """
    fps = float(truth["fps"]) if fps is None else float(fps)
    segments = _segments_at(truth, fps)
    tolerance = tolerance_frames(fps)
    precision, recall, matches = boundary_scores(structure.clusters, segments, tolerance)
    same_rate = segments == list(truth["segments"])
    accuracy, rows = texton_length_accuracy(structure, truth, details=True) if same_rate else (math.nan, [])
    return Score(precision, recall, accuracy, matches, tolerance, segments,
                 detected=len(_starts(structure.clusters)), texton_rows=rows)


def pool(scores):
    """Precision, recall and texton-length accuracy of many takes scored together.

    Matches, detections, true starts and scored clusters are summed over the takes (so a
    long take weighs more than a short one), as if they were one take.

    >>> a = Score(1.0, 0.5, 1.0, [(5, 5)], 10, [{"start": 0}, {"start": 5}, {"start": 9}], detected=1,
    ...           texton_rows=[(0, 0, 5.0, 5.0, True)])
    >>> pool([a, a])
    (1.0, 0.5, 1.0)
    """
    matched = sum(len(s.matches) for s in scores)
    detected = sum(s.detected for s in scores)
    true = sum(len(_starts(s.segments)) for s in scores)
    rows = [r[4] for s in scores for r in s.texton_rows]
    precision = matched / detected if detected else (1.0 if not true else 0.0)
    recall = matched / true if true else 1.0
    return precision, recall, (float(np.mean(rows)) if rows else float("nan"))


def score_take(folder, params=None, bins=None, cache_dir=None, frame="body"):
    """Parse the take in ``folder`` (its features cached, computed in ``frame``: the body's own
    by default, as the builder computes them; see :func:`sequence_features`) and
    :func:`score` it against its truth.json."""
    from ..parse.structure import parse

    truth = load_truth(folder)
    features = sequence_features(folder, bins=bins, cache_dir=cache_dir, frame=frame)
    fps = float(truth["fps"])
    t0 = time.perf_counter()
    structure = parse(features.vectors, fps, params, theta=features.theta_columns, centred=features.centred)
    seconds = time.perf_counter() - t0
    result = score(structure, truth, fps)
    result.structure = structure
    result.parse_seconds = seconds
    result.feature_columns = features.vectors.shape[1]
    return result


def _starts(ranges):
    out = []
    for item in ranges:
        if isinstance(item, dict):
            out.append(int(item["start"]))
        else:
            out.append(int(item[0]))
    return sorted(s for s in out if s != 0)


def boundary_scores(detected_clusters, truth_segments, tolerance_frames=10):
    """Precision and recall of cluster boundaries with one-to-one matching.

    Parameters
    ----------
    detected_clusters : list of (start, end) or dicts with "start"
        Detected clusters (inclusive ranges).
    truth_segments : list of dicts with "start" (as in ``truth.json``) or (start, end)
    tolerance_frames : int
        Largest admissible |detected start - true start|.

    Returns
    -------
    precision : float
    recall : float
    matches : list of (detected_start, true_start)

    Examples
    --------
    >>> boundary_scores([(0, 9), (12, 30), (31, 40)], [{"start": 0}, {"start": 10}])
    (0.5, 1.0, [(12, 10)])
    """
    det = _starts(detected_clusters)
    tru = _starts(truth_segments)
    matches = _match(det, tru, tolerance_frames)
    precision = len(matches) / len(det) if det else (1.0 if not tru else 0.0)
    recall = len(matches) / len(tru) if tru else 1.0
    return precision, recall, matches


def _match(det, tru, tol):
    # Both lists are sorted and admissible pairs lie within a band, so an order-preserving
    # maximum matching is optimal; dynamic programming over (i, j) finds the one with the
    # most pairs and, among those, the least total offset.
    n, m = len(det), len(tru)
    best = [[(0, 0.0)] * (m + 1) for _ in range(n + 1)]
    choice = [[0] * (m + 1) for _ in range(n + 1)]
    for i in range(n - 1, -1, -1):
        for j in range(m - 1, -1, -1):
            options = [(best[i + 1][j], 1), (best[i][j + 1], 2)]
            if abs(det[i] - tru[j]) <= tol:
                c, cost = best[i + 1][j + 1]
                options.append(((c + 1, cost - abs(det[i] - tru[j])), 3))
            value, how = max(options, key=lambda o: o[0])
            best[i][j], choice[i][j] = value, how
    pairs, i, j = [], 0, 0
    while i < n and j < m:
        how = choice[i][j]
        if how == 3:
            pairs.append((det[i], tru[j]))
            i, j = i + 1, j + 1
        elif how == 1:
            i += 1
        else:
            j += 1
    return pairs


def _as_ranges(structure):
    if hasattr(structure, "clusters"):
        clusters = [tuple(c) for c in structure.clusters]
        textons = [(t.start, t.end, t.cluster) for t in structure.textons]
    else:
        clusters = [tuple(c) for c in structure["clusters"]]
        textons = [(t["start"], t["end"], t["cluster"]) for t in structure["textons"]]
    return clusters, textons


def texton_length_accuracy(structure, truth, rel_tol=0.15, details=False):
    """Fraction of detected clusters whose median texton length matches the true period.

    Parameters
    ----------
    structure : tvmedit.engine.parse.structure.Structure or its ``to_json()`` dict
    truth : dict
        ``truth.json`` contents (``segments`` and ``periods_hint``), frames at the same
        rate as the structure.
    rel_tol : float
        Admissible relative error of the median texton length.
    details : bool
        Also return one ``(cluster, segment, median_length, true_period, ok)`` row per
        scored cluster.

    Returns
    -------
    float (NaN when no cluster can be scored), or (float, rows) with ``details``
    """
    clusters, textons = _as_ranges(structure)
    segments = truth["segments"]
    hints = truth.get("periods_hint") or [None] * len(segments)
    rows = []
    for ci, (cs, ce) in enumerate(clusters):
        length = ce - cs + 1
        for si, seg in enumerate(segments):
            overlap = min(ce, seg["end"]) - max(cs, seg["start"]) + 1
            if overlap * 2 > length:
                hint = hints[si] if si < len(hints) else None
                period = hint.get("period_frames") if isinstance(hint, dict) else None
                if period:
                    lengths = [e - s + 1 for s, e, c in textons if c == ci]
                    med = float(np.median(lengths)) if lengths else 0.0
                    ok = abs(med - period) <= rel_tol * period
                    rows.append((ci, si, med, float(period), ok))
                break
    score = float(np.mean([r[4] for r in rows])) if rows else float("nan")
    return (score, rows) if details else score


def load_truth(folder):
    """The ``truth.json`` of a generated sequence folder, as a dict."""
    return json.loads((Path(folder) / "truth.json").read_text())


def sequence_features(folder, bins=None, cache_dir=None, frame="body"):
    """Features of a sequence folder, kept in the feature cache (:mod:`tvmedit.engine.store.featurecache`).

    ``frame`` is ``"body"``: in the body's own frame, as the builder computes them by default
    (:func:`tvmedit.engine.capture.orientation.feature_frame`), or ``"stored"``: in tvmedit's axes, as it does
    with ``body_frame=False``.

    Loading about 17,000-vertex PLY frames costs far more than the histograms; tests and
    benchmarks that score many parameter settings on the same takes read them once. The
    cache lives in ``cache_dir``, by default the builder's (``$XDG_CACHE_HOME/tvmedit/features``),
    under the builder's key: a folder regenerated in place, other bins or a change to the
    code that reads frames and computes histograms all recompute.
    """
    from ..store import featurecache
    from ..store.builder import origin_follows
    from ..features import BinSizes, FeatureAccumulator
    from ..capture.load import iter_frames, open_sequence

    bins = bins or BinSizes()
    if frame not in ("body", "stored"):
        raise ValueError(f"frame must be 'body' or 'stored', not {frame!r}")
    # in the frame of reference the builder would use
    sequence = open_sequence(str(folder), body_frame=frame == "body")
    paths = sequence.paths
    orientation = sequence.orientation.for_features()
    stats = featurecache.stat_list(paths)
    key = featurecache.key(stats, bins, orientation=orientation, meshes=sequence.orientation)
    found = featurecache.read(key, bins, cache_dir)
    if found is not None:
        return found[0]
    acc = FeatureAccumulator(bins, follow=origin_follows(paths, orientation), centred=True)
    for _, frame in iter_frames(paths, orientation=orientation, detail="geometry"):
        acc.add(frame.positions)
    features = acc.result()
    featurecache.write(key, features, {"paths": [row[0] for row in stats], "skipped": []}, cache_dir)
    return features
