"""A sequence's structure laid out on a timeline: what ``tvmedit inspect`` draws, as plain numbers.

The inspector (``tvmedit.player.inspect``) shows one sequence at a time under its 3D view: the
atom-distance curve d_A(t, t_first) of the paper's Figure 4, the motion clusters as bands,
the texton starts as ticks (their height follows the parser's confidence where the parse
gives one), the representative texton of every cluster (eq. (9)) highlighted, the cluster
boundaries (those drawn by hand in another colour, those removed by hand as ghosts) and a
playhead. :class:`Timeline` holds that data and lays it out in a pixel box as rectangles and
one polyline (:meth:`Timeline.shapes`), so the player only draws them, and everything here
is tested without GL.
"""

from dataclasses import dataclass, field

import numpy as np

__all__ = ["Timeline", "Shapes", "timeline", "COLOURS"]

#: RGBA colours of the timeline's parts, 0..1.
COLOURS = {
    "background": (0.07, 0.07, 0.09, 1.0),
    "bands": ((0.23, 0.36, 0.55, 1.0), (0.45, 0.31, 0.52, 1.0), (0.25, 0.48, 0.38, 1.0),
              (0.55, 0.42, 0.24, 1.0)),
    "representative": (1.0, 0.85, 0.3, 1.0),
    "texton": (0.8, 0.85, 0.9, 0.9),
    "boundary": (1.0, 1.0, 1.0, 1.0),
    "corrected": (1.0, 0.55, 0.1, 1.0),
    "removed": (0.9, 0.25, 0.25, 0.6),
    "curve": (0.35, 0.85, 1.0, 1.0),
    "playhead": (1.0, 0.2, 0.35, 1.0),
}

#: Parts of the box, as fractions of its height from the top: the cluster bands and the curve.
BAND = (0.0, 0.16)
CURVE = (0.22, 1.0)


@dataclass
class Shapes:
    """What to draw, in pixels (x right, y down): ``rects`` (n, 4) float32 ``x, y, w, h``
    with ``colours`` (n, 4) float32, and the curve as ``curve`` (T, 2) float32 points."""

    rects: np.ndarray
    colours: np.ndarray
    curve: np.ndarray
    curve_colour: tuple = COLOURS["curve"]


@dataclass
class Timeline:
    """One sequence's structure for the inspector (frames are 0-based, ranges inclusive).

    Attributes
    ----------
    sequence : str
    fps : float
    curve : (T,) float64
        d_A(t, t_first), Figure 4.
    clusters : list of (start, end)
    textons : list of (start, end, cluster)
    confidence : list of (float or None), or None
        Per texton, 0..1, where the parse gives one (None for a texton without).
    representatives : list of (start, end)
        The texton each motion of the database plays.
    added, removed : list of int
        Cluster boundaries drawn and removed by hand (against the automatic parse).
    """

    sequence: str
    fps: float
    curve: np.ndarray
    clusters: list
    textons: list
    confidence: list = None
    representatives: list = field(default_factory=list)
    added: list = field(default_factory=list)
    removed: list = field(default_factory=list)

    @property
    def frames(self):
        return len(self.curve)

    @property
    def boundaries(self):
        """First frames of every cluster but the first."""
        return [s for s, _ in self.clusters[1:]]

    @property
    def texton_starts(self):
        return [t[0] for t in self.textons]

    def cluster_at(self, frame):
        """Index of the cluster holding ``frame``."""
        return next(k for k, (s, e) in enumerate(self.clusters) if s <= frame <= e)

    def texton_at(self, frame):
        """``(start, end, cluster)`` of the texton holding ``frame``, or None."""
        return next((t for t in self.textons if t[0] <= frame <= t[1]), None)

    def nearest_marker(self, frame):
        """``("boundary" or "texton", frame)`` of the marker nearest ``frame`` (a boundary on a
        tie), or None when there is none.

        >>> t = Timeline("a", 10, np.zeros(40), [(0, 19), (20, 39)], [(2, 9, 0), (10, 17, 0)])
        >>> t.nearest_marker(12), t.nearest_marker(18)
        (('texton', 10), ('boundary', 20))
        """
        marks = [(abs(b - frame), 0, "boundary", b) for b in self.boundaries]
        marks += [(abs(s - frame), 1, "texton", s) for s in self.texton_starts]
        return min(marks)[2:] if marks else None

    def x_of(self, frame, box):
        """Pixel x of the left edge of ``frame`` in ``box`` = (x, y, w, h)."""
        x, _, w, _ = box
        return x + w * frame / max(self.frames, 1)

    def frame_at(self, px, box):
        """The frame under pixel x ``px`` (clamped to the sequence)."""
        x, _, w, _ = box
        return int(np.clip((px - x) / max(w, 1) * self.frames, 0, self.frames - 1))

    def shapes(self, box, playhead=None):
        """Lay the timeline out in ``box`` = (x, y, w, h) pixels; returns :class:`Shapes`.

        Top: cluster bands (alternating colours), the representative texton of each cluster
        highlighted in them. Below: the curve, scaled to its largest value, texton starts as
        ticks up from the bottom (full height, or the confidence's share of it), cluster
        boundaries as full-height lines (by hand: orange; removed by hand: red ghosts) and the
        playhead.
        """
        x, y, w, h = (float(v) for v in box)
        unit = w / max(self.frames, 1)
        rects, colours = [[x, y, w, h]], [COLOURS["background"]]

        def rows(part):
            return y + part[0] * h, (part[1] - part[0]) * h

        band_y, band_h = rows(BAND)
        for k, (s, e) in enumerate(self.clusters):
            rects.append([self.x_of(s, box), band_y, (e - s + 1) * unit, band_h])
            colours.append(COLOURS["bands"][k % len(COLOURS["bands"])])
        for s, e in self.representatives:
            rects.append([self.x_of(s, box), band_y + 0.55 * band_h, (e - s + 1) * unit, 0.45 * band_h])
            colours.append(COLOURS["representative"])
        curve_y, curve_h = rows(CURVE)
        line = max(1.0, min(2.0, unit))
        for k, (s, _, _) in enumerate(self.textons):
            known = self.confidence is not None and self.confidence[k] is not None
            share = float(np.clip(self.confidence[k], 0.1, 1.0)) if known else 1.0
            rects.append([self.x_of(s, box), curve_y + curve_h * (1 - share), line, curve_h * share])
            colours.append(COLOURS["texton"])
        for frames, colour in ((self.removed, "removed"), (self.boundaries, "boundary"), (self.added, "corrected")):
            for b in frames:
                rects.append([self.x_of(b, box) - line / 2, y, line + 1, h])
                colours.append(COLOURS[colour])
        if playhead is not None:
            rects.append([self.x_of(playhead + 0.5, box) - 1, y, 2.0, h])
            colours.append(COLOURS["playhead"])
        top = float(np.max(self.curve)) if self.frames and np.max(self.curve) > 0 else 1.0
        points = np.stack([x + (np.arange(self.frames) + 0.5) * unit,
                           curve_y + curve_h * (1 - 0.95 * np.asarray(self.curve) / top)], axis=1)
        return Shapes(np.asarray(rects, np.float32), np.asarray(colours, np.float32), points.astype(np.float32))


def timeline(sequence, structure, parse=None, nodes=()):
    """The :class:`Timeline` of ``sequence`` from its (corrected) ``structure``, its automatic
    ``parse`` (to mark boundaries changed by hand) and the database ``nodes`` (whose textons
    of this sequence are the representatives).
    """
    boundaries = {s for s, _ in structure.clusters[1:]}
    automatic = boundaries if parse is None else {s for s, _ in parse.clusters[1:]}
    confidence = [getattr(t, "confidence", None) for t in structure.textons]
    confidence = [None if c is None else float(c) for c in confidence]
    return Timeline(
        sequence=sequence, fps=float(structure.fps), curve=np.asarray(structure.curve, np.float64),
        clusters=[(int(s), int(e)) for s, e in structure.clusters],
        textons=[(int(t.start), int(t.end), int(t.cluster)) for t in structure.textons],
        confidence=confidence if any(c is not None for c in confidence) else None,
        representatives=[(n.start, n.end) for n in nodes if n.sequence == sequence],
        added=sorted(boundaries - automatic), removed=sorted(automatic - boundaries))
