"""docs/implementations.md's table of other renderers' diffuse is generated from the
declarations (docs/_ext/rd_implementations.py); the committed page must be up to date, and
its numbers for Cycles and MaterialX must equal those of the hand-checked table above it
(whose values tests/test_implementations.py computes from the transcribed sources)."""

from __future__ import annotations

import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parents[1] / "docs"
sys.path.insert(0, str(DOCS / "_ext"))

import rd_implementations  # noqa: E402


def test_the_generated_section_is_up_to_date():
    text = (DOCS / "implementations.md").read_text(encoding="utf-8")
    assert rd_implementations.render(text) == text, "run the docs build (make docs) and commit"


def test_generated_rows_repeat_the_checked_values():
    section = rd_implementations.section()
    assert "| 0.3993 | 0.1489 | 0.2331 | 0.1124 |" in section  # Cycles EON row, checked table
    assert "| 0.4018 | 0.2070 | 0.2357 | 0.2221 |" in section  # MaterialX EON node row
    assert "| 0.4018 | 0.1513 | 0.2357 | 0.1125 |" in section  # roughdiffuse EON row (OpenPBR)
