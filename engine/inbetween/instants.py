"""A surface at every instant: in-between geometry for each step the player and renderer show.

A capture at 10 fps changes the body ten times a second; the player redraws at 60 Hz or more
and a video may be written at 30 or 60 fps. Between two frames shown one after the other, ``a``
then ``b`` (two frames of a texton, a loop's wrap, or the frames of a transition's run), the
surface at fraction ``s`` of the step (``0 <= s < 1``) is

    ``a + s * F``,  where ``F`` = :func:`tvmedit.engine.inbetween.fit.align` (``a`` onto ``b``),

``a``'s own mesh, colours and texture carried smoothly onto ``b``'s surface; at ``s = 1`` ``b``
itself takes over. One alignment serves the three kinds of step, as it serves transitions.

Why one field a step, forward, rather than ``a`` forward and ``b`` back meeting in the middle:
where the two fields are fitted apart they disagree, and the switch in the middle shows it as
a jump of the limbs they carried differently. Carried all the way, ``a`` lies on ``b``'s
surface when ``b`` takes over, so the switch moves the surface by the fit's residual alone (a
centimetre or two at the 99th percentile where a step moves limbs ten), and only the sampling
of the surface (which vertices, which colours) changes there, as at any captured frame. It
also costs half: one fit and one field per step.

Why stored as a float16 displacement of ``a``'s vertices, per step: it is the least that
gives the motion, six bytes a vertex beside the frame's 50-odd (positions, normals, colours,
faces), and half-precision resolves a displacement of up to 0.5 m to a quarter of a millimetre.
The player's work per displayed frame stays an upload and a draw: the displacement is an
attribute, ``s`` a uniform, and the vertex shader adds them (``shaders/mesh.glsl``). Normals are
the frame's own: over one step a normal turns little.

Which steps: every pair of frames some schedule shows one after the other
(:func:`display_pairs`): consecutive frames of each texton, its wrap (last frame to first, or
through the frames that close its loop), and each edge's exit frame, its run and its entry
frame; but none of a sequence captured at :data:`FIELDS_BELOW_FPS` or faster, whose steps
last no longer than a redraw of a 48-60 Hz display: a field there would move the body within
one redraw and costs the build as much as at 10 fps (a 60 fps take has six times the steps).
A step no field was made for (a library built before them) is shown as captured.

The fit for a step is coarse-to-fine over :data:`SIGMAS` with :data:`STEPS` iterations each:
two frames a capture step apart differ by centimetres, not by a transition's cut, and fewer,
finer levels fit them as closely for a fraction of the cost.
"""

import numpy as np

from .blend import matched_both_ways
from .fit import COLOUR_METRES, align, coloured_points, kdtree

__all__ = ["SIGMAS", "STEPS", "KEEP", "FIELDS_BELOW_FPS", "step_field", "helps", "display_pairs", "instants",
           "shown", "moved", "surface_distances", "step_measures", "matched_tail", "matched_both_ways",
           "coloured_points", "COLOUR_METRES"]

#: Capture rates from which a sequence's steps get no field: each lasts about a redraw.
FIELDS_BELOW_FPS = 48.0

#: Gaussian radii (metres), coarse to fine, of a step's fit, iterations at each, nodes at the
#: finest radius and nodes a vertex follows: fewer than a transition's, and as close a fit for
#: two frames a capture step apart at two thirds of the cost (``benchmarks/display_rate.py``).
SIGMAS = (0.12, 0.05)
STEPS = 2
NODES = 1000
FOLLOW = 4


def step_field(a, b, b_normals=None, seed=0, a_normals=None):
    """The float16 displacement (N, 3) of ``a``'s N vertices that lays them on ``b``'s surface,
    or None where it would not bring ``a`` closer to ``b`` (:func:`helps`).

    The fit (:func:`tvmedit.engine.inbetween.fit.align`) leaves each vertex a few millimetres
    off ``b``, in sampling noise as much as in error; given ``b``'s vertex normals, each is then
    moved along its nearest ``b`` vertex's normal onto that vertex's tangent plane, which halves
    what is left (what ``b`` changes when it takes over), at one k-d tree query.

    >>> a = np.random.default_rng(0).random((300, 3)); field = step_field(a, a + [0.0, 0.0, 0.01])
    >>> field.dtype.name, bool(abs(np.median(field[:, 2]) - 0.01) < 0.002)
    ('float16', True)
    """
    a = np.asarray(a, np.float32)
    b = np.asarray(b, np.float32)
    tree = kdtree(b)
    field = align(a, b, seed, sigmas=SIGMAS, steps=STEPS, nodes=NODES, follow=FOLLOW, still_tree=tree)
    if b_normals is not None and len(b):
        warped = a + field
        nearest = tree.query(warped)[1]
        normals = np.asarray(b_normals, np.float32)[nearest]
        off = np.einsum("ij,ij->i", warped - b[nearest], normals)
        field -= off[:, None] * normals
        if a_normals is not None and not helps(a, a_normals, b, b_normals, field, tree):
            return None
    return field.astype(np.float16)


#: A step's field is kept where the surface it carries ``a`` to is at most this share as far
#: from ``b`` as ``a`` is (mean and 99th percentile, point to plane): elsewhere the two frames
#: differ by the capture's noise, not by motion, and the frame is better shown as captured.
KEEP = 0.5
#: ... and where it moves ``a``'s surface along its normals at most this many times as far as
#: ``b`` lies from ``a``.
BULGE = 1.5


def helps(a, a_normals, b, b_normals, field, tree_b, stride=8):
    """Whether ``a + field`` is nearer ``b`` than ``a`` is, by :data:`KEEP`, and moves ``a``'s
    surface off itself no farther than :data:`BULGE` times that: point-to-plane distances of
    every ``stride``-th vertex to ``b`` (a plane through the nearest vertex, along its normal),
    so that two samplings of one surface count as 0 apart, as in :func:`step_measures`. Every
    8th vertex (some 2,000 of a 17,000-vertex frame) decides as every 4th did on 478 of 480
    steps of CMU 13_29, 13_30, the gym and the scvv card, at half the cost (5 ms a step).

    >>> p = np.random.default_rng(1).random((400, 3)); n = np.tile([0.0, 0.0, 1.0], (400, 1))
    >>> helps(p, n, p + [0, 0, 0.02], n, np.tile(np.float32([0, 0, 0.02]), (400, 1)), kdtree(p + [0, 0, 0.02]))
    True
    """
    def plane(points):
        index = tree_b.query(points)[1]
        return np.abs(np.einsum("ij,ij->i", points - b[index], np.asarray(b_normals, np.float32)[index]))

    before, after = plane(a[::stride]), plane((a + field)[::stride])
    # How far the field moves a's surface off itself: no more than b lies off it, or the
    # surfaces in between bulge out of both (a fit pulled along noise or an open border).
    bulge = np.abs(np.einsum("ij,ij->i", field[::stride], np.asarray(a_normals, np.float32)[::stride]))
    tail = lambda d: np.percentile(d, 99)  # noqa: E731
    return bool(after.mean() <= KEEP * before.mean() and tail(after) <= KEEP * tail(before)
                and bulge.mean() <= BULGE * before.mean() and tail(bulge) <= BULGE * tail(before))


def moved(positions, field, s):
    """``positions + s * field`` as float32: the surface at fraction ``s`` of a step (what the
    shader draws, for writing it to a file).

    >>> moved(np.zeros((1, 3), np.float32), np.ones((1, 3), np.float16), 0.25).tolist()
    [[0.25, 0.25, 0.25]]
    """
    out = np.asarray(field, dtype=np.float32) * np.float32(s)
    out += np.asarray(positions, dtype=np.float32)
    return out


def display_pairs(nodes, edges, wraps, row):
    """Every step some schedule of a library shows, as pairs of mesh ids.

    Parameters
    ----------
    nodes : iterable of (sequence, start, end)
        The textons.
    edges : iterable of dict
        ``blends.json``'s edges: ``exit`` and ``entry`` ``[sequence, frame]``, ``first`` and
        ``count`` of its run of in-between frames.
    wraps : iterable of dict
        ``blends.json``'s loop closings: ``texton`` ``[sequence, start, end]``, ``at``,
        ``first`` and ``count``.
    row : callable
        ``row(sequence, frame)`` -> the mesh id of a stored frame; in-between frame ``k`` is
        ``-1 - k``.

    Returns
    -------
    list of (int, int)
        Unique, in a fixed order.

    >>> rows = lambda seq, f: f
    >>> display_pairs([("a", 0, 2)], [], [], rows)
    [(0, 1), (1, 2), (2, 0)]
    >>> display_pairs([("a", 0, 5)], [], [{"texton": ["a", 0, 5], "at": "end", "first": 0, "count": 2}], rows)[-3:]
    [(3, -1), (-1, -2), (-2, 0)]
    """
    pairs = []
    for seq, start, end in nodes:
        pairs += [(row(seq, f), row(seq, f + 1)) for f in range(start, end)]
        pairs.append((row(seq, end), row(seq, start)))
    for wrap in wraps:
        seq, start, end = wrap["texton"]
        run = [-1 - (wrap["first"] + k) for k in range(wrap["count"])]
        if not run:
            continue
        if wrap["at"] == "end":
            chain = [row(seq, end - len(run)), *run, row(seq, start)]
        else:
            chain = [row(seq, end), *run, row(seq, start + len(run))]
        pairs += list(zip(chain, chain[1:]))
    for edge in edges:
        chain = [row(*edge["exit"]), *(-1 - (edge["first"] + k) for k in range(edge["count"])), row(*edge["entry"])]
        pairs += list(zip(chain, chain[1:]))
    return list(dict.fromkeys(pairs))


def instants(count, capture_fps, fps):
    """Where each output frame of a schedule of ``count`` frames at ``capture_fps`` lies when
    written at ``fps``: ``(index, s)``, between schedule frames ``index`` and ``index + 1``.

    The schedule's timing is kept: frame ``k`` is shown at ``k / capture_fps`` seconds, and the
    output lasts as long (``count / capture_fps`` seconds).

    >>> instants(2, 10, 30)
    [(0, 0.0), (0, 0.333), (0, 0.667), (1, 0.0), (1, 0.333), (1, 0.667)]
    >>> instants(4, 10, 5)
    [(0, 0.0), (2, 0.0)]
    """
    total = int(round(count * fps / capture_fps))
    out = []
    for j in range(max(total, 1)):
        x = j * capture_fps / fps
        index = min(int(np.floor(x + 1e-9)), count - 1)
        out.append((index, round(float(min(max(x - index, 0.0), 1.0)), 3)))
    return out


def shown(count, capture_fps, fps, field_of):
    """What each output frame of a schedule of ``count`` frames written at ``fps`` shows:
    ``(index, s, field)``, schedule frame ``index`` moved ``s`` of the way along ``field``
    (None: as stored). ``field_of(index)`` gives the field of the step from frame ``index``
    to the next, or None; it is asked once per step, in order.

    Where a step has no field (a library built before them, or a step where the capture moves
    by its own noise), the output shows the stored frame nearest in time, so that the step
    falls in the middle, as it would at the capture's rate, and does not add to the next.

    >>> fields = {0: "F"}
    >>> list(shown(3, 10, 20, fields.get))
    [(0, 0.0, None), (0, 0.5, 'F'), (1, 0.0, None), (2, 0.0, None), (2, 0.0, None), (2, 0.0, None)]
    """
    last = (None, None)
    for index, s in instants(count, capture_fps, fps):
        if s == 0 or index + 1 >= count:
            yield index, 0.0, None
            continue
        if last[0] != index:
            last = (index, field_of(index))
        if last[1] is not None:
            yield index, s, last[1]
        else:
            yield (index + 1 if s >= 0.5 else index), 0.0, None


def surface_distances(points, positions, faces, tree=None, near=4):
    """Distance (metres) from each of ``points`` to the surface of mesh ``(positions, faces)``.

    The nearest point of the surface lies on a triangle of one of the ``near`` vertices nearest
    to the point (scipy's k-d tree finds them); each such triangle's nearest point is trimesh's
    (:func:`trimesh.triangles.closest_point`, vectorised). Unlike the distance to the nearest
    vertex, two samplings of one surface are 0 apart, so a step measures motion, not sampling.

    >>> square = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    >>> surface_distances(np.array([[0.5, 0.5, 0.1]]), square, np.array([[0, 1, 2], [1, 3, 2]])).round(6).tolist()
    [0.1]
    """
    from trimesh.triangles import closest_point

    positions = np.asarray(positions, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    points = np.asarray(points, dtype=np.float64)
    tree = kdtree(positions) if tree is None else tree
    near = min(near, len(positions))
    _, nearest = tree.query(points, k=near)
    nearest = nearest.reshape(len(points), near)
    # The faces of each vertex, as one flat table: (vertex, face) pairs sorted by vertex.
    order = np.argsort(faces.ravel(), kind="stable")
    owner = faces.ravel()[order]
    face_of = order // 3
    begin = np.searchsorted(owner, np.arange(len(positions)))
    end = np.searchsorted(owner, np.arange(len(positions)), side="right")
    best = np.linalg.norm(positions[nearest[:, 0]] - points, axis=1)   # an isolated vertex still counts
    for k in range(near):
        v = nearest[:, k]
        counts = end[v] - begin[v]
        if not counts.sum():
            continue
        who = np.repeat(np.arange(len(points)), counts)
        slot = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
        tri = face_of[np.repeat(begin[v], counts) + slot]
        distance = np.linalg.norm(closest_point(positions[faces[tri]], points[who]) - points[who], axis=1)
        np.minimum.at(best, who, distance)
    return best


def step_measures(a, b, stride=2):
    """The mean and 99th percentile of the point-to-surface distances, both ways, between two
    displayed meshes ``(positions, faces)`` (every ``stride``-th vertex measured): how far the
    surface moves in one step, and how far its farthest few hundred points move."""
    d = np.concatenate([surface_distances(a[0][::stride], b[0], b[1]),
                        surface_distances(b[0][::stride], a[0], a[1])])
    return float(d.mean()), float(np.percentile(d, 99))


def matched_tail(a, b, stride=2):
    """The 99th percentile of how far the points of two displayed meshes ``(positions,
    colours)`` (colours uint8, 0-255) move, each matched to the nearest point of the other
    that looks alike: the distance in position and colour together (:data:`COLOUR_METRES`),
    both ways, every ``stride``-th point; 0 where a mesh is empty.

    :func:`step_measures` takes the distance to the other surface wherever it is: a forearm
    that leaves the chest for the air, or lies on it in one frame and is raised in the next,
    still lies near *a* surface in both, and reads as still. Matched by colour, its skin
    finds the other frame's skin, and the step reads as far as the forearm went, up to the
    colour's own weight (about 40 cm from skin to a blue shirt): there a point is as near the
    other material where it stands, and a move farther reads as that. Between two frames of
    one material where it stands, colour noise adds about a centimetre.

    A strip of shirt, the same points in both frames, where a patch of skin moves 30 cm along
    it, and 80 cm:

    >>> y = np.linspace(0.0, 1.0, 101); p = np.stack([np.zeros(101), y, np.zeros(101)], axis=1)
    >>> shirt, skin = [40, 90, 170], [224, 172, 140]
    >>> a = np.where((y < 0.2)[:, None], skin, shirt)
    >>> b, c = (np.where(((y >= lo) & (y < lo + 0.2))[:, None], skin, shirt) for lo in (0.3, 0.8))
    >>> round(matched_tail((p, a), (p, b)), 1), round(matched_tail((p, a), (p, c)), 1)
    (0.3, 0.4)
    """
    if not len(a[0]) or not len(b[0]):
        return 0.0
    ka, kb = coloured_points(*a[:2]), coloured_points(*b[:2])
    return matched_both_ways((ka[::stride], kdtree(ka)), (kb[::stride], kdtree(kb)))

