"""The element-wise formulas of the Smith random walk, written once for two back-ends.

The NumPy reference walk (:mod:`.smith`, :mod:`.smith_slopes`) applies these formulas to
arrays; the compiled walk (:mod:`.smith_walk_numba`) applies the very same functions to
scalars inside a Numba loop. :func:`build` takes the primitives (``sqrt``, ``erf``, a
``where`` that selects element-wise, a ``jit`` decorator...) and returns the formulas made of
them, so each formula has one source: NumPy's build passes NumPy/SciPy ufuncs and an identity
``jit``; Numba's passes scalar functions and ``numba.njit(inline="always")``. The functions
use only arithmetic and those primitives; wherever a choice depends on the data they compute
both sides and ``where`` picks one (a ``where`` of Python's conditional expression in Numba).
The callers on NumPy silence floating-point warnings (``np.errstate``): the side not taken
may divide by zero.

Formulas (per direction ω = (x, y, z), roughness α, isotropic slopes):

* ``lambda_upper`` / ``smith_lambda``, ``smith_g1``: Smith's Λ and G1 = 1/(1 + Λ) (Heitz
  2014, "Understanding the masking-shadowing function in microfacet-based BRDFs", JCGT 3(2),
  eqs. 72 (GGX) and 86 (Beckmann)), Λ(−ω) = −1 − Λ(ω) below the horizon (Heitz, Hanika,
  d'Eon, Dachsbacher 2016, "Multiple-scattering microfacet BSDFs with the Smith model",
  Sec. 3);
* ``visible_ggx`` (``visible_ggx_at`` from the azimuth's cosine and sine): GGX visible
  normals by spherical caps (Dupuy & Benyoub 2023, "Sampling visible GGX normals with
  spherical caps", Listing 3);
* ``beckmann_frame``, ``gaussian_pair``, ``slope_proposal_pos``, ``slope_proposal_neg``,
  ``beckmann_normal``: Beckmann visible normals in the stretched configuration (Heitz &
  d'Eon 2014, "Importance sampling microfacet-based BSDFs using the distribution of visible
  normals", Sec. 4), the slope x̃ by composition and rejection (see
  :func:`roughdiffuse.simulate.smith_slopes.sample_visible_normals`);
* ``cosine_about``: a cosine-distributed direction about a normal, in the orthonormal basis of
  Duff et al. 2017 ("Building an orthonormal basis, revisited", JCGT 6(1), Listing 3);
* ``height_step``, ``next_event``: one step of the height-space walk and its next-event
  estimate (Heitz et al. 2016, Sec. 4, eq. 7 inverted; heights as ln u, u = C1(height)).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from types import SimpleNamespace
from typing import Any

__all__ = ["build", "numpy_formulas"]

_SQRT_PI = math.sqrt(math.pi)
_TWO_PI = 2.0 * math.pi
_INF = math.inf


def build(p: Any) -> SimpleNamespace:
    """The walk's formulas made of the primitives ``p``.

    Parameters
    ----------
    p : namespace
        ``jit`` (a decorator), ``where(c, a, b)``, ``maximum``, ``minimum``, ``sqrt``, ``exp``,
        ``log1p``, ``sin``, ``cos``, ``erf``, ``erfc``, ``erfinv``, ``isfinite``.

    Returns
    -------
    SimpleNamespace
        The functions listed in the module docstring.
    """
    jit: Callable = p.jit
    where, maximum, minimum = p.where, p.maximum, p.minimum
    sqrt, exp, log1p, sin, cos = p.sqrt, p.exp, p.log1p, p.sin, p.cos
    erf, erfc, erfinv, isfinite = p.erf, p.erfc, p.erfinv, p.isfinite

    @jit
    def lambda_upper(ggx, cot, alpha):
        """Λ above the horizon from |cot θ| (∞ at the horizon, 0 at the zenith)."""
        a = cot / alpha
        if ggx:
            t2 = 1.0 / (a * a)  # α² tan² θ
            lam = t2 / (2.0 * (1.0 + sqrt(1.0 + t2)))
        else:
            # (erf(a) − 1)/2 + exp(−a²)/(2a√π), with erfc(a) for 1 − erf(a) against the
            # cancellation (one exp and one erfc)
            lam = 0.5 * (exp(-a * a) / (a * _SQRT_PI) - erfc(a))
        up = where(a > 0.0, maximum(lam, 0.0), _INF)
        return where(a < _INF, up, 0.0)

    @jit
    def smith_lambda(ggx, z, alpha):
        """Λ(ω) for a unit direction of z-component ``z``; Λ(−ω) = −1 − Λ(ω) below."""
        az = abs(z)
        s = sqrt(maximum(1.0 - z * z, 0.0))
        cot = where(s > 0.0, az / where(s > 0.0, s, 1.0), _INF)
        up = lambda_upper(ggx, cot, alpha)
        return where(z >= 0.0, up, -1.0 - up)

    @jit
    def smith_g1(ggx, z, alpha):
        """Smith's G1 = 1/(1 + Λ(ω)) above the horizon, z in (0, 1]; for GGX in the form
        2z/(z + √(α²(1 − z²) + z²)) (Heitz 2014, eq. 72 with tan² θ = (1 − z²)/z²: one
        square root and one division)."""
        if ggx:
            return 2.0 * z / (z + sqrt(alpha * alpha * (1.0 - z * z) + z * z))
        return 1.0 / (1.0 + smith_lambda(ggx, z, alpha))

    @jit
    def visible_ggx_at(wx, wy, wz, alpha, cphi, sphi, u2):
        """A GGX visible normal of ω (either side of the horizon) from the cosine and sine
        of a uniform azimuth and a uniform ``u2``."""
        sx, sy = alpha * wx, alpha * wy
        inv = 1.0 / sqrt(sx * sx + sy * sy + wz * wz)
        sx, sy, sz = sx * inv, sy * inv, wz * inv
        z = (1.0 - u2) * (1.0 + sz) - sz
        r = sqrt(minimum(maximum(1.0 - z * z, 0.0), 1.0))
        mx, my, mz = alpha * (r * cphi + sx), alpha * (r * sphi + sy), maximum(z + sz, 0.0)
        norm = sqrt(mx * mx + my * my + mz * mz)
        inv = 1.0 / where(norm > 0.0, norm, 1.0)
        return mx * inv, my * inv, mz * inv

    @jit
    def visible_ggx(wx, wy, wz, alpha, u1, u2):
        """A GGX visible normal of ω (either side of the horizon) from two uniforms."""
        phi = _TWO_PI * u1
        return visible_ggx_at(wx, wy, wz, alpha, cos(phi), sin(phi), u2)

    @jit
    def beckmann_frame(wx, wy, wz, alpha):
        """μ = cot θ̃ of ω in the stretched (α = 1) configuration and its azimuth's cos, sin
        (1, 0 within 1e-300 of the normal, where μ = ∞ and any azimuth serves)."""
        sx, sy = alpha * wx, alpha * wy
        rho = sqrt(sx * sx + sy * sy)
        big = rho > 1e-300  # 1/ρ is finite; below, μ = ∞ and the slopes are isotropic
        inv = 1.0 / where(big, rho, 1.0)
        return where(big, wz * inv, _INF), where(big, sx * inv, 1.0), where(big, sy * inv, 0.0)

    @jit
    def gaussian_pair(u2, u3):
        """Two independent N(0, 1/2) numbers by Box–Muller."""
        radius = sqrt(-log1p(-u2))
        return radius * cos(_TWO_PI * u3), radius * sin(_TWO_PI * u3)

    @jit
    def slope_proposal_pos(mu, u0, u1, u2):
        """One try at x̃ ~ (μ − x̃)⁺ exp(−x̃²) for μ ≥ 0: x̃, or NaN when rejected.

        x̃ < 0 from the mixture of a half-Gaussian (mass μ√π/2) and |x̃| e^{−x̃²} (mass
        1/2); 0 ≤ x̃ < μ from the envelope μ e^{−x̃²} (mass μ (√π/2) erf μ), accepted with
        probability (μ − x̃)/μ.
        """
        erf_mu = erf(mu)
        neg_mass = mu * (_SQRT_PI / 2) + 0.5
        pos_mass = mu * (_SQRT_PI / 2) * erf_mu
        left = u0 * (neg_mass + pos_mass) < neg_mass
        gauss = u1 * neg_mass < mu * (_SQRT_PI / 2)
        # one erfinv serves the part chosen: |erfinv(2 u2 − 1)| is the half-Gaussian,
        # erfinv(u1 erf μ) the Gaussian truncated to [0, μ)
        inv = erfinv(
            where(left, minimum(maximum(2.0 * u2 - 1.0, -1.0 + 1e-16), 1.0 - 1e-16), u1 * erf_mu)
        )
        xl = -where(gauss, abs(inv), sqrt(-log1p(-u2)))
        keep_r = u2 * mu < mu - inv
        return where(left, xl, where(keep_r, inv, math.nan))

    @jit
    def slope_proposal_neg(mu, v0, v1, v2):
        """One try at x̃ ~ (μ − x̃)⁺ exp(−x̃²) for μ < 0: x̃, or NaN when rejected.

        y = −x̃ > m = −μ: for m < 0.8, y from y e^{−y²} truncated to y > m, accepted with
        probability (y − m)/y; for m ≥ 0.8, y = m + s, s ~ Gamma(2, 2m), accepted with
        probability e^{−s²}.
        """
        mn = -mu
        small = mn < 0.8
        y_small = sqrt(mn * mn - log1p(-v0))
        s_big = -(log1p(-v0) + log1p(-v2)) / (2.0 * mn)  # Gamma(2, 2m): two exponentials
        y_big = mn + s_big
        ok = where(small, v1 * y_small < y_small - mn, v1 < exp(-s_big * s_big))
        return where(ok, -where(small, y_small, y_big), math.nan)

    @jit
    def beckmann_normal(alpha, cphi, sphi, tx, ty):
        """The unit normal of the stretched slope (x̃, ỹ) rotated to ω's azimuth."""
        px = alpha * (cphi * tx - sphi * ty)
        py = alpha * (sphi * tx + cphi * ty)
        inv = 1.0 / sqrt(px * px + py * py + 1.0)
        return -px * inv, -py * inv, inv

    @jit
    def cosine_about(mx, my, mz, u0, u1):
        """A cosine-distributed direction about the unit normal m (m_z > 0)."""
        r, phi = sqrt(u0), _TWO_PI * u1
        x, y, z = r * cos(phi), r * sin(phi), sqrt(maximum(1.0 - u0, 0.0))
        a = -1.0 / (1.0 + mz)
        b = mx * my * a
        return (
            x * (1.0 + mx * mx * a) + y * b + z * mx,
            x * b + y * (1.0 + my * my * a) + z * my,
            -x * mx - y * my + z * mz,
        )

    @jit
    def height_step(h, lam, wz, e):
        """A ray leaving log-height h = ln u ≤ 0 in direction ω (Λ(ω) = ``lam``):
        (escapes, next log-height).

        It escapes with probability G1 = u^Λ = e^{Λh} (upward only, ``e`` uniform) and
        otherwise meets the surface at u' = u (1 − e)^(−1/Λ) (Heitz et al. 2016, eq. 7
        inverted), h' = h − ln(1 − e)/Λ ≤ 0; at Λ = ±∞ (a horizontal ray) it stays at h.
        Carrying ln u costs one exp and one log1p per step where u costs two powers.
        """
        escape = (wz > 0.0) & (e > 1.0 - exp(lam * h))
        h_new = h - log1p(-e) / lam
        return escape, minimum(where(isfinite(h_new), h_new, h), 0.0)

    @jit
    def next_event(ox, oy, oz, mx, my, mz, h, lam_o):
        """f cos θo scored at a facet of normal m at log-height h: ⟨ωo, m⟩⁺/π · e^{Λ(ωo) h}
        (u^Λ(ωo); 1 at the top, h = 0, also for a grazing ωo, Λ = ∞)."""
        g1 = exp(where(h < 0.0, lam_o * h, 0.0))
        return maximum(ox * mx + oy * my + oz * mz, 0.0) / math.pi * g1

    return SimpleNamespace(
        lambda_upper=lambda_upper,
        smith_lambda=smith_lambda,
        smith_g1=smith_g1,
        visible_ggx_at=visible_ggx_at,
        visible_ggx=visible_ggx,
        beckmann_frame=beckmann_frame,
        gaussian_pair=gaussian_pair,
        slope_proposal_pos=slope_proposal_pos,
        slope_proposal_neg=slope_proposal_neg,
        beckmann_normal=beckmann_normal,
        cosine_about=cosine_about,
        height_step=height_step,
        next_event=next_event,
    )


def _identity(f: Callable) -> Callable:
    return f


@functools.cache
def numpy_formulas() -> SimpleNamespace:
    """The formulas on NumPy arrays: NumPy and SciPy ufuncs, ``np.where``, no compilation."""
    import numpy as np
    from scipy.special import erf, erfc, erfinv

    return build(
        SimpleNamespace(
            jit=_identity,
            where=np.where,
            maximum=np.maximum,
            minimum=np.minimum,
            sqrt=np.sqrt,
            exp=np.exp,
            log1p=np.log1p,
            sin=np.sin,
            cos=np.cos,
            erf=erf,
            erfinv=erfinv,
            erfc=erfc,
            isfinite=np.isfinite,
        )
    )
