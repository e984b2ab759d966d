"""The one JSON writer: what roughdiffuse writes as JSON is always valid JSON.

Python's :func:`json.dumps` writes ``NaN``, ``Infinity`` and ``-Infinity`` for non-finite
floats, which JSON (RFC 8259) does not have and strict readers (browsers' ``JSON.parse``,
``jq``) refuse. :func:`dumps` writes ``null`` for them instead, turns NumPy scalars and
arrays into numbers and lists, and refuses anything else it cannot write.

>>> dumps({"sigma": 0.3, "standard_error": float("inf"), "n": [1.0, float("nan")]})
'{"sigma": 0.3, "standard_error": null, "n": [1.0, null]}'
"""

from __future__ import annotations

import json
import math
import os
from typing import Any

__all__ = ["dumps", "write_json"]


def _clean(obj: Any) -> Any:
    if isinstance(obj, bool) or obj is None or isinstance(obj, str | int):
        return obj
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {str(k) if not isinstance(k, str) else k: _clean(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_clean(v) for v in obj]
    tolist = getattr(obj, "tolist", None)  # NumPy scalars and arrays
    if callable(tolist):
        return _clean(tolist())
    raise TypeError(f"cannot write {type(obj).__name__} as JSON")


def dumps(obj: Any, **kwargs: Any) -> str:
    """``json.dumps(obj, **kwargs)`` with ``null`` for NaN and infinities (valid JSON)."""
    return json.dumps(_clean(obj), allow_nan=False, **kwargs)


def write_json(path: str | os.PathLike[str], obj: Any, **kwargs: Any) -> Any:
    """Write ``obj`` as valid JSON to ``path``, whole or not at all; return the path."""
    from .atomic import write_text

    return write_text(path, dumps(obj, **kwargs) + "\n")
