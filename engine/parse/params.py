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
#: them was made with (the step each one adds left out).
BEFORE = {"novelty_pace": 0.0, "turn_ratio": 0.0, "novelty_components": 0, "heading_window": 0.0,
          "pause_share": 0.0, "shoulder": 0.0, "rhythm_ratio": 0.0, "comb": 0.0, "settle_free": 0.0,
          "partition": 0.0}

#: ``novelty_threshold`` where it is not given: on whitened rows (``novelty_components`` > 0),
#: in units of the take's own spread, and on the rows as they are (chosen on the development
#: suite, ``benchmarks/accuracy.py``).
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

    Attributes
    ----------
    method : {"energy", "paper"}
        "energy" (default): novelty-based clusters and period-based textons; "paper": the
        sequential procedure of section 4 as printed (see the module docstring).
    window_taps : tuple of float
        Atom window of eq. (5) at ``window_fps``; an odd number >= 3 of taps. The default is
        the paper's 5-tap window {0.25, 0.5, 1, 0.5, 0.25} at 10 fps (0.5 s).
    window_fps : float
        Frame rate at which ``window_taps`` are given; at other rates the window is
        resampled to the same time span.
    beta : float
        Eq. (8) threshold on the smallest atom distance to the current cluster ("paper").
        The paper's 0.07 belongs to its histogram scale (on our normalised 2 cm / 5 degree
        histograms it fires inside every exercise); 0.3 (with ``texton_contrast`` 0.2) gave
        the best boundary scores of a grid (beta 0.07-0.6, contrast 0.2-0.5) on the base
        takes 13_29 and 13_30, and is still far from usable (``benchmarks/accuracy.py``).
    texton_contrast : float
        "paper": a local minimum of d_A(t, t_first) starts a texton only when it lies below
        the maximum since t_first by this fraction of that maximum.
    texton_drop : float
        "paper": and by at least this much in absolute terms (atom-distance units), which
        is what rejects the minima of a still, noisy sequence.
    min_texton : float
        Shortest texton (and shortest period searched), seconds.
    max_period : float
        Longest period searched ("energy"), seconds.
    min_periodicity : float
        "energy": a cluster has textons only when its deepest lag-profile valley is at
        least this fraction of the profile's median deep (still sequences have none).
    period_tolerance : float
        "energy": a shorter lag is preferred when its depth is within this fraction of the
        deepest (depth: how far below the profile's median the mean atom distance falls);
        0.5 chosen by cross-validation on the development suite (0.3 before).
    submultiple : float
        "energy": the chosen lag L gives way to a valley at L/3 or L/2 whose dip below the
        profile's median is at least this fraction of the dip at L, and of the dip at the
        most prominent valley where that is deeper (repetitions that
        alternate a little, e.g. in heading, made the clearest valley two repetitions
        long); 0 turns the test off. On the development suite after step 34, 0.5 scores
        0.98 / 0.97 / 0.93 pooled and 0.9 0.98 / 0.98 / 0.93, against 0.98 / 0.98 / 0.94 at
        0.7 (when the test came in any value in 0.5-0.9 scored alike; 0.4 halved a texton of
        CMU 13_29).
    novelty_window : float
        "energy": length of each of the two blocks compared, seconds. 4 s (3 s until step 4
        of docs/parsing.md) was chosen over 3 s by every fold of leave-one-group-out
        cross-validation on the development suite from step 4 to step 17; it is now held
        fixed there (``benchmarks/accuracy.py``).
    novelty_threshold : float or None
        "energy": smallest energy-distance peak that counts as a cluster boundary, in the
        units of the novelty's rows (with ``partition``, a change of the partition needs
        ``partition_floor`` of it, and the threshold still rules the peaks near the ends,
        behind turns and where the rhythm changes, and the confidence). None (the default) is 0.9 where they are whitened
        (``novelty_components`` > 0: units of the take's own spread along each kept axis) and
        0.05 where they are not (units of histograms and their pace).
    turn_ratio : float
        "energy": a novelty peak is no boundary where the novelty of the same blocks compared
        whichever way the body faces (tvmedit.engine.parse.heading.azimuth_spectrum) stays under this
        fraction of it within 0.5 s: the person turned, the motion did not change; near
        such a turn, boundaries are found and placed on the heading-free rows
        (tvmedit.engine.parse.boundaries, *Boundaries behind a turn*); 0: no veto (nor is there one
        without the azimuth columns, ``theta``).
    novelty_components : int
        "energy": the novelty compares its rows on this many principal axes of the take's
        change, each scaled to its spread (tvmedit.engine.parse.boundaries.whiten), so that an exercise
        that differs from the next in a direction of little variance is seen; 0 compares the
        rows as they are.
    novelty_pace : float
        "energy": weight of each histogram bin's pace of change (its absolute change over
        0.1 s, whatever the frame rate) beside the bin itself in the novelty's frame rows
        (tvmedit.engine.parse.boundaries), so that exercises of alike poses done at another pace are told
        apart; 0 compares poses only. 2 since step 29 of docs/parsing.md (1 before): on the
        whitened rows the weight decides how many of the kept principal axes describe pace.
    heading_window : float
        "energy": the parser reads each frame's azimuth histogram turned back by the person's
        slow heading, tracked by matching the mean histograms of windows of this many
        seconds one second apart (tvmedit.engine.parse.heading), so that a person who turns as they
        exercise is read as if they kept facing one way; 0 reads the histograms as they are.
    min_cluster : float
        "energy": least distance between boundaries, seconds; the first and last cluster
        may be down to 3/4 of it.
    shoulder : float
        "energy", with ``partition`` 0 only (the novelty's peaks): a novelty peak within twice
        ``min_cluster`` of a stronger one already taken that rises less than this share of its
        height above the lowest novelty between them is the stronger peak's shoulder, not a
        boundary; 0 keeps it.
    twin_peak : float
        "energy", with ``partition`` 0 only: an earlier novelty peak within ``min_cluster`` of a stronger one and at
        least this fraction of its height is the boundary instead; 1 (the default since step
        30 of docs/parsing.md, 0.9 before) leaves the rule out: the later steps that place a
        boundary (between whole periods, at the onset) already take it back where the motion
        changes, and with the rule too they took changes 1-2 s off, mostly early.
    analysis_fps : float
        "energy": rate to which the sequence is reduced for cluster detection.
    max_transition : float
        "energy": a cluster of at most this many seconds that shows no period (not one whole
        texton), or changes pose at under half the pace of its neighbour (standing still), is
        a transition and joins the exercise it leads into; 0 keeps it.
    refine_reach : float
        "energy": a boundary moves by up to this many seconds to where blocks of whole periods
        before and after it differ most (tvmedit.engine.parse.onsets.settle); 0 keeps it where step 1 put it.
    onset_reach : float
        "energy": a boundary moves back by up to this many seconds from where steps 1 and 4
        put it to where the motion left the previous exercise's poses (tvmedit.engine.parse.onsets); 0
        keeps it there.
        1 s since step 36 of docs/parsing.md (2 s before): with the partition's changes
        (``partition``), which already lie where the distribution of poses changes, 2 s took
        some changes back 2-3 s early (development suite 0.99 / 0.98 / 0.94 at 1 s and 0.98 /
        0.97 / 0.94 at 2 s; the 26 fresh batches 547 right boundaries of 578 found and 543 of
        579, of 580 changes; with the
        novelty's peaks, before step 36's other parts, 1 s scores 0.99 / 0.98 / 0.93 and 2 s
        0.98 / 0.98 / 0.93).
    weak_boundary : float
        "energy": a boundary whose confidence (tvmedit.engine.parse.confidence) is under this, between two
        clusters of at most one texton each, at least one of which shows no period, is
        dropped; 0 keeps every boundary.
    rhythm_ratio : float
        "energy": a novelty peak under the threshold (but at least 3/4 of it) is a boundary
        where the longer of the periods before and after it is this many times the shorter
        or more, and not a whole multiple of it (tvmedit.engine.parse.rhythm); at least 1, or 0 to leave
        every such peak out.
    pause_share : float
        "energy": where at least this share of a cluster's frames hold still (pauses between
        repetitions), its period and textons are measured on the frames that move and each
        texton keeps the pause after it (tvmedit.engine.parse.pauses); 0 measures every frame.
    comb : float
        "energy": a cluster's textons are cut at half the period P read for it where the lag
        profile also dips near P/2 and 3P/2, P/2's dip at least this share of P's (two
        repetitions that differ read as one period: tvmedit.engine.parse.periods, *Two repetitions in one
        texton*); 0 never.
    settle_free : float
        "energy": weight of the heading-free rows beside the parser's own when a boundary is
        placed between whole periods (``refine_reach``; tvmedit.engine.parse.onsets, *Both views*): each
        view's energy distances scaled to their largest, summed with this weight on the
        heading-free view's; 0 reads the parser's rows alone. Near a vetoed turn, and where
        the settled boundary would move back over frames that are only the old poses turned
        (step 24's test, which reads the boundaries this places), the heading-free rows are
        read alone either way.
    partition : float
        "energy": step 1's boundaries are the changes of the partition of the novelty's
        whitened rows of least within-segment energy scatter plus this penalty per change
        (tvmedit.engine.parse.partition; step 36 of docs/parsing.md), rather than the novelty's peaks over
        ``novelty_threshold``; 0 (or ``novelty_components`` 0: the penalty is in units of the
        whitened rows) takes the peaks, as before step 36. 20 was read off the development
        suite and the fresh batches (16: more false boundaries, 24 fewer right ones).
    partition_floor : float
        "energy": a change of the partition is no boundary where the novelty stays under this
        share of ``novelty_threshold`` within 0.5 s of it (a slow exercise's long cycle cut
        into ``min_cluster`` pieces: CMU 13_29 played at 0.7x); 0 keeps every change.
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
