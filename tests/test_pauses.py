"""Pauses between repetitions (tvmedit.engine.parse.pauses): periods and textons on the frames that move."""

import numpy as np

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
    found = {share: parse(v, 10, StructureParams(pause_share=share)) for share in (0.1, 0.0)}
    lengths = [len(t) for t in found[0.1].textons]
    assert abs(np.median(lengths) - true) <= 0.15 * true, (lengths, true)
    # every texton starts where a repetition moves again, never inside a pause
    moving = set(np.flatnonzero(np.concatenate([np.r_[np.ones(14), np.zeros(h)] for h in pauses])))
    assert sum(t.start in moving for t in found[0.1].textons) >= len(lengths) - 1
    # measured on every frame, the textons follow the movement alone and fall short
    short = [len(t) for t in found[0.0].textons]
    assert abs(np.median(short) - true) > 0.15 * true, (short, true)


def test_a_movement_without_pauses_is_parsed_as_before():
    v, _ = _repetitions([0] * 12)
    with_step, without = (parse(v, 10, StructureParams(pause_share=s)) for s in (0.1, 0.0))
    assert [(t.start, t.end) for t in with_step.textons] == [(t.start, t.end) for t in without.textons]
    assert len(with_step.textons) >= 10


def _reversing(period, n=12, fps=10, noise=0.003, seed=1):
    # A movement along a line and back (a squat's up and down), which slows to nothing at
    # each turn without pausing.
    t = np.arange(int(n * period * fps)) / fps
    x = np.sin(2 * np.pi * t / period)
    v = np.stack([x, 0.5 * x, -x], axis=1) * 0.05
    return v + np.random.default_rng(seed).normal(0, noise, v.shape)


def test_a_quick_movement_that_reverses_is_parsed_as_before():
    # its turns last under MIN_PAUSE, so no frame counts as held
    v = _reversing(1.4)
    with_step, without = (parse(v, 10, StructureParams(pause_share=s)) for s in (0.1, 0.0))
    assert [(t.start, t.end) for t in with_step.textons] == [(t.start, t.end) for t in without.textons]


def test_a_slow_movement_that_reverses_keeps_textons_of_its_period():
    # Turns of a 3 s movement hold long enough to count as held; whichever way it is measured,
    # its textons are one period long.
    v = _reversing(3.0, n=8)
    lengths = [len(t) for t in parse(v, 10).textons]
    assert len(lengths) >= 5 and abs(np.median(lengths) - 30) <= 0.15 * 30, lengths
