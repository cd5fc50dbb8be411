"""A sequence's structure on a timeline (tvmedit.engine.parse.timeline): plain numbers, no GL."""

from types import SimpleNamespace

import numpy as np
import pytest

from tvmedit.engine.parse.timeline import COLOURS, Timeline, timeline


def _line(**extra):
    # 40 frames: two clusters of 20, two textons in each
    textons = [(0, 9, 0), (10, 19, 0), (20, 29, 1), (30, 39, 1)]
    return Timeline("a", 10.0, np.linspace(0, 1, 40), [(0, 19), (20, 39)], textons, **extra)


def test_the_timeline_finds_the_cluster_texton_and_marker_at_a_frame():
    line = _line()
    assert line.frames == 40 and line.boundaries == [20] and line.texton_starts == [0, 10, 20, 30]
    assert line.cluster_at(19) == 0 and line.cluster_at(20) == 1
    assert line.texton_at(25) == (20, 29, 1)
    assert line.nearest_marker(14) == ("texton", 10)
    assert line.nearest_marker(20) == ("boundary", 20)         # a boundary wins a tie with a texton


def test_a_timeline_without_markers_has_no_nearest_one():
    line = Timeline("a", 10.0, np.zeros(5), [(0, 4)], [])
    assert line.nearest_marker(2) is None and line.texton_at(2) is None


def test_pixels_and_frames_map_back_and_forth_within_the_box():
    line, box = _line(), (100, 0, 400, 50)
    assert line.x_of(0, box) == 100 and line.x_of(20, box) == 300
    assert [line.frame_at(line.x_of(f, box) + 1, box) for f in (0, 13, 39)] == [0, 13, 39]
    assert line.frame_at(0, box) == 0 and line.frame_at(1000, box) == 39      # clamped


def test_the_layout_draws_background_bands_ticks_boundaries_and_playhead():
    line = _line(representatives=[(10, 19)], added=[20], removed=[30])
    shapes = line.shapes((0, 0, 400, 100), playhead=5)
    parts = ["background", "bands", "bands", "representative"] + ["texton"] * 4
    parts += ["removed", "boundary", "corrected", "playhead"]
    assert len(shapes.rects) == len(shapes.colours) == len(parts)
    expected = [COLOURS[part] for part in parts]
    expected[1:3] = COLOURS["bands"][:2]                                       # bands alternate
    assert np.array_equal(shapes.colours, np.asarray(expected, np.float32))
    assert shapes.rects.dtype == np.float32 and shapes.curve.shape == (40, 2)
    assert shapes.rects[1].tolist() == [0, 0, 200, 16]                       # the first cluster's band


def test_texton_ticks_follow_the_confidence_at_least_a_tenth_high():
    line = _line(confidence=[1.0, 0.5, None, 0.0])
    ticks = line.shapes((0, 0, 400, 100)).rects[3:7, 3]
    full = 0.78 * 100
    assert ticks.tolist() == pytest.approx([full, 0.5 * full, full, 0.1 * full])


def test_the_timeline_marks_boundaries_drawn_and_removed_by_hand():
    texton = lambda s, e, k: SimpleNamespace(start=s, end=e, cluster=k, confidence=None)  # noqa: E731
    structure = SimpleNamespace(fps=10, curve=np.zeros(30), clusters=[(0, 14), (15, 29)],
                                textons=[texton(0, 14, 0), texton(15, 29, 1)])
    parse = SimpleNamespace(clusters=[(0, 9), (10, 29)])
    nodes = [SimpleNamespace(sequence="a", start=15, end=29), SimpleNamespace(sequence="b", start=0, end=9)]
    line = timeline("a", structure, parse, nodes)
    assert line.added == [15] and line.removed == [10]
    assert line.representatives == [(15, 29)] and line.confidence is None
    assert timeline("a", structure).added == [] and timeline("a", structure).removed == []
