"""The equation numbers a model's formula cites, and what its page says about checking them
(docs/_ext/rd_pages.py: ``CHECKED_EQUATION_NUMBERS``, ``equation_note``)."""

from __future__ import annotations

import sys
from pathlib import Path

from roughdiffuse import registry

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "docs" / "_ext"))

import rd_pages  # noqa: E402

ENTRIES = {entry.id: entry for entry in registry.entries()}


def test_every_checked_id_is_a_model_whose_formula_cites_numbers() -> None:
    """A checked entry names a registered model and a formula with equation numbers (a typo in
    the id, or a formula that lost its numbers, would leave a note nobody sees)."""
    assert rd_pages.CHECKED_EQUATION_NUMBERS
    for model_id, how in rd_pages.CHECKED_EQUATION_NUMBERS.items():
        assert model_id in ENTRIES, model_id
        assert rd_pages.EQUATION_NUMBER.search(rd_pages.formula_of(ENTRIES[model_id])), model_id
        note = rd_pages.equation_note(ENTRIES[model_id])
        assert note.endswith(how) and "not checked" not in note, note


def test_unchecked_numbers_say_so() -> None:
    note = rd_pages.equation_note(ENTRIES["oren-nayar-full"])
    assert "oren-nayar-full" not in rd_pages.CHECKED_EQUATION_NUMBERS
    assert note.startswith("Equation numbers (Eq. 27; Eq. 31):") and "**not checked**" in note


def test_burley_2015_cites_its_diffuse_equation_only() -> None:
    """The 2015 notes' diffuse (Lambertian part and retro-reflection) is their Eq. (4); Eq. (5)
    is the subsurface diffusion profile (pbrt-v3, src/materials/disney.cpp: DisneyDiffuse and
    DisneyRetro cite "Burley 2015, eq (4)", DisneyBSSRDF::Sr "Burley 2015, eq (5)")."""
    note = rd_pages.equation_note(ENTRIES["burley-2015"])
    assert note.startswith("Equation numbers (Eq. 4):"), note
