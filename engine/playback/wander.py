"""An endless walk over the motion graph: a character that keeps moving by itself.

Video textures (Schödl et al., SIGGRAPH 2000) and motion graphs (Kovar et al., SIGGRAPH 2002)
play a capture for ever by a random walk over its transitions. :class:`Wander` does the same
on the pruned, connected graph of section 6, played by the rules of section 8:

- **A visit** enters a motion's texton at an edge's entry frame and plays it cyclically until
  it leaves at the next edge's exit frame: at least one whole cycle (the play length of
  :func:`~tvmedit.engine.graph.compose.play_length`), plus extra cycles drawn around how many
  the capture itself shows (``cycles``), so a motion lasts about as long as it was performed.
  A one-shot motion plays once and moves on. Loops are closed and transitions blended exactly
  as in a composed edit.
- **The next motion** is drawn, not searched. A *goal* is drawn among the allowed motions,
  the ones that have played least so far the likeliest (weight ``exp(-3 t_m / t_mean)`` for
  ``t_m`` frames played), never the motion just left while another exists. Each transition
  ``u -> v`` leaving the current motion then gets the probability

      p(v) ~ exp(-W(u, v) / T) * exp(-2 (d(v, goal) - d(u, goal) + 1)) * r(v)

  with ``W`` the transition weight of eq. (12), ``T`` the temperature (``temperature`` times
  the median weight of the allowed transitions), ``d`` hops within the allowed motions, and
  ``r(v) = 1/4`` for a motion among the last few visited (1 otherwise). Cheap transitions
  are likelier, every step heads on average toward the goal, and no motion dominates.
- **No transition twice in a row**: of the transitions leaving a motion, the one taken the
  last time it was left is not taken again while another exists.
- **It never traps**: the allowed motions (``only`` less ``forbid``) must reach each other
  within themselves; otherwise :class:`~tvmedit.engine.errors.TvmError` names them.

The walk is lazy (:meth:`Wander.__iter__` yields frames for ever, holding no schedule) and a
seed makes it reproducible: the same seed, graph and options give the same frames.
"""

import math
from collections import deque

import networkx as nx
import numpy as np

from ..errors import TvmError
from ..graph.compose import (Composition, Leg, ScheduleEntry, Transition, blend_entries, checked_edge,
                             play_length, plays_once, texton_span)
from ..graph.motiongraph import node_by_key
from ..graph.search import motion_label
from ..inbetween.loops import closing

__all__ = ["Wander", "Walker", "Visit", "RECENT", "VISIT_S", "capture_cycles", "library_walk"]

#: Longest stay a visit draws its cycles around, seconds: an idle character changes motion
#: every few seconds, however long the capture held one.
VISIT_S = 6.0

#: Motions visited lately that a step avoids (a quarter of the odds), and goals are not drawn from.
RECENT = 3


class Visit:
    """One stay in a motion: ``entries`` (its texton frames, then the transition's in-between
    frames) and ``transition`` (the edge taken at its end, indexed from the visit's start)."""

    __slots__ = ("node", "entries", "transition")

    def __init__(self, node, entries, transition):
        self.node, self.entries, self.transition = node, entries, transition


class Wander:
    """A random walk over ``graph``'s motions, played frame by frame for ever.

    Parameters
    ----------
    graph : networkx.DiGraph
        The motion graph (nodes with ``name``, ``sequence``, ``start``, ``end``, ``kind``;
        edges with ``weight``, ``exit_frame``, ``entry_frame`` and optionally ``blend``).
    start : node id or name, optional
        Where the walk begins (default: drawn among the allowed motions).
    seed : int, optional
        Seed of the draws; the same seed gives the same walk.
    only, forbid : iterables of node ids or names
        The motions the walk may play: ``only`` (default all) less ``forbid``.
    temperature : float
        How much cheap transitions are preferred: ``T`` is this times the median weight of
        the allowed transitions (smaller: cheaper transitions more strongly preferred).
    cycles : dict of node id to float, optional
        Cycles of each motion the capture shows; a visit draws its cycles around it (default 2).

    Examples
    --------
    >>> import networkx as nx
    >>> g = nx.DiGraph()
    >>> for n, name in enumerate(["walk", "run", "hop"]):
    ...     g.add_node(n, name=name, sequence="a", start=10 * n, end=10 * n + 2)
    >>> for u, v in [(0, 1), (1, 2), (2, 0), (1, 0)]:
    ...     g.add_edge(u, v, weight=0.5, exit_frame=10 * u + 1, entry_frame=10 * v)
    >>> walk = Wander(g, start="walk", seed=3)
    >>> frames = [entry.frame for entry, _ in zip(walk, range(12))]
    >>> frames[:3]
    [0, 1, 2]
    >>> frames == [entry.frame for entry, _ in zip(Wander(g, start="walk", seed=3), range(12))]
    True
    """

    def __init__(self, graph, start=None, seed=None, only=None, forbid=(), temperature=1.0, cycles=None,
                 weight="weight"):
        self.graph = graph
        self.weight = weight
        allowed = set(graph.nodes) if only is None else {node_by_key(graph, key) for key in only}
        allowed -= {node_by_key(graph, key) for key in forbid}
        if not allowed:
            raise TvmError("A walk needs at least one motion; `only` and `forbid` leave none.")
        self.allowed = sorted(allowed)
        self._check_connected()
        if not (isinstance(temperature, (int, float)) and math.isfinite(temperature) and temperature > 0):
            raise TvmError(f"temperature must be a finite number above 0, got {temperature!r}.")
        weights = [float(d[weight]) for u, v, d in graph.edges(data=True)
                   if u in allowed and v in allowed and u != v]
        median = float(np.median(weights)) if weights else 1.0
        self.temperature = temperature * (median if median > 0 else 1.0)
        self.cycles = {node: float((cycles or {}).get(node, 2.0)) for node in self.allowed}
        self.seed = seed
        self.start = None if start is None else node_by_key(graph, start)
        if self.start is not None and self.start not in allowed:
            raise TvmError(f"The walk cannot start at {motion_label(graph, self.start)}: "
                           f"it is not among the motions it may play.")
        sub = graph.subgraph(self.allowed)
        self._hops = dict(nx.all_pairs_shortest_path_length(sub))

    def _check_connected(self):
        """Refuse a walk whose allowed motions cannot all reach each other within themselves."""
        if len(self.allowed) < 2:
            return
        sub = self.graph.subgraph(self.allowed)
        parts = list(nx.strongly_connected_components(sub))
        if len(parts) > 1:
            groups = "; ".join(f"({k}) " + ", ".join(motion_label(self.graph, n) for n in sorted(part))
                               for k, part in enumerate(sorted(parts, key=min), 1))
            raise TvmError(f"The motions the walk may play fall into groups that cannot reach each other "
                           f"without motions it may not play: {groups}. Allow the motions between them, "
                           f"or keep the walk to one group.")

    def walker(self):
        """A fresh :class:`Walker` of this walk: its draws from the start, by its seed."""
        return Walker(self)

    def visits(self):
        """The walk's visits, for ever: one :class:`Visit` per motion played."""
        graph = self.graph
        walker = self.walker()
        node = walker.first()
        entry = texton_span(graph, node)[1]
        while True:
            sequence, start, end = texton_span(graph, node)
            length = end - start + 1
            target = walker.next(node)
            if target is None:  # a single motion: it plays on for ever
                yield Visit(node, _texton_entries(graph, node, sequence, start, end, entry, length, True), None)
                continue
            w, exit_frame, entry_frame = checked_edge(graph, node, target, self.weight)
            once = plays_once(graph, node)
            extra = 0 if once else walker.extra_cycles(node)
            count = play_length(start, end, entry, exit_frame, once) + extra * length
            entries = _texton_entries(graph, node, sequence, start, end, entry, count, False)
            walker.played(node, count)
            blend = blend_entries(graph, node, target)
            transition = Transition(len(entries) + len(blend), node, target, w, exit_frame, entry_frame,
                                    len(blend))
            yield Visit(node, entries + blend, transition)
            walker.left(node, target)
            node, entry = target, entry_frame

    def __iter__(self):
        """Every frame of the walk, for ever, as :class:`~tvmedit.engine.graph.compose.ScheduleEntry`."""
        for visit in self.visits():
            yield from visit.entries

    def take(self, frames):
        """The first ``frames`` frames of the walk as a :class:`Composition` (one leg per
        transition), which export and render take like any edit."""
        schedule, transitions, legs, keys = [], [], [], []
        visits = self.visits()
        while len(schedule) < frames:
            visit = next(visits)
            if not keys:
                keys.append(visit.node)
            begun = len(schedule)
            schedule += visit.entries[:frames - begun]
            t = visit.transition
            if t is not None and len(schedule) >= begun + t.index:
                transitions.append(Transition(begun + t.index, t.source, t.target, t.weight, t.exit_frame,
                                              t.entry_frame, t.blend))
                legs.append(Leg(t.source, t.target, (t.source, t.target), t.weight, 1, t.index))
                keys.append(t.target)
        starts = [0] + [t.index for t in transitions]
        return Composition(keys, legs, schedule, transitions, loops=1, starts=starts)

class Walker:
    """The draws and the memory of one walk: where to go from a motion, and how many cycles to
    play there. :meth:`Wander.visits` plays its choices; the realtime playhead asks it when
    nothing is queued and tells it what was played (:class:`~tvmedit.engine.playback.Playhead`)."""

    def __init__(self, wander):
        self.wander = wander
        self.rng = np.random.default_rng(wander.seed)
        self.frames = dict.fromkeys(wander.allowed, 0)    # texton frames played per motion
        self.recent = deque(maxlen=min(RECENT, len(wander.allowed) - 1) or 1)
        self.left_by = {}                                 # motion -> where it was last left for
        self.goal = None

    def first(self):
        """The motion the walk starts at."""
        w = self.wander
        return w.start if w.start is not None else w.allowed[int(self.rng.integers(len(w.allowed)))]

    def next(self, node):
        """The motion to go to from ``node`` (None: ``node`` is the only one allowed)."""
        if self.goal is None or self.goal == node:
            self.goal = self._draw_goal(node)
        return self._draw_step(node)

    def played(self, node, frames):
        """``frames`` of ``node``'s texton were shown."""
        if node in self.frames:
            self.frames[node] += frames

    def left(self, node, target):
        """The walk left ``node`` for ``target``."""
        self.left_by[node] = target
        self.recent.append(node)

    def _draw_goal(self, node):
        w = self.wander
        others = [m for m in w.allowed if m != node]
        if not others:
            return node
        fresh = [m for m in others if m not in self.recent] or others
        mean = max(1.0, sum(self.frames.values()) / len(self.frames))
        odds = np.array([math.exp(-6.0 * self.frames[m] / mean) for m in fresh])
        return fresh[int(self.rng.choice(len(fresh), p=odds / odds.sum()))]

    def _draw_step(self, node):
        w, goal = self.wander, self.goal
        choices = sorted(v for v in w.graph.successors(node) if v in w._hops[node] and v != node and v in w.cycles)
        if len(choices) > 1 and self.left_by.get(node) in choices:
            choices.remove(self.left_by[node])
        if not choices:
            return None
        here = w._hops[node].get(goal, 0)
        odds = np.array([math.exp(-float(w.graph.edges[node, v][w.weight]) / w.temperature)
                         * math.exp(-2.0 * (w._hops[v].get(goal, here + 1) - here + 1))
                         * (0.25 if v in self.recent and v != goal else 1.0) for v in choices])
        if not odds.sum() > 0:
            odds = np.ones(len(choices))
        return choices[int(self.rng.choice(len(choices), p=odds / odds.sum()))]

    def extra_cycles(self, node):
        """Whole cycles a visit adds to the one it plays at least: drawn around the capture's
        count, scaled down for a motion that has played more than its even share so far and
        up for one that has played less (motions every path passes through stay in bounds)."""
        mean = sum(self.frames.values()) / len(self.frames)
        share = self.frames.get(node, 0) / mean if mean > 0 else 1.0
        shown = self.wander.cycles.get(node, 2.0) * min(2.0, max(0.0, 2.0 - share))
        return max(0, int(round(self.rng.normal(shown, max(0.5, shown / 3)))) - 1)


def _texton_entries(graph, node, sequence, start, end, entry, count, rests):
    """``count`` frames of ``node``'s texton played cyclically from ``entry``, its loop closed."""
    frames = [start + (entry - start + i) % (end - start + 1) for i in range(count)]
    wrap, at = graph.nodes[node].get("wrap", 0), graph.nodes[node].get("wrap_at", "end")
    marks = closing(frames, start, end, wrap, at, rests=rests) if wrap else [None] * count
    return [ScheduleEntry(node, sequence, frame, None if mark is None else ((node, node), mark))
            for frame, mark in zip(frames, marks)]


def capture_cycles(library, most_s=VISIT_S):
    """``{node id: cycles a visit draws around}``: as many as the motion's cluster shows in the
    capture, at most ``most_s`` seconds of them, and at least one."""
    cycles = {}
    for node in library.nodes:
        cluster = library.structure(node.sequence).clusters[node.cluster]
        start, end = (cluster.start, cluster.end) if hasattr(cluster, "start") else cluster
        length = node.end - node.start + 1
        most = most_s * library.sequence(node.sequence).fps / length
        cycles[node.id] = max(1.0, min((end - start + 1) / length, most))
    return cycles


def library_walk(library, seconds=None, seed=None, only=None, forbid=(), temperature=1.0, start=None):
    """A walk over ``library``'s motions: a :class:`Wander` (endless, lazy), or with ``seconds``
    the first that many seconds of it as an edit (a ``Composition`` with ``library`` and ``fps``
    set, which export and render take like :meth:`Library.edit`'s)."""
    walk = Wander(library.graph, start=start, seed=seed, only=only, forbid=forbid, temperature=temperature,
                  cycles=capture_cycles(library))
    if seconds is None:
        return walk
    fps = library.sequence(library.graph.nodes[walk.allowed[0]]["sequence"]).fps
    if not (isinstance(seconds, (int, float)) and math.isfinite(seconds) and seconds > 0):
        raise TvmError(f"A walk's length must be a finite number of seconds above 0, got {seconds!r}.")
    edit = walk.take(max(1, round(seconds * fps)))
    edit.library, edit.fps = library, fps
    return edit
