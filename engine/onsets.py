"""Where a change of exercise starts: a boundary moved back from the novelty peak to the onset.

The two-block novelty (:func:`engine.atoms.novelty`) peaks where the pose distribution changes
most, which for a slow transition (a 3 s change of pose from one exercise to the next) is its
middle or end, 1-2 s after the person stopped the old exercise. The boundary a person would
draw is where the motion leaves the old exercise. :func:`onset` finds it: the earliest frame
from which every frame up to the peak lies farther from the old exercise's poses than those
poses lie from one another.
"""

import numpy as np

from .features import distance_matrix

__all__ = ["onset"]


def onset(vectors, start, peak, fps, reach=3.0, reference=10.0):
    """The frame where the motion leaves cluster [start, peak) on its way to ``peak``.

    Parameters
    ----------
    vectors : (T, D) array
        Feature vectors (frame distance: Euclidean distance of rows, eq. (2)).
    start : int
        First frame of the cluster before the boundary.
    peak : int
        The boundary found at the novelty peak.
    fps : float
    reach : float
        Seconds before ``peak`` within which the onset is looked for.
    reference : float
        Seconds of the old cluster, ending ``reach`` before the peak, whose poses stand for it.

    Returns
    -------
    int, in [peak - reach, peak]; ``peak`` when the frames before it still look like the old
    cluster, or when the old cluster is too short to tell.

    Examples
    --------
    >>> t = np.arange(80)
    >>> cyc = np.stack([np.sin(2 * np.pi * t / 8), np.cos(2 * np.pi * t / 8)], axis=1)
    >>> v = np.where((t < 50)[:, None], cyc, 3.0 + (t[:, None] - 50) * 0.0)
    >>> v[40:50] = cyc[40:50] + np.linspace(0, 3, 10)[:, None]   # a slow change from frame 40
    >>> onset(v, 0, 50, 10)
    41
    """
    v = np.asarray(vectors, dtype=np.float64)
    k = int(round(reach * fps))
    lo = max(start, peak - k)
    # The reference poses at about 10 fps are enough, and keep this linear in the frame rate.
    step = max(1, int(round(fps / 10.0)))
    ref = v[max(start, lo - int(round(reference * fps))): lo][::-1][::step][::-1]
    if len(ref) < max(4, int(round(1.0 * fps / step))):
        return int(peak)
    # How far the old cluster's poses lie from their nearest others (half a second apart at
    # least, so a pose is not matched with itself a frame later).
    D = distance_matrix(ref)
    gap = max(1, int(round(0.5 * fps / step)))
    idx = np.arange(len(ref))
    D[np.abs(idx[:, None] - idx[None, :]) < gap] = np.inf
    spread = np.nanpercentile(np.where(np.isfinite(D.min(axis=1)), D.min(axis=1), np.nan), 90)
    if not np.isfinite(spread):
        return int(peak)
    away = distance_matrix(v[lo: peak + 1], ref).min(axis=1) > spread
    t = len(away) - 1
    while t > 0 and away[t - 1]:
        t -= 1
    return int(lo + t) if away[-1] else int(peak)
