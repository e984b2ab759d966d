"""Nonlinear least-squares fits of a model's parameters to measurements.

The residual ``model.brdf_cosines(μi, μo, cos_io) · scale − value`` is built from the model's
own formula (no second copy), traced once by JAX in float64, compiled with ``jax.jit`` and
differentiated exactly with ``jax.jacfwd``; :func:`scipy.optimize.least_squares` (trust-region
reflective, bounds, optional robust loss) minimises it from several starting points.

Error bars are the usual linearised ones (e.g. Press et al., *Numerical Recipes*, 3rd ed.,
§15.4–15.5): with J the Jacobian of the residuals at the optimum, M samples and P parameters,
s² = Σ r² / (M − P) and cov = s² (JᵀJ)⁻¹, computed through the singular value decomposition of
the column-scaled J. Directions of (near-)zero singular value are not constrained by the data:
the parameters along them get an infinite standard error, and when that happens at every
starting point (not only at the optimum) the data themselves are degenerate and a
:class:`DegenerateDataWarning` says which parameters they cannot identify.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import jax
import jax.numpy as jnp
import numpy as np
from scipy.optimize import least_squares

from .._validate import ParameterError
from ..models import Model
from ..models.declaration import Param
from .measurements import Measurements
from .summary import AT_BOUND, at_bound, error_notes

__all__ = [
    "DEFAULT_BOUNDS",
    "DEFAULT_NOISE",
    "DegenerateDataWarning",
    "FitResult",
    "NoiseModelWarning",
    "fit",
    "noise_model",
]

def _declared_boxes(names: Sequence[str]) -> dict[str, tuple[float, float]]:
    """For each name, the fit box (``Param.bounds``) that most built-in models declaring a
    parameter of that name give (the first such box on a tie)."""
    from .. import registry

    boxes: dict[str, list[tuple[float, float]]] = {}
    for entry in registry.entries():
        for p in entry.parameters:
            if p.name in names and p.bounds is not None:
                boxes.setdefault(p.name, []).append(p.bounds)
    return {n: max(boxes[n], key=boxes[n].count) for n in names if n in boxes}


DEFAULT_BOUNDS: dict[str, tuple[float, float]] = _declared_boxes(
    ("albedo", "sigma", "roughness", "eta", "limb_darkening")
)
"""Bounds for a parameter of a factory *function* the caller gives none for (radians for
``sigma``), read from the models' declarations: the box most models declaring a parameter of
that name give. A model class's own parameters take the box its declaration gives
(:attr:`roughdiffuse.models.declaration.Param.bounds`)."""


def declared_params(factory: Any) -> dict[str, Param]:
    """The declared parameters of a model class, or of a classmethod factory of one
    (``Mix.from_params``); empty for anything else."""
    cls = factory if isinstance(factory, type) else getattr(factory, "__self__", None)
    if isinstance(cls, type) and issubclass(cls, Model):
        return {p.name: p for p in cls.params}
    return {}

RANK_TOL = 1e-7
"""Singular values of the column-normalised Jacobian below this (relative to the largest)
count as zero: the data do not constrain that combination of parameters."""

Noise = Literal["absolute", "relative"]

DEFAULT_NOISE: Noise = "relative"
"""The noise model of every fit unless told otherwise: :func:`fit`, :func:`~roughdiffuse.fit.
compare_models`, ``roughdiffuse fit`` and the explorer. Measured BRDF values carry an error
proportional to the value (detector gain, calibration of the light and the reference, speckle),
and they span orders of magnitude from normal to grazing angles: with absolute residuals the
brightest samples decide the fit alone. BIC ranks models by the likelihood of the residuals, so
it is only meaningful under the noise model the data have; relative noise is that model for
reflectance measurements. Data with a value <= 0 fall back to absolute noise (with a
:class:`NoiseModelWarning`)."""


class DegenerateDataWarning(UserWarning):
    """The data cannot identify some parameters (e.g. every sample at one geometry)."""


class NoiseModelWarning(UserWarning):
    """Relative noise was asked for, but some values are <= 0: absolute noise is used."""


def noise_model(data: Measurements, noise: str = DEFAULT_NOISE) -> tuple[str, str]:
    """The noise model a fit of ``data`` uses, and a note when it is not the one asked for.

    Relative noise needs every value > 0; otherwise absolute noise is used and the note says
    why. ``ValueError`` for a name other than ``"absolute"`` or ``"relative"``.
    """
    if noise not in ("absolute", "relative"):
        raise ParameterError(f"noise must be 'absolute' or 'relative' (got {noise!r})")
    if noise == "relative" and np.any(data.value <= 0):
        return "absolute", (
            f"{int(np.sum(data.value <= 0))} values are <= 0, which relative noise cannot "
            "weigh: absolute noise used"
        )
    return noise, ""


@dataclass(frozen=True)
class FitResult:
    """Outcome of :func:`fit`.

    Attributes
    ----------
    model : Model
        The model at the best-fit parameters.
    names : tuple of str
        Fitted parameter names; a per-channel parameter appears as ``albedo[0]``, ``albedo[1]``…
    values, errors : array (P,)
        Best-fit values and their standard errors (1 sigma; ``inf`` when not identifiable).
    covariance : array (P, P)
        Linearised covariance (``inf`` entries for unidentifiable directions).
    on_bound : array (P,) of bool
        True where a value sits on (within 1e-6 of the width of) its bound.
    bounds : array (P, 2)
        The bounds used.
    rms : float
        Root-mean-square residual (in the units of the data, unweighted).
    rms_relative : float
        RMS of the residual divided by the data (over samples with data > 0).
    n_samples : int
        Number of residuals M (samples × channels).
    aic, bic : float
        Akaike and Bayesian information criteria, M ln(RSS/M) + 2P and M ln(RSS/M) + P ln M,
        with RSS the (noise-weighted) residual sum of squares.
    identifiable : bool
        False when the data cannot identify every parameter (see the warning).
    warnings : tuple of str
        Human-readable notes (degenerate data, values on bounds, …).
    model_name : str
        Name of the fitted model.
    noise : {"relative", "absolute"}
        The noise model used (see :func:`noise_model`).
    """

    model: Model
    names: tuple[str, ...]
    values: np.ndarray
    errors: np.ndarray
    covariance: np.ndarray
    on_bound: np.ndarray
    bounds: np.ndarray
    rms: float
    rms_relative: float
    n_samples: int
    aic: float
    bic: float
    identifiable: bool
    warnings: tuple[str, ...] = ()
    model_name: str = ""
    nfev: int = 0
    starts: int = 0
    predict: Callable[[Measurements], np.ndarray] | None = field(default=None, repr=False)
    noise: str = DEFAULT_NOISE

    @property
    def params(self) -> dict[str, float]:
        """Best-fit value of each fitted parameter, by name."""
        return dict(zip(self.names, (float(v) for v in self.values), strict=True))

    @property
    def stderr(self) -> dict[str, float]:
        """Standard error of each fitted parameter, by name."""
        return dict(zip(self.names, (float(v) for v in self.errors), strict=True))

    def table(self) -> str:
        """A plain-text table: parameter, value, standard error, flags (the rules of
        :func:`~roughdiffuse.fit.summary.error_notes`: no error at a bound, "not determined"
        for an unusable one)."""
        lines = [
            f"{self.model_name}: {self.n_samples} residuals, {self.noise} noise, "
            f"RMS {self.rms:.4g} ({100 * self.rms_relative:.3g}% of the data), "
            f"AIC {self.aic:.1f}, BIC {self.bic:.1f}"
        ]
        lines.append(f"  {'parameter':<16}{'value':>12}{'std. error':>16}  note")
        for k, (name, note) in enumerate(zip(self.names, error_notes(self), strict=True)):
            err_s = "–" if note == AT_BOUND else note or f"{self.errors[k]:.3g}"
            note = note if note == AT_BOUND else ""
            extra = ""
            if name.startswith("sigma"):
                extra = f"  ({math.degrees(self.values[k]):.2f}°)"
            lines.append(f"  {name:<16}{self.values[k]:>12.5g}{err_s:>16}  {note}{extra}")
        lines.extend(f"  warning: {w}" for w in self.warnings)
        return "\n".join(lines)


# --------------------------------------------------------------------------- layout
@dataclass(frozen=True)
class _Layout:
    factory: Callable[..., Model]
    fixed: tuple[tuple[str, Any], ...]
    params: tuple[str, ...]
    channels: tuple[int, ...]  # 0: scalar parameter, C: one value per channel

    @property
    def names(self) -> tuple[str, ...]:
        out: list[str] = []
        for p, c in zip(self.params, self.channels, strict=True):
            out.extend([p] if c == 0 else [f"{p}[{k}]" for k in range(c)])
        return tuple(out)

    def unpack(self, x: Any) -> dict[str, Any]:
        kw: dict[str, Any] = {}
        k = 0
        for p, c in zip(self.params, self.channels, strict=True):
            kw[p] = x[k] if c == 0 else x[k : k + c]
            k += max(c, 1)
        return kw

    def build(self, x: Any) -> Model:
        return self.factory(**dict(self.fixed), **self.unpack(x))


def _model_name(factory: Any, fixed: Mapping[str, Any]) -> str:
    name = getattr(factory, "__name__", type(factory).__name__)
    if fixed:
        name += "(" + ", ".join(f"{k}={v!r}" for k, v in fixed.items()) + ")"
    return name


def _layout(
    factory: Any, params: Sequence[str] | None, fixed: Mapping[str, Any], channels: int
) -> _Layout:
    is_class = isinstance(factory, type) and issubclass(factory, Model)
    if params is None:
        if not is_class:
            raise ParameterError("params must name the parameters of a model factory function")
        params = tuple(factory.array_fields)
        if factory.params:  # those the declaration gives this choice of categorical values
            choices = {p.name: p.default for p in factory.params if p.categorical}
            choices.update(fixed)
            params = tuple(
                p.name for p in factory.params if not p.categorical and p.applies(choices)
            )
    params = tuple(params)
    if not params:
        raise ParameterError("params must name at least one parameter to fit")
    if is_class:
        fields = {f.name for f in dataclasses.fields(factory)}
        for p in params:
            if p not in fields:
                raise ParameterError(
                    f"{factory.__name__} has no parameter {p!r}; its parameters: "
                    f"{', '.join(sorted(factory.array_fields))}"
                )
            if p not in factory.array_fields:
                raise ParameterError(f"{factory.__name__}.{p} is not numeric and cannot be fitted")
        chan_fields = factory.channel_fields
    else:
        chan_fields = ("albedo",)
    for p in params:
        if p in fixed:
            raise ParameterError(f"parameter {p!r} is both fitted and fixed")
    chans = tuple(channels if (channels and p in chan_fields) else 0 for p in params)
    return _Layout(factory, tuple(sorted(fixed.items())), params, chans)


def _bounds(layout: _Layout, bounds: Any) -> np.ndarray:
    if bounds is None:
        bounds = {}
    if not isinstance(bounds, Mapping):
        seq = list(bounds)
        if len(seq) != len(layout.params):
            raise ParameterError(
                f"bounds must give one (low, high) pair per parameter {layout.params} "
                f"(got {len(seq)})"
            )
        bounds = dict(zip(layout.params, seq, strict=True))
    for key in bounds:
        if key not in layout.params:
            raise ParameterError(
                f"bounds names {key!r}, which is not fitted (params: {layout.params})"
            )
    rows = []
    declared = declared_params(layout.factory)
    for p, c in zip(layout.params, layout.channels, strict=True):
        box = declared[p].bounds if p in declared else None
        if p in bounds:
            lo, hi = (float(v) for v in bounds[p])
        elif box is not None:
            lo, hi = box
        elif p in DEFAULT_BOUNDS:
            lo, hi = DEFAULT_BOUNDS[p]
        else:
            raise ParameterError(
                f"no default bounds for parameter {p!r}: pass bounds={{{p!r}: (lo, hi)}}"
            )
        if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
            raise ParameterError(
                f"bounds of {p!r} must be finite with low < high (got ({lo}, {hi}))"
            )
        rows.extend([(lo, hi)] * max(c, 1))
    return np.asarray(rows, dtype=np.float64)


# --------------------------------------------------------------------------- compiled residuals
_COMPILED: dict[Any, dict[str, Any]] = {}

PAD = 1 << 16
"""Full data sets are padded (with zero weight) to a multiple of this many samples, so that
images of similar size share one compiled function."""


def _like(m: Any, y: Any) -> Any:
    """A one-channel prediction (N,) repeated for every channel of data (N, C)."""
    return jnp.broadcast_to(m[:, None], y.shape) if m.ndim < y.ndim else m


def _compiled(layout: _Layout) -> dict[str, Any]:
    """Jitted functions of this layout (cached): residual, jacobian, normal equations, …"""
    try:
        cached = _COMPILED.get(layout)
        hashable = True
    except TypeError:  # unhashable fixed values: no cache
        cached, hashable = None, False
    if cached is not None:
        return cached

    def predict(x: Any, mu_i: Any, mu_o: Any, cos_io: Any, scale: Any) -> Any:
        f = layout.build(x).brdf_cosines(mu_i, mu_o, cos_io)
        return f * (scale if f.ndim == 1 else scale[:, None])

    def residual(x: Any, mu_i: Any, mu_o: Any, cos_io: Any, scale: Any, y: Any, w: Any) -> Any:
        return ((_like(predict(x, mu_i, mu_o, cos_io, scale), y) - y) * w).ravel()

    jac = jax.jacfwd(residual)

    def normal(x: Any, *arrays: Any) -> tuple[Any, Any, Any]:
        """JᵀJ, Jᵀr and rᵀr: all a Gauss–Newton step needs, without J leaving JAX."""
        r = residual(x, *arrays)
        j = jac(x, *arrays)
        return j.T @ j, j.T @ r, r @ r

    def rss(x: Any, *arrays: Any) -> Any:
        r = residual(x, *arrays)
        return r @ r

    def raw_stats(x: Any, mu_i: Any, mu_o: Any, cos_io: Any, scale: Any, y: Any, w: Any) -> Any:
        """Σ(model − data)² and Σ((model − data)/data)² over used samples (w > 0)."""
        d = _like(predict(x, mu_i, mu_o, cos_io, scale), y) - y
        used = (w != 0) & (y == y)
        d = jnp.where(used, d, 0.0)
        pos = used & (y > 0)
        rel = jnp.where(pos, d / jnp.where(pos, y, 1.0), 0.0)
        return jnp.sum(d * d), jnp.sum(rel * rel), jnp.sum(pos)

    out = {
        "residual": jax.jit(residual),
        "jac": jax.jit(jac),
        "predict": jax.jit(predict),
        "normal": jax.jit(normal),
        "rss": jax.jit(rss),
        "raw_stats": jax.jit(raw_stats),
    }
    if hashable:
        _COMPILED[layout] = out
    return out


def _device(data: Measurements, weights: np.ndarray, pad: bool = False) -> tuple[Any, ...]:
    """The data as float64 JAX arrays (μi, μo, cos_io, scale, value, weight).

    With ``pad``, zero-weight samples at normal incidence fill the arrays up to a multiple of
    :data:`PAD`, so that one compiled function serves many sizes.
    """
    arrays = [data.mu_i, data.mu_o, data.cos_io, data.scale, data.value, weights]
    if pad:
        extra = (-data.size) % PAD
        if extra:
            fill = (1.0, 1.0, 1.0, 1.0, 1.0, 0.0)
            arrays = [
                np.concatenate([a, np.full((extra,) + a.shape[1:], f)])
                for a, f in zip(arrays, fill, strict=True)
            ]
    return tuple(jnp.asarray(a, dtype=jnp.float64) for a in arrays)


def _reweight(fns: dict[str, Any], x: np.ndarray, arrays: tuple[Any, ...]) -> tuple[Any, ...]:
    """Relative-noise weights 1/model(x), clipped to [1/(2 y), 2/y]; padding keeps weight 0."""
    mu_i, mu_o, cos_io, scale, y, w = arrays
    m = _like(fns["predict"](x, mu_i, mu_o, cos_io, scale), y)
    m = jnp.clip(m, 0.5 * y, 2.0 * y)
    return (mu_i, mu_o, cos_io, scale, y, jnp.where(w != 0, 1.0 / m, 0.0))


STEP_TOL = 1e-3
"""Refinement stops when a step is below this fraction of every parameter's standard error."""


def _standard_errors(a: np.ndarray, cost: float, dof: int) -> np.ndarray:
    """sqrt(diag((JᵀJ)⁻¹) · RSS/dof); ``inf`` where JᵀJ is singular."""
    try:
        inv = np.linalg.inv(a)
    except np.linalg.LinAlgError:
        return np.full(a.shape[0], math.inf)
    var = np.diag(inv) * cost / max(dof, 1)
    return np.sqrt(np.where(np.isfinite(var) & (var > 0), var, math.inf))


def _gauss_newton(
    fns: dict[str, Any], x: np.ndarray, arrays: tuple[Any, ...], box: np.ndarray, dof: int
) -> tuple[np.ndarray, int, np.ndarray]:
    """Levenberg–Marquardt from ``x`` on the normal equations, steps clipped to the bounds.

    Used to refine, on all of a large data set, the optimum found on a subset: each step
    needs only JᵀJ and Jᵀr (P×P and P numbers) from the compiled function, where
    :func:`scipy.optimize.least_squares` would move M×P arrays through NumPy. Marquardt's
    damping (Numerical Recipes §15.5.2) with the diagonal of JᵀJ. Stops when the
    Gauss–Newton step is below :data:`STEP_TOL` standard errors (taken, undamped).

    Returns the point, the number of evaluations and the standard errors there.
    """
    lam = 1e-4
    nfev = 0
    a, g, cost = (np.asarray(v) for v in fns["normal"](x, *arrays))
    nfev += 1
    se = _standard_errors(a, float(cost), dof)
    for _ in range(50):
        d = np.diag(a).copy()
        d[d <= 0] = 1.0
        try:
            newton = np.linalg.solve(a, -g)
        except np.linalg.LinAlgError:
            newton = np.full_like(g, math.inf)
        if np.all(np.abs(newton) <= STEP_TOL * se):
            return np.clip(x + newton, box[:, 0], box[:, 1]), nfev, se
        try:
            step = np.linalg.solve(a + lam * np.diag(d), -g)
        except np.linalg.LinAlgError:
            step = np.linalg.lstsq(a + lam * np.diag(d), -g, rcond=None)[0]
        x_new = np.clip(x + step, box[:, 0], box[:, 1])
        cost_new = float(fns["rss"](x_new, *arrays))
        nfev += 1
        if cost_new <= cost:
            moved = np.abs(x_new - x)
            x = x_new
            lam = max(lam / 10.0, 1e-12)
            if np.all(moved <= 1e-12 * (np.abs(x) + 1e-12)):
                break
            a, g, cost = (np.asarray(v) for v in fns["normal"](x, *arrays))
            nfev += 1
            se = _standard_errors(a, float(cost), dof)
        else:
            lam *= 10.0
            if lam > 1e12:
                break
    return x, nfev, se


def _noise_weights(data: Measurements, noise: str) -> np.ndarray:
    if noise == "absolute":
        return np.ones_like(data.value)
    if noise == "relative":
        return 1.0 / data.value
    raise ParameterError(f"noise must be 'absolute' or 'relative' (got {noise!r})")


def _starts(bounds: np.ndarray, n: int, seed: int) -> np.ndarray:
    """Centre of the box, then scrambled Halton points inside its inner 90%."""
    from scipy.stats import qmc

    lo, hi = bounds[:, 0], bounds[:, 1]
    width = hi - lo
    pts = [lo + 0.5 * width]
    if n > 1:
        u = qmc.Halton(d=len(lo), scramble=True, seed=seed).random(n - 1)
        pts.extend(lo + (0.05 + 0.9 * u) * width)
    return np.asarray(pts)


def _null_space_params(jac: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """SVD of the column-normalised Jacobian: (norms, singular values, V) with s sorted."""
    norms = np.sqrt(np.sum(jac * jac, axis=0))
    safe = np.where(norms > 0, norms, 1.0)
    _, s, vt = np.linalg.svd(jac / safe, full_matrices=False)
    s = np.where(norms.max() > 0, s, 0.0)
    return norms, s, vt.T


def _unidentified(jac: np.ndarray) -> np.ndarray:
    """Boolean mask of parameters lying along a null direction of ``jac``."""
    norms, s, v = _null_space_params(jac)
    bad = norms == 0
    if s.size and s[0] > 0:
        for k in np.flatnonzero(s < RANK_TOL * s[0]):
            bad |= np.abs(v[:, k]) > 1e-3
    return bad


def _roughness_errors(
    names: Sequence[str], x: np.ndarray, box: np.ndarray, errors: np.ndarray
) -> np.ndarray:
    """Widen the error of a roughness σ ≥ 0 near 0, where the models depend on σ².

    Oren–Nayar depends on σ only through σ², so near σ = 0 the linearised error in σ,
    SE(σ²)/(2σ), is too small. The 3-sigma interval is taken in σ², [σ² − 3 SE(σ²),
    σ² + 3 SE(σ²)] with SE(σ²) = 2σ SE(σ), mapped back through the square root (0 below 0),
    and the reported error is the larger of SE(σ) and a third of each half-width of that
    interval: far from 0 this is SE(σ); near 0 it keeps σ = 0 within the 3-sigma bar
    whenever σ² = 0 is within 3 standard errors of the fitted σ².
    """
    out = errors.copy()
    for k, name in enumerate(names):
        if name == "sigma" and box[k, 0] == 0.0 and np.isfinite(out[k]):
            s, se_tau = x[k], 2.0 * x[k] * out[k]
            lo = math.sqrt(max(0.0, s * s - 3.0 * se_tau))
            hi = math.sqrt(s * s + 3.0 * se_tau)
            out[k] = max(out[k], (s - lo) / 3.0, (hi - s) / 3.0)
    return out


# --------------------------------------------------------------------------- fit
def fit(
    model_class: type[Model] | Callable[..., Model],
    data: Measurements,
    params: Sequence[str] | None = None,
    bounds: Mapping[str, tuple[float, float]] | Sequence[tuple[float, float]] | None = None,
    *,
    fixed: Mapping[str, Any] | None = None,
    x0: Mapping[str, Any] | None = None,
    n_starts: int = 4,
    loss: str = "linear",
    f_scale: float = 1.0,
    noise: Noise = DEFAULT_NOISE,
    multistart_samples: int = 20_000,
    seed: int = 0,
) -> FitResult:
    """Fit a model's parameters to measurements by nonlinear least squares.

    Parameters
    ----------
    model_class : Model subclass or callable
        The model (e.g. ``OrenNayar``), or any function of keyword parameters returning a
        :class:`~roughdiffuse.models.Model` (e.g. a ``Mix`` built from its weights); it must
        accept JAX tracers, as the model classes do.
    data : Measurements
        What to fit (see :mod:`roughdiffuse.fit.readers`).
    params : sequence of str, optional
        Parameters to fit; default: every numeric parameter of the class (``("albedo",
        "sigma")`` for Oren–Nayar). With RGB data, ``albedo`` is fitted per channel and the
        others are shared.
    bounds : mapping or sequence of (low, high), optional
        Per parameter; defaults from the model's declaration (``Param.bounds``), else
        :data:`DEFAULT_BOUNDS` (σ in radians).
    fixed : mapping, optional
        Other constructor arguments, e.g. ``{"variant": "full"}``.
    x0 : mapping, optional
        A starting point (used first, before the automatic ones).
    n_starts : int
        Number of automatic starting points (centre of the bounds, then Halton points).
    loss, f_scale : str, float
        Robust loss of :func:`scipy.optimize.least_squares` ("linear", "soft_l1", "huber",
        "cauchy", "arctan") and its scale (in units of the weighted residual). With a robust
        loss the noise level in the error bars is 1.4826 × the median absolute deviation of
        the residuals, so that outliers do not inflate them.
    noise : {"relative", "absolute"}
        Noise model (default ``"relative"``, :data:`DEFAULT_NOISE`, as on the command line
        and in the explorer): relative (constant relative noise, e.g. 1% of the value):
        residuals divided by the model value, by iteratively reweighted least squares
        (weights from the previous fit, held fixed in each inner fit), which avoids the bias
        of dividing by the noisy data; or absolute: residuals in data units. Affects
        weights, error bars and AIC/BIC. Data with a value <= 0 are fitted with absolute
        noise (:class:`NoiseModelWarning`).
    multistart_samples : int
        Larger data sets are explored from every start on a random subset of this size;
        the best start is then refined on all the data.
    seed : int
        Seed of the subset and of the starting points.

    Returns
    -------
    FitResult
        Best parameters, standard errors, covariance, on-bound flags, RMS, AIC/BIC.

    Warns
    -----
    DegenerateDataWarning
        When the data cannot identify some parameter (every sample at one geometry, only
        θi = θr = 0, …); its error is then ``inf``.
    NoiseModelWarning
        When relative noise is asked for but some values are <= 0.
    """
    if not isinstance(data, Measurements):
        raise ParameterError(f"data must be a Measurements object (got {type(data).__name__})")
    if int(n_starts) < 1:
        raise ParameterError(f"n_starts must be >= 1 (got {n_starts})")
    fixed = dict(fixed or {})
    layout = _layout(model_class, params, fixed, data.channels)
    box = _bounds(layout, bounds)
    npar = len(layout.names)
    noise, noise_note = noise_model(data, noise)
    if noise_note:
        warnings.warn(noise_note, NoiseModelWarning, stacklevel=2)
    m = data.value.size
    if m < npar:
        raise ParameterError(f"{npar} parameters need at least {npar} values (got {m})")
    starts = _start_points(layout, box, int(n_starts), seed, x0)
    with jax.enable_x64(True):
        fns = _compiled(layout)
        solver = _Solver(fns, box, loss, f_scale, data, noise, multistart_samples, seed)
        x, nfev, null_all = solver.multistart(starts)
        x, k = solver.refinement(x)
        stats = solver.statistics(x)
    errors, cov, notes, identifiable = _error_estimates(
        layout.names, x, box, stats, m, null_all, robust=loss != "linear"
    )
    if noise_note:
        notes.insert(0, noise_note)
    on_bound = _bound_notes(layout.names, x, box, notes)
    if not solver.success:
        notes.append(f"optimizer: {solver.message}")
    rss_safe = max(stats.rss, 1e-300)
    model = layout.build(x)
    return FitResult(
        model=model,
        names=layout.names,
        values=x,
        errors=errors,
        covariance=cov,
        on_bound=on_bound,
        bounds=box,
        rms=math.sqrt(stats.raw_ss / m),
        rms_relative=math.sqrt(stats.rel_ss / stats.n_pos) if stats.n_pos > 0 else math.nan,
        n_samples=m,
        aic=m * math.log(rss_safe / m) + 2 * npar,
        bic=m * math.log(rss_safe / m) + npar * math.log(m),
        identifiable=identifiable,
        warnings=tuple(notes),
        model_name=_model_name(model_class, fixed),
        nfev=nfev + k,
        starts=len(starts),
        predict=_predictor(fns["predict"], x),
        noise=noise,
    )


def _start_points(
    layout: _Layout, box: np.ndarray, n_starts: int, seed: int, x0: Mapping[str, Any] | None
) -> np.ndarray:
    """The starting points: ``x0`` (clipped into the box) first, then :func:`_starts`."""
    starts = _starts(box, n_starts, seed)
    if x0 is None:
        return starts
    first = np.concatenate(
        [
            np.broadcast_to(np.asarray(x0[p], float), (max(c, 1),))
            for p, c in zip(layout.params, layout.channels, strict=True)
        ]
    )
    return np.vstack([np.clip(first, box[:, 0], box[:, 1]), starts])


@dataclass
class _Statistics:
    """What the error estimates need at the optimum (see :func:`_error_estimates`)."""

    jtj: np.ndarray
    rss: float
    jac_sub: np.ndarray
    raw_ss: float
    rel_ss: float
    n_pos: float
    robust_s2: float | None


class _Solver:
    """The steps of :func:`fit` that run the optimizer (inside ``jax.enable_x64``): starts on
    a subset, refinement on all the data, the statistics at the optimum."""

    def __init__(
        self,
        fns: dict[str, Any],
        box: np.ndarray,
        loss: str,
        f_scale: float,
        data: Measurements,
        noise: Noise,
        multistart_samples: int,
        seed: int,
    ) -> None:
        self.fns, self.box, self.loss, self.f_scale = fns, box, loss, f_scale
        self.data, self.noise = data, noise
        self.m, self.npar = data.value.size, box.shape[0]
        w = _noise_weights(data, noise)
        rng = np.random.default_rng(seed)
        if data.size > multistart_samples:
            sub = data.subset(np.sort(rng.choice(data.size, multistart_samples, replace=False)))
            self.arrays_sub = _device(sub, _noise_weights(sub, noise))
        else:
            sub = data
            self.arrays_sub = _device(sub, w)
        self.large = sub is not data
        self.fast = self.large and loss == "linear"
        self.arrays = _device(data, w, pad=self.fast) if self.large else self.arrays_sub
        self.success, self.message = False, ""

    def run(self, x_start: np.ndarray, arrays: tuple[Any, ...]) -> Any:
        """One :func:`scipy.optimize.least_squares` run from ``x_start``."""
        fns = self.fns
        return least_squares(
            lambda x: np.asarray(fns["residual"](x, *arrays)),
            x_start,
            jac=lambda x: np.asarray(fns["jac"](x, *arrays)),
            bounds=(self.box[:, 0], self.box[:, 1]),
            loss=self.loss,
            f_scale=self.f_scale,
            x_scale="jac",
            method="trf",
        )

    def multistart(self, starts: np.ndarray) -> tuple[np.ndarray, int, np.ndarray]:
        """The best fit over the starts on the subset: (x, evaluations, the parameters no
        start can identify). Degenerate data: unidentifiable at every (interior, generic)
        starting point."""
        null_all = np.ones(self.npar, dtype=bool)
        best = None
        nfev = 0
        for x_start in starts:
            null_all &= _unidentified(np.asarray(self.fns["jac"](x_start, *self.arrays_sub)))
            r = self.run(x_start, self.arrays_sub)
            nfev += int(r.nfev)
            if best is None or r.cost < best.cost:
                best = r
        assert best is not None
        self.success, self.message = bool(best.success), str(best.message)
        return np.asarray(best.x, dtype=np.float64), nfev, null_all

    def _refine(self, x: np.ndarray) -> tuple[np.ndarray, int, Any]:
        if self.fast:
            return _gauss_newton(self.fns, x, self.arrays, self.box, self.m - self.npar)
        r = self.run(x, self.arrays)
        self.success, self.message = bool(r.success), str(r.message)
        x = np.asarray(r.x, dtype=np.float64)
        a, _, cost = (np.asarray(v) for v in self.fns["normal"](x, *self.arrays))
        return x, int(r.nfev) + 1, _standard_errors(a, float(cost), self.m - self.npar)

    def refinement(self, x: np.ndarray) -> tuple[np.ndarray, int]:
        """Refine on all the data (a large data set) and reweight (relative noise):
        (x, evaluations)."""
        nfev = 0
        if self.large and self.noise != "relative":
            x, nfev, _ = self._refine(x)
        if self.noise == "relative":
            # iteratively reweighted: weights 1/model, not 1/data (which biases the fit low
            # by about 2 (noise)² of the value), held fixed during each inner fit; stops
            # when the weights move the optimum by less than STEP_TOL standard errors
            for _ in range(8):
                self.arrays = _reweight(self.fns, x, self.arrays)
                x_new, k, se = self._refine(x)
                nfev += k
                done = np.all(np.abs(x_new - x) <= STEP_TOL * se)
                x = x_new
                if done:
                    break
            self.arrays_sub = _reweight(self.fns, x, self.arrays_sub)
        return x, nfev

    def statistics(self, x: np.ndarray) -> _Statistics:
        """Normal matrix, sums of squares and the noise level at the optimum ``x``."""
        fns, arrays = self.fns, self.arrays
        jtj, _, rss = (np.asarray(v) for v in fns["normal"](x, *arrays))
        raw_ss, rel_ss, n_pos = (float(v) for v in fns["raw_stats"](x, *arrays))
        robust_s2 = None
        if self.loss != "linear":  # outliers must not set the noise level: 1.4826 MAD
            res = np.asarray(fns["residual"](x, *arrays))[: self.m]
            robust_s2 = (1.4826 * float(np.median(np.abs(res - np.median(res))))) ** 2
        return _Statistics(
            jtj=jtj,
            rss=float(rss),
            jac_sub=np.asarray(fns["jac"](x, *self.arrays_sub)),
            raw_ss=raw_ss,
            rel_ss=rel_ss,
            n_pos=n_pos,
            robust_s2=robust_s2,
        )


def _error_estimates(
    names: tuple[str, ...],
    x: np.ndarray,
    box: np.ndarray,
    stats: _Statistics,
    m: int,
    null_all: np.ndarray,
    robust: bool,
) -> tuple[np.ndarray, np.ndarray, list[str], bool]:
    """Standard errors and covariance from the normal matrix (infinite for a parameter the
    data cannot identify), with the notes that explain them: (errors, covariance, notes,
    identifiable)."""
    npar = len(names)
    notes: list[str] = []
    dof = m - npar
    s2 = stats.rss / dof if dof > 0 else math.inf
    if robust and stats.robust_s2 is not None and dof > 0:
        s2 = stats.robust_s2
    null_here = _unidentified(stats.jac_sub)
    cov = np.full((npar, npar), math.inf)
    ok = ~null_here
    if np.any(ok):
        a_ok = stats.jtj[np.ix_(ok, ok)]
        dscale = np.sqrt(np.diag(a_ok))
        try:
            inv = np.linalg.inv(a_ok / np.outer(dscale, dscale)) / np.outer(dscale, dscale)
            cov[np.ix_(ok, ok)] = s2 * inv
        except np.linalg.LinAlgError:
            pass
    diag = np.diag(cov)
    errors = np.sqrt(np.where(np.isfinite(diag) & (diag >= 0), diag, math.inf))
    errors = _roughness_errors(names, x, box, errors)
    if m == npar:
        notes.append("as many values as parameters: no error estimate")
    identifiable = not np.any(null_all)
    if not identifiable:
        which = ", ".join(n for n, b in zip(names, null_all, strict=True) if b)
        msg = (
            f"the data cannot identify {which}: its effect on the model is zero or "
            "indistinguishable from another parameter's at every starting point "
            "(e.g. all samples at one geometry); its error bar is infinite"
        )
        warnings.warn(msg, DegenerateDataWarning, stacklevel=3)
        notes.append(msg)
        errors = np.where(null_all, math.inf, errors)
    elif np.any(null_here):
        which = ", ".join(n for n, b in zip(names, null_here, strict=True) if b)
        notes.append(
            f"{which}: the model does not change with it at the optimum "
            "(e.g. σ = 0); linearised error bar infinite"
        )
    return errors, cov, notes, identifiable


def _bound_notes(
    names: tuple[str, ...], x: np.ndarray, box: np.ndarray, notes: list[str]
) -> np.ndarray:
    """Which values lie on their bound (within 1e-6 of the box); a note for each."""
    on_bound = at_bound(x, box)
    for k in np.flatnonzero(on_bound):
        notes.append(f"{names[k]} = {x[k]:.4g} is on its bound")
    return on_bound


def _predictor(pred_fn: Any, x: np.ndarray) -> Callable[[Measurements], np.ndarray]:
    """The fitted model's values at other measurements' geometry (FitResult.predict)."""

    def predict(d: Measurements) -> np.ndarray:
        with jax.enable_x64(True):
            arr = _device(d, np.ones_like(d.value))
            return np.asarray(pred_fn(x, *arr[:4]))

    return predict
