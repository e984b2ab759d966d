"""Weighted sums of models: rough surfaces with diffuse and surface reflection.

The lecture's summary ("many surfaces may be rough and show both diffuse and surface
reflection"): for example ``Mix([(0.9, OrenNayar(0.8, 0.3)), (0.1, TorranceSparrow())])``.

A Mix is a model like the others: its BRDF is the weighted sum of its components', its
directional albedo the weighted sum of theirs, and it is importance-sampled as a mixture of
their own strategies (:func:`mixture`), as Mitsuba 3's ``blendbsdf`` does
(src/bsdfs/blendbsdf.cpp): one component is chosen, its sampler draws wi, and the density is
the mixture's, Σ_k q_k pdf_k(wi). blendbsdf chooses with probability equal to the weight;
here the probability is the weight times the component's albedo estimate
(:meth:`~roughdiffuse.models.base.Model.albedo_estimate`), q_k ∝ w_k a_k(μo), so that a weak
lobe (a Fresnel coat reflecting 4 %) is not sampled as often as the body beneath it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, ClassVar

from .._array import Array, safe_div
from .._validate import ParameterError, check_range
from .base import Model
from .declaration import Param
from .oren_nayar import SIGMA_MAX
from .sampling import Strategy, strategy_for
from .torrance_sparrow import ETA_MAX

__all__ = ["Mix", "mixture"]


class Mix(Model):
    """f = Σ_k w_k f_k.

    Parameters
    ----------
    components : sequence of (weight, model)
        Non-negative weights (they need not sum to 1) and models (a Mix may hold Mixes).

    Notes
    -----
    ``sample``/``pdf`` use the mixture of the components' strategies (:func:`mixture`);
    ``directional_albedo`` is Σ_k w_k times each component's own directional albedo.

    Examples
    --------
    >>> from roughdiffuse import Lambert
    >>> import numpy as np
    >>> m = Mix([(0.5, Lambert(1.0)), (0.5, Lambert(0.0))])
    >>> w = np.array([0.0, 0.0, 1.0])
    >>> round(float(m.brdf(w, w)) * np.pi, 12)
    0.5
    >>> round(float(m.directional_albedo(w)), 12)
    0.5
    """

    components: Sequence[tuple[float | Array, Model]] = ()

    array_fields: ClassVar[tuple[str, ...]] = ("components",)
    channel_fields: ClassVar[tuple[str, ...]] = ()
    # The registry's "mix" is the lecture's rough surface with diffuse and surface reflection,
    # (1 − w) Oren–Nayar full + w Torrance–Sparrow with one σ (see from_params); these are its
    # parameters, not fields of the class.
    factory_params: ClassVar[tuple[Param, ...]] = (
        Param("albedo", "facet albedo ρ of the diffuse part", min=0.0, max=1.0, default=1.0,
              channels=True, example=0.8),
        Param("sigma", "σ, slope-angle standard deviation of both parts", unit="radians",
              min=0.0, max=SIGMA_MAX, default=0.2, example=math.radians(20.0)),
        Param("weight", "w, weight of the specular part", min=0.0, max=1.0, default=0.1),
        Param("eta", "relative refractive index η of the specular part", min=0.0, max=ETA_MAX,
              min_open=True, default=1.5, fit_range=(1.0, 3.0)),
        Param("distribution", "facet distribution of the specular part (Beckmann: α = √2 σ)",
              choices=("gaussian", "beckmann"), default="gaussian"),
    )
    ids: ClassVar[dict[str, dict[str, Any]]] = {"mix": {}}
    labels: ClassVar[dict[str, str]] = {"mix": "Mix: Oren–Nayar full + Torrance–Sparrow"}
    reference: ClassVar[str] = "weighted sum of models (Mitsuba 3 blendbsdf)"
    order: ClassVar[int] = 50
    symbols: ClassVar[dict[str, str]] = {
        "albedo": r"\rho",
        "sigma": r"\sigma",
        "weight": r"w",
        "eta": r"\eta",
    }
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f_r = (1-w)\,f_{\text{Oren–Nayar full}}(\rho,\sigma) +
        w\,f_{\text{Torrance–Sparrow}}(\eta,\sigma)
        ```

        The lecture's rough surface with body and surface reflection: the two models of
        {doc}`oren-nayar-full` and {doc}`torrance-sparrow` with one σ (with
        ``distribution="beckmann"``, the specular part's α is √2 σ). In general a
        {class}`~roughdiffuse.models.mix.Mix` is {math}`f_r = \sum_k w_k f_k`.
        """

    @classmethod
    def from_params(
        cls,
        albedo: float | Array = 1.0,
        sigma: float | Array = 0.2,
        weight: float | Array = 0.1,
        eta: float | Array = 1.5,
        distribution: str = "gaussian",
    ) -> Mix:
        """The registry's ``mix``: (1 − w) ``oren-nayar-full`` (ρ, σ) + w ``torrance-sparrow`` (η,
        σ), both made by the registry.

        With ``distribution="beckmann"`` the specular part has α = √2 σ (the explorer's
        reading: the same small-slope width as the Gaussian).

        >>> m = Mix.from_params(albedo=0.5, sigma=0.3, weight=0.25)
        >>> [round(float(w), 2) for w, _ in m.components]
        [0.75, 0.25]
        """
        from .. import registry

        checked = {p.name: p for p in cls.params}
        w = checked["weight"].check(weight)
        checked["distribution"].check(distribution)
        diffuse = registry.create("oren-nayar-full", albedo=albedo, sigma=sigma)
        if distribution == "beckmann":
            sigma = checked["sigma"].check(sigma)
            alpha = math.sqrt(2.0) * sigma
            specular = registry.create("torrance-sparrow-beckmann", eta=eta, alpha=alpha)
        else:
            specular = registry.create("torrance-sparrow", eta=eta, sigma=sigma)
        return cls([(1.0 - w, diffuse), (w, specular)])

    def __post_init__(self) -> None:
        comps = tuple((w, m) for w, m in self.components)
        if not comps:
            raise ParameterError("components must hold at least one (weight, model) pair")
        for k, (w, m) in enumerate(comps):
            check_range(f"components[{k}] weight", w, 0.0, float("inf"))
            if not isinstance(m, Model):
                raise ParameterError(f"components[{k}] must be a (weight, Model) pair (got {m!r})")
        object.__setattr__(self, "components", comps)

    def parameter_values(self) -> list[Any]:
        vals: list[Any] = []
        for w, m in self.components:
            vals.append(w)
            vals.extend(m.parameter_values())
        return vals

    def parameter_arrays(self, xp: Any, dtype: Any = None) -> dict[str, Any]:
        """The weights and each component's parameters, as :func:`mixture` reads them."""
        from .._array import asarray

        return {
            "weights": tuple(asarray(xp, w, dtype) for w, _ in self.components),
            "components": tuple(m.parameter_arrays(xp, dtype) for _, m in self.components),
        }

    @property
    def channels(self) -> int:
        return max(m.channels for _, m in self.components)

    def channel(self, c: int) -> Mix:
        """This Mix for colour channel ``c`` alone (each component's :meth:`channel`)."""
        return Mix([(w, m.channel(c)) for w, m in self.components])

    @property
    def lobes(self) -> frozenset[str]:
        """The lobe types of the components (``"diffuse"``, ``"glossy"``)."""
        out: set[str] = set()
        for _, m in self.components:
            out |= set(getattr(m, "lobes", {getattr(type(m), "lobe", "diffuse")}))
        return frozenset(out)

    def _weighted_sum(self, values: Sequence[Array], channels: Sequence[int]) -> Array:
        total = None
        ch = self.channels
        for (w, _), f, c in zip(self.components, values, channels, strict=True):
            if ch and not c:
                f = f[..., None]
            term = f * w
            total = term if total is None else total + term
        return total

    def evaluate(self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, dtype: Any) -> Array:
        return self._weighted_sum(
            [m.evaluate(xp, mu_i, mu_o, cos_io, dtype) for _, m in self.components],
            [m.channels for _, m in self.components],
        )

    def directional_albedo(self, wo: Array) -> Array:
        """Σ_k w_k ∫ f_k cos θi dωi: each component by its own rule (closed form or its
        quadrature), which resolves a narrow specular lobe that a rule over the whole
        hemisphere would miss."""
        return self._weighted_sum(
            [m.directional_albedo(wo) for _, m in self.components],
            [m.channels for _, m in self.components],
        )

    def albedo_estimate(self, xp: Any, mu_o: Array, p: dict[str, Any]) -> Array:
        """Σ_k w_k a_k(μo), the components' estimates weighted (see :func:`mixture`)."""
        total = None
        for (_, m), w, pk in zip(self.components, p["weights"], p["components"], strict=True):
            term = w * m.albedo_estimate(xp, mu_o, pk)
            total = term if total is None else total + term
        return total

    def sampling_strategy(self) -> Strategy:
        """The mixture of the components' strategies (:func:`mixture`)."""
        return mixture(tuple(m for _, m in self.components))


def _selection(xp: Any, models: Sequence[Model], mu_o: Array, p: dict[str, Any]) -> list[Array]:
    """q_k = w_k a_k(μo) / Σ_j w_j a_j(μo): the probability of sampling component k.

    Falls back to q_k ∝ w_k where every estimate is 0 (all albedos 0), and to q_k = 1/K
    where every weight is 0 (then f = 0 and any density will do).
    """
    zero = 0.0 * mu_o
    est = [
        w * m.albedo_estimate(xp, mu_o, pk) + zero
        for m, w, pk in zip(models, p["weights"], p["components"], strict=True)
    ]
    ws = [w + zero for w in p["weights"]]
    total_est = sum(est[1:], est[0])
    total_w = sum(ws[1:], ws[0])
    uniform = 1.0 / len(models)
    return [
        xp.where(
            total_est > 0,
            safe_div(xp, e, total_est),
            xp.where(total_w > 0, safe_div(xp, w, total_w), uniform + zero),
        )
        for e, w in zip(est, ws, strict=True)
    ]


def mixture(models: Sequence[Model]) -> Strategy:
    """The sampling strategy of a mixture of ``models`` (Mitsuba 3's ``blendbsdf``).

    The strategy's parameters ``p`` are ``{"weights": (w_k), "components": (p_k)}``
    (:meth:`Mix.parameter_arrays`). Sampling: component k is chosen with probability
    q_k = w_k a_k(μo) / Σ_j w_j a_j(μo) (a_k the component's
    :meth:`~roughdiffuse.models.base.Model.albedo_estimate`) by the first uniform number u1,
    which is then rescaled to [0, 1] within the chosen interval and handed to the
    component's own sampler, as blendbsdf does. The density is Σ_k q_k pdf_k(wi): the sample
    weight f cos θi / pdf is that of the whole mixture, unbiased whatever the q_k. Every
    component's sampler runs on every sample (branch-free code for every array namespace,
    Dr.Jit in Mitsuba included); the chosen one's direction is kept.
    """
    models = tuple(models)
    strategies = tuple(strategy_for(m) for m in models)

    def pdf(xp: Any, wix, wiy, wiz, wox, woy, woz, p: dict) -> Array:
        q = _selection(xp, models, woz, p)
        total = None
        for s, qk, pk in zip(strategies, q, p["components"], strict=True):
            term = qk * s.pdf(xp, wix, wiy, wiz, wox, woy, woz, pk)
            total = term if total is None else total + term
        return total

    def sample(xp: Any, u1, u2, wox, woy, woz, p: dict):
        q = _selection(xp, models, woz, p)
        lo = 0.0 * woz
        x = y = z = None
        for k, (s, qk, pk) in enumerate(zip(strategies, q, p["components"], strict=True)):
            uk = safe_div(xp, u1 - lo, qk)
            # outside [0, 1] where another component is chosen: any valid number will do
            uk = xp.where((uk < 0.0) | (uk > 1.0), 0.5 + 0.0 * uk, uk)
            xk, yk, zk, _ = s.sample(xp, uk, u2, wox, woy, woz, pk)
            if k == 0:
                x, y, z = xk, yk, zk
            else:  # u1 beyond the earlier intervals: this component (or a later one)
                chosen = (u1 >= lo) & (qk > 0)
                x, y, z = xp.where(chosen, xk, x), xp.where(chosen, yk, y), xp.where(chosen, zk, z)
            lo = lo + qk
        return x, y, z, pdf(xp, x, y, z, wox, woy, woz, p)

    name = "mixture(" + ", ".join(s.name for s in strategies) + ")"
    return Strategy(name, sample, pdf)
