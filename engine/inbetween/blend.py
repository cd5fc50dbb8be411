"""In-between frames for a transition between frames of different topology.

An edit jumps from the exit frame of one texton to the entry frame of the next (eq. (10)).
The two are separate reconstructions (other vertices, other triangles) of similar but not
equal poses, so without help every transition is a visible pop, a step far larger than one
frame's motion (the symmetric mean Chamfer distance between displayed frames, :func:`chamfer`).
The paper names motion blending at costly transitions as its future work; this module does it
offline, at build time, and the library stores the frames it makes beside the texton frames.

Method: surface alignment, as Prada et al. (2016) blend meshes without correspondence. A
smooth, non-rigid displacement field carries the outgoing frame ``a`` onto the incoming
surface ``b`` (:func:`align`), and another carries ``b`` back onto ``a``'s half-way warp
(:func:`fields_of`). The in-between frame at time ``t`` (``0 < t < 1``) is ``a`` warped by
``t`` times the first field while ``t < 1/2``, and ``b`` warped back by ``2 (1 - t)`` times the
second from then on: the cut falls in the middle, where the two meet. Every in-between frame is therefore one captured frame's own
mesh with its own colours (and texture), moved smoothly: its area is that of a real frame,
and it is never two people at once, as a blend of two surfaces would be.

The field is fitted as non-rigid ICP with symmetric forces, coarse to fine over the radii
:data:`SIGMAS`, :data:`STEPS` iterations each. Nodes sampled from the moving surface carry
the displacement (:data:`NODES` at the finest radius, as many per radius-wide patch at the
coarser ones, at least :data:`MIN_NODES`; each level starts from the coarser one's field).
In each iteration every node is pulled toward its nearest point of the other surface, and
every one of :data:`TARGET_POINTS` points of the other surface pulls its nearest node toward
itself; the pulls are summed over the nodes with a Gaussian of the radius and divided by the
summed weights (normalised convolution), so the many points of a limb that moved drag its few
nearest nodes, and the limb, along. "Nearest" is measured by position, and in a second fit
by position and colour together (:func:`coloured_points`, a colour difference of 1 weighing
:data:`COLOUR_METRES`), as coloured ICP does (Park, Zhou and Koltun, ICCV 2017). By position
alone, a forearm that leaves the chest finds the chest it lies on and is laid flat onto the
shirt, and the run switches to the incoming frame's forearm in one step (CMU 13_30's
transitions stepped up to 2.35x the natural step measured by colour, the forearms seen smeared
into the shirt at 1280x960); matched by colour, its skin finds the other frame's skin. Colour
misleads too: a face and a hand are both skin, so a point's pull on the node that looks like
it is kept only where it agrees with that node's own match (:func:`_consistent`: without it, a
face was drawn down onto hands raised before the chin, on an HDM05 take); and a textured
capture's colours repeat over its print and change with the light, so on the scvv card a fit
by colour can shear the print. :func:`blend` therefore fits by colour first, and where that
run steps less evenly than the cut allows, fits by position too and keeps the run whose
largest steps are the smaller (:func:`_largest`, on the run's first count of frames). 13_30's transitions then step at most 0.87x the natural step by colour, and the
forearms travel whole (looked at); what is left is milder: on that HDM05 transition the
neck's skin is stretched into the shirt for two frames.
Vertices follow their :data:`FOLLOW` nearest nodes, Gaussian-weighted. A warp is a
multiply-add, so in-between frames cost little once the alignment is made; k-d trees are
built once per frame.

How many in-between frames: enough that no displayed step (vertex Chamfer) exceeds the
*natural step*, the median step between consecutive frames inside the database textons
(:func:`frame_count`), at most :data:`MAX_FRAMES`; the caller may fix the count instead
(``blend_frames``; 0 keeps the paper's cut).
"""

import numpy as np

from ..capture.normals import vertex_normals

__all__ = ["MAX_FRAMES", "FIT", "COLOUR_METRES", "coloured_points", "matched_both_ways",
           "preload", "kdtree", "chamfer",
           "chamfer_and_tail", "texton_steps", "natural_step", "surface_area", "align", "BlendRun", "blend",
           "fields_of", "frame_count", "side", "check_count"]

#: Most in-between frames one transition gets.
MAX_FRAMES = 8
#: The version of the fit that makes a transition's run, recorded in a library's ``blends.json``:
#: 1 by position alone; 3 by position and by position and colour, the smaller kept on the run's
#: first count, which fit and on what count recorded with each run (2 recorded neither; never
#: released); 4 as 3, but by position only where the fit by colour steps less evenly than the
#: cut allows (:func:`blend`). A rebuild copies transitions of the library it replaces only
#: where this version made them.
FIT = 4
#: Nodes carrying the displacement field at the finest radius (sampled from the moving surface).
NODES = 1500
#: Fewest nodes at the coarsest radius, and node density of coarse levels relative to the finest.
MIN_NODES = 200
LEVEL_DENSITY = 3.0
#: Points of the still surface that pull on the nodes.
TARGET_POINTS = 3000
#: Gaussian radii of the field, coarse to fine (metres), and steps at each.
SIGMAS = (0.20, 0.12, 0.08, 0.05, 0.03)
STEPS = 3
#: Nearest nodes a vertex follows.
FOLLOW = 6

#: Metres that a colour difference of 1 (in 0-1 units, per channel) counts as, where
#: points are matched by position and colour (:func:`align`, and
#: :func:`tvmedit.engine.inbetween.instants.matched_tail`'s measure): a capture's colour noise (6 of
#: 255) weighs about a centimetre, and another material (skin beside a shirt, 0.3-0.8 apart)
#: 15-40 cm, so a point finds its partner on its own part of the body.
COLOUR_METRES = 0.5


def preload():
    """Import what making runs needs (scipy's k-d tree and sparse matrices) in this process,
    so that worker processes forked after it have it: a rebuild's pool starts for a handful
    of runs, and each worker would otherwise import scipy on its own."""
    import scipy.sparse  # noqa: F401
    import scipy.spatial  # noqa: F401


def kdtree(points):
    """scipy's k-d tree of ``points`` (N, 3), for :func:`chamfer`'s ``tree_a`` and ``tree_b``."""
    return _kdtree(points)


def _kdtree(points):
    """scipy's k-d tree of ``points``, imported on first use: an edit's schedule needs
    :func:`side` from this module, and the player must start without loading scipy."""
    from scipy.spatial import cKDTree

    # Unbalanced: quicker to build, and the queries give the same answers. Compacted (each
    # node's box shrunk to its points): a display step's field queries a tree some 40,000
    # times, and the tighter boxes make the whole fit 9 % faster for 0.3 ms more a tree build
    # (fields identical on 49 display steps of CMU 13_29).
    return cKDTree(points, balanced_tree=False, compact_nodes=True)


def chamfer(a, b, tree_a=None, tree_b=None, stride=1):
    """Symmetric mean Chamfer distance between two point sets (metres if they are).

    The mean distance from each point of ``a`` to its nearest point of ``b``, and from ``b``
    to ``a``, averaged.

    Parameters
    ----------
    a, b : (N, 3), (M, 3) float
    tree_a, tree_b : cKDTree, optional
        Prebuilt trees of ``a`` and ``b``.
    stride : int
        Average over every ``stride``-th point only (each still measured against every point
        of the other set): a cheaper estimate of the same mean.

    Returns
    -------
    float

    >>> a = np.zeros((1, 3)); b = np.array([[0.0, 0.0, 0.5]])
    >>> chamfer(a, b)
    0.5
    """
    return chamfer_and_tail(a, b, tree_a, tree_b, stride)[0]


def chamfer_and_tail(a, b, tree_a=None, tree_b=None, stride=1):
    """:func:`chamfer`, and the 99th percentile of the same distances both ways: the few
    hundred vertices of a hand or a forearm that move far while the mean stays small.

    >>> a = np.zeros((1, 3)); b = np.array([[0.0, 0.0, 0.5]])
    >>> chamfer_and_tail(a, b)
    (0.5, 0.5)
    """
    tree_a = _kdtree(a) if tree_a is None else tree_a
    tree_b = _kdtree(b) if tree_b is None else tree_b
    a_part, b_part = np.asarray(a)[::stride], np.asarray(b)[::stride]
    ab, ba = tree_b.query(a_part)[0], tree_a.query(b_part)[0]
    return 0.5 * float(ab.mean() + ba.mean()), float(np.percentile(np.concatenate([ab, ba]), 99))


def texton_steps(frames, tails=False):
    """Chamfer distances between consecutive frames of one texton (every 4th vertex averaged).

    Parameters
    ----------
    frames : list of (N_k, 3) float
        Vertex positions of the texton's frames in play order.
    tails : bool
        Give each step as ``(chamfer, 99th percentile)`` (:func:`chamfer_and_tail`).

    Returns
    -------
    list of float
        ``len(frames) - 1`` steps; their median over every texton of a library is its
        *natural step* (:func:`natural_step`).
    """
    trees = [_kdtree(np.asarray(p)) for p in frames]
    steps = [chamfer_and_tail(frames[k], frames[k + 1], trees[k], trees[k + 1], stride=4)
             for k in range(len(frames) - 1)]
    return steps if tails else [mean for mean, _ in steps]


def natural_step(steps):
    """The median of the steps inside the database textons (metres); 0 when there are none.

    >>> natural_step([[0.01, 0.03], [0.02]])
    0.02
    """
    flat = [s for texton in steps for s in texton]
    return float(np.median(flat)) if flat else 0.0


def surface_area(positions, faces):
    """Total area of a triangle mesh: positions (N, 3), faces (M, 3) -> float.

    >>> surface_area(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float), np.array([[0, 1, 2]]))
    0.5
    """
    p = np.asarray(positions, dtype=np.float64)
    f = np.asarray(faces, dtype=np.intp)
    cross = np.cross(p[f[:, 1]] - p[f[:, 0]], p[f[:, 2]] - p[f[:, 0]])
    return float(0.5 * np.sqrt(np.einsum("ij,ij->i", cross, cross)).sum())


def coloured_points(positions, colours):
    """Points ``(N, 6)`` float64 of a mesh's ``positions`` (N, 3) and ``colours`` (N, 3 or 4,
    uint8): position, then colour at :data:`COLOUR_METRES` metres a unit, the space
    :func:`tvmedit.engine.inbetween.instants.matched_tail` measures a step in and
    :func:`align` matches points in.

    >>> coloured_points(np.zeros((1, 3)), np.array([[255, 0, 0]], np.uint8)).tolist()
    [[0.0, 0.0, 0.0, 0.5, 0.0, 0.0]]
    """
    positions, colours = np.asarray(positions, np.float64), np.asarray(colours, np.float64)
    colours = colours.reshape(len(positions), -1)[:, :3] * (COLOUR_METRES / 255.0)
    return np.hstack([positions.reshape(-1, 3), colours])


def matched_both_ways(a, b):
    """The 99th percentile of the distances from each point ``a[0]`` to the nearest point of
    ``b`` (its k-d tree ``b[1]``), and from ``b[0]`` to ``a`` (``a[1]``): the figure of
    :func:`tvmedit.engine.inbetween.instants.matched_tail`, for points of
    :func:`coloured_points` and trees already made.

    >>> p = np.zeros((3, 6)); q = p + [0.0, 0.0, 0.1, 0.0, 0.0, 0.0]
    >>> round(matched_both_ways((p, kdtree(p)), (q, kdtree(q))), 3)
    0.1
    """
    d = np.concatenate([b[1].query(a[0])[0], a[1].query(b[0])[0]])
    return float(np.percentile(d, 99))


def _sample(points, count, seed):
    """``count`` rows of ``points`` spread over the surface (a seeded random choice)."""
    if len(points) <= count:
        return np.arange(len(points))
    return np.sort(np.random.default_rng(seed).choice(len(points), count, replace=False))


def _smoother(nodes, sigma):
    """The (n, n) sparse Gaussian kernel between distinct nodes, cut at two ``sigma`` (the
    node itself is added by the caller): a COO matrix, built and applied without sorting."""
    from scipy import sparse

    tree = _kdtree(nodes)
    pairs = tree.sparse_distance_matrix(tree, 2.0 * sigma, output_type="ndarray")
    weights = np.exp(-0.5 * (pairs["v"] / sigma) ** 2)
    return sparse.coo_matrix((weights, (pairs["i"], pairs["j"])), shape=(len(nodes),) * 2)


def _level_nodes(sigma, most=NODES):
    """Nodes that carry the field at Gaussian radius ``sigma``: about as many per
    ``sigma``-wide patch of the surface as at the finest radius, at most ``most``."""
    return int(min(most, max(MIN_NODES, most * (SIGMAS[-1] / sigma) ** 2 * LEVEL_DENSITY)))


def align(moving, still, seed=0, sigmas=SIGMAS, steps=STEPS, nodes=NODES, follow=FOLLOW, still_tree=None,
          colours=None, carrier=None):
    """A smooth displacement of every vertex of ``moving`` that lays it onto ``still``.

    Non-rigid ICP with symmetric nearest-point forces, smoothed by a Gaussian over nodes
    sampled from ``moving``, coarse to fine (see the module docstring).

    Parameters
    ----------
    moving : (N, 3) float
        Vertices of the frame to warp.
    still : (M, 3) float
        Vertices of the frame to reach.
    seed : int
        Seed of the node sampling (the result is deterministic).
    sigmas, steps, nodes, follow : tuple of float, int, int, int
        The radii, coarse to fine, the iterations at each, the nodes at the finest and the
        nodes each vertex follows: two frames a capture step apart need fewer of each
        (:mod:`.instants`) than a transition's cut.
    still_tree : cKDTree, optional
        :func:`kdtree` of ``still``, where the caller has it (not used with ``colours``).
    colours : tuple of two (N, 3) and (M, 3) uint8, optional
        The colours of ``moving`` and ``still``: points are then matched by position and
        colour together (:func:`coloured_points`), so that a node finds its nearest point of
        the other surface on its own part of the body (see the module docstring).
    carrier : _Carrier, optional
        ``moving``'s nodes (made with the same ``seed``, ``nodes`` and ``follow``) and what
        depends on them alone, where another fit of ``moving`` made them: :func:`blend` fits
        each frame twice, and the second fit takes them from the first.

    Returns
    -------
    (N, 3) float32
        ``moving + result`` lies on ``still``'s surface (to a few millimetres).
    """
    moving = np.asarray(moving, dtype=np.float64)
    still = np.asarray(still, dtype=np.float64)
    carrier = _Carrier(moving, seed, nodes, follow) if carrier is None else carrier
    picked = _sample(still, TARGET_POINTS, seed + 1)
    pulls = still[picked]
    if colours is None:
        targets, looks = pulls, None
        still_tree = _kdtree(still) if still_tree is None else still_tree
    else:  # matched in position and colour: (N, 6) points, a node's look its vertex's colour
        seen = coloured_points(still, colours[1])
        targets, looks = seen[picked], coloured_points(moving, colours[0])[carrier.order, 3:]
        still_tree = _kdtree(seen)
    count, shift = 0, np.zeros((0, 3))
    for sigma in sigmas:
        more = max(count, carrier.count(sigma))
        nodes, kernel, reach = carrier.level(sigma, count, more)
        if more > count:
            carried = _carry(reach, shift) if count else np.zeros((more - count, 3))
            shift, count = np.vstack([shift, carried]), more
        for _ in range(steps):
            warped = nodes + shift
            seen = warped if looks is None else np.hstack([warped, looks[:len(nodes)]])
            matched = still[still_tree.query(seen)[1]]
            pull = matched - warped
            nearest = _kdtree(seen).query(targets)[1]
            if looks is not None:
                nearest = _consistent(nearest, matched, warped, pulls)
            weight = 1.0 + np.bincount(nearest, minlength=len(nodes))
            for axis in range(3):
                pull[:, axis] += np.bincount(nearest, weights=pulls[:, axis] - warped[nearest, axis],
                                             minlength=len(nodes))
            # Normalised convolution: every pull counts once, so the many points of a limb
            # that moved away outweigh the few nodes nearest to them and drag the limb along.
            shift += (kernel @ pull + pull) / (kernel @ weight + weight)[:, None]
    return _carry(carrier.spread(count), shift)


class _Carrier:
    """The nodes sampled from one moving surface, and what depends on them and not on the
    surface they are laid onto: each radius's Gaussian kernel (:func:`_smoother`), and which
    nodes, with what weights, the nodes added at a finer radius and at last every vertex follow
    (:func:`_reach`). Fitted twice (by position, and by position and colour), a frame's nodes
    are the same, and these are made once, a third of a fit's work."""

    def __init__(self, moving, seed=0, most=NODES, follow=FOLLOW):
        self.moving, self.most, self.follow = np.asarray(moving, dtype=np.float64), most, follow
        order = _sample(self.moving, most, seed)
        self.order = order[np.random.default_rng(seed).permutation(len(order))]
        self._made = {}

    def count(self, sigma):
        """Nodes at radius ``sigma`` (:func:`_level_nodes`), at most the surface's vertices."""
        return min(len(self.order), _level_nodes(sigma, self.most))

    def level(self, sigma, before, count):
        """``(nodes, kernel, reach)`` at radius ``sigma``: the first ``count`` nodes, their
        kernel, and how nodes ``before`` to ``count`` follow the ``before`` nodes there were."""
        key = (sigma, before, count)
        if key not in self._made:
            nodes = self.moving[self.order[:count]]
            reach = _reach(nodes[before:], nodes[:before], self.follow) if 0 < before < count else None
            self._made[key] = (nodes, _smoother(nodes, sigma), reach)
        return self._made[key]

    def spread(self, count):
        """How every vertex follows the first ``count`` nodes (:func:`_reach`)."""
        if count not in self._made:
            self._made[count] = _reach(self.moving, self.moving[self.order[:count]], self.follow)
        return self._made[count]


def _consistent(nearest, matched, nodes, points):
    """Which node each point of the still surface pulls, matched by position and colour
    (``nearest``), kept where that node's own match (``matched``, its nearest point of the
    still surface by position and colour) lies nearer the point than the node does: the pull
    and the node's own way agree; elsewhere the node nearest by position. A hand raised before
    the chin finds the face as its nearest skin, but the face's own match is the other frame's
    face, as far from the hand as the face is: pulled by the hand, the face would be drawn down
    onto it (seen on an HDM05 take). A forearm that moved finds the forearm, whose own match
    lies on the other frame's forearm, near the point: that pull stays."""
    gap = np.linalg.norm(matched[nearest] - points, axis=1)
    reach = np.linalg.norm(nodes[nearest] - points, axis=1)
    return np.where(gap < reach, nearest, _kdtree(nodes).query(points)[1])


def _reach(vertices, nodes, follow=FOLLOW):
    """Which nodes each vertex follows, and how much: its :data:`FOLLOW` nearest, Gaussian-
    weighted, as ``(index (V, k), weights (V, k))`` for :func:`_carry`."""
    k = min(follow, len(nodes))
    distance, index = _kdtree(nodes).query(vertices, k=k)
    distance, index = distance.reshape(len(vertices), k), index.reshape(len(vertices), k)
    scale = np.maximum(distance[:, -1:], 1e-9)
    weights = np.exp(-2.0 * (distance / scale) ** 2)
    weights /= weights.sum(axis=1, keepdims=True)
    return index, weights


def _carry(reach, shift):
    """The nodes' displacement ``shift`` carried to the vertices of ``reach`` (:func:`_reach`)."""
    index, weights = reach
    return np.einsum("vk,vkd->vd", weights, shift[index]).astype(np.float32)


class BlendRun:
    """The in-between frames of one transition and the steps they make.

    Attributes
    ----------
    frames : list of tuple
        ``(positions (N, 3) float32, colours (N, 3) uint8, faces (M, 3) uint32, normals (N, 3)
        float32, side)`` per in-between frame, in play order; ``side`` is 0 for a frame warped
        from the outgoing frame, 1 from the incoming one.
    steps : list of float
        Chamfer distance of every displayed step from the exit frame to the entry frame
        (``len(frames) + 1`` of them, every 4th vertex averaged as in :func:`texton_steps`).
    jump : float
        Chamfer distance of the cut itself (exit frame to entry frame).
    fit : dict
        A blended transition's ``{"colour", "chosen_at"}``: whether :func:`blend` kept the fit
        by colour, and on what count it chose; ``{}`` for a cut or a loop's closing. With the
        two frames and the count it says what the run's frames are (``blends.json`` keeps it).
    """

    def __init__(self, frames, steps, jump, fit=None):
        self.frames, self.steps, self.jump, self.fit = frames, steps, jump, fit or {}

    def __len__(self):
        return len(self.frames)


def _warp(mesh, field, amount, side):
    """``(positions, colours, faces, side)`` of ``mesh`` moved by ``amount`` times ``field`` (V, 3)."""
    positions = (np.asarray(mesh[0], np.float32) + np.float32(amount) * field).astype(np.float32)
    return positions, np.asarray(mesh[1], np.uint8), np.asarray(mesh[2], np.uint32), side


def _finished(run):
    """``run`` with every in-between frame's vertex normals, computed once it is chosen."""
    run.frames = [(p, c, f, vertex_normals(p, f), s) for p, c, f, s in run.frames]
    return run


def side(index, count):
    """Which frame the ``index``-th (0-based) of ``count`` in-between frames is warped from:
    0 the outgoing (exit) frame, 1 the incoming (entry) frame. Its time is
    ``t = (index + 1) / (count + 1)``; the cut is at ``t = 1/2``.

    >>> [side(i, 3) for i in range(3)], [side(i, 2) for i in range(2)]
    ([0, 1, 1], [0, 1])
    """
    return 0 if 2 * (index + 1) < count + 1 else 1


def _run(outgoing, incoming, fields, count):
    """The ``count`` in-between frames at times ``k / (count + 1)``, cut at the middle: the
    outgoing frame moved ``t`` of the way by ``fields[0]``, then the incoming frame moved back
    by ``2 (1 - t)`` times ``fields[1]``, which lays it on the outgoing frame's half-way warp."""
    frames = []
    for index in range(count):
        t = (index + 1) / (count + 1)
        if side(index, count) == 0:
            frames.append(_warp(outgoing, fields[0], t, 0))
        else:
            frames.append(_warp(incoming, fields[1], 2.0 * (1.0 - t), 1))
    return frames


def fields_of(a, b, seed=0, colours=None, carriers=None):
    """The two fields of a run from ``a`` to ``b``: ``a`` laid onto ``b``, and ``b`` laid onto
    the half-way surface ``a + field / 2``, not onto ``a``.

    Two fields fitted apart (``a`` onto ``b``, ``b`` onto ``a``) disagree where the fit is
    poor, and the run switches from one to the other in its middle: there a forearm the fits
    carried differently jumps, a few hundred vertices moving far while the mean step stays
    small. Fitting the second onto the first one's middle makes the two warps meet where the
    run switches, to the residual of one fit between surfaces half as far apart.

    ``colours``, ``(a's, b's)`` uint8, match points by colour as well (:func:`align`);
    ``carriers``, ``a``'s and ``b``'s nodes (:class:`_Carrier`), where another fit made them."""
    carriers = carriers or (None, None)
    forward = align(a, b, seed, colours=colours, carrier=carriers[0])
    return forward, align(b, a + 0.5 * forward, seed, colours=None if colours is None else colours[::-1],
                          carrier=carriers[1])


def _steps(ends, frames, stop=None):
    """Chamfer steps from the exit frame through ``frames`` to the entry frame, and their
    99th percentiles; ``ends`` holds ``(points, tree)`` of the exit and entry frames (built
    once per transition). With ``stop``, None as soon as one step reaches it: the middle step,
    where the run switches from one frame's warp to the other's and the fields' residual
    shows, is measured first, so a count that would not help is told by one step rather than
    all (the same answer, sooner)."""
    points = [ends[0][0], *(f[0] for f in frames), ends[1][0]]
    trees = {0: ends[0][1], len(points) - 1: ends[1][1]}
    steps, tails = [0.0] * (len(points) - 1), [0.0] * (len(points) - 1)
    for i in sorted(range(len(steps)), key=lambda i: abs(2 * i + 1 - len(steps))):
        for k in (i, i + 1):
            if k not in trees:
                trees[k] = _kdtree(points[k])
        steps[i], tails[i] = chamfer_and_tail(points[i], points[i + 1], trees[i], trees[i + 1], stride=4)
        if stop is not None and steps[i] >= stop:
            return None
    return steps, tails


def check_count(count):
    """``count`` in-between frames per transition as given (None: as each needs), checked.

    >>> check_count(None), check_count(3.0)
    (None, 3)
    """
    if count is None:
        return None
    from ..checks import whole

    return whole("blend_frames", count, at_least=0, at_most=MAX_FRAMES,
                 hint=" (None: as many as each transition needs)")


def frame_count(jump, natural):
    """In-between frames that bring a cut of Chamfer ``jump`` down to steps of ``natural``.

    >>> frame_count(0.05, 0.02), frame_count(0.01, 0.02), frame_count(1.0, 0.02)
    (2, 0, 8)
    """
    if natural <= 0:
        return 0
    return int(np.clip(np.ceil(jump / natural) - 1, 0, MAX_FRAMES))


def blend(outgoing, incoming, natural, count=None, seed=0, tail=None):
    """In-between frames from the exit frame ``outgoing`` to the entry frame ``incoming``.

    Parameters
    ----------
    outgoing, incoming : tuple
        ``(positions (N, 3), colours (N, 3) uint8, faces (M, 3))`` of the two frames.
    natural : float
        The natural step (metres): the largest step the run should make.
    count : int or None
        In-between frames to make; None: the fewest (up to :data:`MAX_FRAMES`) whose steps
        all stay at or below ``natural``; 0 makes none (the paper's cut).
    seed : int
        Seed of :func:`align`'s sampling.
    tail : float or None
        The natural step's 99th percentile (:func:`chamfer_and_tail`): with no ``count``
        given, the run also takes frames until no step's 99th percentile exceeds it, so that
        no limb jumps where the mean stays small.

    Returns
    -------
    BlendRun
        Made with the fields fitted by position and colour (:func:`fields_of`), or by
        position alone where that gives the smaller largest steps (:func:`_largest`) on a run
        of the first count of frames; its ``fit`` says which and on what count.

    The fit by position is made only where the run fitted by colour has a step whose 99th
    percentile exceeds the cut's shared evenly over the run (the cut's over the count plus
    one). The fit by position steps about that evenly: 0.87-1.44x of it (median 1.03x)
    on 57 transitions of seven libraries (13_29, 13_30, the gym, three HDM05 takes, a 20 fps
    take), 2.7x and 4.7x on the scvv card's two. There it could be kept only for a smaller
    colour-matched step, which it gave on none of the 14 transitions this skips (one would have
    kept it for a product 5 % smaller, its colour-matched step 3 % larger). Blending costs a
    quarter less (13_29, 13_30 and the gym).
    """
    a, b = np.asarray(outgoing[0]), np.asarray(incoming[0])
    ends = ((a, _kdtree(a)), (b, _kdtree(b)))
    jump, cut_tail = chamfer_and_tail(a, b, ends[0][1], ends[1][1], stride=4)
    if count == 0 or (count is None and jump <= natural and (tail is None or cut_tail <= tail)):
        return BlendRun([], [jump], jump)
    n = max(frame_count(jump, natural), 1) if count is None else count
    carriers = (_Carrier(a, seed), _Carrier(b, seed))

    def made(colour):
        fields = fields_of(a, b, seed, (outgoing[1], incoming[1]) if colour else None, carriers)
        frames = _run(outgoing, incoming, fields, n)
        return colour, fields, frames, _steps(ends, frames)

    chosen = made(True)
    if max(chosen[3][1]) > cut_tail / (n + 1):   # steps less evenly than the cut allows
        looks = [coloured_points(*mesh[:2]) for mesh in (outgoing, incoming)]
        looks = [(p, _kdtree(p)) for p in looks]
        chosen = min((chosen, made(False)), key=lambda made: np.prod(_largest(looks, made[2], made[3][1])))
    colour, fields, frames, measured = chosen
    run = _counted(outgoing, incoming, ends, fields, jump, natural, count, tail, n, (frames, measured))
    run.fit = {"colour": colour, "chosen_at": n}
    return _finished(run)


def _counted(outgoing, incoming, ends, fields, jump, natural, count, tail, n, first):
    """The run of :func:`blend` made with ``fields``: ``count`` frames, or (None) the fewest
    from ``n`` on that keep every step within ``natural`` and ``tail``; ``first`` holds the
    frames of ``n`` and their steps (:func:`_steps`), already made."""
    previous = None
    frames, measured = first
    while True:
        if measured is None:
            return previous  # the cut's own residual dominates: more frames would not help
        run = BlendRun(frames, measured[0], jump)
        within = max(measured[0]) <= natural and (tail is None or max(measured[1]) <= tail)
        if count is not None or within or n >= MAX_FRAMES:
            return run
        previous, n = run, n + 1
        frames = _run(outgoing, incoming, fields, n)
        measured = _steps(ends, frames, 0.95 * max(previous.steps))


def _largest(ends, frames, tails):
    """The largest step of a run of ``frames`` (its steps' 99th percentiles ``tails``) by the 99th
    percentile of the vertices' distances to the other frame, ``(by position alone, by
    position and colour)`` (:func:`coloured_points`, every 4th vertex both ways): a run whose
    limb jumps along the body moves vertices far by the second; one whose fit sheared a
    textured surface (colours matched to like colours of a print nearby) by the first.
    :func:`blend` keeps the fit whose run of its first count of frames has the smaller two by
    their product, so that each counts by its ratio whatever its units: a fit by colour that
    halves the second and leaves the first as it was is kept (CMU 13_30), one that lowers the
    second by 1 % and raises the first by 70 % is not (the scvv card). ``ends`` holds the two
    ends' coloured points and k-d trees, made once for both fits."""
    points = [ends[0][0], *(coloured_points(*mesh[:2]) for mesh in frames), ends[1][0]]
    trees = [ends[0][1], *(_kdtree(p) for p in points[1:-1]), ends[1][1]]
    matched = [matched_both_ways((points[k][::4], trees[k]), (points[k + 1][::4], trees[k + 1]))
               for k in range(len(points) - 1)]
    return max(tails), max(matched)
