"""Mitsuba for the tests: libLLVM for the llvm variants, a variant, our plugins registered."""

from __future__ import annotations

import glob
import os
from typing import Any


def mitsuba_variant(variant: str) -> Any:
    """Import Mitsuba, set ``variant``, register roughdiffuse's plugins; return ``mitsuba``.

    Skips the calling test, with the reason, where Mitsuba or the variant is missing.

    The llvm variants need libLLVM >= 15 (``make test`` installs Debian's libllvm19 and
    exports DRJIT_LIBLLVM_PATH; this finds it when the variable is not set).
    """
    if "DRJIT_LIBLLVM_PATH" not in os.environ:
        found = sorted(
            glob.glob("/usr/lib/*/libLLVM.so.1*") + glob.glob("/usr/lib/*/libLLVM-1*.so")
        )
        if found:
            os.environ["DRJIT_LIBLLVM_PATH"] = found[-1]
    import pytest

    mi = pytest.importorskip("mitsuba", reason="Mitsuba 3 is not installed (pip install mitsuba)")
    try:
        mi.set_variant(variant)
    except (ImportError, RuntimeError, AttributeError) as exc:
        pytest.skip(f"Mitsuba variant {variant} is not available here: {exc}")
    from roughdiffuse.integrations.mitsuba import register

    register()
    return mi
