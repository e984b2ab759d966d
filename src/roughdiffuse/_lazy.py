"""Deferred imports: lazy submodules, and work to do once an optional dependency is imported.

``import roughdiffuse`` imports NumPy and the models' code only; JAX, SciPy, matplotlib,
Numba and Mitsuba are imported by the functions that need them (scikit-image's
``lazy_loader`` pattern, PEP 562 module ``__getattr__``).
"""

from __future__ import annotations

import importlib
import sys
import threading
from collections.abc import Callable, Iterable
from types import ModuleType
from typing import Any

__all__ = ["attach", "when_imported"]

_LOCK = threading.RLock()
_WAITING: dict[str, list[Callable[[ModuleType], None]]] = {}


def attach(
    package: str, submodules: Iterable[str] = (), names: dict[str, str] | None = None
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """``__getattr__`` and ``__dir__`` for ``package`` that import ``submodules``, and the
    attributes ``names`` (attribute -> submodule defining it), on first use.

    Examples
    --------
    >>> __getattr__, __dir__ = attach("roughdiffuse", ["fastpath"])  # in a package's __init__
    """
    modules = set(submodules)
    attributes = dict(names or {})

    def __getattr__(name: str) -> Any:
        if name in modules:
            return importlib.import_module(f"{package}.{name}")
        if name in attributes:
            value = getattr(importlib.import_module(f"{package}.{attributes[name]}"), name)
            setattr(sys.modules[package], name, value)
            return value
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__() -> list[str]:
        return sorted(set(vars(sys.modules[package])) | modules | set(attributes))

    return __getattr__, __dir__


def when_imported(name: str, callback: Callable[[ModuleType], None]) -> None:
    """Call ``callback(module)`` now if top-level module ``name`` is imported, else right after
    its import completes (wherever it is imported from: a post-import hook, as ``wrapt``'s).

    Used to register the models as JAX pytrees without importing JAX: a model passed to
    ``jax.jit`` or ``jax.grad`` must be registered before any roughdiffuse code runs.
    """
    with _LOCK:
        module = sys.modules.get(name)
        if module is None or _initialising(module):
            first = name not in _WAITING
            _WAITING.setdefault(name, []).append(callback)
            if first:
                sys.meta_path.insert(0, _PostImportFinder(name))
            return
    callback(module)


def _initialising(module: ModuleType) -> bool:
    spec = getattr(module, "__spec__", None)
    return bool(getattr(spec, "_initializing", False))


def _run(name: str, module: ModuleType) -> None:
    with _LOCK:
        callbacks = _WAITING.pop(name, [])
    for callback in callbacks:
        callback(module)


class _PostImportFinder:  # an importlib.abc.MetaPathFinder, by duck typing (import cost)
    """Finds nothing itself: wraps the loader the other finders return for one module name,
    so that the waiting callbacks run once that module is executed; then removes itself."""

    def __init__(self, name: str) -> None:
        self.name = name

    def find_spec(self, fullname: str, path: Any, target: Any = None) -> Any:
        if fullname != self.name:
            return None
        with _LOCK:
            if self in sys.meta_path:
                sys.meta_path.remove(self)
        spec = None
        for finder in list(sys.meta_path):
            find = getattr(finder, "find_spec", None)
            spec = find(fullname, path, target) if find else None
            if spec is not None:
                break
        if spec is None or spec.loader is None:
            return spec
        spec.loader = _PostImportLoader(spec.loader, fullname)
        return spec


class _PostImportLoader:  # an importlib.abc.Loader
    def __init__(self, loader: Any, name: str) -> None:
        self.loader = loader
        self.name = name

    def create_module(self, spec: Any) -> ModuleType | None:
        return self.loader.create_module(spec)

    def exec_module(self, module: ModuleType) -> None:
        module.__loader__ = self.loader
        if module.__spec__ is not None:
            module.__spec__.loader = self.loader  # leave no trace once imported
        self.loader.exec_module(module)
        _run(self.name, module)

    def __getattr__(self, attr: str) -> Any:  # get_resource_reader, is_package, ...
        return getattr(self.loader, attr)
