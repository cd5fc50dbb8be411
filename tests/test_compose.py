"""Composition, section 8: key motions, best paths and the loop-then-transition schedule."""

import itertools
import json
import random

import networkx as nx
import numpy as np
import pytest

from tvmedit.engine.graph.compose import ScheduleEntry, compose, play_length
from tvmedit.engine.errors import NoPath, TvmError, UnknownMotion


def texton_graph(textons, edges):
    """Motion graph from textons {id: (start, end)} and edges {(u, v): (weight, exit, entry)}."""
    g = nx.DiGraph()
    for node, (start, end) in textons.items():
        g.add_node(node, name=f"m{node}", sequence=f"seq{node}", start=start, end=end)
    for (u, v), (weight, exit_frame, entry_frame) in edges.items():
        g.add_edge(u, v, weight=weight, exit_frame=exit_frame, entry_frame=entry_frame)
    return g


def random_texton_graph(rng, n):
    textons = {}
    for node in range(n):
        start = rng.randrange(0, 30)
        textons[node] = (start, start + rng.randrange(0, 6))
    edges = {}
    for u, v in itertools.permutations(range(n), 2):
        if rng.random() < 0.6:
            edges[u, v] = (float(rng.choice((1, 2, 3))), rng.randint(*textons[u]), rng.randint(*textons[v]))
    return texton_graph(textons, edges)


def frames(edit):
    return [(entry.node, entry.frame) for entry in edit.schedule]


def three_textons(exit_b, entry_b=14):
    """A (frames 0-2) -> B (frames 10-15, entered at ``entry_b``, left at ``exit_b``) -> C (30-32)."""
    return texton_graph({0: (0, 2), 1: (10, 15), 2: (30, 32)},
                        {(0, 1): (1.0, 2, entry_b), (1, 2): (2.0, exit_b, 30)})


def middle(edit):
    return [frame for node, frame in frames(edit) if node == 1]


def test_texton_left_after_its_entry_plays_on_to_the_exit():
    edit = compose(three_textons(exit_b=12), [0, 2])
    assert frames(edit)[:3] == [(0, 0), (0, 1), (0, 2)]
    assert middle(edit) == [14, 15, 10, 11, 12, 13, 14, 15, 10, 11, 12]
    assert frames(edit)[-3:] == [(2, 30), (2, 31), (2, 32)]
    assert [(t.index, t.source, t.target, t.exit_frame, t.entry_frame) for t in edit.transitions] == [
        (3, 0, 1, 2, 14), (14, 1, 2, 12, 30)]
    assert play_length(10, 15, 14, 12) == 11


def test_exit_just_before_entry_plays_the_texton_once():
    assert middle(compose(three_textons(exit_b=13), [0, 2])) == [14, 15, 10, 11, 12, 13]
    # Entered at its first frame and left at its last: the same, without wrapping.
    assert middle(compose(three_textons(exit_b=15, entry_b=10), [0, 2])) == [10, 11, 12, 13, 14, 15]


def test_exit_at_the_entry_frame_plays_once_and_then_reaches_it_again():
    assert middle(compose(three_textons(exit_b=14), [0, 2])) == [14, 15, 10, 11, 12, 13, 14]


def test_single_frame_texton_is_shown_once():
    g = texton_graph({0: (5, 5), 1: (7, 7)}, {(0, 1): (1.0, 5, 7)})
    assert frames(compose(g, [0, 1])) == [(0, 5), (1, 7)]


def test_every_texton_shows_all_its_frames_then_leaves_at_the_first_chance():
    rng = random.Random(8)
    for _ in range(300):
        g = random_texton_graph(rng, rng.randrange(3, 7))
        keys = [rng.randrange(len(g)) for _ in range(rng.randrange(2, 5))]
        try:
            edit = compose(g, keys)
        except NoPath:
            continue
        bounds = [0] + [t.index for t in edit.transitions] + [len(edit.schedule)]
        for k, (a, b) in enumerate(zip(bounds, bounds[1:])):
            stay = edit.schedule[a:b]
            node = stay[0].node
            start, end = g.nodes[node]["start"], g.nodes[node]["end"]
            shown = [entry.frame for entry in stay]
            assert {entry.node for entry in stay} == {node}
            assert set(shown) == set(range(start, end + 1))
            if k > 0:
                assert shown[0] == edit.transitions[k - 1].entry_frame
            if k < len(edit.transitions):
                exit_frame = edit.transitions[k].exit_frame
                assert shown[-1] == exit_frame
                # No earlier frame after a full cycle was the exit: the transition is the first allowed.
                assert exit_frame not in shown[end - start:-1]
            # Playback within a stay steps one frame at a time, cyclically.
            for x, y in zip(shown, shown[1:]):
                assert y == (x + 1 if x < end else start)


def test_legs_report_path_cost_edges_and_frames():
    g = texton_graph({0: (0, 2), 1: (10, 15), 2: (30, 32), 3: (40, 41)},
                     {(0, 1): (1.0, 2, 14), (1, 2): (2.0, 12, 30), (2, 3): (0.5, 31, 40),
                      (0, 2): (9.0, 0, 30)})
    edit = compose(g, ["m0", "m2", "m3"])
    assert [(leg.path, leg.cost, leg.edges, leg.frames) for leg in edit.legs] == [
        ((0, 1, 2), 2.0, 2, 3 + 11), ((2, 3), 0.5, 1, 5)]
    # Each leg runs from its key motion's first frame up to the next key motion's first frame.
    assert edit.schedule[14] == ScheduleEntry(2, "seq2", 30)
    assert len(edit.schedule) == 14 + 5 + 2
    document = json.loads(json.dumps(edit.to_json()))
    assert document["legs"][0] == {"from": 0, "to": 2, "path": [0, 1, 2], "cost": 2.0, "edges": 2,
                                   "frames": 14}
    assert document["schedule"][0] == {"node": 0, "sequence": "seq0", "frame": 0}


def test_repeated_key_motion_is_an_empty_leg():
    g = three_textons(exit_b=12)
    plain, repeated = compose(g, [0, 2]), compose(g, [0, 0, 2, 2])
    assert frames(repeated) == frames(plain)
    assert [(leg.path, leg.cost, leg.edges, leg.frames) for leg in repeated.legs] == [
        ((0,), 0.0, 0, 0), ((0, 1, 2), 2.0, 2, 14), ((2,), 0.0, 0, 0)]


def test_loops_repeat_the_last_key_motion():
    g = three_textons(exit_b=12)
    once, twice = compose(g, [0, 2]), compose(g, [0, 2], loops=3)
    assert frames(twice)[len(once.schedule):] == [(2, 30), (2, 31), (2, 32)] * 2
    forever = compose(g, [0, 2], loops=None)
    assert forever.schedule == once.schedule
    head = list(itertools.islice(forever.frames(), len(once.schedule) + 7))
    assert [e.frame for e in head[len(once.schedule):]] == [30, 31, 32, 30, 31, 32, 30]
    assert len(list(once.frames())) == len(once.schedule)


def test_last_key_motion_loops_from_where_it_is_entered():
    g = texton_graph({0: (0, 1), 1: (10, 13)}, {(0, 1): (1.0, 1, 12)})
    assert [f for n, f in frames(compose(g, [0, 1], loops=2)) if n == 1] == [12, 13, 10, 11] * 2


def test_forbidden_motions_by_name_are_avoided():
    g = texton_graph({0: (0, 1), 1: (2, 3), 2: (4, 5), 3: (6, 7)},
                     {(0, 1): (1.0, 0, 2), (1, 3): (1.0, 2, 6), (0, 2): (2.0, 0, 4), (2, 3): (2.0, 4, 6)})
    assert compose(g, [0, 3]).legs[0].path == (0, 1, 3)
    assert compose(g, [0, 3], forbidden=["m1"]).legs[0].path == (0, 2, 3)


def test_bad_keys_are_explained():
    g = three_textons(exit_b=12)
    with pytest.raises(UnknownMotion, match="'nope'.*known motions are m0, m1, m2"):
        compose(g, ["m0", "nope"])
    with pytest.raises(UnknownMotion):
        compose(g, [0, True])  # a bool is not an id
    with pytest.raises(TvmError, match="at least two key motions"):
        compose(g, ["m0"])
    with pytest.raises(TvmError, match="loops"):
        compose(g, [0, 2], loops=0)
    with pytest.raises(NoPath, match="'m2' to 'm0'"):
        compose(g, [2, 0])


def test_numpy_ids_come_back_as_plain_ints():
    edit = compose(three_textons(exit_b=12), np.array([0, 2]))
    assert json.dumps(edit.to_json())
    assert type(edit.keys[0]) is int and type(edit.legs[0].source) is int
