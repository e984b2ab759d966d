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
from collections.abc import Callable
from typing import Any, TypeVar

__all__ = ["renamed_parameter"]

F = TypeVar("F", bound=Callable[..., Any])


def renamed_parameter(old: str, new: str, since: str) -> Callable[[F], F]:
    """Let the decorated function accept keyword ``old`` as ``new`` (with a warning).

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

    def decorate(fn: F) -> F:
        @functools.wraps(fn)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            if old in kwargs:
                if new in kwargs:
                    raise TypeError(
                        f"{fn.__name__}() got both {old!r} and its new name {new!r}; give {new!r}"
                    )
                warnings.warn(
                    f"{fn.__name__}(): the keyword {old!r} is renamed {new!r} (since "
                    f"roughdiffuse {since}); {old!r} will be removed",
                    DeprecationWarning,
                    stacklevel=2,
                )
                kwargs[new] = kwargs.pop(old)
            return fn(*args, **kwargs)

        return wrapper  # type: ignore[return-value]

    return decorate
