"""Motion database, eq. (9): one representative texton per motion cluster.

The structure parser (section 4) cuts every sequence into motion clusters, and each cluster
into motion textons that repeat the same movement. The database keeps, per cluster, the
texton that is closest to a seamless loop: the one with the smallest texton distance
d_T, eq. (6). A library may hold several sequences (several people, several takes); the
database holds the representatives of all of them, each remembering where it came from.

Clusters that do not repeat: one-shot motions. The paper assumes every cluster repeats
its texton at least twice. Real takes are often not exercises: a person waves, holds up a
card, talks; the parser reports such stretches as clusters with one texton or none, and one
texton is no evidence of a motion that can be looped. Such a cluster (fewer than
``min_textons``) becomes a *one-shot* motion (``kind="once"``): the whole cluster, played
through once, entered at its first frame and left from a frame of its last part
(:mod:`tvmedit.engine.graph.motiongraph` restricts eq. (10) to those frames; :mod:`tvmedit.engine.graph.compose` plays it
once). A slow exercise (a 3-4 s twist or toe touch, done twice) often holds only one whole
texton once its start is aligned, yet its cluster runs on for a good part of another cycle:
a cluster at least ``REPEAT_SPAN`` (1.5) times as long as its only texton shows the motion
going on past one cycle, so its texton is kept as a cycle.
"""

import math
from dataclasses import dataclass

#: Fewest textons a cluster needs before its representative enters the database.
MIN_TEXTONS = 2
#: A cluster with fewer textons still enters when it is this many times as long as its texton.
REPEAT_SPAN = 1.5
#: Kinds of motion: a representative texton played cyclically, or a cluster played once.
CYCLE, ONCE = "cycle", "once"


@dataclass
class Node:
    """One motion of the database: a representative texton, a node of the motion graph.

    Attributes
    ----------
    id : int
        Position in the database, stable across builds of the same input: nodes are numbered
        from 0 in sequence order, then by start frame.
    name : str
        What a user types to pick the motion; defaults to ``"<sequence>/<k>"`` with ``k`` the
        1-based, two-digit rank of the node within its sequence (``"walk/01"``). Renamable.
    sequence : str
        Name of the sequence the frames come from.
    start, end : int
        First and last frame of the texton (of the cluster, for a one-shot), inclusive, as
        indices within ``sequence``.
    cluster : int
        Index of the texton's motion cluster within ``sequence``.
    texton_distance : float
        d_T of the texton, eq. (6): how far its last atom is from its first (for a one-shot,
        the atom distance from its first frame to its last, where the parse gives it).
    intensity : float or None
        Motion intensity, eq. (11); ``None`` until the graph step measures it.
    kind : str
        ``"cycle"``: a texton played cyclically (section 8); ``"once"``: a one-shot motion,
        played through once from its first frame (see the module docstring).

    Examples
    --------
    >>> node = Node(id=0, name="walk/01", sequence="walk", start=3, end=14, cluster=0,
    ...             texton_distance=0.02)
    >>> node.n_frames
    12
    """

    id: int
    name: str
    sequence: str
    start: int
    end: int
    cluster: int
    texton_distance: float
    intensity: float | None = None
    kind: str = CYCLE

    @property
    def n_frames(self):
        """Number of frames in the texton, n(T_i) in eq. (11)."""
        return self.end - self.start + 1

    @property
    def once(self):
        """Whether this is a one-shot motion, played through once rather than cyclically."""
        return self.kind == ONCE


def select_textons(textons, min_textons=MIN_TEXTONS, clusters=None):
    """Representative texton of every cluster of one sequence, eq. (9).

    Parameters
    ----------
    textons : iterable of objects with ``.start``, ``.end``, ``.cluster``, ``.distance``
        The textons of one sequence; ``distance`` is the texton distance d_T, eq. (6).
    min_textons : int
        Clusters with fewer textons than this are left out (see the module docstring)...
    clusters : list of (start, end), optional
        ...unless, with the clusters' inclusive frame ranges given, the cluster is at least
        ``REPEAT_SPAN`` times as long as its longest texton.

    Returns
    -------
    list
        One texton per kept cluster, the one with the smallest ``distance`` (the earliest
        one on a tie), ordered by start frame.

    Examples
    --------
    >>> from types import SimpleNamespace as T
    >>> textons = [T(start=0, end=9, cluster=0, distance=0.3),
    ...            T(start=10, end=19, cluster=0, distance=0.1),
    ...            T(start=20, end=24, cluster=1, distance=0.0)]
    >>> [(t.start, t.end) for t in select_textons(textons)]
    [(10, 19)]
    >>> [(t.start, t.end) for t in select_textons(textons, min_textons=1)]
    [(10, 19), (20, 24)]
    >>> [(t.start, t.end) for t in select_textons(textons, clusters=[(0, 19), (18, 28)])]
    [(10, 19), (20, 24)]
    """
    by_cluster = {}
    for texton in textons:
        by_cluster.setdefault(texton.cluster, []).append(texton)

    def repeats(cluster, members):
        """Whether the cluster is played as a cycle rather than once."""
        if len(members) >= min_textons:
            return True
        if clusters is None:
            return False
        start, end = clusters[cluster]
        return end - start + 1 >= REPEAT_SPAN * max(t.end - t.start + 1 for t in members)

    chosen = [min(members, key=lambda t: (t.distance, t.start))
              for cluster, members in by_cluster.items() if repeats(cluster, members)]
    return sorted(chosen, key=lambda t: t.start)


def build_database(structures, min_textons=MIN_TEXTONS):
    """Nodes of the motion database for all sequences of a library, eq. (9), with one-shots.

    Parameters
    ----------
    structures : dict of str to (textons, clusters)
        Parsed structure per sequence name, in sequence order (the order numbers the
        nodes). ``textons`` is an iterable of objects with ``.start``, ``.end``,
        ``.cluster``, ``.distance``; ``clusters`` is the list of inclusive frame ranges
        ``(start, end)`` that ``texton.cluster`` indexes. An object with ``.textons`` and
        ``.clusters`` attributes (and optionally ``.curve``, the atom distance of each frame
        from the first of its cluster) is accepted in place of the pair.
    min_textons : int
        Clusters with fewer textons (and not running on past their only one, see the module
        docstring) become one-shot motions spanning the cluster.

    Returns
    -------
    list of Node
        Ids 0, 1, ... in sequence order, then by start frame; ``intensity`` is ``None``.

    Examples
    --------
    >>> from types import SimpleNamespace as T
    >>> walk = [T(start=0, end=9, cluster=0, distance=0.3),
    ...         T(start=10, end=19, cluster=0, distance=0.1)]
    >>> run = [T(start=0, end=5, cluster=0, distance=0.2),
    ...        T(start=6, end=11, cluster=0, distance=0.4)]
    >>> for node in build_database({"walk": (walk, [(0, 19), (20, 31)]), "run": (run, [(0, 11)])}):
    ...     print(node.id, node.name, node.start, node.end, node.kind)
    0 walk/01 10 19 cycle
    1 walk/02 20 31 once
    2 run/01 0 5 cycle
    """
    nodes = []
    for sequence, value in structures.items():
        textons, clusters = _unpack(sequence, value)
        curve = getattr(value, "curve", None)
        cycles = {t.cluster: t for t in select_textons(textons, min_textons, clusters)}
        singles = {}
        for texton in textons:
            singles.setdefault(texton.cluster, texton)
        motions = []
        for index, (start, end) in enumerate(clusters):
            if index in cycles:
                texton = cycles[index]
                motions.append((int(texton.start), int(texton.end), index, float(texton.distance), CYCLE))
            else:
                motions.append((int(start), int(end), index, _once_distance(curve, end, singles.get(index)), ONCE))
        for rank, (start, end, cluster, distance, kind) in enumerate(sorted(motions), start=1):
            nodes.append(Node(id=len(nodes), name=f"{sequence}/{rank:02d}", sequence=sequence,
                              start=start, end=end, cluster=cluster, texton_distance=distance, kind=kind))
    return nodes


def advice(nodes, better=None):
    """What a user can do with a database too small to edit (fewer than two motions), or None.

    Structure parameters are named as in ``tvmedit.engine.parse.structure.StructureParams``;
    ``better``, ``({name: value}, motions)``, is a parse setting tried and found to give more.

    >>> advice([])
    'the library has no motions, so there is nothing to edit: build it from sequences with frames.'
    >>> talk = [Node(0, "talk/01", "talk", 0, 99, 0, 0.1, kind="once")]
    >>> print(advice(talk))
    the library has one motion, talk/01 (played once), and an edit needs two: build it with another take as well (several sequences make one library), or let the parser cut this take into more motions with a shorter min_cluster or a lower novelty_threshold.
    >>> print(advice(talk, better=({"min_cluster": 1.0, "partition": 5.0}, 3)))
    the library has one motion, talk/01 (played once), and an edit needs two: build it with another take as well (several sequences make one library), or let the parser cut this take into more motions: with min_cluster=1 and partition=5 it finds 3 (tried).
    """
    if len(nodes) >= 2:
        return None
    if not nodes:
        return "the library has no motions, so there is nothing to edit: build it from sequences with frames."
    node = nodes[0]
    head = (f"the library has one motion, {node.name} ({'played once' if node.once else 'a cycle'}), and "
            "an edit needs two: build it with another take as well (several sequences make one library), or ")
    if better is not None:
        setting, count = better
        given = " and ".join(f"{name}={value:g}" for name, value in setting.items())
        return head + f"let the parser cut this take into more motions: with {given} it finds {count} (tried)."
    return head + ("let the parser cut this take into more motions with a shorter min_cluster or a lower "
                   "novelty_threshold.")


def _once_distance(curve, end, texton):
    """The atom distance from a one-shot's first frame to its last: the parse's curve there
    (measured from the start of the cluster when no texton covers it), else the distance of
    the cluster's only texton, else 0."""
    if curve is not None and texton is None and int(end) < len(curve) and math.isfinite(float(curve[int(end)])):
        return float(curve[int(end)])
    return float(texton.distance) if texton is not None else 0.0


def _unpack(sequence, value):
    # Checks at the door: a texton pointing outside its clusters is a parser bug, and it is
    # far easier to find here than as a wrong transition frame two steps later.
    if hasattr(value, "textons"):
        textons, clusters = value.textons, value.clusters
    else:
        textons, clusters = value
    textons = list(textons)
    for texton in textons:
        if not 0 <= texton.cluster < len(clusters):
            raise ValueError(f"sequence {sequence!r}: texton {texton.start}-{texton.end} "
                             f"names cluster {texton.cluster}, but there are {len(clusters)}")
        if not 0 <= texton.start <= texton.end:
            raise ValueError(f"sequence {sequence!r}: texton {texton.start}-{texton.end} "
                             "is not a frame range")
    return textons, list(clusters)
