"""The MaterialX document of an exported ``.mtlx``, ready for MaterialX's shader generators
(shared by tests/test_export.py and tests/test_export_materialx_glsl.py)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest


def load_document(path: Path) -> tuple[Any, Any, Any]:
    """``(MaterialX, document, search path)``: the file read, the standard data libraries
    attached, and the document validated by MaterialX (an assertion with its message).
    Skips the test when the ``materialx`` package is not installed."""
    mx = pytest.importorskip(
        "MaterialX", reason="materialx is not installed (pip install materialx)"
    )
    doc = mx.createDocument()
    mx.readFromXmlFile(doc, str(path))
    lib = mx.createDocument()
    search = mx.getDefaultDataSearchPath()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), search, lib)
    doc.setDataLibrary(lib)
    valid, message = doc.validate()
    assert valid, message
    return mx, doc, search
