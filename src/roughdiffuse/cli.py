"""The ``roughdiffuse`` command: parses arguments and calls the library, nothing more.

Subcommands live in :mod:`roughdiffuse.commands`, one module each, each with a
``register(subparsers)`` function.

Errors are sorted by whose they are (:func:`classify`):

* the user's (exit status 2, one line): a :class:`~roughdiffuse.commands.UsageError`, a
  :class:`~roughdiffuse._validate.ParameterError` (every refusal of a value by roughdiffuse's
  own code, naming the parameter), an ``OSError`` (a file or folder that cannot be read or
  written, a full disk), a ``MemoryError``;
* anything else is a bug (exit status 1): it says so and where, and ``--debug`` (or
  ``ROUGHDIFFUSE_DEBUG=1``) prints the traceback. A plain ``ValueError`` (from NumPy, SciPy,
  JAX or roughdiffuse) is a bug too, not bad input.

The sorting looks at the exception's type only.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import os
import sys
import traceback
import warnings
from collections.abc import Iterator, Sequence
from typing import Any

from ._env import env_flag
from ._validate import ParameterError
from ._version import version
from .commands import COMMANDS, UsageError
from .commands._conflicts import check_options
from .io.reading import clip_echo

EPILOG = """\
examples:
  roughdiffuse eval --model oren-nayar --sigma 20 --albedo 0.8 --theta-i 30 --theta-r 60
  roughdiffuse models
  roughdiffuse figures -o figures/
  roughdiffuse <command> --help

Bad input prints one line and exits with status 2; an internal error (a bug) exits with
status 1 and says where; --debug prints its traceback.

Angles on the command line are in degrees; the Python API takes radians.
"""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line, status 2, no usage dump
        self.exit(2, clip_echo(f"{self.prog}: error: {message}") + "\n")

    def _get_value(self, action: argparse.Action, arg_string: str) -> Any:
        # every option's value passes here: an empty one (-o "", --report "") is refused,
        # never taken as "not given" (an empty output name would write to the default place)
        if action.option_strings and not arg_string.strip() and action.default != "":
            what = action.metavar or action.dest.upper()
            raise argparse.ArgumentError(action, f"empty value; give {what}")
        return super()._get_value(action, arg_string)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every registered subcommand."""
    parser = _Parser(
        prog="roughdiffuse",
        description="Reflectance of rough matte surfaces: models, images, ground truth, fits.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"roughdiffuse {version()}")
    parser.add_argument(
        "--debug", action="store_true", help="print the traceback of any error (for bug reports)"
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name in COMMANDS:
        importlib.import_module(f"{__package__}.commands.{name}").register(sub)
    for p in sub.choices.values():  # `roughdiffuse CMD --debug` works too
        p.add_argument(
            "--debug", action="store_true", default=argparse.SUPPRESS, help=argparse.SUPPRESS
        )
    return parser


def classify(exc: BaseException) -> str | None:
    """The one-line message for a user error, or None for an internal error (a bug)."""
    if isinstance(exc, UsageError | ParameterError):
        return str(exc)
    if isinstance(exc, OSError):
        what = exc.strerror or str(exc) or type(exc).__name__
        if exc.filename is not None:
            return f"{os.fsdecode(exc.filename)!r}: {what}"
        return what
    if isinstance(exc, MemoryError):
        return "not enough memory for this job; ask for less (a smaller size or count)"
    return None


def _where(exc: BaseException) -> str:
    frames = traceback.extract_tb(exc.__traceback__)
    if not frames:
        return ""
    f = frames[-1]
    return f" at {f.filename}:{f.lineno} in {f.name}"


def report_error(exc: BaseException, prog: str, debug: bool) -> int:
    """Print ``exc`` for the user and return the exit status: 2 for a user error, 1 for a
    bug."""
    message = classify(exc)
    if debug:
        traceback.print_exception(exc, file=sys.stderr)
    if message is not None:
        print(clip_echo(f"{prog}: error: {message}"), file=sys.stderr)
        return 2
    hint = "" if debug else "; rerun with --debug for the traceback"
    print(
        f"{prog}: internal error (a bug in roughdiffuse {version()}, please report it): "
        + clip_echo(f"{type(exc).__name__}: {exc}{_where(exc)}{hint}"),
        file=sys.stderr,
    )
    return 1


@contextlib.contextmanager
def deprecations_shown(prog: str) -> Iterator[None]:
    """roughdiffuse's own ``DeprecationWarning``s (a renamed parameter, say) shown as one line
    each, ``<prog>: warning: …``: Python hides them outside ``__main__``."""
    with warnings.catch_warnings():
        warnings.filterwarnings("always", category=DeprecationWarning, module=r"roughdiffuse\b")
        others = warnings.showwarning

        def show(message: Any, category: type[Warning], *args: Any, **kwargs: Any) -> None:
            if issubclass(category, DeprecationWarning):
                print(f"{prog}: warning: {message}", file=sys.stderr)
            else:
                others(message, category, *args, **kwargs)

        warnings.showwarning = show
        yield


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``roughdiffuse`` console script; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 0
    prog = f"roughdiffuse {args.command}"
    try:
        debug = bool(args.debug) or env_flag("ROUGHDIFFUSE_DEBUG")
        env_flag("ROUGHDIFFUSE_FASTPATH", default=True)  # read by the models: refused here first
    except ValueError as exc:
        print(clip_echo(f"{prog}: error: {exc}"), file=sys.stderr)
        return 2
    try:
        check_options(parser, args, argv)  # conflicting or inapplicable flags: exit 2
        with deprecations_shown(prog):
            return int(args.func(args) or 0)
    except KeyboardInterrupt:
        print(f"{prog}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError as exc:
        if exc.filename is not None:
            return report_error(exc, prog, debug)
        # whoever read the output went away (`roughdiffuse models | head -1`): stop quietly,
        # with the status of a process killed by SIGPIPE, and no flush error at exit
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 128 + 13
    except Exception as exc:  # noqa: BLE001 - sorted into user errors and bugs
        return report_error(exc, prog, debug)
    finally:
        from .io.atomic import allow_replacing

        allow_replacing(None)  # the outputs this command kept are its own business only


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
