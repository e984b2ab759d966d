"""roughdiffuse's models as Mitsuba 3 BSDF plugins: one per registry id.

>>> import mitsuba as mi                                              # doctest: +SKIP
>>> mi.set_variant("llvm_ad_rgb")                                     # doctest: +SKIP
>>> from roughdiffuse.integrations import mitsuba as rdmi            # doctest: +SKIP
>>> rdmi.register()                                                   # doctest: +SKIP
>>> bsdf = mi.load_dict({"type": "roughdiffuse_oren_nayar", "sigma": 0.3,
...                      "albedo": {"type": "rgb", "value": [0.8, 0.6, 0.4]}})  # doctest: +SKIP

Every model of :mod:`roughdiffuse.registry` (the package's own, those of other packages'
entry points and those added by :func:`roughdiffuse.register_model` before :func:`register`
is called) becomes the plugin ``roughdiffuse_<id with underscores>``: ``roughdiffuse_lambert``,
``roughdiffuse_oren_nayar``, ``roughdiffuse_oren_nayar_full``, ``roughdiffuse_fujii``,
``roughdiffuse_eon``, ``roughdiffuse_torrance_sparrow``,
``roughdiffuse_torrance_sparrow_beckmann``, ``roughdiffuse_mix``,
``roughdiffuse_lommel_seeliger``, ``roughdiffuse_lunar_lambert``, ``roughdiffuse_v_cavity``
(the exact V-cavity surface, read from its table by ``dr.gather``), ... (every model whose
class has ``mitsuba = True``: not a Monte Carlo simulation such as ``SmithDiffuse``).
``roughdiffuse models`` lists them with their parameters. The plugin's parameters are the
model's declared ones (:class:`~roughdiffuse.models.declaration.Param`), named as in
roughdiffuse:

* a parameter with colour channels (``albedo``) is a Mitsuba texture (a float,
  ``{"type": "rgb", ...}``, a bitmap...);
* any other number is a float, in the declared unit (angles in radians, as in Python);
* a categorical parameter is a string. The categorical values an id fixes are its defaults
  and may be changed, within the same class: ``roughdiffuse_oren_nayar`` with
  ``"variant": "full"`` is ``roughdiffuse_oren_nayar_full``.

A parameter the model does not take, or a value out of its range, is a ``ValueError`` naming
the parameter and its range. Parameters left out take their declared defaults.

The formulas are not copied here: the plugin builds the model from its parameters, with
Dr.Jit values in place of numbers (:mod:`.drjit_namespace`), and calls its own
``brdf_cosines`` for ``eval`` and its own sampling strategy
(:meth:`~roughdiffuse.models.base.Model.sampling_strategy`) for ``sample``/``pdf``; a Mix
samples one component chosen by weight × albedo estimate, as in Python. Mitsuba's
conventions: ``si.wi`` points to the viewer (roughdiffuse's ``wo``), the ``wo`` argument to
the light (roughdiffuse's ``wi``); ``eval`` includes the cosine of the light direction; the
BSDF is one-sided (0 and pdf 0 below the horizon). A model with a glossy lobe (one of its
components for a Mix) has Mitsuba's ``GlossyReflection`` flag, the others
``DiffuseReflection``.

Float parameters are ``mi.Float`` values listed by ``mi.traverse`` as differentiable (a
texture as ``albedo.value`` and so on); in the ``llvm_ad_*``/``cuda_ad_*`` variants they can
be changed in place and differentiated. In ``scalar_*`` variants they are plain floats: load
a new BSDF to change them. A model's static numbers (fields not in its ``array_fields``:
``VCavity``'s σ and ρ, which select its table) are fixed when the BSDF is loaded: plain
floats, not listed by ``mi.traverse``; ``roughdiffuse_v_cavity`` computes its table then
(the first load of a (σ, ρ) takes a few seconds, :func:`roughdiffuse.models.vcavity.vcavity_table`).

The ``llvm`` variants need libLLVM 19 (Debian: ``apt-get install libllvm19``, then
``export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1``); with an older one
:func:`register` refuses them (:mod:`.drjit_llvm`) rather than let LLVM abort the process.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import Any

from .. import registry
from .._validate import ParameterError
from ..models import Model
from ..models.declaration import Param
from .drjit_llvm import require_llvm

__all__ = ["plugin_name", "plugins", "register"]


def plugin_name(model_id: str) -> str:
    """The Mitsuba plugin name of a registry id.

    >>> plugin_name("oren-nayar-full")
    'roughdiffuse_oren_nayar_full'
    """
    return "roughdiffuse_" + model_id.replace("-", "_")


def plugins() -> dict[str, registry.Entry]:
    """Plugin name -> registry entry, for every model the registry holds now that runs on
    Dr.Jit (class attribute ``mitsuba``: the closed forms and the tabulated ``VCavity``; a
    simulation such as ``SmithDiffuse`` cannot)."""
    return {plugin_name(e.id): e for e in registry.entries() if e.cls.mitsuba}


def _factory(cls: type[Model]) -> Callable[..., Model]:
    """What builds the class from its declared parameters (``from_params`` if it has one)."""
    return getattr(cls, "from_params", cls)


def _lobes(model: Model) -> set[str]:
    """The lobe types of ``model`` (a Mix: those of its components)."""
    lobes = getattr(model, "lobes", None)
    return set(lobes) if lobes is not None else {type(model).lobe}


_MISSING = object()


@dataclasses.dataclass(frozen=True)
class _PluginSpec:
    """What a plugin class needs to know of its registry entry: the model factory and its
    parameters sorted by kind (categorical, per-channel textures, plain numbers)."""

    entry: registry.Entry
    factory: Callable[..., Model]
    plugin: str
    declared: dict[str, Param]
    categorical: list[Param]
    textures: list[Param]
    numbers: list[Param]
    static: set[str]

    @classmethod
    def of(cls, entry: registry.Entry) -> _PluginSpec:
        model = entry.cls
        fields = set()
        if dataclasses.is_dataclass(model):
            fields = {f.name for f in dataclasses.fields(model)}
        numbers = [p for p in model.params if not p.channels and not p.categorical]
        arrays = set(model.array_fields)
        return cls(
            entry=entry,
            factory=_factory(model),
            plugin=plugin_name(entry.id),
            declared={p.name: p for p in model.params},
            categorical=[p for p in model.params if p.categorical],
            textures=[p for p in model.params if p.channels and not p.categorical],
            numbers=numbers,
            static={p.name for p in numbers if p.name in fields and p.name not in arrays},
        )


def _set_parameters(bsdf: Any, mi: Any, spec: _PluginSpec, props: Any) -> None:
    """Check the scene's properties and set the plugin's parameters from them: attributes
    named as declared (Mitsuba's traverse/update sets them by name); the plugin's own
    attributes start with ``rd_``."""
    for key in props.keys():
        if key not in spec.declared:
            raise ParameterError(
                f"{spec.plugin} has no parameter {key!r}; its parameters: "
                f"{', '.join(spec.declared) or 'none'}"
            )
    choices = {
        p.name: str(props.get(p.name, spec.entry.fixed.get(p.name, p.default)))
        for p in spec.categorical
    }
    for p in spec.categorical:
        p.check(choices[p.name])
    # validate with the given numbers (a texture: its default, it has no one value)
    given = {p.name: float(props[p.name]) for p in spec.numbers if p.name in props}
    constant = {}
    for p in spec.textures:
        if p.name in props and isinstance(props[p.name], float | int):
            constant[p.name] = float(props[p.name])
    bsdf.rd_model = spec.factory(**choices, **given, **constant)  # ParameterError if out of range
    bsdf.rd_choices = choices
    bsdf.rd_numbers = []
    bsdf.rd_static = {  # fixed now (a table's σ, ρ): plain floats
        name: float(getattr(bsdf.rd_model, name)) for name in spec.static
    }
    if bsdf.rd_static:
        bsdf.rd_model.brdf_cosines(1.0, 1.0, 1.0)  # build the table now, not mid-render
    for p in spec.numbers:  # the numbers this instance has (e.g. sigma or alpha)
        if p.name in spec.static:
            continue
        value = getattr(bsdf.rd_model, p.name, _MISSING)
        if value is _MISSING:  # built by from_params: the declared parameter itself
            if not p.applies(choices):
                continue
            value = given.get(p.name, p.default)
        if value is None:
            continue
        setattr(bsdf, p.name, mi.Float(float(value)))
        bsdf.rd_numbers.append(p.name)
    bsdf.rd_textures = [p.name for p in spec.textures if p.applies(choices)]
    for name in bsdf.rd_textures:
        setattr(bsdf, name, props.get_texture(name, float(spec.declared[name].default)))


def _set_flags(bsdf: Any, mi: Any) -> None:
    """The plugin's lobe flags from the model's lobes (diffuse, glossy)."""
    lobes = _lobes(bsdf.rd_model)
    bsdf.rd_lobe_flags = [
        flag
        for name, flag in (
            ("diffuse", mi.BSDFFlags.DiffuseReflection),
            ("glossy", mi.BSDFFlags.GlossyReflection),
        )
        if name in lobes
    ] or [mi.BSDFFlags.DiffuseReflection]
    bsdf.rd_lobe = bsdf.rd_lobe_flags[-1]  # sampled type: glossy if there is such a lobe
    flags = mi.BSDFFlags.FrontSide
    for flag in bsdf.rd_lobe_flags:
        flags = flags | flag
    bsdf.m_flags = flags
    bsdf.m_components = [flags]


def _model_methods(mi: Any, dr: Any, spec: _PluginSpec) -> dict[str, Callable[..., Any]]:
    """The plugin's methods that evaluate and sample the model on Dr.Jit values."""
    from .drjit_namespace import drjit_namespace as xp
    from .drjit_namespace import unwrap, wrap

    def channel_mean(c: Any) -> Any:
        return (c[0] + c[1] + c[2]) * (1.0 / 3.0)

    def _model(self: Any, si: Any, active: Any, mean: bool = False) -> Model:
        """The model with this BSDF's Dr.Jit values (textures evaluated at ``si``; their
        channel mean where ``mean``: sampling needs one number per lane)."""
        kwargs: dict[str, Any] = {**self.rd_choices, **self.rd_static}
        for name in self.rd_numbers:
            kwargs[name] = wrap(getattr(self, name))
        for name in self.rd_textures:
            value = getattr(self, name).eval(si, active)
            kwargs[name] = wrap(channel_mean(value) if mean else value)
        return spec.factory(**kwargs)

    def _brdf(self: Any, si: Any, wi: Any, active: Any) -> Any:
        """f(wi = light, wo = si.wi) as a Color3f (roughdiffuse's direction names)."""
        mu_i = dr.clip(wi.z, 0.0, 1.0)
        mu_o = dr.clip(si.wi.z, 0.0, 1.0)
        cos_io = dr.clip(dr.dot(wi, si.wi), -1.0, 1.0)
        f = self._model(si, active).brdf_cosines(wrap(mu_i), wrap(mu_o), wrap(cos_io))
        return mi.Color3f(unwrap(f))

    def _strategy(self: Any, si: Any, active: Any) -> tuple[Any, dict[str, Any]]:
        model = self._model(si, active, mean=True)
        return model.sampling_strategy(), model.parameter_arrays(xp)

    def _pdf(self: Any, si: Any, wi: Any, active: Any) -> Any:
        strategy, p = self._strategy(si, active)
        d = si.wi
        pdf = strategy.pdf(
            xp, wrap(wi.x), wrap(wi.y), wrap(wi.z), wrap(d.x), wrap(d.y), wrap(d.z), p
        )
        return unwrap(pdf)

    def _sample_direction(self: Any, si: Any, sample2: Any, active: Any) -> tuple[Any, Any]:
        strategy, p = self._strategy(si, active)
        d = si.wi
        x, y, z, pdf = strategy.sample(
            xp, wrap(sample2.x), wrap(sample2.y), wrap(d.x), wrap(d.y), wrap(d.z), p
        )
        return mi.Vector3f(unwrap(x), unwrap(y), unwrap(z)), unwrap(pdf)

    return {
        "_model": _model,
        "_brdf": _brdf,
        "_strategy": _strategy,
        "_pdf": _pdf,
        "_sample_direction": _sample_direction,
    }


def _make_plugin_class(mi: Any, dr: Any, entry: registry.Entry) -> type:
    """A Mitsuba ``BSDF`` subclass for the registry ``entry`` (for the variant set now)."""
    spec = _PluginSpec.of(entry)
    methods = _model_methods(mi, dr, spec)

    class RoughdiffuseBSDF(mi.BSDF):
        def __init__(self, props: Any) -> None:
            mi.BSDF.__init__(self, props)
            _set_parameters(self, mi, spec, props)
            _set_flags(self, mi)

        def _enabled(self, ctx: Any) -> bool:
            return any(ctx.is_enabled(flag) for flag in self.rd_lobe_flags)

        # -------------------------------------------------------------- the model
        _model = methods["_model"]
        _brdf = methods["_brdf"]
        _strategy = methods["_strategy"]
        _pdf = methods["_pdf"]
        _sample_direction = methods["_sample_direction"]

        # -------------------------------------------------------------- Mitsuba API
        def sample(self, ctx: Any, si: Any, sample1: Any, sample2: Any, active: Any = True):
            d = si.wi
            wi, pdf = self._sample_direction(si, sample2, active)
            active = active & (d.z > 0) & (wi.z > 0) & (pdf > 0)
            active = active & self._enabled(ctx)
            bs = dr.zeros(mi.BSDFSample3f)
            bs.wo = wi
            bs.pdf = dr.select(active, pdf, 0.0)
            bs.eta = 1.0
            bs.sampled_type = mi.UInt32(+self.rd_lobe)
            bs.sampled_component = mi.UInt32(0)
            value = self._brdf(si, wi, active) * (wi.z / dr.select(active, pdf, 1.0))
            return bs, dr.select(active, value, 0.0)

        def eval(self, ctx: Any, si: Any, wo: Any, active: Any = True):
            active = active & (si.wi.z > 0) & (wo.z > 0) & self._enabled(ctx)
            value = self._brdf(si, wo, active) * dr.clip(wo.z, 0.0, 1.0)
            return dr.select(active, value, 0.0)

        def pdf(self, ctx: Any, si: Any, wo: Any, active: Any = True):
            active = active & (si.wi.z > 0) & (wo.z > 0) & self._enabled(ctx)
            return dr.select(active, self._pdf(si, wo, active), 0.0)

        def eval_pdf(self, ctx: Any, si: Any, wo: Any, active: Any = True):
            return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

        def traverse(self, callback: Any) -> None:
            for name in self.rd_textures:
                callback.put(name, getattr(self, name), mi.ParamFlags.Differentiable)
            for name in self.rd_numbers:
                callback.put(name, getattr(self, name), mi.ParamFlags.Differentiable)

        def parameters_changed(self, keys: Any = None) -> None:
            pass

        def to_string(self) -> str:
            return f"Roughdiffuse[{spec.plugin}: {self.rd_model!r}]"

    RoughdiffuseBSDF.__name__ = f"Roughdiffuse{entry.cls.__name__}BSDF"
    return RoughdiffuseBSDF


def register() -> list[str]:
    """Register a plugin for every model of the registry with Mitsuba, for the current variant.

    Call it after ``mi.set_variant(...)``, again after switching variants, and again after
    :func:`roughdiffuse.register_model` to add a model registered since.

    Returns
    -------
    list of str
        The registered plugin names.

    Raises
    ------
    ValueError
        If no variant is set, or it is an ``llvm`` one and Dr.Jit loads a libLLVM too old to
        run it (:func:`~roughdiffuse.integrations.drjit_llvm.require_llvm`).
    """
    import drjit as dr
    import mitsuba as mi

    if mi.variant() is None:
        raise ParameterError("set a Mitsuba variant first (mi.set_variant('scalar_rgb'), ...)")
    require_llvm(mi.variant())  # an old libLLVM would abort the process at the first kernel
    names = []
    for name, entry in plugins().items():
        plugin = _make_plugin_class(mi, dr, entry)
        mi.register_bsdf(name, lambda props, plugin=plugin: plugin(props))
        names.append(name)
    return names
