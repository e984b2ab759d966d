"""Every model by its public id: the one list the command line, fits, the explorer, reports,
benchmarks and ``roughdiffuse models`` read.

An id (kebab-case, e.g. ``oren-nayar-full``) names a model class and the categorical values it
fixes; the class's own declaration (:class:`~roughdiffuse.models.declaration.Param` records in
``params``, ``ids``, ``labels``, ``lobe``, ``sampling``, ``reference``) says the rest.

Models from other packages join in two ways (see docs/developer/adding-a-model.md):

* an entry point in the group ``roughdiffuse.models`` naming the class, loaded the first time
  the registry is read::

      [project.entry-points."roughdiffuse.models"]
      minnaert = "minnaert_model:Minnaert"

* :func:`register_model` (also ``roughdiffuse.register_model``), for interactive use.

>>> from roughdiffuse import registry
>>> registry.get("oren-nayar-full").create(albedo=0.5, sigma=0.3)
OrenNayar(albedo=0.5, sigma=0.3, variant='full')
>>> [p.name for p in registry.get("torrance-sparrow-beckmann").parameters]
['eta', 'alpha']
"""

from __future__ import annotations

import copy
import dataclasses
import importlib.metadata
import re
import threading
import warnings
from collections.abc import Mapping
from typing import Any, TypeVar

from ._validate import ParameterError
from .deprecation import rename_keywords
from .models.base import Model
from .models.declaration import Param

__all__ = [
    "ENTRY_POINT_GROUP",
    "Entry",
    "create",
    "entries",
    "get",
    "id_of",
    "ids",
    "register_model",
    "to_json",
]

ENTRY_POINT_GROUP = "roughdiffuse.models"
"""The entry-point group other packages list their model classes in."""

_ID = re.compile(r"^[a-z0-9]+(?:-[a-z0-9]+)*$")
_LOCK = threading.RLock()
_ENTRIES: dict[str, Entry] = {}
_ALIAS_RECORDS: dict[tuple[str, type], dict[str, Any]] = {}  # Entry.alias, once per id and class
_LOADED = False

M = TypeVar("M", bound=type)


@dataclasses.dataclass(frozen=True)
class Entry:
    """One public model id: its class, the categorical values it fixes, where it comes from.

    Attributes
    ----------
    id : str
        Public kebab-case id.
    cls : type
        The model class.
    fixed : mapping
        Categorical parameters the id fixes (``{"variant": "full"}``).
    source : str
        ``"roughdiffuse"`` for the package's own models, else the distribution (or module)
        that registered it.
    """

    id: str
    cls: type[Model]
    fixed: Mapping[str, Any]
    source: str = "roughdiffuse"

    @property
    def label(self) -> str:
        """Human-readable name for menus, plots and reports."""
        return self.cls.labels.get(self.id, self.id)

    @property
    def lobe(self) -> str:
        """``"diffuse"`` or ``"glossy"``."""
        return self.cls.lobe

    @property
    def reference(self) -> str:
        """The source paper."""
        return self.cls.reference

    @property
    def glsl(self) -> bool:
        """Whether the explorer draws this model: a closed form, whose GLSL is printed from its
        code (:mod:`roughdiffuse.engine.glsl`)."""
        return bool(self.cls.closed_form)

    def example(self) -> dict[str, Any]:
        """The example parameter set: the declared ``example`` (else the default) of each
        parameter that exists for the example's choices (the benchmarks' point and the first
        one the interface-wide tests run).

        >>> get("oren-nayar").example()
        {'albedo': 0.8, 'sigma': 0.3490658503988659}
        """
        start = {p.name: p.default if p.example is None else p.example for p in self.parameters}
        return {p.name: start[p.name] for p in self.applicable(start)}

    @property
    def parameters(self) -> tuple[Param, ...]:
        """The parameters a user sets for this id (those it fixes left out): every one that
        exists for the values the id fixes, including those that exist only for some value
        of a categorical parameter the id leaves free (:meth:`applicable` picks those of
        one choice)."""
        return tuple(
            p for p in self.cls.params
            if p.name not in self.fixed and p.applies({**self._free_values(p), **self.fixed})
        )

    @staticmethod
    def _free_values(p: Param) -> dict[str, Any]:
        """Values under which ``p`` applies (its own ``when``): the free categoricals."""
        return {k: v[0] if isinstance(v, tuple) else v for k, v in (p.when or {}).items()}

    def choices(self, values: Mapping[str, Any] | None = None) -> dict[str, Any]:
        """The categorical values of one parameter set: those in ``values``, those the id
        fixes, else the declared defaults."""
        values = values or {}
        out = {p.name: values.get(p.name, p.default) for p in self.parameters if p.categorical}
        return {**out, **self.fixed}

    def applicable(self, values: Mapping[str, Any] | None = None) -> tuple[Param, ...]:
        """The parameters that exist for the categorical values in ``values`` (the others at
        their defaults): e.g. ``coated`` with ``base="eon"`` takes ``base_roughness`` and
        not Oren–Nayar's ``sigma``.

        >>> [p.name for p in get("coated").applicable({"base": "eon"})][:3]
        ['base', 'albedo', 'base_roughness']
        """
        chosen = self.choices(values)
        return tuple(p for p in self.parameters if p.applies(chosen))

    def param(self, name: str) -> Param:
        """The parameter ``name`` of this id (``ValueError`` naming the accepted ones)."""
        for p in self.parameters:
            if p.name == name:
                return p
        raise ParameterError(
            f"model {self.id!r} has no parameter {name!r}; its parameters: "
            f"{', '.join(p.name for p in self.parameters) or 'none'}"
        )

    def defaults(self) -> dict[str, Any]:
        """Parameter name -> default value (those that exist for the default choices)."""
        return {p.name: p.default for p in self.applicable()}

    def create(self, **params: Any) -> Model:
        """The model with these parameters (the others at their defaults).

        Raises
        ------
        ValueError
            For a parameter this id does not take, or a value out of its range.
        """
        params = rename_keywords(self.cls, params, f"model {self.id!r}")
        for name in params:
            self.param(name)
        kwargs = {**self.fixed, **params}
        factory = getattr(self.cls, "from_params", None)
        if factory is not None:
            return factory(**kwargs)
        return self.cls(**kwargs)

    def matches(self, model: Model) -> bool:
        """Whether ``model`` is an instance this id describes (its class and fixed values)."""
        return type(model) is self.cls and all(
            getattr(model, k, None) == v for k, v in self.fixed.items()
        )

    def alias(self) -> dict[str, Any] | None:
        """For an :class:`~roughdiffuse.models.alias.Alias`, its base model and conversion
        (``None`` for any other model): what the explorer shows and uses for the base
        model's ground truth (the alias itself is traced like any model).

        ``base``: the registry id of the equal model (from :meth:`Alias.base_model`);
        ``fixed``: the base's categorical values that id leaves open; ``text``: each base
        parameter as an expression of this model's; ``to_base``: each as a JSON expression
        tree (a name, a number, or ``[op, operand, ...]``); ``javascript``: the body of a
        JavaScript function computing them (``None`` with the reason in ``why`` when
        ``to_base`` cannot be traced); all from :meth:`Alias.conversion`.
        """
        from .models.alias import Alias

        if not issubclass(self.cls, Alias):
            return None
        key = (self.id, self.cls)
        if key not in _ALIAS_RECORDS:  # traced once: /api/models asks often
            _ALIAS_RECORDS[key] = self._alias_record()
        return copy.deepcopy(_ALIAS_RECORDS[key])

    def _alias_record(self) -> dict[str, Any]:
        from .engine.trace import TraceError

        base = self.create().base_model()
        base_id = id_of(base)
        if base_id is None:
            why = f"{base!r} has no id"
            return {"base": None, "fixed": {}, "to_base": None, "javascript": None, "text": None,
                    "why": why}
        fixed = {p.name: getattr(base, p.name) for p in get(base_id).parameters if p.categorical}
        try:
            traced, why = self.cls.conversion(), None
        except TraceError as exc:
            return {"base": base_id, "fixed": fixed, "to_base": None, "javascript": None,
                    "text": None, "why": str(exc)}
        return {"base": base_id, "fixed": fixed, "to_base": traced["tree"],
                "javascript": traced["javascript"], "text": traced["text"], "why": why}

    def to_json(self) -> dict[str, Any]:
        """The record of ``roughdiffuse models --json`` and the explorer's ``/api/models``."""
        return {
            "id": self.id,
            "class": f"{self.cls.__module__}.{self.cls.__qualname__}",
            "label": self.label,
            "lobe": self.lobe,
            "reference": self.reference,
            "source": self.source,
            "glsl": self.glsl,
            "fixed": dict(self.fixed),
            "parameters": [p.to_json() for p in self.parameters],
            "alias": self.alias(),
        }


# ---------------------------------------------------------------------------- registering
def _check_class(cls: type) -> None:
    """Refuse a class whose declaration is incomplete or contradicts itself."""
    if not (isinstance(cls, type) and issubclass(cls, Model)):
        raise TypeError(f"register_model takes a Model subclass (got {cls!r})")
    name = cls.__qualname__
    if not cls.ids:
        raise TypeError(f"{name} declares no ids (class attribute ids = {{'my-model': {{}}}})")
    by_name = {p.name: p for p in cls.params}
    if len(by_name) != len(cls.params):
        raise TypeError(f"{name}.params names a parameter twice")
    for model_id, fixed in cls.ids.items():
        if not _ID.match(model_id):
            raise TypeError(f"{name}: id {model_id!r} is not kebab-case (e.g. 'oren-nayar-full')")
        for key, value in fixed.items():
            p = by_name.get(key)
            if p is None or not p.categorical or value not in (p.choices or ()):
                raise TypeError(f"{name}: id {model_id!r} fixes {key}={value!r}, not a choice")
    if hasattr(cls, "from_params") or not dataclasses.is_dataclass(cls):
        return
    # fields declared by param() agree with params by construction; a class that lists
    # params itself (written before param(), or in another package) is held to its fields
    fields = {f.name: f for f in dataclasses.fields(cls)}
    for p in cls.params:
        f = fields.get(p.name)
        if f is None:
            raise TypeError(f"{name}.params declares {p.name!r}, which is not a field")
        if p.when is None and f.default is not dataclasses.MISSING and f.default != p.default:
            raise TypeError(
                f"{name}.{p.name}: the field's default {f.default!r} differs from the "
                f"declared default {p.default!r}"
            )


def register_model(cls: M, *, source: str | None = None, replace: bool = False) -> M:
    """Make ``cls`` a first-class model under each of its ids; returns ``cls`` (a decorator).

    Parameters
    ----------
    cls : type
        A :class:`~roughdiffuse.models.base.Model` subclass declaring ``params`` and ``ids``.
    source : str, optional
        Where it comes from (shown by ``roughdiffuse models``); default: its module.
    replace : bool
        Allow replacing an id another class holds (else ``ValueError``).

    Raises
    ------
    TypeError
        If the declaration is incomplete (no ids, an id that is not kebab-case, a fixed value
        that is not a choice, a field default that differs from the declared one).
    ValueError
        If an id is taken by another class.
    """
    _check_class(cls)
    origin = source or cls.__module__.split(".")[0]
    with _LOCK:
        for model_id in cls.ids:
            old = _ENTRIES.get(model_id)
            if old is not None and old.cls is not cls and not replace:
                raise ValueError(
                    f"model id {model_id!r} is taken by {old.cls.__module__}."
                    f"{old.cls.__qualname__} (from {old.source})"
                )
        for model_id, fixed in cls.ids.items():
            _ENTRIES[model_id] = Entry(model_id, cls, dict(fixed), origin)
    return cls


def _register_builtins() -> None:
    from .models import builtin_classes

    for cls in builtin_classes():
        register_model(cls, source="roughdiffuse")


def _load_entry_points() -> None:
    """Register the classes other installed packages list under :data:`ENTRY_POINT_GROUP`.

    A plugin that fails to load is skipped with a warning naming it: one broken package
    must not stop the command line.
    """
    for ep in importlib.metadata.entry_points(group=ENTRY_POINT_GROUP):
        try:
            cls = ep.load()
            dist = getattr(ep, "dist", None)
            register_model(cls, source=dist.name if dist is not None else ep.value)
        except Exception as exc:  # noqa: BLE001 - report and go on
            warnings.warn(
                f"roughdiffuse: model plugin {ep.name!r} ({ep.value}) not loaded: {exc}",
                RuntimeWarning,
                stacklevel=2,
            )


def _ensure_loaded() -> None:
    global _LOADED
    if _LOADED:
        return
    with _LOCK:
        if not _LOADED:
            _register_builtins()
            _LOADED = True  # before the plugins: a plugin may read the registry
            _load_entry_points()


# ---------------------------------------------------------------------------- reading
def ids() -> list[str]:
    """Every model id, the package's own first, in declaration order."""
    _ensure_loaded()
    return list(_ENTRIES)


def entries() -> list[Entry]:
    """Every :class:`Entry`, in the order of :func:`ids`."""
    _ensure_loaded()
    return list(_ENTRIES.values())


def get(model_id: str) -> Entry:
    """The :class:`Entry` of ``model_id`` (``ValueError`` listing the ids if unknown)."""
    _ensure_loaded()
    entry = _ENTRIES.get(model_id)
    if entry is None:
        from .io.reading import short

        raise ParameterError(
            f"unknown model {short(model_id)}; choose one of: {', '.join(_ENTRIES)}"
        )
    return entry


def create(model_id: str, **params: Any) -> Model:
    """The model ``model_id`` with these parameters, e.g. ``create("eon", roughness=0.5)``."""
    return get(model_id).create(**params)


def id_of(model: Model) -> str | None:
    """The id describing ``model`` (its class and the values the id fixes), or ``None``."""
    for entry in entries():
        if entry.matches(model):
            return entry.id
    return None


def to_json() -> list[dict[str, Any]]:
    """Every model as ``roughdiffuse models --json`` prints it, one object per id."""
    return [e.to_json() for e in entries()]
