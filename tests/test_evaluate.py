"""The scorer (tvmedit.engine.lab.evaluate) on tiny hand-made parses whose figures are known."""

import json
import math

import numpy as np
import pytest

from tvmedit.engine.lab.evaluate import (Score, boundary_scores, load_truth, pool, score, sequence_features,
                                         texton_length_accuracy, tolerance_frames)
from tvmedit.engine.parse.structure import Structure, Texton


def _structure(clusters, textons=(), frames=None):
    """A parse of ``clusters`` ((start, end), inclusive) and ``textons`` ((start, end, cluster))."""
    frames = frames or clusters[-1][1] + 1
    return Structure([tuple(c) for c in clusters], [Texton(s, e, c, 0.0) for s, e, c in textons],
                     np.zeros(frames))


def _truth(starts, frames, fps=10, periods=None):
    """A truth.json of segments starting at ``starts``, each with its period in frames (or none)."""
    ends = [s - 1 for s in starts[1:]] + [frames - 1]
    segments = [{"start": s, "end": e, "label": f"m{i}"} for i, (s, e) in enumerate(zip(starts, ends))]
    hints = [{"period_frames": p} if p else {} for p in (periods or [None] * len(starts))]
    return {"fps": fps, "segments": segments, "periods_hint": hints}


def test_a_boundary_within_one_second_is_found_and_one_beyond_is_not():
    assert tolerance_frames(10) == 10 and tolerance_frames(25) == 25
    assert boundary_scores([(0, 29), (30, 59)], [{"start": 0}, {"start": 40}], 10)[2] == [(30, 40)]
    assert boundary_scores([(0, 28), (29, 59)], [{"start": 0}, {"start": 40}], 10) == (0.0, 0.0, [])


def test_frame_zero_is_no_decision_and_is_never_scored():
    assert boundary_scores([(0, 59)], [{"start": 0, "end": 59}]) == (1.0, 1.0, [])


def test_two_detections_near_one_true_start_count_one_hit_one_false():
    precision, recall, matches = boundary_scores([(0, 18), (19, 22), (23, 40)], [{"start": 0}, {"start": 20}], 5)
    assert (precision, recall) == (0.5, 1.0)
    assert matches == [(19, 20)]                         # the nearer of the two


def test_the_matching_finds_the_most_pairs_before_the_nearest():
    # Nearest first would pair 10 with 9 and leave 5 and 14 apart; two pairs can be made.
    precision, recall, matches = boundary_scores([(0, 4), (5, 9), (10, 20)], [(0, 8), (9, 13), (14, 20)], 5)
    assert matches == [(5, 9), (10, 14)]
    assert (precision, recall) == (1.0, 1.0)


def test_nothing_found_or_only_false_starts_score_zero():
    truth = [{"start": 0}, {"start": 30}]
    assert boundary_scores([(0, 59)], truth) == (0.0, 0.0, [])
    assert boundary_scores([(0, 9), (10, 59)], [{"start": 0}]) == (0.0, 1.0, [])


def test_texton_lengths_within_15_percent_of_the_period_count():
    truth = _truth([0, 40], 80, periods=[10, 10])
    near = _structure([(0, 39), (40, 79)], [(0, 10, 0), (11, 21, 0), (40, 51, 1), (52, 63, 1)])
    accuracy, rows = texton_length_accuracy(near, truth, details=True)
    assert accuracy == 0.5                               # 11 frames for 10: yes; 12 frames: no
    assert [(ci, si, med, ok) for ci, si, med, _, ok in rows] == [(0, 0, 11.0, True), (1, 1, 12.0, False)]


def test_a_cluster_without_textons_counts_as_a_wrong_length():
    truth = _truth([0, 40], 80, periods=[10, 10])
    assert texton_length_accuracy(_structure([(0, 39), (40, 79)], [(0, 9, 0)]), truth) == 0.5


def test_a_cluster_is_scored_against_the_segment_holding_most_of_it():
    truth = _truth([0, 40], 80, periods=[10, 20])
    parse = _structure([(0, 49), (50, 79)], [(0, 19, 0), (50, 59, 1)])
    _, rows = texton_length_accuracy(parse, truth, details=True)
    assert [(ci, si) for ci, si, *_ in rows] == [(0, 0), (1, 1)]
    assert [ok for *_, ok in rows] == [False, False]     # 20 frames for 10, 10 frames for 20


def test_segments_without_a_period_are_not_scored():
    truth = _truth([0, 40], 80, periods=[None, 10])
    parse = _structure([(0, 39), (40, 79)], [(0, 4, 0), (40, 49, 1)])
    assert texton_length_accuracy(parse, truth, details=True)[1][0][:2] == (1, 1)
    assert math.isnan(texton_length_accuracy(parse, _truth([0, 40], 80)))


def test_a_saved_parse_scores_as_the_parse_itself():
    truth = _truth([0, 40], 80, periods=[10, 10])
    parse = _structure([(0, 39), (40, 79)], [(0, 9, 0), (40, 52, 1)])
    saved = {"clusters": [list(c) for c in parse.clusters],
             "textons": [{"start": t.start, "end": t.end, "cluster": t.cluster} for t in parse.textons]}
    assert texton_length_accuracy(saved, truth) == texton_length_accuracy(parse, truth) == 0.5


def test_score_reports_boundaries_textons_and_what_it_found():
    truth = _truth([0, 40, 90], 120, periods=[10, 10, 10])
    parse = _structure([(0, 44), (45, 69), (70, 119)], [(0, 9, 0), (45, 54, 1), (70, 79, 2)])
    result = score(parse, truth)
    assert (result.precision, result.recall) == (0.5, 0.5)
    assert result.matches == [(45, 40)] and result.detected == 2 and result.tolerance_frames == 10
    assert result.texton_accuracy == 1.0


def test_a_parse_at_another_rate_is_scored_against_rescaled_truth():
    truth = _truth([0, 40], 80, fps=10, periods=[10, 10])
    parse = _structure([(0, 89), (90, 159)], [(0, 19, 0), (90, 109, 1)])
    result = score(parse, truth, fps=20)
    assert [s["start"] for s in result.segments] == [0, 80] and result.tolerance_frames == 20
    assert result.matches == [(90, 80)] and (result.precision, result.recall) == (1.0, 1.0)
    assert math.isnan(result.texton_accuracy)


def test_pooled_figures_weigh_a_take_by_what_it_holds():
    hit = Score(1.0, 1.0, 1.0, [(40, 40)], 10, [{"start": 0}, {"start": 40}], detected=1,
                texton_rows=[(0, 0, 10.0, 10.0, True)])
    misses = Score(0.0, 0.0, 0.0, [], 10, [{"start": 0}, {"start": 40}], detected=3,
                   texton_rows=[(0, 0, 20.0, 10.0, False)] * 3)
    assert pool([hit, misses]) == (0.25, 0.5, 0.25)
    assert pool([]) == (1.0, 1.0, pytest.approx(float("nan"), nan_ok=True))


def test_truth_is_read_from_the_take_folder(tmp_path):
    truth = _truth([0, 40], 80)
    (tmp_path / "truth.json").write_text(json.dumps(truth))
    assert load_truth(tmp_path) == truth


def test_features_in_an_unknown_frame_are_refused(tmp_path):
    with pytest.raises(ValueError, match="frame must be 'body' or 'stored'"):
        sequence_features(tmp_path, frame="world")
