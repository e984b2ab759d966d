"""Every registry model declares its formula (``Model.formula``) and the symbol of each of its
parameters (``Model.symbols``): the site's model pages are generated from them."""

from __future__ import annotations

import re
import textwrap

import pytest

from roughdiffuse import registry


def _formula(entry: registry.Entry) -> str:
    text = entry.cls.formula
    return textwrap.dedent(text.get(entry.id, "") if isinstance(text, dict) else text)


@pytest.mark.parametrize("entry", registry.entries(), ids=lambda e: e.id)
def test_model_declares_a_typeset_formula(entry: registry.Entry) -> None:
    text = _formula(entry)
    blocks = re.findall(r"```\{math\}\n(.*?)\n```", text, flags=re.S)
    assert blocks, f"{entry.id}: no math block in its formula"
    assert all(b.count("{") == b.count("}") for b in blocks), entry.id  # balanced LaTeX
    latex = " ".join(blocks) + " " + " ".join(re.findall(r"\{math\}`([^`]*)`", text))
    for p in entry.parameters:
        if p.choices is not None or p.name in entry.fixed:
            continue  # a choice selects the formula, it is not a symbol in it
        symbol = entry.cls.symbols.get(p.name)
        assert symbol, f"{entry.id}: parameter {p.name!r} has no symbol"
        assert symbol in latex, f"{entry.id}: {symbol!r} ({p.name}) is not in the formula"
