"""Rule: nothing the user typed is silently ignored. Conflicting flags, flags that do not
apply to the chosen output, a parameter set twice, duplicated axis values and numbers that
would overflow later are refused with one line naming them (exit status 2)."""

from __future__ import annotations

import argparse

import pytest

from roughdiffuse.cli import build_parser, main
from roughdiffuse.commands import UsageError, _conflicts


def run(argv: list[str]) -> int:
    """``main(argv)``, with argparse's own refusals (SystemExit) as their status."""
    try:
        return main(argv)
    except SystemExit as exc:
        return int(exc.code)


@pytest.mark.parametrize(
    ("argv", "named"),
    [
        (["eval", "--param", "sigma=10", "--sigma", "30"], ("--sigma", "--param sigma")),
        (["eval", "--param", "sigma=10", "--param", "sigma=20"], ("--param sigma",)),
        (["render", "--bits", "16", "--alpha", "-o", "{tmp}/x.npy"], ("--bits", ".png")),
        (["render", "--bits", "8", "-o", "{tmp}/x.exr"], ("--bits",)),  # typed default too
        (["render", "--alpha", "-o", "{tmp}/x.npy"], ("--alpha",)),
        (["render", "--light", "30,0", "--light-theta", "20", "-o", "{tmp}/x.png"], ("--light",)),
        (
            ["plot", "plane", "--light", "30,0", "--light-phi", "9", "-o", "{tmp}/p.png"],
            ("--light",),
        ),
        (["fit", "{tmp}/d.csv", "--compare", "--model", "lambert"], ("--compare", "--model")),
        (["fit", "{tmp}/d.csv", "--shape", "sphere"], ("--shape", "image")),
        (["fit", "{tmp}/d.npy", "--exposure", "2"], ("--exposure", ".png")),
        (["albedo", "--variance", "-o", "{tmp}/a.png"], ("--variance", "--output")),
        (["albedo", "--variance", "--table", "{tmp}/a.csv"], ("--variance", "--table")),
        (["albedo", "--model", "lambert", "--roughness", "2"], ("--roughness", "lambert")),
        (["albedo", "--model", "eon", "--roughness", "2"], ("--roughness", "2")),
        (["simulate", "--table", "{tmp}/t.npz", "--report"], ("--table", "--report")),
        (["simulate", "--table", "{tmp}/t.npz", "--theta-i", "10"], ("--table", "--theta-i")),
        (["simulate", "--step", "5"], ("--step", "--table")),
        (["simulate", "--sigma", "20,20"], ("--sigma", "20")),
        (["simulate", "--table", "{tmp}/t.npz", "--step", "0.001"], ("--step 0.001", "memory")),
        (["simulate", "--table", "{tmp}/t.npy", "--sigma", "20"], ("--table", ".npz")),
        (["stereo", "--demo", "--lights", "l.json", "-o", "{tmp}/o"], ("--demo", "--lights")),
        (["figures", "--only", "", "-o", "{tmp}/f"], ("--only",)),
        (["fit", "{tmp}/d.png", "--exposure", "1e308"], ("--exposure", "64")),
        (["fit", "{tmp}/d.csv", "--loss", "cauchy", "--f-scale", "1e308"], ("--f-scale",)),
    ],
)
def test_ignored_or_conflicting_input_is_refused(argv, named, tmp_path, capsys):
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    assert run(argv) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1, err
    for text in named:
        assert text in err, err
    assert sorted(tmp_path.iterdir()) == []  # nothing written, nothing left


MINIMAL = {
    "render": ["-o", "x.npy"],
    "plot": ["plane", "-o", "x.png"],
    "fit": ["d.csv"],
    "albedo": [],
    "simulate": [],
    "stereo": ["-o", "o"],
    "figures": [],
    "export": ["--model", "eon", "--to", "mitsuba", "-o", "x.xml"],
}
OTHER_MODE = {
    "plot": ["cross-section", "-o", "x.png"],
    "stereo": ["--method", "l1", "-o", "o"],
}
"""A mode of the command where an AppliesOnly rule of its minimal mode does not hold."""
"""A command line of each command on which no conditional flag applies."""


def _rules():
    for command, rules in _conflicts.RULES.items():
        for k, rule in enumerate(rules):
            # the id names the flags, not the rule's repr (a lambda's address differs between
            # pytest-xdist workers, which must collect the same ids)
            flags = "+".join(getattr(rule, "flags", None) or (rule.first, rule.second))
            yield pytest.param(command, rule, id=f"{command}:{type(rule).__name__}:{k}:{flags}")


@pytest.mark.parametrize(("command", "rule"), list(_rules()))
def test_every_declared_pair_is_refused(command, rule, monkeypatch):
    """Each declaration of the table, checked as if the user had typed its flags."""
    parser = build_parser()
    sub = _conflicts._subparser(parser, command)
    flags = (rule.first, rule.second) if isinstance(rule, _conflicts.Conflict) else rule.flags
    for flag in flags:
        assert flag in sub._option_string_actions, f"{command} has no {flag}"
    argv = [command, *MINIMAL[command]]
    args = parser.parse_args(argv)
    if isinstance(rule, _conflicts.AppliesOnly) and rule.when(args):
        # the minimal command is a mode where the flags apply: take one where they do not
        argv = [command, *OTHER_MODE[command]]
        args = parser.parse_args(argv)
        assert not rule.when(args), f"no mode of {command} where {flags} do not apply"
    for flag in flags:
        typed = frozenset(
            {sub._option_string_actions[flag].dest}
            | (
                {sub._option_string_actions[f].dest for f in flags}
                if isinstance(rule, _conflicts.Conflict)
                else set()
            )
        )
        monkeypatch.setattr(_conflicts, "given_options", lambda *a, typed=typed: typed)
        with pytest.raises(UsageError, match=flag):
            _conflicts.check_options(parser, args, argv)
        if isinstance(rule, _conflicts.Conflict):
            break


def test_only_typed_flags_count(tmp_path):
    parser = build_parser()
    argv = ["render", "-o", str(tmp_path / "x.npy"), "--sigma", "20"]
    typed = _conflicts.given_options(parser, argv, "render")
    assert {"output", "sigma"} <= typed and "bits" not in typed and "alpha" not in typed
    args = parser.parse_args(argv)
    _conflicts.check_options(parser, args, argv)  # no error: --bits left at its default
    assert args.bits == 8  # and the defaults are back after the second parse
    assert _conflicts.given(argparse.Namespace()) == frozenset()
