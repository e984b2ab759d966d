"""Other renderers' diffuse BRDFs, each named after its source and citing its file and function.

Where a renderer computes a formula roughdiffuse already has, the variant is an
:class:`~roughdiffuse.models.alias.Alias`: the other project's parameter names and the
conversion, declared once. Three formulas are new, and have a kernel of their own:

* Blender Cycles' Diffuse BSDF (and the Principled BSDF's diffuse roughness): Fujii's single
  scattering plus ρ times EON's multiple-scattering lobe (``bsdf_oren_nayar_setup`` folds ρ²
  into the lobe, and the closure weight is the base colour again: ρ³ where EON has ρ²);
* MaterialX's ``oren_nayar_diffuse_bsdf`` with ``energy_compensation``: EON after the node
  clamps N·L, N·V and L·V to [1e-8, 1] (L·V < 0, light and view on opposite sides, becomes 0);
* OSL's BSDL ``oren_nayar_diffuse_bsdf`` (testrender) with ``energy_compensation``: EON with
  floors of 1e-7 and no L·V clamp.

Where an engine ships several diffuse BRDFs, the variant of what it renders by default is
:data:`ENGINE_DEFAULTS`'s; the others are opt-in there, and their pages say so.

The transcriptions of each source are in ``tests/test_implementations.py``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

from .._array import Array, clip, maximum
from .alias import alias
from .base import Model, register_pytree
from .burley import Burley
from .chan import Chan
from .declaration import Param
from .eon import EON, eon_albedo, multiple_scattering
from .fujii import K1, K2, fon_albedo, fon_lobe
from .hammon import Hammon
from .lambert import Lambert
from .oren_nayar import SIGMA_MAX, OrenNayar

__all__ = [
    "ENGINES",
    "ENGINE_DEFAULTS",
    "engine_variant",
    "CyclesDiffuse",
    "FilamentBurley",
    "FilamentLambert",
    "MaterialXEON",
    "MaterialXEONGenOSL",
    "MaterialXOrenNayar",
    "Mitsuba06RoughDiffuse",
    "OpenPBRDiffuse",
    "OSLEON",
    "Pbrt3OrenNayar",
    "UnityDiffuseGGX",
    "UnityDisneyDiffuse",
    "UnrealBurley",
    "UnrealChan",
]

MX_EPS = 1e-8
"""MaterialX's M_FLOAT_EPS, the lower clamp of N·L, N·V and L·V in the node."""

BSDL_EPS = 1e-7
"""The floor of 1 − E and 1 − Ē in OSL's BSDL ``OrenNayarDiffuseLobe::eval_impl``."""

UNITY_DISNEY_NORM = 1.03571
"""HDRP's ``DisneyDiffuseNoPI`` divides by this (its albedo at normal view, ρ = r = 1)."""

ENGINES: dict[str, tuple[str, ...]] = {
    "blender": ("cycles-diffuse", "cycles-principled", "cycles-osl"),
    "cycles": ("cycles-diffuse", "cycles-principled", "cycles-osl"),
    "filament": ("filament-lambert", "filament-burley"),
    "materialx": ("materialx-oren-nayar", "materialx-eon", "materialx-eon-genosl"),
    "mitsuba06": ("mitsuba06-roughdiffuse", "mitsuba06-roughdiffuse-fast"),
    "openpbr": ("openpbr-diffuse",),
    "osl": ("materialx-oren-nayar", "osl-eon"),
    "pbrt3": ("pbrt3-oren-nayar",),
    "unity": ("unity-disney-diffuse", "unity-diffuse-ggx"),
}
"""Each engine's variants, its shipped default first, then those it offers as opt-in:
Filament's ``BRDF_DIFFUSE`` is ``DIFFUSE_LAMBERT`` (``Fd_Burley`` compiled out); HDRP's Lit
calls ``DisneyDiffuse`` (``DiffuseGGX`` opt-in); MaterialX's ``oren_nayar_diffuse_bsdf`` and
OSL's closure default to ``energy_compensation`` off, the qualitative model (EON is the
switch turned on); Cycles' Diffuse BSDF, Principled BSDF and OSL closure build one closure
(``cycles-diffuse``). Unreal is not listed: its shaders were not read here, so
``unreal-burley`` and ``unreal-chan`` are named by id."""

ENGINE_DEFAULTS: dict[str, str] = {name: ids[0] for name, ids in ENGINES.items()}
"""The variant ``convert --to ENGINE`` picks: the engine's shipped default."""


def engine_variant(name: str) -> str:
    """The registry id ``name`` stands for: an engine's default variant
    (:data:`ENGINE_DEFAULTS`, case-insensitive), or ``name`` itself (an id, opt-in included).

    >>> engine_variant("Unity"), engine_variant("unity-diffuse-ggx")
    ('unity-disney-diffuse', 'unity-diffuse-ggx')
    """
    return ENGINE_DEFAULTS.get(name.strip().lower(), name)

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
    "Diffuse Roughness" builds the same closure (``cycles-principled``), and so does Cycles' OSL
    closure ``oren_nayar_diffuse_bsdf(N, albedo, roughness)`` (``cycles-osl``:
    ``osl/closures_setup.h``, ``osl_closure_oren_nayar_diffuse_bsdf_setup``, weight × albedo):
    it has no ``energy_compensation`` switch and always adds the ρ³ lobe, so a MaterialX
    document through genosl renders this in Cycles, with or without the switch.

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
            "Blender node: Diffuse BSDF, Principled BSDF, or the OSL closure (same closure)",
            choices=("diffuse", "principled", "osl"),
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
        "cycles-osl": {"node": "osl"},
    }
    labels: ClassVar[dict[str, str]] = {
        "cycles-diffuse": "Blender Cycles Diffuse BSDF",
        "cycles-principled": "Blender Cycles Principled diffuse roughness",
        "cycles-osl": "Blender Cycles OSL oren_nayar_diffuse_bsdf closure",
    }
    reference: ClassVar[str] = (
        "Blender Cycles, intern/cycles/kernel/closure/bsdf_oren_nayar.h, bsdf_oren_nayar_setup "
        "and bsdf_oren_nayar_get_intensity (closure weight: svm/closure.h; OSL: "
        "osl/closures_setup.h, osl_closure_oren_nayar_diffuse_bsdf_setup)"
    )
    order: ClassVar[int] = _ORDER

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
    eps: ClassVar[float] = MX_EPS  # the floors of 1 − E and 1 − Ē

    def _kernel(
        self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, albedo: Array, roughness: Array
    ) -> Array:
        nl, nv, lv = self._cosines(xp, mu_i, mu_o, cos_io)
        return eon_floored(xp, nl, nv, lv, albedo, roughness, self.eps)

    @staticmethod
    def _cosines(xp: Any, mu_i: Array, mu_o: Array, cos_io: Array) -> tuple[Array, ...]:
        """N·L, N·V and L·V clamped as the node clamps them, to [1e-8, 1]."""
        return tuple(clip(xp, x, MX_EPS, 1.0) for x in (mu_i, mu_o, cos_io))


def eon_floored(
    xp: Any, nl: Array, nv: Array, lv: Array, albedo: Array, r: Array, eps: float
) -> Array:
    """EON as shading languages write it (EON paper Eq. 11–13): 1 − E_F(μ) and 1 − Ē_F
    floored at ``eps``, so that r = 0 adds ρ² eps/π (MaterialX 1e-8, BSDL 1e-7)."""
    single = albedo * fon_lobe(xp, nl, nv, lv, r)
    avg = (1.0 + K2 * r) / (1.0 + K1 * r)
    one_minus_avg = 1.0 - avg
    rho_ms = albedo * albedo * avg / (1.0 - albedo * maximum(xp, one_minus_avg, 0.0))
    multi = (
        rho_ms
        * maximum(xp, 1.0 - fon_albedo(xp, nv, r), eps)
        * maximum(xp, 1.0 - fon_albedo(xp, nl, r), eps)
        / maximum(xp, one_minus_avg, eps)
    )
    return (single + multi) / math.pi


@register_pytree
@dataclass(frozen=True)
class OSLEON(MaterialXEON):
    """OSL's ``oren_nayar_diffuse_bsdf`` closure with ``energy_compensation = 1``, as BSDL
    (testrender) evaluates it: EON with no L·V clamp.

    ``src/libbsdl/include/BSDL/MTX/bsdf_oren_nayar_diffuse_impl.h``,
    ``OrenNayarDiffuseLobe::eval_impl`` (in OSL since PR 1817, 2024): N·L and N·V clamped to
    [0, 1], L·V to [−1, 1] (so EON's negative s is kept), 1 − E and 1 − Ē floored at 1e-7.
    The closure's weight is ρ f_ss + ρ_ms f_ms per π, as EON's. (MaterialX's GLSL node's
    formula with other clamps and floors: hence the subclass.)
    """

    params: ClassVar[tuple[Param, ...]] = (
        _colour("albedo ρ"),
        _unit("roughness", "roughness r (EON's, not an angle)"),
    )
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f = f_{\mathrm{EON}}(\rho, r),\quad 1 - E_F,\ 1 - \bar E_F \ \text{floored at}\ 10^{-7}
        ```

        EON (the `eon` page) as OSL's BSDL writes it: no L·V clamp (unlike MaterialX's GLSL
        node, `materialx-eon`); the floors add ρ² 10⁻⁷/π at r = 0.
        """
    ids: ClassVar[dict[str, dict[str, Any]]] = {"osl-eon": {}}
    labels: ClassVar[dict[str, str]] = {
        "osl-eon": "OSL testrender oren_nayar_diffuse_bsdf (energy_compensation)"
    }
    reference: ClassVar[str] = (
        "OpenShadingLanguage, src/libbsdl/include/BSDL/MTX/bsdf_oren_nayar_diffuse_impl.h, "
        "OrenNayarDiffuseLobe::eval_impl and E_FON_analytic"
    )
    order: ClassVar[int] = _ORDER + 15
    eps: ClassVar[float] = BSDL_EPS

    @staticmethod
    def _cosines(xp: Any, mu_i: Array, mu_o: Array, cos_io: Array) -> tuple[Array, ...]:
        """N·L and N·V clamped to [0, 1], L·V to [−1, 1] (BSDL's ``CLAMP``)."""
        return clip(xp, mu_i, 0.0, 1.0), clip(xp, mu_o, 0.0, 1.0), clip(xp, cos_io, -1.0, 1.0)


# ----------------------------------------------------------------------------- aliases
ALPHA_MAX = SIGMA_MAX * math.sqrt(2.0)


# ----------------------------------------------------------------------------- the table
# The variants that are another model after a change of parameters, one row each: class
# name, id and label (the renderer), the base model (and the categorical values it fixes),
# the renderer's parameters, the conversion and its rule, the source (file, function), the
# formula the model page shows, and the class docstring.
_M = __name__

Mitsuba06RoughDiffuse = alias(
    "Mitsuba06RoughDiffuse", _M,
    ids={"mitsuba06-roughdiffuse": {"variant": "full"},
         "mitsuba06-roughdiffuse-fast": {"variant": "fast"}},
    labels={"mitsuba06-roughdiffuse": "Mitsuba 0.6 roughdiffuse",
            "mitsuba06-roughdiffuse-fast": "Mitsuba 0.6 roughdiffuse (useFastApprox)"},
    base=OrenNayar,
    base_choices={"variant": {"full": {"variant": "full"}, "fast": {"variant": "qualitative"}}},
    params=(_colour("reflectance ρ"),
            _unit("alpha", "alpha = √2 σ (Beckmann RMS slope)", 0.5, ALPHA_MAX),
            Param("variant", "full, or useFastApprox", choices=("full", "fast"), default="full")),
    to_base=lambda albedo, alpha: {"albedo": albedo, "sigma": alpha * (1.0 / math.sqrt(2.0))},
    rule="σ = α/√2", order=_ORDER + 40,
    reference="Mitsuba 0.6, src/bsdfs/roughdiffuse.cpp, RoughDiffuse::eval",
    symbols={"albedo": r"\rho", "alpha": r"\alpha"},
    formula=r"""
        ```{math}
        f = f_{\mathrm{ON}}\Bigl(\rho, \sigma = \frac{\alpha}{\sqrt{2}}\Bigr)
        ```

        Full Oren–Nayar (`oren-nayar-full`), or the qualitative model for the fast variant,
        with Mitsuba 0.6's α = √2 σ.
        """,
    doc="""Mitsuba 0.6 ``roughdiffuse``: Oren–Nayar with α, the Beckmann RMS slope, σ = α/√2;
    the full model by default, the qualitative one with ``useFastApprox``.""",
)  # fmt: skip


MaterialXOrenNayar = alias(
    "MaterialXOrenNayar", _M, model_id="materialx-oren-nayar",
    label="MaterialX oren_nayar_diffuse_bsdf", base=OrenNayar,
    base_fixed={"variant": "qualitative"},
    params=(_colour("color ρ"), _unit("roughness", "roughness = Oren–Nayar σ in radians")),
    to_base=lambda albedo, roughness: {"albedo": albedo, "sigma": roughness},
    rule="σ = roughness", order=_ORDER + 20,
    reference="MaterialX, libraries/pbrlib/genglsl/lib/mx_microfacet_diffuse.glsl, "
    "mx_oren_nayar_diffuse",
    formula=r"""
        ```{math}
        f = f_{\mathrm{ON}}(\rho, \sigma = r)
        ```

        The qualitative Oren–Nayar model (the `oren-nayar` page) with σ = roughness, in radians.
        """,
    doc="""MaterialX ``oren_nayar_diffuse_bsdf`` (``energy_compensation = false``): the
    qualitative Oren–Nayar model, ``roughness`` = σ in radians. Its L·V clamp changes
    nothing (the s/t term is cut at 0 anyway) except within 1e-8 of the horizon.""",
)

MaterialXEONGenOSL = alias(
    "MaterialXEONGenOSL", _M, model_id="materialx-eon-genosl",
    label="MaterialX oren_nayar_diffuse_bsdf (energy_compensation) through genosl",
    base=OrenNayar, base_fixed={"variant": "qualitative"},
    params=(_colour("color ρ"), _unit("roughness", "roughness (σ in radians once dropped)")),
    to_base=lambda albedo, roughness: {"albedo": albedo, "sigma": roughness},
    rule="σ = roughness", order=_ORDER + 12,
    reference="MaterialX, libraries/pbrlib/genosl/pbrlib_genosl_impl.mtlx, "
    "IM_oren_nayar_diffuse_bsdf_genosl (energy_compensation not passed); OSL BSDL, "
    "bsdf_oren_nayar_diffuse_impl.h, OrenNayarDiffuseLobe::eval_impl (its default branch)",
    formula=r"""
        ```{math}
        f = f_{\mathrm{ON}}(\rho, \sigma = r)
        ```

        What an EON node (`materialx-eon`) renders through MaterialX's OSL generator: the
        qualitative Oren–Nayar model (the `oren-nayar` page) with σ = roughness.
        """,
    doc="""MaterialX ``oren_nayar_diffuse_bsdf`` with ``energy_compensation = true`` as its OSL
    output renders it. ``pbrlib_genosl_impl.mtlx`` writes the node as
    ``oren_nayar_diffuse_bsdf(normal, color, roughness)`` and never passes
    ``energy_compensation``, so OSL's closure (BSDL, testrender) takes its default, 0: the
    qualitative Oren–Nayar model, σ = roughness (Cycles' OSL closure renders ``cycles-osl``
    instead).""",
)

OpenPBRDiffuse = alias(
    "OpenPBRDiffuse", _M, model_id="openpbr-diffuse", label="OpenPBR base_diffuse_roughness",
    base=EON, params=(_colour("base_color ρ"), _unit("roughness", "base_diffuse_roughness r")),
    to_base=lambda albedo, roughness: {"albedo": albedo, "roughness": roughness},
    rule="r = base_diffuse_roughness", order=_ORDER + 30,
    reference="J. Portsmouth, P. Kutz, S. Hill, EON: A practical energy-preserving rough "
    "diffuse BRDF, JCGT 2025 (arXiv 2410.18026), Eq. 11-13: OpenPBR 1.1's "
    "base_diffuse_roughness",
    formula=r"""
        ```{math}
        f = f_{\mathrm{EON}}(\rho, r)
        ```

        EON (the `eon` page), base_color ρ and base_diffuse_roughness r, as the EON paper
        writes it (the OpenPBR specification's copy of the compensation term has 1/π twice).
        """,
    doc="""OpenPBR 1.1's diffuse base (``base_color``, ``base_diffuse_roughness``): EON as
    the EON paper (Portsmouth, Kutz, Hill, JCGT 2025, Eq. 11-13) writes it. The citation is
    the paper, not the specification's section "Base: Diffuse": the specification's
    multiple-scattering term has a typo (1/π appears twice). (MaterialX's
    ``open_pbr_surface`` graph evaluates it through ``oren_nayar_diffuse_bsdf``:
    ``materialx-eon``, with the L·V clamp, in GLSL, ESSL and MSL; ``materialx-eon-genosl``
    through OSL.)""",
)

Pbrt3OrenNayar = alias(
    "Pbrt3OrenNayar", _M, model_id="pbrt3-oren-nayar", label="pbrt-v3 OrenNayar",
    base=OrenNayar, base_fixed={"variant": "qualitative"},
    params=(_colour("R ρ"), _unit("sigma_deg", "sigma, σ in degrees", 20.0, 90.0)),
    to_base=lambda albedo, sigma_deg: {"albedo": albedo, "sigma": sigma_deg * (math.pi / 180.0)},
    rule="σ = sigma · π/180", order=_ORDER + 50,
    reference="pbrt-v3, src/core/reflection.cpp, OrenNayar::f (and its constructor)",
    symbols={"albedo": r"\rho", "sigma_deg": r"\sigma_{\circ}"},
    formula=r"""
        ```{math}
        f = f_{\mathrm{ON}}\Bigl(\rho, \sigma = \frac{\pi}{180}\,\sigma_{\circ}\Bigr)
        ```

        The qualitative Oren–Nayar model (the `oren-nayar` page), σ given in degrees.
        """,
    doc="""pbrt-v3 ``OrenNayar``: the qualitative model with σ given in degrees.""",
)

UnrealBurley = alias(
    "UnrealBurley", _M, model_id="unreal-burley", label="Unreal Diffuse_Burley", base=Burley,
    params=(_colour("DiffuseColor ρ"), _unit("roughness", "Roughness")),
    to_base=lambda albedo, roughness: {"albedo": albedo, "roughness": roughness},
    rule="r = Roughness", order=_ORDER + 60,
    reference="Unreal Engine, Engine/Shaders/Private/BRDF.ush, Diffuse_Burley",
    formula=r"""
        ```{math}
        f = f_{\mathrm{Burley}}(\rho, r)
        ```

        Burley's diffuse (the `burley` page) at Unreal's Roughness r.
        """,
    doc="""Unreal Engine ``Diffuse_Burley``: Burley 2012 with the material's Roughness as it
    is.""",
)

FilamentLambert = alias(
    "FilamentLambert", _M, model_id="filament-lambert", label="Filament Fd_Lambert (default)",
    base=Lambert, params=(_colour("baseColor ρ (diffuse colour)"),),
    to_base=lambda albedo: {"albedo": albedo}, rule="ρ = diffuse colour",
    order=_ORDER + 65, symbols={"albedo": r"\rho"},
    reference="Filament, shaders/src/surface_brdf.fs (formerly brdf.fs), diffuse and "
    "Fd_Lambert (#define BRDF_DIFFUSE DIFFUSE_LAMBERT)",
    formula=r"""
        ```{math}
        f = \frac{\rho}{\pi}
        ```

        Lambert (the `lambert` page): what Filament renders, whatever the roughness.
        """,
    doc="""Filament's default diffuse: ``diffuse()`` returns ``Fd_Lambert()`` = 1/π, since
    ``BRDF_DIFFUSE`` is defined as ``DIFFUSE_LAMBERT``; roughness does not act on it.""",
)

FilamentBurley = alias(
    "FilamentBurley", _M, model_id="filament-burley", label="Filament Fd_Burley", base=Burley,
    params=(_colour("baseColor ρ"),
            _unit("roughness", "perceptual roughness (squared before Fd_Burley)")),
    to_base=lambda albedo, roughness: {"albedo": albedo, "roughness": roughness * roughness},
    rule="r = perceptual roughness²", order=_ORDER + 70,
    reference="Filament, shaders/src/surface_brdf.fs (formerly brdf.fs), Fd_Burley "
    "(roughness = perceptual²; compiled out: BRDF_DIFFUSE is DIFFUSE_LAMBERT)",
    formula=r"""
        ```{math}
        f = f_{\mathrm{Burley}}(\rho, r^2)
        ```

        Burley's diffuse (the `burley` page) at Filament's perceptual roughness squared.
        Compiled out in Filament, which renders Lambert (`filament-lambert`) by default.
        """,
    doc="""Filament ``Fd_Burley``: Burley 2012 called with α = perceptual roughness².
    Compiled out in Filament: its ``BRDF_DIFFUSE`` is ``DIFFUSE_LAMBERT``, so it renders
    ``filament-lambert`` unless the shader is rebuilt with ``DIFFUSE_BURLEY``.""",
)

UnrealChan = alias(
    "UnrealChan", _M, model_id="unreal-chan", label="Unreal Diffuse_Chan", base=Chan,
    params=(_colour("DiffuseColor ρ"),
            _unit("roughness", "Roughness (perceptual; α = Roughness²)")),
    to_base=lambda albedo, roughness: {"albedo": albedo, "alpha": roughness * roughness},
    rule="α = Roughness²", order=_ORDER + 80,
    reference="Unreal Engine 5, Engine/Shaders/Private/BRDF.ush, Diffuse_Chan",
    formula=r"""
        ```{math}
        f = f_{\mathrm{Chan}}(\rho, \alpha = r^2)
        ```

        Chan's diffuse (the `chan` page) at α = Roughness².
        """,
    doc="""Unreal Engine 5 ``Diffuse_Chan``: Chan's diffuse with a2 = Roughness⁴ (GGX α =
    Roughness²) and RetroReflectivityWeight 1.""",
)

UnityDiffuseGGX = alias(
    "UnityDiffuseGGX", _M, model_id="unity-diffuse-ggx", label="Unity DiffuseGGX (Hammon)",
    base=Hammon, params=(_colour("albedo ρ"),
                         _unit("roughness", "roughness = GGX α (perceptual roughness²)", 0.3)),
    to_base=lambda albedo, roughness: {"albedo": albedo, "alpha": roughness},
    rule="α = roughness", order=_ORDER + 90,
    reference="Unity Graphics, Packages/com.unity.render-pipelines.core/ShaderLibrary/"
    "BSDF.hlsl, DiffuseGGXNoPI and DiffuseGGX",
    formula=r"""
        ```{math}
        f = f_{\mathrm{Hammon}}(\rho, \alpha = r)
        ```

        Hammon's GGX diffuse (the `hammon` page) with Unity's roughness as the GGX α. Opt-in
        in Unity, whose HDRP Lit renders `unity-disney-diffuse`.
        """,
    doc="""Unity's ``DiffuseGGX`` (``DiffuseGGXNoPI``/π times the diffuse colour): Hammon's
    GGX diffuse with ``roughness`` = GGX α (perceptual roughness²). Opt-in in Unity: HDRP's Lit
    renders ``DisneyDiffuse`` (``unity-disney-diffuse``).""",
)

UnityDisneyDiffuse = alias(
    "UnityDisneyDiffuse", _M, model_id="unity-disney-diffuse",
    label="Unity HDRP DisneyDiffuse (Lit default)", base=Burley,
    params=(_colour("diffuseColor ρ"),
            _unit("roughness", "perceptualRoughness (as it is, not squared)")),
    to_base=lambda albedo, roughness: {
        "albedo": albedo * (1.0 / UNITY_DISNEY_NORM), "roughness": roughness},
    rule="ρ_Burley = diffuseColor/1.03571, r = perceptualRoughness", order=_ORDER + 85,
    reference="Unity Graphics, Packages/com.unity.render-pipelines.core/ShaderLibrary/"
    "BSDF.hlsl, DisneyDiffuseNoPI and DisneyDiffuse (called by HDRP Runtime/Material/Lit/"
    "Lit.hlsl, BSDF)",
    formula=r"""
        ```{math}
        f = \frac{1}{1.03571}\,f_{\mathrm{Burley}}(\rho, r)
        ```

        Burley's diffuse (the `burley` page) at HDRP's perceptual roughness r, scaled by
        1/1.03571; F_D90 = 0.5 + r (1 + ωi·ωo) is Burley's 0.5 + 2r cos² θd.
        """,
    doc="""Unity HDRP's default Lit diffuse: ``DisneyDiffuse`` = ``DisneyDiffuseNoPI``/π times
    the diffuse colour, i.e. Burley 2012 at the perceptual roughness (not squared), divided by
    1.03571 (the albedo at normal view for ρ = r = 1). ``DiffuseGGX`` (``unity-diffuse-ggx``)
    is opt-in.""",
)
