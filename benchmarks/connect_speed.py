"""Speed of making a motion graph strongly connected (tvmedit.engine.graph.connect), against its limit.

    .venv/bin/python benchmarks/connect_speed.py [--seed 0]

For 100 to 1,000 motions: a complete graph with random weights (eq. (12)), pruned two ways,
then connected. "mu 0.9" is eq. (14) as the builder applies it (random weights leave few
cut-off motions); "one way out" keeps only each motion's lightest edge, which leaves many
components, the hard case for the fewest-edges search. Prints the seconds each takes, the
number of components before and edges added, and whether the fewest-edges answer is exact
or greedy. Limit: the connection step at 1,000 motions under 1 s.
"""

import argparse
import time

import numpy as np

from tvmedit.engine.graph.connect import connect, strongly_connected

LIMIT_S = 1.0
SIZES = (100, 200, 500, 1000)


def cases(n, rng):
    w = rng.random((n, n))
    np.fill_diagonal(w, np.inf)
    off = ~np.eye(n, dtype=bool)
    mean = np.where(off, w, 0).sum(axis=1) / (n - 1)
    yield "mu 0.9", w, (w < 0.9 * mean[:, None]) & off
    one = np.zeros((n, n), bool)
    one[np.arange(n), np.argmin(w, axis=1)] = True
    yield "one way out", w, one


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    print(f"{'motions':>7}  {'pruning':<12} {'parts':>5} {'added':>5} {'fewest':>7} {'seconds':>8}")
    worst = 0.0
    for n in SIZES:
        for name, w, kept in cases(n, rng):
            started = time.perf_counter()
            result = connect(w, kept)
            seconds = time.perf_counter() - started
            joined = kept.copy()
            for edge in result.added:
                joined[edge] = True
            assert strongly_connected(joined)
            if n == SIZES[-1]:
                worst = max(worst, seconds)
            print(f"{n:>7}  {name:<12} {result.components:>5} {len(result.added):>5} "
                  f"{'exact' if result.fewest else 'greedy':>7} {seconds:8.3f}")
    verdict = "ok" if worst < LIMIT_S else "OVER THE LIMIT"
    print(f"connection at {SIZES[-1]} motions: {worst:.3f} s (limit {LIMIT_S:g} s): {verdict}")
    return 0 if worst < LIMIT_S else 1


if __name__ == "__main__":
    raise SystemExit(main())
