"""Orbit camera around a target, Z up, with framing that makes the subject fill the view.

Angles are in degrees, distances in metres. Azimuth is measured in the XY plane from +X towards
+Y; the default -90 puts the camera on -Y looking along +Y, so +X is to the right of the image.
Elevation lifts the camera above the XY plane.
"""

import dataclasses
import functools
import math

import numpy as np
from pyrr import matrix44


@dataclasses.dataclass(frozen=True)
class Camera:
    """A perspective camera on a sphere around ``target``.

    Frozen: ``orbit`` and ``dataclasses.replace`` return new cameras, so a camera handed to a
    video cannot drift under it.

    >>> cam = Camera(target=(0, 0, 1), azimuth=-90, elevation=0, distance=3)
    >>> cam.eye.round(6).tolist()
    [0.0, -3.0, 1.0]
    >>> cam.orbit(90).azimuth
    0.0
    """

    target: tuple = (0.0, 0.0, 1.0)
    azimuth: float = -90.0
    elevation: float = 10.0
    distance: float = 3.0
    fov: float = 35.0
    aspect: float = 4 / 3
    radius: float = 1.0
    """Size of the subject around ``target`` (m); sets the near and far planes."""

    @classmethod
    def framing(cls, bounds, aspect, azimuth=-90.0, elevation=10.0, fov=35.0, margin=1.08,
                all_azimuths=False):
        """The camera at the given angles closest to the centre of ``bounds`` that sees all of it.

        Every corner of the box is kept inside the view with ``margin`` to spare, using the exact
        perspective at these angles, so a standing person fills the height of the image rather
        than the height of a bounding sphere. With ``all_azimuths`` the distance is the largest
        over a full turn, so an orbiting video never cuts the subject.

        Parameters
        ----------
        bounds : ((xmin, ymin, zmin), (xmax, ymax, zmax))
        aspect : float, width / height of the image

        >>> cam = Camera.framing(((-0.3, -0.2, 0.0), (0.3, 0.2, 1.8)), aspect=4 / 3, elevation=0)
        >>> cam.target
        (0.0, 0.0, 0.9)
        >>> 2.9 < cam.distance < 3.4
        True
        """
        low, high = (np.asarray(b, dtype=np.float64) for b in bounds)
        if not (np.isfinite(low).all() and np.isfinite(high).all() and (high >= low).all()):
            raise ValueError(f"bounds should be ((xmin, ymin, zmin), (xmax, ymax, zmax)), got {bounds!r}")
        centre = (low + high) / 2
        corners = np.array([[x, y, z] for x in (low[0], high[0]) for y in (low[1], high[1])
                            for z in (low[2], high[2])]) - centre
        radius = max(float(np.linalg.norm(high - low)) / 2, 1e-3)
        tan_v = math.tan(math.radians(fov) / 2)
        tan_h = tan_v * aspect
        azimuths = np.arange(0.0, 360.0, 5.0) if all_azimuths else [azimuth]
        distance = 0.0
        for az in azimuths:
            right, up, back = _basis(az, elevation)
            x, y, z = corners @ right, corners @ up, corners @ back
            # A corner at depth (distance - z) in front of the eye is inside the view when
            # |x| <= (distance - z) * tan_h / margin, and likewise for y.
            needed = z + margin * np.maximum(np.abs(x) / tan_h, np.abs(y) / tan_v)
            distance = max(distance, float(needed.max()))
        distance = max(distance, 1.1 * radius)  # keep the eye outside the subject
        return cls(target=tuple(centre.tolist()), azimuth=float(azimuth), elevation=float(elevation),
                   distance=distance, fov=float(fov), aspect=float(aspect), radius=radius)

    def orbit(self, degrees):
        """The same camera turned by ``degrees`` of azimuth around the target (counter-clockwise seen from above)."""
        return dataclasses.replace(self, azimuth=(self.azimuth + degrees + 180.0) % 360.0 - 180.0)

    def with_aspect(self, aspect):
        return dataclasses.replace(self, aspect=float(aspect))

    @property
    def eye(self):
        """Camera position (3,) in world coordinates."""
        _, _, back = _basis(self.azimuth, self.elevation)
        return np.asarray(self.target, dtype=np.float64) + self.distance * back

    @property
    def near(self):
        return max(self.distance - 1.5 * self.radius, 0.01 * self.distance)

    @property
    def far(self):
        return (self.distance + self.radius) * 10.0

    def view_matrix(self):
        """World -> camera (4, 4) float32 for row vectors (``p @ view``), so its bytes upload as a GL mat4."""
        return self._matrices[0].copy()

    def projection_matrix(self):
        """Camera -> clip (4, 4) float32 for row vectors (``p @ view @ projection``)."""
        return self._matrices[1].copy()

    @functools.cached_property
    def _matrices(self):
        # Computed once per camera (cameras are frozen); a player asks every frame.
        _, up, _ = _basis(self.azimuth, self.elevation)
        view = matrix44.create_look_at(self.eye, np.asarray(self.target, dtype=np.float64), up, dtype=np.float32)
        projection = matrix44.create_perspective_projection(self.fov, self.aspect, self.near, self.far,
                                                            dtype=np.float32)
        return view, projection


def _basis(azimuth, elevation):
    """Right, up and back (towards the eye) unit vectors of a camera at these angles."""
    az, el = math.radians(azimuth), math.radians(elevation)
    back = np.array([math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)])
    right = np.array([-math.sin(az), math.cos(az), 0.0])
    up = np.cross(back, right)
    return right, up, back


class CameraControls:
    """Orbit, zoom and reset for an app with a ``camera`` framed on ``_bounds`` (the player's
    and the inspector's)."""

    def home_camera(self, aspect):
        # Framed for every azimuth, so orbiting never cuts the actor.
        return Camera.framing(self._bounds, aspect, all_azimuths=True)

    def reset_camera(self):
        self.camera = self.home_camera(self.camera.aspect)

    def set_aspect(self, aspect):
        self.camera = self.camera.with_aspect(aspect)

    def orbit(self, azimuth_deg, elevation_deg=0.0):
        elevation = min(max(self.camera.elevation + elevation_deg, -85.0), 85.0)
        self.camera = dataclasses.replace(self.camera.orbit(azimuth_deg), elevation=elevation)

    def zoom(self, factor):
        distance = min(max(self.camera.distance * factor, 0.2 * self.camera.radius), 50.0 * self.camera.radius)
        self.camera = dataclasses.replace(self.camera, distance=distance)
