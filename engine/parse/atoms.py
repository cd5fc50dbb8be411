"""Motion atoms, section 4, eq. (5): the atom window and distance, and what is built on them.

A *motion atom* is a short window of frames centred on one frame; the *atom distance*
d_A(t1, t2, K) of eq. (5) is a weighted sum of frame distances over two such windows. The
parser (:mod:`tvmedit.engine.parse.structure`) reads a sequence's structure from these quantities: the
distance curve d_A(t, t_first), the lag profile (self-similarity at lag L, whose minima are
periods) and the two-block novelty (whose peaks are cluster boundaries).

Within K frames of either end of the sequence, the atom window is cut at the end and the
remaining weights are rescaled to the full window's total, so an atom distance keeps its
scale.
"""

import numpy as np

from ..features import distance_matrix

__all__ = ["PAPER_TAPS", "PAPER_FPS", "atom_window", "atom_distance", "atom_distances_to",
           "lag_profile", "novelty", "atoms_along_lag", "block_means"]

#: The paper's 5-tap window {0.25, 0.5, 1, 0.5, 0.25} at 10 fps (0.5 s).
PAPER_TAPS = (0.25, 0.5, 1.0, 0.5, 0.25)
PAPER_FPS = 10.0


def atom_window(fps, taps=PAPER_TAPS, taps_fps=PAPER_FPS):
    """Weights w(k), k = -K..K, of the atom window of eq. (5) at frame rate ``fps``.

    The taps, given at ``taps_fps``, are read as a piecewise-linear function of time and
    sampled at the frames within the same time span; the result is scaled to the same
    total as the given taps, so atom distances compare across frame rates.

    Returns
    -------
    (2K + 1,) float64

    Examples
    --------
    >>> atom_window(10).tolist()
    [0.25, 0.5, 1.0, 0.5, 0.25]
    >>> len(atom_window(30)), round(float(atom_window(30).sum()), 6)
    (13, 2.5)
    """
    taps = np.asarray(taps, dtype=np.float64)
    k0 = len(taps) // 2
    if abs(fps - taps_fps) < 1e-9:
        return taps.copy()
    span = k0 / taps_fps
    k = max(1, int(round(span * fps)))
    times = np.arange(-k, k + 1) / fps
    w = np.interp(times, np.arange(-k0, k0 + 1) / taps_fps, taps)
    return w * (taps.sum() / w.sum())


def atom_distance(vectors, t1, t2, window) -> float:
    """Atom distance d_A(t1, t2, K) of eq. (5).

    Parameters
    ----------
    vectors : (T, D) array
        Feature vectors, one row per frame.
    t1, t2 : int
        Centres of the two atoms.
    window : (2K + 1,) array
        w(-K..K), e.g. :func:`atom_window`. Offsets k for which t1 + k or t2 + k falls
        outside the sequence are left out and the rest rescaled to the window's total.

    Examples
    --------
    >>> v = np.array([[0.0], [1.0], [0.0], [1.0], [0.0], [1.0]])
    >>> atom_distance(v, 1, 3, [0.25, 0.5, 1, 0.5, 0.25])
    0.0
    >>> atom_distance(v, 0, 1, [0.5, 1, 0.5])  # frame distance 1 at every tap, weights sum 2
    2.0
    """
    return float(atom_distances_to(vectors, t1, np.array([t2]), window)[0])


def atom_distances_to(vectors, t, others, window) -> np.ndarray:
    """d_A(t, u) for every u in ``others`` (1-D int array), vectorised over u.

    Returns
    -------
    (len(others),) float64
    """
    v = np.asarray(vectors)
    T = len(v)
    w = np.asarray(window, dtype=np.float64)
    K = len(w) // 2
    others = np.asarray(others, dtype=np.intp)
    num = np.zeros(len(others))
    den = np.zeros(len(others))
    for k in range(-K, K + 1):
        a = t + k
        if a < 0 or a >= T:
            continue
        b = others + k
        ok = (b >= 0) & (b < T)
        diff = v[b[ok]].astype(np.float64) - v[a]
        num[ok] += w[k + K] * np.sqrt(np.einsum("nd,nd->n", diff, diff))
        den[ok] += w[k + K]
    return np.where(den > 0, num / np.maximum(den, 1e-300), np.nan) * w.sum()


def _lag_frame_distances(v, lag):
    diff = v[lag:].astype(np.float64) - v[: len(v) - lag]
    return np.sqrt(np.einsum("nd,nd->n", diff, diff))


def atoms_along_lag(v, lag, w):
    """d_A(u, u + lag) for every valid u: the windowed sum of frame distances at that lag."""
    d = _lag_frame_distances(v, lag)
    n = len(d)
    K = len(w) // 2
    ones = np.ones(n)
    num = np.convolve(d, w[::-1], mode="full")[K: K + n]
    den = np.convolve(ones, w[::-1], mode="full")[K: K + n]
    return num / den * w.sum()


def lag_profile(vectors, lags, window) -> np.ndarray:
    """Mean atom distance mean_u d_A(u, u + L) for each lag L (self-similarity at lag L).

    Parameters
    ----------
    vectors : (T, D) array
    lags : 1-D int array, each in 1..T-1
    window : (2K + 1,) array

    Returns
    -------
    (len(lags),) float64; its minima are candidate periods.

    Examples
    --------
    >>> t = np.arange(60)
    >>> v = np.stack([np.sin(2 * np.pi * t / 12), np.cos(2 * np.pi * t / 12)], axis=1)
    >>> int(np.argmin(lag_profile(v, np.arange(4, 20), atom_window(10)))) + 4
    12
    """
    v = np.asarray(vectors)
    w = np.asarray(window, dtype=np.float64)
    return np.array([atoms_along_lag(v, int(L), w).mean() for L in lags])


def novelty(vectors, block, min_block=None) -> np.ndarray:
    """Energy-distance novelty between the ``block`` frames before and after each frame.

    n(t) = 2 mean d(X, Y) - mean d(X, X') - mean d(Y, Y') with X = frames [t - block, t),
    Y = frames [t, t + block), d the frame distance and the within-block means taken over
    distinct pairs. Computed in chunks, so memory and time grow linearly with T.

    Parameters
    ----------
    vectors : (T, D) array
    block : int
        Frames per block (cut at the sequence's ends).
    min_block : int, optional
        Frames below which a block is too short to judge; n is 0 there. Default ``block``//3.

    Returns
    -------
    (T,) float64

    Examples
    --------
    >>> v = np.r_[np.zeros((20, 2)), np.ones((20, 2))]
    >>> n = novelty(v, 10)
    >>> int(np.argmax(n)), round(float(n.max()), 4)
    (20, 2.8284)
    """
    v = np.asarray(vectors, dtype=np.float64)
    T = len(v)
    if min_block is None:
        min_block = max(2, block // 3)
    out = np.zeros(T)
    chunk = max(4 * block, 64)
    for c0 in range(0, T, chunk):
        c1 = min(T, c0 + chunk)
        lo, hi = max(0, c0 - block), min(T, c1 + block)
        D = distance_matrix(v[lo:hi])
        # 2-D prefix sums make each block mean O(1).
        S = np.zeros((hi - lo + 1, hi - lo + 1))
        S[1:, 1:] = D.cumsum(0).cumsum(1)

        def box(a, b, c, d):
            return S[b, d] - S[a, d] - S[b, c] + S[a, c]

        for t in range(c0, c1):
            a, b = max(lo, t - block), min(hi, t + block)
            n_left, n_right = t - a, b - t
            if n_left < min_block or n_right < min_block:
                continue
            i, j, k = a - lo, t - lo, b - lo
            cross = box(i, j, j, k) / (n_left * n_right)
            left = box(i, j, i, j) / (n_left * (n_left - 1))
            right = box(j, k, j, k) / (n_right * (n_right - 1))
            out[t] = 2.0 * cross - left - right
    return out


def block_means(vectors, step):
    """Means of successive blocks of ``step`` frames: a 10 fps view of a faster capture.

    The last block is padded by repeating the last frame.

    Returns
    -------
    (ceil(T / step), D) float64

    >>> block_means(np.arange(5.0)[:, None], 2).ravel().tolist()
    [0.5, 2.5, 4.0]
    """
    v = np.asarray(vectors, dtype=np.float64)
    if step == 1:
        return v
    T = len(v)
    n = -(-T // step)
    padded = np.concatenate([v, np.repeat(v[-1:], n * step - T, axis=0)])
    return padded.reshape(n, step, -1).mean(axis=1)
