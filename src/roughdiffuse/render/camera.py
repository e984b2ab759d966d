"""The orthographic camera and distant lights.

Directions use the world frame of :mod:`roughdiffuse.render.shapes` (x right, y up, z towards
the default viewer) and the usual spherical angles: θ from +z, φ the azimuth from +x towards
+y. θ = 0 is the default view (and, for a light, a light behind the viewer: the full moon).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import check_range

__all__ = ["DistantLight", "OrthographicCamera", "direction"]


def direction(theta: float, phi: float = 0.0) -> np.ndarray:
    """Unit vector (sin θ cos φ, sin θ sin φ, cos θ) for angles in radians."""
    st = math.sin(theta)
    return np.array([st * math.cos(phi), st * math.sin(phi), math.cos(theta)])


@dataclass(frozen=True)
class DistantLight:
    """A light at infinity (parallel rays) in direction (θ, φ), irradiance E0.

    Parameters
    ----------
    theta, phi : float
        Direction *towards* the light, radians; θ in [0, π].
    irradiance : float or sequence of 3 floats
        E0, the irradiance on a plane facing the light (per RGB channel if 3 values).
    """

    theta: float = 0.0
    phi: float = 0.0
    irradiance: Any = 1.0

    def __post_init__(self) -> None:
        check_range("theta", self.theta, 0.0, math.pi, unit="radians")
        check_range("phi", self.phi, -math.inf, math.inf, unit="radians")
        e0 = np.asarray(self.irradiance, dtype=np.float64)
        check_range("irradiance", e0, 0.0, math.inf, channels=True)
        if e0.ndim == 1:
            object.__setattr__(self, "irradiance", tuple(float(x) for x in e0))

    @property
    def direction(self) -> np.ndarray:
        """Unit vector towards the light."""
        return direction(self.theta, self.phi)


@dataclass(frozen=True)
class OrthographicCamera:
    """A camera at infinity looking along −v, v = direction(θ, φ); the shape fills the frame.

    Parameters
    ----------
    theta, phi : float
        Direction *towards* the viewer, radians; θ in [0, π].
    margin : float
        Empty border around the shape, as a fraction of its projected size (default 0.04).

    Notes
    -----
    Image axes: "right" r = normalise(y × v) and "up" u = v × r, so that with θ = 0 the
    image x axis is the world x axis and the image's up is world y. Looking straight down or
    up the y axis, r = x.
    """

    theta: float = 0.0
    phi: float = 0.0
    margin: float = 0.04

    def __post_init__(self) -> None:
        check_range("theta", self.theta, 0.0, math.pi, unit="radians")
        check_range("phi", self.phi, -math.inf, math.inf, unit="radians")
        check_range("margin", self.margin, 0.0, 10.0)

    @property
    def view(self) -> np.ndarray:
        """Unit vector towards the viewer."""
        return direction(self.theta, self.phi)

    def basis(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(right, up, view) unit vectors of the image plane."""
        v = self.view
        right = np.cross([0.0, 1.0, 0.0], v)
        n = np.linalg.norm(right)
        right = np.array([1.0, 0.0, 0.0]) if n < 1e-9 else right / n
        up = np.cross(v, right)
        return right, up / np.linalg.norm(up), v

    def frame(self, shape: Any, height: int, width: int) -> tuple[np.ndarray, float]:
        """World point at the image centre and the pixel size that fits ``shape``."""
        right, up, _ = self.basis()
        r_lo, r_hi = shape.extent(right)
        u_lo, u_hi = shape.extent(up)
        centre = 0.5 * (r_lo + r_hi) * right + 0.5 * (u_lo + u_hi) * up
        scale = 1.0 + 2.0 * self.margin
        pixel = max((r_hi - r_lo) * scale / width, (u_hi - u_lo) * scale / height)
        return centre, float(pixel)
