"""roughdiffuse's models as Mitsuba 3 BSDF plugins.

>>> import mitsuba as mi                                              # doctest: +SKIP
>>> mi.set_variant("llvm_ad_rgb")                                     # doctest: +SKIP
>>> from roughdiffuse.integrations import mitsuba as rdmi            # doctest: +SKIP
>>> rdmi.register()                                                   # doctest: +SKIP
>>> bsdf = mi.load_dict({"type": "roughdiffuse_oren_nayar", "sigma": 0.3,
...                      "albedo": {"type": "rgb", "value": [0.8, 0.6, 0.4]}})  # doctest: +SKIP

Plugins (parameters named as in roughdiffuse; σ in radians):

=================================  ==============================================
``roughdiffuse_lambert``           albedo
``roughdiffuse_oren_nayar``        albedo, sigma, variant ("qualitative" | "full")
``roughdiffuse_fujii``             albedo, roughness
``roughdiffuse_eon``               albedo, roughness
``roughdiffuse_torrance_sparrow``  eta, distribution ("gaussian" | "beckmann"), sigma
                                   (Gaussian) or alpha (Beckmann; sigma there: α = √2 σ)
=================================  ==============================================

``albedo`` is a texture (a float, ``{"type": "rgb", ...}``, a bitmap...). The formulas are
not copied here: ``eval`` calls the model's own ``_kernel`` and ``sample``/``pdf`` the
strategy of :mod:`roughdiffuse.models.sampling`, through the Dr.Jit array namespace of
:mod:`.drjit_namespace`. Mitsuba's conventions: ``si.wi`` points to the viewer (roughdiffuse's
``wo``), the ``wo`` argument to the light (roughdiffuse's ``wi``); ``eval`` includes the
cosine of the light direction; the BSDF is one-sided (0 and pdf 0 below the horizon).

Scalar parameters are ``mi.Float`` values listed by ``mi.traverse`` as differentiable; in
the ``llvm_ad_*``/``cuda_ad_*`` variants they can be changed in place and differentiated.
In ``scalar_*`` variants they are plain floats: load a new BSDF to change them.

The ``llvm`` variants need libLLVM 15 or newer (Debian: ``apt-get install libllvm19``, then
``export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1``).
"""

from __future__ import annotations

import dataclasses
from typing import Any

from ..models import EON, Fujii, Lambert, Model, OrenNayar, TorranceSparrow
from ..models.sampling import strategy_for

__all__ = ["PLUGINS", "register"]

PLUGINS: dict[str, type[Model]] = {
    "roughdiffuse_lambert": Lambert,
    "roughdiffuse_oren_nayar": OrenNayar,
    "roughdiffuse_fujii": Fujii,
    "roughdiffuse_eon": EON,
    "roughdiffuse_torrance_sparrow": TorranceSparrow,
}
"""Plugin name -> model class."""

_STRING_FIELDS = ("variant", "distribution")


def _defaults(cls: type[Model]) -> dict[str, Any]:
    return {f.name: f.default for f in dataclasses.fields(cls)}  # type: ignore[arg-type]


def _make_plugin_class(mi: Any, dr: Any, model_cls: type[Model]) -> type:
    """A Mitsuba ``BSDF`` subclass for ``model_cls`` (for the variant set now)."""
    from .drjit_namespace import drjit_namespace as xp
    from .drjit_namespace import unwrap, wrap

    defaults = _defaults(model_cls)
    scalar_fields = [f for f in model_cls.array_fields if f != "albedo"]
    has_albedo = "albedo" in model_cls.array_fields
    glossy = model_cls is TorranceSparrow
    lobe = mi.BSDFFlags.GlossyReflection if glossy else mi.BSDFFlags.DiffuseReflection

    class RoughdiffuseBSDF(mi.BSDF):
        def __init__(self, props: Any) -> None:
            mi.BSDF.__init__(self, props)
            kwargs: dict[str, Any] = {}
            for name in scalar_fields:  # a parameter left unset keeps the class's default
                if name in props:
                    kwargs[name] = float(props[name])
            for name in _STRING_FIELDS:
                if name in defaults:
                    kwargs[name] = str(props.get(name, defaults[name]))
            # validates the parameters (ValueError naming the parameter and its range)
            self.model = model_cls(**kwargs)
            self.strategy = strategy_for(self.model)
            # the parameters this instance has (Torrance-Sparrow: sigma or alpha)
            self.scalar_fields = [n for n in scalar_fields if getattr(self.model, n) is not None]
            for name in self.scalar_fields:
                setattr(self, name, mi.Float(float(getattr(self.model, name))))
            if has_albedo:
                self.albedo = props.get_texture("albedo", float(defaults["albedo"]))
            self.m_flags = lobe | mi.BSDFFlags.FrontSide
            self.m_components = [self.m_flags]

        # -------------------------------------------------------------- the model
        def _params(self, si: Any, active: Any) -> dict[str, Any]:
            p = {name: wrap(getattr(self, name)) for name in self.scalar_fields}
            if has_albedo:
                p["albedo"] = wrap(self.albedo.eval(si, active))
            return p

        def _brdf(self, si: Any, wi: Any, active: Any) -> Any:
            """f(wi = light, wo = si.wi) as a Color3f (roughdiffuse's direction names)."""
            mu_i = dr.clip(wi.z, 0.0, 1.0)
            mu_o = dr.clip(si.wi.z, 0.0, 1.0)
            cos_io = dr.clip(dr.dot(wi, si.wi), -1.0, 1.0)
            f = self.model._kernel(
                xp, wrap(mu_i), wrap(mu_o), wrap(cos_io), **self._params(si, active)
            )
            return mi.Color3f(unwrap(f))

        def _pdf(self, si: Any, wi: Any) -> Any:
            p = {name: wrap(getattr(self, name)) for name in self.scalar_fields}
            d = si.wi
            pdf = self.strategy.pdf(
                xp, wrap(wi.x), wrap(wi.y), wrap(wi.z), wrap(d.x), wrap(d.y), wrap(d.z), p
            )
            return unwrap(pdf)

        # -------------------------------------------------------------- Mitsuba API
        def sample(self, ctx: Any, si: Any, sample1: Any, sample2: Any, active: Any = True):
            p = {name: wrap(getattr(self, name)) for name in self.scalar_fields}
            d = si.wi
            x, y, z, pdf = self.strategy.sample(
                xp, wrap(sample2.x), wrap(sample2.y), wrap(d.x), wrap(d.y), wrap(d.z), p
            )
            wi = mi.Vector3f(unwrap(x), unwrap(y), unwrap(z))
            pdf = unwrap(pdf)
            active = active & (d.z > 0) & (wi.z > 0) & (pdf > 0)
            active = active & ctx.is_enabled(lobe)
            bs = dr.zeros(mi.BSDFSample3f)
            bs.wo = wi
            bs.pdf = dr.select(active, pdf, 0.0)
            bs.eta = 1.0
            bs.sampled_type = mi.UInt32(+lobe)
            bs.sampled_component = mi.UInt32(0)
            value = self._brdf(si, wi, active) * (wi.z / dr.select(active, pdf, 1.0))
            return bs, dr.select(active, value, 0.0)

        def eval(self, ctx: Any, si: Any, wo: Any, active: Any = True):
            active = active & (si.wi.z > 0) & (wo.z > 0) & ctx.is_enabled(lobe)
            value = self._brdf(si, wo, active) * dr.clip(wo.z, 0.0, 1.0)
            return dr.select(active, value, 0.0)

        def pdf(self, ctx: Any, si: Any, wo: Any, active: Any = True):
            active = active & (si.wi.z > 0) & (wo.z > 0) & ctx.is_enabled(lobe)
            return dr.select(active, self._pdf(si, wo), 0.0)

        def eval_pdf(self, ctx: Any, si: Any, wo: Any, active: Any = True):
            return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

        def traverse(self, callback: Any) -> None:
            if has_albedo:
                callback.put("albedo", self.albedo, mi.ParamFlags.Differentiable)
            for name in self.scalar_fields:
                callback.put(name, getattr(self, name), mi.ParamFlags.Differentiable)

        def parameters_changed(self, keys: Any = None) -> None:
            pass

        def to_string(self) -> str:
            return f"Roughdiffuse[{self.model!r}]"

    RoughdiffuseBSDF.__name__ = f"Roughdiffuse{model_cls.__name__}BSDF"
    return RoughdiffuseBSDF


def register() -> list[str]:
    """Register every plugin of :data:`PLUGINS` with Mitsuba for the current variant.

    Call it after ``mi.set_variant(...)`` (and again after switching variants).

    Returns
    -------
    list of str
        The registered plugin names.
    """
    import drjit as dr
    import mitsuba as mi

    if mi.variant() is None:
        raise ValueError("set a Mitsuba variant first (mi.set_variant('scalar_rgb'), ...)")
    for name, cls in PLUGINS.items():
        plugin = _make_plugin_class(mi, dr, cls)
        mi.register_bsdf(name, lambda props, plugin=plugin: plugin(props))
    return list(PLUGINS)
