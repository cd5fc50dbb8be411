"""Connectivity (tvmedit.engine.graph.connect): optimal against brute force, and every pair reachable on real takes.

Brute force enumerates every subset of the edges pruning removed on small random weight
matrices: the least largest added weight of any subset that makes the graph strongly
connected, and the fewest edges among the subsets that reach it. ``connect`` must give both.
"""

import itertools
import json

import networkx as nx
import numpy as np
import pytest

from tvmedit.engine.graph import connect as connection
from tvmedit.engine.graph.connect import connect, strongly_connected
from tvmedit.engine.graph.database import Node
from tvmedit.engine.errors import NoPath
from tvmedit.engine.graph.motiongraph import graph_from, prune
from tvmedit.engine.store.library import Library

from conftest import built_library
from interrupt import refused, tvmedit


def _brute_force(w, kept):
    """``(least largest added weight, fewest edges at it)`` over every subset of the candidates."""
    n = len(w)
    candidates = [(i, j) for i in range(n) for j in range(n) if i != j and not kept[i, j]]
    best = (np.inf, np.inf)
    for size in range(len(candidates) + 1):
        for subset in itertools.combinations(candidates, size):
            largest = max((w[e] for e in subset), default=-np.inf)
            if (largest, size) >= best:
                continue
            adjacency = kept.copy()
            for e in subset:
                adjacency[e] = True
            if strongly_connected(adjacency):
                best = (largest, size)
    return best


def _random_case(rng, n):
    w = rng.integers(1, 12, size=(n, n)).astype(float)     # small integers: many ties
    np.fill_diagonal(w, np.inf)
    unpruned = {(i, j): w[i, j] for i in range(n) for j in range(n) if i != j}
    kept = np.zeros((n, n), bool)
    for i, j in prune(unpruned, mu=rng.uniform(0.4, 1.0)):
        kept[i, j] = True
    return w, kept


def test_added_weight_and_edge_count_equal_brute_force_on_random_graphs():
    rng = np.random.default_rng(12)
    checked = 0
    for case in range(150):
        n = 3 if case < 50 else 4
        w, kept = _random_case(rng, n)
        result = connect(w, kept)
        adjacency = kept.copy()
        for e in result.added:
            adjacency[e] = True
        assert strongly_connected(adjacency)
        assert all(not kept[e] for e in result.added)
        largest, fewest = _brute_force(w, kept)
        if fewest == 0:
            assert result.added == [] and result.largest is None
            continue
        checked += 1
        assert result.largest == largest, (w, kept)
        assert max(w[e] for e in result.added) == largest
        assert result.fewest and len(result.added) == fewest, (w, kept, result)
    assert checked > 60


def test_five_motions_against_brute_force_where_enumeration_is_affordable():
    rng = np.random.default_rng(3)
    checked = 0
    while checked < 12:
        w, kept = _random_case(rng, 5)
        if (~kept).sum() - 5 > 14:       # at most 2^14 subsets to enumerate
            continue
        result = connect(w, kept)
        largest, fewest = _brute_force(w, kept)
        if fewest:
            assert (result.largest, len(result.added)) == (largest, fewest)
            checked += 1


def test_large_graphs_fall_back_to_greedy_and_stay_connected(monkeypatch):
    # Many cut-off motions: far more subsets than the exact search may try.
    monkeypatch.setattr(connection, "EXACT_BUDGET", 200)
    rng = np.random.default_rng(0)
    n = 60
    w = rng.random((n, n))
    np.fill_diagonal(w, np.inf)
    kept = np.zeros((n, n), bool)
    kept[np.arange(n), np.argsort(w, axis=1)[:, 0]] = True      # one way out of each motion
    result = connect(w, kept)
    adjacency = kept.copy()
    for e in result.added:
        adjacency[e] = True
    assert strongly_connected(adjacency)
    # the bottleneck guarantee does not depend on the search: nothing cheaper connects
    cheaper = kept | (w < result.largest) & np.isfinite(w)
    assert not strongly_connected(cheaper)


def test_graph_from_marks_added_edges_and_off_keeps_the_paper():
    nodes = [Node(i, f"t/{i:02d}", "t", 10 * i, 10 * i + 4, i, 0.0, 1.0) for i in range(4)]
    rng = np.random.default_rng(1)
    for _ in range(50):
        unpruned = {(i, j): float(rng.random()) for i in range(4) for j in range(4) if i != j}
        frames = {(i, j): (10 * i, 10 * j) for i, j in unpruned}
        paper = graph_from(nodes, unpruned, frames, mu=0.6, connect="off")
        joined = graph_from(nodes, unpruned, frames, mu=0.6)
        assert set(paper.edges) == prune(unpruned, 0.6)
        assert not any(added for *_, added in paper.edges(data="added"))
        assert nx.is_strongly_connected(joined)
        added = {(i, j) for i, j, a in joined.edges(data="added") if a}
        assert set(joined.edges) == set(paper.edges) | added and not added & set(paper.edges)
        assert joined.graph["connect"]["added"] == len(added)
        if added:
            assert joined.graph["connect"]["largest_weight"] == max(unpruned[e] for e in added)
            assert joined.edges[next(iter(added))]["exit_frame"] == next(iter(added))[0] * 10


def test_a_library_opens_with_the_connection_its_build_stored(small_library):
    import subprocess
    import sys

    library = Library.open(small_library)
    stored, found = library.graph, library.graph_at(library.graph.graph["mu"])   # read back; searched anew
    assert stored.graph["connect"]["added"] > 0, "the gym's pruned graph needs edges added"
    assert sorted(stored.edges(data=True)) == sorted(found.edges(data=True))
    assert stored.graph["connect"] == found.graph["connect"]
    # Read back, the connection needs no search: a command that opens the library starts without scipy.
    opened = subprocess.run([sys.executable, "-c", "import sys; from tvmedit import Library; "
                             "Library.open(sys.argv[1]).graph; print('scipy' in sys.modules)", str(small_library)],
                            capture_output=True, text=True, check=True)
    assert opened.stdout.strip() == "False"


def test_a_stored_connection_that_does_not_fit_the_graph_is_found_anew():
    nodes = [Node(i, f"t/{i:02d}", "t", 10 * i, 10 * i + 4, i, 0.0, 1.0) for i in range(4)]
    unpruned = {(i, j): 0.1 if j == i + 1 else 0.9 for i in range(4) for j in range(4) if i != j}
    frames = {(i, j): (10 * i, 10 * j) for i, j in unpruned}
    right = graph_from(nodes, unpruned, frames, mu=0.5)
    summary = right.graph["connect"]
    added = [(i, j) for i, j, a in right.edges(data="added") if a]
    assert graph_from(nodes, unpruned, frames, mu=0.5, connected=(summary, added)).graph["connect"] == summary
    assert added == [(3, 0)]    # the one edge that closes the chain 0 -> 1 -> 2 -> 3
    # Kept already, not an edge, too few, too many, and one as heavy that leaves 0 unreached.
    for wrong in ([(0, 1)], [(2, 2)], [], [(1, 0), (2, 0), (3, 0)], [(3, 1)]):
        read = graph_from(nodes, unpruned, frames, mu=0.5, connected=(summary, wrong))
        assert sorted(read.edges(data=True)) == sorted(right.edges(data=True)), wrong


def test_forbidden_motion_that_cuts_a_pair_off_is_named():
    nodes = [Node(i, f"t/{i:02d}", "t", 10 * i, 10 * i + 4, i, 0.0, 1.0) for i in range(3)]
    unpruned = {(0, 1): 1.0, (1, 2): 1.0, (2, 0): 1.0, (0, 2): 9.0, (1, 0): 9.0, (2, 1): 9.0}
    frames = {(i, j): (10 * i, 10 * j) for i, j in unpruned}
    library_graph = graph_from(nodes, unpruned, frames, mu=0.9)
    from tvmedit.engine.graph.search import best_path

    assert best_path(library_graph, 0, 2) == [0, 1, 2]
    with pytest.raises(NoPath) as error:
        best_path(library_graph, 0, 2, forbidden=[1])
    assert "'t/01'" in str(error.value) and "forbidden" in str(error.value)


def _all_pairs_reachable(library):
    """Every ordered pair of motions has a path, and the added weight is the brute-force optimum."""
    graph = library.graph
    assert nx.is_strongly_connected(graph)
    nodes = [n.id for n in library.nodes]
    for a in nodes:
        for b in nodes:
            library.edit([a, b])          # raises NoPath if a pair were cut off
    summary = graph.graph["connect"]
    if summary["added"]:
        unpruned = graph.graph["unpruned"]
        n = len(nodes)
        w = np.full((n, n), np.inf)
        for (i, j), value in unpruned.items():
            w[i, j] = value
        kept = np.zeros((n, n), bool)
        for i, j, added in graph.edges(data="added"):
            kept[i, j] = not added
        candidates = sorted({v for (i, j), v in unpruned.items() if not kept[i, j]})
        least = next(t for t in candidates if strongly_connected(kept | (w <= t)))
        assert summary["largest_weight"] == least
    return summary


def test_gym_library_connects_every_pair(small_library):
    summary = _all_pairs_reachable(Library.open(small_library))
    assert summary["mode"] == "auto"


@pytest.mark.parametrize("take", ["13_29", "13_30"])
def test_real_takes_connect_every_pair(take, request, tmp_path):
    folder = request.getfixturevalue(f"take_{take}")
    _all_pairs_reachable(Library.open(built_library(take, folder, smooth=False)))   # test_loops' and test_blend's


def test_every_pair_exits_0_through_the_cli_and_info_shows_added_edges(paper_library, small_library):
    # the pairs the paper's graph cuts off are the ones to try through the command line
    cut_off = [(a.name, b.name) for a, b in itertools.permutations(Library.open(paper_library).nodes, 2)
               if refused(Library.open(paper_library), a.id, b.id)]
    assert cut_off
    for a, b in cut_off[:4]:
        result = tvmedit("path", small_library, a, b, "--json")
        assert result.returncode == 0, result.stderr
    info = json.loads(tvmedit("info", small_library, "--json").stdout)
    paper = json.loads(tvmedit("info", paper_library, "--json").stdout)
    assert paper["connect"]["mode"] == "off" and not any(e["added"] for e in paper["edges"])
    added = [e for e in info["edges"] if e["added"]]
    assert info["connect"]["added"] == len(added) > 0
    assert {(e["from"], e["to"]) for e in info["edges"] if not e["added"]} == \
           {(e["from"], e["to"]) for e in paper["edges"]}
    text = tvmedit("info", small_library).stdout
    assert f"{len(added)} of them added to connect it" in text and "(added)" in text


def test_a_library_of_two_takes_is_connected_across_them(take_13_29, take_13_30, tmp_path):
    from tvmedit import engine

    library = engine.build([("13_29", take_13_29), ("13_30", take_13_30)], tmp_path / "both.tvmlib", workers=2,
                           blend_frames=0, smooth=False)
    graph = library.graph
    assert nx.is_strongly_connected(graph)
    sequence = nx.get_node_attributes(graph, "sequence")
    across = {(sequence[i], sequence[j]) for i, j in graph.edges if sequence[i] != sequence[j]}
    assert across == {("13_29", "13_30"), ("13_30", "13_29")}
    _all_pairs_reachable(library)
