"""The installed package's version, read from its metadata on first use (a leaf module)."""

from __future__ import annotations

import functools

__all__ = ["version"]


@functools.cache
def version() -> str:
    """``roughdiffuse``'s version (``"0.0.0+unknown"`` when run from a source tree without
    install metadata). importlib.metadata is imported here, on the first call only."""
    from importlib.metadata import PackageNotFoundError
    from importlib.metadata import version as _installed

    try:
        return _installed("roughdiffuse")
    except PackageNotFoundError:  # pragma: no cover - running from a source tree
        return "0.0.0+unknown"
