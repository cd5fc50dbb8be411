"""How sure the parse is of each cluster boundary and each texton, so a user knows where to look first.

Both figures are in [0, 1], higher is surer, and come from quantities the parser already uses
(:mod:`engine.structure`):

* **Boundary confidence** (one per cluster, of the boundary that starts it): the two-block
  novelty (energy distance, :func:`engine.atoms.novelty`) at the boundary relative to the
  threshold a boundary must pass, as ``1 - threshold / height``: 0 for a peak just at the
  threshold, 0.5 for one twice as high, towards 1 for a sharp change of exercise. The first
  cluster's start (frame 0) is no decision and gets 1.
* **Texton confidence**: how closely the motion returns to the texton's first pose when the
  next texton starts, against how far it went in between:
  ``1 - d_A(start, end + 1) / mean_t d_A(start, t)`` over the texton's frames (atom distance,
  eq. (5)). A clean cycle comes back to about 1; a texton cut at the wrong length, or a stretch
  that does not repeat, stays near 0.
"""

import numpy as np

from .atoms import atom_distance, atom_distances_to

__all__ = ["boundary_confidence", "boundary_confidences", "texton_confidence"]


def boundary_confidence(height, threshold):
    """``1 - threshold / height``, clipped to [0, 1]; 0 for a height at or under the threshold.

    >>> boundary_confidence(0.2, 0.05), boundary_confidence(0.05, 0.05), boundary_confidence(0.1, 0)
    (0.75, 0.0, 1.0)
    """
    height, threshold = float(height), float(threshold)
    if height <= 0:
        return 0.0
    return float(min(1.0, max(0.0, 1.0 - threshold / height)))


def boundary_confidences(curve, step, clusters, threshold):
    """Confidence of each cluster's starting boundary.

    Parameters
    ----------
    curve : (N,) array
        The novelty of the sequence reduced by ``step`` (frame t lies at index t // step).
    step : int
    clusters : list of (start, end)
    threshold : float
        The novelty a boundary must reach (``StructureParams.novelty_threshold``).

    Returns
    -------
    list of float, one per cluster (1.0 for the first).

    >>> boundary_confidences(np.array([0, 0.1, 0.4, 0.1, 0]), 1, [(0, 1), (2, 4)], 0.1)
    [1.0, 0.75]
    """
    curve = np.asarray(curve, dtype=np.float64)
    out = []
    for k, (start, _) in enumerate(clusters):
        if k == 0 or len(curve) == 0:
            out.append(1.0)
            continue
        i = min(len(curve) - 1, int(start) // max(1, int(step)))
        out.append(boundary_confidence(curve[max(0, i - 1): i + 2].max(), threshold))
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
