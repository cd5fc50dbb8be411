"""Best path, eq. (15)-(16): tiny hand-built graphs with known answers, and brute force."""

import math
import random

import networkx as nx
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tvmedit.engine.errors import NoPath, UnknownMotion
from tvmedit.engine.graph.search import SearchIndex, best_path, minimum_mu, path_cost


def motion_graph(weights, mu=None, nodes=None):
    """A motion graph as engine/graph.py builds it, from weights {(i, j): w}.

    With ``mu`` the weights are the unpruned ones and edge i -> j is kept iff
    w(i, j) < mu * mean_j' w(i, j'), eq. (13)-(14); without it every edge is kept.
    """
    nodes = sorted({i for edge in weights for i in edge} | set(nodes or ()))
    g = nx.DiGraph(unpruned=dict(weights), mu=mu) if mu is not None else nx.DiGraph()
    for i in nodes:
        g.add_node(i, name=f"m{i}", sequence=f"seq{i}", start=0, end=3)
    kept = prune(weights, mu) if mu is not None else weights
    for (i, j), w in kept.items():
        g.add_edge(i, j, weight=w, exit_frame=0, entry_frame=0)
    return g


def prune(weights, mu):
    """Edges that survive pruning at ``mu``, eq. (14): strictly below mu times the mean."""
    total, count = {}, {}
    for (i, _), w in weights.items():
        total[i] = total.get(i, 0.0) + w
        count[i] = count.get(i, 0) + 1
    return {(i, j): w for (i, j), w in weights.items() if w < mu * total[i] / count[i]}


def brute_force(g, source, target):
    """Least (cost, edges) over all simple paths, and the paths that reach it."""
    best, paths = None, []
    for path in nx.all_simple_paths(g, source, target):
        key = (path_cost(g, path), len(path) - 1)
        if best is None or key < best:
            best, paths = key, [path]
        elif key == best:
            paths.append(path)
    return best, paths


def random_tied_graph(rng, n, density):
    """Random digraph whose weights come from {1, 2, 3}, so that ties abound."""
    return {(i, j): float(rng.choice((1, 2, 3))) for i in range(n) for j in range(n)
            if i != j and rng.random() < density}


def test_brute_force_on_a_thousand_tied_graphs():
    rng = random.Random(15)
    checked = 0
    for _ in range(1200):
        n = rng.choice((5, 6, 7))
        g = motion_graph(random_tied_graph(rng, n, rng.choice((0.3, 0.45, 0.6))), nodes=range(n))
        for _ in range(3):
            source, target = rng.sample(range(n), 2)
            best, paths = brute_force(g, source, target)
            if best is None:
                with pytest.raises(NoPath):
                    best_path(g, source, target)
                continue
            path = best_path(g, source, target)
            assert (path_cost(g, path), len(path) - 1) == best
            # Ties go to the path whose nodes, read backwards from the target, are smallest.
            assert path == min(paths, key=lambda p: p[::-1])
            # Algorithm 1 is exact for the cost, eq. (15); only the edge count may be off.
            paper = best_path(g, source, target, method="paper")
            assert path_cost(g, paper) == best[0] and len(paper) - 1 >= best[1]
            checked += 1
    assert checked > 1000


def test_algorithm_1_as_printed_takes_an_extra_edge():
    # 0 -> 1 -> 2 reaches node 2 at cost 1, so Algorithm 1 keeps that prefix; the heavier
    # edge 2 -> 3 then makes it cost 2, the same as the shorter 0 -> 2 -> 3.
    g = motion_graph({(0, 1): 1.0, (1, 2): 1.0, (0, 2): 2.0, (2, 3): 2.0})
    assert best_path(g, 0, 3, method="paper") == [0, 1, 2, 3]
    assert best_path(g, 0, 3) == [0, 2, 3]


def test_one_rough_transition_loses_to_many_smooth_ones():
    g = motion_graph({(0, 4): 5.0, (0, 1): 1.0, (1, 2): 1.0, (2, 3): 1.0, (3, 4): 1.0})
    assert best_path(g, 0, 4) == [0, 1, 2, 3, 4]


def test_equal_costs_go_to_fewer_edges():
    g = motion_graph({(0, 1): 2.0, (1, 2): 1.0, (2, 3): 1.0, (0, 3): 2.0})
    assert best_path(g, 0, 3) == [0, 3]


def test_ties_between_equal_paths_go_to_smaller_ids():
    g = motion_graph({(0, 2): 1.0, (0, 1): 1.0, (2, 3): 1.0, (1, 3): 1.0})
    assert best_path(g, 0, 3) == [0, 1, 3]


def test_source_equal_to_target_is_an_empty_leg():
    g = motion_graph({(0, 1): 1.0})
    assert best_path(g, 1, 1) == [1]


def test_forbidden_motion_is_routed_around():
    g = motion_graph({(0, 1): 1.0, (1, 3): 1.0, (0, 2): 2.0, (2, 3): 2.0})
    assert best_path(g, 0, 3, forbidden=[1]) == [0, 2, 3]
    assert best_path(g, 0, 3, forbidden=[1], method="paper") == [0, 2, 3]


@settings(max_examples=200, deadline=None)
@given(st.data())
def test_forbidden_motions_never_appear(data):
    n = data.draw(st.integers(4, 8))
    pairs = [(i, j) for i in range(n) for j in range(n) if i != j]
    weights = data.draw(st.dictionaries(st.sampled_from(pairs), st.sampled_from([1.0, 2.0, 3.0]),
                                        min_size=1))
    g = motion_graph(weights, nodes=range(n))
    source, target = data.draw(st.sampled_from(pairs))
    forbidden = data.draw(st.sets(st.sampled_from([i for i in range(n) if i not in (source, target)])))
    free = g.subgraph([i for i in g if i not in forbidden])
    for method in ("exact", "paper"):
        try:
            path = best_path(g, source, target, forbidden=forbidden, method=method)
        except NoPath:
            assert not nx.has_path(free, source, target)
        else:
            assert not forbidden & set(path)
            assert path_cost(g, path) == brute_force(free, source, target)[0][0]


def test_no_path_names_both_motions_and_the_mu_that_connects():
    # Node 0 reaches 2 only through 1 (ratio 0.5, then ratio 1): the graph at mu 0.9 has no path.
    weights = {(0, 1): 1.0, (0, 2): 3.0, (1, 0): 1.0, (1, 2): 1.0, (2, 0): 1.0, (2, 1): 1.0}
    g = motion_graph(weights, mu=0.9)
    with pytest.raises(NoPath) as caught:
        best_path(g, 0, 2)
    error = caught.value
    assert error.mu == 1.01 and (error.source, error.target) == (0, 2)
    message = str(error)
    assert "'m0'" in message and "'m2'" in message and "mu = 1.01" in message
    assert "mu=1.01" in message and message.count(". ") == 0
    assert best_path(motion_graph(weights, mu=error.mu), 0, 2) == [0, 1, 2]
    # Eq. (14) is strict: at exactly the worst ratio the edge is still pruned.
    with pytest.raises(NoPath):
        best_path(motion_graph(weights, mu=1.0), 0, 2)


def test_reported_mu_is_the_smallest_round_one_that_connects():
    rng = np.random.default_rng(14)
    found = 0
    for _ in range(300):
        n = int(rng.integers(4, 9))
        weights = {(i, j): float(rng.random()) for i in range(n) for j in range(n) if i != j}
        g = motion_graph(weights, mu=0.6)
        source, target = (int(x) for x in rng.choice(n, 2, replace=False))
        try:
            best_path(g, source, target)
        except NoPath as error:
            found += 1
            best_path(motion_graph(weights, mu=error.mu), source, target)
            with pytest.raises(NoPath):
                best_path(motion_graph(weights, mu=round(error.mu - 0.01, 2)), source, target)
    assert found > 20


def test_forbidden_motions_can_leave_no_mu():
    # Every edge out of motion 0, pruned or not, leads to the forbidden motion 1.
    weights = {(0, 1): 1.0, (1, 2): 1.0, (2, 0): 1.0, (1, 0): 1.0, (2, 1): 1.0}
    g = motion_graph(weights, mu=0.9)
    with pytest.raises(NoPath) as caught:
        best_path(g, 0, 2, forbidden=[1])
    assert caught.value.mu == float("inf") and "any mu" in str(caught.value)
    assert minimum_mu(g, 0, 2, forbidden=[1]) == float("inf")


def test_forbidden_key_motion_has_no_path():
    g = motion_graph({(0, 1): 1.0})
    with pytest.raises(NoPath, match="'m1' is itself forbidden"):
        best_path(g, 0, 1, forbidden=[1])


def test_graph_without_unpruned_weights_still_explains():
    g = motion_graph({(0, 1): 1.0, (2, 1): 1.0})
    with pytest.raises(NoPath, match="larger mu") as caught:
        best_path(g, 0, 2)
    assert caught.value.mu is None


def test_unknown_motion_lists_the_known_ones():
    g = motion_graph({(0, 1): 1.0})
    with pytest.raises(UnknownMotion, match=r"^there is no target motion 7; known motions are m0, m1 "
                                            r"\(or an id from 0 to 1\)\.$"):
        best_path(g, 0, 7)


def test_index_follows_added_edges():
    g = motion_graph({(0, 1): 1.0, (1, 2): 1.0})
    assert best_path(g, 0, 2) == [0, 1, 2]
    g.add_edge(0, 2, weight=1.0)
    assert best_path(g, 0, 2) == [0, 2]
    g.edges[0, 2]["weight"] = 5.0
    assert best_path(g, 0, 2, index=SearchIndex.from_graph(g)) == [0, 1, 2]


def test_dense_graph_agrees_with_networkx_minimax():
    # On a pruned random graph of 60 motions the cost must match a plain bisection over
    # thresholds with networkx reachability, and the edge count its unweighted BFS.
    rng = np.random.default_rng(3)
    n = 60
    weights = {(i, j): float(rng.random()) for i in range(n) for j in range(n) if i != j}
    g = motion_graph(weights, mu=0.9)
    for source, target in rng.choice(n, (20, 2)):
        source, target = int(source), int(target)
        if source == target:
            continue
        path = best_path(g, source, target)
        cost = path_cost(g, path)
        below = nx.DiGraph((u, v) for u, v, w in g.edges(data="weight") if w <= cost)
        assert len(path) - 1 == nx.shortest_path_length(below, source, target)
        strictly = nx.DiGraph((u, v) for u, v, w in g.edges(data="weight") if w < cost)
        assert not (source in strictly and target in strictly and nx.has_path(strictly, source, target))


def test_reported_mu_connects_the_graph_the_builder_makes():
    # The same check through tvmedit.engine.graph.motiongraph.graph_from, which prunes the real library's graph.
    from tvmedit.engine.graph.database import Node
    from tvmedit.engine.graph.motiongraph import graph_from

    rng = np.random.default_rng(5)
    n = 8
    nodes = [Node(i, f"take/{i:02d}", "take", 10 * i, 10 * i + 4, i, 0.0, 1.0) for i in range(n)]
    unpruned = {(i, j): float(rng.random()) for i in range(n) for j in range(n) if i != j}
    frames = {(i, j): (10 * i, 10 * j) for i, j in unpruned}
    refused = 0
    for source in range(n):
        for target in range(n):
            try:
                best_path(graph_from(nodes, unpruned, frames, mu=0.5, connect="off"), source, target)
            except NoPath as error:
                refused += 1
                assert f"'take/{source:02d}'" in str(error)
                best_path(graph_from(nodes, unpruned, frames, mu=error.mu, connect="off"), source, target)
    assert refused > 5


def test_a_motion_reaches_itself_at_no_cost_and_any_mu():
    g = nx.DiGraph(unpruned={(0, 1): 1.0, (1, 0): 2.0}, mu=0.9)
    g.add_edge(0, 1, weight=1.0)
    assert best_path(g, 0, 0) == [0]
    assert SearchIndex.of(g).bottleneck(0, 0) == -math.inf
    assert minimum_mu(g, 0, 0) == 0.0
