"""The interface every reflectance model shares (after pbrt-v4's BxDF: f, Sample_f, PDF, rho).

A model is a frozen dataclass holding its parameters: :class:`Model` makes each subclass one
(and a JAX pytree), and builds its ``params`` from the fields declared by
:func:`~roughdiffuse.models.declaration.param`. Its formula lives in one method,
``_kernel(xp, mu_i, mu_o, cos_io, **params)``, written against the array API standard and
evaluated on the three local cosines (see :mod:`roughdiffuse.frames`). Everything else, the
vector interface, validation, horizon handling, colour channels, JAX dispatch, quadrature and
sampling, is here, once.

Conventions: ``wi`` points to the light, ``wo`` to the viewer, z is the normal; the BRDF has
no cosine in it (pbrt's convention); it is 0 when either direction is below the horizon
(z < 0) and finite on it (z = 0).
"""

from __future__ import annotations

import dataclasses
import inspect
from typing import Any, ClassVar, dataclass_transform

import numpy as np

from .._array import (
    Array,
    asarray,
    clip,
    concrete,
    is_jax,
    is_tracer,
    namespace,
    result_dtype,
)
from .._lazy import when_imported
from .._validate import ParameterError
from ..engine.dispatch import compiled
from ..frames import check_cosines, local_cosines, unit_components, world_cosines
from .constraints import Constraint, check_constraints
from .declaration import Param, declared_params, param
from .sampling import COSINE, BSDFSample, Strategy

__all__ = ["BSDFSample", "Model"]

LOBES: tuple[str, ...] = ("diffuse", "glossy")
"""The lobe types a model may declare (Mitsuba 3's DiffuseReflection, GlossyReflection)."""


_JITTED: dict[str, Any] = {}


def _jitted(method: str) -> Any:
    fn = _JITTED.get(method)
    if fn is None:
        import jax

        fn = jax.jit(lambda model, *args: getattr(model, method)(*args))
        _JITTED[method] = fn
    return fn


@dataclass_transform(frozen_default=True, field_specifiers=(dataclasses.field, param))
class Model:
    """Base class of the reflectance models. Subclasses are frozen dataclasses.

    Each subclass is made a frozen dataclass and a JAX pytree (:func:`register_pytree`) when
    it is defined: it declares its fields, with no decorator. A model declares itself once,
    in its fields (``name: float | Array = param(...)``) and class attributes; validation,
    the pytree leaves, the command line, fits, ``roughdiffuse models`` and the explorer
    derive from them (see :mod:`roughdiffuse.registry` and docs/developer/adding-a-model.md).

    Class attributes
    ----------------
    params : tuple of Param
        The parameters (:class:`~roughdiffuse.models.declaration.Param`): name, meaning,
        unit, range, default, colour channels, choices. Derived from the fields declared by
        :func:`~roughdiffuse.models.declaration.param`, in field order, after
        ``factory_params``. The constructor checks each value against its declaration. (A
        class may still list ``params`` itself, with plain fields: code written before
        ``param``; the registry then checks the fields' defaults against it.)
    factory_params : tuple of Param
        Parameters of a ``from_params`` factory that are not fields (``Mix``'s σ and weight,
        ``Coated``'s ``base`` id and the base's albedo); they come first in ``params``.
    ids : dict
        Public kebab-case id(s) -> the categorical values each fixes, e.g.
        ``{"oren-nayar": {"variant": "qualitative"}, "oren-nayar-full": {"variant": "full"}}``.
    labels : dict
        Id -> human-readable label (plots, reports, the explorer's menus); defaults to the id.
    lobe : {"diffuse", "glossy"}
        The lobe type.
    sampling : Strategy
        The importance-sampling strategy (:mod:`.sampling`): ``COSINE``, ``CLTC``, ...
    reference : str
        The source paper.
    formula : str or dict
        The BRDF as the model's page states it: MyST Markdown (indented as it likes: it is
        dedented) with MyST ``math`` directive blocks of LaTeX carrying the paper's equation
        numbers, and the conventions of the implementation (floors, clamps, limits); a dict
        id -> text when the ids of a class differ. The site's model pages show it
        (docs/_ext/rd_pages.py).
    symbols : dict
        Parameter name -> its LaTeX symbol in ``formula`` (``{"albedo": r"\\rho"}``).
    order : int
        Where the model's ids come in the registry (``roughdiffuse models``): classes are
        sorted by ``order``, then module name, then definition order. Default 1000 (after
        the package's first models).
    traceable : bool
        False for a model computed by simulation on concrete NumPy values (``SmithDiffuse``):
        it cannot be traced by ``jax.jit`` (the renderer, fits).
    closed_form : bool
        True for a formula of elementwise operations on the three cosines with its numeric
        parameters as inputs: what the compiled fast path (Numba traces it with scalars),
        ``compare_models`` and the interface-wide tests need. False for a simulation
        (``SmithDiffuse``) and for a model tabulated from a solver (``VCavity``, which still
        runs under ``jax.jit``).
    mitsuba : bool
        Whether the model is a Mitsuba 3 plugin (:mod:`roughdiffuse.integrations.mitsuba`):
        its ``_kernel`` runs on the Dr.Jit namespace (elementwise functions, and gathers
        from a table of constants with ``xp.take``), and a numeric parameter that is not in
        ``array_fields`` (static: it selects a table) is fixed when the BSDF is loaded.
        Defaults to ``closed_form`` unless the class (or a base other than ``Model``)
        declares it: every closed form is a plugin, a simulation is not, ``VCavity`` (a
        table) sets it True.
    array_fields : tuple of str
        Numeric parameters (JAX pytree leaves, differentiable); derived from ``params``.
        Other fields are static.
    channel_fields : tuple of str
        Parameters that may carry a trailing colour-channel axis; derived from ``params``.
    """

    params: ClassVar[tuple[Param, ...]] = ()
    factory_params: ClassVar[tuple[Param, ...]] = ()
    constraints: ClassVar[tuple[Constraint, ...]] = ()  # models.constraints: rules together
    ids: ClassVar[dict[str, dict[str, Any]]] = {}
    labels: ClassVar[dict[str, str]] = {}
    lobe: ClassVar[str] = "diffuse"
    sampling: ClassVar[Strategy] = COSINE
    reference: ClassVar[str] = ""
    formula: ClassVar[str | dict[str, str]] = ""
    symbols: ClassVar[dict[str, str]] = {}
    order: ClassVar[int] = 1000
    traceable: ClassVar[bool] = True
    closed_form: ClassVar[bool] = True
    mitsuba: ClassVar[bool] = True
    array_fields: ClassVar[tuple[str, ...]] = ()
    channel_fields: ClassVar[tuple[str, ...]] = ()

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        own_fields = set(inspect.get_annotations(cls))
        dataclasses.dataclass(frozen=True)(cls)
        # the frozen dataclass's __setattr__/__delattr__ are Model's (the same rule for every
        # model): a class that still applies @dataclass(frozen=True) itself may do so
        for name in ("__setattr__", "__delattr__"):
            if name in cls.__dict__:
                delattr(cls, name)
        fields = dataclasses.fields(cls)  # type: ignore[arg-type]
        declared = declared_params(fields)
        if "params" in cls.__dict__:
            if declared:
                raise TypeError(
                    f"{cls.__name__} lists params and declares fields with param(): "
                    "declare each parameter once"
                )
            own_params = True
        else:
            factory = cls.__dict__.get("factory_params", ())
            own_params = bool(factory) or any(p.name in own_fields for p in declared)
            if declared or factory:
                cls.params = (*factory, *declared)
        if not any("mitsuba" in c.__dict__ for c in cls.__mro__ if c is not Model):
            cls.mitsuba = cls.closed_form  # a closed form is a plugin unless it says otherwise
        if own_params:
            if "array_fields" not in cls.__dict__:
                cls.array_fields = tuple(p.name for p in cls.params if not p.categorical)
            if "channel_fields" not in cls.__dict__:
                cls.channel_fields = tuple(p.name for p in cls.params if p.channels)
        if not isinstance(cls.sampling, Strategy):
            raise TypeError(f"{cls.__name__}.sampling must be a Strategy (got {cls.sampling!r})")
        if cls.lobe not in LOBES:
            raise TypeError(f"{cls.__name__}.lobe must be one of {LOBES} (got {cls.lobe!r})")
        register_pytree(cls)

    def __setattr__(self, name: str, value: Any) -> None:
        raise dataclasses.FrozenInstanceError(f"cannot assign to field {name!r}")

    def __delattr__(self, name: str) -> None:
        raise dataclasses.FrozenInstanceError(f"cannot delete field {name!r}")

    def __post_init__(self) -> None:
        self._validate()

    def _validate(self) -> None:
        """Check every declared parameter (``ValueError`` naming it, its unit and its range).

        Categorical parameters first; a parameter whose ``when`` does not hold must be
        ``None``; lists of channel values become float64 arrays (one pytree leaf).
        """
        fields = {f.name for f in dataclasses.fields(self)}  # type: ignore[arg-type]
        declared = [p for p in self.params if p.name in fields]
        if not declared:
            self._coerce_channels()
            return
        for p in declared:
            if p.categorical:
                p.check(getattr(self, p.name))
        choices = {p.name: getattr(self, p.name) for p in declared if p.categorical}
        for p in declared:
            if p.categorical:
                continue
            value = getattr(self, p.name)
            if not p.applies(choices):
                if value is not None:
                    raise ParameterError(
                        f"{p.name} applies only with {p.when_text()} (got {p.name}={value!r})"
                    )
                continue
            object.__setattr__(self, p.name, p.check(value))
        check_constraints(self)  # combinations valid one by one but not together

    def sampling_strategy(self) -> Strategy:
        """The importance-sampling strategy of this instance (the class's ``sampling``)."""
        return type(self).sampling

    # ------------------------------------------------------------------ formula
    def _kernel(self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, **p: Array) -> Array:
        """The BRDF from the local cosines (mu in [0, 1]); subclasses implement it."""
        raise NotImplementedError

    def kernel(self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, **params: Any) -> Array:
        """The model's formula on the local cosines, with the parameters given as arrays.

        For code that supplies its own parameter values in its own array namespace ``xp``
        (the Mitsuba 3 plugins pass Dr.Jit values and textures). ``mu_i``, ``mu_o`` must lie
        in [0, 1] and ``cos_io`` in [-1, 1]; no horizon test or validation is made (use
        :meth:`brdf_cosines` for that). ``params`` are the model's ``array_fields``.
        Subclasses implement the formula in ``_kernel``.
        """
        return self._kernel(xp, mu_i, mu_o, cos_io, **params)

    # ------------------------------------------------------------------ helpers
    def _coerce_channels(self) -> None:
        """Turn a list or tuple of channel values into a float64 array (one pytree leaf)."""
        for f in self.channel_fields:
            value = getattr(self, f)
            if isinstance(value, list | tuple):
                object.__setattr__(self, f, np.asarray(value, dtype=np.float64))

    def parameter_values(self) -> list[Any]:
        """The numeric parameters as given (those unset, ``None``, left out; a model holding
        models, :class:`~roughdiffuse.models.mix.Mix`, includes theirs): what decides the
        array namespace of a call and whether it is traced."""
        return [getattr(self, f) for f in self.array_fields if getattr(self, f) is not None]

    def _xp(self, *arrays: Any) -> Any:
        return namespace(*arrays, *self.parameter_values())

    def parameter_arrays(self, xp: Any, dtype: Any = None) -> dict[str, Any]:
        """The numeric parameters as arrays of namespace ``xp`` (those unset, ``None``, for
        this instance left out): what :meth:`kernel` and the sampling strategies
        (:mod:`.sampling`) receive. A model holding models nests their records."""
        return {
            f: asarray(xp, getattr(self, f), dtype)
            for f in self.array_fields
            if getattr(self, f) is not None
        }

    @property
    def channels(self) -> int:
        """Number of colour channels of the output (0 for a scalar albedo)."""
        for f in self.channel_fields:
            a = concrete(getattr(self, f))
            if a is not None and a.ndim == 1:
                return int(a.shape[0])
            if a is None and getattr(getattr(self, f), "ndim", 0) == 1:
                return int(getattr(self, f).shape[0])
        return 0

    def _should_jit(self, xp: Any, *arrays: Any) -> bool:
        if not is_jax(xp):
            return False
        return not any(is_tracer(a) for a in (*arrays, *self.parameter_values()))

    def brdf_cosines(self, mu_i: Array, mu_o: Array, cos_io: Array) -> Array:
        """The BRDF from the local cosines n·wi, n·wo and wi·wo (no normalisation done).

        This is the entry point of renderers and tables that already hold cosines. Output
        shape: the broadcast shape of the inputs, plus a channel axis for RGB albedo. Large
        NumPy inputs run compiled, on every core (:mod:`roughdiffuse.engine.dispatch`).
        A cosine beyond ±1 is refused (:func:`~roughdiffuse.frames.check_cosines`); a triple
        off the Gram condition is not (renderers clamp μ at the horizon), and gives the
        model's clamped value.
        """
        check_cosines(mu_i, mu_o, cos_io, pairs=False)
        fast = compiled(self, "brdf_cosines", mu_i, mu_o, cos_io)
        if fast is not None:
            return fast
        xp = self._xp(mu_i, mu_o, cos_io)
        dtype = result_dtype(xp, mu_i, mu_o, cos_io)
        mu_i, mu_o, cos_io = (asarray(xp, a, dtype) for a in (mu_i, mu_o, cos_io))
        return self.evaluate(xp, mu_i, mu_o, cos_io, dtype)

    def evaluate(self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, dtype: Any) -> Array:
        """The BRDF on local cosines already arrays of namespace ``xp`` and ``dtype``: 0 where
        either direction is below the horizon, the cosines clamped, a channel axis added for
        channel parameters, then :meth:`kernel` on :meth:`parameter_arrays`.

        :meth:`brdf_cosines` once the namespace is chosen: what a model built of other models
        (:class:`~roughdiffuse.models.mix.Mix`, :class:`~roughdiffuse.models.coated.Coated`)
        calls on them, inside its own evaluation (traced or not).
        """
        p = self.parameter_arrays(xp, dtype)
        above = (mu_i >= 0) & (mu_o >= 0)
        mi, mo, c = clip(xp, mu_i, 0.0, 1.0), clip(xp, mu_o, 0.0, 1.0), clip(xp, cos_io, -1.0, 1.0)
        if self.channels:
            mi, mo, c, above = mi[..., None], mo[..., None], c[..., None], above[..., None]
        val = self._kernel(xp, mi, mo, c, **p)
        return xp.where(above, val, xp.zeros_like(val))

    # ------------------------------------------------------------------ interface
    def brdf(self, wi: Array, wo: Array) -> Array:
        """BRDF value f_r(wi, wo) in 1/sr, without the cosine.

        Parameters
        ----------
        wi, wo : array (..., 3)
            Directions towards the light and the viewer in the local frame (z = normal);
            normalised here; they broadcast against each other.

        Returns
        -------
        array (...) or (..., C)
            In the namespace of the inputs (NumPy, JAX, PyTorch); a channel axis is added
            for an RGB albedo. 0 where either direction is below the horizon. Large NumPy
            inputs run compiled, on every core (:mod:`roughdiffuse.engine.dispatch`).
        """
        fast = compiled(self, "brdf", wi, wo)
        if fast is not None:
            return fast
        xp = self._xp(wi, wo)
        if self._should_jit(xp, wi, wo):
            for name, w in (("wi", wi), ("wo", wo)):
                unit_components(xp, w, name)  # validate eagerly; jit cannot raise
            local_cosines(xp, wi, wo)  # shape checks
            return _jitted("brdf")(self, wi, wo)
        dtype = result_dtype(xp, wi, wo)
        mu_i, mu_o, cos_io = local_cosines(xp, wi, wo, dtype)
        return self.evaluate(xp, mu_i, mu_o, cos_io, dtype)

    def radiance(self, n: Array, l: Array, v: Array, irradiance: Array | float = 1.0) -> Array:
        """Reflected radiance L = f_r · E0 · cos θi for world-space directions.

        Parameters
        ----------
        n, l, v : array (..., 3)
            Surface normal, direction to the light, direction to the viewer (any frame).
        irradiance : float or array (C,)
            E0 ≥ 0, the irradiance on a plane facing the source (per channel if an array).

        Returns
        -------
        array (...) or (..., C)
            Radiance; 0 where the point faces away from the light or the viewer. Large NumPy
            inputs run compiled, on every core (:mod:`roughdiffuse.engine.dispatch`).
        """
        _check_irradiance(irradiance)
        fast = compiled(self, "radiance", n, l, v, irradiance=irradiance)
        if fast is not None:
            return fast
        xp = self._xp(n, l, v, irradiance)
        if self._should_jit(xp, n, l, v, irradiance):
            for name, w in (("n", n), ("l", l), ("v", v)):
                unit_components(xp, w, name)
            return _jitted("radiance")(self, n, l, v, irradiance)
        dtype = result_dtype(xp, n, l, v)
        mu_i, mu_o, cos_io = world_cosines(xp, n, l, v, dtype)
        f = self.evaluate(xp, mu_i, mu_o, cos_io, dtype)
        cos_i = clip(xp, mu_i, 0.0, 1.0)
        e0 = asarray(xp, irradiance, dtype)
        if f.ndim == cos_i.ndim + 1:
            cos_i = cos_i[..., None]
        elif e0.ndim == 1:
            f, cos_i = f[..., None], cos_i[..., None]
        return f * e0 * cos_i

    def directional_albedo(self, wo: Array) -> Array:
        """∫ f_r(wi, wo) cos θi dωi over the upper hemisphere.

        Gauss–Legendre quadrature split at the kinks of the Oren–Nayar family (θi = θr and
        φ = ±π/2), accurate to about 1e-6 for the diffuse models; models with a closed form
        override this.
        """
        from ._hemisphere_albedo import hemisphere_albedo

        return hemisphere_albedo(self, wo)

    def sample(self, u: Array, wo: Array) -> BSDFSample:
        """Importance-sample wi given ``wo`` from uniform numbers ``u`` of shape (..., 2).

        The strategy is the class's ``sampling`` (see :mod:`.sampling`): cosine-weighted
        hemisphere by default, EON's clipped LTC for EON and Fujii, facet-normal sampling
        for Torrance–Sparrow, the mixture of its components' strategies for a Mix.
        """
        from .sampling import sample_model

        return sample_model(self, u, wo)

    def pdf(self, wi: Array, wo: Array) -> Array:
        """Density (per solid angle) with which :meth:`sample` returns ``wi`` given ``wo``."""
        from .sampling import pdf_model

        return pdf_model(self, wi, wo)

    def channel(self, c: int) -> Model:
        """This model for colour channel ``c`` alone: each channel parameter with one value per
        channel replaced by its ``c``-th value (a scalar or one-value parameter kept).

        A per-channel evaluator (the fast path) calls this instead of looking inside the
        model; :class:`~roughdiffuse.models.mix.Mix` passes it on to its components.

        >>> from roughdiffuse import Lambert
        >>> Lambert([0.9, 0.5, 0.2]).channel(1)
        Lambert(albedo=0.5)
        """
        changes = {}
        for f in self.channel_fields:
            value = getattr(self, f)
            if getattr(value, "ndim", 0) == 1:
                changes[f] = float(value[c]) if value.shape[0] > 1 else float(value[0])
        return dataclasses.replace(self, **changes) if changes else self  # type: ignore[type-var]

    def albedo_estimate(self, xp: Any, mu_o: Array, p: dict[str, Any]) -> Array:
        """A cheap estimate of the directional albedo at view cosine ``mu_o``.

        ``p`` holds the parameters as the sampling strategies receive them
        (:meth:`parameter_arrays`). :class:`~roughdiffuse.models.mix.Mix` samples component
        k with probability proportional to w_k times this estimate. Default: the ``albedo``
        parameter (the mean of its channels), or 1 for a model without one; Torrance–Sparrow
        overrides it. It only steers sampling: the estimates change the variance, never the
        mean.
        """
        a = p.get("albedo")
        if a is None:
            return 1.0 + 0.0 * mu_o
        if self.channels:
            a = xp.sum(a, axis=-1) / self.channels
        return a + 0.0 * mu_o

    def _closed_form_albedo(self, wo: Array, albedo_of_mu: Any) -> Array:
        """Directional albedo from a closed form ``albedo_of_mu(xp, mu_o, **params)``.

        Handles the namespace, validation of ``wo``, the channel axis and the horizon (0 for
        wo below it) once for every model that has a closed form.
        """
        xp = self._xp(wo)
        dtype = result_dtype(xp, wo)
        _, _, z = unit_components(xp, wo, "wo", dtype)
        if self.channels:
            z = z[..., None]
        val = albedo_of_mu(xp, clip(xp, z, 0.0, 1.0), **self.parameter_arrays(xp, dtype))
        return xp.where(z >= 0, val, 0.0 * val)


_IRRADIANCE = Param("irradiance", "irradiance E0", min=0.0, default=1.0, channels=True)


def _check_irradiance(value: Any) -> None:
    """E0 must be finite and non-negative (a negative E0 would give negative radiance)."""
    if getattr(value, "ndim", 0) > 1:  # per-point E0: check all values as one channel list
        _IRRADIANCE.check(value.reshape(-1))
    else:
        _IRRADIANCE.check(value)


def register_pytree(cls: type) -> type:
    """Make a model dataclass a JAX pytree: numeric fields are leaves, the rest static.

    :class:`Model` applies it to each subclass; applying it again (as a decorator, in code
    written before) does nothing. Registered when JAX is imported (now, if it is), so
    defining a model does not import JAX.
    ``jax.tree_util.register_dataclass`` is not used: in JAX 0.10 its tree definitions of two
    classes with the same field names compare equal (Lambert and LommelSeeliger, say), so a
    jitted function could reuse one model's compiled code for the other. Unflattening skips
    ``__post_init__``: JAX passes placeholders that are not parameter values.
    """
    if cls.__dict__.get("_pytree_registered"):
        return cls
    cls._pytree_registered = True  # type: ignore[attr-defined]
    fields = [f.name for f in dataclasses.fields(cls)]
    data = tuple(f for f in fields if f in cls.array_fields)
    meta = tuple(f for f in fields if f not in cls.array_fields)

    def flatten(obj: Any) -> tuple[tuple[Any, ...], tuple[Any, ...]]:
        return tuple(getattr(obj, f) for f in data), tuple(getattr(obj, f) for f in meta)

    def unflatten(aux: tuple[Any, ...], children: Any) -> Any:
        obj = object.__new__(cls)
        for name, value in (*zip(data, children, strict=True), *zip(meta, aux, strict=True)):
            object.__setattr__(obj, name, value)
        return obj

    when_imported("jax", lambda jax: jax.tree_util.register_pytree_node(cls, flatten, unflatten))
    return cls
