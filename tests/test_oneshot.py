"""One-shot motions: takes that are not exercises become motions played through once.

Database (a cluster with fewer than two textons), graph (eq. 10 restricted: entered at the
first frame, left from the last part) and composition (played once to the exit), on
hand-built features whose answers are known.
"""

from types import SimpleNamespace

import networkx as nx
import numpy as np

from tvmedit.engine.graph.compose import compose
from tvmedit.engine.graph.database import Node, build_database
from tvmedit.engine.graph.motiongraph import build_graph, entry_range, exit_range, nodes_of


def _features():
    # One sequence: frames 0-9 a cycle (values 0..4 twice), frames 10-29 a one-shot that
    # drifts from 10 to 29 (a wave that never comes back).
    cycle = [0.0, 1.0, 2.0, 3.0, 4.0] * 2
    once = [float(v) for v in range(10, 30)]
    return np.array(cycle + once)[:, None]


def _nodes():
    textons = [SimpleNamespace(start=0, end=4, cluster=0, distance=0.1),
               SimpleNamespace(start=5, end=9, cluster=0, distance=0.2)]
    return build_database({"take": (textons, [(0, 9), (10, 29)])})


def test_cluster_without_repeats_is_a_one_shot_node():
    nodes = _nodes()
    assert [(n.name, n.start, n.end, n.kind) for n in nodes] == [
        ("take/01", 0, 4, "cycle"), ("take/02", 10, 29, "once")]
    assert exit_range(nodes[1]) == (25, 29) and entry_range(nodes[1]) == (10, 10)
    assert exit_range(nodes[0]) == entry_range(nodes[0]) == (0, 4)


def test_one_shot_is_entered_at_its_start_and_left_from_its_last_part():
    G = build_graph(_nodes(), {"take": _features()}, mu=10.0)
    exit_frame, entry_frame = G.edges[0, 1]["exit_frame"], G.edges[0, 1]["entry_frame"]
    # Into the one-shot: only its first frame (value 10) may be entered; the cycle's closest
    # frame to it is frame 4 (value 4).
    assert (exit_frame, entry_frame) == (4, 10)
    assert G.edges[0, 1]["weight"] > 0
    # Out of the one-shot: only frames 25-29 (values 25..29) may be left; the closest of them
    # to the cycle is 25, entering the cycle at its frame with value 4. Unrestricted, eq. (10)
    # would have left at frame 10, before the wave is under way.
    assert (G.edges[1, 0]["exit_frame"], G.edges[1, 0]["entry_frame"]) == (25, 4)
    assert [n.kind for n in nodes_of(G)] == ["cycle", "once"]


def test_one_shot_plays_through_once_to_its_exit_then_leaves():
    G = build_graph(_nodes(), {"take": _features()}, mu=10.0)
    edit = compose(G, [1, 0])
    frames = [e.frame for e in edit.schedule]
    # 10..25 once (no cycle rule, no repeat), then the cycle from its entry frame 4.
    assert frames[:16] == list(range(10, 26))
    assert frames[16:] == [4, 0, 1, 2, 3]
    edit = compose(G, [0, 1])
    frames = [e.frame for e in edit.schedule]
    # The cycle plays whole and leaves at 4; the one-shot, the last key motion, plays whole once.
    assert frames == [0, 1, 2, 3, 4] + list(range(10, 30))


def test_one_shot_is_an_ordinary_graph_node():
    # Pruned, searched and exported like any node: the graph is a plain DiGraph of ids.
    G = build_graph(_nodes(), {"take": _features()})
    assert isinstance(G, nx.DiGraph) and set(G.nodes) == {0, 1}
    assert G.nodes[1]["kind"] == "once" and isinstance(Node(**{**G.nodes[1], "id": 1}), Node)
