"""The user's configuration file: ``$XDG_CONFIG_HOME/roughdiffuse/config.toml``.

Settings that belong to the user's machine rather than to one run (where Blender's Python is)
live in one TOML file in the user's configuration home, after the XDG Base Directory
specification: ``$XDG_CONFIG_HOME`` when it is an absolute path, else ``~/.config``. A
relative ``XDG_CONFIG_HOME`` is ignored, as the specification says, and so is a home that is
not absolute: the file is never looked for in the current folder. For example::

    [blender]
    python = "/opt/blender-env/bin/python"

:func:`setting` reads one value; a file that is not valid TOML, or a value of the wrong type,
is refused naming the file (:class:`~roughdiffuse._validate.ParameterError`). Each caller
checks its own values (:func:`roughdiffuse.exporters.blender_run.blender_command` checks that
the program is an absolute path to an executable file).
"""

from __future__ import annotations

import os
import tomllib
from pathlib import Path

from ._validate import ParameterError

__all__ = ["config_path", "setting"]


def config_path() -> Path | None:
    """The configuration file's path (whether it exists or not); ``None`` when no absolute
    configuration home is known (no ``XDG_CONFIG_HOME`` and no absolute home folder)."""
    base = os.environ.get("XDG_CONFIG_HOME", "")
    if not os.path.isabs(base):
        home = os.path.expanduser("~")
        if not os.path.isabs(home):
            return None
        base = os.path.join(home, ".config")
    return Path(base) / "roughdiffuse" / "config.toml"


def setting(section: str, key: str) -> tuple[str, Path] | None:
    """The text value of ``key`` in ``[section]`` of the configuration file, with the file's
    path (for messages); ``None`` when the file, the section or the key is absent.

    Raises
    ------
    ParameterError
        If the file cannot be read or is not valid TOML, or the value is not a string.
    """
    path = config_path()
    if path is None or not path.is_file():
        return None
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except OSError as exc:
        raise ParameterError(f"{path}: cannot read ({exc.strerror or exc})") from None
    except tomllib.TOMLDecodeError as exc:
        raise ParameterError(f"{path}: not a valid TOML file ({exc})") from None
    table = data.get(section)
    if not isinstance(table, dict) or key not in table:
        return None
    value = table[key]
    if not isinstance(value, str):
        raise ParameterError(
            f"{path}: [{section}] {key} must be a string (got a {type(value).__name__})"
        )
    return value, path
