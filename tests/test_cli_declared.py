"""The command line reads the declarations: its shorthand options and their ranges come from
each model's ``Param`` records, and it sorts errors by their type alone."""

from __future__ import annotations

import math

import pytest

from roughdiffuse import cli, registry
from roughdiffuse._validate import ParameterError, check_range
from roughdiffuse.models.declaration import Param


def _numeric_names() -> set[str]:
    return {
        p.name
        for e in registry.entries()
        for p in e.parameters
        if not p.categorical and len(p.name) > 1
    }


def _option_help(command: str, flag: str) -> str:
    parser = cli.build_parser()
    sub = parser._subparsers._group_actions[0].choices[command]  # noqa: SLF001
    for action in sub._actions:  # noqa: SLF001
        if flag in action.option_strings:
            return action.help
    raise AssertionError(f"{command} has no {flag}")


def test_every_declared_numeric_parameter_has_a_shorthand_with_its_range():
    names = _numeric_names()
    assert {"albedo", "sigma", "roughness", "eta", "alpha", "limb_darkening"} <= names
    for name in names:
        help_text = _option_help("eval", "--" + name.replace("_", "-"))
        for e in registry.entries():
            for p in e.parameters:
                if p.name != name:
                    continue
                if p.unit == "radians":  # the command line takes degrees
                    assert f"{math.degrees(p.max):g}]" in help_text and "DEGREES" in help_text
                else:
                    assert p.interval in help_text, (name, p.interval, help_text)


def test_a_shorthand_sets_the_declared_parameter_in_degrees(capsys):
    # hapke's theta_bar is declared in radians, [0, π/3]: 70 degrees is out of its range
    assert cli.main(["eval", "--model", "hapke", "--theta-bar", "70"]) == 2
    err = capsys.readouterr().err
    assert "--theta-bar" in err and "60" in err
    assert cli.main(["eval", "--model", "hapke", "--theta-bar", "20"]) == 0


def test_render_keeps_alpha_for_the_png_coverage():
    assert "coverage" in _option_help("render", "--alpha")


def test_param_check_and_check_range_refuse_alike():
    p = Param("k", "an exponent", min=0.0, max=2.0, default=1.0)
    for bad in (3.0, math.nan, True, None, "1"):
        with pytest.raises(ParameterError) as a:
            p.check(bad)
        with pytest.raises(ParameterError) as b:
            check_range("k", bad, 0.0, 2.0)
        assert str(a.value) == str(b.value)
    assert issubclass(ParameterError, ValueError)


def _with_command(monkeypatch, func):
    """Make ``roughdiffuse eval`` run ``func`` instead."""
    import roughdiffuse.commands.eval as ev

    monkeypatch.setattr(ev, "run", func)


def test_a_plain_valueerror_from_roughdiffuse_code_is_a_bug(capsys, monkeypatch):
    def buggy(args):
        raise ValueError("an internal inconsistency")  # raised here, in the command's code

    _with_command(monkeypatch, buggy)
    assert cli.main(["eval"]) == 1
    assert "internal error" in capsys.readouterr().err


def test_a_parameter_error_is_bad_input_wherever_it_is_raised(capsys, monkeypatch):
    def refuses(args):
        raise ParameterError("count must be >= 1 (got 0)")

    _with_command(monkeypatch, refuses)
    assert cli.main(["eval"]) == 2
    assert capsys.readouterr().err.strip() == "roughdiffuse eval: error: count must be >= 1 (got 0)"
