"""The edited sequence: best paths between key motions played as a frame schedule (section 8).

The user picks two or more key motions; between each neighbouring pair the best path of
eq. (15)-(16) is searched, and the paths are played one after another. Every texton is a
cycle (section 5: after its last frame comes its first), and section 8 plays it so that "the
transition is as fast as possible but every frame in the motion texton is rendered at least
once before transition". A texton of L frames, entered at frame e and left at frame x (both
absolute, start <= e, x <= end), is therefore shown for

    n(e, x) = L + ((x - e + 1) mod L)                                         (play length)

frames: the smallest n >= L whose last frame, e + n - 1 taken cyclically, is x. The first
key motion starts at its first frame; the last is played ``loops`` full cycles from where it
is entered (forever with ``loops=None``).

A one-shot motion (``kind="once"``, a stretch of a take that does not repeat, see
:mod:`tvmedit.engine.graph.database`) is not a cycle: it is entered at its first frame and played through
once to its exit frame x, which lies in its last part (:func:`tvmedit.engine.graph.motiongraph.exit_range`), so
it shows n = ((x - e) mod L) + 1 frames, the first arrival at x. As the last key motion, or
while the player rests in it, it plays whole and starts again.

Where the library holds in-between frames for an edge (:mod:`tvmedit.engine.inbetween.blend`; the graph's edge
attribute ``blend`` counts them), they are played between the exit frame and the entry frame:
they replace the cut and shorten no texton. Each is a :class:`ScheduleEntry` with ``blend``
set to ``((from, to), i)``; its node, sequence and frame are those of the frame it was
warped from (the exit frame for the first half of the run, the entry frame for the rest).

A leg whose two key motions are the same motion is empty: path ``[key]``, cost 0, no edges,
no frames. The motion simply continues, and the next leg starts where it would have. With a
time asked (``timing``, :mod:`tvmedit.engine.graph.timing`) it is a hold: the motion plays on cyclically for
that many frames, and the next leg starts from the frame it has reached. A leg between two
motions with a time asked takes the path and extra loops :func:`tvmedit.engine.graph.timing.plan_leg` picks.

:func:`compose` plans a whole edit at once; :class:`tvmedit.engine.playback.Playhead` plays the
same schedule one frame at a time while key motions are queued and unqueued, for the realtime player.
"""

import itertools
import math
from dataclasses import dataclass, field
from functools import partial
from itertools import repeat
from typing import NamedTuple


from ..errors import LibraryError, TvmError
from ..checks import MAX_LOOPS, whole
from .motiongraph import node_by_key
from .search import SearchIndex, best_path, motion_label
from ..inbetween.loops import closing

#: Most frames a key motion of the player may be held for (an hour at 1,000 fps).
MAX_HOLD = 3_600_000

__all__ = ["ScheduleEntry", "Transition", "Leg", "Composition", "compose",
           "play_length"]


class ScheduleEntry(NamedTuple):
    """One frame of the edited sequence: frame ``frame`` of ``sequence``, inside texton ``node``,
    or with ``blend = ((from, to), i)`` the ``i``-th in-between frame of that edge.

    A named tuple rather than a dataclass: an edit has thousands of them and a tuple is
    several times cheaper to make.
    """

    node: int
    sequence: str
    frame: int
    blend: tuple | None = None

    @property
    def key(self):
        """The mesh to show, as ``MeshSource.frame_mesh`` takes it: ``(sequence, frame)``, or
        ``(sequence, frame, blend)`` for an in-between frame."""
        return (self.sequence, self.frame) if self.blend is None else (self.sequence, self.frame, self.blend)

    def to_json(self):
        """This frame as ``tvmedit path --json`` lists it; ``blend`` only for an in-between frame."""
        data = {"node": self.node, "sequence": self.sequence, "frame": self.frame}
        if self.blend is not None:
            data["blend"] = [list(self.blend[0]), self.blend[1]]
        return data


@dataclass(frozen=True)
class Transition:
    """An edge taken: the texton ``target`` starts at schedule position ``index``, after
    ``blend`` in-between frames (positions ``index - blend`` to ``index - 1``)."""

    index: int
    source: int
    target: int
    weight: float
    exit_frame: int
    entry_frame: int
    blend: int = 0

    def to_json(self):
        """This transition as ``tvmedit path --json`` lists it."""
        return {"index": self.index, "from": self.source, "to": self.target, "weight": self.weight,
                "exit_frame": self.exit_frame, "entry_frame": self.entry_frame, "blend_frames": self.blend}


@dataclass(frozen=True)
class Leg:
    """Best path between two neighbouring key motions, eq. (16).

    ``frames`` counts the schedule from the first frame of key motion ``source`` up to the
    first frame of key motion ``target``: the source's own play and the textons between.
    ``loops`` are the extra cycles each motion of the path but the last plays (all 0 unless a
    length was asked). A leg asked to last a time (:mod:`tvmedit.engine.graph.timing`) has ``asked``, in
    seconds, and ``goal``, the frames it aimed at; a hold is a leg whose path is its source.
    """

    source: int
    target: int
    path: tuple
    cost: float
    edges: int
    frames: int
    loops: tuple = ()
    asked: float | None = None
    goal: int | None = None

    def to_json(self):
        """This leg as ``tvmedit path --json`` lists it; loops and times only where a time was asked."""
        record = {"from": self.source, "to": self.target, "path": list(self.path), "cost": self.cost,
                  "edges": self.edges, "frames": self.frames}
        if self.asked is not None:
            record.update(loops=list(self.loops), asked_s=self.asked, goal_frames=self.goal)
        return record


@dataclass
class Composition:
    """A composed edit: its legs, its frame schedule and the transitions in it.

    With ``loops=None`` the schedule holds one cycle of the last key motion and
    :meth:`frames` repeats that cycle forever.
    """

    keys: list
    legs: list
    schedule: list
    transitions: list
    loops: int | None = 1
    cycle: int = field(default=0, repr=False)  # frames in one cycle of the last key motion
    steady: list = field(default=None, repr=False)  # with loops=None: the cycle repeated after it
    library: object = field(default=None, repr=False)  # set by Library.edit: where frames come from
    starts: list = field(default_factory=list)  # schedule index at which each key motion begins
    fps: float | None = None  # set by Library.edit: frames a second, for lengths in seconds

    def frames(self):
        """Iterate the schedule; without end when ``loops`` is None."""
        yield from self.schedule
        if self.loops is None:
            yield from itertools.cycle(self.steady or self.schedule[len(self.schedule) - self.cycle:])

    def legs_json(self):
        """Each leg's JSON, with ``asked_s`` (null where no time was asked) and ``achieved_s``
        when the frame rate is known."""
        legs = [leg.to_json() for leg in self.legs]
        if self.fps:
            for leg, record in zip(self.legs, legs):
                record.update(asked_s=leg.asked, achieved_s=leg.frames / self.fps)
        return legs

    def to_json(self):
        """The JSON of ``tvmedit path --json``."""
        return {"keys": list(self.keys), "loops": self.loops, "fps": self.fps, "key_starts": list(self.starts),
                "legs": self.legs_json(),
                "schedule": [entry.to_json() for entry in self.schedule],
                "transitions": [t.to_json() for t in self.transitions]}


def play_length(start, end, entry, exit, once=False):
    """Frames a texton ``start..end`` shows when entered at ``entry`` and left at ``exit``.

    The smallest count >= L = end - start + 1 whose last frame is ``exit``, playing
    cyclically from ``entry``: n(e, x) = L + ((x - e + 1) mod L). A one-shot (``once``)
    is left on its first arrival at ``exit``: n = ((x - e) mod L) + 1.

    >>> play_length(10, 15, 14, 13)  # 14 15 10 11 12 13
    6
    >>> play_length(10, 15, 14, 14)  # 14 15 10 11 12 13 14
    7
    >>> play_length(10, 15, 14, 12)  # 14 15 10 11 12 13 14 15 10 11 12
    11
    >>> play_length(10, 15, 10, 14, once=True)  # 10 11 12 13 14
    5
    """
    length = end - start + 1
    if once:
        return (exit - entry) % length + 1
    return length + (exit - entry + 1) % length


def _cycle(start, end, entry, count):
    """The first ``count`` frames of the texton played cyclically from ``entry``."""
    once = list(range(entry, end + 1)) + list(range(start, entry))
    return (once * (count // len(once) + 1))[:count]


# tuple.__new__ straight from C: a long edit makes thousands of entries, and this skips the
# Python-level constructor of the named tuple.
_new_entry = partial(tuple.__new__, ScheduleEntry)


def _entries(node, sequence, frames):
    """:class:`ScheduleEntry` of each texton frame in ``frames`` of ``node`` (none in-between)."""
    return list(map(_new_entry, zip(repeat(node), repeat(sequence), frames, repeat(None))))


def blend_entries(graph, u, v):
    """The in-between frames the library holds for edge ``u -> v`` (none without a run)."""
    from ..inbetween.blend import side

    data = graph.edges[u, v]
    count = data.get("blend", 0)
    ends = ((u, graph.nodes[u]["sequence"], data["exit_frame"]), (v, graph.nodes[v]["sequence"], data["entry_frame"]))
    return [ScheduleEntry(*ends[side(i, count)], ((u, v), i)) for i in range(count)]


def texton_span(graph, node):
    """``(sequence, start, end)`` of ``node``'s texton."""
    data = graph.nodes[node]
    return data["sequence"], data["start"], data["end"]


def plays_once(graph, node):
    """Whether ``node`` is a one-shot motion, played once rather than looped."""
    return graph.nodes[node].get("kind") == "once"


def _check_frame(graph, node, frame, edge, role):
    """Refuse an ``edge`` whose ``role`` ("exit" or "entry") frame lies outside ``node``'s
    texton: a library out of step with its graph, to be rebuilt."""
    _, start, end = texton_span(graph, node)
    if not start <= frame <= end:
        raise LibraryError(f"Edge {edge[0]} -> {edge[1]} of the motion graph has {role} frame "
                           f"{frame} outside texton {motion_label(graph, node)} (frames {start}-{end}); "
                           f"rebuild the library.")


def checked_edge(graph, u, v, weight):
    """``(weight, exit frame, entry frame)`` of edge ``u -> v``, its frames checked against the textons."""
    data = graph.edges[u, v]
    _check_frame(graph, u, data["exit_frame"], (u, v), "exit")
    _check_frame(graph, v, data["entry_frame"], (u, v), "entry")
    return float(data[weight]), data["exit_frame"], data["entry_frame"]


def _check_loops(loops):
    """Loops are a whole number of cycles, bounded: the schedule holds every frame."""
    if loops is None:
        return None
    return whole("loops", loops, at_least=1, at_most=MAX_LOOPS,
                 hint=" (None plays the last key motion for ever)")


def compose(graph, keys, forbidden=(), loops=1, weight="weight", index=None, timing=None):
    """Compose an edit through the key motions, section 8.

    Parameters
    ----------
    graph : networkx.DiGraph, the pruned motion graph; nodes carry ``sequence``, ``start``,
        ``end``, edges ``weight``, ``exit_frame`` and ``entry_frame``
    keys : sequence of node ids or names, two or more key motions in order
    forbidden : iterable of node ids or names, motions no path may visit (section 8)
    loops : int or None, full cycles of the last key motion (None: forever, :meth:`Composition.frames`)
    weight : str, edge attribute of the transition cost, eq. (12)
    index : SearchIndex, optional, a prebuilt index of ``graph``
    timing : tvmedit.engine.graph.timing.Timing, optional
        How long each leg should last (:meth:`tvmedit.engine.graph.timing.Timing.request`); a leg
        with a time is planned by :func:`tvmedit.engine.graph.timing.plan_leg`, and a leg from a
        motion to itself with a time is a hold.

    Returns
    -------
    Composition

    Raises
    ------
    NoPath, UnknownMotion, DurationError (a missed time with ``timing.strict``)

    Examples
    --------
    Two textons of three frames; the edge leaves motion 0 at frame 11 and enters motion 1 at 21:

    >>> import networkx as nx
    >>> g = nx.DiGraph()
    >>> g.add_node(0, name="walk", sequence="a", start=10, end=12)
    >>> g.add_node(1, name="run", sequence="b", start=20, end=22)
    >>> g.add_edge(0, 1, weight=0.5, exit_frame=11, entry_frame=21)
    >>> edit = compose(g, ["walk", "run"])
    >>> [(e.node, e.frame) for e in edit.schedule]
    [(0, 10), (0, 11), (0, 12), (0, 10), (0, 11), (1, 21), (1, 22), (1, 20)]
    >>> edit.legs[0].to_json()
    {'from': 0, 'to': 1, 'path': [0, 1], 'cost': 0.5, 'edges': 1, 'frames': 5}
    """
    loops = _check_loops(loops)
    keys = [node_by_key(graph, key) for key in keys]
    if len(keys) < 2:
        raise TvmError(f"An edit needs at least two key motions, where it starts and where it goes; "
                       f"got {len(keys)}: add the motion to go to.")
    forbidden = {node_by_key(graph, key) for key in forbidden}
    index = SearchIndex.of(graph, weight) if index is None else index

    schedule, transitions, legs, starts = [], [], [], [0]
    sequence, start, end = texton_span(graph, keys[0])
    entry, clock = start, 0.0
    for i, (source, target) in enumerate(zip(keys, keys[1:])):
        began = len(schedule)
        planned, goal = _leg_goal(timing, i, clock, began, source == target)
        path, extra = _route(graph, source, entry, target, goal, weight, forbidden, index)
        if len(path) == 1 and goal:  # a hold: the motion plays on, and the next leg starts where it is
            schedule += _entries(source, sequence, _cycle(start, end, entry, goal))
            entry = start + (entry - start + goal) % (end - start + 1)
        cost, (sequence, start, end), entry = _play_path(graph, path, extra, (sequence, start, end), entry,
                                                         weight, schedule, transitions)
        frames = len(schedule) - began
        legs.append(Leg(source, target, tuple(path), cost, len(path) - 1, frames, tuple(extra),
                        None if goal is None else timing.durations[i], goal))
        if goal is not None:
            timing.check(graph, i + 1, source, target, frames, goal)
        clock = len(schedule) if planned is None else planned
        starts.append(len(schedule))
    schedule, steady, length = _play_last(graph, keys[-1], (sequence, start, end), entry, loops, schedule)
    return Composition(keys, legs, schedule, transitions, loops, cycle=length, starts=starts, steady=steady)


def _leg_goal(timing, i, clock, began, hold):
    """``(planned, goal)`` of leg ``i``: the schedule index the timing plans its end at, and the
    frames it should last from ``began``; both None where no time is asked. A ``hold`` (a leg
    from a motion to itself) lasts what was asked, late or not."""
    planned = timing.planned(i, clock) if timing else None
    goal = None if planned is None else max(0, math.floor(planned + 0.5) - began)
    if goal is not None and hold:
        goal = math.floor(timing.durations[i] * timing.fps + 0.5)
    return planned, goal


def _play_last(graph, key, texton, entry, loops, schedule):
    """``(schedule, steady, cycle)``: ``schedule`` followed by ``loops`` cycles of the last key
    motion ``key`` (its ``texton`` entered at ``entry``), every loop closed; ``steady`` is the
    cycle repeated for ever with ``loops=None`` (else None), ``cycle`` its length in frames."""
    sequence, start, end = texton
    length = end - start + 1
    # Played for ever (loops=None), the cycle after the first is the one repeated: its loop is
    # closed as the playhead closes it, which the first may not be when entered in its window.
    more = length if loops is None else 0
    schedule += _entries(key, sequence, _cycle(start, end, entry, length * (loops or 1) + more))
    schedule = _close_loops(graph, schedule)
    steady = schedule[len(schedule) - more:] if more else None
    schedule = schedule[:len(schedule) - more]
    return schedule, steady, length


def _play_path(graph, path, extra, texton, entry, weight, schedule, transitions):
    """Append the frames of ``path`` (each motion but the last with ``extra`` cycles) to
    ``schedule`` and its transitions to ``transitions``, from ``texton`` entered at ``entry``.
    Returns the path's largest cost, the last motion's texton and its entry frame."""
    sequence, start, end = texton
    cost = 0.0
    for (u, v), k in zip(zip(path, path[1:]), extra):
        w, exit_frame, entry_frame = checked_edge(graph, u, v, weight)
        cost = max(cost, w)
        count = play_length(start, end, entry, exit_frame, plays_once(graph, u)) + k * (end - start + 1)
        schedule += _entries(u, sequence, _cycle(start, end, entry, count))
        blend = blend_entries(graph, u, v)
        schedule += blend
        transitions.append(Transition(len(schedule), u, v, w, exit_frame, entry_frame, len(blend)))
        sequence, start, end = texton_span(graph, v)
        entry = entry_frame
    return cost, (sequence, start, end), entry


def _close_loops(graph, schedule):
    """``schedule`` with the frames next to every wrap of a cycle replaced by its texton's
    loop-closing frames (:mod:`tvmedit.engine.inbetween.loops`; the graph's node attributes ``wrap`` and
    ``wrap_at`` say how many and where). A visit is a run of entries of one node with no
    in-between frame; the last one is taken to go on, as the player rests in the last key
    motion (and an exported edit may be looped). The length is unchanged."""
    if not any(count for _, count in graph.nodes(data="wrap")):
        return schedule
    closed, i = list(schedule), 0
    while i < len(closed):
        node, j = closed[i].node, i
        while j < len(closed) and closed[j].node == node and closed[j].blend is None:
            j += 1
        count, at = graph.nodes[node].get("wrap", 0), graph.nodes[node].get("wrap_at", "end")
        if count and j > i:
            _, start, end = texton_span(graph, node)
            marks = closing([e.frame for e in closed[i:j]], start, end, count, at, rests=j == len(closed))
            for k, mark in enumerate(marks):
                if mark is not None:
                    closed[i + k] = ScheduleEntry(node, closed[i + k].sequence, closed[i + k].frame,
                                                  ((node, node), mark))
        i = max(j, i + 1)
    return closed


def _route(graph, source, entry, target, goal, weight, forbidden, index):
    """Path of a leg and the extra loops of each motion on it but the last.

    With no ``goal`` (frames), the best path of eq. (15)-(16) played as early as section 8
    allows; with one, the plan of :func:`tvmedit.engine.graph.timing.plan_leg` (a leg to the same motion
    is a hold, played by :func:`compose`).
    """
    if goal is None or source == target:
        path = best_path(graph, source, target, weight, forbidden, index=index)
        return path, (0,) * (len(path) - 1)
    from .timing import plan_leg

    plan = plan_leg(graph, source, entry, target, goal, forbidden, weight)
    return list(plan.path), plan.loops
