"""Legs of a given length: the path and loop counts that make a leg last the frames asked.

The paper ends with "the length of edited sequence is out of control": a leg lasts as long as
its best path and the loop-then-transition rule of section 8 make it. Here a leg, from the
first frame of one key motion to the first frame of the next, is asked to last ``D`` frames.

A schedule of a leg from key motion S (entered at ``e_S``) to T is a walk S = v_0 -> ... ->
v_m = T through the pruned graph, T only at its end and no forbidden motion on it, with a loop
count k_i >= 0 for each visit v_i (i < m; 0 for a one-shot). Visit i shows the play length of
:func:`tvmedit.engine.graph.compose.play_length` plus k_i whole cycles of its L_i frames, so
every frame of a texton is shown before it is left on the exit frame of its edge, as section 8
asks. The leg lasts N = the sum of the visits' frames. The planner returns the least schedule by:

1. miss = max(0, |N - D| - 1): within one frame of ``D`` when any schedule can be;
2. the largest transition cost on the walk, eq. (15);
3. the number of transitions, eq. (16);
4. |N - D|, then N (the exact length first, the shorter before the longer);
5. the spread of the loops: the fewest cycles any one texton plays extra.

The dynamic programme: a state is (motion v, entry frame e, frames t elapsed when v begins),
since what a visit shows depends on nothing else. For a cost limit C (edges of weight <= C
only) the reachable t = 0..H of each state are one Python integer used as a bit set, filled in
layers of j transitions: a cyclic state's set is closed under adding L_v (by doubling shifts),
and each edge v -> w shifts it by the play length into (w, entry) of layer j + 1. A bit already
set for the state in an earlier layer is dropped, since every continuation from it was open
with fewer transitions; so each (state, t) is expanded once and T never.

* Fewest transitions at C: the first layer whose bits at T fall in the accepted window.
* Least cost: feasibility only grows with C, so the least feasible C is searched among the
  edge weights from the minimax cost of the best path (eq. (15), a lower bound) upwards, by
  doubling, then bisection.
* The window: {D-1, D, D+1} when the unrestricted programme reaches it, else the lengths at the
  smallest miss m reached. No length beyond H = D + 1 + m is nearer, so H starts at D + 1 +
  (longest texton) and grows to D + 1 + m, or doubles while T is not reached at all.

The walk is read back from the layers, latest arrivals first. Loop counts whose cycles add to
the same frames give the same length, so criterion 5 bisects the largest count over a
subset-sum bit set and deals the loops out in proportion to the textons' lengths.
"""

import bisect
import math
import warnings
import weakref
from dataclasses import dataclass

import numpy as np

from ..errors import DurationError, DurationWarning, ParameterError, TvmError
from ..checks import number
from .search import SearchIndex, best_path, motion_label, path_cost

__all__ = ["LegPlan", "Timing", "TimingIndex", "plan_leg", "miss", "MAX_SECONDS"]

#: The longest leg, in frames, a caller may ask for or the planner searches (5.5 hours at 10
#: fps): the programme keeps a bit set of this many bits for every state it reaches.
MAX_FRAMES = 200_000
#: The longest leg, hold or time a caller may ask for, in seconds (an hour).
MAX_SECONDS = 3600.0

_INDEXES = weakref.WeakKeyDictionary()


def miss(frames, asked):
    """Frames by which a leg of ``frames`` misses ``asked``, one frame either way being a hit.

    >>> miss(49, 50), miss(51, 50), miss(47, 50)
    (0, 0, 2)
    """
    return max(0, abs(frames - asked) - 1)


@dataclass(frozen=True)
class LegPlan:
    """One planned leg.

    Attributes
    ----------
    path : tuple of node ids
        The walk, source first, target last.
    entries : tuple of int
        The entry frame of each visit of the walk, the target's included.
    loops : tuple of int
        Extra whole cycles each visit but the target's plays.
    frames : int
        Frames from the source's first frame to the target's (N).
    cost : float
        Largest transition weight on the walk, eq. (15); 0 for a walk of one motion.
    """

    path: tuple
    entries: tuple
    loops: tuple
    frames: int
    cost: float

    @property
    def edges(self):
        """Transitions on the path."""
        return len(self.path) - 1


class TimingIndex:
    """What the planner reads of a motion graph: textons, and edges sorted by weight.

    Edges are read from the graph per node and only as far as a search's cost limit needs,
    lightest first, so planning in a big graph touches few of them. Get one with :meth:`of`,
    cached on the graph object (like :class:`tvmedit.engine.graph.search.SearchIndex`, which it reads).
    """

    def __init__(self, graph, weight="weight"):
        self.graph = graph
        self.search = SearchIndex.of(graph, weight)
        self.texton = {node: (int(data["start"]), int(data["end"]), data.get("kind") == "once")
                       for node, data in graph.nodes(data=True)}
        self.longest = max((end - start + 1 for start, end, _ in self.texton.values()), default=1)
        finite = self.search.weights[np.isfinite(self.search.weights)]
        #: The distinct edge weights, ascending: the cost limits worth trying.
        self.weights = np.unique(finite).tolist()
        self._out = {}

    @classmethod
    def of(cls, graph, weight="weight"):
        """The index of ``graph``, made once and kept while its nodes and edges count the same."""
        key = (graph.number_of_nodes(), graph.number_of_edges(), weight)
        cached = _INDEXES.get(graph)
        if cached is None or cached[0] != key:
            cached = (key, cls(graph, weight))
            _INDEXES[graph] = cached
        return cached[1]

    def out(self, node, limit=math.inf):
        """``[(weight, target, exit_frame, entry_frame), ...]`` out of ``node``, lightest first.

        Holds at least every edge of weight <= ``limit`` (read on first need); callers stop
        at the first heavier one.
        """
        known = self._out.get(node)
        if known is None:
            row = self.search.weights[self.search.row[node]]
            order = np.argsort(row, kind="stable")
            order = order[:np.count_nonzero(np.isfinite(row))]
            known = self._out[node] = (row[order], order, [])
        weights, order, edges = known
        if len(edges) == len(order) or (edges and edges[-1][0] > limit):
            return edges
        need = len(order) if limit == math.inf else int(np.searchsorted(weights, limit, side="right"))
        if need > len(edges):
            adjacent, nodes = self.graph[node], self.search.nodes
            for k in range(len(edges), need):
                data = adjacent[nodes[order[k]]]
                edges.append((float(weights[k]), nodes[order[k]], int(data["exit_frame"]),
                              int(data["entry_frame"])))
        return edges

    def play(self, node, entry, exit):
        """Frames a visit of ``node`` entered at ``entry`` shows before leaving at ``exit``, no loops."""
        start, end, once = self.texton[node]
        length = end - start + 1
        if once:
            return (exit - entry) % length + 1
        return length + (exit - entry + 1) % length

    def leave(self, node, entry, exit, target):
        """:meth:`play` and then the in-between frames the library holds for the edge to
        ``target`` (:mod:`tvmedit.engine.inbetween.blend`): the frames from entering ``node`` to entering ``target``."""
        return self.play(node, entry, exit) + self.graph[node][target].get("blend", 0)

    def cycle(self, node):
        """Frames of one extra loop of ``node``; 0 for a one-shot, which cannot loop."""
        start, end, once = self.texton[node]
        return 0 if once else end - start + 1


def _close(bits, length, horizon):
    """Bit set ``bits`` closed under adding ``length`` (any number of times), up to ``horizon``."""
    step = length
    while step and step <= horizon:
        bits |= bits << step
        step <<= 1
    return bits


class _Layers:
    """The layered programme of one leg at one cost limit (see the module docstring).

    ``arrivals[j]`` and ``ready[j]`` map a state (node, entry) to the bit set of the times it
    begins, and of the times it may be left (after its loops), with exactly j transitions;
    ``hits[j]`` maps the target's entry frames to the times it begins.
    """

    def __init__(self, index, source, entry, target, limit, horizon, blocked, window):
        self.index, self.target, self.limit, self.blocked = index, target, limit, blocked
        mask = (1 << (horizon + 1)) - 1
        seen_arrival, seen_ready = {}, {}
        self.arrivals, self.ready, self.hits = [], [], [{}]
        self.hit = None
        frontier = {(source, entry): 1}
        while frontier:
            arrivals, ready = {}, {}
            for state, bits in frontier.items():
                new = bits & ~seen_arrival.get(state, 0)
                if not new:
                    continue
                seen_arrival[state] = seen_arrival.get(state, 0) | new
                closed = _close(new, index.cycle(state[0]), horizon) & mask & ~seen_ready.get(state, 0)
                arrivals[state] = new
                if closed:
                    seen_ready[state] = seen_ready.get(state, 0) | closed
                    ready[state] = closed
            self.arrivals.append(arrivals)
            self.ready.append(ready)
            frontier, hits = self._step(ready, mask)
            self.hits.append(hits)
            if window is not None and any(bits & window for bits in hits.values()):
                self.hit = len(self.hits) - 1
                return

    def _step(self, ready, mask):
        """``(frontier, hits)`` of the next layer: every edge under the limit out of the states
        ``ready`` to leave, their time bit sets shifted by the play length."""
        index, target, limit, blocked = self.index, self.target, self.limit, self.blocked
        frontier, hits = {}, {}
        for (node, entry), bits in ready.items():
            for weight, v, exit, next_entry in index.out(node, limit):
                if weight > limit:
                    break
                if v in blocked:
                    continue
                shifted = (bits << index.leave(node, entry, exit, v)) & mask
                if not shifted:
                    continue
                into = hits if v == target else frontier
                key = next_entry if v == target else (v, next_entry)
                into[key] = into.get(key, 0) | shifted
        return frontier, hits

    def reached(self):
        """Bit set of every time the target can begin, over all layers."""
        total = 0
        for hits in self.hits:
            for bits in hits.values():
                total |= bits
        return total

    def walk(self, layer, entry, frames):
        """Read back a schedule that begins the target at ``frames`` via ``entry`` in ``layer``.

        Returns ``[(node, entry, begins, loops), ...]`` from the source to the target.
        """
        index = self.index
        visits = [(self.target, entry, frames, 0)]
        node, time = self.target, frames
        for j in range(layer - 1, -1, -1):
            found = None
            for (u, e), bits in sorted(self.ready[j].items()):
                for weight, v, exit, next_entry in index.out(u, self.limit):
                    if weight > self.limit:
                        break
                    if v != node or next_entry != entry:
                        continue
                    left = time - index.leave(u, e, exit, v)
                    if left >= 0 and bits >> left & 1:
                        found = (u, e, left)
                        break
                if found:
                    break
            u, e, left = found
            arrived = self.arrivals[j][u, e]
            length = index.cycle(u)
            begins = left
            while not arrived >> begins & 1:
                begins -= length
            visits.append((u, e, begins, (left - begins) // length if length else 0))
            node, entry, time = u, e, begins
        return visits[::-1]


def _mask(times):
    """Bit set of ``times``."""
    bits = 0
    for t in times:
        if t >= 0:
            bits |= 1 << t
    return bits


def _nearest_miss(bits, asked):
    """Smallest :func:`miss` of the times in ``bits``; None when empty."""
    if not bits:
        return None
    below = bits & ((1 << asked) - 1)
    above = bits >> asked
    misses = []
    if below:
        misses.append(miss(below.bit_length() - 1, asked))
    if above:
        misses.append(miss((above & -above).bit_length() - 1 + asked, asked))
    return min(misses)


def _spread(visits, index):
    """Loop counts with the same total frames and the smallest largest count (criterion 5)."""
    lengths = [index.cycle(node) for node, _, _, _ in visits[:-1]]
    extra = sum(k * length for k, length, in zip((v[3] for v in visits), lengths))
    if not extra:
        return [0] * len(lengths)
    cyclic = sum(lengths)
    low, high = -(-extra // cyclic), max(v[3] for v in visits)

    def sums(cap):
        table = [1]
        for length in lengths:
            bits = table[-1]
            table.append(_close_capped(bits, length, cap, extra))
        return table

    while low < high:
        middle = (low + high) // 2
        if sums(middle)[-1] >> extra & 1:
            high = middle
        else:
            low = middle + 1
    table = sums(low)
    loops, left = [0] * len(lengths), extra
    for i in range(len(lengths) - 1, -1, -1):
        length = lengths[i]
        if not length:
            continue
        share = left / max(1, sum(lengths[:i + 1]))  # loops each texton left would play if even
        choices = [k for k in range(low + 1) if k * length <= left and table[i] >> (left - k * length) & 1]
        k = min(choices, key=lambda c: (abs(c - share), c))
        loops[i], left = k, left - k * length
    return loops


def _close_capped(bits, length, cap, top):
    """``bits`` with up to ``cap`` cycles of ``length`` frames added, kept to times 0..``top``.

    >>> bin(_close_capped(0b1, 2, 2, 5))
    '0b10101'
    """
    total = bits
    if length:
        for k in range(1, cap + 1):
            if k * length > top:
                break
            total |= bits << (k * length)
    return total & ((1 << (top + 1)) - 1)


def plan_leg(graph, source, entry, target, asked, forbidden=(), weight="weight", index=None):
    """The best schedule of a leg asked to last ``asked`` frames (criteria 1-5 of the module).

    Parameters
    ----------
    graph : networkx.DiGraph
        The pruned motion graph, as :func:`tvmedit.engine.graph.compose.compose` takes it.
    source, target : node ids
        The two key motions of the leg, different (a leg from a motion to itself is a hold,
        which :func:`tvmedit.engine.graph.compose.compose` plays without a search).
    entry : int
        The frame at which ``source`` is entered (its first frame for the first key motion).
    asked : int
        Frames the leg should last, from the source's first frame to the target's; >= 0.
    forbidden : iterable of node ids
        Motions the walk may not visit.
    weight : str
        Edge attribute of the transition cost, eq. (12).
    index : TimingIndex, optional

    Returns
    -------
    LegPlan

    Raises
    ------
    NoPath
        When the target cannot be reached at all (as :func:`tvmedit.engine.graph.search.best_path`).

    Examples
    --------
    A texton of 4 frames (10-13) with an edge from frame 13 into a 3-frame texton: the source
    plays 4 frames, then 4 more per loop, so 12 frames are asked and 12 are made:

    >>> import networkx as nx
    >>> g = nx.DiGraph()
    >>> g.add_node(0, name="walk", sequence="a", start=10, end=13)
    >>> g.add_node(1, name="run", sequence="b", start=20, end=22)
    >>> g.add_edge(0, 1, weight=0.5, exit_frame=13, entry_frame=20)
    >>> plan = plan_leg(g, 0, 10, 1, 12)
    >>> plan.path, plan.loops, plan.frames
    ((0, 1), (2,), 12)
    """
    if source == target:
        raise ValueError("plan_leg plans a leg between two different motions; a motion to itself is a hold")
    index = TimingIndex.of(graph, weight) if index is None else index
    forbidden = frozenset(forbidden)
    asked = max(0, int(asked))
    # Raises NoPath, with its advice, when nothing connects the two; its cost bounds eq. (15) below.
    least = path_cost(graph, best_path(graph, source, target, weight, forbidden,
                                       index=SearchIndex.of(graph, weight)), weight)

    def run(limit, horizon, times):
        return _Layers(index, source, entry, target, limit, horizon, forbidden,
                       None if times is None else _mask(times))

    horizon = asked + 1 + index.longest
    times = (asked - 1, asked, asked + 1)
    layers = run(least, horizon, times)
    if layers.hit is None:
        layers = _cheapest(run, index.weights, least, horizon, times, tried_least=True)
    if layers is None:
        times, horizon = _nearest(run, asked, horizon)
        layers = _cheapest(run, index.weights, least, horizon, times, tried_least=False)
    hits = layers.hits[layers.hit]
    frames, entry_t = min(((t, e) for e, bits in hits.items() for t in times if t >= 0 and bits >> t & 1),
                          key=lambda pair: (abs(pair[0] - asked), pair))
    visits = layers.walk(layers.hit, entry_t, frames)
    path = tuple(v[0] for v in visits)
    return LegPlan(path, tuple(v[1] for v in visits), tuple(_spread(visits, index)), frames,
                   path_cost(graph, list(path), weight))


def _nearest(run, asked, horizon):
    """The lengths at the smallest miss any schedule makes (none makes 0), and a horizon holding them."""
    while True:
        found = _nearest_miss(run(math.inf, horizon, None).reached(), asked)
        if found is not None and found <= horizon - asked - 1:
            return (asked - 1 - found, asked + 1 + found), horizon
        if found is not None:
            horizon = asked + 1 + found
        elif horizon >= MAX_FRAMES:
            raise TvmError(f"no schedule of this leg lasts {MAX_FRAMES} frames or fewer; "
                           f"choose key motions that are closer in the motion graph.")
        else:
            horizon = min(2 * horizon, MAX_FRAMES)


def _cheapest(run, weights, least, horizon, times, tried_least):
    """Layers at the least cost limit whose schedules reach ``times``; None if no limit does.

    ``tried_least`` says that the limit ``least``, a lower bound, is known to fall short.
    Limits are tried up from it in doubling steps, then by bisection.
    """
    start = bisect.bisect_left(weights, least) - (0 if tried_least else 1)
    bad, good, tried = start, None, {}
    step = 1
    while good is None and bad < len(weights) - 1:
        probe = min(start + step, len(weights) - 1)
        tried[probe] = run(weights[probe], horizon, times)
        if tried[probe].hit is not None:
            good = probe
        else:
            bad, step = probe, step * 2
    if good is None:
        return None
    while good - bad > 1:
        middle = (good + bad) // 2
        tried[middle] = run(weights[middle], horizon, times)
        if tried[middle].hit is not None:
            good = middle
        else:
            bad = middle
    return tried[good]


@dataclass(frozen=True)
class Timing:
    """How long each leg of an edit is asked to last: seconds, or None for as short as section 8 plays it.

    Make one with :meth:`request`, which checks what the caller gives. ``compose`` asks
    :meth:`planned` for each leg the frame at which its target should begin, counted on the
    clock of the times asked (so a leg one frame short or long does not shift the ones after
    it), and hands each leg it played to :meth:`check`.
    """

    durations: tuple
    fps: float
    strict: bool = False
    told: tuple = ()  # per leg planned: (the caller's leg it belongs to, or None: a final hold; seconds asked)

    @classmethod
    def request(cls, graph, keys, fps, durations=None, at=None, holds=None, strict=False):
        """Check the caller's lengths and return ``(keys, timing)``, holds put in as repeated keys.

        Parameters
        ----------
        graph : networkx.DiGraph
        keys : list of node ids
            The key motions, resolved.
        fps : float
            Frames a second of the library.
        durations : sequence of (float or None), optional
            Seconds of each leg, len(keys) - 1 of them; None leaves a leg as short as it plays.
        at : sequence of float, optional
            Instead of ``durations``: the time each key motion begins, 0 first, never earlier
            than the one before.
        holds : dict of key -> float, optional
            Seconds that a key motion keeps looping once it begins, before the path to the next
            one (within that leg's asked time, if it has one); a key given twice in ``keys``
            with a duration between is the same.
        strict : bool
            A leg no schedule makes within a frame raises :class:`~tvmedit.engine.errors.DurationError`
            instead of a warning.

        Returns
        -------
        (list of node ids, Timing or None): None when nothing is asked.
        """
        from .motiongraph import node_by_key

        legs = len(keys) - 1
        if durations is not None and at is not None:
            raise ParameterError("give durations= or at=, not both: durations are the legs' lengths, "
                                 "at the times the key motions begin.")
        if at is not None:
            at = _seconds("at", at, len(keys))
            if at[0] != 0:
                raise ParameterError(f"at={at[0]:g} for the first key motion: it begins at 0, so at= starts with 0.")
            for i in range(1, len(at)):
                if at[i] < at[i - 1]:
                    raise ParameterError(f"at= goes back in time: key motion {i + 1} at {at[i]:g} s comes "
                                         f"before key motion {i} at {at[i - 1]:g} s; give the times in order.")
            durations = [b - a for a, b in zip(at, at[1:])]
        durations = [None] * legs if durations is None else _seconds("durations", durations, legs, free=True)
        fps = number("fps", fps, above=0)
        held = {node_by_key(graph, key): number(f"holds[{key!r}]", value, at_least=0, at_most=MAX_SECONDS)
                for key, value in (holds or {}).items()}
        for seconds in durations + list(held.values()):
            if seconds is not None and seconds * fps > MAX_FRAMES:
                raise ParameterError(f"{seconds:g} s is {seconds * fps:.0f} frames at {fps:g} fps; a leg or hold "
                                     f"may last at most {MAX_FRAMES} frames ({MAX_FRAMES / fps:g} s): split it.")
        for node in held:
            if node not in keys:
                raise ParameterError(f"holds names motion {motion_label(graph, node)}, which is not among the "
                                     f"key motions; hold one of them.")
        if not held and all(d is None for d in durations):
            return list(keys), None
        out_keys, out, told = [keys[0]], [], []
        for i, key in enumerate(keys):
            if key in held:
                out_keys.append(key)
                out.append(held[key])
                told.append((i + 1 if i < legs else None, held[key]))
            if i < legs:
                out_keys.append(keys[i + 1])
                given = durations[i]
                out.append(None if given is None else max(0.0, given - held.get(key, 0.0)))
                told.append((i + 1, given))
        return out_keys, cls(tuple(out), fps, bool(strict), tuple(told))

    def planned(self, leg, clock):
        """Frame (a float) at which leg ``leg``'s target should begin, from ``clock``, the one at
        which its source was to begin; None for a leg left free."""
        asked = self.durations[leg]
        return None if asked is None else clock + asked * self.fps

    def check(self, graph, leg, source, target, frames, goal):
        """Warn (or raise, when strict) where leg ``leg`` (from 1) misses its goal by over a frame."""
        asked = self.durations[leg - 1]
        if asked is None or miss(frames, goal) == 0:
            return
        number, given = self.told[leg - 1] if self.told else (leg, asked)
        what = f"leg {number}" if source != target else f"the hold of leg {number}" if number else "the final hold"
        lasts, on_time = (round(n / self.fps, 2) for n in (frames, goal))  # not 0.166895 s at 29.959 fps
        kept = "" if goal == round(asked * self.fps) else f" ({on_time:g} s to keep the next key motion on time)"
        kept += "" if source == target or asked == given else f" after its hold ({given:g} s in all)"
        message = (f"{what} ({motion_label(graph, source)} -> {motion_label(graph, target)}) was asked to "
                   f"last {asked:g} s{kept} and lasts {lasts:g} s ({frames} frames at {self.fps:g} fps), "
                   f"the nearest any schedule of the loop-then-transition rule makes")
        if self.strict:
            raise DurationError(f"{message}; ask for {lasts:g} s or choose other key motions.")
        warnings.warn(message + ".", DurationWarning, stacklevel=4)


def _seconds(name, values, count, free=False):
    """A list of ``count`` times in seconds, each in range (None where ``free`` allows)."""
    values = list(values)
    if len(values) != count:
        raise ParameterError(f"{name}= has {len(values)} value{'s' * (len(values) != 1)}; this edit needs {count}"
                             f" ({'one a leg' if name == 'durations' else 'one a key motion'}).")
    return [None if free and v is None else number(f"{name}[{i}]", v, at_least=0, at_most=MAX_SECONDS)
            for i, v in enumerate(values)]
