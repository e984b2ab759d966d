"""The ``roughdiffuse`` command: parses arguments and calls the library, nothing more.

Subcommands live in :mod:`roughdiffuse.commands`, one module each, each with a
``register(subparsers)`` function. Bad input (a ``ValueError`` from the library or a
:class:`~roughdiffuse.commands.UsageError`) prints one line and exits with status 2.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence

from . import __version__
from .commands import COMMANDS, UsageError

EPILOG = """\
examples:
  roughdiffuse eval --model oren-nayar --sigma 20 --albedo 0.8 --theta-i 30 --theta-r 60
  roughdiffuse models
  roughdiffuse figures -o figures/
  roughdiffuse <command> --help

Angles on the command line are in degrees; the Python API takes radians.
"""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line, status 2, no usage dump
        self.exit(2, f"{self.prog}: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every registered subcommand."""
    parser = _Parser(
        prog="roughdiffuse",
        description="Reflectance of rough matte surfaces: models, images, ground truth, fits.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"roughdiffuse {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name in COMMANDS:
        importlib.import_module(f"{__package__}.commands.{name}").register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``roughdiffuse`` console script; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 0
    try:
        return int(args.func(args) or 0)
    except (UsageError, ValueError) as exc:
        print(f"roughdiffuse {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"roughdiffuse {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
