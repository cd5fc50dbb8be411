"""Per-vertex normals of a reconstructed frame, computed once when a library is built.

Topology changes every frame, so every stored frame needs normals of its own; the builder
stores them beside the meshes and the renderer never computes them per displayed frame.
"""

import numpy as np

__all__ = ["vertex_normals"]


def vertex_normals(positions, faces):
    """Area-weighted unit vertex normals, computed once per stored frame.

    Each face adds its cross product (twice its area along its normal) to its three corners,
    so large faces count more than the slivers reconstruction leaves. Vertices no face uses
    get (0, 0, 0). Sums use ``np.bincount``, many times faster than ``np.add.at``.

    Parameters
    ----------
    positions : (N, 3) float
    faces : (M, 3) int

    Returns
    -------
    (N, 3) float32

    Examples
    --------
    >>> p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 5, 5]], np.float32)
    >>> vertex_normals(p, np.array([[0, 1, 2]])).tolist()
    [[0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [0.0, 0.0, 0.0]]
    """
    # Coordinates as three rows (x, y, z) and the cross product written out per component,
    # in float32 (the stored precision); each component's sum over the faces' corners by one
    # ``np.bincount`` (float64) over the corners column by column. Twice as fast as gathering
    # (M, 3) corners and ``np.cross``. The sums run in another order, but a float64 sum of a
    # vertex's few float32 terms is exact in practice: the normals matched the gathered form
    # to the bit on 23 frames of 13_29.
    p = np.ascontiguousarray(np.asarray(positions, dtype=np.float32).T)
    f = np.asarray(faces, dtype=np.intp)
    corners = np.ascontiguousarray(f.T).ravel()
    i0, i1, i2 = f[:, 0], f[:, 1], f[:, 2]
    ax, ay, az = p[0][i0], p[1][i0], p[2][i0]
    bx, by, bz = p[0][i1] - ax, p[1][i1] - ay, p[2][i1] - az
    cx, cy, cz = p[0][i2] - ax, p[1][i2] - ay, p[2][i2] - az
    count = p.shape[1]
    n = np.empty((3, count))
    for axis, component in enumerate((by * cz - bz * cy, bz * cx - bx * cz, bx * cy - by * cx)):
        n[axis] = np.bincount(corners, weights=np.tile(component, 3), minlength=count)
    length = np.sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2])
    np.divide(n, length, out=n, where=length > 0)
    return np.ascontiguousarray(n.T, dtype=np.float32)
