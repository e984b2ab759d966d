"""Renamed keyword arguments keep working for a while, with a ``DeprecationWarning``.

After scikit-image's deprecation helpers: the function is written with the new name only,
and a decorator maps the old one.

>>> import warnings
>>> @renamed_parameter("theta_o", "theta_r", since="0.2")
... def view(theta_r):
...     return theta_r
>>> with warnings.catch_warnings(record=True) as caught:
...     warnings.simplefilter("always")
...     view(theta_o=0.5), caught[0].category.__name__
(0.5, 'DeprecationWarning')
"""

from __future__ import annotations

import functools
import warnings
from collections.abc import Callable, Mapping
from typing import Any, TypeVar

__all__ = ["rename_keywords", "renamed_keywords", "renamed_parameter"]

F = TypeVar("F", bound=Callable[..., Any])

_RENAMED: dict[Any, dict[str, tuple[str, str]]] = {}
"""Decorated function or class -> {old keyword: (new keyword, version that renamed it)}."""


def renamed_parameter(old: str, new: str, since: str) -> Callable[[F], F]:
    """Let the decorated function, or class (its constructor), accept keyword ``old`` as
    ``new`` (with a warning).

    Parameters
    ----------
    old, new : str
        The former and the current keyword.
    since : str
        The roughdiffuse version that renamed it (named in the warning).

    Raises
    ------
    TypeError
        At call time, if both ``old`` and ``new`` are given.
    """

    def decorate(obj: F) -> F:
        if isinstance(obj, type):  # a class: its constructor, and the table others read
            _RENAMED[obj] = {**_RENAMED.get(obj, {}), old: (new, since)}
            init = obj.__init__

            @functools.wraps(init)
            def init_wrapper(self: Any, *args: Any, **kwargs: Any) -> None:
                init(self, *args, **rename_keywords(obj, kwargs, f"{obj.__name__}()"))

            obj.__init__ = init_wrapper  # type: ignore[misc]
            return obj
        _RENAMED[obj] = {**_RENAMED.get(obj, {}), old: (new, since)}

        @functools.wraps(obj)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            return obj(*args, **rename_keywords(obj, kwargs, f"{obj.__name__}()"))

        _RENAMED[wrapper] = _RENAMED[obj]
        return wrapper  # type: ignore[return-value]

    return decorate


def renamed_keywords(obj: Any) -> dict[str, str]:
    """Old keyword -> new keyword of a function or class :func:`renamed_parameter` decorated
    (a class's base classes included); ``{}`` for any other.

    >>> from roughdiffuse.models.hapke import Hapke
    >>> renamed_keywords(Hapke)
    {'g': 'xi'}
    """
    return {old: new for old, (new, _) in _table(obj).items()}


def _table(obj: Any) -> dict[str, tuple[str, str]]:
    """{old: (new, since)} of ``obj`` (a class's base classes first)."""
    owners = obj.__mro__[::-1] if isinstance(obj, type) else (obj,)
    return {k: v for o in owners for k, v in _RENAMED.get(o, {}).items()}


def rename_keywords(
    obj: Any, values: Mapping[str, Any], where: str, stacklevel: int = 2
) -> dict[str, Any]:
    """``values`` with each old keyword of ``obj`` replaced by its new one, with a
    ``DeprecationWarning`` naming ``where`` (e.g. ``"Hapke()"`` or ``"--param g"``) for each.

    Raises
    ------
    TypeError
        If both an old keyword and its new one are given.
    """
    out = dict(values)
    for old, (new, since) in _table(obj).items():
        if old not in out:
            continue
        if new in out:
            raise TypeError(f"{where} got both {old!r} and its new name {new!r}; give {new!r}")
        warnings.warn(
            f"{where}: the keyword {old!r} is renamed {new!r} (since roughdiffuse {since}); "
            f"{old!r} will be removed",
            DeprecationWarning,
            stacklevel=stacklevel + 1,
        )
        out[new] = out.pop(old)
    return out
