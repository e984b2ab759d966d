"""Other renderers' diffuse BRDFs, each named after its source and citing its file and function.

Where a renderer computes a formula roughdiffuse already has, the variant is an
:class:`~roughdiffuse.models.alias.Alias`: the other project's parameter names and the
conversion, declared once. Two formulas are new, and have a kernel of their own:

* Blender Cycles' Diffuse BSDF (and the Principled BSDF's diffuse roughness): Fujii's single
  scattering plus ρ times EON's multiple-scattering lobe (``bsdf_oren_nayar_setup`` folds ρ²
  into the lobe, and the closure weight is the base colour again: ρ³ where EON has ρ²);
* MaterialX's ``oren_nayar_diffuse_bsdf`` with ``energy_compensation``: EON after the node
  clamps N·L, N·V and L·V to [1e-8, 1] (L·V < 0, light and view on opposite sides, becomes 0).

The transcriptions of each source are in ``tests/test_implementations.py``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

from .._array import Array, clip, maximum
from .alias import Alias
from .base import Model, register_pytree
from .burley import Burley
from .chan import Chan
from .declaration import Param
from .eon import EON, eon_albedo, multiple_scattering
from .fujii import K1, K2, fon_albedo, fon_lobe
from .hammon import Hammon
from .oren_nayar import SIGMA_MAX, OrenNayar

__all__ = [
    "CyclesDiffuse",
    "FilamentBurley",
    "MaterialXEON",
    "MaterialXOrenNayar",
    "Mitsuba06RoughDiffuse",
    "OpenPBRDiffuse",
    "Pbrt3OrenNayar",
    "UnityDiffuseGGX",
    "UnrealBurley",
    "UnrealChan",
]

MX_EPS = 1e-8
"""MaterialX's M_FLOAT_EPS, the lower clamp of N·L, N·V and L·V in the node."""

_ORDER = 300  # after roughdiffuse's own models


def _colour(text: str = "base colour ρ") -> Param:
    return Param("albedo", text, min=0.0, max=1.0, default=1.0, channels=True, example=0.8)


def _unit(name: str, text: str, example: float = 0.5, hi: float = 1.0) -> Param:
    return Param(name, text, min=0.0, max=hi, default=0.0, example=example)


# ----------------------------------------------------------------------------- new formulas
@register_pytree
@dataclass(frozen=True)
class CyclesDiffuse(Model):
    """Blender Cycles' Diffuse BSDF: f = ρ/π A_F (1 + r s/t) + ρ · f_ms,EON(ρ, r).

    Cycles (``intern/cycles/kernel/closure/bsdf_oren_nayar.h``, ``bsdf_oren_nayar_setup`` and
    ``bsdf_oren_nayar_get_intensity``; weight from ``svm/closure.h``) computes Fujii's model
    plus EON's multiple-scattering lobe, and multiplies the whole closure by the base colour,
    so the lobe carries ρ³ where EON's carries ρ². At ρ = 1 it is EON. The Principled BSDF's
    "Diffuse Roughness" builds the same closure (``cycles-principled``).

    Examples
    --------
    >>> import numpy as np
    >>> wo = np.array([0.6, 0.0, 0.8])
    >>> round(float(CyclesDiffuse(1.0, 0.7).directional_albedo(wo)), 12)  # EON at ρ = 1
    1.0
    """

    albedo: float | Array = 1.0
    roughness: float | Array = 0.0
    node: str = "diffuse"

    params: ClassVar[tuple[Param, ...]] = (
        _colour("base colour ρ (Color)"),
        _unit("roughness", "Roughness r (Fujii's, not an angle)"),
        Param(
            "node",
            "Blender node: Diffuse BSDF or Principled BSDF (same closure)",
            choices=("diffuse", "principled"),
            default="diffuse",
        ),
    )
    symbols: ClassVar[dict[str, str]] = {"albedo": r"\rho", "roughness": r"r"}
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f = \frac{\rho}{\pi}\,A_F\Bigl(1 + r\,\frac{s}{t}\Bigr) + \rho\,f_{\mathrm{ms}}(\rho, r),
        \quad A_F = \frac{1}{1 + (\pi/2 - 2/3)\,r}
        ```

        s = ωi·ωo − μi μo, t = max(μi, μo) where s > 0 and 1 elsewhere (Fujii's model), and
        {math}`f_{\mathrm{ms}}` EON's multiple-scattering lobe (the `eon` page), so the lobe
        carries ρ³ where EON's carries ρ².
        """
    ids: ClassVar[dict[str, dict[str, Any]]] = {
        "cycles-diffuse": {"node": "diffuse"},
        "cycles-principled": {"node": "principled"},
    }
    labels: ClassVar[dict[str, str]] = {
        "cycles-diffuse": "Blender Cycles Diffuse BSDF",
        "cycles-principled": "Blender Cycles Principled diffuse roughness",
    }
    reference: ClassVar[str] = (
        "Blender Cycles, intern/cycles/kernel/closure/bsdf_oren_nayar.h, bsdf_oren_nayar_setup "
        "and bsdf_oren_nayar_get_intensity (closure weight: svm/closure.h)"
    )
    order: ClassVar[int] = _ORDER
    test_points: ClassVar[dict[str, tuple[dict[str, Any], ...]]] = {
        "cycles-diffuse": ({"roughness": 0.0}, {"roughness": 1.0, "albedo": 0.5})
    }

    def _kernel(
        self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, albedo: Array, roughness: Array
    ) -> Array:
        f_ss = albedo / math.pi * fon_lobe(xp, mu_i, mu_o, cos_io, roughness)
        return f_ss + albedo * multiple_scattering(xp, mu_i, mu_o, albedo, roughness)

    def directional_albedo(self, wo: Array) -> Array:
        """Closed form ρ E_F(μo) + ρ · ρ_ms (1 − E_F(μo)) (EON paper Eq. 14, lobe × ρ)."""
        return self._closed_form_albedo(
            wo, lambda xp, mu, albedo, roughness: eon_albedo(xp, mu, albedo, roughness, albedo)
        )


@register_pytree
@dataclass(frozen=True)
class MaterialXEON(Model):
    """MaterialX ``oren_nayar_diffuse_bsdf`` with ``energy_compensation = true``.

    ``libraries/pbrlib/genglsl/mx_oren_nayar_diffuse_bsdf.glsl`` clamps N·L, N·V and L·V to
    [1e-8, 1], then evaluates ``mx_oren_nayar_compensated_diffuse``
    (``lib/mx_microfacet_diffuse.glsl``): EON, with its own floors (1 − E at 1e-8, 1 − Ē at
    1e-8). Clamping L·V at 0 removes EON's negative s = L·V − μi μo where light and view
    lie on opposite sides: the white furnace reaches 1.15 at grazing.
    """

    albedo: float | Array = 1.0
    roughness: float | Array = 0.0

    params: ClassVar[tuple[Param, ...]] = (
        _colour("color ρ"),
        _unit("roughness", "roughness r (EON's, not an angle)"),
    )
    symbols: ClassVar[dict[str, str]] = {"albedo": r"\rho", "roughness": r"r"}
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f = f_{\mathrm{EON}}\bigl(\rho, r;\ \hat\mu_i, \hat\mu_o, \hat c\bigr),\quad
        c = \omega_i\cdot\omega_o,\ \hat x = \min\bigl(\max(x, 10^{-8}), 1\bigr)
        ```

        EON (the `eon` page) on the cosines clamped as MaterialX's node clamps them; the L·V
        clamp changes every value with ωi·ωo < 0.
        """
    ids: ClassVar[dict[str, dict[str, Any]]] = {"materialx-eon": {}}
    labels: ClassVar[dict[str, str]] = {
        "materialx-eon": "MaterialX oren_nayar_diffuse_bsdf (energy_compensation)"
    }
    reference: ClassVar[str] = (
        "MaterialX, libraries/pbrlib/genglsl/mx_oren_nayar_diffuse_bsdf.glsl, "
        "mx_oren_nayar_diffuse_bsdf; lib/mx_microfacet_diffuse.glsl, "
        "mx_oren_nayar_compensated_diffuse"
    )
    order: ClassVar[int] = _ORDER + 10
    test_points: ClassVar[dict[str, tuple[dict[str, Any], ...]]] = {
        "materialx-eon": ({"roughness": 0.0}, {"roughness": 1.0})
    }

    def _kernel(
        self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, albedo: Array, roughness: Array
    ) -> Array:
        nl, nv, lv = (clip(xp, x, MX_EPS, 1.0) for x in (mu_i, mu_o, cos_io))
        r = roughness
        single = albedo * fon_lobe(xp, nl, nv, lv, r)
        avg = (1.0 + K2 * r) / (1.0 + K1 * r)
        one_minus_avg = 1.0 - avg
        rho_ms = albedo * albedo * avg / (1.0 - albedo * maximum(xp, one_minus_avg, 0.0))
        multi = (
            rho_ms
            * maximum(xp, 1.0 - fon_albedo(xp, nv, r), MX_EPS)
            * maximum(xp, 1.0 - fon_albedo(xp, nl, r), MX_EPS)
            / maximum(xp, one_minus_avg, MX_EPS)
        )
        return (single + multi) / math.pi


# ----------------------------------------------------------------------------- aliases
@register_pytree
@dataclass(frozen=True)
class MaterialXOrenNayar(Alias):
    """MaterialX ``oren_nayar_diffuse_bsdf`` (``energy_compensation = false``): the
    qualitative Oren–Nayar model, ``roughness`` = σ in radians. Its L·V clamp changes
    nothing (the s/t term is cut at 0 anyway) except within 1e-8 of the horizon."""

    albedo: float | Array = 1.0
    roughness: float | Array = 0.0

    params: ClassVar[tuple[Param, ...]] = (
        _colour("color ρ"),
        _unit("roughness", "roughness = Oren–Nayar σ in radians"),
    )
    symbols: ClassVar[dict[str, str]] = {"albedo": r"\rho", "roughness": r"r"}
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f = f_{\mathrm{ON}}(\rho, \sigma = r)
        ```

        The qualitative Oren–Nayar model (the `oren-nayar` page) with σ = roughness, in radians.
        """
    ids: ClassVar[dict[str, dict[str, Any]]] = {"materialx-oren-nayar": {}}
    labels: ClassVar[dict[str, str]] = {"materialx-oren-nayar": "MaterialX oren_nayar_diffuse_bsdf"}
    reference: ClassVar[str] = (
        "MaterialX, libraries/pbrlib/genglsl/lib/mx_microfacet_diffuse.glsl, mx_oren_nayar_diffuse"
    )
    order: ClassVar[int] = _ORDER + 20
    base: ClassVar[type[Model]] = OrenNayar
    base_fixed: ClassVar[dict[str, Any]] = {"variant": "qualitative"}

    @staticmethod
    def to_base(albedo: Any, roughness: Any) -> dict[str, Any]:
        """σ = roughness."""
        return {"albedo": albedo, "sigma": roughness}


@register_pytree
@dataclass(frozen=True)
class OpenPBRDiffuse(Alias):
    """OpenPBR 1.1's diffuse base (``base_color``, ``base_diffuse_roughness``): EON as the
    specification writes it. (MaterialX's ``open_pbr_surface`` graph evaluates it through
    ``oren_nayar_diffuse_bsdf``: ``materialx-eon``, with the L·V clamp.)"""

    albedo: float | Array = 1.0
    roughness: float | Array = 0.0

    params: ClassVar[tuple[Param, ...]] = (
        _colour("base_color ρ"),
        _unit("roughness", "base_diffuse_roughness r"),
    )
    symbols: ClassVar[dict[str, str]] = {"albedo": r"\rho", "roughness": r"r"}
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f = f_{\mathrm{EON}}(\rho, r)
        ```

        EON (the `eon` page), base_color ρ and base_diffuse_roughness r.
        """
    ids: ClassVar[dict[str, dict[str, Any]]] = {"openpbr-diffuse": {}}
    labels: ClassVar[dict[str, str]] = {"openpbr-diffuse": "OpenPBR base_diffuse_roughness"}
    reference: ClassVar[str] = (
        "OpenPBR Surface 1.1 specification, section 'Base: Diffuse' (base_diffuse_roughness, EON)"
    )
    order: ClassVar[int] = _ORDER + 30
    base: ClassVar[type[Model]] = EON

    @staticmethod
    def to_base(albedo: Any, roughness: Any) -> dict[str, Any]:
        """r = base_diffuse_roughness."""
        return {"albedo": albedo, "roughness": roughness}


ALPHA_MAX = SIGMA_MAX * math.sqrt(2.0)


@register_pytree
@dataclass(frozen=True)
class Mitsuba06RoughDiffuse(Alias):
    """Mitsuba 0.6 ``roughdiffuse``: Oren–Nayar with α, the Beckmann RMS slope, σ = α/√2;
    the full model by default, the qualitative one with ``useFastApprox``."""

    albedo: float | Array = 1.0
    alpha: float | Array = 0.0
    variant: str = "full"

    params: ClassVar[tuple[Param, ...]] = (
        _colour("reflectance ρ"),
        _unit("alpha", "alpha = √2 σ (Beckmann RMS slope)", 0.5, ALPHA_MAX),
        Param("variant", "full, or useFastApprox", choices=("full", "fast"), default="full"),
    )
    symbols: ClassVar[dict[str, str]] = {"albedo": r"\rho", "alpha": r"\alpha"}
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f = f_{\mathrm{ON}}\Bigl(\rho, \sigma = \frac{\alpha}{\sqrt{2}}\Bigr)
        ```

        Full Oren–Nayar (`oren-nayar-full`), or the qualitative model for the fast variant,
        with Mitsuba 0.6's α = √2 σ.
        """
    ids: ClassVar[dict[str, dict[str, Any]]] = {
        "mitsuba06-roughdiffuse": {"variant": "full"},
        "mitsuba06-roughdiffuse-fast": {"variant": "fast"},
    }
    labels: ClassVar[dict[str, str]] = {
        "mitsuba06-roughdiffuse": "Mitsuba 0.6 roughdiffuse",
        "mitsuba06-roughdiffuse-fast": "Mitsuba 0.6 roughdiffuse (useFastApprox)",
    }
    reference: ClassVar[str] = "Mitsuba 0.6, src/bsdfs/roughdiffuse.cpp, RoughDiffuse::eval"
    order: ClassVar[int] = _ORDER + 40
    base: ClassVar[type[Model]] = OrenNayar

    def base_model(self) -> Model:
        """``OrenNayar(ρ, α/√2, "full" or "qualitative")``."""
        return OrenNayar(variant=self._base_variant(), **self.to_base(self.albedo, self.alpha))

    def _base_variant(self) -> str:
        return "full" if self.variant == "full" else "qualitative"

    def _kernel(self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, **p: Array) -> Array:
        shape = OrenNayar(variant=self._base_variant())
        return shape._kernel(xp, mu_i, mu_o, cos_io, **self.to_base(**p))

    @staticmethod
    def to_base(albedo: Any, alpha: Any) -> dict[str, Any]:
        """σ = α/√2."""
        return {"albedo": albedo, "sigma": alpha * (1.0 / math.sqrt(2.0))}


@register_pytree
@dataclass(frozen=True)
class Pbrt3OrenNayar(Alias):
    """pbrt-v3 ``OrenNayar``: the qualitative model with σ given in degrees."""

    albedo: float | Array = 1.0
    sigma_deg: float | Array = 0.0

    params: ClassVar[tuple[Param, ...]] = (
        _colour("R ρ"),
        _unit("sigma_deg", "sigma, σ in degrees", 20.0, 90.0),
    )
    symbols: ClassVar[dict[str, str]] = {"albedo": r"\rho", "sigma_deg": r"\sigma_{\circ}"}
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f = f_{\mathrm{ON}}\Bigl(\rho, \sigma = \frac{\pi}{180}\,\sigma_{\circ}\Bigr)
        ```

        The qualitative Oren–Nayar model (the `oren-nayar` page), σ given in degrees.
        """
    ids: ClassVar[dict[str, dict[str, Any]]] = {"pbrt3-oren-nayar": {}}
    labels: ClassVar[dict[str, str]] = {"pbrt3-oren-nayar": "pbrt-v3 OrenNayar"}
    reference: ClassVar[str] = (
        "pbrt-v3, src/core/reflection.cpp, OrenNayar::f (and its constructor)"
    )
    order: ClassVar[int] = _ORDER + 50
    base: ClassVar[type[Model]] = OrenNayar
    base_fixed: ClassVar[dict[str, Any]] = {"variant": "qualitative"}

    @staticmethod
    def to_base(albedo: Any, sigma_deg: Any) -> dict[str, Any]:
        """σ = sigma · π/180."""
        return {"albedo": albedo, "sigma": sigma_deg * (math.pi / 180.0)}


@register_pytree
@dataclass(frozen=True)
class UnrealBurley(Alias):
    """Unreal Engine ``Diffuse_Burley``: Burley 2012 with the material's Roughness as it is."""

    albedo: float | Array = 1.0
    roughness: float | Array = 0.0

    params: ClassVar[tuple[Param, ...]] = (
        _colour("DiffuseColor ρ"),
        _unit("roughness", "Roughness"),
    )
    symbols: ClassVar[dict[str, str]] = {"albedo": r"\rho", "roughness": r"r"}
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f = f_{\mathrm{Burley}}(\rho, r)
        ```

        Burley's diffuse (the `burley` page) at Unreal's Roughness r.
        """
    ids: ClassVar[dict[str, dict[str, Any]]] = {"unreal-burley": {}}
    labels: ClassVar[dict[str, str]] = {"unreal-burley": "Unreal Diffuse_Burley"}
    reference: ClassVar[str] = "Unreal Engine, Engine/Shaders/Private/BRDF.ush, Diffuse_Burley"
    order: ClassVar[int] = _ORDER + 60
    base: ClassVar[type[Model]] = Burley

    @staticmethod
    def to_base(albedo: Any, roughness: Any) -> dict[str, Any]:
        """r = Roughness."""
        return {"albedo": albedo, "roughness": roughness}


@register_pytree
@dataclass(frozen=True)
class FilamentBurley(Alias):
    """Filament ``Fd_Burley``: Burley 2012 called with α = perceptual roughness²."""

    albedo: float | Array = 1.0
    roughness: float | Array = 0.0

    params: ClassVar[tuple[Param, ...]] = (
        _colour("baseColor ρ"),
        _unit("roughness", "perceptual roughness (squared before Fd_Burley)"),
    )
    symbols: ClassVar[dict[str, str]] = {"albedo": r"\rho", "roughness": r"r"}
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f = f_{\mathrm{Burley}}(\rho, r^2)
        ```

        Burley's diffuse (the `burley` page) at Filament's perceptual roughness squared.
        """
    ids: ClassVar[dict[str, dict[str, Any]]] = {"filament-burley": {}}
    labels: ClassVar[dict[str, str]] = {"filament-burley": "Filament Fd_Burley"}
    reference: ClassVar[str] = "Filament, shaders/src/brdf.fs, Fd_Burley (roughness = perceptual²)"
    order: ClassVar[int] = _ORDER + 70
    base: ClassVar[type[Model]] = Burley

    @staticmethod
    def to_base(albedo: Any, roughness: Any) -> dict[str, Any]:
        """r = perceptual roughness²."""
        return {"albedo": albedo, "roughness": roughness * roughness}


@register_pytree
@dataclass(frozen=True)
class UnrealChan(Alias):
    """Unreal Engine 5 ``Diffuse_Chan``: Chan's diffuse with a2 = Roughness⁴ (GGX α =
    Roughness²) and RetroReflectivityWeight 1."""

    albedo: float | Array = 1.0
    roughness: float | Array = 0.0

    params: ClassVar[tuple[Param, ...]] = (
        _colour("DiffuseColor ρ"),
        _unit("roughness", "Roughness (perceptual; α = Roughness²)"),
    )
    symbols: ClassVar[dict[str, str]] = {"albedo": r"\rho", "roughness": r"r"}
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f = f_{\mathrm{Chan}}(\rho, \alpha = r^2)
        ```

        Chan's diffuse (the `chan` page) at α = Roughness².
        """
    ids: ClassVar[dict[str, dict[str, Any]]] = {"unreal-chan": {}}
    labels: ClassVar[dict[str, str]] = {"unreal-chan": "Unreal Diffuse_Chan"}
    reference: ClassVar[str] = "Unreal Engine 5, Engine/Shaders/Private/BRDF.ush, Diffuse_Chan"
    order: ClassVar[int] = _ORDER + 80
    base: ClassVar[type[Model]] = Chan

    @staticmethod
    def to_base(albedo: Any, roughness: Any) -> dict[str, Any]:
        """α = Roughness²."""
        return {"albedo": albedo, "alpha": roughness * roughness}


@register_pytree
@dataclass(frozen=True)
class UnityDiffuseGGX(Alias):
    """Unity's ``DiffuseGGX`` (``DiffuseGGXNoPI``/π times the diffuse colour): Hammon's
    GGX diffuse with ``roughness`` = GGX α (HDRP passes perceptual roughness²)."""

    albedo: float | Array = 1.0
    roughness: float | Array = 0.0

    params: ClassVar[tuple[Param, ...]] = (
        _colour("albedo ρ"),
        _unit("roughness", "roughness = GGX α (perceptual roughness²)", 0.3),
    )
    symbols: ClassVar[dict[str, str]] = {"albedo": r"\rho", "roughness": r"r"}
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f = f_{\mathrm{Hammon}}(\rho, \alpha = r)
        ```

        Hammon's GGX diffuse (the `hammon` page) with Unity's roughness as the GGX α.
        """
    ids: ClassVar[dict[str, dict[str, Any]]] = {"unity-diffuse-ggx": {}}
    labels: ClassVar[dict[str, str]] = {"unity-diffuse-ggx": "Unity DiffuseGGX (Hammon)"}
    reference: ClassVar[str] = (
        "Unity Graphics, Packages/com.unity.render-pipelines.core/ShaderLibrary/BSDF.hlsl, "
        "DiffuseGGXNoPI and DiffuseGGX"
    )
    order: ClassVar[int] = _ORDER + 90
    base: ClassVar[type[Model]] = Hammon

    @staticmethod
    def to_base(albedo: Any, roughness: Any) -> dict[str, Any]:
        """α = roughness."""
        return {"albedo": albedo, "alpha": roughness}
