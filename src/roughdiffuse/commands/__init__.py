"""Subcommands of the ``roughdiffuse`` CLI, one module each.

To add a command, write ``commands/NAME.py`` with ``register(subparsers)`` (which adds a
parser and sets ``func``) and add ``NAME`` to :data:`COMMANDS`.
"""

COMMANDS: list[str] = [
    "eval",
    "models",
    "explore",
    "render",
    "plot",
    "figures",
    "fit",
    "albedo",
    "simulate",
    "stereo",
    "bench",
    "photometry",
    "data",
    "convert",
    "export",
]


class UsageError(Exception):
    """Bad command-line input: printed as one line, exit status 2."""
