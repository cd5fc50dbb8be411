"""How sure the parse is of each cluster boundary and each texton, so a user knows where to look first.

Both figures are in [0, 1], higher is surer, and come from quantities the parser already uses
(:mod:`tvmedit.engine.parse.structure`):

* **Boundary confidence** (one per cluster, of the boundary that starts it): how strong the
  change is and how sure its place. The strength is the two-block novelty (energy distance,
  :func:`tvmedit.engine.parse.atoms.novelty`) at the novelty's peak by the boundary relative to
  the threshold a boundary must pass, as ``1 - threshold / height``: 0 for a peak just at the
  threshold, 0.5 for one twice as high, towards 1 for a sharp change of exercise. The place:
  the parser moves a boundary off its peak, to whole periods and to the onset of the change
  (:mod:`tvmedit.engine.parse.onsets`), and a boundary moved d seconds keeps
  ``exp(-d / MOVED_S)`` of its peak's figure, because most wrong boundaries are true changes
  placed a second or two off, where the novelty is as high as at a right one. The peak is the
  novelty's highest point within the reach of those rules either side
  (``refine_reach + onset_reach``), never past halfway to a neighbouring boundary. The first
  cluster's start (frame 0) is no decision and gets 1.
* **Texton confidence**: how closely the motion returns to the texton's first pose when the
  next texton starts, against how far it went in between:
  ``1 - d_A(start, end + 1) / mean_t d_A(start, t)`` over the texton's frames (atom distance,
  eq. (5)). A clean cycle comes back to about 1; a texton cut at the wrong length, or a stretch
  that does not repeat, stays near 0.
"""

import numpy as np

from .atoms import atom_distance, atom_distances_to

__all__ = ["boundary_confidence", "boundary_confidences", "texton_confidence", "MOVED_S", "LOOK_BELOW"]

#: Seconds over which a boundary's confidence falls to 1/e of its novelty peak's as the
#: parser's placing rules move it off that peak (the module docstring).
MOVED_S = 0.5

#: Boundaries under this confidence are the ones to look at first (the report marks them in
#: red): a small share of all boundaries, holding a large share of the wrong ones.
LOOK_BELOW = 0.1


def boundary_confidence(height, threshold):
    """``1 - threshold / height``, clipped to [0, 1]; 0 for a height at or under the threshold.

    >>> boundary_confidence(0.2, 0.05), boundary_confidence(0.05, 0.05), boundary_confidence(0.1, 0)
    (0.75, 0.0, 1.0)
    """
    height, threshold = float(height), float(threshold)
    if height <= 0:
        return 0.0
    return float(min(1.0, max(0.0, 1.0 - threshold / height)))


def boundary_confidences(curve, step, clusters, threshold, reach=0, moved=0.0):
    """Confidence of each cluster's starting boundary.

    Parameters
    ----------
    curve : (N,) array
        The novelty of the sequence reduced by ``step`` (frame t lies at index t // step).
    step : int
    clusters : list of (start, end)
    threshold : float
        The novelty a boundary must reach (``StructureParams.novelty_threshold``).
    reach : int
        Frames either side of a boundary (never past halfway to a neighbouring one) within
        which its novelty peak is looked for; 0 reads the novelty at the boundary itself
        (the highest of the curve's rows within a step of it), as the weak-split step
        (:mod:`tvmedit.engine.parse.joins`) does. Otherwise the peak is the curve's highest row in
        reach, read alone, and its distance from the boundary is counted in whole steps of
        the curve (at 15-60 fps a step is 2-6 frames).
    moved : float
        Frames over which the confidence falls to 1/e as the boundary lies off that peak
        (0: not at all).

    Returns
    -------
    list of float, one per cluster (1.0 for the first).

    >>> curve = np.array([0, 0.1, 0.4, 0.1, 0, 0, 0])
    >>> boundary_confidences(curve, 1, [(0, 1), (2, 6)], 0.1)
    [1.0, 0.75]

    The same change with its boundary moved two frames later, off the peak: read where it
    lies, it has no confidence; read at its peak and discounted by the move, some.

    >>> boundary_confidences(curve, 1, [(0, 3), (4, 6)], 0.1)
    [1.0, 0.0]
    >>> [round(c, 3) for c in boundary_confidences(curve, 1, [(0, 3), (4, 6)], 0.1, reach=3, moved=2)]
    [1.0, 0.276]
    """
    curve = np.asarray(curve, dtype=np.float64)
    step = max(1, int(step))
    starts = [int(s) for s, _ in clusters]
    ends = starts[1:] + [int(clusters[-1][1]) + 1] if len(clusters) else []
    out = []
    for k, start in enumerate(starts):
        if k == 0 or len(curve) == 0:
            out.append(1.0)
            continue
        i = min(len(curve) - 1, start // step)
        if reach <= 0:
            out.append(boundary_confidence(curve[max(0, i - 1): i + 2].max(), threshold))
            continue
        # The peak: the novelty's highest point within reach, short of halfway to either neighbour.
        lo = max((starts[k - 1] + start) // 2, start - int(reach)) // step
        hi = min(len(curve) - 1, min((start + ends[k]) // 2, start + int(reach)) // step)
        m = lo + int(np.argmax(curve[lo: hi + 1])) if hi >= lo else i
        away = abs(m * step - start)
        keep = float(np.exp(-away / moved)) if moved > 0 else 1.0
        out.append(boundary_confidence(curve[m], threshold) * keep)
    return out


def texton_confidence(vectors, start, end, window):
    """Confidence of the texton [start, end] (inclusive) of ``vectors`` (see the module docstring).

    >>> t = np.arange(40)
    >>> v = np.stack([np.sin(2 * np.pi * t / 10), np.cos(2 * np.pi * t / 10)], axis=1)
    >>> round(texton_confidence(v, 10, 19, [0.5, 1, 0.5]), 3)
    1.0
    """
    v = np.asarray(vectors)
    if end <= start:
        return 0.0
    back = min(int(end) + 1, len(v) - 1)
    along = atom_distances_to(v, int(start), np.arange(start + 1, end + 1), window)
    spread = float(np.nanmean(along)) if len(along) else 0.0
    if not spread > 0:
        return 0.0
    return float(min(1.0, max(0.0, 1.0 - atom_distance(v, int(start), back, window) / spread)))
