"""Frames of reference: which way is up, what the units are, and whether the capture is mirrored.

tvmedit works in one frame: Z up, metres, the subject facing -Y (the default camera's side),
as section 3's spherical coordinates assume (phi measured from +Z, r bins in metres).
Captures arrive in their own frames: glTF is Y up; a depth camera writes its own coordinates
(looking along +Z, image down along +Y, the subject facing the camera); exporters write
millimetres or centimetres. :func:`detect` works out the frame of a sequence and says why,
and :class:`Orientation` maps it to tvmedit's at load time, so features, camera framing,
player and report all see the subject the same way whatever frame it came in.

How up is found, in order:

1. ``up`` given by the user (``--up +y``).
2. The format's convention: glTF is Y up (its specification).
3. The body's principal axis over the sequence: the direction of largest spread of the
   vertices of frames sampled across the whole sequence, each frame about its own centre
   (a standing person is several times taller than wide; a bust with its shoulders is still
   taller than deep). Centring each frame keeps the person's path out of it: pooled as they
   lay, the frames of a person crossing the volume spread further along the path than up
   the body. For a depth
   camera (an scvv sequence) up lies across the camera's view axis, so only X and Y are
   considered. An axis within :data:`SNAP_DEGREES` of a coordinate axis is taken as that
   axis; a clearly oblique one (a tilted camera, a rotated export) is used as measured.
   Its sign: the end of the body that holds still over the sequence is the bottom, where
   the feet meet the floor or the body leaves the camera's view, while the head and hands
   move. Where neither end is clearly steadier the positive direction is taken.
4. Otherwise the format's default: Z up, as tvmedit has always read PLY, OBJ and OFF.

Units: the body's extent along up in a frame (the median over the sampled frames); more
than 300 units is millimetres,
more than 3 centimetres, else metres (a person or a bust, in any of the three, falls in one
class only). ``units`` overrides.

Front: the way the subject faces is turned to -Y, the default camera's side. It is given
(``--front -z``), or a depth camera's subject faces the camera (scvv: -Z), or else it is the
convention of the up axis (:func:`_default_front`: +Z for Y up, as glTF and OpenGL face a
model; -Y for Z up, so Z-up data stays as it is). No cue in the vertices was found reliable
enough to overrule that rule: the feet's toes, the head over the neck and the body's third
moment each point the wrong way in a third to a half of the frames of takes whose front is
known (the synthetic gym, CMU 13_29 and 13_30, HDM05). So the rule holds where nothing is
given, ``check`` says which front it chose and how to turn it, and a front given once is kept
by the library (its rebuilds and corrections) and can be stated beside the frames
(``{"front": "-z"}`` in ``sequence.json``).

Mirror: some capture apps store a mirror image of the scene (what a front "selfie" camera
shows its user), so text held up to the camera reads backwards. Nothing in the coordinates
tells, and the scvv capture shared with tvmedit is not mirrored (its card reads correctly
once upright, though the preview image of the app and the raw camera images it textures
with are mirrored), so ``mirror`` is off unless given.

Features in the body's own frame (``body_frame``, ``--body-frame``; the default). Putting a
take upright is not enough for it to parse the same: section 3's histograms move with a tilt
of a degree or two and with a turn about up, and nothing in a take tells which way its Z was.
So features are computed in a frame that is a function of the vertices and turns with them
(:func:`feature_frame`): up is the principal axis of the sampled frames, each about its own
centre (the body's shape, not its path); front-back is the lesser principal axis across up,
signed by its third moment; left-right completes them (so the parser's mirror test still
swaps left and right). A take and any rotation of it in any units then get the same features
to a vertex's share of a bin, and the same clusters and textons. Meshes, camera, player and
report keep the frame detected above either way. A body whose longest axis is not clearly so,
or lies more than :data:`FRAME_DEGREES` from the up chosen (a bust; ``--up`` given against the
body), has no frame of its own and keeps tvmedit's axes; ``--no-body-frame`` asks for them.
"""

import math
from dataclasses import dataclass, field, replace

import numpy as np

from ..features import spread_indices

__all__ = ["Orientation", "detect", "feature_frame", "parse_up", "sample_indices", "AXES", "SNAP_DEGREES", "UNITS",
           "FRAME_DEGREES", "IDENTITY"]

AXES = {"+x": (1.0, 0.0, 0.0), "-x": (-1.0, 0.0, 0.0), "+y": (0.0, 1.0, 0.0),
        "-y": (0.0, -1.0, 0.0), "+z": (0.0, 0.0, 1.0), "-z": (0.0, 0.0, -1.0)}
#: Metres per unit.
UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001}
#: A principal axis this close to a coordinate axis is taken as that axis.
SNAP_DEGREES = 30.0
#: The body's own up (:func:`feature_frame`) is used for features only this close to the up
#: detected or given; further off, that up was chosen against the body's axis on purpose.
FRAME_DEGREES = 10.0
#: How much clearer the principal axis must be than the next (variance ratio) to be trusted.
DOMINANCE = 1.5
#: How much steadier one end must be than the other to tell the bottom.
STEADIER = 1.3
#: Fewest vertices per frame for the body's shape to say anything (test meshes have a few).
MIN_VERTICES = 200
#: Frames sampled across the sequence for detection.
SAMPLES = 12
#: The identity rotation, as :class:`Orientation` holds matrices.
IDENTITY = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
#: Formats whose coordinates are a depth camera's (looking along +Z, facing its user).
DEPTH_CAMERA_FORMATS = ("scvv",)
#: Formats with a fixed up axis.
FORMAT_UP = {"gltf": ("+y", "glTF is Y up (its specification)")}


def parse_up(text, what="up"):
    """A unit vector from ``+x`` ... ``-z`` (or ``x``, ``Y``...): an up axis, or ``what`` it is.

    >>> parse_up("-y").tolist(), parse_up("Z").tolist()
    ([0.0, -1.0, 0.0], [0.0, 0.0, 1.0])
    """
    key = str(text).strip().lower()
    key = key if key[:1] in "+-" else "+" + key
    if key not in AXES:
        raise ValueError(f"{what} must be one of {', '.join(AXES)}, not {text!r}")
    return np.array(AXES[key])


def _nearest_axis(vector):
    """The name of the coordinate axis nearest ``vector`` (what ``--front`` takes).

    >>> _nearest_axis([0.2, -0.9, 0.1])
    '-y'
    """
    return max(AXES, key=lambda name: float(np.dot(AXES[name], vector)))


def _rows(matrix):
    """A 3x3 matrix as a tuple of row tuples of floats (how :class:`Orientation` holds one)."""
    return tuple(tuple(float(v) for v in row) for row in matrix)


def sample_indices(n):
    """Indices of the (up to :data:`SAMPLES`) frames, spread over a sequence of ``n``, that its
    frame of reference is detected from.

    >>> sample_indices(5).tolist(), len(sample_indices(1000))
    ([0, 1, 2, 3, 4], 12)
    """
    return spread_indices(n, SAMPLES)


def _axis_name(vector):
    for name, axis in AXES.items():
        if np.allclose(vector, axis):
            return name
    return "(" + ", ".join(f"{v:+.2f}" for v in vector) + ")"


@dataclass(frozen=True)
class Orientation:
    """The map from a capture's coordinates to tvmedit's (Z up, metres, facing -Y).

    ``p_tvmedit = scale * matrix @ p_file``. ``matrix`` is a rotation, or a reflection when
    the capture is mirrored (then triangles are re-wound so that they keep facing out).

    Attributes
    ----------
    matrix : tuple of 3 tuples of 3 floats
    scale : float, metres per unit
    up : str, the file's up axis (``"+y"``, or a vector where oblique)
    units : str, ``"m"``, ``"cm"`` or ``"mm"``
    mirrored : bool
    reasons : dict, ``{"up": ..., "units": ..., "mirror": ..., "features": ...}``: why, in words
    features : tuple of 3 tuples of 3 floats
        The rotation from tvmedit's frame to the body's own (:func:`feature_frame`), in which
        features are computed (:meth:`for_features`); the identity where there is none.

    >>> o = Orientation.make(parse_up("+y"), front=(0, 0, 1), units="mm")
    >>> o.apply(np.array([[0.0, 1000.0, 0.0], [0.0, 0.0, 1000.0]])).round(6).tolist()
    [[0.0, 0.0, 1.0], [0.0, -1.0, 0.0]]
    >>> Orientation().is_identity
    True
    """

    matrix: tuple = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    scale: float = 1.0
    up: str = "+z"
    units: str = "m"
    mirrored: bool = False
    reasons: dict = field(default_factory=dict, compare=False, hash=False)
    features: tuple = IDENTITY

    @property
    def front(self):
        """The coordinate axis nearest the way the subject faces, in the file's coordinates:
        ``"+z"`` ... (what ``--front`` takes; across an oblique up, the front is that axis
        made square to it)."""
        return _nearest_axis(-np.asarray(self.matrix[1]))

    @classmethod
    def make(cls, up, front=None, units="m", mirrored=False, reasons=None):
        """The orientation that takes ``up`` to +Z and ``front`` (the way the subject faces,
        default: chosen so that Z-up data stays as it is) to -Y."""
        up = np.asarray(up, dtype=np.float64)
        up = up / np.linalg.norm(up)
        if front is None:
            front = _default_front(up)
        front = np.asarray(front, dtype=np.float64)
        front = front - up * float(front @ up)
        if np.linalg.norm(front) < 1e-6:
            front = _default_front(up) - up * float(_default_front(up) @ up)
        front /= np.linalg.norm(front)
        ey = -front
        ex = np.cross(ey, up)
        if mirrored:
            ex = -ex
        matrix = np.array([ex, ey, up])
        matrix[np.abs(matrix) < 1e-12] = 0.0
        return cls(_rows(matrix), UNITS[units], _axis_name(up), units, bool(mirrored), dict(reasons or {}))

    @property
    def is_identity(self):
        return self.scale == 1.0 and np.array_equal(np.array(self.matrix), np.eye(3))

    def apply(self, positions):
        """Positions (N, 3) in the file's frame -> tvmedit's, float32."""
        if self.is_identity:
            return positions
        m = np.asarray(self.matrix, dtype=np.float64) * self.scale
        return (np.asarray(positions, dtype=np.float64) @ m.T).astype(np.float32)

    def apply_faces(self, faces):
        """Triangles re-wound when the map is a reflection, so their normals still face out."""
        return faces[:, ::-1] if self.mirrored else faces

    def same_coordinates(self, other):
        """Whether ``other`` (an Orientation, or None for the identity) takes the same file
        coordinates to tvmedit's: the same matrix, scale and mirror, whatever the body frame
        features are computed in. Frames read with either go back to their files alike.

        >>> Orientation().same_coordinates(None), Orientation(scale=0.001).same_coordinates(Orientation())
        (True, False)
        """
        other = Orientation() if other is None else other
        return (self.matrix, self.scale, self.mirrored) == (other.matrix, other.scale, other.mirrored)

    def undo(self, positions, faces):
        """``(positions float32, faces)`` of a frame in tvmedit's frame taken back to the file's
        coordinates and units (what an export in a capture's format writes).

        >>> o = Orientation.make(parse_up("+y"), units="mm")
        >>> p, f = o.undo(o.apply(np.array([[1.0, 2.0, 3.0]])), np.array([[0, 1, 2]]))
        >>> p.round(3).tolist(), f.tolist()
        ([[1.0, 2.0, 3.0]], [[0, 1, 2]])
        """
        matrix = np.asarray(self.matrix, dtype=np.float64) * self.scale
        positions = np.asarray(positions, dtype=np.float64) @ np.linalg.inv(matrix).T
        return positions.astype(np.float32), self.apply_faces(np.asarray(faces))

    def for_features(self):
        """The map from the file's coordinates to the body's own frame, where features are
        computed: this one followed by :attr:`features` (an :class:`Orientation` itself, for
        :func:`tvmedit.engine.capture.load.read_frame`)."""
        combined = np.asarray(self.features) @ np.asarray(self.matrix)
        return Orientation(_rows(combined), self.scale, self.up, self.units, self.mirrored, dict(self.reasons))

    def to_json(self):
        return {"matrix": [list(row) for row in self.matrix], "scale": self.scale, "up": self.up,
                "units": self.units, "mirrored": self.mirrored, "reasons": dict(self.reasons),
                "features": [list(row) for row in self.features]}

    @classmethod
    def from_json(cls, data):
        return cls(_rows(data["matrix"]), float(data["scale"]), data["up"], data["units"], bool(data["mirrored"]),
                   dict(data.get("reasons", {})), _rows(data.get("features", IDENTITY)))

    def describe(self):
        """One line per decision, for ``tvmedit check``."""
        lines = [f"up axis: {self.up} ({self.reasons.get('up', 'given')})",
                 f"units: {self.units} ({self.reasons.get('units', 'given')})"]
        if "front" in self.reasons:
            lines.append(f"front: {self.front} ({self.reasons['front']})")
        if self.mirrored or "mirror" in self.reasons:
            lines.append(f"mirrored: {'yes' if self.mirrored else 'no'} ({self.reasons.get('mirror', 'given')})")
        if "features" in self.reasons:
            lines.append(f"features computed in {self.reasons['features']}")
        return lines


def _default_front(up):
    """The way a subject faces in the usual convention of its up axis: +Z for Y up (glTF,
    OpenGL), -Z for Y down (a camera facing the subject), else -Y (so Z-up data stays as it is)."""
    if abs(up[1]) >= math.cos(math.radians(SNAP_DEGREES)):
        return np.array([0.0, 0.0, math.copysign(1.0, up[1])])
    return np.array([0.0, -1.0, 0.0])


def _principal(points, axes):
    """Unit principal direction of ``points`` within the coordinate ``axes`` and how clearly it
    leads (variance ratio of the first to the second direction)."""
    sub = points[:, axes] - points[:, axes].mean(axis=0)
    values, vectors = np.linalg.eigh(np.cov(sub.T))
    direction = np.zeros(3)
    direction[axes] = vectors[:, -1]
    ratio = values[-1] / max(values[-2], 1e-18)
    return direction, ratio


def _snap(direction, axes):
    best = max(axes, key=lambda a: abs(direction[a]))
    angle = math.degrees(math.acos(min(1.0, abs(direction[best]))))
    if angle <= SNAP_DEGREES:
        snapped = np.zeros(3)
        snapped[best] = 1.0 if direction[best] >= 0 else -1.0
        return snapped, angle
    return direction / np.linalg.norm(direction), angle


def _ends(frames, direction):
    """Std over frames of the low and the high end (2nd and 98th percentiles) along ``direction``."""
    lows, highs = [], []
    for positions in frames:
        t = np.asarray(positions, dtype=np.float64) @ direction
        k = max(0, int(0.02 * (len(t) - 1)))
        part = np.partition(t, (k, len(t) - 1 - k))
        lows.append(part[k])
        highs.append(part[len(t) - 1 - k])
    return float(np.std(lows)), float(np.std(highs))


def _front(front, direction, depth_camera, reasons):
    """The way the subject faces (file coordinates) and why (``reasons["front"]``): ``front``
    given, a depth camera's, or the convention of ``direction`` up."""
    if front is not None:
        vector = parse_up(front, "front")
        if not _across(vector, direction):
            turns = [name for name, axis in AXES.items() if _across(np.array(axis), direction)]
            raise ValueError(f"the front {front} lies along the up axis {_axis_name(direction)}; a front "
                             f"must lie across it: {', '.join(turns)}")
        reasons["front"] = "given"
        return vector
    if depth_camera:
        vector, why = np.array([0.0, 0.0, -1.0]), "a depth camera's subject faces it"  # the camera at the origin
    else:
        vector, why = _default_front(direction), f"the convention of {_axis_name(direction)} up, not found in the body"
    square = vector - direction * float(vector @ direction)   # as Orientation.make turns it
    reasons["front"] = f"{why}; if the render shows a back, set --front {_nearest_axis(-square)}"
    return vector


def _across(front, up):
    """Whether ``front`` lies far enough across ``up`` to be made square to it (the two at
    least :data:`SNAP_DEGREES` apart, as a front given along an oblique up may be)."""
    return abs(float(np.dot(front, up))) <= math.cos(math.radians(SNAP_DEGREES))


def detect(frames, format=None, up=None, units=None, mirror=None, body_frame=True, front=None):
    """The :class:`Orientation` of a sequence from a sample of its frames, with the reasons.

    Parameters
    ----------
    frames : list of (N, 3) arrays
        Vertex positions of frames sampled across the sequence, in the file's coordinates.
    format : str or None
        ``"gltf"``, ``"scvv"``, ``"ply"``...: its convention is used where it has one.
    up : str or None
        ``"+x"`` ... ``"-z"``: the user's answer, taken as it is.
    units : str or None
        ``"m"``, ``"cm"`` or ``"mm"``: likewise.
    mirror : bool or None
        Mirror the capture back (left-right); default: no.
    front : str or None
        ``"+x"`` ... ``"-z"``: the way the subject faces, across up; default: a depth camera's
        subject faces it, else the convention of the up axis.
    body_frame : bool
        Compute features in the body's own frame (:func:`feature_frame`), so that the take
        parses alike however it is turned (the default); False: in tvmedit's axes. Either
        way the body's frame is measured and reported (``reasons["features"]``).

    Returns
    -------
    Orientation

    Examples
    --------
    A column along -Y, in millimetres, that crouches and stands: its top (far along -Y)
    moves, its bottom stays on the floor at y = 0:

    >>> rng = np.random.default_rng(0)
    >>> frames = []
    >>> for k in range(10):
    ...     height = 1.8 - 0.4 * (k % 3) / 2
    ...     frames.append(rng.uniform([-0.2, -height, -0.1], [0.2, 0.0, 0.1], (500, 3)) * 1000)
    >>> o = detect(frames)
    >>> o.up, o.units
    ('-y', 'mm')
    >>> bool(o.apply(frames[0]).max(axis=0)[2] > 1.7)
    True
    """
    reasons = {}
    depth_camera = format in DEPTH_CAMERA_FORMATS
    frames = [np.asarray(f, dtype=np.float64) for f in frames if len(f)]
    if up is not None:
        direction = parse_up(up)
        reasons["up"] = "given"
    elif format in FORMAT_UP:
        name, why = FORMAT_UP[format]
        direction = parse_up(name)
        reasons["up"] = why
    else:
        direction, reasons["up"] = _detect_up(frames, depth_camera)
    front = _front(front, direction, depth_camera, reasons)
    if units is None:
        units, reasons["units"] = _detect_units(frames, direction)
    else:
        reasons["units"] = "given"
    if mirror is None:
        mirror = False
    else:
        reasons["mirror"] = "given"
    orientation = Orientation.make(direction, front=front, units=units, mirrored=mirror, reasons=reasons)
    matrix, body = feature_frame([orientation.apply(f) for f in frames])
    found = not np.array_equal(matrix, np.eye(3))
    if not body_frame:
        matrix = np.eye(3)
        reasons["features"] = ("tvmedit's axes, as asked (" + ("the body's own frame would be: " if found
                               else "the body has no frame of its own: ") + body + ")")
    else:
        reasons["features"] = (f"the body's own frame: {body}" if found
                               else f"tvmedit's axes (no frame of the body's own: {body})")
    return replace(orientation, features=_rows(matrix), reasons=reasons)


def _shapes(frames):
    """The sampled frames' vertices, each frame about its own centre (the body's shape, not
    its path across the capture volume), pooled and thinned to about 60,000 (the same ones
    whatever frame the coordinates are in)."""
    centred = [f - f.mean(axis=0) for f in (np.asarray(f, dtype=np.float64) for f in frames)]
    stride = max(1, sum(len(f) for f in centred) // 60000)
    return np.concatenate(centred)[::stride]


def _detect_up(frames, depth_camera):
    default = np.array([0.0, 0.0, 1.0])
    if not frames or min(len(f) for f in frames) < MIN_VERTICES:
        return default, "tvmedit's default: too few vertices per frame to tell a body's axis"
    # Each frame about its own centre, as in feature_frame: the body's shape, not its path.
    # Pooled as they lie, a person who jogs or walks across the volume makes the path the
    # longest axis (an HDM05 take jogging in circles came out lying on its side, up = +y).
    points = _shapes(frames)
    axes = [0, 1] if depth_camera else [0, 1, 2]
    direction, ratio = _principal(points, axes)
    if ratio < DOMINANCE:
        if depth_camera:
            return np.array([0.0, -1.0, 0.0]), ("a depth camera's convention (image down along +y): "
                                                "the body has no clearly longest axis across the view")
        return default, "tvmedit's default: the body has no clearly longest axis"
    direction, angle = _snap(direction, axes)
    low, high = _ends(frames, direction)
    where = "a depth camera looks along +z, so up lies across it; " if depth_camera else ""
    letter = "xyz"[int(np.argmax(np.abs(direction)))]
    axis_text = (f"the body's longest axis is {letter}" + (f" ({angle:.0f} degrees off)" if angle >= 1 else "")
                 if np.abs(direction).max() == 1.0 else
                 f"the body's longest axis is oblique, {angle:.0f} degrees from {letter}")
    if max(low, high) < 1e-9 or max(low, high) < STEADIER * min(low, high):
        if not depth_camera and abs(direction[2]) == 1.0:
            direction = default
        elif direction[int(np.argmax(np.abs(direction)))] < 0:
            direction = -direction
        return direction, f"{where}{axis_text}; neither end holds still more than the other, so its positive end"
    if high < low:
        direction = -direction
    return direction, (f"{where}{axis_text}, and one end holds still over the sequence "
                       f"({min(low, high) * 100 / max(low, high):.0f}% of the other's movement): "
                       "the bottom, where the body meets the floor or leaves the view")


def _detect_units(frames, direction):
    if not frames or min(len(f) for f in frames) < MIN_VERTICES:
        return "m", "tvmedit's default: too few vertices per frame to measure a body"
    extents = []
    for positions in frames:
        t = positions @ direction
        k = max(0, int(0.01 * (len(t) - 1)))
        part = np.partition(t, (k, len(t) - 1 - k))
        extents.append(part[len(t) - 1 - k] - part[k])
    extent = float(np.median(extents))
    if extent > 300:
        units = "mm"
    elif extent > 3:
        units = "cm"
    else:
        units = "m"
    names = {"m": "metres", "cm": "centimetres", "mm": "millimetres"}
    return units, f"the body is {extent:.3g} units tall: {names[units]}, {extent * UNITS[units]:.2f} m"


def feature_frame(frames):
    """The body's own frame over the sequence, in which features are computed, and why.

    Parameters
    ----------
    frames : list of (N, 3) arrays
        Vertex positions of frames sampled across the sequence, in tvmedit's frame (Z up).

    Returns
    -------
    matrix : (3, 3) float64
        A rotation whose rows are the body's axes: row 3 its up (the principal axis of the
        pooled vertices, on the side of +Z), row 2 its front-back axis (the lesser principal
        axis across up, signed so that its third moment is positive), row 1 their cross
        product. The identity where the body gives no such frame.
    reason : str

    Notes
    -----
    Every axis is a function of the vertices that turns with them: for a rotation ``R``
    near the identity, ``feature_frame(frames @ R.T)`` is ``feature_frame(frames) @ R.T``,
    so features computed in it (:meth:`Orientation.for_features`) are the same whichever
    way the take was turned. It is used only within :data:`FRAME_DEGREES` of up.

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> body = rng.normal(0.0, [0.2, 0.1, 0.5], (2000, 3)) + [0.0, 0.0, 0.9]
    >>> body[:, 1] -= rng.exponential(0.05, 2000)          # a front that sticks out
    >>> c, s = np.cos(0.1), np.sin(0.1)
    >>> turn = np.array([[1, 0, 0], [0, c, -s], [0, s, c]]) @ np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    >>> a, b = feature_frame([body])[0], feature_frame([body @ turn.T])[0]
    >>> bool(np.allclose(b @ turn, a))
    True
    """
    if not frames or min(len(f) for f in frames) < MIN_VERTICES:
        return np.eye(3), "too few vertices per frame to tell a body's axes"
    points = _shapes(frames)
    values, vectors = np.linalg.eigh(np.cov(points.T))
    up = vectors[:, -1] * (1.0 if vectors[2, -1] >= 0 else -1.0)
    tilt = math.degrees(math.acos(min(1.0, abs(float(up[2])))))
    if values[-1] < DOMINANCE * values[-2]:
        return np.eye(3), "the body has no clearly longest axis"
    if tilt > FRAME_DEGREES:
        return np.eye(3), f"the body's longest axis is {tilt:.0f} degrees off up"
    across = points - np.outer(points @ up, up)
    values, vectors = np.linalg.eigh(np.cov(across.T))
    front = vectors[:, 1]   # the lesser of the two across up (index 0 is along up, variance 0)
    skew = float(np.mean((across @ front) ** 3)) / max(values[1], 1e-30) ** 1.5
    if skew < 0:
        front, skew = -front, -skew
    matrix = np.array([np.cross(front, up), front, up])
    yaw = math.degrees(math.atan2(matrix[1, 0], matrix[1, 1]))
    return matrix, (f"its longest axis {tilt:.2f} degrees from up, its front-back axis {yaw:.0f} "
                    f"degrees about it (skewness {skew:.2f})")
