"""What the explorer's server computes in Python: the vase image and ground truth.

Both depend on other parts of roughdiffuse (:mod:`roughdiffuse.render`,
:mod:`roughdiffuse.simulate`); when a part is missing, :func:`info` says so and the page hides
what needs it. No table of ground truth ships with the package: the server runs the solver for
the plane of incidence on request (0.1–0.3 s for a new σ, cached).

What a request may cost is bounded: the vase comes in the sizes of :data:`VASE_SIZES` only,
and at most :data:`VASE_COMPILED` compiled renderers are kept (:class:`CompiledVariants`);
the ground truth keeps :data:`GROUND_TRUTH_CACHED` curves.
"""

from __future__ import annotations

import functools
import math
import threading
from collections.abc import Callable, Hashable
from typing import Any

import numpy as np

from .. import registry
from .._validate import ParameterError
from .._version import version
from .datasets import MAX_CSV_BYTES, MAX_MERL_BYTES
from .params import flat_key, model_from_params

__all__ = [
    "THETA_R_DEG",
    "VASE_COMPILED",
    "VASE_SIZES",
    "CompiledVariants",
    "Unavailable",
    "ground_truth",
    "info",
    "number",
    "params_from_query",
    "vase_png",
]

VASE_SIZES = (64, 128, 200, 256, 512)
"""Image sizes (pixels) the vase endpoint offers; the page asks for 200."""

VASE_COMPILED = 8
"""Compiled vase renderers kept at once: each (model, size) compiles once (3–5 s of CPU,
about 9 MB); see :class:`CompiledVariants`."""

GROUND_TRUTH_CACHED = 64
"""Ground-truth curves kept (45 floats each)."""


class CompiledVariants:
    """A bound on the renderer's compiled variants.

    The renderer compiles one function per (model structure, image size) into JAX's own
    caches, which grow without bound and cannot drop a single entry. This class counts the
    variants compiled since the caches were last emptied; when a new one would make more than
    ``maxsize``, it empties them (``clear``, by default :func:`jax.clear_caches`) first. So at
    most ``maxsize`` variants are held at any time; a variant in use again is not counted
    twice.

    Parameters
    ----------
    maxsize : int
        Variants kept.
    clear : callable, optional
        Empties the compiled caches.
    """

    def __init__(self, maxsize: int = VASE_COMPILED, clear: Callable[[], None] | None = None):
        self.maxsize = maxsize
        self.clears = 0
        self._clear = clear
        self._keys: set[Hashable] = set()
        self._lock = threading.Lock()

    def __len__(self) -> int:
        return len(self._keys)

    def __contains__(self, key: Hashable) -> bool:
        return key in self._keys

    def use(self, key: Hashable) -> None:
        """Note that ``key`` is about to be rendered (compiled if new)."""
        with self._lock:
            if key in self._keys:
                return
            if len(self._keys) >= self.maxsize:
                self._keys.clear()  # the caches are emptied: nothing stays compiled
                if self._clear is not None:
                    self._clear()
                else:
                    import jax

                    jax.clear_caches()
                self.clears += 1
            self._keys.add(key)


VASE_VARIANTS = CompiledVariants()
"""The vase endpoint's compiled variants."""


class Unavailable(Exception):
    """The part of roughdiffuse an endpoint needs is not installed or has no data."""


def number(q: dict[str, str], key: str, default: float) -> float:
    """The finite number ``q[key]`` (``default`` when absent); ``ValueError`` naming ``key``."""
    return _float(q, key, default)


def _float(q: dict[str, str], key: str, default: float) -> float:
    text = q.get(key)
    if text is None:
        return default
    try:
        v = float(text)
    except ValueError:
        raise ParameterError(f"{key} must be a number (got {text!r})") from None
    if not math.isfinite(v):
        raise ParameterError(f"{key} must be finite (got {text!r})")
    return v


def channel_values(q: dict[str, str], key: str, default: float) -> list[float]:
    """A per-channel parameter of the query: three comma-separated numbers, or one for all
    three (R = G = B)."""
    text = q.get(key, str(default))
    try:
        values = [float(a) for a in text.split(",")]
    except ValueError:
        raise ParameterError(
            f"{key} must be one or three comma-separated numbers (got {text!r})"
        ) from None
    if len(values) == 1:
        values = values * 3
    if len(values) != 3:
        raise ParameterError(f"{key} must be one or three comma-separated numbers (got {text!r})")
    return values


def params_from_query(q: dict[str, str]) -> dict[str, Any]:
    """Explorer parameters (see :func:`~roughdiffuse.explorer.params.model_from_params`) from
    URL query values; σ in radians."""
    albedo = channel_values(q, "albedo", 0.8)
    out = {
        "model": q.get("model", "oren-nayar"),
        "albedo": albedo,
        "sigma": _float(q, "sigma", 0.0),
        "roughness": _float(q, "roughness", 0.0),
        "eta": _float(q, "eta", 1.5),
        "weight": _float(q, "weight", 0.0),
        "limb": _float(q, "limb", 0.5),
        "alpha": _float(q, "alpha", math.sqrt(2.0) * 0.2),
        "distribution": q.get("distribution", "gaussian"),
        "base": q.get("base", "oren-nayar-full"),  # Coated's base and its r
        "base_roughness": _float(q, "base_roughness", 0.5),
    }
    try:
        entry = registry.get(out["model"])
    except ParameterError:
        return out  # model_from_params names the models it takes
    for p in entry.parameters:  # the model's other numbers (an alias's sigma_deg, ...)
        key = flat_key(entry, p.name)
        if key not in out and key in q and not p.categorical and not p.channels:
            out[key] = _float(q, key, p.default)
    return out


def _render_vase() -> Any:
    """A function (model, query) -> PNG bytes of the vase, or None without the renderer."""
    try:
        from ..io.images import linear_to_srgb
        from ..render import DistantLight, SurfaceOfRevolution, render
    except ImportError:
        return None

    def vase(model: Any, q: dict[str, str]) -> bytes:
        import io

        import numpy as np
        from PIL import Image

        theta = _float(q, "light_theta", 0.0)
        phi = _float(q, "light_phi", 0.0)
        if not 0.0 <= theta <= 180.0:
            raise ParameterError(f"light_theta must be in [0, 180] degrees (got {theta:g})")
        exposure = _float(q, "exposure", 0.0)
        if not -10.0 <= exposure <= 10.0:
            raise ParameterError(f"exposure must be in [-10, 10] stops (got {exposure:g})")
        size = _float(q, "size", 200)
        if size not in VASE_SIZES:
            raise ParameterError(
                f"size must be one of {', '.join(map(str, VASE_SIZES))} pixels (got {size:g})"
            )
        size = int(size)
        # E0 = π and 2^exposure, as on the page's sphere (a white Lambert surface facing the
        # light has radiance 1)
        light = DistantLight(math.radians(theta), math.radians(phi), math.pi)
        VASE_VARIANTS.use((type(model).__name__, repr(_static_fields(model)), size))
        image, _ = render(model, SurfaceOfRevolution(), light, size=size, samples_per_pixel=4)
        rgb = np.asarray(image, dtype=np.float64) * 2.0**exposure
        if not np.all(np.isfinite(rgb)):
            raise ParameterError(
                f"these parameters give a vase image with NaN or infinite radiance "
                f"({q.get('model', 'oren-nayar')}: eta={q.get('eta', '1.5')}, "
                f"sigma={q.get('sigma', '0')}, roughness={q.get('roughness', '0')})"
            )
        if rgb.ndim == 2:
            rgb = np.repeat(rgb[..., None], 3, axis=-1)
        data = np.round(linear_to_srgb(rgb) * 255.0).astype(np.uint8)
        buf = io.BytesIO()
        Image.fromarray(data, "RGB").save(buf, format="PNG")
        return buf.getvalue()

    return vase


def _static_fields(model: Any) -> tuple[Any, ...]:
    """The fields of ``model`` that select a compiled variant (strings: variant,
    distribution), and those of a Mix's components."""
    import dataclasses

    if not dataclasses.is_dataclass(model):
        return ()
    out: list[Any] = []
    for f in dataclasses.fields(model):
        v = getattr(model, f.name)
        if isinstance(v, str):
            out.append(v)
        elif f.name == "components":
            out.extend((type(m).__name__, _static_fields(m)) for _, m in v)
    return tuple(out)


def _solver() -> Any:
    """The V-cavity solver's BRDF function, or None when roughdiffuse.simulate is missing."""
    try:
        from ..simulate.surface import brdf
    except ImportError:
        return None
    return brdf


THETA_R_DEG = tuple(float(t) for t in range(-88, 89, 4))
"""Viewing angles of the ground-truth curve (signed: > 0 on the light's side)."""

_SOLVER_LOCK = threading.Lock()  # one solver run at a time: the machine may have 2 cores


@functools.lru_cache(maxsize=GROUND_TRUTH_CACHED)
def _plane_of_incidence(
    sigma: float, theta_i_deg: float, albedo: float, bounces: str = "all"
) -> tuple[float, ...]:
    brdf = _solver()
    tr = np.radians(np.abs(THETA_R_DEG))
    delta_phi = np.where(np.asarray(THETA_R_DEG) >= 0, 0.0, math.pi)
    with _SOLVER_LOCK:
        f = brdf(
            math.radians(theta_i_deg),
            tr,
            delta_phi,
            sigma=sigma,
            albedo=albedo,
            bounces="all" if bounces == "all" else int(bounces),
        )
    return tuple(float(v) for v in np.asarray(f))


def info() -> dict[str, Any]:
    """Capabilities of this server, for the page."""
    return {
        "version": version(),
        "vase": _render_vase() is not None,
        "groundtruth": _solver() is not None,
        "upload_bytes": {"merl": MAX_MERL_BYTES, "csv": MAX_CSV_BYTES},
    }


def vase_png(q: dict[str, str]) -> bytes:
    """PNG bytes of the vase (Oren and Nayar's Fig. 7 clay vase, :func:`~roughdiffuse.render.
    clay_vase_profile`), rendered by the Python renderer with the model the query describes,
    lit from ``light_theta``, ``light_phi`` (degrees), ``exposure`` in stops."""
    model = model_from_params(params_from_query(q))
    render = _render_vase()
    if render is None:
        raise Unavailable("the Python renderer (roughdiffuse.render) is not available")
    return render(model, q)


def ground_truth(q: dict[str, str]) -> dict[str, Any]:
    """V-cavity radiance in the plane of incidence, from the solver (one or all bounces).

    Query: ``sigma`` (radians, (0, π/2]), ``theta_i`` (degrees, [0, 90)), ``albedo`` ([0, 1]),
    ``bounces`` (``"1"``: shadowing and masking only, the single-scattering part Oren and
    Nayar's direct term models; ``"all"``: with every interreflection, the default).
    The values are put on a grid (σ to 1e-4 rad, θi to 0.1°, ρ to 0.001) so that small
    slider moves hit the cache; the grid value is kept inside the range (σ ≥ 1e-4 and
    ≤ π/2, θi ≤ 89.9°), and it is the one validated, used and returned. Computed on demand
    by :func:`roughdiffuse.simulate.surface.brdf` with its default settings (0.1–0.3 s for
    the 45 angles on a quiet core, any σ; cached), at θr = −88°, −84°, …, 88°.

    Returns
    -------
    dict
        ``theta_r`` (degrees), ``brdf`` (1/sr), ``radiance`` (f E0 cos θi with E0 = π, as on
        the page), the parameters, and a ``note`` for the page.
    """
    if _solver() is None:
        raise Unavailable("the V-cavity solver (roughdiffuse.simulate) is not available")
    sigma = _float(q, "sigma", 0.3)
    theta_i = _float(q, "theta_i", 0.0)
    albedo = _float(q, "albedo", 0.8)
    bounces = q.get("bounces", "all")
    if bounces not in ("1", "all"):
        raise ParameterError(f"bounces must be '1' or 'all' (got {bounces!r})")
    if not 0.0 < sigma <= math.pi / 2:
        raise ParameterError(f"sigma must be in (0, π/2] radians (got {sigma!r})")
    if not 0.0 <= theta_i < 90.0:
        raise ParameterError(f"theta_i must be in [0, 90) degrees (got {theta_i!r})")
    if not 0.0 <= albedo <= 1.0:
        raise ParameterError(f"albedo must be in [0, 1] (got {albedo!r})")
    # on a grid so that small slider moves hit the cache, kept inside the accepted range
    sigma = min(max(round(sigma, 4), 1e-4), math.pi / 2)
    theta_i = min(round(theta_i, 1), 89.9)
    albedo = round(albedo, 3)
    if not (0.0 < sigma <= math.pi / 2 and 0.0 <= theta_i < 90.0 and 0.0 <= albedo <= 1.0):
        raise AssertionError(f"grid values out of range: {sigma!r}, {theta_i!r}, {albedo!r}")
    f = _plane_of_incidence(sigma, theta_i, albedo, bounces)
    e_cos = math.pi * math.cos(math.radians(theta_i))
    return {
        "theta_r": list(THETA_R_DEG),
        "brdf": list(f),
        "radiance": [v * e_cos for v in f],
        "sigma": sigma,
        "theta_i": theta_i,
        "albedo": albedo,
        "bounces": bounces,
        "note": (
            f"V-cavity ground truth (roughdiffuse.simulate, "
            f"{'all bounces' if bounces == 'all' else 'one bounce'}, default settings): "
            f"σ = {math.degrees(sigma):.1f}°, θi = {theta_i:.1f}°, ρ = {albedo:.3f} "
            "(model A's green albedo)."
        ),
    }
