"""The non-rigid fit that lays one reconstruction onto another: one alignment for every step.

A transition's run (:mod:`.blend`), a loop's closing (:mod:`.loops`) and a display step
(:mod:`.instants`) each move one captured frame onto another of different vertices and
triangles. :func:`align` gives the smooth displacement of every vertex that does it.

Why this method, written here: Prada et al. (2016) blend meshes without correspondence by
surface alignment. trimesh's ``registration`` module, the kept library that comes nearest, fits
rigidly (ICP) or deforms a template by non-rigid ICP (``nricp_amberg``, ``nricp_sumner``),
which solve a sparse system over every vertex at every step and match by position alone; a fit
here smooths over 1,500 nodes and may match by colour. scipy's ``cKDTree`` gives the nearest
points and its sparse matrices the smoothing.

The field is fitted as non-rigid ICP with symmetric forces, coarse to fine over the radii
:data:`SIGMAS`, :data:`STEPS` iterations each. Nodes sampled from the moving surface carry
the displacement (:data:`NODES` at the finest radius, as many per radius-wide patch at the
coarser ones, at least :data:`MIN_NODES`; each level starts from the coarser one's field).
In each iteration every node is pulled toward its nearest point of the other surface, and
every one of :data:`TARGET_POINTS` points of the other surface pulls its nearest node toward
itself; the pulls are summed over the nodes with a Gaussian of the radius and divided by the
summed weights (normalised convolution), so the many points of a limb that moved drag its few
nearest nodes, and the limb, along. Vertices follow their :data:`FOLLOW` nearest nodes,
Gaussian-weighted (:class:`Carrier` keeps what depends on the nodes alone, for a second fit of
the same frame).

"Nearest" is measured by position, or by position and colour together (``colours``;
:func:`coloured_points`, a colour difference of 1 weighing :data:`COLOUR_METRES`), as coloured
ICP does (Park, Zhou and Koltun, ICCV 2017). By position alone, a forearm that leaves the chest
finds the chest it lies on and is laid flat onto the shirt, and a transition's run switches to
the incoming frame's forearm in one step (CMU 13_30's transitions stepped up to 2.35x the
natural step measured by colour, the forearms seen smeared into the shirt at 1280x960);
matched by colour, its skin finds the other frame's skin. Colour misleads too: a face and a
hand are both skin, so a point's pull on the node that looks like it is kept only where it
agrees with that node's own match (:func:`_consistent`: without it, a face was drawn down onto
hands raised before the chin, on an HDM05 take); and a textured capture's colours repeat over
its print and change with the light, so on the scvv card a fit by colour can shear the print.
:func:`tvmedit.engine.inbetween.blend.blend` weighs the two fits for each transition.
"""

import numpy as np

__all__ = ["NODES", "MIN_NODES", "LEVEL_DENSITY", "TARGET_POINTS", "SIGMAS", "STEPS", "FOLLOW", "COLOUR_METRES",
           "coloured_points", "kdtree", "align", "Carrier"]

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


def kdtree(points):
    """scipy's k-d tree of ``points`` (N, 3 or 6), imported on first use: an edit's schedule
    needs :func:`tvmedit.engine.inbetween.blend.side`, and the player must start without
    loading scipy."""
    from scipy.spatial import cKDTree

    # Unbalanced: quicker to build, and the queries give the same answers. Compacted (each
    # node's box shrunk to its points): a display step's field queries a tree some 40,000
    # times, and the tighter boxes make the whole fit 9 % faster for 0.3 ms more a tree build
    # (fields identical on 49 display steps of CMU 13_29).
    return cKDTree(points, balanced_tree=False, compact_nodes=True)


def _sample(points, count, seed):
    """``count`` rows of ``points`` spread over the surface (a seeded random choice)."""
    if len(points) <= count:
        return np.arange(len(points))
    return np.sort(np.random.default_rng(seed).choice(len(points), count, replace=False))


def _smoother(nodes, sigma):
    """The (n, n) sparse Gaussian kernel between distinct nodes, cut at two ``sigma`` (the
    node itself is added by the caller): a COO matrix, built and applied without sorting."""
    from scipy import sparse

    tree = kdtree(nodes)
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
    carrier : Carrier, optional
        ``moving``'s nodes (made with the same ``seed``, ``nodes`` and ``follow``) and what
        depends on them alone, where another fit of ``moving`` made them:
        :func:`tvmedit.engine.inbetween.blend.blend` may fit each frame twice, and the second
        fit takes them from the first.

    Returns
    -------
    (N, 3) float32
        ``moving + result`` lies on ``still``'s surface (to a few millimetres).
    """
    moving = np.asarray(moving, dtype=np.float64)
    still = np.asarray(still, dtype=np.float64)
    carrier = Carrier(moving, seed, nodes, follow) if carrier is None else carrier
    picked = _sample(still, TARGET_POINTS, seed + 1)
    pulls = still[picked]
    if colours is None:
        targets, looks = pulls, None
        still_tree = kdtree(still) if still_tree is None else still_tree
    else:  # matched in position and colour: (N, 6) points, a node's look its vertex's colour
        seen = coloured_points(still, colours[1])
        targets, looks = seen[picked], coloured_points(moving, colours[0])[carrier.order, 3:]
        still_tree = kdtree(seen)
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
            nearest = kdtree(seen).query(targets)[1]
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


class Carrier:
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
    return np.where(gap < reach, nearest, kdtree(nodes).query(points)[1])


def _reach(vertices, nodes, follow=FOLLOW):
    """Which nodes each vertex follows, and how much: its :data:`FOLLOW` nearest, Gaussian-
    weighted, as ``(index (V, k), weights (V, k))`` for :func:`_carry`."""
    k = min(follow, len(nodes))
    distance, index = kdtree(nodes).query(vertices, k=k)
    distance, index = distance.reshape(len(vertices), k), index.reshape(len(vertices), k)
    scale = np.maximum(distance[:, -1:], 1e-9)
    weights = np.exp(-2.0 * (distance / scale) ** 2)
    weights /= weights.sum(axis=1, keepdims=True)
    return index, weights


def _carry(reach, shift):
    """The nodes' displacement ``shift`` carried to the vertices of ``reach`` (:func:`_reach`)."""
    index, weights = reach
    return np.einsum("vk,vkd->vd", weights, shift[index]).astype(np.float32)
