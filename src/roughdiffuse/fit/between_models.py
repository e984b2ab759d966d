"""Fit one model's parameters to another model: the best match, and how far apart they stay.

:func:`convert` finds the parameters of a target model (a registry id) whose reflectance best
reproduces a source model, by least squares over the hemisphere, and reports the difference
that remains.

Sampling and weighting: the pairs (wi, wo) are the tensor product of an ``n``-point
Gauss–Legendre rule in μi = cos θi and in μo = cos θo on [0, 1] and of ``n`` midpoints in the
azimuth difference Δφ on [0, π] (the models are isotropic and symmetric in ±Δφ). Since
dω = dμ dφ, the weights approximate the integral over both hemispheres in solid angle. The
residual is the difference of f cos θi at these pairs, divided by the root mean square of the
source's f cos θi, plus the difference of the directional albedos at the ``n`` values of μo
(by the same rule; weight ``albedo_weight``), divided by the source's mean albedo.

Reported: the root-mean-square and the largest relative difference of f cos θi (relative to
the source's RMS f cos θi, so that a zero of the source does not blow up a ratio) at the pairs,
and the RMS and largest relative difference of the directional albedo (each model's own
``directional_albedo``) at the μo nodes.

>>> import roughdiffuse as rd
>>> r = convert(rd.OrenNayar(0.8, 0.349), target="pbrt3-oren-nayar")
>>> round(r.params["sigma_deg"], 3), r.rms_f < 1e-9
(19.996, True)
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import registry
from .._validate import ParameterError, check_range
from ..engine.dispatch import use_fastpath
from ..models.base import Model

__all__ = ["Conversion", "convert"]

N_MAX = 64
"""Most points per axis of the sampling: n³ pairs (262,144 at 64) are evaluated per solver
step; beyond, the arrays outgrow a workstation's memory long before the result improves."""


@dataclass(frozen=True)
class Conversion:
    """The result of :func:`convert`.

    Attributes
    ----------
    source, target : str
        The source's id (or class name) and the target's registry id.
    params : dict
        The target's parameters (albedo as a float, or a list per channel).
    model : Model
        The target model built with them.
    rms_f, max_f : float
        RMS and largest difference of f cos θi, relative to the source's RMS f cos θi.
    rms_albedo, max_albedo : float
        RMS and largest relative difference of the directional albedo over μo.
    """

    source: str
    target: str
    params: dict[str, Any]
    model: Model
    rms_f: float
    max_f: float
    rms_albedo: float
    max_albedo: float
    fixed: dict[str, Any] = field(default_factory=dict)

    def snippet(self) -> str:
        """Python that builds the target model."""
        args = ", ".join(f"{k}={_fmt(v)}" for k, v in self.params.items())
        return f'import roughdiffuse as rd\nmodel = rd.registry.create("{self.target}", {args})'

    def command(self) -> str:
        """The ``roughdiffuse eval`` command line of the target."""
        opts = " ".join(f"--param {k}={_fmt(v, cli=True)}" for k, v in self.params.items())
        return f"roughdiffuse eval --model {self.target} {opts}"

    def summary(self) -> str:
        """Parameters and differences, as ``roughdiffuse convert`` prints them."""
        lines = [f"{self.source} -> {self.target}"]
        lines += [f"  {k} = {_fmt(v)}" for k, v in self.params.items()]
        lines += [
            f"  f cos θi: RMS difference {_pct(self.rms_f)}, max {_pct(self.max_f)} "
            "(relative to the source's RMS f cos θi)",
            f"  directional albedo: RMS difference {_pct(self.rms_albedo)}, "
            f"max {_pct(self.max_albedo)}",
        ]
        return "\n".join(lines)

    def to_json(self) -> dict[str, Any]:
        """The record ``roughdiffuse convert --json`` prints and exports embed."""
        return {
            "source": self.source,
            "target": self.target,
            "params": self.params,
            "rms_f": self.rms_f,
            "max_f": self.max_f,
            "rms_albedo": self.rms_albedo,
            "max_albedo": self.max_albedo,
        }


def _pct(x: float) -> str:
    return f"{100.0 * x:.3g} %"


def _fmt(v: Any, cli: bool = False) -> str:
    if isinstance(v, list):
        inner = ",".join(f"{x:.6g}" for x in v)
        return inner if cli else f"[{inner}]"
    return f"{v:.6g}" if isinstance(v, float) else repr(v)


def _unpack(x: np.ndarray, colour: list, shape: list, reps: int, channels: int) -> dict[str, Any]:
    """The parameters from the solver's vector: ``reps`` values per colour parameter (a list
    when there are channels), then one per shape parameter."""
    out: dict[str, Any] = {}
    for k, p in enumerate(colour):
        vals = [float(v) for v in x[k * reps : (k + 1) * reps]]
        out[p.name] = vals if channels else vals[0]
    out.update({p.name: float(v) for p, v in zip(shape, x[len(colour) * reps :], strict=True)})
    return out


def _grid(n: int) -> tuple[np.ndarray, ...]:
    from ..quadrature import gauss_legendre

    mu, wmu = gauss_legendre(n, 0.0, 1.0)
    phi = (np.arange(n) + 0.5) * math.pi / n
    mi, mo, ph = np.meshgrid(mu, mu, phi, indexing="ij")
    weight = (wmu[:, None, None] * wmu[None, :, None]) * (math.pi / n) * np.ones_like(ph)
    si, so = np.sqrt(1.0 - mi * mi), np.sqrt(1.0 - mo * mo)
    cos_io = mi * mo + si * so * np.cos(ph)
    return mi.ravel(), mo.ravel(), cos_io.ravel(), weight.ravel(), mu, wmu


def _albedos(model: Model, mu: np.ndarray) -> np.ndarray:
    wo = np.stack([np.sqrt(1.0 - mu * mu), np.zeros_like(mu), mu], axis=-1)
    return np.asarray(model.directional_albedo(wo), dtype=np.float64)


def _source_id(model: Model) -> str:
    return registry.id_of(model) or type(model).__name__


def _target_entry(target: str) -> tuple[str, Any]:
    """The registry entry of ``target`` (an engine's name gives its default variant); a model
    that is not a closed form is refused."""
    from ..models.renderers import engine_variant

    target = engine_variant(target)
    entry = registry.get(target)
    if not getattr(entry.cls, "closed_form", True):
        raise ParameterError(f"target {target!r} is not a closed-form model; choose another target")
    return target, entry


def _check_inputs(source: Any, n: int, albedo_weight: float) -> None:
    """Refuse, by name, a source that is not a model, ``n`` outside [1, ``N_MAX``] and an
    ``albedo_weight`` that is not a finite number >= 0."""
    if not isinstance(source, Model):
        raise ParameterError(
            f"source must be a roughdiffuse model, e.g. roughdiffuse.create('eon') "
            f"(got a {type(source).__name__})"
        )
    check_range("n", n, 1, N_MAX)
    check_range("albedo_weight", albedo_weight, 0.0, math.inf)


def convert(
    source: Model,
    target: str = "eon",
    *,
    n: int = 12,
    albedo_weight: float = 1.0,
    fixed: Mapping[str, Any] | None = None,
    progress: bool = False,
) -> Conversion:
    """The parameters of ``target`` that best reproduce ``source``, and the difference left.

    Parameters
    ----------
    source : Model
        Any closed-form model (a grey or an RGB albedo; RGB is converted per channel with a
        shared roughness fitted to the channel mean).
    target : str
        A registry id (``"eon"``, ``"cycles-diffuse"``, ``"materialx-eon"``, ...), or an
        engine's name (``"unity"``, ``"filament"``, ...: its default variant,
        :data:`roughdiffuse.models.renderers.ENGINE_DEFAULTS`).
    n : int
        Points per axis of the hemisphere sampling (see the module docstring): n³ pairs.
    albedo_weight : float
        Weight of the directional-albedo residuals against those of f cos θi.
    fixed : mapping, optional
        Target parameters held at given values (not fitted).
    progress : bool
        Show a progress bar on standard error (:func:`roughdiffuse.progress.progress`): one
        step per start of the least-squares search, the target's evaluations counted.

    Returns
    -------
    Conversion

    Raises
    ------
    ParameterError
        For a source that is not a model or gives values that are not finite, ``n`` outside
        [1, ``N_MAX``], an ``albedo_weight`` that is not a finite number >= 0, an unknown or
        not closed-form target, or a target that cannot reach the source's albedo (its
        largest directional albedo, at the albedo parameter's maximum, is below the
        source's), with the two values. Anything else the solver raises is a bug.
    """
    from scipy.optimize import least_squares

    from ..progress import progress as progress_bar

    _check_inputs(source, n, albedo_weight)
    target, entry = _target_entry(target)
    fixed = dict(fixed or {})
    # the numbers of the target's choices (fixed or default): Coated over EON fits r, not σ
    numeric = [p for p in entry.applicable(fixed) if not p.categorical and p.name not in fixed]
    colour = [p for p in numeric if p.channels]
    shape = [p for p in numeric if not p.channels]
    mi, mo, cio, weight, mu, wmu = _grid(n)
    with use_fastpath(False):
        f_src = np.asarray(source.brdf_cosines(mi, mo, cio), dtype=np.float64)
        a_src = _albedos(source, mu)
    _check_source_values(source, f_src, a_src)
    channels = f_src.shape[-1] if f_src.ndim == 2 else 0
    reps = max(channels, 1)
    y = f_src * (mi[:, None] if channels else mi)
    w_f = weight[:, None] if channels else weight
    scale_f = math.sqrt(float(np.sum(w_f * y * y) / np.sum(w_f * np.ones_like(y)))) or 1.0
    scale_a = float(np.mean(np.abs(a_src))) or 1.0
    sqrt_wf, sqrt_wa = np.sqrt(w_f), np.sqrt(wmu[:, None] if channels else wmu)

    def unpack(x: np.ndarray) -> dict[str, Any]:
        return _unpack(x, colour, shape, reps, channels)

    def grid_albedo(f_cos: np.ndarray) -> np.ndarray:
        # ∫ f cos θi dωi at each μo node by the same rule (Δφ in [0, π] counted twice)
        w = 2.0 * weight.reshape(n, n, n) / wmu[np.newaxis, :, np.newaxis]
        cube = (f_cos.reshape(n, n, n, -1) * w[..., np.newaxis]).sum(axis=(0, 2))
        return cube if channels else cube[:, 0]

    y_a = grid_albedo(y if channels else y[:, None])

    evaluations = [0]

    def residual(x: np.ndarray) -> np.ndarray:
        evaluations[0] += 1
        bar.set_postfix_str(f"{evaluations[0]} evaluations", refresh=False)
        m = entry.create(**fixed, **unpack(x))
        with use_fastpath(False):
            f = np.asarray(m.brdf_cosines(mi, mo, cio), dtype=np.float64)
        f = f * (mi[:, None] if channels else mi)
        a = grid_albedo(f if channels else f[:, None])
        return np.concatenate(
            [
                (sqrt_wf * (f - y) / scale_f).ravel(),
                (albedo_weight * sqrt_wa * (a - y_a) / scale_a).ravel(),
            ]
        )

    _check_albedo_range(entry, source, a_src, mu, wmu, fixed, colour)
    params_list = [p for p in colour for _ in range(reps)] + shape
    lo = np.array([_lower_bound(p) for p in params_list], dtype=float)
    hi = np.array([p.max if p.max is not None else 1e6 for p in params_list], dtype=float)
    starts = _starts(params_list, lo, hi)
    fits = []
    with progress_bar(len(starts), f"convert to {target}", unit="start",
                      enabled=progress) as bar:
        for x0 in starts:
            fits.append(least_squares(residual, x0, bounds=(lo, hi), xtol=1e-15, ftol=1e-15,
                                      gtol=1e-15))
            bar.update(1)
    best = min(fits, key=lambda res: res.cost)
    params = unpack(best.x)
    params = {p.name: params[p.name] for p in numeric}
    grid = (mi, mo, cio, weight, mu, wmu)
    return _conversion(source, target, entry, fixed, params, grid, f_src, a_src)


def _conversion(source: Model, target: str, entry: Any, fixed: dict[str, Any],
                params: dict[str, Any], grid: tuple[np.ndarray, ...], f_src: np.ndarray,
                a_src: np.ndarray) -> Conversion:
    """The :class:`Conversion` of ``source`` to the ``target`` of these fitted ``params``:
    the model built and its differences from the source on the sampling ``grid``."""
    mi, mo, cio, weight, mu, wmu = grid
    model = entry.create(**fixed, **params)
    with use_fastpath(False):
        f_t = np.asarray(model.brdf_cosines(mi, mo, cio), dtype=np.float64)
        a_t = _albedos(model, mu)
    return Conversion(
        _source_id(source),
        target,
        params,
        model,
        *_differences(f_src, f_t, a_src, a_t, mi, weight, wmu),
        fixed=fixed,
    )


def _check_source_values(source: Model, f_src: np.ndarray, a_src: np.ndarray) -> None:
    """Refuse a source whose BRDF or albedo is not finite at the sampled directions: the
    solver's residuals would be (SciPy: "Residuals are not finite in the initial point")."""
    for what, values in (("BRDF", f_src), ("directional albedo", a_src)):
        bad = ~np.isfinite(values)
        if np.any(bad):
            raise ParameterError(
                f"source {source!r}: its {what} is not finite at {int(bad.sum())} of "
                f"{bad.size} sampled directions; it cannot be converted"
            )


def _lower_bound(p: Any) -> float:
    """The least value the solver may try for ``p``: its declared minimum, or just above it
    when the minimum is excluded (η > 0; least squares may stop on a bound)."""
    if p.min is None:
        return -1e6
    if getattr(p, "min_open", False):
        return float(np.nextafter(p.min, np.inf)) if p.min != 0 else 1e-9
    return float(p.min)


def _starts(params: list[Any], lo: np.ndarray, hi: np.ndarray) -> list[np.ndarray]:
    """Start points: each parameter's example (else default), and for the shape parameters a
    few values across their range (least squares can stop in a local minimum)."""
    x0 = np.array([p.default if p.example is None else p.example for p in params], dtype=float)
    x0 = np.clip(x0, lo, hi)
    starts = [x0]
    for k, p in enumerate(params):
        if p.channels:
            continue
        for t in (0.1, 0.5, 0.9):
            x = x0.copy()
            x[k] = lo[k] + t * (min(hi[k], 1e3) - lo[k])
            starts.append(x)
    return starts


def _differences(
    f_src: np.ndarray,
    f_t: np.ndarray,
    a_src: np.ndarray,
    a_t: np.ndarray,
    mi: np.ndarray,
    weight: np.ndarray,
    wmu: np.ndarray,
) -> tuple[float, float, float, float]:
    m = mi[:, None] if f_src.ndim == 2 else mi
    w = weight[:, None] if f_src.ndim == 2 else weight
    src, diff = f_src * m, (f_t - f_src) * m
    scale = math.sqrt(float(np.sum(w * src * src) / np.sum(w * np.ones_like(src))))
    scale = scale or 1.0
    rms_f = math.sqrt(float(np.sum(w * diff * diff) / np.sum(w * np.ones_like(diff)))) / scale
    max_f = float(np.max(np.abs(diff))) / scale
    wa = wmu[:, None] if a_src.ndim == 2 else wmu
    rel = (a_t - a_src) / np.where(np.abs(a_src) > 0, np.abs(a_src), 1.0)
    rms_a = math.sqrt(float(np.sum(wa * rel * rel) / np.sum(wa * np.ones_like(rel))))
    return rms_f, max_f, rms_a, float(np.max(np.abs(rel)))


def _check_albedo_range(
    entry: registry.Entry,
    source: Model,
    a_src: np.ndarray,
    mu: np.ndarray,
    wmu: np.ndarray,
    fixed: Mapping[str, Any],
    colour: list[Any],
) -> None:
    """Refuse a target whose cosine-weighted albedo cannot reach the source's."""
    if not colour:
        return
    src = float(np.max(np.sum((wmu * mu * 2.0)[:, None] * a_src.reshape(len(mu), -1), axis=0)))
    # each colour parameter at either end (an albedo brightens at its maximum, a coat's
    # absorption at its minimum), the others along one line through their ranges
    bounded = [p for p in colour if p.max is not None]
    ends = [
        {p.name: (p.max if top else _lower_bound(p)) for p, top in zip(bounded, pick, strict=True)}
        for pick in itertools.product((True, False), repeat=len(bounded))
    ]
    shape = [p for p in entry.applicable(fixed) if not p.categorical and not p.channels]
    shape = [p for p in shape if p.name not in fixed]
    best = 0.0
    grid = np.linspace(0.0, 1.0, 11)
    for t, colours in itertools.product(grid if shape else [0.0], ends):
        values = {
            p.name: _lower_bound(p) + t * (min(p.max, 1e3) - _lower_bound(p))
            for p in shape
            if p.min is not None and p.max is not None
        }
        with use_fastpath(False):
            a = _albedos(entry.create(**fixed, **colours, **values), mu)
        best = max(best, float(np.sum(wmu * mu * 2.0 * a)))
    if src > best * (1.0 + 1e-3):
        raise ParameterError(
            f"target {entry.id!r} cannot represent the source's albedo: its largest "
            f"hemispherical albedo is {best:.4f} (albedo parameter at its maximum), the "
            f"source's is {src:.4f}; choose a target that reaches it or lower the source's albedo"
        )
