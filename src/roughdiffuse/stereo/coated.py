"""Photometric stereo of glossy rough objects: a coated rough-diffuse model fitted per pixel.

Clay, plastic, painted wood and glazed ceramics carry a dielectric coat over a rough matte
base. Their images hold highlights that the rough fit (:func:`.rough`) takes for diffuse
light, and cast shadows that a threshold on dark values misses or overdoes. Here the image
model is :class:`~roughdiffuse.models.coated.Coated` (a coat of index η and GGX roughness α
over a rough-diffuse base of albedo ρ and roughness σ; Weidlich and Wilkie, "Arbitrarily
layered micro-facet surfaces", GRAPHITE 2007), I_kc = E_kc f_r(l_k, v; n_p, ρ_pc, σ, α, η)
max(n_p·l_k, 0) with v = +z, fitted by the batched Levenberg–Marquardt of
:func:`.rough.fit_pixels`: per pixel the normal and albedo; σ and α one each for the object
(their Gauss–Newton steps from the Schur complement of the per-pixel systems) or one per
pixel. η is fixed (1.5, glazes and plastics, unless given): the images of a coat determine
it poorly next to α and the albedo.

Highlights are part of the model, not rejected. Shadows are found from the model and the
current normals: an observation is left out where the light is behind the pixel's normal
(attached, n·l ≤ 0; the model is 0 there and its derivative too) or where the surface,
integrated from the current normals (:func:`.depth.integrate`), stands between the pixel and
the light (cast; :func:`cast_shadows` marches from each pixel towards each light over the
depth map); observations darker than the rough fit's threshold stay out too (shadows of
parts outside the mask, which the integrated surface does not hold). The fit starts from
the rough fit's normals, and the shadows are found again after each fit, ``shadow_rounds``
times.

A coat of η > 1 cannot vanish: on a matte object the fit runs to the bounds of σ and α.
When the coated fit's mean squared relative residual is not below the rough fit's, the
result is the rough fit's (``CoatedResult.coat`` False, α NaN): a choice between the two
models by their residuals.

Standard errors are the Gauss–Newton ones, as for the rough fit: s² (JᵀJ)⁻¹ per pixel, and
s² S⁻¹ for σ and α, S the 2 × 2 Schur complement, with s² the residual variance.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import ParameterError
from ..models.base import Model
from ..models.coated import Coated
from .depth import integrate
from .inputs import StereoInput
from .lambertian import observation_weights
from .rough import Family, PixelFit, RoughResult, fit_box, fit_pixels, rough

__all__ = ["CoatedFamily", "CoatedResult", "cast_shadows", "coated", "parameter_count"]

BASES: dict[str, str] = {
    "oren-nayar": "sigma",
    "oren-nayar-full": "sigma",
    "fujii": "roughness",
    "eon": "roughness",
}
"""The bases a coated fit takes (registry ids) and the name of each one's roughness."""

ALPHA_START = 0.2
"""Starting coat roughness α of a fit for one α (GGX; glazes and plastics span 0.05–0.4)."""

DEPTH_TOLERANCE = 1.0
"""Height (pixel units) by which the integrated surface must stand above a ray towards the
light to cast a shadow: the integration's own error, and a pixel's extent, stay below it."""


def parameter_count(channels: int = 1) -> int:
    """Parameters of one pixel of the coated model: the normal (2), the albedo of each
    channel, σ and α; K lights give K values per channel, so at least ``2 + 1 + 2`` lights are
    needed whatever the channels (a colour image's channels share the normal, σ and α)."""
    del channels
    return 2 + 1 + 2


@dataclass(frozen=True)
class CoatedFamily(Family):
    """The coated models of a fit: the base's albedo and roughness (``base_param``, e.g.
    ``"sigma"``) and the coat's α vary; η, the distribution and the absorption are kept.
    :attr:`names` are ``(base_param, "roughness")``."""

    base_param: str = "sigma"

    def build(self, albedo: Any, values: Sequence[Any]) -> Model:
        """The coat with its base's albedo and roughness, and its α, set to these values."""
        base_value, alpha = values
        model = self.model
        assert isinstance(model, Coated)
        base = dataclasses.replace(model.base, albedo=albedo, **{self.base_param: base_value})
        return dataclasses.replace(model, base=base, roughness=alpha)


@dataclass
class CoatedResult(RoughResult):
    """Per-pixel results of coated photometric stereo: those of :class:`RoughResult` (its
    ``albedo`` and ``roughness`` are the base's: ρ and σ) with the coat's.

    Attributes
    ----------
    alpha : float or array (P,)
        The coat's roughness α (GGX).
    alpha_se : float or array (P,)
        Its standard error.
    eta : float
        The coat's index (fixed).
    base : str
        Registry id of the base.
    shadow_rounds : int
        How many times the shadows were found again from the fitted normals.
    coat : bool
        Whether the coat explains the images: False when the coated fit's mean squared
        relative residual is not below the rough fit's (a matte object: a coat of η > 1
        cannot vanish, and the fit runs to its bounds); the normals, albedo and σ are then
        the rough fit's, and α is NaN.
    """

    alpha: Any = 0.0
    alpha_se: Any = 0.0
    eta: float = 1.5
    base: str = "oren-nayar-full"
    shadow_rounds: int = 0
    coat: bool = True

    @property
    def sigma(self) -> Any:
        """The base's roughness (``roughness``; σ for an Oren–Nayar base)."""
        return self.roughness

    @property
    def sigma_se(self) -> Any:
        return self.roughness_se


def _family(base: str, eta: float, distribution: str) -> CoatedFamily:
    """The coated models over the registry's ``base``: its albedo and roughness, and the
    coat's α, fitted in their declared boxes; η and the distribution kept."""
    from .. import registry

    if base not in BASES:
        raise ParameterError(
            f"base must be one of {', '.join(map(repr, BASES))} (a base with a roughness; "
            f"got {base!r})"
        )
    base_model = registry.create(base)
    name = BASES[base]
    model = Coated(base_model, eta, ALPHA_START, distribution)
    return CoatedFamily(
        model,
        (name, "roughness"),
        (fit_box(base_model, name), fit_box(model, "roughness")),
        base_param=name,
    )


def cast_shadows(
    depth: np.ndarray,
    mask: np.ndarray,
    directions: np.ndarray,
    tolerance: float = DEPTH_TOLERANCE,
    slopes: np.ndarray | None = None,
) -> np.ndarray:
    """Observations (K, P) in a cast shadow: the surface z(x, y) (pixel units, NaN outside
    the object) stands above the ray from the pixel towards light k.

    The ray starts at the top of the pixel's footprint, half its slope above its centre
    (``slopes`` (P,), |∇z| of each object pixel; none: a flat pixel), and is marched one
    pixel at a time across the image (x right, y up; row 0 at the top), its height rising by
    l_z / |l_xy| per pixel, until it leaves the image or rises above the highest point of
    the surface; an occluder is a sample higher than the ray by
    more than ``tolerance``. The surface is sampled by bilinear interpolation between the
    four nearest pixels (below a convex surface, never above it), or the nearest pixel where
    one of the four lies outside the object. Pixels outside the object do not occlude.
    """
    z = np.asarray(depth, dtype=np.float64)
    m = np.asarray(mask, dtype=bool)
    h, w = m.shape
    rows, cols = np.nonzero(m)
    z0 = z[m] + (0.0 if slopes is None else 0.5 * np.asarray(slopes, dtype=np.float64))
    top = float(np.nanmax(z))
    height = np.where(np.isfinite(z), z, -np.inf)
    shadow = np.zeros((len(directions), rows.size), dtype=bool)
    for k, (lx, ly, lz) in enumerate(np.asarray(directions, dtype=np.float64)):
        across = math.hypot(lx, ly)
        if across < 1e-9:
            continue  # a light on the view axis: a height field casts no shadow
        dx, dy, rise = lx / across, ly / across, lz / across
        idx = np.flatnonzero(np.isfinite(z0))
        for s in range(1, int(math.hypot(h, w)) + 1):
            ray = z0[idx] + s * rise
            keep = ray < top - tolerance
            idx, ray = idx[keep], ray[keep]
            rf, cf = rows[idx] - s * dy, cols[idx] + s * dx
            inside = (rf > -0.5) & (rf < h - 0.5) & (cf > -0.5) & (cf < w - 0.5)
            idx, ray, rf, cf = idx[inside], ray[inside], rf[inside], cf[inside]
            if idx.size == 0:
                break
            hit = _surface(height, rf, cf) > ray + tolerance
            shadow[k, idx[hit]] = True
            idx = idx[~hit]
    return shadow


def _surface(height: np.ndarray, rf: np.ndarray, cf: np.ndarray) -> np.ndarray:
    """The height map at fractional (row, column): bilinear between the four nearest pixels,
    the nearest pixel's value where one of them is −∞ (outside the object)."""
    h, w = height.shape
    r0 = np.clip(np.floor(rf).astype(np.int64), 0, h - 1)
    c0 = np.clip(np.floor(cf).astype(np.int64), 0, w - 1)
    r1, c1 = np.minimum(r0 + 1, h - 1), np.minimum(c0 + 1, w - 1)
    fr, fc = np.clip(rf - r0, 0.0, 1.0), np.clip(cf - c0, 0.0, 1.0)
    corners = height[r0, c0], height[r0, c1], height[r1, c0], height[r1, c1]
    whole = np.all(np.isfinite(corners), axis=0)
    safe = [np.where(whole, v, 0.0) for v in corners]
    bilinear = (safe[0] * (1 - fc) + safe[1] * fc) * (1 - fr) + (
        safe[2] * (1 - fc) + safe[3] * fc
    ) * fr
    nearest = height[
        np.clip(np.rint(rf).astype(np.int64), 0, h - 1),
        np.clip(np.rint(cf).astype(np.int64), 0, w - 1),
    ]
    return np.where(whole, bilinear, nearest)


def model_weights(
    data: StereoInput, normals: np.ndarray, depth_method: str = "poisson", shadow: float = 0.0
) -> np.ndarray:
    """0/1 weights (K, P) of the observations the coated model explains: valid (finite, not
    saturated), lit by the light (n·l > 0 for the current normals), not in a cast shadow
    of the surface integrated from them (:func:`cast_shadows`) and, with ``shadow`` > 0, not
    darker than that fraction of the pixel's brightest (:func:`.observation_weights`: the
    shadows the integrated surface misses, e.g. of parts outside the mask)."""
    m = data.mask
    n = np.asarray(normals, dtype=np.float64)
    good = np.all(np.isfinite(n), axis=1)
    lit = (np.nan_to_num(n) @ data.directions.T).T > 0  # (K, P)
    image = np.full(m.shape + (3,), np.nan)
    image[m] = n
    usable = m & np.all(np.isfinite(image), axis=-1)
    cast = np.zeros_like(lit)
    if usable.sum() >= 2:
        z = integrate(image, usable, depth_method)
        tilt = np.hypot(n[:, 0], n[:, 1]) / np.maximum(n[:, 2], 0.05)  # |∇z|, ≤ 20 (87°)
        cast = cast_shadows(z, m, data.directions, slopes=np.nan_to_num(tilt))
    keep = data.valid[:, m] & lit & ~cast & good[None, :]
    if shadow > 0:
        keep &= observation_weights(data, shadow) > 0
    return keep.astype(np.float64)


def _start_albedo(family: CoatedFamily, albedo: np.ndarray, base_value: float) -> np.ndarray:
    """The base albedo whose coated value matches the rough fit's albedo ρ_r (the value of the
    uncoated base of albedo ρ_r), at μi = μo = 0.8 with the light and view 90° apart in
    azimuth and a smooth coat (no highlight there): the coat's transmittance, about 0.6,
    taken out, so the fit starts near its answer."""
    grid = np.linspace(0.0, 1.0, 101)
    mu = np.array([0.8])
    cos_io = np.array([0.64])
    coated_value = np.array(
        [
            float(family.build(a, [base_value, 0.0]).brdf_cosines(mu, mu, cos_io)[0])
            if a > 0
            else 0.0
            for a in grid
        ]
    )
    bare = family.model.base
    uncoated = np.array(
        [
            float(
                dataclasses.replace(bare, albedo=a, **{family.base_param: base_value}).brdf_cosines(
                    mu, mu, cos_io
                )[0]
            )
            for a in grid
        ]
    )
    target = np.interp(np.clip(np.nan_to_num(albedo, nan=0.5), 0.0, 1.0), grid, uncoated)
    return np.clip(np.interp(target, coated_value, grid), 1e-3, 1.0)


def coated(
    data: StereoInput,
    *,
    base: str = "oren-nayar-full",
    eta: float = 1.5,
    distribution: str = "ggx",
    per_pixel: bool = False,
    start: RoughResult | None = None,
    shadow: float = 0.02,
    shadow_rounds: int = 2,
    depth_method: str = "poisson",
    iterations: int = 30,
    precision: str = "single",
    progress: bool = False,
) -> CoatedResult:
    """Fit normals, base albedo and roughness, and the coat's α, of a coated object.

    Parameters
    ----------
    data : StereoInput
        K ≥ 5 images (:func:`parameter_count`) with their lights and mask.
    base : str
        Registry id of the base under the coat (one of :data:`BASES`).
    eta : float
        The coat's relative index η, kept fixed (in [1.05, 3]).
    distribution : {"ggx", "beckmann"}
        The coat's facet distribution.
    per_pixel : bool
        σ and α per pixel instead of one each for the object.
    start : RoughResult, optional
        Starting normals, albedo and σ (default: :func:`.rough` with the base model and the
        threshold ``shadow``).
    shadow : float
        Observations darker than this fraction of the pixel's brightest are left out, as
        by the rough fit (its start), besides the shadows found from the model.
    shadow_rounds : int
        Times the shadows are found again from the fitted normals, each followed by a fit
        (0: the start's normals only).
    depth_method : {"poisson", "frankot-chellappa"}
        Integration of the normals for the cast shadows.
    iterations, precision, progress
        As :func:`.rough`.

    Returns
    -------
    CoatedResult

    Examples
    --------
    >>> import roughdiffuse as rd
    >>> from roughdiffuse import stereo
    >>> truth = rd.Coated(rd.OrenNayar(0.6, 0.4, "full"), 1.5, 0.3)
    >>> data = stereo.synthetic_sphere(truth, size=24, lights=12, noise=0.0)
    >>> res = stereo.coated(data)
    >>> round(float(res.alpha), 2), round(float(res.sigma), 2)
    (0.3, 0.4)
    """
    family = _family(base, eta, distribution)
    name = family.base_param
    if data.count < parameter_count(data.channels):
        raise ParameterError(
            f"the coated model has {parameter_count(data.channels)} parameters per pixel "
            f"(normal 2, albedo, {name}, coat α): it needs at least "
            f"{parameter_count(data.channels)} lights (got {data.count})"
        )
    if not isinstance(shadow_rounds, int) or shadow_rounds < 0:
        raise ParameterError(f"shadow_rounds must be an integer ≥ 0 (got {shadow_rounds!r})")
    if start is None:
        start = rough(
            data, family.model.base, shadow=shadow, precision=precision, progress=progress
        )
    lo, hi = family.bounds[0]
    base0 = float(np.clip(np.nanmedian(start.roughness), lo + 0.02 * (hi - lo), 0.8 * hi))
    current: Any = dataclasses.replace(start, albedo=_start_albedo(family, start.albedo, base0))
    initial = np.array([base0, ALPHA_START])
    weights = model_weights(data, start.normals, depth_method, shadow)
    label = "coated photometric stereo"
    done = 0
    for round_ in range(shadow_rounds + 1):
        fit = fit_pixels(
            data,
            family,
            start=current,
            weights=weights,
            initial=initial,
            per_pixel=per_pixel,
            subset_start=round_ == 0,
            iterations=iterations,
            precision=precision,
            progress=progress,
            label=label,
        )
        done = round_
        if round_ == shadow_rounds:
            break
        again = model_weights(data, fit.normals, depth_method, shadow)
        if np.array_equal(again, weights):
            break
        weights, current, initial = again, fit, fit.values
    coat = {"eta": float(eta), "base": base, "shadow_rounds": done}
    return _result(fit, start, family.base_param, per_pixel, coat)


def _result(
    fit: PixelFit, start: RoughResult, name: str, per_pixel: bool, coat: dict[str, Any]
) -> CoatedResult:
    """The coated fit as a :class:`CoatedResult` (``coat``: η, base id, shadow rounds), or
    the rough start's result when the coat does not lower the mean squared relative
    residual (``coat=False``, α NaN)."""
    values, se = fit.values, fit.values_se
    pick = (lambda a, j: a[:, j]) if per_pixel else (lambda a, j: float(a[j]))
    if not np.nanmean(fit.residual**2) < np.nanmean(np.asarray(start.residual) ** 2):
        # the coat does not explain the images better than the bare base: keep the base
        fields = {f.name: getattr(start, f.name) for f in dataclasses.fields(RoughResult)}
        nan = np.full_like(values[:, 1], np.nan) if per_pixel else math.nan
        return CoatedResult(**fields, alpha=nan, alpha_se=nan, coat=False, **coat)
    return CoatedResult(
        normals=fit.normals,
        albedo=fit.albedo,
        roughness=pick(values, 0),
        roughness_name=name,
        roughness_se=pick(se, 0),
        normal_se=fit.normal_se,
        albedo_se=fit.albedo_se,
        residual=fit.residual,
        weights=fit.weights,
        iterations=fit.iterations,
        alpha=pick(values, 1),
        alpha_se=pick(se, 1),
        **coat,
    )
