"""Motion graph, section 6: node distance, transition frames, intensity, weights, pruning.

Every node is a representative texton of the database (eq. (9)). Between two nodes the
transition goes through the pair of frames that look most alike, eq. (10); its cost is that
frame distance divided by the motion intensity of the node being left, eq. (11)-(12),
because a jump is less visible in a fast motion than in a slow one. The complete graph is
then pruned node by node against the mean cost of leaving that node, eq. (13)-(14).

Direction. The node distance d_V and the transition frames are symmetric: leaving i at
frame t_i* for j at frame t_j* is the same pair of frames as leaving j at t_j* for i at
t_i*. They are computed once per unordered pair, so ties in the argmin cannot pick
different frames for the two directions. The weight is not symmetric: eq. (12) divides by
the intensity of the *source* node, so w(i, j) != w(j, i) whenever the two intensities
differ, and pruning, which compares a weight with the mean over the source's edges, may
keep one direction and drop the other.

A frozen texton (all frames alike) has intensity 0 and eq. (12) would divide by zero. The
intensity is floored at :data:`MIN_INTENSITY` in the weight only (the node attribute keeps
the measured value). Leaving such a node then costs d_V / MIN_INTENSITY: finite, so paths
out of it still compare by their size, and huge, which is what eq. (12) says about a jump
out of a motion with no movement to hide it. A one-frame texton has no neighbouring frames
and counts as frozen.

One-shot motions (``Node.kind == "once"``, see :mod:`tvmedit.engine.graph.database`) are played through
once, not cyclically, so eq. (10) is restricted for them: a one-shot is entered only at its
first frame and left only from a frame of its last part (the last :data:`EXIT_SHARE` of its
frames). Their d_V and transition frames therefore differ by direction; between two cycles
they stay symmetric. They are otherwise ordinary nodes: weighted, pruned and searched alike.

Pruning is applied exactly as eq. (14) says: an edge goes when w >= mu * mean. When all
edges leaving a node weigh the same (always so in a two-node database) none of them is
below mu * mean for mu <= 1, and that node has no way out; the unpruned weights kept in
``G.graph["unpruned"]`` let a caller explain such a dead end.

Such dead ends are the paper's graph. By default (``connect="auto"``) :func:`graph_from`
then adds back the fewest, lightest complete-graph edges that make every motion reach every
other (:mod:`tvmedit.engine.graph.connect`, which proves the choice optimal); those edges carry
``added=True`` and ``G.graph["connect"]`` says how many were added and why.
"""

import math
from dataclasses import asdict, replace

import networkx as nx
import numpy as np

from .database import ONCE, Node
from ..errors import TvmError, UnknownMotion
from ..features import distance_matrix

#: Default pruning parameter mu of eq. (14).
MU = 0.9

#: Intensity used in eq. (12) for textons whose measured intensity is below it.
MIN_INTENSITY = 1e-9

#: The last part of a one-shot motion it may be left from: this share of its frames (at least one).
EXIT_SHARE = 0.25


def exit_range(node):
    """``(first, last)`` frames a node may be left from, eq. (10): any frame of a cycle, the
    last :data:`EXIT_SHARE` of a one-shot.

    >>> exit_range(Node(0, "a/01", "a", 10, 29, 0, 0.0, kind="once"))
    (25, 29)
    """
    if node.kind == ONCE:
        return node.end - max(1, int(math.ceil(EXIT_SHARE * node.n_frames))) + 1, node.end
    return node.start, node.end


def entry_range(node):
    """``(first, last)`` frames a node may be entered at, eq. (10): any frame of a cycle, the
    first frame of a one-shot."""
    return (node.start, node.start) if node.kind == ONCE else (node.start, node.end)


def motion_intensity(vectors):
    """Motion intensity of a texton, eq. (11): mean distance between neighbouring frames.

    Parameters
    ----------
    vectors : (n, D) array_like
        Feature vectors of the texton's frames, in order.

    Returns
    -------
    float
        The mean over the n - 1 neighbouring pairs; 0.0 for a single frame.

    Examples
    --------
    >>> motion_intensity([[0.0, 0.0], [3.0, 0.0], [3.0, 1.0]])
    2.0
    """
    v = np.asarray(vectors, dtype=np.float64)
    if len(v) < 2:
        return 0.0
    return float(np.linalg.norm(np.diff(v, axis=0), axis=1).mean())


def edge_weights(distances, intensities):
    """Edge weights of the complete graph, eq. (12).

    Parameters
    ----------
    distances : (N, N) array_like
        Node distances d_V, eq. (10).
    intensities : (N,) array_like
        Motion intensities, eq. (11); values below :data:`MIN_INTENSITY` count as it.

    Returns
    -------
    (N, N) float64
        ``w[i, j] = d_V[i, j] / intensity[i]`` (the source's intensity), ``inf`` on the
        diagonal.

    Examples
    --------
    >>> edge_weights([[0.0, 2.0], [2.0, 0.0]], [1.0, 4.0]).tolist()
    [[inf, 2.0], [0.5, inf]]
    """
    d = np.asarray(distances, dtype=np.float64)
    floor = np.maximum(np.asarray(intensities, dtype=np.float64), MIN_INTENSITY)
    w = d / floor[:, None]
    np.fill_diagonal(w, np.inf)
    return w


def transitions(nodes, vectors_by_sequence):
    """Node distances and transition frames for every ordered pair of nodes, eq. (10).

    Parameters
    ----------
    nodes : list of Node
        The database; ``nodes[k].id`` must be ``k``.
    vectors_by_sequence : dict of str to (T, D) array
        Feature vectors of every sequence a node comes from; D must agree across sequences
        (pad the r histograms of a library alike, see ``Features.pad_r``).

    Returns
    -------
    distances : (N, N) float64
        d_V with a zero diagonal; symmetric between cycles (one-shots restrict eq. (10) to
        their exit and entry frames, :func:`exit_range`, :func:`entry_range`).
    frames : dict of (int, int) to (int, int)
        ``frames[i, j] = (exit, entry)`` for all i != j: ``exit`` is t_i*, a frame of
        node i's sequence, and ``entry`` is t_j*, a frame of node j's sequence, both
        absolute indices. Between two cycles ``frames[j, i]`` is the same pair swapped.
    intensities : (N,) float64
        Motion intensity of every node, eq. (11), as measured (not floored).

    Examples
    --------
    >>> nodes = [Node(0, "a/01", "a", 0, 1, 0, 0.0), Node(1, "a/02", "a", 3, 4, 1, 0.0)]
    >>> a = np.array([[0.0], [1.0], [9.0], [3.0], [5.0]])
    >>> d, frames, intensity = transitions(nodes, {"a": a})
    >>> float(d[0, 1]), frames[0, 1], frames[1, 0], intensity.tolist()
    (2.0, (1, 3), (3, 1), [1.0, 2.0])
    """
    blocks = [_frames_of(node, vectors_by_sequence) for node in nodes]
    n = len(nodes)
    if n == 0:
        return np.zeros((0, 0)), {}, np.zeros(0)
    widths = {block.shape[1] for block in blocks}
    if len(widths) > 1:
        raise ValueError(f"feature vectors of the sequences differ in length {sorted(widths)}; "
                         "pad the r histograms of a library to one width first")
    # One distance matrix over all node frames, cut into blocks, costs one BLAS call instead
    # of N^2 small ones; the database keeps one texton per cluster, so it stays small.
    offsets = np.cumsum([0] + [len(block) for block in blocks])
    d_all = distance_matrix(np.concatenate(blocks))
    distances = np.zeros((n, n))
    frames = {}
    intensities = np.zeros(n)
    for i in range(n):
        rows = slice(offsets[i], offsets[i + 1])
        # Differences taken directly, not from d_all: the |a|^2 + |b|^2 - 2ab form leaves
        # about 3e-8 of round-off near zero, which would hide a frozen texton.
        intensities[i] = motion_intensity(blocks[i])
        for j in range(i + 1, n):
            if nodes[i].kind == ONCE or nodes[j].kind == ONCE:
                for a, b in ((i, j), (j, i)):
                    distances[a, b], frames[a, b] = _restricted(d_all, offsets, nodes[a], nodes[b], a, b)
                continue
            block = d_all[rows, offsets[j]:offsets[j + 1]]
            t_i, t_j = np.unravel_index(np.argmin(block), block.shape)
            distances[i, j] = distances[j, i] = block[t_i, t_j]
            exit_i, entry_j = nodes[i].start + int(t_i), nodes[j].start + int(t_j)
            frames[i, j] = (exit_i, entry_j)
            frames[j, i] = (entry_j, exit_i)
    return distances, frames, intensities


def _restricted(d_all, offsets, source, target, a, b):
    """d_V and ``(exit, entry)`` from ``source`` (at position ``a``) to ``target`` (``b``) over
    the frames each may be left from and entered at, eq. (10)."""
    x0, x1 = exit_range(source)
    e0, e1 = entry_range(target)
    rows = slice(offsets[a] + x0 - source.start, offsets[a] + x1 - source.start + 1)
    cols = slice(offsets[b] + e0 - target.start, offsets[b] + e1 - target.start + 1)
    block = d_all[rows, cols]
    t_x, t_e = np.unravel_index(np.argmin(block), block.shape)
    return float(block[t_x, t_e]), (x0 + int(t_x), e0 + int(t_e))


def prune(unpruned, mu=MU):
    """Edges that survive pruning, eq. (13)-(14).

    For each source node i the mean weight is taken over its N - 1 edges to the other
    nodes (the infinite self-edge is not among them); edge (i, j) is pruned when
    ``w(i, j) >= mu * mean``.

    Parameters
    ----------
    unpruned : dict of (int, int) to float
        Weights of the complete graph, eq. (12), for all i != j.
    mu : float
        The parameter of eq. (14); larger keeps more edges.

    Returns
    -------
    set of (int, int)
        The kept edges.

    Examples
    --------
    >>> w = {(0, 1): 1.0, (0, 2): 3.0, (1, 0): 2.0, (1, 2): 2.0}
    >>> sorted(prune(w, mu=0.9))
    [(0, 1)]
    >>> sorted(prune(w, mu=2.0))
    [(0, 1), (0, 2), (1, 0), (1, 2)]
    """
    by_source = {}
    for (i, j), w in unpruned.items():
        by_source.setdefault(i, []).append(w)
    means = {i: sum(ws) / len(ws) for i, ws in by_source.items()}
    return {(i, j) for (i, j), w in unpruned.items() if w < mu * means[i]}


def graph_from(nodes, unpruned, transitions, mu=MU, connect="auto", connected=None):
    """The pruned motion graph from stored weights and transition frames, no features needed.

    Parameters
    ----------
    nodes : list of Node
        The database, intensities filled in.
    unpruned : dict of (int, int) to float
        Weights of the complete graph, eq. (12), for all i != j.
    transitions : dict of (int, int) to (int, int)
        ``(exit, entry)`` frames for all i != j, as returned by :func:`transitions`.
    mu : float
        The parameter of eq. (14).
    connect : {"auto", "off"}
        ``"auto"`` adds the complete-graph edges :func:`tvmedit.engine.graph.connect.connect` chooses, so
        that every motion reaches every other; ``"off"`` keeps the pruned graph as printed.
    connected : (dict, list of (int, int)), optional
        How a build connected this graph at this ``mu`` (``graph.json``'s ``connect`` summary
        and ``added`` edges): used as it is where it is of the same mode and its edges are
        edges of the complete graph that pruning dropped, else the connection is found anew.

    Returns
    -------
    networkx.DiGraph
        Nodes are ids with attributes ``name``, ``sequence``, ``start``, ``end``,
        ``cluster``, ``texton_distance``, ``intensity``; edges carry ``weight``,
        ``exit_frame`` (t_i*, in the source's sequence), ``entry_frame`` (t_j*, in the
        target's) and ``added`` (True for an edge put back to connect the graph).
        ``G.graph`` holds ``mu``, ``unpruned`` and ``transitions`` (copies), so the graph
        can be pruned again at another mu, and ``connect``, the summary of
        :meth:`tvmedit.engine.graph.connect.Connection.summary`.

    Examples
    --------
    >>> nodes = [Node(0, "a/01", "a", 0, 1, 0, 0.0, 1.0), Node(1, "a/02", "a", 3, 4, 1, 0.0, 2.0)]
    >>> G = graph_from(nodes, {(0, 1): 2.0, (1, 0): 1.0}, {(0, 1): (1, 3), (1, 0): (3, 1)}, mu=1.5)
    >>> G.edges[0, 1]
    {'weight': 2.0, 'exit_frame': 1, 'entry_frame': 3, 'added': False}
    >>> G.graph["mu"], G.nodes[1]["name"]
    (1.5, 'a/02')
    """
    from . import connect as connection

    if connect not in connection.MODES:
        raise ValueError(f"connect should be one of {', '.join(connection.MODES)}, not {connect!r}")
    G = nx.DiGraph(mu=mu, unpruned=dict(unpruned), transitions=dict(transitions))
    for node in nodes:
        attributes = asdict(node)
        G.add_node(attributes.pop("id"), **attributes)
    kept = sorted(prune(unpruned, mu))
    found = connection.Connection()
    if connect == "auto":
        found = (_stored(connected, unpruned, set(kept), G.number_of_nodes())
                 or connection.connect(*_dense(G, unpruned, kept)))
    for (i, j), added in [*((edge, False) for edge in kept), *((edge, True) for edge in found.added)]:
        exit_frame, entry_frame = transitions[i, j]
        G.add_edge(i, j, weight=unpruned[i, j], exit_frame=exit_frame, entry_frame=entry_frame, added=added)
    G.graph["connect"] = found.summary(connect)
    return G


def _stored(connected, unpruned, kept, n):
    """The :class:`tvmedit.engine.graph.connect.Connection` a build stored (``connected``, see
    :func:`graph_from`) for this graph of ``n`` motions pruned to ``kept``, or None where there
    is none or it does not fit: its edges not ones pruning dropped, its largest weight not
    theirs, or the graph not connected with them."""
    from .connect import Connection, connected_without_scipy

    if connected is None:
        return None
    summary, added = connected
    try:
        added = sorted((int(i), int(j)) for i, j in added)
        found = Connection(added, summary["largest_weight"], bool(summary["fewest"]), int(summary["components_before"]))
    except (KeyError, TypeError, ValueError):
        return None
    fits = (summary.get("mode") == "auto" and summary.get("added") == len(added)
            and all(edge in unpruned and edge not in kept for edge in added)
            and found.largest == (max(unpruned[edge] for edge in added) if added else None))
    if not fits:
        return None
    joined = np.zeros((n, n), dtype=bool)
    for i, j in [*kept, *added]:
        joined[i, j] = True
    return found if connected_without_scipy(joined) else None


def _dense(G, unpruned, kept):
    """``(weights, kept)`` as (N, N) arrays over the graph's nodes in id order (ids 0..N-1)."""
    n = G.number_of_nodes()
    weights = np.full((n, n), np.inf)
    for (i, j), w in unpruned.items():
        weights[i, j] = w
    mask = np.zeros((n, n), bool)
    for i, j in kept:
        mask[i, j] = True
    return weights, mask


def build_graph(nodes, vectors_by_sequence, mu=MU, connect="auto"):
    """The motion graph of a database, section 6: eq. (10)-(14) in one call.

    Parameters
    ----------
    nodes : list of Node
        The database from ``build_database``; ``nodes[k].id`` must be ``k``. The nodes are
        not changed; the graph's nodes carry the measured intensity (get them back as
        ``Node`` objects with :func:`nodes_of`).
    vectors_by_sequence : dict of str to (T, D) array
        Feature vectors of every sequence, rows indexed by frame.
    mu : float
        The parameter of eq. (14).
    connect : {"auto", "off"}
        Whether to make the pruned graph strongly connected, see :func:`graph_from`.

    Returns
    -------
    networkx.DiGraph
        As described in :func:`graph_from`.

    Examples
    --------
    >>> nodes = [Node(0, "a/01", "a", 0, 1, 0, 0.0), Node(1, "a/02", "a", 2, 3, 1, 0.0),
    ...          Node(2, "a/03", "a", 4, 5, 2, 0.0)]
    >>> a = np.array([[0.0], [1.0], [3.0], [5.0], [9.0], [10.0]])
    >>> G = build_graph(nodes, {"a": a}, connect="off")
    >>> sorted(G.edges)
    [(0, 1), (1, 0), (2, 1)]
    >>> sorted(build_graph(nodes, {"a": a}).edges)  # motion 2 was a source: one edge in is added
    [(0, 1), (1, 0), (1, 2), (2, 1)]
    >>> G.edges[2, 1]["exit_frame"], G.edges[2, 1]["entry_frame"]
    (4, 3)
    """
    for k, node in enumerate(nodes):
        if node.id != k:
            raise ValueError(f"node ids must be 0, 1, ... in order; node {node.name!r} at "
                             f"position {k} has id {node.id}")
    distances, frames, intensities = transitions(nodes, vectors_by_sequence)
    w = edge_weights(distances, intensities)
    unpruned = {(i, j): float(w[i, j]) for (i, j) in frames}
    measured = [replace(node, intensity=float(x)) for node, x in zip(nodes, intensities)]
    return graph_from(measured, unpruned, frames, mu, connect)


def nodes_of(graph):
    """The graph's nodes as ``Node`` objects, ordered by id (what a library stores).

    Examples
    --------
    >>> G = graph_from([Node(0, "a/01", "a", 0, 1, 0, 0.1, 1.0)], {}, {})
    >>> nodes_of(G)
    [Node(id=0, name='a/01', sequence='a', start=0, end=1, cluster=0, texton_distance=0.1, intensity=1.0, kind='cycle')]
    """
    return [Node(id=i, **graph.nodes[i]) for i in sorted(graph.nodes)]


#: Names an unknown-motion message lists before it says "...".
def node_by_key(graph_or_nodes, key):
    """Id of the node a user means by ``key``: an id, an id written as digits, or a name.

    Parameters
    ----------
    graph_or_nodes : networkx.DiGraph or list of Node
    key : int or str

    Returns
    -------
    int

    Raises
    ------
    UnknownMotion
        When no node has that id or name; the message lists the known names.

    Examples
    --------
    >>> nodes = [Node(0, "walk/01", "walk", 0, 9, 0, 0.1), Node(1, "run/01", "run", 0, 5, 0, 0.1)]
    >>> node_by_key(nodes, "run/01"), node_by_key(nodes, "1"), node_by_key(nodes, 0)
    (1, 1, 0)
    >>> node_by_key(nodes, "jump")
    Traceback (most recent call last):
    ...
    tvmedit.engine.errors.UnknownMotion: there is no motion 'jump'; known motions are walk/01, run/01 (or an id from 0 to 1).
    """
    names = _names(graph_or_nodes)
    if isinstance(key, str):
        text = key.strip()
        for i, name in names.items():
            if name == text:
                return i
        if text.isdigit() and int(text) in names:
            return int(text)
    elif isinstance(key, (int, np.integer)) and not isinstance(key, bool) and int(key) in names:
        return int(key)
    raise UnknownMotion.among(key, dict(sorted(names.items())))


def rename(graph_or_nodes, key, name):
    """Give the node that ``key`` names (see :func:`node_by_key`) a new name; returns its id.

    A name must be unique, non-empty, not all digits (digits are read as an id) and one line
    of printable characters (a newline or an escape code would break every table that lists
    it). Leading and trailing spaces are dropped.

    Examples
    --------
    >>> nodes = [Node(0, "walk/01", "walk", 0, 9, 0, 0.1), Node(1, "run/01", "run", 0, 5, 0, 0.1)]
    >>> rename(nodes, "walk/01", "stroll")
    0
    >>> nodes[0].name
    'stroll'
    >>> rename(nodes, 1, "stroll")
    Traceback (most recent call last):
    ...
    tvmedit.engine.errors.TvmError: the name 'stroll' is already taken by motion 0; pick another
    """
    i = node_by_key(graph_or_nodes, key)
    new = str(name).strip()
    if not new or new.isdigit():
        raise TvmError(f"{name!r} cannot name a motion; use a name with at least one non-digit")
    if not new.isprintable():
        raise TvmError(f"{name!r} cannot name a motion: it holds a line break or a control character; "
                       "use one line of printable characters")
    for other, existing in _names(graph_or_nodes).items():
        if existing == new and other != i:
            raise TvmError(f"the name {new!r} is already taken by motion {other}; pick another")
    if isinstance(graph_or_nodes, nx.Graph):
        graph_or_nodes.nodes[i]["name"] = new
    else:
        next(node for node in graph_or_nodes if node.id == i).name = new
    return i


def _names(graph_or_nodes):
    """``{id: name}`` of a motion graph's nodes or of a list of :class:`Node`."""
    if isinstance(graph_or_nodes, nx.Graph):
        return {i: data["name"] for i, data in graph_or_nodes.nodes(data=True)}
    return {node.id: node.name for node in graph_or_nodes}


def _frames_of(node, vectors_by_sequence):
    """The feature vectors of ``node``'s texton frames, (L, D); a missing or short sequence is refused."""
    if node.sequence not in vectors_by_sequence:
        raise ValueError(f"no feature vectors for sequence {node.sequence!r} of node {node.name!r}")
    vectors = np.asarray(vectors_by_sequence[node.sequence])
    if not 0 <= node.start <= node.end < len(vectors):
        raise ValueError(f"node {node.name!r} spans frames {node.start}-{node.end}, but sequence "
                         f"{node.sequence!r} has {len(vectors)} feature vectors")
    return vectors[node.start:node.end + 1]
