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
the light (cast; :func:`cast_shadows`, one sweep of the depth map per light); observations
darker than the rough fit's threshold stay out too (shadows of parts outside the mask, which
the integrated surface does not hold). The fit starts from
Lambertian photometric stereo (the table solver) or the rough fit (the direct one), and the
shadows are found again after each fit, ``shadow_rounds`` times.

Two solvers. ``"table"`` (the default): σ and α (and, with ``light_scale``, one factor on
every light's intensity) by the direct fit of a subsample of well-lit pixels, then every
pixel's normal and albedo by a compiled Levenberg–Marquardt on the model tabulated per
light from its own evaluation (:mod:`.coated_table`), a pixel left with a high residual
solved again from the Lambertian normal of the darker half of its observations
(:func:`_retry`); each shadow round refits the subsample and the pixels. ``"direct"``:
every pixel on the model itself by :func:`.rough.fit_pixels` (σ and α by the Schur
complement, or per pixel).

A coat of η > 1 cannot vanish: on a matte object the fit runs to the bounds of σ and α.
When the coated fit's mean squared relative residual is not below the rough fit's, the
result is the rough fit's (``CoatedResult.coat`` False, α NaN): a choice between the two
models by their residuals.

Standard errors are those of the rough fit: Gauss–Newton's s² (JᵀJ)⁻¹ per pixel, and for σ
and α the pixels' sandwich S⁻¹ B S⁻¹ (:func:`.rough.fit_pixels`; S the 2 × 2 Schur
complement, B the spread of the pixels' profiled scores), which holds when the model misfits
a pixel as a whole. The table solver's σ and α come from the smoother pixels of the object
(:data:`SMOOTH`): a pixel whose normals spread much over its footprint averages a narrow
coat's highlight into a broader one.
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
from .depth import clear_cache, integrate, prefactor
from .footprint import normal_spread, smoothest
from .inputs import StereoInput
from .lambertian import LambertianResult, lambertian, lambertian_normals, observation_weights
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

SCALE_BOX = (0.01, 100.0)
"""The fit box of the light scale s (intensities off by up to a factor 100 either way)."""

SUBSAMPLE = 512
"""Pixels of the subsample on which the table solver fits σ, α and the light scale."""

SOLVERS = ("table", "direct")
"""``solver`` of :func:`coated`: the table of the model with the object's values fitted on a
subsample (:mod:`.coated_table`), or the direct fit of every pixel on the model itself."""

SETTLED = 1e-3
"""The table solver's shadow rounds stop when fewer than this fraction of the observations
changed from shadowed to kept or back."""

SMOOTH = 0.25
"""After the first round the table solver draws its subsample again among the well-lit
pixels whose normals differ least from their neighbours' (this fraction of them, and at
least the subsample's size), and fits σ and α on it once more. A pixel's footprint spans the
normals between its neighbours'; where they spread by a fair part of α, the pixel's value
is the mean of the model over them, not the model at their mean: a broader highlight. On
the α = 0.1 vase of ``scripts/stereo_renders.py`` at 128² (its belly's ridge and its neck
spread 5–12° a pixel), σ from the true normals and 512 well-lit pixels of each draw: 0.39–
0.42 over all of them, 0.396–0.402 over the smoothest quarter (truth 0.4)."""

RESTART = 0.25
"""The least starting base roughness of a fit, as a fraction of its box (σ: 0.39), and where
it starts a second time when the subsample's refit (:func:`_polish`) stopped at its lower
bound: at σ = 0 the model's slope in σ is 0 (Oren–Nayar's A and B are functions of σ²), so
a fit that reaches it, or starts near it, stays. The rough fit that starts the coated one
gives σ = 0 on most coated objects (the highlights); from there (σ 0.03 before), on the
renders of ``scripts/stereo_renders.py`` at 128², the fits with a light scale of the α = 0.1
sphere and blob stopped at α 0.20 and σ 0.03–0.06 (normals 0.9–1.0° off; now α 0.100 and
0.102, σ 0.42 ± 0.01 and 0.42 ± 0.02, 0.30° and 0.50°), and the refit of the α = 0.1 blob's
pixels within 60° of the view at σ = 0 ± ∞ (from 0.39: 0.405 ± 0.014)."""

RETRY = (3.0, 0.1)
"""The table solver fits a pixel again from a second start when its relative residual is
above RETRY[0] times the object's RETRY[1] quantile (:func:`_retry`): the noise's level,
from the pixels the model fits (the median rises with the pixels stuck, which may be most
of them on an object facing the camera under a narrow coat)."""

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
    :attr:`names` are ``(base_param, "roughness")``, then ``"light_scale"`` with
    :attr:`light_scale`: one factor s on every light's intensity (:meth:`scale`), for
    intensities known only relative to each other."""

    base_param: str = "sigma"
    light_scale: bool = False

    def build(self, albedo: Any, values: Sequence[Any]) -> Model:
        """The coat with its base's albedo and roughness, and its α, set to these values."""
        base_value, alpha = values[0], values[1]
        model = self.model
        assert isinstance(model, Coated)
        base = dataclasses.replace(model.base, albedo=albedo, **{self.base_param: base_value})
        return dataclasses.replace(model, base=base, roughness=alpha)

    def scale(self, values: Sequence[Any]) -> Any:
        """The light scale s (the third value) when :attr:`light_scale`, else 1."""
        return values[2] if self.light_scale else 1.0


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
    light_scale, light_scale_se : float
        The factor fitted on every light's intensity, with its standard error (1 and 0
        when not fitted).
    solver : str
        ``"table"`` or ``"direct"`` (see :func:`coated`).
    table_error : float
        The table solver's measured table error, relative to each light's brightest value
        (:attr:`.coated_table.CoatedTable.error`); NaN for the direct solver.
    """

    alpha: Any = 0.0
    alpha_se: Any = 0.0
    eta: float = 1.5
    base: str = "oren-nayar-full"
    shadow_rounds: int = 0
    coat: bool = True
    light_scale: float = 1.0
    light_scale_se: float = 0.0
    solver: str = "direct"
    table_error: float = math.nan

    @property
    def sigma(self) -> Any:
        """The base's roughness (``roughness``; σ for an Oren–Nayar base)."""
        return self.roughness

    @property
    def sigma_se(self) -> Any:
        return self.roughness_se


def _family(base: str, eta: float, distribution: str, light_scale: bool = False) -> CoatedFamily:
    """The coated models over the registry's ``base``: its albedo and roughness, and the
    coat's α, fitted in their declared boxes (and the light scale in :data:`SCALE_BOX`);
    η and the distribution kept."""
    from .. import registry

    if base not in BASES:
        raise ParameterError(
            f"base must be one of {', '.join(map(repr, BASES))} (a base with a roughness; "
            f"got {base!r})"
        )
    base_model = registry.create(base)
    name = BASES[base]
    model = Coated(base_model, eta, ALPHA_START, distribution)
    names: tuple[str, ...] = (name, "roughness")
    bounds = (fit_box(base_model, name), fit_box(model, "roughness"))
    if light_scale:
        names, bounds = (*names, "light_scale"), (*bounds, SCALE_BOX)
    return CoatedFamily(model, names, bounds, base_param=name, light_scale=light_scale)


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
    (``slopes`` (P,), |∇z| of each object pixel; none: a flat pixel), and crosses the image
    (x right, y up; row 0 at the top) one column at a time, or one row where the light's
    direction in the image runs more along y, its height rising by l_z / |l_x| (or
    / |l_y|) per step; an occluder is a sample higher than the ray by more than
    ``tolerance``. The surface is sampled where the ray crosses each column (row): linearly
    between the two nearest pixels (below a convex surface, never above it), or the nearest
    pixel where one of them lies outside the object. Pixels outside the object do not
    occlude.

    Rays towards one light are parallel, so the highest the surface stands above the ray
    from each pixel follows from the next column's (row's) in one sweep of the image per
    light, from the far side (the horizon of the height field; the next column's values
    are taken linearly between its two pixels nearest the ray): O(H W) per light instead of
    O(H W max(H, W)) for marching each ray. Compiled (Numba), parallel over the lights.
    """
    return _unshadowed(depth, mask, directions, tolerance, slopes) == 0.0


def _unshadowed(depth: np.ndarray | None, mask: np.ndarray, directions: np.ndarray,
                tolerance: float, slopes: np.ndarray | None, normals: np.ndarray | None = None,
                keep: np.ndarray | None = None) -> np.ndarray:
    """0/1 weights (K, P): 1 where ``keep`` (K, P; none: everywhere) and, with ``normals``
    (P, 3), lit (n·l > 0; a NaN normal is not), and not in a cast shadow of ``depth``
    (:func:`cast_shadows`; none: no surface casts one). One compiled pass, no (K, P)
    temporaries (96 lights and a megapixel: 0.7 GB each)."""
    from .coated_kernels import sweep_shadows

    m = np.asarray(mask, dtype=bool)
    rows, cols = np.nonzero(m)
    if depth is None:
        height, z0 = np.full(m.shape, -np.inf), np.zeros(rows.size)
    else:
        z = np.asarray(depth, dtype=np.float64)
        height = np.ascontiguousarray(np.where(np.isfinite(z), z, -np.inf))
        z0 = z[m] + (0.0 if slopes is None else 0.5 * np.asarray(slopes, dtype=np.float64))
    count = len(directions)
    keep = np.ones((count, rows.size), dtype=np.bool_) if keep is None else keep
    n = np.zeros((0, 3)) if normals is None else np.ascontiguousarray(normals, dtype=np.float64)
    out = np.empty((count, rows.size))
    sweep_shadows(height, rows, cols, np.ascontiguousarray(z0, dtype=np.float64),
                  np.ascontiguousarray(directions, dtype=np.float64), float(tolerance), n,
                  np.ascontiguousarray(keep, dtype=np.bool_), out)
    return out


def model_weights(
    data: StereoInput, normals: np.ndarray, depth_method: str = "poisson", shadow: float = 0.0,
    kept: np.ndarray | None = None,
) -> np.ndarray:
    """0/1 weights (K, P) of the observations the coated model explains: valid (finite, not
    saturated), lit by the light (n·l > 0 for the current normals), not in a cast shadow
    of the surface integrated from them (:func:`cast_shadows`) and, with ``shadow`` > 0, not
    darker than that fraction of the pixel's brightest (:func:`.observation_weights`: the
    shadows the integrated surface misses, e.g. of parts outside the mask). ``kept``
    (K, P) bool: those of the threshold, when already at hand (``shadow`` is then not
    used)."""
    m = data.mask
    n = np.asarray(normals, dtype=np.float64)
    image = np.full(m.shape + (3,), np.nan)
    image[m] = n
    usable = m & np.all(np.isfinite(image), axis=-1)
    z, tilt = None, None
    if usable.sum() >= 2:
        z = integrate(image, usable, depth_method)
        tilt = np.nan_to_num(np.hypot(n[:, 0], n[:, 1]) / np.maximum(n[:, 2], 0.05))  # ≤ 20
    if kept is None:
        kept = (observation_weights(data, shadow) > 0) if shadow > 0 else data.observed
    elif np.shape(kept) != data.observed.shape:  # the kernel reads it unchecked
        raise ParameterError(f"kept must have shape {data.observed.shape} (lights, object "
                             f"pixels; got {np.shape(kept)})")
    return _unshadowed(z, m, data.directions, DEPTH_TOLERANCE, tilt, normals=n, keep=kept)


def _start_albedo(family: CoatedFamily, albedo: np.ndarray, base_value: float) -> np.ndarray:
    """The base albedo whose coated value matches the rough fit's albedo ρ_r (the value of the
    uncoated base of albedo ρ_r), at μi = μo = 0.8 with the light and view 90° apart in
    azimuth and a smooth coat (no highlight there): the coat's transmittance, about 0.6,
    taken out, so the fit starts near its answer."""
    grid = np.linspace(0.0, 1.0, 101)
    mu = np.array([0.8])
    cos_io = np.array([0.64])
    # one model per albedo of the grid, evaluated at once (the albedo broadcasts)
    coated_value = np.ravel(family.build(grid, [base_value, 0.0]).brdf_cosines(mu, mu, cos_io))
    bare = dataclasses.replace(family.model.base, albedo=grid, **{family.base_param: base_value})
    uncoated = np.ravel(bare.brdf_cosines(mu, mu, cos_io))
    target = np.interp(np.clip(np.nan_to_num(albedo, nan=0.5), 0.0, 1.0), grid, uncoated)
    return np.clip(np.interp(target, coated_value, grid), 1e-3, 1.0)


def coated(
    data: StereoInput,
    *,
    base: str = "oren-nayar-full",
    eta: float = 1.5,
    distribution: str = "ggx",
    per_pixel: bool = False,
    start: RoughResult | LambertianResult | None = None,
    shadow: float = 0.02,
    shadow_rounds: int = 2,
    depth_method: str = "poisson",
    iterations: int = 30,
    precision: str = "single",
    progress: bool = False,
    light_scale: bool = False,
    solver: str = "table",
    subsample: int = SUBSAMPLE,
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
        σ and α per pixel instead of one each for the object (the direct solver; no light
        scale).
    start : RoughResult or LambertianResult, optional
        Starting normals and albedo (and σ, from a rough fit). Default: Lambertian
        photometric stereo with the threshold ``shadow`` for the table solver, the rough
        fit (:func:`.rough`) of the base for the direct one.
    shadow : float
        Observations darker than this fraction of the pixel's brightest are left out, as
        by the rough fit, besides the shadows found from the model.
    shadow_rounds : int
        Times the shadows are found again from the fitted normals, each followed by a fit
        (0: the start's normals only).
    depth_method : {"poisson", "frankot-chellappa"}
        Integration of the normals for the cast shadows.
    iterations, precision, progress
        As :func:`.rough` (the direct fits; the table solver's per-pixel steps are at most
        ``iterations`` too).
    light_scale : bool
        Fit one factor s on every light's intensity (an object-wide unknown, e.g.
        DiLiGenT's intensities, which are relative): the highlight's height against the
        base's light fixes it; the albedo alone cannot absorb it (ρ enters the coated model
        nonlinearly, and the coat's reflection not at all).
    solver : {"table", "direct"}
        ``"table"`` (default): σ, α (and s) fitted by the direct fit on a subsample of
        ``subsample`` well-lit pixels, then every pixel's normal and albedo by a compiled
        Levenberg–Marquardt on the model tabulated per light (:mod:`.coated_table`; its
        measured error is :attr:`CoatedResult.table_error`). ``"direct"``: every pixel
        fitted on the model itself (slow: the coat's quadrature rules per light and pixel).
    subsample : int
        Pixels of the table solver's subsample (all pixels when there are fewer).

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
    if solver not in SOLVERS:
        raise ParameterError(f"solver must be one of {', '.join(map(repr, SOLVERS))} "
                             f"(got {solver!r})")
    if not isinstance(subsample, int) or subsample < 16:
        raise ParameterError(f"subsample must be an integer ≥ 16 (got {subsample!r})")
    family = _family(base, eta, distribution, light_scale and not per_pixel)
    name = family.base_param
    if data.count < parameter_count(data.channels):
        raise ParameterError(
            f"the coated model has {parameter_count(data.channels)} parameters per pixel "
            f"(normal 2, albedo, {name}, coat α): it needs at least "
            f"{parameter_count(data.channels)} lights (got {data.count})"
        )
    if not isinstance(shadow_rounds, int) or shadow_rounds < 0:
        raise ParameterError(f"shadow_rounds must be an integer ≥ 0 (got {shadow_rounds!r})")
    coat = {"eta": float(eta), "base": base, "solver": solver}
    opts = _Options(shadow, shadow_rounds, depth_method, iterations, precision, progress)
    try:
        if solver == "table" and not per_pixel:
            return _table_fit(data, family, start, opts, subsample, coat)
        if not isinstance(start, RoughResult):
            start = rough(
                data, family.model.base, shadow=shadow, precision=precision, progress=progress,
                start=start,
            )
        fit, done = _direct_fit(data, family, start, opts, per_pixel)
        return _result(fit, start, family, per_pixel, {**coat, "shadow_rounds": done})
    finally:
        clear_cache()  # the depth's factorisation, kept for the shadow rounds


def _initial(family: CoatedFamily, start: RoughResult) -> tuple[np.ndarray, Any]:
    """The starting σ, α (and light scale 1) of a fit from the rough fit ``start`` (its σ,
    at least :data:`RESTART` of the box), and the start with its albedo converted to the
    coated model's (:func:`_start_albedo`)."""
    lo, hi = family.bounds[0]
    base0 = float(np.clip(np.nanmedian(start.roughness), lo + RESTART * (hi - lo), 0.8 * hi))
    current = dataclasses.replace(start, albedo=_start_albedo(family, start.albedo, base0))
    initial = [base0, ALPHA_START] + ([1.0] if family.light_scale else [])
    return np.array(initial), current


@dataclass(frozen=True)
class _Options:
    """The options of :func:`coated` that both solvers follow."""

    shadow: float
    rounds: int
    depth_method: str
    iterations: int
    precision: str
    progress: bool


def _direct_fit(
    data: StereoInput,
    family: CoatedFamily,
    start: RoughResult,
    opts: _Options,
    per_pixel: bool,
    weights: np.ndarray | None = None,
) -> tuple[PixelFit, int]:
    """The fit of every pixel of ``data`` on the model itself (:func:`.rough.fit_pixels`),
    the shadows found again after each fit ``shadow_rounds`` times; the fit and the rounds
    done. ``weights`` (K, P): the first round's, instead of those of the start's normals."""
    initial, current = _initial(family, start)
    shadow, depth_method = opts.shadow, opts.depth_method
    if weights is None:
        weights = model_weights(data, start.normals, depth_method, shadow)
    done = 0
    for round_ in range(opts.rounds + 1):
        fit = fit_pixels(
            data,
            family,
            start=current,
            weights=weights,
            initial=initial,
            per_pixel=per_pixel,
            subset_start=round_ == 0,
            iterations=opts.iterations,
            precision=opts.precision,
            progress=opts.progress,
            label="coated photometric stereo",
        )
        done = round_
        if round_ == opts.rounds:
            break
        again = model_weights(data, fit.normals, depth_method, shadow)
        if np.array_equal(again, weights):
            break
        weights, current, initial = again, fit, fit.values
    return fit, done


def _well_lit(weights: np.ndarray, ok: np.ndarray, count: int,
              spread: np.ndarray | None = None) -> np.ndarray:
    """Up to ``count`` pixels (sorted indices) drawn at random among those with at least
    the median number of kept observations: their highlights and shading are seen. With
    ``spread`` (P,), the angle between each pixel's normal and its neighbours'
    (:func:`.footprint.normal_spread`), among the :data:`SMOOTH` fraction of them (at least
    ``count``) whose spread is least."""
    kept = weights.sum(axis=0)
    pool = np.flatnonzero(ok & (kept >= max(np.median(kept[ok]) if ok.any() else 0, 3)))
    if pool.size <= count:
        return pool
    if spread is not None:
        pool = smoothest(spread, pool, SMOOTH, count)
    return np.sort(np.random.default_rng(0).choice(pool, count, replace=False))


def _pixels(data: StereoInput, pick: np.ndarray) -> StereoInput:
    """``data`` with the mask reduced to the object pixels ``pick`` (indices in mask order)."""
    rows, cols = np.nonzero(data.mask)
    mask = np.zeros_like(data.mask)
    mask[rows[pick], cols[pick]] = True
    return dataclasses.replace(data, mask=mask)


def _table_fit(
    data: StereoInput,
    family: CoatedFamily,
    start: RoughResult | LambertianResult | None,
    opts: _Options,
    subsample: int,
    coat: dict[str, Any],
) -> CoatedResult:
    """The table solver of :func:`coated`: the object's values from the direct fit of a
    subsample of well-lit pixels, then every pixel on the model's table; the shadows found
    again from the fitted normals after each round, and the subsample's fit redone with
    them where at least :data:`SETTLED` of its own observations changed, and after the first
    round always, drawn again among the smoother pixels (:data:`SMOOTH`) from the table
    fit's normals (the table kept while it stands for the values fitted again, :func:`_kept`;
    the rounds stop when fewer than
    :data:`SETTLED` of all the observations changed and the table was kept). A
    matte object (the coat does not lower the subsample's residual) gets the rough fit of
    every pixel. With the table kept, a round solves again only the pixels whose
    observations changed."""
    from .coated_table import coated_table, solve_pixels

    depth_method = opts.depth_method
    iterations, precision = opts.iterations, opts.precision
    base_model = family.model.base
    first, kept, weights, pick, sub, sub_start = _table_start(data, base_model, start, opts,
                                                              subsample)
    obs = data.observations
    normals, albedo = first.normals, None
    done = 0
    fit, sub_fit, table, tabled, checked, redo = None, None, None, None, None, None
    sub_weights = None
    for round_ in range(opts.rounds + 1):
        # the object's values: the direct fit of the subsample (from the last round's)
        now = weights[:, pick]
        if sub_fit is None:
            sub_fit, _ = _direct_fit(sub, family, sub_start,
                                     dataclasses.replace(opts, rounds=0, progress=False), False,
                                     weights=now)
        elif np.mean(now != sub_weights) >= SETTLED:
            # the subsample's own shadows changed: its values may move
            sub_fit = fit_pixels(sub, family, start=sub_fit, weights=now,
                                 initial=sub_fit.values, subset_start=False,
                                 iterations=iterations, precision=precision)
        sub_weights = now
        if round_ == 0 and not _coat_helps(sub_fit, sub_start):
            return _matte(data, base_model, first, opts, coat)
        values = sub_fit.values
        if table is not None and checked is not values:
            table = _kept(table, family, tabled, values, data.directions)
        if table is None:
            table = coated_table(lambda rho, v=values: family.build(rho, v), float(values[1]),
                                 data.directions)
            tabled, redo = values, None
        checked = values
        if albedo is None:
            albedo = _start_albedo(family, np.asarray(first.albedo), float(values[0]))
            albedo = albedo / family.scale(values)
        light = data.intensities * family.scale(tabled)
        if redo is None or fit is None:
            fit = solve_pixels(table, light, obs, weights, normals, albedo,
                               iterations=iterations)
        else:
            # same table: only the pixels whose observations changed move
            part = solve_pixels(table, light, obs[:, redo], weights[:, redo], normals[redo],
                                albedo[redo], iterations=iterations)
            for key, value in part.items():
                fit[key] = fit[key].copy()
                fit[key][redo] = value
        fit = _retry(data, table, light, obs, weights, fit, iterations)
        done = round_
        if round_ == opts.rounds:
            break
        again = model_weights(data, fit["normals"], depth_method, kept=kept)
        sub_fit = dataclasses.replace(
            sub_fit, normals=fit["normals"][pick], albedo=fit["albedo"][pick])
        moved = False
        if round_ == 0:  # the subsample again, among the smoother pixels (SMOOTH)
            pick, sub, sub_fit = _polish(data, family, sub_fit, fit, again, subsample, opts)
            sub_weights = again[:, pick]
            table = _kept(table, family, tabled, sub_fit.values, data.directions)
            checked, moved = sub_fit.values, table is None
        if np.mean(again != weights) < SETTLED and not moved:
            break
        redo = np.any(again != weights, axis=0)
        weights, normals, albedo = again, fit["normals"], fit["albedo"]
    assert fit is not None and sub_fit is not None
    return _table_result(fit, sub_fit, family, weights, obs, table.error,
                         {**coat, "shadow_rounds": done})


def _matte(data: StereoInput, base_model: Model, first: RoughResult | LambertianResult,
           opts: _Options, coat: dict[str, Any]) -> CoatedResult:
    """The result of a matte object (the coat did not lower the subsample's residual): the
    rough fit of every pixel (``first`` when it is one), α NaN."""
    full = first if isinstance(first, RoughResult) else rough(
        data, base_model, shadow=opts.shadow, precision=opts.precision,
        progress=opts.progress, start=first)
    fields = {f.name: getattr(full, f.name) for f in dataclasses.fields(RoughResult)}
    return CoatedResult(**fields, alpha=math.nan, alpha_se=math.nan, coat=False,
                        shadow_rounds=0, **coat)


def _relative_residual(cost: np.ndarray, weights: np.ndarray, obs: np.ndarray) -> np.ndarray:
    """RMS residual of each pixel over its kept observations, relative to their mean."""
    kept = weights.sum(axis=0) * obs.shape[2]
    mean = np.einsum("kp,kpc->p", weights, obs) / np.maximum(kept, 1)
    return np.sqrt(cost / np.maximum(kept, 1)) / np.maximum(mean, 1e-30)


def _retry(data: StereoInput, table: Any, light: np.ndarray, obs: np.ndarray,
           weights: np.ndarray, fit: dict[str, np.ndarray], iterations: int
           ) -> dict[str, np.ndarray]:
    """``fit`` with the pixels whose relative residual is high (:data:`RETRY`) fitted again
    from the Lambertian normal of the darker half of their kept observations, and the lower
    cost of the two kept.

    A narrow coat's highlight (α ≈ 0.1) pulls the Lambertian start of the pixels that see it
    by tens of degrees, beyond the reach of the table's Levenberg–Marquardt, which then
    stops at a local minimum with a residual tens of times the noise's (more so when the
    highlight's peak is saturated and left out). The highlight falls within a minority of
    the lights, so the darker half of a pixel's observations is the base's diffuse light,
    whose Lambertian normal lies within a few degrees of the truth."""
    from .coated_table import solve_pixels

    rel = _relative_residual(fit["cost"], weights, obs)
    ok = fit["ok"] & np.isfinite(rel)
    if not ok.any():
        return fit
    factor, quantile = RETRY
    again = np.flatnonzero(ok & (rel > factor * np.quantile(rel[ok], quantile)))
    if again.size == 0:
        return fit
    grey = data.grey[:, again]  # (K, R)
    w = weights[:, again]
    kept = np.where(w > 0, grey, np.nan)
    darker = w * (grey <= np.nanmedian(kept, axis=0)[None, :])
    start = lambertian_normals(grey, data.directions, darker)
    good = np.all(np.isfinite(start), axis=1)
    again, start = again[good], start[good]
    second = solve_pixels(table, light, obs[:, again], weights[:, again], start,
                          fit["albedo"][again], iterations=iterations)
    better = second["ok"] & (second["cost"] < fit["cost"][again])
    out = {key: value.copy() for key, value in fit.items()}
    for key, value in second.items():
        out[key][again[better]] = value[better]
    return out


def _table_start(data: StereoInput, base_model: Model,
                 start: RoughResult | LambertianResult | None, opts: _Options,
                 subsample: int) -> tuple[Any, np.ndarray, np.ndarray, np.ndarray,
                                          StereoInput, RoughResult]:
    """The table solver's start: the start's normals and albedo (Lambertian photometric
    stereo by default), the threshold's weights (K, P) bool, the model's weights from the
    start's normals, the subsample of well-lit pixels (indices, and as an input), and the
    rough fit of the subsample (the start restricted to it when it is a rough fit)."""
    if opts.depth_method == "poisson":
        prefactor(data.mask)  # the depth's factorisation, beside the Lambertian start
    kept = observation_weights(data, opts.shadow)  # the threshold's, once for every round
    first = lambertian(data, weights=kept) if start is None else start
    kept = kept > 0
    weights = model_weights(data, first.normals, opts.depth_method, kept=kept)
    ok = np.all(np.isfinite(first.normals), axis=1) & (weights.sum(axis=0) >= 3)
    pick = _well_lit(weights, ok, subsample)
    sub = _pixels(data, pick)
    sub_start = _restricted(first, pick)
    if not isinstance(first, RoughResult):
        sub_start = rough(sub, base_model, shadow=opts.shadow, precision=opts.precision,
                          start=sub_start)
    return first, kept, weights, pick, sub, sub_start


def _polish(data: StereoInput, family: CoatedFamily, sub_fit: PixelFit,
            fit: dict[str, np.ndarray], weights: np.ndarray, count: int, opts: _Options
            ) -> tuple[np.ndarray, StereoInput, PixelFit]:
    """The subsample drawn again among the smoother well-lit pixels (:data:`SMOOTH`, from
    the table fit ``fit``'s normals and the weights (K, P) they give), and the object's
    values fitted on it from the table fit's normals and albedo, starting from
    ``sub_fit``'s values: the joint fit from the start's normals can stop short along σ (the
    α = 0.1 blob render at 128²: 0.365 ± 0.007; from the table fit's normals, or from the
    true ones, 0.396 ± 0.005). Returns the new subsample (indices, input) and its fit."""
    normals = fit["normals"]
    ok = fit["ok"] & np.all(np.isfinite(normals), axis=1)
    pick = _well_lit(weights, ok, count, normal_spread(data.mask, normals))
    sub = _pixels(data, pick)
    start = dataclasses.replace(sub_fit, normals=normals[pick], albedo=fit["albedo"][pick])

    def refit(initial: np.ndarray) -> PixelFit:
        return fit_pixels(sub, family, start=start, weights=weights[:, pick], initial=initial,
                          subset_start=False, iterations=opts.iterations,
                          precision=opts.precision)

    polished = refit(np.asarray(sub_fit.values, dtype=np.float64))
    lo, hi = family.bounds[0]
    if polished.values[0] <= lo + 1e-6 * (hi - lo):
        # at σ = 0 the model's slope in σ is 0 (Oren–Nayar's A and B are functions of σ²):
        # a fit that reaches it stays; from RESTART of the box too, the lower residual kept
        initial = np.array(polished.values, dtype=np.float64)
        initial[0] = lo + RESTART * (hi - lo)
        other = refit(initial)
        if np.nanmean(other.residual**2) < np.nanmean(polished.residual**2):
            polished = other
    return pick, sub, polished


def _kept(table: Any, family: CoatedFamily, tabled: np.ndarray, values: np.ndarray,
          directions: np.ndarray) -> Any:
    """``table`` (made of the object's values ``tabled``) when it stands for the model of
    ``values`` (the subsample fitted again) within :data:`.coated_table.ERROR_BOUND`,
    measured as its own error is (:func:`.coated_table.table_error`), plus the light
    scale's relative change (every value scales with it); the error it carries is then
    this one. Else None: a new table, at the cost of a solve of every pixel (6 s of 37 on
    the 1024² α = 0.3 sphere render of ``scripts/stereo_renders.py``). At 128² the α = 0.3
    objects' refits move σ and α by up to 0.007 and 0.005: the table's error from 2.7e-3
    to at most 3.7e-3 (on the 1024² sphere, normals 0.006° apart, at most 0.07°, from
    those of a new table); the α = 0.1 objects' by up to 0.26 and 0.04: 1.9e-2 to 0.29."""
    from .coated_table import ERROR_BOUND, table_error

    error = table_error(table, lambda rho: family.build(rho, values), directions)
    error += abs(float(family.scale(values)) / float(family.scale(tabled)) - 1.0)
    return dataclasses.replace(table, error=error) if error <= ERROR_BOUND else None


def _coat_helps(fit: PixelFit, start: RoughResult) -> bool:
    """Whether the coated fit's mean squared relative residual is below the rough fit's."""
    return bool(np.nanmean(fit.residual**2) < np.nanmean(np.asarray(start.residual) ** 2))


def _restricted(result: Any, pick: np.ndarray) -> Any:
    """A start (rough or Lambertian result) restricted to the pixels ``pick``."""
    if isinstance(result, RoughResult):
        per = {f.name: getattr(result, f.name) for f in dataclasses.fields(RoughResult)}
        for key in ("normals", "albedo", "normal_se", "albedo_se", "residual"):
            per[key] = np.asarray(per[key])[pick]
        per["weights"] = np.asarray(per["weights"])[:, pick]
        if np.ndim(per["roughness"]) == 1:
            per["roughness"] = per["roughness"][pick]
            per["roughness_se"] = per["roughness_se"][pick]
        return RoughResult(**per)
    return LambertianResult(result.normals[pick], result.albedo[pick],
                            result.residual[pick], result.weights[:, pick])


def _table_result(fit: dict[str, np.ndarray], sub_fit: PixelFit, family: CoatedFamily,
                  weights: np.ndarray, obs: np.ndarray, table_error: float,
                  coat: dict[str, Any]) -> CoatedResult:
    """The table solver's pixels with their Gauss–Newton standard errors (s² (JᵀJ)⁻¹, s²
    the pixel's residual variance) and the object's values from the subsample's fit."""
    ok = fit["ok"]
    c = obs.shape[2]
    kept = weights.sum(axis=0) * c
    s2 = fit["cost"] / np.maximum(kept - (2 + c), 1)
    var = fit["a_inv_diag"] * s2[:, None]
    rel = _relative_residual(fit["cost"], weights, obs)
    values, se = sub_fit.values, sub_fit.values_se
    scaled = family.light_scale
    return CoatedResult(
        normals=fit["normals"],
        albedo=fit["albedo"],
        roughness=float(values[0]),
        roughness_name=family.base_param,
        roughness_se=float(se[0]),
        normal_se=np.where(ok, np.sqrt(np.maximum(var[:, 0] + var[:, 1], 0.0)), np.nan),
        albedo_se=np.where(ok[:, None], np.sqrt(np.maximum(var[:, 2:], 0.0)), np.nan),
        residual=np.where(ok, rel, np.nan),
        weights=np.where(ok[None, :], weights, 0.0),
        iterations=int(np.max(fit["steps"], initial=0)),
        alpha=float(values[1]),
        alpha_se=float(se[1]),
        light_scale=float(values[2]) if scaled else 1.0,
        light_scale_se=float(se[2]) if scaled else 0.0,
        table_error=float(table_error),
        **coat,
    )


def _result(
    fit: PixelFit, start: RoughResult, family: CoatedFamily, per_pixel: bool,
    coat: dict[str, Any]
) -> CoatedResult:
    """The coated fit as a :class:`CoatedResult` (``coat``: η, base id, solver, shadow
    rounds), or the rough start's result when the coat does not lower the mean squared
    relative residual (``coat=False``, α NaN)."""
    values, se = fit.values, fit.values_se
    pick = (lambda a, j: a[:, j]) if per_pixel else (lambda a, j: float(a[j]))
    if not _coat_helps(fit, start):
        # the coat does not explain the images better than the bare base: keep the base
        fields = {f.name: getattr(start, f.name) for f in dataclasses.fields(RoughResult)}
        nan = np.full_like(values[:, 1], np.nan) if per_pixel else math.nan
        return CoatedResult(**fields, alpha=nan, alpha_se=nan, coat=False, **coat)
    scaled = family.light_scale
    return CoatedResult(
        normals=fit.normals,
        albedo=fit.albedo,
        roughness=pick(values, 0),
        roughness_name=family.base_param,
        roughness_se=pick(se, 0),
        normal_se=fit.normal_se,
        albedo_se=fit.albedo_se,
        residual=fit.residual,
        weights=fit.weights,
        iterations=fit.iterations,
        alpha=pick(values, 1),
        alpha_se=pick(se, 1),
        light_scale=float(values[2]) if scaled else 1.0,
        light_scale_se=float(se[2]) if scaled else 0.0,
        **coat,
    )
