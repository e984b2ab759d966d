"""Every example line in every command's ``--help`` runs as printed (exit status 0).

The lines are read from the parsers' epilogs (continuation lines joined, ``# comments``
dropped, ``*`` expanded as a shell would) and run in order in an empty folder, so a line may
use the files an earlier one wrote (``render --lights ... -o stack/`` then ``stereo
stack/*.npy``). Two commands are only parsed: ``explore`` serves until Ctrl-C, and ``bench``
takes minutes (its harness has its own tests in tests/test_bench.py).
"""

from __future__ import annotations

import glob
import shlex

import pytest

from roughdiffuse.cli import build_parser, main

PARSE_ONLY = {"explore", "bench"}
SLOW = {"", "render", "plot", "figures", "fit", "albedo", "simulate", "stereo"}
"""Commands whose examples render, fit or solve (seconds to minutes each): run by
``make test-all``; the quick ones (eval, models, data) run in every test run."""


def _examples(text: str) -> list[list[str]]:
    lines, current = [], ""
    for raw in (text or "").splitlines():
        s = raw.strip()
        if current:
            current += " " + s.rstrip("\\").strip()
            if not s.endswith("\\"):
                lines.append(current)
                current = ""
        elif s.startswith("roughdiffuse ") and "<" not in s and "`" not in s:
            if s.endswith("\\"):
                current = s.rstrip("\\").strip()
            else:
                lines.append(s)
    return [shlex.split(line, comments=True) for line in lines]


def _epilogs() -> dict[str, str]:
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    out = {"": parser.epilog or ""}
    out.update({name: p.epilog or "" for name, p in sub.choices.items()})
    return out


def _cases() -> list:
    cases = []
    for name, epilog in _epilogs().items():
        marks = [pytest.mark.slow] if name in SLOW else []
        cases.append(pytest.param(name, epilog, id=name or "roughdiffuse", marks=marks))
    return cases


def test_every_command_has_examples() -> None:
    for name, epilog in _epilogs().items():
        assert _examples(epilog), f"{name or 'roughdiffuse'} --help shows no example"


@pytest.mark.parametrize(("name", "epilog"), _cases())
def test_help_examples_run_as_printed(name, epilog, tmp_path, monkeypatch, capsys) -> None:  # noqa: ANN001
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("ROUGHDIFFUSE_DATA_DIR", str(tmp_path / "cache"))
    for argv in _examples(epilog):
        assert argv[0] == "roughdiffuse"
        args = [m for a in argv[1:] for m in (sorted(glob.glob(a)) if "*" in a else [a])]
        if args and args[0] in PARSE_ONLY:
            build_parser().parse_args(args)
            continue
        try:
            code = main(args)
        except SystemExit as exc:  # --help, --version
            code = exc.code
        err = capsys.readouterr().err
        assert code == 0, f"{' '.join(argv)} exited {code}: {err}"
