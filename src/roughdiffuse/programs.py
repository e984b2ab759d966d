"""The one way roughdiffuse finds and starts another program: never from the current folder.

Rule: no code runs from an untrusted place. The current folder is untrusted (a downloaded
archive, a shared drive): a program found there, or through a relative entry of ``PATH``
(``.``, an empty entry, ``bin``), is never started. Every program the toolkit starts goes
through :func:`run`, which takes an absolute path (from :func:`find_program`, an explicit
setting such as ``ROUGHDIFFUSE_BLENDER_PYTHON``, or :data:`PYTHON`) and gives the child a
``PATH`` of absolute entries only (:func:`trusted_path`). ``tests/test_hostile_programs.py``
checks that no other module of the package calls :mod:`subprocess`.

>>> trusted_path("/usr/bin::.:bin:/bin")
'/usr/bin:/bin'
"""

from __future__ import annotations

import contextlib
import os
import shutil
import subprocess
import sys
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

__all__ = ["PYTHON", "find_program", "run", "trusted_environ", "trusted_path"]

PYTHON = [sys.executable, "-P"]
"""How roughdiffuse starts Python: this interpreter, and ``-P`` keeps the current folder off
``sys.path`` (a ``numpy.py`` or ``roughdiffuse/`` there is not imported)."""


def trusted_path(path: str | None = None) -> str:
    """``path`` (default: ``$PATH``) without its relative entries, which name the current
    folder (``.``, empty) or folders inside it (``bin``)."""
    raw = os.environ.get("PATH", os.defpath) if path is None else path
    return os.pathsep.join(p for p in raw.split(os.pathsep) if p and os.path.isabs(p))


def find_program(name: str) -> str | None:
    """The absolute path of the program ``name`` on :func:`trusted_path` (``None`` if absent).

    A name with a folder in it is not searched: it is returned, made absolute, only if it is
    an executable file (an explicit setting by the user).
    """
    if os.sep in name or (os.altsep and os.altsep in name):
        candidate = Path(name).expanduser().absolute()
        ok = candidate.is_file() and os.access(candidate, os.X_OK)
        return str(candidate) if ok else None
    found = shutil.which(name, path=trusted_path())
    return str(Path(found).absolute()) if found else None


def child_environ(extra: Mapping[str, str] | None = None, drop: Sequence[str] = ()) -> dict:
    """This process's environment for a child: :func:`trusted_path` as ``PATH``, ``extra``
    added, the names in ``drop`` removed."""
    env = {k: v for k, v in os.environ.items() if k not in drop}
    env["PATH"] = trusted_path()
    env.update(extra or {})
    return env


def run(
    args: Sequence[str],
    *,
    env: Mapping[str, str] | None = None,
    drop_env: Sequence[str] = (),
    **kwargs: Any,
) -> subprocess.CompletedProcess:
    """:func:`subprocess.run` of ``args`` (a list: no shell), whose program ``args[0]`` must
    be an absolute path; the child's environment is :func:`child_environ` of ``env``.

    Raises
    ------
    ValueError
        If ``args[0]`` is not an absolute path (it would be looked up from the current folder).
    """
    if not args or not os.path.isabs(args[0]):
        raise ValueError(
            f"a program is started by its absolute path, not {str(args[0] if args else '')!r}"
        )
    child = child_environ(env, drop_env)
    return subprocess.run(list(args), env=child, check=kwargs.pop("check", False), **kwargs)  # noqa: S603 - a list, absolute program


def start(
    args: Sequence[str],
    *,
    env: Mapping[str, str] | None = None,
    **kwargs: Any,
) -> subprocess.Popen:
    """:class:`subprocess.Popen` of ``args`` under the rules of :func:`run` (absolute
    program, the child's environment from :func:`child_environ`), for a caller that watches
    the child while it runs."""
    if not args or not os.path.isabs(args[0]):
        raise ValueError(
            f"a program is started by its absolute path, not {str(args[0] if args else '')!r}"
        )
    return subprocess.Popen(list(args), env=child_environ(env), **kwargs)  # noqa: S603 - a list, absolute program


@contextlib.contextmanager
def trusted_environ() -> Iterator[None]:
    """Within the block, this process's ``PATH`` is :func:`trusted_path` (for a library that
    looks programs up itself, such as :mod:`webbrowser`)."""
    saved = os.environ.get("PATH")
    os.environ["PATH"] = trusted_path()
    try:
        yield
    finally:
        if saved is None:
            os.environ.pop("PATH", None)
        else:
            os.environ["PATH"] = saved


TimeoutExpired = subprocess.TimeoutExpired
"""Raised by :func:`run` when its ``timeout`` passes (callers need not import subprocess)."""
