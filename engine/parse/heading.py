"""Which way a person faces as they exercise: the slow turn tracked, and undone for the parser.

A person seldom keeps facing one way through a take: they turn a little between repetitions,
turn back, drift round while jogging or kicking, or turn on purpose (HDM05's clips, stitched
each facing as the last one ended, drift 15-75 degrees over a take; CMU subject 13 turns
10-40 degrees over 13_29 and 13_30, as far as this tracker reads). Every azimuth (theta)
histogram then shifts around the circle with the heading, although the motion does not
change, and the parser, which compares histograms as they stand, saw it three ways: novelty
peaks inside an exercise (a turn looks like a change of pose), repetitions farther apart than
they are (a period missed or doubled), and a boundary moved early by the onset step (the old
exercise's poses, seen turned, look left behind).

:func:`heading_track` follows the slow part of the heading: the mean theta histogram of each
``window`` seconds of frames (whole repetitions, so the motion's own phase averages out),
taken every :data:`HOP` seconds, is compared with the next one turned by every whole number
of bins up to :data:`MOST` degrees either way; the turn that brings them nearest is the
heading's change over that hop, and the heading is their running sum, linear between window
centres. Whole bins only, so a turn is followed in steps of a bin (5 degrees) a second: 6
degrees a second is followed as 5, 3 as 5, and successive windows that match best unturned
(the synthetic actor on its spot) are left exactly as they are. The rounding is not made up
later, so what is left drifts by up to half a bin a second, and a change of exercise can
leave a lasting offset of a bin or a few (a synthetic take that never turns ends 5 degrees
off); the parser compares frames a few seconds apart, for which either is small. Windows
shorter than a repetition let the motion's own phase through in 5 degree steps. Summing
fractions of a bin and rounding the sum instead scored less on the suite (below).
:func:`turned` shifts each frame's theta histogram by an angle, a fraction of a bin shared
linearly between the two bins it falls between (a turn about the vertical changes no r or
phi histogram); :func:`tvmedit.engine.parse.structure.parser_view` reads every frame turned back by the
tracked heading (``StructureParams.heading_window``), so every step of the parser compares
poses as if the person had kept facing one way. The stored features stay eq. (1)'s.

Measured on the development suite (``benchmarks/accuracy.py``, 42 takes; precision / recall /
texton length, the defaults): in the body's axes pooled 0.953 / 0.940 / 0.874 -> 0.979 /
0.934 / 0.898. Gained: CMU 13_29 turning 6 degrees a second (its meshes rotated) lost its
false boundary inside an exercise and a wrong texton, the synthetic actor swaying over +/- 90
degrees a half-period texton of its side bends; HDM05 three false boundaries and a missed
one (around a block of floor deposits, at a take's start) and four wrong texton lengths.
Lost: two true boundaries (CMU 13_30 at 1.4x, an HDM05 take). Still wrong: CMU 13_30 swaying
over +/- 90 degrees keeps half-period textons of its one-hand toe touches. In tvmedit's axes
(``TVMEDIT_DEV_FRAME=stored``) 0.959 / 0.934 / 0.888 -> 0.959 / 0.927 / 0.894 (13_29 turning:
five errors -> one; HDM05 gained and lost about as much). Windows of 3-6 s score alike
(body's axes 0.966-0.979 / 0.934-0.940 / 0.898-0.904, tvmedit's 0.959-0.966 / 0.927-0.947 /
0.889-0.909); at 2 s the motion's own phase moves the window means (0.946 / 0.927 / 0.889).
The default is the novelty's own 4 s block. Summing fractions of a bin (read off
the fit's parabola) and rounding the sum: 0.966 / 0.927 / 0.914 in the body's axes, 0.959 /
0.934 / 0.884 in tvmedit's; turning the view by the fractions too: 0.965 / 0.921 / 0.914.

Written with numpy alone: the match is a circular shift of a 72-bin histogram, 13 shifts per
hop; a library (scipy.signal's correlation, scikit-image's phase correlation) would do the
same arithmetic on arrays this small.
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

    Why: with features in the body's own frame (:mod:`tvmedit.engine.capture.orientation`) the body's
    front falls anywhere within a 5 degree bin, and the parser, whose decisions were
    taken on hard-edged histograms of takes facing along an axis, lost boundaries:
    development suite pooled precision / recall / texton accuracy 0.94 / 0.93 / 0.92 in
    the body's frame against 0.97 / 0.95 / 0.96 in tvmedit's axes. Smoothed (with the
    strong-edge rule of :mod:`tvmedit.engine.parse.boundaries`), 0.95 / 0.96 / 0.93 and 0.97 / 0.95 /
    0.95, and leave-one-group-out in the body's frame 0.902 / 0.874 / 0.908 -> 0.929 /
    0.958 / 0.912 (``benchmarks/accuracy.py``). Smoothing phi as well, or wider kernels,
    cost recall (0.87-0.93 pooled).

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
