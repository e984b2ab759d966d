"""Fujii's improved Oren–Nayar model (FON) and its exact directional albedo.

Y. Fujii, "A tiny improvement of Oren-Nayar reflectance model" (2012)::

    f = ρ (A + B s/t),   s = wi·wo − μi μo,   t = max(μi, μo) if s > 0 else 1,
    A = 1/(π + (π/2 − 2/3) r),   B = r A,   r in [0, 1].

Negative s is kept (no clamp). With K1 = 1/2 − 2/(3π) this is f = ρ/π A_F (1 + r s/t),
A_F = 1/(1 + K1 r), the form of the EON paper (Portsmouth, Kutz, Hill, "EON: a practical
energy-preserving rough diffuse BRDF", JCGT 2025, arXiv 2410.18026, Eq. 3–5). That paper
gives the model's directional albedo in closed form (its Eq. 8)::

    E_F(μ) = A_F + (B_F/π) G(μ),   S = √(1 − μ²),
    G(μ) = S (acos μ − S μ) + (2/3) [(S/μ)(1 − S³) − S],

and its cosine-weighted average Ē_F = A_F (1 + K2 r), K2 = 2/3 − 28/(15π).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

from .._array import Array, clip, maximum, safe_sqrt
from .base import Model, register_pytree
from .declaration import Param
from .oren_nayar import TAN_FLOOR
from .sampling import CLTC, Strategy

__all__ = ["Fujii", "fon_albedo", "fon_average_albedo", "K1", "K2"]

K1 = 0.5 - 2.0 / (3.0 * math.pi)
K2 = 2.0 / 3.0 - 28.0 / (15.0 * math.pi)


def fon_lobe(xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, r: Array) -> Array:
    """A_F (1 + r s/t): the FON BRDF times π/ρ (EON paper Eq. 3–5)."""
    s = cos_io - mu_i * mu_o
    t = maximum(xp, maximum(xp, mu_i, mu_o), TAN_FLOOR)
    s_over_t = xp.where(s > 0, s / t, s)
    return (1.0 + r * s_over_t) / (1.0 + K1 * r)


def fon_albedo(xp: Any, mu: Array, r: Array) -> Array:
    """E_F(μ), the directional albedo of FON at ρ = 1, in closed form (EON paper Eq. 8).

    The term (S/μ)(1 − S³) is rewritten as S μ (1 + S + S²)/(1 + S) (from 1 − S = μ²/(1 + S)),
    so μ = 0 (grazing) needs no special case: G(0) = π/2 − 2/3.
    """
    mu = clip(xp, mu, 0.0, 1.0)
    s = safe_sqrt(xp, 1.0 - mu * mu)
    g = s * (xp.atan2(s, mu) - s * mu) + (2.0 / 3.0) * (s * mu * (1.0 + s + s * s) / (1.0 + s) - s)
    a_f = 1.0 / (1.0 + K1 * r)
    return a_f + (r * a_f / math.pi) * g


def fon_average_albedo(r: Array) -> Array:
    """Ē_F = 2 ∫ E_F(μ) μ dμ = A_F (1 + K2 r) (EON paper Eq. 9)."""
    return (1.0 + K2 * r) / (1.0 + K1 * r)


@register_pytree
@dataclass(frozen=True)
class Fujii(Model):
    """Fujii's Oren–Nayar (FON) BRDF, f = ρ (A + B s/t).

    Parameters
    ----------
    albedo : float or array (C,)
        ρ in [0, 1].
    roughness : float
        Fujii's r in [0, 1] (not an angle).

    Examples
    --------
    >>> import numpy as np
    >>> n = np.array([0.0, 0.0, 1.0])
    >>> float(Fujii(1.0, 0.0).brdf(n, n) * np.pi)  # r = 0 is Lambert
    1.0
    """

    albedo: float | Array = 1.0
    roughness: float | Array = 0.0

    params: ClassVar[tuple[Param, ...]] = (
        Param("albedo", "albedo ρ", min=0.0, max=1.0, default=1.0, channels=True, example=0.8),
        Param(
            "roughness",
            "Fujii's roughness r (not an angle)",
            min=0.0,
            max=1.0,
            default=0.0,
            example=0.5,
        ),
    )
    ids: ClassVar[dict[str, dict[str, Any]]] = {"fujii": {}}
    labels: ClassVar[dict[str, str]] = {"fujii": "Fujii (FON)"}
    sampling: ClassVar[Strategy] = CLTC
    reference: ClassVar[str] = "Y. Fujii, A tiny improvement of Oren-Nayar reflectance model (2012)"
    order: ClassVar[int] = 20
    test_points: ClassVar[dict[str, tuple[dict[str, Any], ...]]] = {"fujii": ({"roughness": 0.6},)}
    symbols: ClassVar[dict[str, str]] = {
        "albedo": r"\rho",
        "roughness": r"r",
    }
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f_r = \rho\,\Bigl(A + B\,\frac{s}{t}\Bigr),\qquad s = \omega_i\cdot\omega_o -
        \mu_i\mu_o,\qquad t = \begin{cases}\max(\mu_i,\mu_o) & s > 0,\\ 1 & s \le
        0,\end{cases}
        ```
        ```{math}
        A = \frac{1}{\pi + (\pi/2 - 2/3)\,r},
        ```
        ```{math}
        B = r\,A
        ```

        Fujii (2012); the same as {math}`f_r = \frac{\rho}{\pi}A_F\bigl(1 + r\,s/t\bigr)`,
        {math}`A_F = 1/(1 + K_1 r)`, {math}`K_1 = \tfrac12 - \tfrac{2}{3\pi}` (EON paper, Eq.
        3–5). Negative s is kept (no clamp, unlike Oren–Nayar's max(0, ·)); t is floored at
        10⁻⁶. r is not an angle; r = 0 is Lambert.
        """

    def _kernel(
        self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, albedo: Array, roughness: Array
    ) -> Array:
        return albedo / math.pi * fon_lobe(xp, mu_i, mu_o, cos_io, roughness)

    def directional_albedo(self, wo: Array) -> Array:
        """Closed form ρ E_F(μo) (EON paper Eq. 8)."""
        return self._closed_form_albedo(
            wo, lambda xp, mu, albedo, roughness: albedo * fon_albedo(xp, mu, roughness)
        )
