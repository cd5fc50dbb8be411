"""Speed of planning an edit of a given length (tvmedit.engine.graph.timing) against the 0.5 s limit.

    .venv/bin/python benchmarks/timing_speed.py [--nodes 1000] [--edits 10] [--seed 0]

The motion graph of ``search_speed.py``: ``--nodes`` textons of 8-30 frames, every edge
weighed at random and pruned at mu = 0.9 (about 45 % of all pairs kept). Each edit has ten
random key motions and asks every leg to last 60 s (600 frames at 10 fps, 1,800 at 30 fps).
Prints, per frame rate, the time to compose the whole edit (plans of nine legs and the frame
schedule): the first edit on a fresh graph, which also builds the search indexes, and the
median of ``--edits`` more; and how many legs came within a frame of 60 s.
"""

import argparse
import time
import warnings

import numpy as np

from tvmedit.engine.graph.compose import compose
from tvmedit.engine.graph.timing import Timing, miss
from search_speed import dense_motion_graph, time_ms

LIMIT_S = 0.5


def edit(graph, keys, fps, seconds):
    keys, timing = Timing.request(graph, keys, fps, durations=[seconds] * (len(keys) - 1))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return compose(graph, keys, timing=timing)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--nodes", type=int, default=1000)
    parser.add_argument("--edits", type=int, default=10)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    for fps in (10, 30):
        graph = dense_motion_graph(args.nodes, 0.9, rng)
        keys = iter(rng.choice(args.nodes, 10, replace=False).tolist() for _ in range(args.edits + 1))
        c0, t0 = time.process_time(), time.perf_counter()
        first = edit(graph, next(keys), fps, 60)
        cold_cpu, cold_wall = time.process_time() - c0, time.perf_counter() - t0
        made = [first]
        wall, cpu = time_ms(lambda: made.append(edit(graph, next(keys), fps, 60)), args.edits)
        legs = [leg for e in made for leg in e.legs]
        hit = sum(not miss(leg.frames, leg.goal) for leg in legs)
        edges = np.mean([leg.edges for leg in legs])
        print(f"{fps} fps, {args.nodes} motions, {graph.number_of_edges():,} edges, 10 keys x 60 s legs:")
        print(f"  first edit (indexes built): {cold_wall:5.3f} s wall, {cold_cpu:5.3f} s CPU = "
              f"{cold_cpu / LIMIT_S:.2f} x the {LIMIT_S:g} s limit")
        print(f"  median of {args.edits} more:      {wall / 1e3:5.3f} s wall, {cpu / 1e3:5.3f} s CPU = "
              f"{cpu / 1e3 / LIMIT_S:.2f} x the limit")
        print(f"  legs within a frame of 60 s: {hit} of {len(legs)}; {edges:.1f} transitions a leg on average")


if __name__ == "__main__":
    main()
