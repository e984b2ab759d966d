"""The one parser of roughdiffuse's boolean environment variables.

``ROUGHDIFFUSE_DEBUG`` and ``ROUGHDIFFUSE_FASTPATH`` are read by :func:`env_flag`: ``1``,
``true``, ``yes``, ``on`` mean on and ``0``, ``false``, ``no``, ``off`` (or empty) mean off,
in any case and with spaces around; unset means the default. Anything else is a
``ValueError`` naming the variable, never a guess (``ROUGHDIFFUSE_DEBUG=false`` is off).

>>> import os
>>> os.environ["ROUGHDIFFUSE_EXAMPLE"] = " False "
>>> env_flag("ROUGHDIFFUSE_EXAMPLE", default=True)
False
"""

from __future__ import annotations

import os

from ._validate import ParameterError

__all__ = ["FALSE", "TRUE", "env_flag"]

TRUE = frozenset({"1", "true", "yes", "on"})
FALSE = frozenset({"", "0", "false", "no", "off"})


def env_flag(name: str, default: bool = False) -> bool:
    """The boolean environment variable ``name`` (``default`` when unset).

    Raises
    ------
    ValueError
        If it is set to something other than the words above.
    """
    raw = os.environ.get(name)
    if raw is None:
        return default
    word = raw.strip().lower()
    if word in TRUE:
        return True
    if word in FALSE:
        return False
    shown = raw if len(raw) <= 20 else raw[:20] + "…"
    raise ParameterError(
        f"{name} must be one of 1, true, yes, on (on) or 0, false, no, off (off); got {shown!r}"
    )
