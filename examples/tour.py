"""A tour that visits every motion of the database, exported as a new TVM sequence in tour/.

    python examples/tour.py [LIB]

From each possible first motion the tour always goes on to the unvisited motion that the
cheapest best path reaches (eq. 15); the start that visits the most motions wins. Motions
that cannot be reached at the library's mu are reported.
"""

import sys

from tvmedit import Library, NoPath
from tvmedit.engine.graph.export import export_edit
from tvmedit.engine.graph.search import best_path, path_cost
from tvmedit.demo import demo_library

lib = Library.open(sys.argv[1] if len(sys.argv) > 1 else demo_library())
graph = lib.graph


def greedy_tour(start):
    tour, left = [start], set(graph.nodes) - {start}
    while left:
        reachable = []
        for target in sorted(left):
            try:
                reachable.append((path_cost(graph, best_path(graph, tour[-1], target)), target))
            except NoPath:
                pass
        if not reachable:
            break
        tour.append(min(reachable)[1])
        left.discard(tour[-1])
    return tour


tour = max((greedy_tour(start) for start in sorted(graph.nodes)), key=len)
if len(tour) < 2:
    sys.exit(f"no transitions at mu = {lib.mu}: rebuild the library with a larger --mu")
edit = lib.edit(tour)
print("tour:", " -> ".join(graph.nodes[n]["name"] for n in tour))
missing = sorted(set(graph.nodes) - set(tour))
if missing:
    print("not reachable on this tour:", ", ".join(graph.nodes[n]["name"] for n in missing))
record = export_edit(edit, "tour", force=True)
print(f"exported {len(record['frames'])} frames with {len(record['transitions'])} transitions to tour/")
