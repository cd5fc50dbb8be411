"""Best path between two key motions: minimax cost, eq. (15), fewest edges, eq. (16).

The cost of a path is its largest edge weight, eq. (15), because one rough transition spoils
a path however smooth the others are. Among the paths of least cost the best one has the
fewest edges, eq. (16). Forbidden motions (section 8) are motions no path may pass through:
every edge into them counts as infinitely heavy.

The paper solves eq. (16) with a modified Dijkstra, Algorithm 1. As printed it is not exact:
it keeps, for each node, the cheapest prefix and only among equally cheap prefixes the
shortest, so a prefix that is cheaper but longer wins over one that is costlier but shorter,
even when a heavier edge later on makes both cost the same. On the graph below the path
0 -> 1 -> 2 -> 3 and the path 0 -> 2 -> 3 both cost 2, yet Algorithm 1 settles node 2 through
node 1 at cost 1 and returns the three-edge path:

>>> import networkx as nx
>>> g = nx.DiGraph()
>>> g.add_weighted_edges_from([(0, 1, 1.0), (1, 2, 1.0), (0, 2, 2.0), (2, 3, 2.0)])
>>> best_path(g, 0, 3, method="paper")
[0, 1, 2, 3]
>>> best_path(g, 0, 3)
[0, 2, 3]

The exact method therefore splits the problem in two: a minimax Dijkstra finds the least
cost C*, then a breadth-first search over the edges of weight <= C* finds the fewest edges.
Both run on a dense weight matrix (:class:`SearchIndex`), so that the realtime player can
search while a frame plays (``benchmarks/search_speed.py`` times it).
"""

import heapq
import math
import weakref

import numpy as np

from ..errors import LibraryError, NoPath, UnknownMotion

__all__ = ["SearchIndex", "best_path", "path_cost", "minimum_mu", "motion_label"]

# One index per graph object, rebuilt when the node or edge count or the weight key changes.
_INDEXES = weakref.WeakKeyDictionary()


def motion_label(graph, node):
    """A motion as a user knows it: its ``name`` attribute, else its id.

    >>> import networkx as nx
    >>> g = nx.DiGraph()
    >>> g.add_node(0, name="gym/03")
    >>> g.add_node(1)
    >>> motion_label(g, 0), motion_label(g, 1)
    ("'gym/03'", '1')
    """
    name = graph.nodes[node].get("name") if node in graph else None
    return repr(name) if name is not None else str(node)


def _check_node(graph, node, role):
    """Refuse a ``node`` that is not in ``graph``, naming the motions it knows."""
    if node not in graph:
        names = {n: graph.nodes[n].get("name", n) for n in graph.nodes}
        raise UnknownMotion.among(node, names, role)


class SearchIndex:
    """The motion graph as a dense weight matrix, for searches in vectorised numpy.

    Parameters
    ----------
    nodes : list
        Node ids in row order (sorted where the ids are comparable, so that ties go to the
        smallest ids).
    weights : (len(nodes), len(nodes)) float64
        ``weights[a, b]`` is the weight of the edge from ``nodes[a]`` to ``nodes[b]``;
        ``inf`` where there is no edge and on the diagonal, eq. (12).

    Build one with :meth:`of`, which caches it on the graph object. The cache notices added
    or removed nodes and edges, not weights changed in place: after such an edit, pass
    ``index=SearchIndex.from_graph(graph)`` to the search.

    >>> import networkx as nx
    >>> g = nx.DiGraph()
    >>> g.add_weighted_edges_from([(0, 1, 0.5), (1, 0, 0.25)])
    >>> SearchIndex.of(g).weights
    array([[ inf, 0.5 ],
           [0.25,  inf]])
    """

    def __init__(self, nodes, weights):
        self.nodes = list(nodes)
        self.weights = np.asarray(weights, dtype=np.float64)
        self.row = {node: i for i, node in enumerate(self.nodes)}
        if self.weights.shape != (len(self.nodes), len(self.nodes)):
            raise ValueError(f"'weights' should be a {len(self.nodes)}x{len(self.nodes)} matrix, "
                             f"got shape {self.weights.shape}")
        # Any path costs at least its first and its last edge: a floor for eq. (15).
        self.least_out = self.weights.min(axis=1, initial=np.inf)
        self.least_in = self.weights.min(axis=0, initial=np.inf)

    @classmethod
    def from_graph(cls, graph, weight="weight"):
        """Index of ``graph`` with edge attribute ``weight`` as the cost; not cached."""
        try:
            nodes = sorted(graph.nodes)
        except TypeError:
            nodes = list(graph.nodes)
        row = {node: i for i, node in enumerate(nodes)}
        n = len(nodes)
        weights = np.full((n, n), np.inf)
        sources, targets, values = [], [], []
        for u, neighbours in graph.adjacency():
            i = row[u]
            for v, data in neighbours.items():
                sources.append(i)
                targets.append(row[v])
                values.append(data.get(weight, 1.0))
        values = np.asarray(values, dtype=np.float64)
        if np.isnan(values).any():
            k = int(np.flatnonzero(np.isnan(values))[0])
            raise LibraryError(f"Edge {nodes[sources[k]]} -> {nodes[targets[k]]} of the motion "
                               f"graph has weight NaN; rebuild the library.")
        weights[sources, targets] = values
        # A self-loop never shortens a path; eq. (12) sets its weight to infinity.
        np.fill_diagonal(weights, np.inf)
        return cls(nodes, weights)

    @classmethod
    def of(cls, graph, weight="weight"):
        """The cached index of ``graph``, built on first use."""
        key = (graph.number_of_nodes(), graph.number_of_edges(), weight)
        cached = _INDEXES.get(graph)
        if cached is None or cached[0] != key:
            cached = (key, cls.from_graph(graph, weight))
            _INDEXES[graph] = cached
        return cached[1]

    def blocked(self, forbidden):
        """Boolean mask of the rows of the ``forbidden`` node ids."""
        mask = np.zeros(len(self.nodes), dtype=bool)
        mask[[self.row[node] for node in forbidden]] = True
        return mask

    def bottleneck(self, s, t, blocked=None):
        """Least cost, eq. (15), of a path from row ``s`` to row ``t``; ``inf`` if none.

        A minimax Dijkstra over the dense matrix. Once the cheapest open node costs c, every
        open node of cost c is settled in the same numpy sweep (ties and the nodes reached
        through edges of weight <= c), so the Python loop runs once per level and breadth-first
        layer, not once per node. A settled node keeps its final cost, which is <= every later
        level, so relaxing all columns never lowers it; an ``inf`` mask keeps it out of
        Extract-Min. Levels below the floor, the larger of the cheapest edge out of ``s`` and
        the cheapest edge into ``t``, are raised to it: the answer is at least the floor, and a
        path through nodes settled at the floor instead of below costs no more than the
        answer. The cost of the empty path is ``-inf`` (0 in :func:`path_cost`).
        """
        if s == t:
            return -math.inf
        w = self.weights
        n = len(self.nodes)
        cost = np.full(n, np.inf)
        cost[s] = -np.inf
        closed = np.full(n, -np.inf) if blocked is None else np.where(blocked, np.inf, -np.inf)
        closed[s] = -np.inf
        open_cost = np.empty(n)
        reach = np.empty(n)
        floor = max(self.least_out[s], self.least_in[t])
        while True:
            np.maximum(cost, closed, out=open_cost)
            u = open_cost.argmin()
            level = max(open_cost[u], floor)
            if open_cost[u] == np.inf:
                return np.inf
            if open_cost[t] <= level:
                return float(level)
            new = (open_cost <= level).nonzero()[0]
            closed[new] = np.inf
            np.maximum(w[u] if new.size == 1 else w[new].min(axis=0), level, out=reach)
            np.minimum(cost, reach, out=cost)

    def fewest_edges(self, s, t, limit, blocked=None):
        """Rows of a fewest-edge path from ``s`` to ``t`` using edges of weight <= ``limit``.

        Breadth-first by layers, stopping at the first layer with an edge into ``t``. Walking
        back, each node takes the smallest row of the previous layer with an edge into it, so
        among equally short paths the one whose rows, read backwards from ``t``, are smallest
        wins. Returns None when ``t`` cannot be reached.
        """
        w = self.weights
        seen = np.zeros(len(self.nodes), dtype=bool) if blocked is None else blocked.copy()
        if seen[t]:
            return None
        seen[s] = True
        layers = [np.array([s])]
        while not (w[layers[-1], t] <= limit).any():
            reached = (w[layers[-1]] <= limit).any(axis=0) & ~seen
            if not reached.any():
                return None
            seen |= reached
            layers.append(reached.nonzero()[0])
        rows = [t]
        for layer in reversed(layers):
            # argmax finds the first True: the smallest row of the layer with an edge onward.
            rows.append(int(layer[(w[layer, rows[-1]] <= limit).argmax()]))
        return rows[::-1]

    def paper(self, s, t, blocked=None):
        """Rows of the path that Algorithm 1 returns, as printed; None when ``d[t]`` is inf.

        Extract-Min breaks ties by the smallest row. Edges into blocked rows weigh infinity,
        as in section 8; such an edge can only touch nodes of infinite cost, so it is skipped.
        """
        n = len(self.nodes)
        w = self.weights
        d = [math.inf] * n                                        # (2)-(4)
        previous = [None] * n
        length = [math.inf] * n                                   # undefined until set
        d[s] = 0.0                                                # (5)
        length[s] = 0                                             # (6)
        in_q = [True] * n                                         # (7)-(8)
        queue = [(d[v], v) for v in range(n)]
        heapq.heapify(queue)
        while queue:                                              # (9)
            du, u = heapq.heappop(queue)                          # (10)
            if not in_q[u] or du != d[u]:
                continue
            in_q[u] = False                                       # (11)
            row = w[u]
            targets = np.flatnonzero(np.isfinite(row))
            if blocked is not None:
                targets = targets[~blocked[targets]]
            for v in targets.tolist():                            # (12)
                c = max(d[u], float(row[v]))
                if c < d[v]:                                      # (13)
                    d[v] = c                                      # (14)
                    length[v] = length[u] + 1                     # (15)
                    previous[v] = u                               # (16)
                    heapq.heappush(queue, (c, v))
                elif c == d[v]:                                   # (17)
                    if length[u] + 1 < length[v]:                 # (18)
                        length[v] = length[u] + 1                 # (19)
                        previous[v] = u                           # (20)
        if d[t] == math.inf:
            return None
        rows = [t]
        while rows[-1] != s:
            rows.append(previous[rows[-1]])
        return rows[::-1]


def path_cost(graph, path, weight="weight"):
    """Cost of a path, eq. (15): its largest edge weight; 0 for a single motion.

    >>> import networkx as nx
    >>> g = nx.DiGraph()
    >>> g.add_weighted_edges_from([(0, 1, 0.2), (1, 2, 0.7)])
    >>> path_cost(g, [0, 1, 2]), path_cost(g, [1])
    (0.7, 0.0)
    """
    return max((float(graph.edges[u, v][weight]) for u, v in zip(path, path[1:])), default=0.0)


def _threshold_ratios(graph, index):
    """Each unpruned edge's w(i, j) over the mean weight of i's edges, eq. (13)-(14).

    Edge i -> j survives pruning at mu iff its ratio < mu, so the least mu that connects two
    motions is just above the minimax ratio of a path between them.
    """
    unpruned = graph.graph["unpruned"]
    n = len(index.nodes)
    ratios = np.full((n, n), np.inf)
    if not unpruned:
        return ratios
    pairs = [(index.row[i], index.row[j]) for i, j in unpruned if i in index.row and j in index.row]
    values = np.fromiter((w for (i, j), w in unpruned.items() if i in index.row and j in index.row),
                         dtype=np.float64, count=len(pairs))
    if not pairs:
        return ratios
    rows, cols = np.array(pairs).T
    total = np.bincount(rows, weights=values, minlength=n)
    count = np.bincount(rows, minlength=n)
    with np.errstate(divide="ignore", invalid="ignore"):
        mean = total / count
        ratio = values / mean[rows]
    # A node whose mean weight is 0 keeps no edge at any mu (w < mu * 0 never holds).
    ratio[~np.isfinite(ratio) | ~(mean[rows] > 0)] = np.inf
    ratios[rows, cols] = ratio
    np.fill_diagonal(ratios, np.inf)
    return ratios


def minimum_mu(graph, source, target, forbidden=()):
    """Smallest round mu at which pruning, eq. (14), keeps a path from source to target.

    Uses ``graph.graph["unpruned"]``, the weights of all edges before pruning. The value is
    rounded up to two decimals and stays strictly above the path's worst threshold ratio,
    since eq. (14) prunes an edge whose weight equals mu times the mean. Returns ``inf``
    when no mu connects them (a forbidden motion blocks every route) and None when the
    graph does not carry its unpruned weights.

    >>> import networkx as nx
    >>> g = nx.DiGraph(unpruned={(0, 1): 1.0, (0, 2): 3.0, (1, 0): 1.0, (1, 2): 1.0,
    ...                          (2, 0): 1.0, (2, 1): 1.0}, mu=0.9)
    >>> g.add_nodes_from([0, 1, 2])
    >>> minimum_mu(g, 0, 2)  # 0 -> 1 has ratio 0.5 and 1 -> 2 ratio 1: mu must exceed 1
    1.01
    """
    if "unpruned" not in graph.graph:
        return None
    if source == target:
        return 0.0  # the empty path: the motion simply continues, at any mu
    nodes = SearchIndex.of(graph)
    index = SearchIndex(nodes.nodes, _threshold_ratios(graph, nodes))
    blocked = index.blocked(forbidden)
    if blocked[index.row[source]] or blocked[index.row[target]]:
        return math.inf
    ratio = index.bottleneck(index.row[source], index.row[target], blocked)
    if ratio == math.inf:
        return math.inf
    mu = math.ceil(max(ratio, 0.0) * 100) / 100
    if mu <= ratio * (1 + 1e-9):
        mu = round(mu + 0.01, 2)
    return mu


def _no_path(graph, source, target, forbidden):
    """The :class:`NoPath` error for ``source`` to ``target``, with the mu it was pruned at."""
    a, b = motion_label(graph, source), motion_label(graph, target)
    held = graph.graph.get("mu")
    at = f" pruned at mu = {held:g}" if held is not None else ""
    for node in (source, target):
        if node in forbidden:
            return NoPath(f"No path leads from motion {a} to {b} because {motion_label(graph, node)} "
                          f"is itself forbidden; allow it or choose another key motion.",
                          source=source, target=target, mu=math.inf)
    if forbidden and _reaches(graph, source, target):
        names = ", ".join(motion_label(graph, node) for node in sorted(forbidden))
        which = "it" if len(forbidden) == 1 else "one of them"
        return NoPath(f"No path leads from motion {a} to {b} without the forbidden motion"
                      f"{'s' if len(forbidden) > 1 else ''} {names}; allow {which} or choose another key motion.",
                      source=source, target=target, mu=math.inf)
    mu = minimum_mu(graph, source, target, forbidden)
    if mu is None:
        message = (f"No path leads from motion {a} to {b} in the motion graph{at}; "
                   f"rebuild with a larger mu or choose another key motion.")
    elif mu == math.inf:
        reason = " because the forbidden motions block every route" if forbidden else ""
        message = (f"No path leads from motion {a} to {b} at any mu{reason}; "
                   f"choose another key motion{' or allow more motions' if forbidden else ''}.")
    else:
        message = (f"No path leads from motion {a} to {b} in the motion graph{at}, but a path "
                   f"exists from mu = {mu:g}: rebuild with mu={mu:g} or choose another key motion.")
    return NoPath(message, source=source, target=target, mu=mu)


def _reaches(graph, source, target):
    """Whether the graph as it stands, nothing forbidden, leads from source to target."""
    index = SearchIndex.of(graph)
    return index.bottleneck(index.row[source], index.row[target], None) < np.inf


def best_path(graph, source, target, weight="weight", forbidden=(), method="exact", index=None):
    """Best path from one key motion to the next, eq. (15)-(16).

    Parameters
    ----------
    graph : networkx.DiGraph
        The pruned motion graph, eq. (12)-(14).
    source, target : node ids
        The two key motions. Equal ids give ``[source]``: the motion simply continues.
    weight : str
        Edge attribute holding the transition cost w(T_i, T_j), eq. (12).
    forbidden : iterable of node ids
        Motions the path may not visit (section 8).
    method : {"exact", "paper"}
        ``"exact"``: least cost, then fewest edges, ties to the path whose nodes read
        backwards from the target have the smallest ids. ``"paper"``: Algorithm 1 as printed,
        which may return more edges than needed (see the module docstring).
    index : SearchIndex, optional
        A prebuilt index of ``graph``; by default one is built and cached on the graph.

    Returns
    -------
    list of node ids, from ``source`` to ``target``.

    Raises
    ------
    NoPath
        When no path avoids the forbidden motions; its message names the smallest mu that
        would connect the two motions, from ``graph.graph["unpruned"]``.
    UnknownMotion
        When a motion is not in the graph.

    Examples
    --------
    One rough transition costs more than several smooth ones:

    >>> import networkx as nx
    >>> g = nx.DiGraph()
    >>> g.add_weighted_edges_from([(0, 3, 0.9), (0, 1, 0.2), (1, 2, 0.3), (2, 3, 0.2)])
    >>> best_path(g, 0, 3)
    [0, 1, 2, 3]
    >>> best_path(g, 0, 3, forbidden=[2])
    [0, 3]
    """
    for node, role in ((source, "source"), (target, "target")):
        _check_node(graph, node, role)
    forbidden = set(forbidden)
    for node in forbidden:
        _check_node(graph, node, "forbidden")
    if source in forbidden or target in forbidden:
        raise _no_path(graph, source, target, forbidden)
    if source == target:
        return [source]
    index = SearchIndex.of(graph, weight) if index is None else index
    s, t = index.row[source], index.row[target]
    blocked = index.blocked(forbidden) if forbidden else None
    if method == "exact":
        limit = index.bottleneck(s, t, blocked)
        rows = index.fewest_edges(s, t, limit, blocked) if limit < np.inf else None
    elif method == "paper":
        rows = index.paper(s, t, blocked)
    else:
        raise ValueError(f"method should be 'exact' or 'paper', got {method!r}")
    if rows is None:
        raise _no_path(graph, source, target, forbidden)
    return [index.nodes[r] for r in rows]
