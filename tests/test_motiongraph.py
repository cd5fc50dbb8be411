"""Motion graph, eq. (10)-(14), on a three-node database whose weights are worked out by hand.

Feature vectors are 2-D points, so a frame distance is the plain distance between points.

    sequence "a": frame 0 (0, 0), 1 (1, 0), 2 (100, 100), 3 (3, 0), 4 (5, 0), 5 (7, 0)
    sequence "b": frame 0 (50, 50), 1 (10, 0), 2 (10, 4)

    node 0 = a/01, frames 0-1:  (0, 0) (1, 0)          intensity 1 / 1       = 1
    node 1 = a/02, frames 3-5:  (3, 0) (5, 0) (7, 0)   intensity (2 + 2) / 2 = 2
    node 2 = b/01, frames 1-2:  (10, 0) (10, 4)        intensity 4 / 1       = 4

Frames a2 and b0 lie far from everything and outside every node: a transition frame that
pointed at them would mean relative and absolute frame indices got mixed up.

    d_V(0, 1) = |(1,0) - (3,0)|  = 2   at frames a1, a3
    d_V(0, 2) = |(1,0) - (10,0)| = 9   at frames a1, b1
    d_V(1, 2) = |(7,0) - (10,0)| = 3   at frames a5, b1

    w(0,1) = 2/1 = 2     w(0,2) = 9/1 = 9      mean 5.5    0.9 * mean = 4.95
    w(1,0) = 2/2 = 1     w(1,2) = 3/2 = 1.5    mean 1.25   0.9 * mean = 1.125
    w(2,0) = 9/4 = 2.25  w(2,1) = 3/4 = 0.75   mean 1.5    0.9 * mean = 1.35

Kept at mu = 0.9: (0,1), (1,0), (2,1).
"""

import math

import networkx as nx
import numpy as np
import pytest

from tvmedit.engine.graph.database import Node
from tvmedit.engine.errors import TvmError, UnknownMotion
from tvmedit.engine.graph.motiongraph import (MIN_INTENSITY, build_graph, graph_from, node_by_key, nodes_of, prune,
                          rename)

VECTORS = {
    "a": np.array([[0, 0], [1, 0], [100, 100], [3, 0], [5, 0], [7, 0]], dtype=np.float32),
    "b": np.array([[50, 50], [10, 0], [10, 4]], dtype=np.float32),
}


def database():
    return [Node(0, "a/01", "a", 0, 1, 0, 0.01),
            Node(1, "a/02", "a", 3, 5, 1, 0.02),
            Node(2, "b/01", "b", 1, 2, 0, 0.03)]


@pytest.fixture
def graph():
    """The paper's graph, pruned by eq. (14) alone (connection is tested in test_connect)."""
    return build_graph(database(), VECTORS, connect="off")


def test_unpruned_weights_match_the_hand_computation(graph):
    expected = {(0, 1): 2.0, (0, 2): 9.0, (1, 0): 1.0, (1, 2): 1.5, (2, 0): 2.25, (2, 1): 0.75}
    assert graph.graph["unpruned"].keys() == expected.keys()
    for edge, w in expected.items():
        assert graph.graph["unpruned"][edge] == pytest.approx(w, abs=1e-6)


def test_transition_frames_are_the_hand_computed_argmin(graph):
    # Absolute frames within each node's own sequence; (j, i) is (i, j) swapped.
    assert graph.graph["transitions"] == {
        (0, 1): (1, 3), (1, 0): (3, 1),
        (0, 2): (1, 1), (2, 0): (1, 1),
        (1, 2): (5, 1), (2, 1): (1, 5),
    }
    assert graph.edges[2, 1]["exit_frame"] == 1 and graph.edges[2, 1]["entry_frame"] == 5
    assert graph.edges[0, 1]["exit_frame"] == 1 and graph.edges[0, 1]["entry_frame"] == 3


def test_pruning_keeps_exactly_the_edges_below_mu_times_mean(graph):
    assert sorted(graph.edges) == [(0, 1), (1, 0), (2, 1)]
    assert graph.graph["mu"] == 0.9


def test_graph_is_directed(graph):
    # Same frames, different cost: the source's intensity divides (eq. (12)).
    assert graph.edges[0, 1]["weight"] == pytest.approx(2.0)
    assert graph.edges[1, 0]["weight"] == pytest.approx(1.0)
    # 2 -> 1 costs 0.75 (below 1.35) and stays; 1 -> 2 costs 1.5 (above 1.125) and goes.
    assert graph.has_edge(2, 1) and not graph.has_edge(1, 2)


def test_self_edges_never_present_even_when_mu_keeps_everything():
    G = build_graph(database(), VECTORS, mu=100.0)
    assert G.number_of_edges() == 6
    assert nx.number_of_selfloops(G) == 0
    assert all(i != j for i, j in G.graph["unpruned"])


def test_larger_mu_keeps_more_edges():
    # mu = 1.3: node 0 keeps w < 7.15 (2, not 9); node 1 keeps w < 1.625 (1 and 1.5);
    # node 2 keeps w < 1.95 (0.75, not 2.25).
    G = build_graph(database(), VECTORS, mu=1.3)
    assert sorted(G.edges) == [(0, 1), (1, 0), (1, 2), (2, 1)]


def test_nodes_carry_database_attributes_and_measured_intensity(graph):
    assert graph.nodes[1] == {"name": "a/02", "sequence": "a", "start": 3, "end": 5, "cluster": 1,
                              "texton_distance": 0.02, "intensity": pytest.approx(2.0), "kind": "cycle"}
    assert [n.intensity for n in nodes_of(graph)] == pytest.approx([1.0, 2.0, 4.0])


def test_input_nodes_are_not_changed():
    nodes = database()
    build_graph(nodes, VECTORS)
    assert all(node.intensity is None for node in nodes)


@pytest.mark.parametrize("mu", [0.5, 0.9, 1.3, 2.0])
def test_repruning_stored_weights_gives_the_same_graph(mu):
    built = build_graph(database(), VECTORS, mu=mu)
    stored = build_graph(database(), VECTORS, mu=0.9)
    rebuilt = graph_from(nodes_of(stored), stored.graph["unpruned"],
                         stored.graph["transitions"], mu)
    assert dict(rebuilt.nodes(data=True)) == dict(built.nodes(data=True))
    assert sorted(rebuilt.edges(data=True)) == sorted(built.edges(data=True))
    assert rebuilt.graph == built.graph


def test_edge_equal_to_mu_times_mean_is_pruned():
    # Mean of node 0's edges is (1 + 3) / 2 = 2; at mu = 0.5 the threshold is exactly 1.
    w = {(0, 1): 1.0, (0, 2): 3.0}
    assert prune(w, mu=0.5) == set()
    assert prune(w, mu=0.51) == {(0, 1)}


def test_two_node_database_has_no_edges_unless_mu_exceeds_one():
    # Each node has one edge, which is its own mean: w >= mu * w for every mu <= 1.
    nodes = database()[:2]
    assert build_graph(nodes, VECTORS, connect="off").number_of_edges() == 0
    assert sorted(build_graph(nodes, VECTORS, mu=1.01).edges) == [(0, 1), (1, 0)]
    # connected by default: both directions put back, marked as added
    G = build_graph(nodes, VECTORS)
    assert sorted(G.edges(data="added")) == [(0, 1, True), (1, 0, True)]


def test_frozen_texton_gets_a_finite_weight_through_the_intensity_floor():
    # Node 1 repeats one frame (5, 0): intensity 0. Its way out to node 0 (frame (1, 0),
    # 4 away) costs 4 / MIN_INTENSITY instead of a division by zero.
    vectors = {"a": np.array([[0, 0], [1, 0], [5, 0], [5, 0]], dtype=np.float32)}
    nodes = [Node(0, "a/01", "a", 0, 1, 0, 0.0), Node(1, "a/02", "a", 2, 3, 1, 0.0)]
    G = build_graph(nodes, vectors, mu=2.0)
    assert G.nodes[1]["intensity"] == 0.0
    assert G.edges[1, 0]["weight"] == pytest.approx(4.0 / MIN_INTENSITY)
    assert math.isfinite(G.edges[1, 0]["weight"])
    assert G.edges[0, 1]["weight"] == pytest.approx(4.0)


def test_node_by_key_resolves_ids_digit_strings_and_names(graph):
    assert node_by_key(graph, 2) == 2
    assert node_by_key(graph, np.int64(2)) == 2
    assert node_by_key(graph, "2") == 2
    assert node_by_key(graph, "a/02") == 1
    assert node_by_key(graph, " b/01 ") == 2


def test_unknown_key_gives_one_sentence_listing_the_known_names(graph):
    with pytest.raises(UnknownMotion) as error:
        node_by_key(graph, "jump")
    assert str(error.value) == ("there is no motion 'jump'; known motions are a/01, a/02, b/01 "
                                "(or an id from 0 to 2).")
    with pytest.raises(UnknownMotion):
        node_by_key(graph, 3)
    with pytest.raises(UnknownMotion):
        node_by_key(graph, True)


def test_renamed_node_is_found_by_its_new_name_only(graph):
    assert rename(graph, "a/02", "stride") == 1
    assert node_by_key(graph, "stride") == 1
    with pytest.raises(UnknownMotion, match="stride"):
        node_by_key(graph, "a/02")
    with pytest.raises(TvmError, match="already taken"):
        rename(graph, 0, "stride")
    with pytest.raises(TvmError, match="non-digit"):
        rename(graph, 0, "12")


def test_feature_vectors_of_unequal_length_are_refused():
    vectors = {"a": VECTORS["a"], "b": np.zeros((3, 5), dtype=np.float32)}
    with pytest.raises(ValueError, match="pad the r histograms"):
        build_graph(database(), vectors)


def test_node_outside_its_sequence_is_refused():
    nodes = [Node(0, "a/01", "a", 4, 9, 0, 0.0)]
    with pytest.raises(ValueError, match="has 6 feature vectors"):
        build_graph(nodes, VECTORS)


def test_empty_database_gives_an_empty_graph():
    G = build_graph([], {})
    assert G.number_of_nodes() == 0 and G.graph["unpruned"] == {}
