"""Shapes with exact ray intersection: sphere, plane, surfaces of revolution, cylinder, moon.

World frame (fixed here, used by the camera and the lights): x to the right, y up, z towards
the default viewer. Surfaces of revolution (vase, cylinder) turn about the y axis.

Every shape intersects a bundle of parallel rays ``o + t d`` (the orthographic camera and a
distant light both give one direction ``d`` for all rays), branch-free in JAX, returning the
ray parameter of the nearest hit, a hit mask and the unit outward normal. Rays run over the
whole line (t from −∞), so the origins may lie anywhere on the ray: the camera puts them on
the plane through the centre of the scene, which keeps float32 round-off small.

The surface of revolution of a polyline profile is a stack of cone frusta and flat annuli;
its ray intersection is the exact root of one quadratic per frustum (or one plane per
annulus). A smooth profile (a function r(y)) is first hit as its inscribed polyline (``segments``
frusta, within O(h²) of the surface), then, when the function runs on JAX arrays, three
Newton steps on ρ(t) − r(y(t)) = 0 move the hit onto the smooth surface itself, where the
normal (x/ρ, −r'(y), z/ρ) uses the exact derivative (``jax.jvp``). A NumPy-only function
gets its slope interpolated between the nodes instead. The silhouette (coverage) and the
cast-shadow rays use the polyline.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import partial
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np

from .._validate import ParameterError, check_range

__all__ = [
    "Cylinder",
    "Moon",
    "Plane",
    "Shape",
    "Sphere",
    "SurfaceOfRevolution",
    "clay_vase_profile",
]

Vec3 = tuple[Any, Any, Any]
"""Three arrays (or scalars): the x, y, z components of points or directions."""

_INF = float("inf")


def _dot(a: Vec3, b: Vec3) -> Any:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _safe_div(num: Any, den: Any, default: float = 0.0) -> Any:
    nz = den != 0
    return jnp.where(nz, num / jnp.where(nz, den, 1.0), default)


class Shape:
    """Interface of the shapes: nearest intersection, occlusion, framing."""

    convex: bool = True
    """A convex shape casts no shadow on itself (the occlusion test is skipped)."""

    def intersect(self, o: Vec3, d: Vec3) -> tuple[Any, Any, Vec3]:
        """Nearest hit of the rays ``o + t d`` over all real t.

        Parameters
        ----------
        o : three arrays
            Ray origins (x, y, z components, any common shape).
        d : three scalars
            Common unit direction of the rays.

        Returns
        -------
        t : array
            Ray parameter of the nearest hit (``inf`` where there is none).
        hit : bool array
        normal : three arrays
            Unit outward normal at the hit (arbitrary where there is no hit).
        """
        raise NotImplementedError

    def occluded(self, p: Vec3, d: Vec3, t_min: float) -> Any:
        """True where the ray ``p + t d``, t > ``t_min``, meets the shape (a cast shadow)."""
        return jnp.zeros(jnp.shape(p[0]), dtype=bool)

    def extent(self, axis: np.ndarray) -> tuple[float, float]:
        """Lowest and highest value of ``x · axis`` over the shape (the camera's framing)."""
        raise NotImplementedError

    @property
    def scale(self) -> float:
        """A length typical of the shape (sets the self-intersection tolerance)."""
        return 1.0


@dataclass(frozen=True)
class Sphere(Shape):
    """A sphere of radius ``radius`` centred at the origin.

    Intersection: with b = o·d and c = o·o − R², the nearest root is t = −b − √(b² − c).
    """

    radius: float = 1.0

    def __post_init__(self) -> None:
        check_range("radius", self.radius, 0.0, math.inf, lo_open=True)

    def intersect(self, o: Vec3, d: Vec3) -> tuple[Any, Any, Vec3]:
        r = self.radius
        b = _dot(o, d)
        # o·o − b² is the squared distance of the ray to the centre: c − b² without cancellation
        perp = [o[k] - b * d[k] for k in range(3)]
        disc = r * r - (perp[0] ** 2 + perp[1] ** 2 + perp[2] ** 2)
        hit = disc >= 0
        h = jnp.sqrt(jnp.where(hit, disc, 0.0))
        t = jnp.where(hit, -b - h, _INF)
        # p = o + t d = perp − h d
        n = tuple((perp[k] - h * d[k]) / r for k in range(3))
        return t, hit, n

    def extent(self, axis: np.ndarray) -> tuple[float, float]:
        return -self.radius, self.radius

    @property
    def scale(self) -> float:
        return self.radius


@dataclass(frozen=True)
class Moon(Sphere):
    """The full-moon preset: a sphere with the moon's albedo.

    :func:`~roughdiffuse.render.render` gives the model this albedo (when the model has an
    ``albedo`` field). 0.12 is the moon's average normal albedo in the visible (Hapke 2012,
    Table 11.1 quotes 0.11–0.13 for the lunar highlands and maria together).
    """

    albedo: float = 0.12

    def __post_init__(self) -> None:
        super().__post_init__()
        check_range("albedo", self.albedo, 0.0, 1.0)


@dataclass(frozen=True)
class Plane(Shape):
    """The infinite plane through the origin with normal ``normal`` (default +z, facing the
    default viewer). Every pixel sees the same geometry, so its image is one radiance value.
    """

    normal: tuple[float, float, float] = (0.0, 0.0, 1.0)

    def __post_init__(self) -> None:
        n = np.asarray(self.normal, dtype=np.float64)
        if n.shape != (3,) or not np.all(np.isfinite(n)) or not np.any(n):
            raise ParameterError(f"normal must be a non-zero finite 3-vector (got {self.normal!r})")
        object.__setattr__(self, "normal", tuple(float(x) for x in n / np.linalg.norm(n)))

    def intersect(self, o: Vec3, d: Vec3) -> tuple[Any, Any, Vec3]:
        n = self.normal
        dn = _dot(d, n)
        on = _dot(o, n)
        hit = jnp.broadcast_to(jnp.asarray(dn != 0), jnp.shape(on))
        t = jnp.where(hit, _safe_div(-on, dn), _INF)
        # the side that faces the ray
        sign = jnp.where(jnp.asarray(dn) > 0, -1.0, 1.0)
        normal = tuple(jnp.broadcast_to(sign * n[k], jnp.shape(on)) for k in range(3))
        return t, hit, normal

    def extent(self, axis: np.ndarray) -> tuple[float, float]:
        return -1.0, 1.0


def clay_vase_profile(y: Any) -> Any:
    """Radius of the default clay vase at height ``y`` in [−1, 1] (a foot, a round body,
    a narrow neck and a flared lip that overhangs the neck).

    Works on NumPy and JAX arrays.

    Examples
    --------
    >>> round(float(clay_vase_profile(1.0)), 2)  # the lip
    0.32
    """
    xp = jnp if isinstance(y, jax.Array) else np
    s = (xp.asarray(y) + 1.0) / 2.0  # 0 at the foot, 1 at the lip
    body = 0.45 * xp.exp(-(((s - 0.38) / 0.24) ** 2))
    lip = 0.10 * xp.exp(-(((s - 1.0) / 0.06) ** 2))
    return 0.22 + body + lip


def _polyline(profile: Any, y_range: tuple[float, float], segments: int) -> tuple[np.ndarray, ...]:
    """Nodes (y, r) and node tangents of a profile given as points or as a function."""
    if callable(profile):
        y0, y1 = (float(v) for v in y_range)
        if not (math.isfinite(y0) and math.isfinite(y1) and y0 < y1):
            raise ParameterError(
                f"y_range must be two finite heights, low < high (got {y_range!r})"
            )
        y = np.linspace(y0, y1, segments + 1)
        r = np.asarray(profile(y), dtype=np.float64)
        h = 1e-5 * (y1 - y0)
        slope = (np.asarray(profile(y + h)) - np.asarray(profile(y - h))) / (2 * h)
        tan = np.stack([slope, np.ones_like(slope)], axis=-1)  # (dr, dy), going up
        smooth = True
    else:
        pts = np.asarray(profile, dtype=np.float64)
        if pts.ndim != 2 or pts.shape[1] != 2 or pts.shape[0] < 2:
            raise ParameterError(f"profile points must have shape (N >= 2, 2) (got {pts.shape})")
        y, r = pts[:, 0], pts[:, 1]
        tan = None
        smooth = False
    if not (np.all(np.isfinite(r)) and np.all(np.isfinite(y))):
        raise ParameterError("profile must be finite")
    if np.any(r < 0):
        raise ParameterError(f"profile radius must be >= 0 (got {r.min():g})")
    return y, r, tan, smooth  # type: ignore[return-value]


def _traceable(profile: Any) -> bool:
    """True when ``profile`` runs on JAX arrays (needed for the exact, refined hit)."""
    try:
        out = jax.eval_shape(profile, jax.ShapeDtypeStruct((3,), jnp.float32))
    except Exception:  # noqa: BLE001 - any failure means: NumPy only
        return False
    return getattr(out, "shape", None) == (3,)


@dataclass(frozen=True)
class SurfaceOfRevolution(Shape):
    """A solid of revolution about the y axis (a vase), closed by flat caps.

    Parameters
    ----------
    profile : callable or array (N, 2), optional
        The radius r(y) as a function of the height (NumPy-vectorised), or points
        (y, r) of a polyline drawn from the bottom to the top (the solid's outside on the
        right of the direction of travel in the (r, y) plane, so an overhang is a segment
        going out at constant y). Default: :func:`clay_vase_profile`.
    y_range : (float, float)
        Heights where a function profile starts and ends (default −1, 1).
    segments : int
        Number of frusta a function profile is cut into (default 128).

    Attributes
    ----------
    exact : bool
        True when the profile is a function that runs on JAX arrays: normals are then
        exact (see the module notes).

    Notes
    -----
    A frustum from (y_a, r_a) to (y_b, r_b) is the cone ρ = g + h t along the ray, with
    ρ² = x² + z²; the hit is the smaller admissible root of
    (d_x² + d_z² − h²) t² + 2 (o_x d_x + o_z d_z − g h) t + (o_x² + o_z² − g²) = 0.
    The outward normal of a piece with tangent (Δr, Δy) in the (ρ, y) plane is
    (x/ρ Δy, −Δr, z/ρ Δy), normalised.
    """

    profile: Any = field(default=None, compare=False, hash=False)
    y_range: tuple[float, float] = (-1.0, 1.0)
    segments: int = 128
    nodes: tuple[tuple[float, ...], ...] = field(init=False, repr=False)
    exact: bool = field(init=False)
    _function: Any = field(init=False, default=None, compare=False, hash=False, repr=False)

    convex = False

    def __post_init__(self) -> None:
        if not isinstance(self.segments, int) or not 1 <= self.segments <= 4096:
            raise ParameterError(
                f"segments must be an integer in [1, 4096] (got {self.segments!r})"
            )
        profile = clay_vase_profile if self.profile is None else self.profile
        y, r, tan, smooth = _polyline(profile, self.y_range, self.segments)
        exact = smooth and _traceable(profile)
        object.__setattr__(self, "exact", exact)
        object.__setattr__(self, "_function", profile if exact else None)
        ya, yb, ra, rb = y[:-1], y[1:], r[:-1], r[1:]
        if smooth:
            ta, tb = tan[:-1], tan[1:]
        else:
            seg = np.stack([rb - ra, yb - ya], axis=-1)
            ta = tb = seg
        # close the solid with flat caps at the ends that are off the axis
        pieces = [(ya, yb, ra, rb, ta, tb)]
        if r[0] > 0:
            cap = np.array([[r[0], 0.0]])
            pieces.insert(0, ([y[0]], [y[0]], [0.0], [r[0]], cap, cap))
        if r[-1] > 0:
            cap = np.array([[-r[-1], 0.0]])
            pieces.append(([y[-1]], [y[-1]], [r[-1]], [0.0], cap, cap))
        cols = [
            np.concatenate([np.asarray(p[k], dtype=np.float64) for p in pieces]) for k in range(6)
        ]
        ya, yb, ra, rb, ta, tb = cols
        keep = (np.abs(yb - ya) + np.abs(rb - ra)) > 0
        ta = ta / np.linalg.norm(ta, axis=-1, keepdims=True)
        tb = tb / np.linalg.norm(tb, axis=-1, keepdims=True)
        table = np.stack([ya, yb, ra, rb, ta[:, 0], ta[:, 1], tb[:, 0], tb[:, 1]], axis=0)[:, keep]
        object.__setattr__(self, "nodes", tuple(tuple(float(v) for v in row) for row in table))

    # -------------------------------------------------------------- geometry
    def _tables(self) -> tuple[jnp.ndarray, jnp.ndarray, jnp.ndarray]:
        """(pieces, cones, annuli) as float32 constants.

        pieces: 8 rows (ya, yb, ra, rb, tangent at a (Δr, Δy), tangent at b), one column per
        piece. cones: rows (y_lo, y_hi, k, r_a − k y_a, piece index) for Δy ≠ 0.
        annuli: rows (y, r_lo², r_hi², piece index) for Δy = 0.
        """
        table = np.asarray(self.nodes, dtype=np.float64)
        ya, yb, ra, rb = table[:4]
        idx = np.arange(table.shape[1], dtype=np.float64)
        flat = ya == yb
        c = ~flat
        k = (rb[c] - ra[c]) / (yb[c] - ya[c])
        cones = np.stack(
            [np.minimum(ya[c], yb[c]), np.maximum(ya[c], yb[c]), k, ra[c] - k * ya[c], idx[c]]
        )
        lo, hi = np.minimum(ra[flat], rb[flat]), np.maximum(ra[flat], rb[flat])
        annuli = np.stack([ya[flat], lo * lo, hi * hi, idx[flat]])
        as32 = partial(jnp.asarray, dtype=jnp.float32)
        return as32(table), as32(cones), as32(annuli)

    @staticmethod
    def _nearest(
        cones: Any, annuli: Any, o: Vec3, d: Vec3, t_min: Any, any_hit: bool
    ) -> tuple[Any, Any]:
        """Nearest admissible hit t > t_min over all pieces and its piece index (as float).

        One pass over the cones and one over the annuli (``jax.lax.fori_loop``); the ray
        quantities that do not depend on the piece are computed once.
        """
        shape = jnp.shape(o[0])
        od = o[0] * d[0] + o[2] * d[2]
        o2 = o[0] * o[0] + o[2] * o[2]
        d2 = d[0] * d[0] + d[2] * d[2]
        oy, dy = o[1], d[1]
        init = (jnp.full(shape, _INF, jnp.float32), jnp.full(shape, -1.0, jnp.float32))

        def cone(i: Any, carry: tuple[Any, Any]) -> tuple[Any, Any]:
            t_best, idx = carry
            lo, hi, k, c0, piece = cones[0, i], cones[1, i], cones[2, i], cones[3, i], cones[4, i]
            g = c0 + k * oy  # cone radius at the ray's height: ρ = g + h t
            h = k * dy
            a = d2 - h * h
            b = od - g * h
            c = o2 - g * g
            disc = b * b - a * c
            ok = disc >= 0
            sq = jnp.sqrt(jnp.where(ok, disc, 0.0))
            q = -(b + jnp.where(b >= 0, sq, -sq))
            r1 = jnp.where(a != 0, q / jnp.where(a != 0, a, 1.0), _INF)
            r2 = jnp.where(q != 0, c / jnp.where(q != 0, q, 1.0), _INF)

            def admissible(t: Any) -> Any:
                y = oy + t * dy
                return ok & (t > t_min) & (y >= lo) & (y <= hi) & (g + h * t >= 0)

            t = jnp.minimum(
                jnp.where(admissible(r1), r1, _INF), jnp.where(admissible(r2), r2, _INF)
            )
            closer = t < t_best
            return (
                jnp.where(closer, t, t_best).astype(t_best.dtype),  # x64 tables, f32 rays
                jnp.where(closer, piece, idx).astype(idx.dtype),
            )

        def annulus(i: Any, carry: tuple[Any, Any]) -> tuple[Any, Any]:
            t_best, idx = carry
            y, lo2, hi2, piece = annuli[0, i], annuli[1, i], annuli[2, i], annuli[3, i]
            t = _safe_div(y - oy, dy, _INF)
            x = o[0] + t * d[0]
            z = o[2] + t * d[2]
            rho2 = x * x + z * z
            ok = (dy != 0) & (rho2 >= lo2) & (rho2 <= hi2) & (t > t_min)
            closer = ok & (t < t_best)
            return (
                jnp.where(closer, t, t_best).astype(t_best.dtype),  # x64 tables, f32 rays
                jnp.where(closer, piece, idx).astype(idx.dtype),
            )

        carry = jax.lax.fori_loop(0, cones.shape[1], cone, init)
        return jax.lax.fori_loop(0, annuli.shape[1], annulus, carry)

    def intersect(self, o: Vec3, d: Vec3) -> tuple[Any, Any, Vec3]:
        table, cones, annuli = self._tables()
        t, idx = self._nearest(cones, annuli, o, d, -_INF, False)
        hit = idx >= 0
        t_safe = jnp.where(hit, t, 0.0)
        x = o[0] + t_safe * d[0]
        y = o[1] + t_safe * d[1]
        z = o[2] + t_safe * d[2]
        rho = jnp.sqrt(x * x + z * z)
        seg = table[:, jnp.maximum(idx, 0.0).astype(jnp.int32)]
        ya, yb, ra, rb = seg[0], seg[1], seg[2], seg[3]
        flat = ya == yb
        u = jnp.where(flat, _safe_div(rho - ra, rb - ra), _safe_div(y - ya, yb - ya))
        u = jnp.clip(u, 0.0, 1.0)
        tr = (1.0 - u) * seg[4] + u * seg[6]  # interpolated tangent (Δr, Δy)
        ty = (1.0 - u) * seg[5] + u * seg[7]
        nx = _safe_div(x, rho) * ty
        nz = _safe_div(z, rho) * ty
        ny = -tr
        if self._function is not None:
            # Newton's method on ρ(t) − r(y(t)) = 0 from the polyline hit: the smooth
            # surface's own point, where the normal is (x/ρ, −r'(y), z/ρ) exactly
            ok, (ex, ey, ez) = self._refine(o, d, t_safe, hit & ~flat)
            nx, ny, nz = jnp.where(ok, ex, nx), jnp.where(ok, ey, ny), jnp.where(ok, ez, nz)
        norm = jnp.sqrt(nx * nx + ny * ny + nz * nz)
        norm = jnp.where(norm > 0, norm, 1.0)
        return jnp.where(hit, t, _INF), hit, (nx / norm, ny / norm, nz / norm)

    def _refine(self, o: Vec3, d: Vec3, t0: Any, candidate: Any) -> tuple[Any, Vec3]:
        """Newton steps from the polyline hit ``t0`` onto the smooth profile's surface.

        Returns where the refined point is accepted (it converged, stayed within a few
        segment heights and inside ``y_range``) and the unnormalised normal there.
        """
        fn = self._function
        y_lo, y_hi = (float(v) for v in self.y_range)

        def residual(t: Any) -> tuple[Any, ...]:
            x = o[0] + t * d[0]
            y = o[1] + t * d[1]
            z = o[2] + t * d[2]
            rho = jnp.sqrt(x * x + z * z)
            r, dr = jax.jvp(fn, (y,), (jnp.ones_like(y),))
            f = rho - r
            df = _safe_div(x * d[0] + z * d[2], rho) - dr * d[1]
            return f, df, x, y, z, rho, dr

        f0 = residual(t0)[0]
        t = t0
        for _ in range(3):
            f, df = residual(t)[:2]
            t = t - _safe_div(f, df)
        f, _, x, y, z, rho, dr = residual(t)
        h = (y_hi - y_lo) / self.segments
        ok = (
            candidate
            & jnp.isfinite(t)
            & (jnp.abs(t - t0) < 2.0 * h)
            & (jnp.abs(f) <= jnp.abs(f0))
            & (y >= y_lo)
            & (y <= y_hi)
            & (rho > 0)
        )
        return ok, (_safe_div(x, rho), -dr, _safe_div(z, rho))

    def occluded(self, p: Vec3, d: Vec3, t_min: float) -> Any:
        _, cones, annuli = self._tables()
        _, idx = self._nearest(cones, annuli, p, d, t_min, True)
        return idx >= 0

    def extent(self, axis: np.ndarray) -> tuple[float, float]:
        ya, yb, ra, rb = (np.asarray(v) for v in self.nodes[:4])
        y = np.concatenate([ya, yb])
        r = np.concatenate([ra, rb])
        ay = float(axis[1])
        across = math.sqrt(max(0.0, 1.0 - ay * ay))
        lo = np.min(ay * y - across * r)
        hi = np.max(ay * y + across * r)
        return float(lo), float(hi)

    @property
    def scale(self) -> float:
        ya, yb, ra, rb = (np.asarray(v) for v in self.nodes[:4])
        return float(max(np.ptp(np.concatenate([ya, yb])), np.max(np.concatenate([ra, rb]))))


@dataclass(frozen=True)
class Cylinder(Shape):
    """A closed cylinder of radius ``radius`` and height ``height`` about the y axis, centred
    at the origin: exactly one frustum of slope 0 and two flat caps.
    """

    radius: float = 0.5
    height: float = 2.0
    surface: SurfaceOfRevolution = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        check_range("radius", self.radius, 0.0, math.inf, lo_open=True)
        check_range("height", self.height, 0.0, math.inf, lo_open=True)
        h, r = 0.5 * float(self.height), float(self.radius)
        object.__setattr__(self, "surface", SurfaceOfRevolution(profile=[(-h, r), (h, r)]))

    def intersect(self, o: Vec3, d: Vec3) -> tuple[Any, Any, Vec3]:
        return self.surface.intersect(o, d)

    def extent(self, axis: np.ndarray) -> tuple[float, float]:
        return self.surface.extent(axis)

    @property
    def scale(self) -> float:
        return self.surface.scale
