"""Pauses between repetitions: a cluster's period and textons measured on the frames that move.

People pause between repetitions: they stand a moment after a squat. The pause is part of the
repetition a user would loop (a texton runs from one repetition's start to the next), but the
lag profile (:mod:`tvmedit.engine.parse.periods`) sees held frames as a valley at every lag that
maps one onto another: its clearest valley is the movement's own length, pauses left out, so
textons fall short of the repetitions and a long pause becomes a texton of its own.

Where at least ``pause_share`` of a cluster's frames are held (:func:`moving_frames`), its
period and textons are found on the frames that move, as if the pauses were cut out, and each
texton then keeps the pause after it (:func:`with_pauses`; the last one at most a period of
it, so standing still that closes a cluster stays out). A frame is held where its pose changes
over about 0.2 s by under :data:`HELD_PACE` of the cluster's 75th percentile change: a
threshold relative to the cluster's own motion, so that reconstruction noise and the
exercise's speed set the scale. Only runs of at least :data:`MIN_PAUSE` held frames count,
since a movement that reverses slows to nothing for a moment at each turn. Where the moving
frames show no period, the cluster is measured on every frame.
"""

import numpy as np

__all__ = ["moving_frames", "with_pauses", "HELD_PACE", "MIN_PAUSE"]

#: A frame is held where its pose changes over 0.2 s by under this share of the cluster's
#: 75th percentile change.
HELD_PACE = 0.3

#: Shortest run of held frames that counts as a pause, seconds.
MIN_PAUSE = 0.3


def moving_frames(v, cs, ce, fps, share):
    """Frames of the cluster [cs, ce] that move, where at least ``share`` of them are held.

    Parameters
    ----------
    v : (T, D) array
        The parser's rows.
    cs, ce : int
        The cluster's first and last frame.
    fps : float
    share : float
        Least share of held frames for the pauses to count; 0 never.

    Returns
    -------
    (M,) int array of frame indices, or None
        None where the cluster holds too few held frames (or too few that move to measure).

    >>> t = np.arange(60)
    >>> v = np.stack([np.sin(t), np.cos(t)], axis=1)
    >>> moving_frames(v, 0, 59, 10, 0.1) is None           # moves all the time
    True
    >>> v[20:35] = v[20]                                    # a 1.5 s pause
    >>> m = moving_frames(v, 0, 59, 10, 0.1)
    >>> len(m), bool(np.isin(np.arange(22, 34), m).any())
    (47, False)
    """
    if not share > 0 or ce - cs < 4:
        return None
    seg = np.asarray(v[cs: ce + 1], dtype=np.float64)
    n = len(seg)
    k = max(1, int(round(0.1 * fps)))
    i = np.arange(n)
    change = np.linalg.norm(seg[np.minimum(i + k, n - 1)] - seg[np.maximum(i - k, 0)], axis=1)
    held = change < HELD_PACE * np.percentile(change, 75)
    # A movement that reverses slows to nothing for a moment at each turn: only held runs of
    # at least MIN_PAUSE are pauses.
    shortest = int(round(MIN_PAUSE * fps))
    edges = np.flatnonzero(np.diff(np.r_[0, held.astype(np.int8), 0]))
    for a, b in zip(edges[::2], edges[1::2]):
        if b - a < shortest:
            held[a:b] = False
    if held.mean() < share or (~held).sum() < 5:
        return None
    return np.flatnonzero(~held) + cs


def with_pauses(textons, moving, ce, period):
    """Textons found on the moving frames (indices into ``moving``) back on the sequence's
    frames, each keeping the pause after it: it runs to the frame before the next texton's
    start, the last one to the next moving frame after it (or to the cluster's end ``ce``),
    but at most ``period`` frames past its own last moving frame.

    >>> class T: pass
    >>> a, b = T(), T()
    >>> a.start, a.end, b.start, b.end = 0, 2, 3, 5
    >>> moving = np.array([10, 11, 12, 20, 21, 22, 30])
    >>> [(t.start, t.end) for t in with_pauses([a, b], moving, 40, period=10)]
    [(10, 19), (20, 29)]
    >>> a.start, a.end, b.start, b.end = 0, 2, 3, 6       # the last reaches the last moving frame:
    >>> [(t.start, t.end) for t in with_pauses([a, b], moving, 40, period=3)]   # a period of stillness
    [(10, 19), (20, 33)]
    """
    if not textons:
        return textons
    # The last one keeps at most a period of stillness (not a stretch of standing that closes
    # the cluster).
    last = int(moving[textons[-1].end]) + int(period)
    for t in textons:
        after = t.end + 1
        t.start = int(moving[t.start])
        t.end = int(moving[after]) - 1 if after < len(moving) else int(ce)
    for a, b in zip(textons, textons[1:]):
        a.end = b.start - 1
    textons[-1].end = min(textons[-1].end, last)
    return textons
