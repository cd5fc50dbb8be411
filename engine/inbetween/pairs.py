"""Where a transition joins two textons: of the frame pairs that eq. (10) all but ties, the pair
whose bodies look alike.

Eq. (10) leaves texton ``i`` at frame ``t_i*`` and enters texton ``j`` at ``t_j*``, the pair of
their frames whose feature vectors are nearest. The spherical histograms of eq. (1)-(4) say how
the body's surface spreads about the sequence's origin, not where each limb is: forearms
crossed before the chest and a hand raised to the face spread alike. Near the minimum, many
pairs of frames differ in their distance by less than the histograms' own noise, and the one
eq. (10) picks may put the arms far apart. No blend carries a forearm from the chest to the
face without a jump where the run switches from one frame's warp to the other's
(:mod:`tvmedit.engine.inbetween.blend`): a non-rigid fit lays each surface on the nearest part
of the other, and nothing tells it which part is the forearm.

The rule: among the pairs of the exit and entry ranges (:func:`tvmedit.engine.graph.motiongraph.exit_range`,
``entry_range``) whose feature distance is at most ``1 +`` :data:`TIE` times eq. (10)'s, the
:data:`MOST` nearest by it, the transition is made at the pair whose bodies are nearest by
:func:`pose_distance` (positions and colours matched both ways, as
:func:`tvmedit.engine.inbetween.instants.matched_tail` measures a step), and at eq. (10)'s own
pair unless another is nearer by at least ``1 -`` :data:`KEEP`. The graph's weights stay eq.
(12)'s, from eq. (10)'s distance: pruning, connection, paths and their costs are the paper's;
only where the transitions chosen are made moves, to a pair that costs at most :data:`TIE`
more by the features.

Measured (``benchmarks/display_rate.py``, CMU 13_29 and 13_30 at 10 fps through mocap2tvm and
the synthetic gym): the largest step of a blended transition, each point matched to the
nearest point of the other frame that looks alike, over the natural step by the same measure,
fell from 1.98x to 1.18x on 13_29 (transitions over 1.25x: none of 16, four before), from 3.65x
to 2.35x on 13_30 (six of ten over, eight before) and from 0.84x to 0.77x on the gym; point to
surface and at 60 fps every figure stays within its bar. Looked at in 1280x960 frames: 13_29's
06->05 turns one forearm a little at the switch; 13_30's 02->03 still moves a forearm from
before the body to the face there (its two textons share no pose with the arms alike), a
shorter jump than before, and its first frame warped back from the entry smears a foot.
Pairs within 10 % of the minimum held no better pose on 13_30's 02->03; within 25 % they did.
Choosing costs a build 0.25-0.27 s on those takes and 0.23 s on 13_29 at 60 fps, whose
candidates are a tenth of a second apart (:func:`stride`; 4 of its 16 transitions move, by a
tenth of a second to a fifth); :data:`SAMPLE` points a frame, at most :data:`MOST` pairs a
transition.
"""

import numpy as np

from .blend import matched_both_ways
from .fit import coloured_points, kdtree

__all__ = ["TIE", "MOST", "SAMPLE", "KEEP", "candidates", "stride", "pose_points", "pose_distance", "best_join"]

#: Pairs whose feature distance is within this share of eq. (10)'s minimum are candidates.
TIE = 0.25
#: Most candidate pairs a transition looks at (the nearest by feature distance).
MOST = 64
#: Points of a frame its pose is compared on (spread over its vertices).
SAMPLE = 400
#: Eq. (10)'s own pair is kept unless another's pose distance is below this share of its own.
KEEP = 0.8


def candidates(distances, chosen, most=MOST, tie=TIE, strides=(1, 1)):
    """Candidate pairs ``(row, column)`` of the feature ``distances`` between the exit range's
    frames (rows) and the entry range's (columns): those within ``tie`` of the distance at
    ``chosen`` (eq. (10)'s pair, always first), nearest first, at most ``most``; with
    ``strides``, only rows and columns a whole number of strides from ``chosen``'s.

    Neighbouring frames of a 60 fps capture have all but equal features, so the pairs nearest
    by them lie within a few frames of eq. (10)'s: a stride of :func:`stride` frames looks at
    the capture as at 10 fps, the same span of time for the same number of pairs.

    >>> d = np.array([[1.0, 1.2], [3.0, 1.1]])
    >>> candidates(d, (0, 0)), candidates(d, (0, 0), strides=(2, 1))
    ([(0, 0), (1, 1), (0, 1)], [(0, 0), (0, 1)])
    """
    distances = np.asarray(distances, dtype=np.float64)
    limit = (1.0 + tie) * distances[chosen]
    near = distances <= limit
    near[(np.arange(near.shape[0]) - chosen[0]) % strides[0] != 0, :] = False
    near[:, (np.arange(near.shape[1]) - chosen[1]) % strides[1] != 0] = False
    rows, columns = np.nonzero(near)
    order = np.argsort(distances[rows, columns], kind="stable")
    pairs = [(int(rows[k]), int(columns[k])) for k in order if (rows[k], columns[k]) != tuple(chosen)]
    return [tuple(int(x) for x in chosen)] + pairs[:most - 1]


def stride(fps):
    """Frames between candidate frames of a capture at ``fps``: about a tenth of a second.

    >>> stride(10), stride(29.97), stride(60)
    (1, 3, 6)
    """
    return max(1, int(round(fps / 10.0)))


def pose_points(positions, colours, sample=SAMPLE):
    """``(points, tree)`` of a frame's pose: ``sample`` of its vertices spread over its index
    order (a reconstruction lists them surface patch by surface patch), each as position and
    colour (:func:`tvmedit.engine.inbetween.fit.coloured_points`), and their k-d tree."""
    positions = np.asarray(positions)
    index = np.linspace(0, len(positions) - 1, min(sample, len(positions))).astype(np.intp)
    points = coloured_points(positions[index], np.asarray(colours).reshape(len(positions), -1)[index])
    return points, kdtree(points)


def pose_distance(a, b):
    """How far apart two poses (:func:`pose_points`) are: the 99th percentile of each point's
    distance to the nearest point of the other that looks alike, both ways (metres), as
    :func:`tvmedit.engine.inbetween.instants.matched_tail` measures a step.

    >>> p = np.random.default_rng(0).random((50, 3)); c = np.full((50, 3), 128)
    >>> pose_distance(pose_points(p, c), pose_points(p, c)), pose_distance(pose_points(p, c), pose_points(p + 1, c)) > 0.5
    (0.0, True)
    """
    return matched_both_ways(a, b)


def best_join(pairs, pose, keep=KEEP):
    """The pair of ``pairs`` (eq. (10)'s first) where the transition is made: the one whose
    poses are nearest, ``pose(exit, entry)`` (:func:`pose_distance`), or the first unless
    another is nearer than ``keep`` times it.

    >>> best_join([(0, 0), (1, 1), (2, 2)], lambda a, b: {0: 1.0, 1: 0.9, 2: 0.5}[a])
    (2, 2)
    >>> best_join([(0, 0), (1, 1)], lambda a, b: {0: 1.0, 1: 0.9}[a])
    (0, 0)
    """
    first = pose(*pairs[0])
    best, nearest = pairs[0], first
    for pair in pairs[1:]:
        distance = pose(*pair)
        if distance < nearest:
            best, nearest = pair, distance
    return best if nearest < keep * first else pairs[0]
