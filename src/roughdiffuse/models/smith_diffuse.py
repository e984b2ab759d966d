"""The Smith microsurface with Lambertian facets as a model: a simulation, not a formula.

f(ωi, ωo) of microfacets of albedo ρ that reflect by Lambert's law, heights uncorrelated,
isotropic Beckmann or GGX slopes of roughness α, all orders of interreflection: the random
walk of Heitz, Hanika, d'Eon and Dachsbacher, "Multiple-scattering microfacet BSDFs with the
Smith model", SIGGRAPH 2016 (their diffuse material), computed by
:mod:`roughdiffuse.simulate.smith`. Hammon's GGX diffuse (GDC 2017) was fitted to this
surface with GGX slopes.

It is Monte Carlo: each evaluation traces ``samples`` paths per distinct geometry (seeded,
so the same call gives the same values), on concrete NumPy values. It cannot be traced
(``jax.jit``), compiled by the fast path, or written in GLSL (``traceable = False``): meant
for tables, comparisons and reports, not images.
"""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np

from .._array import Array, asarray, concrete
from .._validate import ParameterError
from .base import Model
from .declaration import albedo_param, param

__all__ = ["SmithDiffuse"]


class SmithDiffuse(Model):
    """Smith microsurface of Lambertian facets, all bounces, by Monte Carlo (1/sr).

    Parameters
    ----------
    albedo : float or array (C,)
        Facet albedo ρ in [0, 1] (per channel: one walk serves every channel, order k
        weighted by ρ^k).
    alpha : float
        Roughness α in [0, 2]; 0 is Lambert.
    distribution : {"beckmann", "ggx"}
        Slope distribution.
    samples : int
        Paths per distinct geometry (standard error ∝ 1/√samples; 4096 gives about 1 %).
    seed : int
        Seed of the walk.

    Examples
    --------
    >>> import numpy as np
    >>> m = SmithDiffuse(albedo=0.5, alpha=0.0)
    >>> round(float(m.brdf(np.array([0.0, 0.6, 0.8]), np.array([0.0, 0.0, 1.0]))) * np.pi, 12)
    0.5
    """

    albedo: float | Array = albedo_param("facet albedo ρ")
    alpha: float | Array = param(
        "roughness α of the slope distribution",
        min=0.0,
        max=2.0,
        default=0.0,
        example=0.5,
    )
    distribution: str = param("slope distribution", choices=("beckmann", "ggx"), default="beckmann")
    samples: int = 4096
    seed: int = 0

    ids: ClassVar[dict[str, dict[str, Any]]] = {
        "smith-diffuse-beckmann": {"distribution": "beckmann"},
        "smith-diffuse-ggx": {"distribution": "ggx"},
    }
    labels: ClassVar[dict[str, str]] = {
        "smith-diffuse-beckmann": "Smith diffuse microsurface (Beckmann, Monte Carlo)",
        "smith-diffuse-ggx": "Smith diffuse microsurface (GGX, Monte Carlo)",
    }
    reference: ClassVar[str] = (
        "Heitz, Hanika, d'Eon, Dachsbacher, Multiple-scattering microfacet BSDFs with the "
        "Smith model, ACM TOG 35(4) (SIGGRAPH 2016)"
    )
    traceable: ClassVar[bool] = False
    closed_form: ClassVar[bool] = False
    symbols: ClassVar[dict[str, str]] = {
        "albedo": r"\rho",
        "alpha": r"\alpha",
    }
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f_r(\omega_i,\omega_o) = \sum_{k\ge 1}\rho^k f_k(\omega_i,\omega_o;\alpha)
        ```
        ```{math}
        D_{\mathrm{Beckmann}}(h) =
        \frac{e^{-\tan^2\theta_h/\alpha^2}}{\pi\alpha^2\cos^4\theta_h},\qquad
        D_{\mathrm{GGX}}(h) = \frac{\alpha^2}{\pi\cos^4\theta_h\,(\alpha^2+\tan^2\theta_h)^2}
        ```

        No closed form: f_k, the k-bounce part on a Smith microsurface (uncorrelated heights)
        of Lambertian facets with normal distribution D, is estimated by the random walk of
        Heitz, Hanika, d'Eon and Dachsbacher (SIGGRAPH 2016), ``samples`` paths per geometry
        with a fixed seed (standard error ∝ 1/√samples). α = 0 is Lambert.
        """

    order: ClassVar[int] = 160
    def __post_init__(self) -> None:
        super().__post_init__()
        for name, lo in (("samples", 2), ("seed", 0)):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int | np.integer) or v < lo:
                raise ParameterError(f"{name} must be an integer >= {lo} (got {v!r})")

    def _kernel(
        self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, albedo: Array, alpha: Array
    ) -> Array:
        values = [concrete(a) for a in (mu_i, mu_o, cos_io, albedo, alpha)]
        if any(v is None for v in values):
            raise ParameterError(
                "SmithDiffuse is a Monte Carlo simulation on concrete values: it cannot be "
                "traced (jax.jit, grad), compiled by the fast path or written in GLSL"
            )
        from ..simulate.smith import random_walk

        mi, mo, c, rho, a = (np.asarray(v, dtype=np.float64) for v in values)
        mi, mo, c = np.broadcast_arrays(mi, mo, c)
        si = np.sqrt(np.maximum(1.0 - mi * mi, 0.0))
        so = np.sqrt(np.maximum(1.0 - mo * mo, 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            cd = np.where(si * so > 0, (c - mi * mo) / (si * so), 1.0)
        ti, tr = np.arccos(np.clip(mi, 0.0, 1.0)), np.arccos(np.clip(mo, 0.0, 1.0))
        dp = np.arccos(np.clip(cd, -1.0, 1.0))
        # one walk per distinct geometry (a table's rows repeat them for every channel)
        key = np.stack([ti.ravel(), tr.ravel(), dp.ravel()], axis=1)
        uniq, inverse = np.unique(key, axis=0, return_inverse=True)
        rhos = tuple(float(r) for r in np.atleast_1d(rho).ravel())
        r = random_walk(uniq[:, 0], uniq[:, 1], uniq[:, 2], float(a), rhos, "all",
                        self.distribution, samples=self.samples, seed=self.seed)
        vals = r.values[:, inverse.ravel()]  # (channels or 1, N)
        shape = mi.shape
        if self.channels:  # the base class put a channel axis on the cosines: (..., 1)
            out = np.moveaxis(vals.reshape((len(rhos), *shape[:-1])), 0, -1)
        else:
            out = vals[0].reshape(shape)
        return asarray(xp, out, getattr(mu_i, "dtype", None))

    def directional_albedo_estimate(self, theta_i: Any) -> tuple[np.ndarray, np.ndarray]:
        """Directional albedo and its standard error by the walk (scalar albedo only)."""
        from ..simulate.smith import directional_albedo

        return directional_albedo(theta_i, float(self.alpha), float(self.albedo), "all",
                                  self.distribution, samples=self.samples, seed=self.seed)

