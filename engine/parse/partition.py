"""Where a take changes, read over whole blocks: the kernel change-point partition.

The novelty of :mod:`tvmedit.engine.parse.boundaries` compares the ``novelty_window`` seconds
before each frame with those after it. Two exercises of alike poses differ little within a
few seconds, and their novelty peaks under the threshold. A change point is a property of
the take as a whole: the partition here compares every stretch with every other and keeps
the cuts that pay for themselves.

**What it minimises.** For rows x_1..x_T (the novelty's whitened rows, about 10 a second:
:func:`tvmedit.engine.parse.boundaries.novelty_rows`), a partition into segments S_1..S_K costs

    sum_k (1 / |S_k|) sum_{i, j in S_k} |x_i - x_j|  +  penalty * (K - 1),

the within-segment energy scatter plus a penalty per change. This is the kernel change-point
criterion of Arlot, Celisse and Harchaoui (JMLR 2019, "A kernel multiple change-point
algorithm via model selection") with the energy-distance kernel -|x - y| of Matteson and
James (JASA 2014): a cut between two segments lowers the scatter by their energy distance
weighted by their lengths, the novelty's own statistic taken over whole segments. Every
segment is at least ``min_len`` rows long (the parser's ``min_cluster``) and at most
``max_len`` (60 s), so the cost grows with T times ``max_len``, not T squared. The minimum is
exact: dynamic programming over segment ends.

**Why written here.** ``ruptures`` (the usual Python library for change points) offers kernel
change-point detection with linear, Gaussian and cosine kernels but not the energy kernel,
and it is not among tvmedit's dependencies; SciPy has none. The dynamic program is twenty
lines of NumPy over at most a few thousand rows (milliseconds per take).
"""

from __future__ import annotations

import numpy as np

__all__ = ["energy_partition", "MAX_SEGMENT_S"]

#: Longest segment of the partition, seconds of rows (see the module docstring).
MAX_SEGMENT_S = 60.0


def _pair_sums(x, max_len):
    """q[e, n]: the sum of |x_i - x_j| over the pairs i < j of the segment of n rows that ends
    before row e (rows e - n .. e - 1), for n <= max_len (0 where the segment would start
    before row 0)."""
    T = len(x)
    # back[j, k] = |x_j - x_{j-k}|, then summed over k = 1..n: row j's distances to the n rows
    # before it.
    back = np.zeros((T, max_len))
    for k in range(1, min(max_len, T)):
        back[k:, k] = np.linalg.norm(x[k:] - x[:-k], axis=1)
    back = np.cumsum(back, axis=1)
    q = np.zeros((T + 1, max_len + 1))
    # A segment of n rows ending before e is the one of n - 1 rows ending before e - 1, and
    # row e - 1 with its distances to those n - 1 rows.
    for n in range(2, max_len + 1):
        q[n:, n] = q[n - 1: T, n - 1] + back[n - 1: T, n - 1]
    return q


def energy_partition(rows, penalty, min_len, max_len=None):
    """The change points of the partition of ``rows`` of least energy scatter plus ``penalty``
    per change (see the module docstring).

    Parameters
    ----------
    rows : (T, C) array
    penalty : float
        Cost of one change, in the units of the rows' distances times rows.
    min_len : int
        Fewest rows in a segment (>= 1).
    max_len : int, optional
        Most rows in a segment; default T (no limit: memory then grows with T squared, 8 T^2
        bytes twice). At least 2 * ``min_len``.

    Returns
    -------
    list of int
        Indices of the first row of every segment but the first, increasing.

    Examples
    --------
    Two blocks of different poses, each alternating between two of its own (a cyclic
    exercise), and the same take with a penalty no change pays for:

    >>> a, b = np.array([[0.0, 0.0], [1.0, 0.0]]), np.array([[0.0, 3.0], [1.0, 3.0]])
    >>> x = np.vstack([np.tile(a, (15, 1)), np.tile(b, (10, 1))])
    >>> energy_partition(x, 10.0, 4), energy_partition(x, 1e6, 4)
    ([30], [])
    """
    x = np.asarray(rows, dtype=np.float64)
    T = len(x)
    m = max(1, int(min_len))
    L = T if max_len is None else max(2 * m, int(max_len))
    L = min(L, T)
    if T < 2 * m:
        return []
    q = _pair_sums(x, L)
    best = np.full(T + 1, np.inf)
    best[0] = -penalty           # the first segment pays no change; best[1 .. m-1] stay inf
    back = np.zeros(T + 1, dtype=int)
    scale = 2.0 / np.maximum(np.arange(L + 1), 1)
    for end in range(m, T + 1):
        top = min(L, end)
        # Segments of n = m .. top rows ending here: the best partition before each (best[end
        # - n], read backwards), its scatter (2 / n times its pair sum: the mean distance over
        # ordered pairs times n) and a change.
        cost = best[end - top: end - m + 1][::-1] + scale[m: top + 1] * q[end, m: top + 1] + penalty
        k = int(np.argmin(cost))
        best[end], back[end] = cost[k], end - m - k
    if not np.isfinite(best[T]):
        return []
    out, end = [], T
    while end > 0:
        start = int(back[end])
        if start > 0:
            out.append(start)
        end = start
    return sorted(out)
