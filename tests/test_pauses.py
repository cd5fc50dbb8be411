"""Pauses between repetitions (tvmedit.engine.parse.pauses): periods and textons on the frames that move."""

import numpy as np
import pytest

from tvmedit.engine.parse.pauses import moving_frames, with_pauses
from tvmedit.engine.parse.structure import StructureParams, parse


def _repetitions(pauses, cycle=14, noise=0.003, seed=0):
    # A cyclic movement of ``cycle`` frames, each repetition followed by a pause of the given
    # number of frames held in the pose it ended in, with a little noise (a still body's
    # reconstruction still changes).
    rows, starts = [], []
    for hold in pauses:
        starts.append(sum(len(r) for r in rows))
        phase = 2 * np.pi * np.arange(cycle) / cycle
        rows.append(np.stack([np.sin(phase), np.cos(phase) - 1, np.sin(2 * phase)], axis=1) * 0.05)
        rows.append(np.zeros((hold, 3)))
    v = np.vstack(rows) + np.random.default_rng(seed).normal(0, noise, (sum(len(r) for r in rows), 3))
    return v, np.diff(starts)


def test_textons_run_from_one_repetition_to_the_next_pause_included():
    pauses = np.random.default_rng(3).integers(0, 15, 12)
    v, intervals = _repetitions(pauses)
    true = np.mean(intervals)
    found = parse(v, 10, StructureParams(pause_share=0.1))
    lengths = [len(t) for t in found.textons]
    assert abs(np.median(lengths) - true) <= 0.15 * true, (lengths, true)
    # every texton starts where a repetition moves again, never inside a pause
    moving = set(np.flatnonzero(np.concatenate([np.r_[np.ones(14), np.zeros(h)] for h in pauses])))
    assert sum(t.start in moving for t in found.textons) >= len(lengths) - 1


def test_a_movement_without_pauses_is_measured_on_every_frame():
    v, _ = _repetitions([0] * 12)
    paused, every = (parse(v, 10, StructureParams(pause_share=s)) for s in (0.1, 0.0))
    assert [(t.start, t.end) for t in paused.textons] == [(t.start, t.end) for t in every.textons]
    assert len(paused.textons) >= 10


def _reversing(period, n=12, fps=10, noise=0.003, seed=1):
    # A movement along a line and back (a squat's up and down), which slows to nothing at
    # each turn without pausing.
    t = np.arange(int(n * period * fps)) / fps
    x = np.sin(2 * np.pi * t / period)
    v = np.stack([x, 0.5 * x, -x], axis=1) * 0.05
    return v + np.random.default_rng(seed).normal(0, noise, v.shape)


def test_a_quick_movement_that_reverses_has_no_pauses():
    # its turns last under MIN_PAUSE, so no frame counts as held
    v = _reversing(1.4)
    assert moving_frames(v, 0, len(v) - 1, 10, 0.1) is None
    paused, every = (parse(v, 10, StructureParams(pause_share=s)) for s in (0.1, 0.0))
    assert [(t.start, t.end) for t in paused.textons] == [(t.start, t.end) for t in every.textons]


def test_a_slow_movement_that_reverses_keeps_textons_of_its_period():
    # Turns of a 3 s movement hold long enough to count as held; whichever way it is measured,
    # its textons are one period long.
    v = _reversing(3.0, n=8)
    lengths = [len(t) for t in parse(v, 10).textons]
    assert len(lengths) >= 5 and abs(np.median(lengths) - 30) <= 0.15 * 30, lengths


def test_only_runs_of_held_frames_long_enough_are_pauses():
    t = np.arange(60)
    v = np.stack([np.sin(t), np.cos(t)], axis=1)
    v[20:22] = v[20]                                        # 0.2 s: a movement's turn, no pause
    assert moving_frames(v, 0, 59, 10, 0.01) is None
    v[40:50] = v[40]                                        # 1 s: a pause
    m = moving_frames(v, 0, 59, 10, 0.01)
    assert not np.isin(np.arange(42, 49), m).any() and np.isin([20, 21], m).all()
    assert moving_frames(v, 0, 59, 10, 0.0) is None         # a share of 0: pauses never count


class _Texton:
    def __init__(self, start, end):
        self.start, self.end = start, end


def test_each_texton_keeps_the_pause_after_it_the_last_at_most_a_period():
    moving = np.array([10, 11, 12, 20, 21, 22, 30])
    found = with_pauses([_Texton(0, 2), _Texton(3, 5)], moving, 60, period=10)
    assert [(t.start, t.end) for t in found] == [(10, 19), (20, 29)]
    last = with_pauses([_Texton(0, 2), _Texton(3, 6)], moving, 60, period=5)
    assert [(t.start, t.end) for t in last] == [(10, 19), (20, 35)]    # the cluster ends at 60
    assert with_pauses([], moving, 60, period=5) == []


@pytest.mark.parser
@pytest.mark.slow
def test_repetitions_with_pauses_get_textons_of_a_whole_repetition(devsuite):
    # The suite's "rests-long-20fps" take: the synthetic actor pauses up to 1.5 s after each
    # repetition. Measured on the frames that move (StructureParams.pause_share), each
    # texton is a repetition with its pause: squats of 3.0 s with theirs, and knee raises of
    # a whole left-right cycle.
    from tvmedit.engine.lab.evaluate import score
    take = devsuite.take("synth", "rests-long-20fps")
    structure = parse(take.vectors, take.fps, StructureParams(pause_share=0.1), theta=take.theta,
                      centred=take.centred)
    found = score(structure, take.truth, take.fps)
    assert found.texton_accuracy == 1.0 and all(ok for *_, ok in found.texton_rows), found.texton_rows
    squats = [row for row in found.texton_rows if abs(row[3] / take.fps - 3.01) < 0.05]   # frames
    assert squats and squats[0][-1], found.texton_rows
