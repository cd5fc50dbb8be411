"""Parameters of the motion-structure parse (:func:`tvmedit.engine.parse.structure.parse`), each with its range.

:class:`StructureParams` holds every threshold and reach of both methods, with what each is for
and how its default was chosen; :meth:`StructureParams.recorded` reads back the parameters a
library recorded, giving the parameters added since the values the parse was made without.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field, fields

from .atoms import PAPER_FPS, PAPER_TAPS
from ..errors import ParameterError
from ..checks import MAX_FPS, number, whole

__all__ = ["StructureParams", "BEFORE", "MAX_WINDOW_S", "MAX_TAPS", "WHITENED_THRESHOLD", "RAW_THRESHOLD"]


#: Parameters added after libraries were first written, at the value a parse recorded without
#: them was made with (the rule each one adds left out).
BEFORE = {"novelty_pace": 0.0, "turn_ratio": 0.0, "novelty_components": 0, "heading_window": 0.0,
          "pause_share": 0.0, "shoulder": 0.0, "rhythm_ratio": 0.0, "comb": 0.0, "settle_free": 0.0,
          "partition": 0.0}

#: ``novelty_threshold`` where it is not given: on whitened rows (``novelty_components`` > 0),
#: in units of the take's own spread, and on the rows as they are (chosen on the development
#: suite, :mod:`tvmedit.engine.lab.accuracy`).
WHITENED_THRESHOLD = 0.9
RAW_THRESHOLD = 0.05

#: Longest atom window (eq. (5)), seconds, and most taps it may have.
MAX_WINDOW_S = 10.0
MAX_TAPS = 101


def _param(default, count=False, **limits):
    """A numeric field of :class:`StructureParams` with its range (see :func:`tvmedit.engine.checks.number`);
    ``count``: a whole number (:func:`tvmedit.engine.checks.whole`)."""
    return field(default=default, metadata={"limits": limits, "check": whole if count else number})


@dataclass(frozen=True)
class StructureParams:
    """Parameters of :func:`tvmedit.engine.parse.structure.parse`; times in seconds.

    Defaults were chosen on the development suite (:mod:`tvmedit.engine.lab.accuracy`, held out
    by group and by person) and checked on batches made after them (:mod:`tvmedit.engine.lab.fresh`).
    A rule's parameter at 0 turns the rule off.

    Attributes
    ----------
    method : {"energy", "paper"}
        "energy" (default): novelty-based clusters and period-based textons; "paper": the
        sequential procedure of section 4 as printed (see :mod:`tvmedit.engine.parse.structure`).
    window_taps : tuple of float
        Atom window of eq. (5) at ``window_fps``; an odd number >= 3 of taps. The default is
        the paper's 5-tap window {0.25, 0.5, 1, 0.5, 0.25} at 10 fps (0.5 s).
    window_fps : float
        Frame rate at which ``window_taps`` are given; at other rates the window is resampled
        to the same time span.
    beta : float
        "paper": eq. (8)'s threshold on the smallest atom distance to the current cluster. The
        paper's 0.07 belongs to its histogram scale; 0.3 suits the normalised histograms here.
    texton_contrast : float
        "paper": a local minimum of d_A(t, t_first) starts a texton only when it lies below the
        maximum since t_first by this fraction of that maximum.
    texton_drop : float
        "paper": and by at least this much in absolute terms (atom-distance units), which
        rejects the minima of a still, noisy sequence.
    min_texton : float
        Shortest texton (and shortest period searched), seconds.
    max_period : float
        Longest period searched ("energy"), seconds.
    min_periodicity : float
        "energy": a cluster has textons only when its deepest lag-profile valley dips at least
        this fraction of the profile's median (a still stretch has none).
    period_tolerance : float
        "energy": a shorter lag is preferred when its depth is within this fraction of the
        deepest (a multiple of the period is a valley too).
    submultiple : float
        "energy": the chosen lag L gives way to L/3 or L/2 where the dip there is at least this
        fraction of L's (and of the most prominent valley's): repetitions that alternate a
        little make the clearest valley two repetitions long.
    novelty_window : float
        "energy": length of each of the two blocks the novelty compares.
    novelty_threshold : float or None
        "energy": the novelty a boundary needs, in the units of its rows. None: 0.9 on whitened
        rows (units of the take's own spread), 0.05 on rows as they are.
    novelty_pace : float
        "energy": weight of each bin's change over 0.1 s beside the bin in the novelty's rows,
        so exercises of alike poses at another pace are told apart.
    novelty_components : int
        "energy": the novelty's rows are compared on this many principal axes of the take's
        change, each scaled to its spread (:func:`tvmedit.engine.parse.boundaries.whiten`).
    turn_ratio : float
        "energy": no boundary where the heading-free novelty stays under this fraction of the
        novelty within 0.5 s: the person turned, the motion did not change.
    heading_window : float
        "energy": windows over which the person's slow heading is tracked and undone
        (:mod:`tvmedit.engine.parse.heading`).
    min_cluster : float
        "energy": least distance between boundaries; the first and last cluster may be down to
        3/4 of it.
    shoulder : float
        "energy", with ``partition`` 0 only: a novelty peak within twice ``min_cluster`` of a
        stronger one that rises less than this share of its height above the valley between
        them is that peak's flank, not a boundary.
    twin_peak : float
        "energy", with ``partition`` 0 only: an earlier novelty peak within ``min_cluster`` of a
        stronger one and at least this fraction of its height is the boundary instead; 1 leaves
        the rule out.
    analysis_fps : float
        "energy": rate the sequence is reduced to for the novelty.
    max_transition : float
        "energy": a cluster this short that shows no period, or moves at under half its
        neighbour's pace, joins the exercise it leads into (:mod:`tvmedit.engine.parse.joins`).
    refine_reach : float
        "energy": how far a boundary may move to lie between whole periods
        (:func:`tvmedit.engine.parse.onsets.settle`).
    onset_reach : float
        "energy": how far a boundary may move back to where the motion left the previous
        exercise's poses (:func:`tvmedit.engine.parse.onsets.onset`).
    weak_boundary : float
        "energy": a boundary of confidence under this between two clusters of at most one
        texton, one of them without a period, is dropped.
    rhythm_ratio : float
        "energy": a novelty peak under the threshold (at least 3/4 of it) is a boundary where
        the periods either side differ by this ratio and not by a whole multiple
        (:mod:`tvmedit.engine.parse.rhythm`).
    pause_share : float
        "energy": where this share of a cluster's frames hold still, its period and textons are
        measured on the frames that move (:mod:`tvmedit.engine.parse.pauses`).
    comb : float
        "energy": textons are cut at half the period P where the lag profile also dips near
        P/2 and 3P/2, P/2's dip at least this share of P's (two repetitions read as one).
    settle_free : float
        "energy": weight of the heading-free rows beside the parser's own when a boundary is
        placed between whole periods.
    partition : float
        "energy": the boundaries are the changes of the kernel partition of the novelty's
        whitened rows with this penalty per change (:mod:`tvmedit.engine.parse.partition`); 0,
        or ``novelty_components`` 0, takes the novelty's peaks over the threshold.
    partition_floor : float
        "energy": a change of the partition is no boundary where the novelty stays under this
        share of ``novelty_threshold`` within 0.5 s of it (a slow cycle cut into pieces).
    """

    method: str = "energy"
    window_taps: tuple = PAPER_TAPS
    window_fps: float = _param(PAPER_FPS, above=0, at_most=MAX_FPS)
    beta: float = _param(0.3, at_least=0)
    texton_contrast: float = _param(0.2, at_least=0, at_most=1)
    texton_drop: float = _param(0.05, at_least=0)
    min_texton: float = _param(0.4, above=0, at_most=600)
    max_period: float = _param(5.0, above=0, at_most=600)
    min_periodicity: float = _param(0.05, at_least=0, at_most=1)
    period_tolerance: float = _param(0.5, at_least=0, at_most=1)
    submultiple: float = _param(0.7, at_least=0, at_most=1)
    novelty_window: float = _param(4.0, above=0, at_most=3600)
    novelty_threshold: float | None = _param(None, at_least=0)
    novelty_pace: float = _param(2.0, at_least=0, at_most=100)
    novelty_components: int = _param(10, count=True, at_least=0, at_most=1000)
    turn_ratio: float = _param(0.4, at_least=0, at_most=1)
    heading_window: float = _param(4.0, at_least=0, at_most=600)
    min_cluster: float = _param(2.0, above=0, at_most=3600)
    twin_peak: float = _param(1.0, at_least=0, at_most=1)
    shoulder: float = _param(0.2, at_least=0, at_most=1)
    analysis_fps: float = _param(10.0, above=0, at_most=MAX_FPS)
    max_transition: float = _param(4.0, at_least=0, at_most=3600)
    refine_reach: float = _param(1.5, at_least=0, at_most=60)
    onset_reach: float = _param(1.0, at_least=0, at_most=60)
    weak_boundary: float = _param(0.25, at_least=0, at_most=1)
    rhythm_ratio: float = _param(1.5, at_least=0, at_most=100)
    pause_share: float = _param(0.1, at_least=0, at_most=1)
    comb: float = _param(0.5, at_least=0, at_most=1)
    settle_free: float = _param(1.0, at_least=0, at_most=100)
    partition: float = _param(20.0, at_least=0)
    partition_floor: float = _param(0.7, at_least=0)

    def __post_init__(self):
        if self.method not in ("energy", "paper"):
            raise ParameterError(f"method={self.method!r} is not a structure method; use 'energy' or 'paper'.")
        if self.novelty_threshold is None:
            whitened = whole("novelty_components", self.novelty_components, at_least=0) > 0
            object.__setattr__(self, "novelty_threshold", WHITENED_THRESHOLD if whitened else RAW_THRESHOLD)
        for f in fields(self):
            if "limits" in f.metadata:
                value = f.metadata["check"](f.name, getattr(self, f.name), **f.metadata["limits"])
                object.__setattr__(self, f.name, value)
        taps = tuple(number("window_taps", tap, at_least=0) for tap in self.window_taps)
        if not 3 <= len(taps) <= MAX_TAPS or len(taps) % 2 == 0 or not sum(taps) > 0:
            raise ParameterError(f"window_taps has {len(taps)} taps summing to {sum(taps):g}; the atom "
                                 f"window needs an odd number from 3 to {MAX_TAPS} of them, not all 0.")
        object.__setattr__(self, "window_taps", taps)
        if (len(taps) - 1) / self.window_fps > MAX_WINDOW_S:
            raise ParameterError(f"window_fps={self.window_fps:g} makes the atom window "
                                 f"{(len(taps) - 1) / self.window_fps:g} s long; it may span at most "
                                 f"{MAX_WINDOW_S:g} s.")
        if 0 < self.rhythm_ratio < 1:
            raise ParameterError(f"rhythm_ratio={self.rhythm_ratio:g} is a ratio of the longer period to the "
                                 f"shorter, at least 1; use 0 to leave weak peaks out.")
        if self.max_period <= self.min_texton:
            raise ParameterError(f"max_period={self.max_period:g} must be above "
                                 f"min_texton={self.min_texton:g}.")
        # A threshold of the other scale (an older script's 0.05 with whitened rows, say).
        if self.novelty_components > 0 and self.novelty_threshold < 5 * RAW_THRESHOLD:
            warnings.warn(f"novelty_threshold={self.novelty_threshold:g} is in units of the take's own spread "
                          f"while novelty_components={self.novelty_components} whitens the novelty's rows "
                          f"({WHITENED_THRESHOLD:g} is the default there; {RAW_THRESHOLD:g} belongs to "
                          f"novelty_components=0); expect many more boundaries.", stacklevel=3)
        elif self.novelty_components == 0 and self.novelty_threshold > 0.5 * WHITENED_THRESHOLD:
            warnings.warn(f"novelty_threshold={self.novelty_threshold:g} is in units of histograms with "
                          f"novelty_components=0 (the default there is {RAW_THRESHOLD:g}; "
                          f"{WHITENED_THRESHOLD:g} belongs to whitened rows); expect few or no boundaries.",
                          stacklevel=3)

    @classmethod
    def recorded(cls, data):
        """The parameters a parse recorded (``Structure.params``, a library's manifest), with
        each parameter added since it was made at the value that parse was made without
        (:data:`BEFORE`), so that re-deriving it does what the parse did.

        >>> StructureParams.recorded({"novelty_threshold": 0.05}).novelty_components
        0
        >>> StructureParams.recorded({}).novelty_threshold   # made without whitening: its threshold
        0.05
        >>> StructureParams.recorded({}).heading_window      # and read the histograms as they stood
        0.0
        >>> StructureParams.recorded({}).pause_share         # and measured every frame of a cluster
        0.0
        >>> StructureParams.recorded({}).partition           # and took the novelty's peaks
        0.0
        >>> StructureParams.recorded(StructureParams().__dict__) == StructureParams()
        True
        """
        return cls(**{**BEFORE, **{k: v for k, v in data.items() if k in cls.__dataclass_fields__}})
