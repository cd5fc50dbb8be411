"""Which way a person faces as they exercise: the slow turn tracked, and undone for the parser.

A person seldom keeps facing one way through a take: they turn a little between repetitions,
drift round while jogging, or turn on purpose. Every azimuth (theta) histogram then shifts
around the circle with the heading although the motion does not change, and a parser that
compares histograms as they stand reads a turn as a change of pose, misses repetitions, and
moves boundaries early.

:func:`heading_track` follows the slow part of the heading: the mean theta histogram of each
``window`` seconds of frames (whole repetitions, so the motion's own phase averages out),
taken every :data:`HOP` seconds, is compared with the next one turned by every whole number
of bins up to :data:`MOST` degrees either way; the turn that brings them nearest is the
heading's change over that hop, and the heading is their running sum, linear between window
centres. Whole bins only, so windows that match best unturned are left exactly as they are;
what is left drifts by at most half a bin a second, small over the few seconds the parser
compares. :func:`turned` shifts each frame's theta histogram by an angle, a fraction of a bin
shared linearly between the two bins it falls between (a turn about the vertical changes no r
or phi histogram); :func:`tvmedit.engine.parse.structure.parser_view` reads every frame turned
back by the tracked heading (``StructureParams.heading_window``). The stored features stay
eq. (1)'s.

Two views of the azimuth histograms serve the parser too. :func:`azimuth_smoothed` convolves
each theta histogram with (1/4, 1/2, 1/4) around the circle, so a body turned a fraction of a
5 degree bin moves a fraction of its vertices across a bin edge, not whole shares.
:func:`azimuth_spectrum` keeps only what no turn changes (the magnitudes of the histogram's
Fourier coefficients about the circle): the heading-free rows of the turn veto.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["heading_track", "turned", "azimuth_smoothed", "azimuth_spectrum", "HOP", "MOST"]

#: Seconds between the windows whose mean histograms are matched.
HOP = 1.0

#: Largest turn, in degrees, looked for between two windows one hop apart (30 degrees a second).
MOST = 30.0


def turned(vectors, theta, heading):
    """Feature rows with each frame's body turned by ``heading`` (radians) about the vertical.

    Each azimuth histogram is shifted around the circle by its frame's angle (positive: to
    higher bins), a fraction of a bin shared linearly between the two bins it falls between;
    the r and phi columns are left as they are.

    Parameters
    ----------
    vectors : (T, D) array
    theta : slice
        The azimuth histogram's columns.
    heading : (T,) array or float
        Radians, one per frame (or one for all).

    Returns
    -------
    (T, D) float64

    Examples
    --------
    >>> v = np.array([[7.0, 1.0, 0.0, 0.0, 0.0]])
    >>> turned(v, slice(1, 5), np.pi / 2).tolist()        # a quarter turn: one bin of four
    [[7.0, 0.0, 1.0, 0.0, 0.0]]
    >>> turned(v, slice(1, 5), np.pi / 4).tolist()        # half a bin: shared
    [[7.0, 0.5, 0.5, 0.0, 0.0]]
    """
    out = np.array(vectors, dtype=np.float64)
    h = out[:, theta].copy()
    n = h.shape[1]
    shift = np.broadcast_to(np.asarray(heading, dtype=np.float64) * n / (2 * np.pi), (len(out),))
    whole = np.floor(shift).astype(int)[:, None]
    frac = (shift - np.floor(shift))[:, None]
    j = np.arange(n)
    rows = np.arange(len(out))[:, None]
    out[:, theta] = (1 - frac) * h[rows, (j - whole) % n] + frac * h[rows, (j - whole - 1) % n]
    return out


def heading_track(vectors, theta, fps, window=4.0):
    """The slow part of the heading at every frame, radians, relative to the first window's.

    Parameters
    ----------
    vectors : (T, D) array
        Feature rows (the parser's view: azimuth histograms smoothed).
    theta : slice
        The azimuth histogram's columns.
    fps : float
    window : float
        Seconds of frames averaged into each histogram matched; whole repetitions of the
        slowest exercise, so that its phase averages out.

    Returns
    -------
    (T,) float64, in units of 2 pi / (number of theta bins) a bin; held at the first window
    centre's value before it and at the last one's after it (the first and last half window).
    0 throughout for a take shorter than a window and a hop, whose windows match best
    unturned, or whose azimuth bins are wider than 15 degrees (a whole bin is too coarse a
    turn to follow). Frames that are not finite count as empty histograms.

    Examples
    --------
    >>> t = np.arange(300)                                  # 30 s at 10 fps, 72 bins
    >>> j = np.arange(72)
    >>> pose = lambda centre: np.exp(-0.5 * (((j - centre + 36) % 72 - 36) / 3.0) ** 2)
    >>> v = np.array([pose(10 + 4 * np.sin(2 * np.pi * k / 12)) for k in t])   # no turn
    >>> float(np.abs(heading_track(v, slice(0, 72), 10)).max())
    0.0
    >>> v = turned(v, slice(0, 72), np.radians(6.0) * t / 10)                  # 6 degrees a second
    >>> h = np.degrees(heading_track(v, slice(0, 72), 10))
    >>> bool(abs(h[250] - h[50] - 120) <= 25)                                   # 20 s: 120 degrees
    True
    """
    # A row that is not finite (a frame the caller could not measure) counts as empty.
    h = np.nan_to_num(np.asarray(vectors, dtype=np.float64)[:, theta], nan=0.0, posinf=0.0, neginf=0.0)
    T, n = h.shape
    out = np.zeros(T)
    half = max(1, int(round(window * fps / 2)))
    step = max(1, int(round(HOP * fps)))
    centres = np.arange(half, T - half + 1, step)
    most = int(MOST * n // 360)
    # Bins wider than 15 degrees (or none): a whole bin is too coarse a turn to follow.
    if most < 2 or len(centres) < 2:
        return out
    sums = np.vstack([np.zeros((1, n)), np.cumsum(h, axis=0)])
    means = (sums[centres + half] - sums[centres - half]) / (2 * half)
    shifts = np.arange(-most, most + 1)
    # For each pair of successive windows, the whole-bin turn that brings the first nearest
    # the second (the smallest turn among equals: none, where none does better).
    errors = np.stack([((np.roll(means[:-1], s, axis=1) - means[1:]) ** 2).sum(axis=1) for s in shifts], axis=1)
    order = np.argsort(np.abs(shifts), kind="stable")
    best = shifts[order][np.argmin(errors[:, order], axis=1)]
    heading = np.concatenate([[0.0], np.cumsum(best)]) * 2 * np.pi / n
    return np.interp(np.arange(T), centres, heading)


def azimuth_smoothed(vectors, theta):
    """Feature rows whose azimuth (theta) histograms are smoothed over neighbouring bins.

    Each theta histogram is convolved with (1/4, 1/2, 1/4) around the circle (bin j takes
    a quarter of bins j - 1 and j + 1), so a vertex counts partly in the bins next to its
    own: the histogram of a body turned by a fraction of a bin changes by a fraction of
    its vertices, not by whole shares jumping across hard edges. The r and phi histograms
    and each row's total are unchanged. :func:`tvmedit.engine.parse.structure.parse` reads the
    features through it (method "energy"); stored features stay eq. (1)'s.

    Why: with features in the body's own frame (:mod:`tvmedit.engine.capture.orientation`) the
    body's front falls anywhere within a 5 degree bin, and decisions taken on hard-edged
    histograms moved with it.

    Parameters
    ----------
    vectors : (T, D) array
        Rows of :attr:`Features.vectors`.
    theta : slice
        Their theta columns (:attr:`Features.theta_columns`).

    Returns
    -------
    (T, D) float64
        A new array.

    Examples
    --------
    >>> v = np.array([[9.0, 1.0, 0.0, 0.0, 0.0, 7.0]])
    >>> azimuth_smoothed(v, slice(1, 5)).tolist()
    [[9.0, 0.5, 0.25, 0.0, 0.25, 7.0]]
    """
    out = np.array(vectors, dtype=np.float64)
    h = out[:, theta].copy()
    out[:, theta] = 0.5 * h + 0.25 * (np.roll(h, 1, axis=1) + np.roll(h, -1, axis=1))
    return out


def azimuth_spectrum(vectors, theta):
    """Feature rows whose azimuth histograms are replaced by their circular spectrum's
    magnitudes: the same rows whichever way the body faces about up.

    A turn of the body about up shifts its theta histogram around the circle and leaves the
    magnitude of every Fourier coefficient as it was; scaled so that the Euclidean distance
    between two rows' spectra is at most the distance between the rows (Parseval). The r and
    phi columns stay.
    :mod:`tvmedit.engine.parse.boundaries` compares blocks this way to tell a turn from a new motion.

    Parameters
    ----------
    vectors : (T, D) array
    theta : slice
        The azimuth histogram's columns.

    Returns
    -------
    (T, D') float64
        The r and phi columns, then ``n // 2 + 1`` spectrum magnitudes (n theta bins).

    Examples
    --------
    >>> v = np.array([[5.0, 1.0, 0.0, 0.0, 0.0], [5.0, 0.0, 0.0, 1.0, 0.0]])
    >>> s = azimuth_spectrum(v, slice(1, 5))
    >>> s.shape, bool(np.allclose(s[0], s[1]))
    ((2, 4), True)
    """
    v = np.asarray(vectors, dtype=np.float64)
    h = v[:, theta]
    n = h.shape[1]
    weight = np.full(n // 2 + 1, math.sqrt(2.0))
    weight[0] = 1.0
    if n % 2 == 0:
        weight[-1] = 1.0
    spectrum = np.abs(np.fft.rfft(h, axis=1)) * weight / math.sqrt(n)
    rest = np.ones(v.shape[1], dtype=bool)
    rest[theta] = False
    return np.hstack([v[:, rest], spectrum])
