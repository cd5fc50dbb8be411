"""What plays next: the edited sequence one frame at a time, while key motions are queued.

:func:`tvmedit.engine.graph.compose.compose` plans a whole edit at once; the realtime player
cannot, because the user picks the next key motion while the current one plays. A
:class:`Playhead` keeps the same rules and applies them one frame at a time:

- what plays when nothing is queued: the current texton loops (section 5: every texton is a
  cycle), or a walker (:mod:`tvmedit.engine.playback.wander`) chooses the next motion;
- where a queued key motion is reached: by the best path of eq. (15)-(16) from the last
  queued key motion, searched when it is queued;
- when a texton is left: by the play length rule of section 8, n(e, x) = L + ((x - e + 1)
  mod L) (:func:`tvmedit.engine.graph.compose.play_length`), counted from the frames already
  shown, so that a texton queued late still shows all its frames before the transition;
- what lies between two textons: the in-between frames the library holds for the edge, and
  the loop-closing frames of a texton that wraps (:mod:`tvmedit.engine.inbetween.loops`).

The same rules give the same frames: starting at ``keys[0]`` and queuing ``keys[1:]`` plays
exactly ``compose(graph, keys)``. The playhead knows no clock or window; the window asks it
for the next frame at its own rate and only reads its state.
"""

import itertools
from collections import deque
from dataclasses import dataclass

from ..checks import whole
from ..graph.compose import (MAX_HOLD, ScheduleEntry, Transition, blend_entries, checked_edge, play_length,
                             plays_once, texton_span)
from ..graph.motiongraph import node_by_key
from ..graph.search import SearchIndex, best_path
from ..inbetween.loops import closed_at

__all__ = ["Playhead"]


@dataclass
class _Visit:
    """One stay in a texton: entered at ``entry``, left after ``exit`` (None: it rests there)."""

    node: int
    sequence: str
    start: int
    end: int
    entry: int
    exit: int | None = None
    once: bool = False            # a one-shot: left on its first arrival at the exit frame
    shown: int = 0
    leg: int | None = None        # serial of the queued key motion whose path planned it
    key: bool = False             # this visit is that key motion
    arrival: Transition | None = None  # the edge that leads in (index filled in when taken)
    hold: int = 0                 # frames it keeps looping beyond the rule (a held key motion)

    @property
    def length(self):
        """Frames in one cycle of the texton."""
        return self.end - self.start + 1

    def remaining(self):
        """Frames still to show before leaving: the play length rule, counted from now.

        The visit shows at least ``hold`` frames more than the rule asks (a hold, then the
        rule from where the hold ends, as :func:`compose` plays a hold).
        """
        if self.exit is None:
            return None
        least = max(self.hold + 1, self.shown, 1) if self.once else max(self.length + self.hold, self.shown)
        return least + (self.exit - self.entry - least + 1) % self.length - self.shown


class Playhead:
    """Frame-by-frame playback of an edit whose key motions arrive while it plays.

    The state machine behind the realtime player, free of any clock or window: each
    :meth:`advance` returns the next :class:`ScheduleEntry`. With nothing queued the current
    texton loops. :meth:`queue` plans the best path from the last queued key motion (or the
    current texton) to a new one; the current texton is finished first, by the same
    play length rule as :func:`compose`, so that queuing ``keys[1:]`` after starting at
    ``keys[0]`` plays exactly ``compose(graph, keys)``.

    >>> import networkx as nx
    >>> g = nx.DiGraph()
    >>> g.add_node(0, name="walk", sequence="a", start=10, end=12)
    >>> g.add_node(1, name="run", sequence="b", start=20, end=22)
    >>> g.add_edge(0, 1, weight=0.5, exit_frame=11, entry_frame=21)
    >>> head = Playhead(g, "walk")
    >>> head.advance().frame, head.queue("run"), head.frames_until_next_key()
    (10, [0, 1], 4)
    >>> [head.advance().frame for _ in range(6)], head.current_node, head.queue_list
    ([11, 12, 10, 11, 21, 22], 1, [])
    """

    def __init__(self, graph, start_node, forbidden=(), weight="weight", index=None, walker=None):
        self.graph = graph
        self.walker = walker        # a Walker (tvmedit.engine.playback.wander): with nothing queued, walk on
        self.weight = weight
        self.forbidden = {node_by_key(graph, key) for key in forbidden}
        self.index = SearchIndex.of(graph, weight) if index is None else index
        node = node_by_key(graph, start_node)
        sequence, start, end = texton_span(graph, node)
        self._visit = _Visit(node, sequence, start, end, start, once=plays_once(graph, node))
        self._plan = deque()
        self._blending = deque()    # in-between frames still to play before the current visit
        self._queue = []            # (key node, leg serial), in play order
        self._serial = itertools.count()
        self.played = 0             # frames returned so far: the schedule index of the next one
        self.transitions = []
        self._walk_hold = None      # (visit, its hold before the walk lengthened it)

    @property
    def current_node(self):
        """The texton now playing."""
        return self._visit.node

    @property
    def queue_list(self):
        """Key motions queued and not yet begun, in the order they will play."""
        return [node for node, _ in self._queue]

    @property
    def queue_holds(self):
        """Frames each queued key motion is held for once it begins (0: not held), as :attr:`queue_list`."""
        holds = {visit.leg: visit.hold for visit in self._plan if visit.key}
        return [holds.get(serial, 0) for _, serial in self._queue]

    @property
    def passing_through(self):
        """Whether the motion playing is only on the way to a queued key motion."""
        return bool(self._queue) and self._visit.leg is not None and not self._visit.key

    @property
    def wandering(self):
        """Whether the walk, not the queue, chooses what plays next."""
        return self.walker is not None and not self._queue

    def _last_visit(self):
        """The visit the plan ends in: where the next queued path starts."""
        return self._plan[-1] if self._plan else self._visit

    def queue(self, node, hold=0):
        """Plan the best path to key motion ``node`` after the ones already queued.

        Returns the path (node ids). Queuing the motion the plan already ends at is an
        empty leg: the path is ``[node]`` and nothing changes, unless ``hold`` is given.
        ``hold`` frames make the key motion loop that much longer once it begins, before the
        path to whatever is queued after it (as a hold in :func:`compose`); for the motion the
        plan already ends at, they count from now if it is playing. Raises
        :class:`~tvmedit.engine.errors.NoPath` (or :class:`~tvmedit.engine.errors.UnknownMotion`) and leaves
        the queue unchanged when the motion cannot be reached.
        """
        node = node_by_key(self.graph, node)
        hold = whole("hold", hold, at_least=0, at_most=MAX_HOLD)
        self._drop_walk_step()
        last = self._last_visit()
        path = best_path(self.graph, last.node, node, self.weight, self.forbidden, index=self.index)
        if len(path) == 1:
            if hold:
                last.hold = (last.shown if last is self._visit else 0) + hold
            return path
        edges = [checked_edge(self.graph, u, v, self.weight) for u, v in zip(path, path[1:])]
        serial = next(self._serial)
        previous = last
        for (u, v), (w, exit_frame, entry_frame) in zip(zip(path, path[1:]), edges):
            previous.exit = exit_frame
            sequence, start, end = texton_span(self.graph, v)
            previous = _Visit(v, sequence, start, end, entry_frame, once=plays_once(self.graph, v), leg=serial,
                              key=v == node, arrival=Transition(-1, u, v, w, exit_frame, entry_frame),
                              hold=hold if v == node else 0)
            self._plan.append(previous)
        self._queue.append((node, serial))
        return path

    def unqueue_last(self):
        """Drop the last queued key motion and its path; returns it, or None if none is queued.

        When the playhead is already inside that path, the texton now playing stays and loops.
        """
        if not self._queue:
            return None
        node, serial = self._queue.pop()
        while self._plan and self._plan[-1].leg == serial:
            self._plan.pop()
        self._last_visit().exit = None
        return node

    def holding(self):
        """Frames the motion playing is still held for (0 when it is not held)."""
        return max(0, self._visit.hold - self._visit.shown)

    def frames_until_next_key(self):
        """Frames :meth:`advance` returns before the next queued key motion's first one.

        None when nothing is queued; 0 when the next frame already belongs to it.
        """
        if not self._queue:
            return None
        total = len(self._blending) + self._visit.remaining()
        for visit in self._plan:
            total += self.graph.edges[visit.arrival.source, visit.arrival.target].get("blend", 0)
            if visit.key:
                return total
            total += play_length(visit.start, visit.end, visit.entry, visit.exit, visit.once)
        raise AssertionError("a queued key motion is missing from the plan")

    def advance(self):
        """The next frame of the edited sequence."""
        if self._blending:
            self.played += 1
            return self._blending.popleft()
        visit = self._visit
        if self.walker is not None and not self._plan and not self._queue and visit.exit is None:
            self._walk_step(visit)
        if visit.remaining() == 0:
            if self.walker is not None:
                self.walker.played(visit.node, visit.shown)
                if self._walk_hold is not None and self._walk_hold[0] is visit:
                    self.walker.left(visit.node, self._plan[0].node)
                    self._walk_hold = None
            visit = self._plan.popleft()
            a = visit.arrival
            blend = blend_entries(self.graph, a.source, a.target)
            self.transitions.append(Transition(self.played + len(blend), a.source, a.target, a.weight,
                                               a.exit_frame, a.entry_frame, len(blend)))
            if visit.key:
                self._queue.pop(0)
            self._visit = visit
            if blend:
                self._blending.extend(blend[1:])
                self.played += 1
                return blend[0]
        frame = visit.start + (visit.entry - visit.start + visit.shown) % visit.length
        closing = self._closing(visit, frame)
        visit.shown += 1
        self.played += 1
        if closing is not None:
            return closing
        return ScheduleEntry(visit.node, visit.sequence, frame)

    def peek(self):
        """The frame :meth:`advance` will return next, without playing it (the player draws the
        body on its way there, :mod:`tvmedit.engine.inbetween.instants`).

        Where a walker is to choose the next motion now, it chooses here (what :meth:`advance`
        would do first); a key motion queued before the next :meth:`advance` may still change it.
        """
        if self._blending:
            return self._blending[0]
        visit = self._visit
        if self.walker is not None and not self._plan and not self._queue and visit.exit is None:
            self._walk_step(visit)
        if visit.remaining() == 0:
            visit = self._plan[0]
            a = visit.arrival
            blend = blend_entries(self.graph, a.source, a.target)
            if blend:
                return blend[0]
            return ScheduleEntry(visit.node, visit.sequence, visit.entry)
        frame = visit.start + (visit.entry - visit.start + visit.shown) % visit.length
        closing = self._closing(visit, frame)
        return closing if closing is not None else ScheduleEntry(visit.node, visit.sequence, frame)

    def _walk_step(self, visit):
        """Plan the walk's next motion from ``visit``: its edge, and the extra cycles to play first."""
        target = self.walker.next(visit.node)
        if target is None:      # the only motion the walk may play: it rests here
            return
        w, exit_frame, entry_frame = checked_edge(self.graph, visit.node, target, self.weight)
        extra = 0 if visit.once else self.walker.extra_cycles(visit.node)
        self._walk_hold = (visit, visit.hold)
        visit.exit, visit.hold = exit_frame, max(visit.hold, visit.shown + extra * visit.length)
        sequence, start, end = texton_span(self.graph, target)
        self._plan.append(_Visit(target, sequence, start, end, entry_frame, once=plays_once(self.graph, target),
                                 arrival=Transition(-1, visit.node, target, w, exit_frame, entry_frame)))

    def _drop_walk_step(self):
        """Forget the walk's planned step (a key motion was queued): the queue goes first."""
        if self._walk_hold is None:
            return
        visit, hold = self._walk_hold
        self._plan.clear()
        visit.exit, visit.hold = None, hold
        self._walk_hold = None

    def _closing(self, visit, frame):
        """The loop-closing frame shown instead of texton frame ``frame`` (:mod:`tvmedit.engine.inbetween.loops`),
        or None: where the visit plays the texton's whole closing window and wraps next to it,
        as :func:`compose` marks it."""
        data = self.graph.nodes[visit.node]
        count = data.get("wrap", 0)
        if not count:
            return None
        index = closed_at(visit.shown, frame, visit.start, visit.end, count, data.get("wrap_at", "end"),
                          visit.remaining())
        if index is None:
            return None
        return ScheduleEntry(visit.node, visit.sequence, frame, ((visit.node, visit.node), index))
