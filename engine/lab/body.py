"""The synthetic actor's body: an implicit surface posed, reconstructed frame by frame.

A smooth implicit body (ellipsoids and tapered capsules joined by a polynomial smooth-min of
radius :data:`BLEND`) is posed (:func:`primitives`) and its surface extracted with marching
cubes on a voxel grid that has a random sub-voxel offset per frame (:func:`make_frame`), so
the vertex count and connectivity change every frame, as in a multi-camera capture. Vertices
carry Gaussian noise (:data:`NOISE_M`) and the colour of their garment (:data:`PALETTE`).
Z up, metres, feet on z = 0, the subject facing -Y; :func:`turned_about` and
:func:`turn_headings` turn the actor on its feet.
"""

import numpy as np

from .exercises import POSE

NOISE_M = 0.002             # Gaussian vertex noise, metres


# Axes of the rest pose: forward (the subject faces -Y), the subject's left, and up.
F, L, U = np.array([0.0, -1.0, 0.0]), np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0])
SKIN, HAIR, SHIRT, TROUSERS, SHOES = range(5)
PALETTE = np.array([[222, 170, 138], [62, 42, 30], [40, 92, 170], [48, 52, 68], [236, 236, 232]],
                   dtype=float)
MATERIALS = ["skin", "hair", "shirt", "trousers", "shoes"]
BLEND = 0.03                # smooth-min radius, metres


def _rot(axis, angle):
    c, s = np.cos(angle), np.sin(angle)
    i, j = {"x": (1, 2), "y": (2, 0), "z": (0, 1)}[axis]
    r = np.eye(3)
    r[i, i] = r[j, j] = c
    r[j, i], r[i, j] = s, -s
    return r


def _limb(side_axis, fwd, up, flex, abd):
    """Unit direction of a limb that hangs down, swung out by abd and forward by flex, and the
    unit direction perpendicular to it in the swing plane (forward when hanging)."""
    d = np.cos(abd) * (-np.cos(flex) * up + np.sin(flex) * fwd) + np.sin(abd) * side_axis
    n = np.sin(flex) * up + np.cos(flex) * fwd
    return d, n


def primitives(pose, build=1.0):
    """Primitives of the posed body, feet resting on z = 0 (plus the pose's jump lift).

    ``build`` scales the radii of the trunk and limbs (0.8 slim, 1.3 heavy).

    Returns a list of tuples ``("cap", a, b, ra, rb, part)`` (tapered capsule from a to b)
    and ``("ell", centre, axes (3, 3) columns, radii (3,), part)``; part names the body
    part, which decides the colour.
    """
    p = dict(zip(POSE, pose))
    trunk = _rot("z", p["yaw"]) @ _rot("y", p["roll"]) @ _rot("x", p["pitch"])
    pelvis = _rot("z", 0.4 * p["yaw"])
    tf, tl, tu = trunk @ F, trunk @ L, trunk @ U
    prims = []
    root = np.zeros(3)
    prims.append(("ell", root + 0.02 * U, pelvis, np.array([0.165, 0.11, 0.11]), "pelvis"))
    prims.append(("ell", root + tu * 0.17, trunk, np.array([0.145, 0.10, 0.13]), "belly"))
    prims.append(("ell", root + tu * 0.36 - tf * 0.005, trunk, np.array([0.175, 0.11, 0.15]), "chest"))
    neck = root + tu * 0.49
    head = neck + tu * 0.16 + tf * 0.015
    prims.append(("cap", neck, neck + tu * 0.10, 0.052, 0.048, "neck"))
    prims.append(("ell", head, trunk, np.array([0.078, 0.095, 0.106]), "head"))
    shoulder = {}
    for s, side in ((1.0, "l"), (-1.0, "r")):
        shoulder[side] = root + tu * 0.46 + tl * (0.175 * s)
    prims.append(("cap", shoulder["l"], shoulder["r"], 0.058, 0.058, "girdle"))
    feet = []
    for s, side in ((1.0, "l"), (-1.0, "r")):
        arm, n = _limb(tl * s, tf, tu, p["sh_flex_" + side], p["sh_abd_" + side])
        elbow = shoulder[side] + 0.29 * arm
        e = p["elbow_" + side]
        fore = np.cos(e) * arm + np.sin(e) * n
        wrist = elbow + 0.25 * fore
        prims.append(("cap", shoulder[side], elbow, 0.05, 0.04, "upperarm"))
        prims.append(("cap", elbow, wrist, 0.038, 0.03, "forearm"))
        prims.append(("cap", wrist + 0.02 * fore, wrist + 0.1 * fore, 0.034, 0.03, "hand"))
        pf, pl = pelvis @ F, pelvis @ L
        hip = root + pl * (0.09 * s) - 0.06 * U
        thigh, n = _limb(pl * s, pf, U, p["hip_flex_" + side], p["hip_abd_" + side])
        knee = hip + 0.42 * thigh
        k = p["knee_" + side]
        shin = np.cos(k) * thigh - np.sin(k) * n
        ankle = knee + 0.41 * shin
        prims.append(("cap", hip, knee, 0.085, 0.055, "thigh"))
        prims.append(("cap", knee, ankle, 0.052, 0.038, "shin"))
        toe = p["toe_" + side]
        foot = np.cos(toe) * pf - np.sin(toe) * U
        heel = ankle - 0.045 * pf - 0.035 * U
        tip = ankle + 0.16 * foot - 0.025 * U
        prims.append(("cap", heel, tip, 0.042, 0.036, "foot"))
        feet += [heel, tip, ankle]
    # Feet rest on the floor, centred under the body (or the right foot, as "plant" says),
    # unless the actor jumps.
    feet = np.array(feet)
    sole = min(feet[0::3, 2].min() - 0.042, feet[1::3, 2].min() - 0.036)
    shift = np.array([-feet[2::3, 0].mean(), -feet[2::3, 1].mean(), p["lift"] - sole])
    if p["plant"]:
        # Where the body's centre would be were the left foot the right one's mirror image:
        # the right ankle moved onto the pelvis's mid-plane.
        side = pelvis @ L
        right = feet[5] - (feet[5] @ side) * side
        shift[:2] = (1 - p["plant"]) * shift[:2] - p["plant"] * right[:2]
    moved = []
    for prim in prims:
        if prim[0] == "cap":
            moved.append(("cap", prim[1] + shift, prim[2] + shift, prim[3] * build, prim[4] * build, prim[5]))
        else:
            moved.append(("ell", prim[1] + shift, prim[2], prim[3] * build, prim[4]))
    return moved


def _part_material(part, local, t):
    """Material of vertices nearest one primitive (local coords for the head, t for arms)."""
    if part == "head":
        hair = (local[:, 2] > 0.015) | ((local[:, 1] > 0.02) & (local[:, 2] > -0.045))
        return np.where(hair, HAIR, SKIN)
    if part == "upperarm":
        return np.where(t < 0.5, SHIRT, SKIN)
    return {"pelvis": TROUSERS, "belly": SHIRT, "chest": SHIRT, "neck": SKIN, "girdle": SHIRT,
            "forearm": SKIN, "hand": SKIN, "thigh": TROUSERS, "shin": TROUSERS, "foot": SHOES}[part]


def _distance(prim, x, y, z):
    """Signed distance of one primitive (negative inside) and, for capsules, the position t
    along the axis; x, y, z broadcast (grid axes or flat vertex coordinates)."""
    if prim[0] == "cap":
        _, a, b, ra, rb, _ = prim
        ba = b - a
        qx, qy, qz = x - a[0], y - a[1], z - a[2]
        t = np.clip((qx * ba[0] + qy * ba[1] + qz * ba[2]) / (ba @ ba + 1e-12), 0.0, 1.0)
        d = np.sqrt((qx - t * ba[0]) ** 2 + (qy - t * ba[1]) ** 2 + (qz - t * ba[2]) ** 2)
        return d - (ra + (rb - ra) * t), t
    _, c, axes, r, _ = prim
    qx, qy, qz = x - c[0], y - c[1], z - c[2]
    k0 = k1 = 0.0
    for i in range(3):
        q = qx * axes[0, i] + qy * axes[1, i] + qz * axes[2, i]
        k0 = k0 + (q / r[i]) ** 2
        k1 = k1 + (q / r[i] ** 2) ** 2
    k0 = np.sqrt(k0)
    return k0 * (k0 - 1.0) / (np.sqrt(k1) + 1e-9), None


def _bounds(prim):
    if prim[0] == "cap":
        _, a, b, ra, rb, _ = prim
        r = max(ra, rb)
        return np.minimum(a, b) - r, np.maximum(a, b) + r
    _, c, axes, r, _ = prim
    half = np.sqrt(((axes * r) ** 2).sum(axis=1))
    return c - half, c + half


def _field(prims, h, origin, shape):
    """Smooth-min of all primitives on the grid ``origin + h * index``; each primitive is
    evaluated only inside its own bounding box (grown by the blend radius)."""
    field = np.full(shape, 1.0, dtype=np.float32)
    k = np.float32(BLEND)
    for prim in prims:
        lo, hi = _bounds(prim)
        i0 = np.maximum(np.floor((lo - BLEND - origin) / h).astype(int), 0)
        i1 = np.minimum(np.ceil((hi + BLEND - origin) / h).astype(int) + 1, shape)
        axes = [(origin[i] + h * np.arange(i0[i], i1[i])).astype(np.float32) for i in range(3)]
        d, _ = _distance(prim, axes[0][:, None, None], axes[1][None, :, None], axes[2][None, None, :])
        sub = field[i0[0]:i1[0], i0[1]:i1[1], i0[2]:i1[2]]
        w = np.clip(0.5 + (sub - d) / (2 * k), 0.0, 1.0)
        sub[...] = sub + w * (d - sub) - k * w * (1.0 - w)
    return field


def make_frame(pose, voxel, rng, build=1.0, noise=NOISE_M, colours=True):
    """One reconstructed frame of the actor in the given pose (``build``: see :func:`primitives`;
    ``noise``: standard deviation of the vertex noise, metres).

    Returns ``vertices (V, 3) float32``, ``faces (F, 3) int32`` (outward winding) and
    ``colours (V, 3) uint8``; with ``colours=False``, None for the colours, which a take's
    features never look at (the development suite's takes), for 10-30 % less work: ``rng``
    still makes the colours' draws (:func:`_colour_noise`), so every later frame of the take
    is the same.
    """
    from skimage.measure import marching_cubes

    prims = primitives(pose, build)
    boxes = np.array([_bounds(p) for p in prims])
    lo, hi = boxes[:, 0].min(axis=0) - 2 * voxel, boxes[:, 1].max(axis=0) + 2 * voxel
    origin = lo - rng.uniform(0.0, voxel, 3)
    shape = tuple(np.ceil((hi - origin) / voxel).astype(int) + 1)
    field = _field(prims, voxel, origin, shape)
    verts, faces, _, _ = marching_cubes(field, 0.0, spacing=(voxel,) * 3,
                                        gradient_direction="descent", allow_degenerate=False)
    verts = verts + origin + rng.normal(0.0, noise, verts.shape)
    if colours:
        colours = _colours(prims, verts, rng)
    else:
        _colour_noise(rng, len(verts))
        colours = None
    return verts.astype(np.float32), faces.astype(np.int32), colours


def turn_headings(n, fps, turns, seed=0):
    """The heading (radians) of an actor who turns to face another way now and then.

    Every 5-10 s at random the actor turns by 1/2 to 1 times ``turns`` degrees to either side,
    over 1 s (smoothly), as people do between repetitions; 0 at every frame where ``turns`` is
    0. ``n`` frames at ``fps``; the turns' own random numbers (from ``seed``) leave every
    other draw of a take as it was.

    >>> h = np.degrees(turn_headings(300, 10.0, 90.0, seed=1))
    >>> float(h[0]), bool(np.abs(np.diff(h)).max() > 5), bool(np.abs(np.diff(h)[:40]).max() == 0)
    (0.0, True, True)
    """
    t = np.arange(n) / fps
    heading = np.zeros(n)
    if not turns or n == 0:
        return heading
    rng = np.random.default_rng(seed + 2000)
    at = rng.uniform(5.0, 10.0)
    while at < t[-1]:
        angle = np.radians(turns) * rng.uniform(0.5, 1.0) * rng.choice([-1.0, 1.0])
        x = np.clip(t - at, 0.0, 1.0)
        heading = heading + angle * x * x * (3 - 2 * x)
        at += 1.0 + rng.uniform(5.0, 10.0)
    return heading


def turned_about(verts, angle, at=(0.0, 0.0)):
    """Vertices (Z up) turned by ``angle`` radians about the vertical through ``at`` (x, y).

    ``at`` is the spot the person turns on: people turn on their feet. Until VERSION 3 each
    frame turned about its own centre, which moves with the pose (0.1-0.2 m as the actor bends
    to touch its toes): the feet slid by up to twice that in a turn of 180 degrees, and a
    turned left-right exercise lost its mirror symmetry about any fixed point.

    >>> v = np.array([[0.2, 0.0, 1.0], [0.0, 0.0, 0.0]])          # a hand out front, a foot
    >>> np.round(turned_about(v, np.pi), 6).tolist()              # the foot stays where it was
    [[-0.2, 0.0, 1.0], [0.0, 0.0, 0.0]]
    """
    centre = np.array([at[0], at[1], 0.0])
    return (np.asarray(verts) - centre) @ _rot("z", angle).T + centre


def _colours(prims, verts, rng):
    """Garment colour of the nearest primitive, with a little brightness and hue noise."""
    x, y, z = verts.T
    dist = np.empty((len(prims), len(verts)))
    ts = []
    for i, prim in enumerate(prims):
        dist[i], t = _distance(prim, x, y, z)
        ts.append(t)
    nearest = dist.argmin(axis=0)
    material = np.empty(len(verts), dtype=int)
    for i, prim in enumerate(prims):
        sel = nearest == i
        if not sel.any():
            continue
        part = prim[-1]
        local = (verts[sel] - prim[1]) @ prim[2] if prim[0] == "ell" else None
        t = ts[i][sel] if ts[i] is not None else None
        material[sel] = _part_material(part, local, t)
    brightness, noise = _colour_noise(rng, len(verts))
    colour = PALETTE[material] * brightness + noise
    return np.clip(np.rint(colour), 0, 255).astype(np.uint8)


def _colour_noise(rng, count):
    """The random draws of ``count`` vertices' colours, in the order :func:`_colours` makes
    them: a brightness a vertex (0.92-1.06) and a noise a channel (3 of 255)."""
    return rng.uniform(0.92, 1.06, (count, 1)), rng.normal(0.0, 3.0, (count, 3))
