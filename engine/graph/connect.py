"""Connectivity: the pruned motion graph made strongly connected at the least transition cost.

Eq. (14) prunes each motion's edges against the mean weight of its own edges. Nothing in it
keeps a way out of, or into, every motion: a motion can become a sink (every key pressed
there is refused) or a source (nothing ever reaches it), and the paper lists "key motion
unreachable" as a problem left to the user. Motion-graph practice since Kovar et al. (2002)
keeps the graph strongly connected instead. :func:`connect` adds back edges of the complete
graph (eq. (12) weights, eq. (10) transition frames) until every motion reaches every other,
chosen by two criteria in turn.

1. **Least largest added weight (exact).** Let P be the pruned edges, C the complete graph's
   edges and, for a threshold t, ``G_t = P + {e in C - P : w(e) <= t}``. Let t* be the least
   weight of an edge of C - P for which G_t* is strongly connected, found by binary search
   over the sorted candidate weights.

   *Claim: no strongly connected graph H with P <= H <= C has a largest added weight below
   t*, and the edges chosen here have largest weight exactly t*.*

   *Proof.* Adding edges never breaks strong connectivity, and G_t grows with t, so
   "G_t is strongly connected" is monotone in t and the binary search finds the least such
   candidate weight. Let H be strongly connected with P <= H <= C and let m be the largest
   weight of its added edges H - P (m is the weight of an edge of C - P). Every added edge
   of H has weight <= m, so H <= G_m, and G_m, a supergraph of a strongly connected graph
   on the same nodes, is strongly connected; by the minimality of t*, m >= t*. The edges
   chosen below all have weight <= t*, so their largest weight is at most t*; by the claim
   just proved for H = P + chosen edges, it is at least t*: it is t*. (When P is already
   strongly connected, nothing is added.)

2. **Fewest added edges.** Among edges of weight <= t*, as few as possible are added. The
   pruned graph is condensed into its strongly connected components; a set of component
   pairs makes it strongly connected or not whatever edge realises each pair, so each pair
   is realised by its lightest edge (ties by the smaller (i, j)), and the search runs over
   pairs. Any answer needs at least ``max(sources, sinks)`` edges of the condensation
   (Eswaran and Tarjan 1976: each source needs an edge in, each sink an edge out); sets of
   that size and up are enumerated, smallest total weight first among the fewest, as long as
   at most :data:`EXACT_BUDGET` sets are tried. Beyond that the answer is the greedy one
   (rounds of Eswaran and Tarjan's pairing of sinks with sources, lightest edge first), marked
   ``fewest=False`` unless it meets the lower bound. The least threshold holds either way.

Everything runs on dense (N, N) arrays with scipy's strongly connected components, so that
large graphs connect quickly (``benchmarks/connect_speed.py`` times it); a graph already
connected is told so without loading scipy (:func:`connected_without_scipy`), and a library
opened at its own mu reads back the connection its build stored
(:func:`tvmedit.engine.graph.motiongraph.graph_from`).
"""

import itertools
import math
from dataclasses import dataclass, field

import numpy as np

#: Values of ``build(connect=...)`` and ``tvmedit build --connect``.
MODES = ("auto", "off")

#: Sets of component pairs the exact fewest-edges search may try before it settles for greedy.
EXACT_BUDGET = 20_000


@dataclass
class Connection:
    """The edges :func:`connect` adds, and why.

    Attributes
    ----------
    added : list of (int, int)
        Edges of the complete graph added to the pruned one, sorted.
    largest : float or None
        Their largest weight t* (None when none was needed).
    fewest : bool
        True when ``added`` is proven as small as possible (exact search), False when the
        search ran past :data:`EXACT_BUDGET` and the greedy set was kept.
    components : int
        Strongly connected components of the pruned graph before connecting.
    """

    added: list = field(default_factory=list)
    largest: float | None = None
    fewest: bool = True
    components: int = 1

    def summary(self, mode="auto"):
        """JSON-ready summary for ``info`` and the library (mode, count, largest weight, why)."""
        return {"mode": mode, "added": len(self.added), "largest_weight": self.largest,
                "fewest": self.fewest, "components_before": self.components,
                "reason": self.reason(mode)}

    def reason(self, mode="auto"):
        """One sentence for ``info``: why edges were added, or why none were."""
        if mode == "off":
            return "the graph is the paper's, pruned by eq. (14) alone"
        if not self.added:
            return "the pruned graph already leads from every motion to every other"
        return (f"the pruned graph fell into {self.components} parts; {len(self.added)} edge"
                f"{'s' if len(self.added) != 1 else ''} of the complete graph, the largest of weight "
                f"{self.largest:.4g} (the least possible), join them so every motion reaches every other")


def strongly_connected(adjacency):
    """Whether the directed graph of a boolean (N, N) adjacency matrix is strongly connected.

    >>> strongly_connected(np.array([[0, 1], [1, 0]], bool)), strongly_connected(np.array([[0, 1], [0, 0]], bool))
    (True, False)
    """
    return len(adjacency) < 2 or _components(adjacency)[0] == 1


def connected_without_scipy(adjacency):
    """:func:`strongly_connected`, breadth first from the first node both ways, a numpy pass a
    level: for a graph asked once, where importing scipy would cost more than the search
    (0.37 s, a third of a command's start). Slower than scipy's on a graph of a thousand
    motions asked many times (:func:`connect`'s search).

    >>> ring, chain = np.array([[0, 1], [1, 0]], bool), np.array([[0, 1], [0, 0]], bool)
    >>> connected_without_scipy(ring), connected_without_scipy(chain)
    (True, False)
    """
    adjacency = np.asarray(adjacency, dtype=bool)
    return len(adjacency) < 2 or (_reaches_all(adjacency) and _reaches_all(adjacency.T))


def _reaches_all(adjacency):
    """Whether the first node reaches every node of a boolean (N, N) adjacency."""
    seen = np.zeros(len(adjacency), dtype=bool)
    seen[0] = True
    frontier = seen.copy()
    while frontier.any():
        frontier = adjacency[frontier].any(axis=0) & ~seen
        seen |= frontier
    return bool(seen.all())


def connect(weights, kept):
    """Edges to add to a pruned graph so that it becomes strongly connected (module docstring).

    Parameters
    ----------
    weights : (N, N) array_like of float
        Complete-graph weights, eq. (12); the diagonal and non-finite entries are never added.
    kept : (N, N) array_like of bool
        The edges that survived pruning, eq. (14).

    Returns
    -------
    Connection

    Raises
    ------
    ValueError
        When even the complete graph (its finite edges) is not strongly connected.

    Examples
    --------
    Motion 2 is a sink: the lightest way out of it is added, not the heavier one.

    >>> w = np.array([[np.inf, 1.0, 5.0], [1.0, np.inf, 1.0], [4.0, 3.0, np.inf]])
    >>> kept = np.array([[0, 1, 0], [1, 0, 1], [0, 0, 0]], bool)
    >>> c = connect(w, kept)
    >>> c.added, c.largest, c.fewest
    ([(2, 1)], 3.0, True)
    """
    w = np.array(weights, dtype=np.float64)
    kept = np.array(kept, dtype=bool)
    n = len(w)
    if w.shape != (n, n) or kept.shape != (n, n):
        raise ValueError(f"weights {w.shape} and kept {kept.shape} must be one square shape")
    np.fill_diagonal(kept, False)
    if connected_without_scipy(kept):   # nothing to add, and scipy not loaded to say so
        return Connection(components=1)
    count, labels = _components(kept)
    # Work on the condensation: component-level kept edges and lightest candidate edges.
    between, best = _condense(w, kept, labels, count)
    threshold = _least_threshold(between, best)
    pairs = _pairs_up_to(between, best, threshold)
    chosen, fewest = _fewest(between, pairs, best, threshold)
    added = sorted(_realise(w, kept, labels, chosen))
    return Connection(added, float(max(w[i, j] for i, j in added)), fewest, count)


def _components(adjacency):
    """``(count, labels)``: the strongly connected components of a dense (N, N) adjacency."""
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import connected_components

    return connected_components(csr_matrix(adjacency), directed=True, connection="strong")


def _condense(w, kept, labels, count):
    """``between`` (k, k) bool: a kept edge joins the components; ``best`` (k, k): the lightest
    candidate (not kept, finite) weight from one component to another, inf where none."""
    between = np.zeros((count, count), bool)
    rows, cols = np.nonzero(kept)
    between[labels[rows], labels[cols]] = True
    candidate = np.where(kept | ~np.isfinite(w), np.inf, w)
    np.fill_diagonal(candidate, np.inf)
    order = np.argsort(labels, kind="stable")
    starts = np.searchsorted(labels[order], np.arange(count))
    rows = np.minimum.reduceat(candidate[order], starts, axis=0)
    best = np.minimum.reduceat(rows[:, order], starts, axis=1)
    np.fill_diagonal(best, np.inf)
    np.fill_diagonal(between, False)
    return between, best


def _least_threshold(between, best):
    """The least candidate weight t* at which the condensation is strongly connected."""
    values = np.unique(best[np.isfinite(best)])
    if not len(values) or not strongly_connected(between | (best <= values[-1])):
        raise ValueError("even the complete motion graph is not strongly connected "
                         "(some transitions have no finite weight)")
    low, high = 0, len(values) - 1
    while low < high:
        middle = (low + high) // 2
        if strongly_connected(between | (best <= values[middle])):
            high = middle
        else:
            low = middle + 1
    return float(values[low])


def _pairs_up_to(between, best, threshold):
    """Candidate component pairs of weight <= t*, lightest first (ties by pair)."""
    a, b = np.nonzero((best <= threshold) & ~between)
    order = np.lexsort((b, a, best[a, b]))
    return [(int(a[k]), int(b[k])) for k in order]


def _fewest(between, pairs, best, threshold):
    """The fewest pairs that connect the condensation, exact within the budget."""
    greedy = _greedy(between, np.where(best <= threshold, best, np.inf))
    k = len(between)
    outgoing, incoming = between.any(axis=1), between.any(axis=0)
    sinks = [c for c in range(k) if not outgoing[c]]
    sources = [c for c in range(k) if not incoming[c]]
    lower = max(len(sinks), len(sources))
    if len(greedy) == lower or math.comb(len(pairs), lower) > EXACT_BUDGET:
        return greedy, len(greedy) == lower
    reach = [_bits(np.nonzero(between[c])[0]) for c in range(k)]
    tried = 0
    for size in range(lower, len(greedy)):
        found = None
        for subset in itertools.combinations(pairs, size):
            tried += 1
            if tried > EXACT_BUDGET:
                return greedy, False
            if not _covers(subset, sinks, sources):
                continue
            if _connected_with(reach, subset):
                cost = sum(best[p] for p in subset)
                if found is None or cost < found[0]:
                    found = (cost, list(subset))
        if found is not None:
            return found[1], True
    return greedy, True


def _greedy(between, allowed):
    """Rounds of Eswaran and Tarjan's pairing: in each round every sink of the condensation
    gets its lightest allowed edge to a source not yet taken in that round (else to any other
    part), then every source still without a way in gets its lightest allowed edge in; the
    condensation is then recomputed. A first round adds max(sources, sinks) edges, the lower
    bound; each round leaves fewer parts, so it ends. A round is a few numpy passes over
    (k, k) arrays."""
    adjacency = between.copy()
    chosen = []
    while True:
        count, labels = _components(adjacency)
        if count == 1:
            return chosen
        parts, lightest = _condense(allowed, adjacency, labels, count)
        sinks = np.nonzero(~parts.any(axis=1))[0]
        free = ~parts.any(axis=0)
        links = []
        for sink in sinks:
            row = lightest[sink]
            target = np.where(free, row, np.inf).argmin()
            if not np.isfinite(row[target]):
                target = row.argmin()
            free[target] = False
            links.append((sink, target))
        for source in np.nonzero(free)[0]:
            links.append((lightest[:, source].argmin(), source))
        for a, b in links:
            pair = _lightest_pair(allowed, adjacency, labels == a, labels == b)
            chosen.append(pair)
            adjacency[pair] = True


def _lightest_pair(w, adjacency, rows, cols):
    """The lightest ``(i, j)`` with i in ``rows`` and j in ``cols`` (boolean masks) not already
    in ``adjacency`` (ties by the smaller pair)."""
    rows, cols = np.nonzero(rows)[0], np.nonzero(cols)[0]
    block = np.where(adjacency[np.ix_(rows, cols)], np.inf, w[np.ix_(rows, cols)])
    r, c = np.unravel_index(np.argmin(block), block.shape)
    return int(rows[r]), int(cols[c])


def _covers(subset, sinks, sources):
    """Whether the component pairs ``subset`` give every sink an edge out and every source one in."""
    starts = {a for a, _ in subset}
    ends = {b for _, b in subset}
    return all(c in starts for c in sinks) and all(c in ends for c in sources)


def _bits(indices):
    """The integer bit set with the bits ``indices`` on.

    >>> bin(_bits([0, 2]))
    '0b101'
    """
    value = 0
    for i in indices:
        value |= 1 << int(i)
    return value


def _connected_with(reach, subset):
    """Whether the condensation plus ``subset`` is strongly connected (bit-set search)."""
    reach = list(reach)
    for a, b in subset:
        reach[a] |= 1 << b
    k = len(reach)
    everyone = (1 << k) - 1
    forward = _closure(reach, 0)
    if forward != everyone:
        return False
    back = [0] * k
    for a in range(k):
        bits = reach[a]
        while bits:
            low = bits & -bits
            back[low.bit_length() - 1] |= 1 << a
            bits ^= low
    return _closure(back, 0) == everyone


def _closure(reach, start):
    """Bit set of the nodes reachable from ``start`` where ``reach[a]`` is a's successors' bit set."""
    seen = 1 << start
    frontier = seen
    while frontier:
        step = 0
        bits = frontier
        while bits:
            low = bits & -bits
            step |= reach[low.bit_length() - 1]
            bits ^= low
        frontier = step & ~seen
        seen |= frontier
    return seen


def _realise(w, kept, labels, pairs):
    """Each component pair as its lightest candidate edge (ties by the smaller (i, j))."""
    return [_lightest_pair(w, kept, labels == a, labels == b) for a, b in pairs]
