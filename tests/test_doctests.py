"""The examples in the docstrings of every module of roughdiffuse run and give what they show.

Modules are found by walking the package (:func:`pkgutil.walk_packages`), so a new module's
examples are tested without being listed anywhere. A module is skipped only when an optional
dependency it imports is missing (Mitsuba 3 and Dr.Jit for the integrations).
"""

from __future__ import annotations

import doctest
import importlib
import io
import pkgutil

import pytest

import roughdiffuse

OPTIONAL = {"mitsuba", "drjit"}  # optional dependencies (pyproject's extras)


def _module_names() -> list[str]:
    names = [roughdiffuse.__name__]
    for info in pkgutil.walk_packages(roughdiffuse.__path__, prefix="roughdiffuse."):
        if not info.name.endswith(".__main__"):  # importing it runs the command line
            names.append(info.name)
    return sorted(names)


MODULES = _module_names()


def test_every_module_is_found():
    # a few modules known to carry examples, from different subpackages
    for name in ("roughdiffuse.frames", "roughdiffuse.io.atomic", "roughdiffuse.render"):
        assert name in MODULES


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    try:
        module = importlib.import_module(name)
    except ImportError as exc:
        if exc.name and exc.name.split(".")[0] in OPTIONAL:
            pytest.skip(f"{name} needs the optional dependency {exc.name}")
        raise
    tests = doctest.DocTestFinder(exclude_empty=True).find(module, name)
    tests = [t for t in tests if t.examples]
    if not tests:
        return
    out = io.StringIO()
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    for t in tests:
        runner.run(t, out=out.write)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, out.getvalue()
