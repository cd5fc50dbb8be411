"""Legs of a given length (tvmedit.engine.graph.timing) against brute-force enumeration of every schedule."""

import functools
import itertools
import math
import random

import networkx as nx
import pytest

from tvmedit.engine.graph.compose import compose
from tvmedit.engine.errors import DurationError, DurationWarning, NoPath
from tvmedit.engine.graph.timing import Timing, TimingIndex, miss, plan_leg


def random_graph(rng):
    """2-6 textons of 3-12 frames (a few one-shots), weights with ties, random exit/entry frames."""
    g = nx.DiGraph()
    n = rng.randint(2, 6)
    for node in range(n):
        start = rng.randrange(0, 40)
        once = rng.random() < 0.15
        g.add_node(node, name=f"m{node}", sequence=f"s{node}", start=start,
                   end=start + rng.randint(3, 12) - 1, kind="once" if once else "cycle")
    density = rng.choice((0.3, 0.5, 0.8))
    for u, v in itertools.permutations(range(n), 2):
        if rng.random() < density:
            a, b = g.nodes[u], g.nodes[v]
            length = a["end"] - a["start"] + 1
            exit = (rng.randint(a["end"] - max(1, math.ceil(0.25 * length)) + 1, a["end"])
                    if a["kind"] == "once" else rng.randint(a["start"], a["end"]))
            entry = b["start"] if b["kind"] == "once" else rng.randint(b["start"], b["end"])
            g.add_edge(u, v, weight=float(rng.choice((1, 2, 3))), exit_frame=exit, entry_frame=entry)
    return g


def brute_force(graph, source, entry, target, asked, forbidden=()):
    """(frames, cost, transitions) of the best schedule, by enumerating every schedule.

    Every schedule up to ``bound`` frames is listed (all walks, all loop counts); the bound
    grows until it is past the nearest length found, beyond which nothing is nearer.
    """
    index = TimingIndex(graph)
    bound = asked + 1
    while True:
        @functools.lru_cache(maxsize=None)
        def outcomes(node, entered, time):
            found = set()
            length = index.cycle(node)
            for weight, v, exit, next_entry in index.out(node):
                if v in forbidden:
                    continue
                for k in itertools.count():
                    ends = time + index.play(node, entered, exit) + k * length
                    if ends > bound:
                        break
                    if v == target:
                        found.add((ends, weight, 1))
                    else:
                        found |= {(n, max(c, weight), e + 1) for n, c, e in outcomes(v, next_entry, ends)}
                    if not length:
                        break
            return frozenset(found)

        schedules = outcomes(source, entry, 0)
        if schedules:
            best = min(schedules, key=lambda s: (miss(s[0], asked), s[1], s[2], abs(s[0] - asked), s[0]))
            if miss(best[0], asked) <= bound - asked - 1:
                return best
        bound *= 2


def replay(graph, plan, source, entry):
    """Frames and cost of the plan, played edge by edge; checks it is a legal schedule."""
    index = TimingIndex(graph)
    assert plan.path[0] == source and plan.entries[0] == entry
    assert plan.path[-1] not in plan.path[1:-1]
    frames, cost = 0, 0.0
    for i, (u, v) in enumerate(zip(plan.path, plan.path[1:])):
        data = graph.edges[u, v]
        assert data["entry_frame"] == plan.entries[i + 1]
        assert plan.loops[i] >= 0 and (index.cycle(u) or not plan.loops[i])
        frames += index.play(u, plan.entries[i], data["exit_frame"]) + plan.loops[i] * index.cycle(u)
        cost = max(cost, data["weight"])
    return frames, cost


def test_plans_agree_with_brute_force_on_600_random_graphs():
    rng = random.Random(14)
    checked = 0
    while checked < 600:
        g = random_graph(rng)
        source, target = rng.sample(sorted(g.nodes), 2)
        s = g.nodes[source]
        entry = s["start"] if s["kind"] == "once" else rng.randint(s["start"], s["end"])
        forbidden = {rng.choice(sorted(g.nodes))} - {source, target} if rng.random() < 0.2 else set()
        asked = rng.randint(0, 45)
        try:
            plan = plan_leg(g, source, entry, target, asked, forbidden=forbidden)
        except NoPath:
            assert not nx.has_path(g.subgraph(set(g) - forbidden), source, target)
            continue
        expected = brute_force(g, source, entry, target, asked, frozenset(forbidden))
        assert (plan.frames, plan.cost, plan.edges) == expected, (g.nodes(data=True), g.edges(data=True),
                                                                 source, entry, target, asked, forbidden)
        assert replay(g, plan, source, entry) == (plan.frames, plan.cost)
        assert not set(plan.path) & forbidden
        checked += 1


def test_a_long_leg_spreads_its_loops():
    # Two textons of 5 frames on the way: 40 extra frames are 4 loops each, not 8 and 0.
    g = nx.DiGraph()
    for node, start in ((0, 0), (1, 10), (2, 20)):
        g.add_node(node, name=f"m{node}", sequence="s", start=start, end=start + 4)
    g.add_edge(0, 1, weight=1.0, exit_frame=4, entry_frame=10)
    g.add_edge(1, 2, weight=1.0, exit_frame=14, entry_frame=20)
    plan = plan_leg(g, 0, 0, 2, 50)
    assert plan.frames == 50 and plan.path == (0, 1, 2) and plan.loops == (4, 4)


def test_a_leg_shorter_than_any_schedule_gets_the_shortest():
    g = nx.DiGraph()
    g.add_node(0, name="a", sequence="s", start=0, end=9)
    g.add_node(1, name="b", sequence="s", start=20, end=24)
    g.add_edge(0, 1, weight=1.0, exit_frame=9, entry_frame=20)
    plan = plan_leg(g, 0, 0, 1, 3)
    assert plan.frames == 10 and plan.loops == (0,)
    # 25 frames: 20 or 30 are made, one loop; the shorter wins the tie.
    assert plan_leg(g, 0, 0, 1, 25).frames == 20


def test_cheaper_path_wins_when_both_hit_the_length():
    g = nx.DiGraph()
    for node in range(3):
        g.add_node(node, name=f"m{node}", sequence="s", start=10 * node, end=10 * node + 3)
    g.add_edge(0, 2, weight=3.0, exit_frame=3, entry_frame=20)
    g.add_edge(0, 1, weight=1.0, exit_frame=3, entry_frame=10)
    g.add_edge(1, 2, weight=1.0, exit_frame=13, entry_frame=20)
    assert plan_leg(g, 0, 0, 2, 16).path == (0, 1, 2)
    # 5 frames: only the direct edge comes within a frame (4 frames); two textons take 8.
    assert plan_leg(g, 0, 0, 2, 5).path == (0, 2)


@pytest.mark.parametrize("asked", [0, 7, 300])
def test_unreachable_target_is_no_path(asked):
    g = nx.DiGraph()
    g.add_node(0, name="a", sequence="s", start=0, end=3)
    g.add_node(1, name="b", sequence="s", start=5, end=8)
    with pytest.raises(NoPath):
        plan_leg(g, 0, 0, 1, asked)


def _two_textons():
    g = nx.DiGraph()
    g.add_node(0, name="walk", sequence="a", start=0, end=4)
    g.add_node(1, name="run", sequence="b", start=10, end=12)
    g.add_edge(0, 1, weight=0.5, exit_frame=4, entry_frame=10)
    g.add_edge(1, 0, weight=0.5, exit_frame=12, entry_frame=0)
    return g


def test_timed_edit_keeps_the_key_motions_on_the_clock_asked():
    g = _two_textons()
    keys, timing = Timing.request(g, [0, 1, 0], fps=10, durations=[1.5, 0.9])
    edit = compose(g, keys, timing=timing)
    # walk plays 5 + 5k frames: 15; run 3 + 3k: 9, so key motions begin at 0, 15, 24.
    assert edit.starts == [0, 15, 24]
    assert [leg.loops for leg in edit.legs] == [(2,), (2,)]
    runs = [len(list(group)) for _, group in itertools.groupby(e.node for e in edit.schedule)]
    assert runs == [15, 9, 5]


def test_a_missed_leg_warns_and_strict_raises():
    g = _two_textons()
    keys, timing = Timing.request(g, [0, 1], fps=10, durations=[0.7])  # 5 or 10 frames, not 6-8
    with pytest.warns(DurationWarning, match=r"leg 1 \('walk' -> 'run'\) was asked to last 0.7 s and lasts 0.5 s"):
        assert compose(g, keys, timing=timing).legs[0].frames == 5
    keys, timing = Timing.request(g, [0, 1], fps=10, durations=[0.7], strict=True)
    with pytest.raises(DurationError, match="ask for 0.5 s"):
        compose(g, keys, timing=timing)


def test_a_miss_at_a_capture_frame_rate_says_seconds_to_the_hundredth():
    # A depth camera's 29.959 fps: 5 frames are 0.166894... s, said as 0.17 s.
    g = _two_textons()
    keys, timing = Timing.request(g, [0, 1], fps=29.959, durations=[0.25], strict=True)
    with pytest.raises(DurationError, match=r"lasts 0.17 s \(5 frames at 29.959 fps\).*ask for 0.17 s"):
        compose(g, keys, timing=timing)


def test_a_hold_plays_the_motion_on_and_the_next_leg_starts_there():
    g = _two_textons()
    keys, timing = Timing.request(g, [0, 1], fps=10, durations=[1.5], holds={0: 0.7})
    assert keys == [0, 0, 1] and timing.durations == (0.7, pytest.approx(0.8))
    edit = compose(g, keys, timing=timing)
    frames = [e.frame for e in edit.schedule]
    # 7 frames of walk from frame 0, then walk again from frame 2 to its exit at 4 (all 5 shown).
    assert frames[:7] == [0, 1, 2, 3, 4, 0, 1] and edit.starts[:2] == [0, 7]
    assert frames[7:edit.starts[2]] == [2, 3, 4, 0, 1, 2, 3, 4]
