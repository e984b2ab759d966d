"""Blender's own Python, run as a separate process: the ``.blend`` export and the Blender check.

The ``bpy`` wheel (Blender as a Python module) pins its own NumPy, so it lives in a virtual
environment of its own (``make install-blender`` makes ``.venv-blender``), and roughdiffuse
runs it as a subprocess on :mod:`roughdiffuse.exporters.blender_scene`. Where it is found
(:func:`blender_command`):

1. the command line's ``--blender-python PATH`` (:func:`use_blender_python`);
2. the environment variable ``ROUGHDIFFUSE_BLENDER_PYTHON``;
3. ``python`` in the ``[blender]`` table of the user's configuration file
   (:mod:`roughdiffuse.user_config`: ``~/.config/roughdiffuse/config.toml``), an absolute
   path;
4. the environment ``make install-blender`` creates beside the installed package:
   ``.venv-blender/bin/python`` in the source checkout roughdiffuse is imported from, or
   beside the virtual environment it is installed in (``.venv`` and ``.venv-blender`` side
   by side).

Each of 1-3 names a Python with ``bpy``, or a ``blender`` executable (run as ``blender
--background --python ...``), and must be an executable file: a setting that names none is
refused, naming where it came from. Never from the current folder: a ``.venv-blender``
there is not run (no code runs from an untrusted place, :mod:`roughdiffuse.programs`).
"""

from __future__ import annotations

import json
import os
import shutil
import sys
import tempfile
from pathlib import Path
from typing import Any

from .._validate import ParameterError
from ..io.atomic import atomic_write
from ..programs import TimeoutExpired, find_program, run

__all__ = [
    "ENV",
    "BlenderError",
    "blender_command",
    "check_blend",
    "run_scene",
    "use_blender_python",
    "write_blend",
]

ENV = "ROUGHDIFFUSE_BLENDER_PYTHON"
"""The environment variable naming Blender's Python (or a ``blender`` executable)."""

SCENE = Path(__file__).with_name("blender_scene.py")
_VENV = Path(".venv-blender") / "bin" / "python"


class BlenderError(RuntimeError):
    """Blender's process failed (its last lines of output are in the message)."""


def _beside_package() -> list[Path]:
    """The folders where ``make install-blender`` leaves ``.venv-blender`` for this package:
    the source checkout it is imported from, and the folder holding its virtual environment."""
    roots = []
    checkout = Path(__file__).resolve().parents[3]
    if (checkout / "pyproject.toml").is_file():
        roots.append(checkout)
    if sys.prefix != sys.base_prefix:  # installed in a virtual environment
        roots.append(Path(sys.prefix).resolve().parent)
    return roots


_chosen: list[str] = []  # the --blender-python of this process (use_blender_python)


def use_blender_python(path: str | os.PathLike[str] | None) -> None:
    """Use ``path`` as Blender's Python in this process, before every other setting (the
    command line's ``--blender-python``); ``None`` forgets it. Checked when it is used
    (:func:`blender_command`)."""
    _chosen[:] = [] if path is None else [os.fspath(path)]


def _command(exe: str) -> list[str]:
    if Path(exe).name.startswith("blender"):
        return [exe, "--background", "--factory-startup", "--python-exit-code", "1", "--python"]
    return [exe]


def _setting() -> tuple[str, str, bool] | None:
    """(value, where it comes from, whether it must be absolute) of the first setting given."""
    from ..user_config import setting

    if _chosen:
        return _chosen[0], "--blender-python", False
    named = os.environ.get(ENV, "").strip()
    if named:
        return named, ENV, False
    configured = setting("blender", "python")
    if configured is not None:
        value, path = configured
        return value, f"{path}: [blender] python", True
    return None


def blender_command() -> list[str] | None:
    """The command that runs a script with ``bpy`` (``None`` where none is found): from the
    first of ``--blender-python``, ``ROUGHDIFFUSE_BLENDER_PYTHON`` and the configuration file
    that is given, else from beside the package (see the module).

    Raises
    ------
    ParameterError
        If the setting used names no executable file, or the configuration file's is not an
        absolute path (it would be looked for from the current folder).
    """
    given = _setting()
    if given is not None:
        value, origin, absolute = given
        if absolute and not os.path.isabs(os.path.expanduser(value)):
            raise ParameterError(f"{origin} must be an absolute path (got {value!r})")
        exe = find_program(value)
        if exe is None:
            raise ParameterError(f"{origin}: {value!r} is not an executable file")
        return _command(exe)
    for root in _beside_package():
        candidate = root / _VENV
        if candidate.is_file() and os.access(candidate, os.X_OK):
            return [str(candidate)]
    return None


def run_scene(material: Path, jobs: list[dict[str, Any]], timeout: float = 900.0) -> None:
    """Run :mod:`~roughdiffuse.exporters.blender_scene` on the exported script ``material``
    with these jobs (see that module for their fields).

    Raises
    ------
    BlenderError
        If no Blender interpreter is found, or its process fails or times out.
    """
    command = blender_command()
    if command is None:
        raise BlenderError(
            f"no Blender interpreter: run `make install-blender`, give --blender-python or "
            f"set {ENV}"
        )
    with tempfile.TemporaryDirectory(prefix="roughdiffuse-blender-") as tmp:
        request = Path(tmp) / "request.json"
        request.write_text(
            json.dumps({"material": str(Path(material).resolve()), "jobs": jobs}), "utf-8"
        )
        args = [*command, str(SCENE)] + (["--"] if len(command) > 1 else []) + [str(request)]
        try:
            # Blender's Python has its own packages (NumPy 1.26): none of this process's paths
            done = run(
                args, capture_output=True, text=True, timeout=timeout, cwd=tmp,
                drop_env=("PYTHONPATH", "PYTHONHOME"),
            )  # fmt: skip
        except (OSError, TimeoutExpired) as exc:
            raise BlenderError(f"Blender ({command[0]}) did not run: {exc}") from None
    if done.returncode != 0:
        tail = "\n".join((done.stdout + done.stderr).strip().splitlines()[-12:])
        raise BlenderError(f"Blender ({command[0]}) failed with status {done.returncode}:\n{tail}")


BLEND_MAGIC = (b"BLENDER", b"\x28\xb5\x2f\xfd", b"\x1f\x8b")
"""How a ``.blend`` file starts: its header ``BLENDER``, or compressed (``compress=True``,
which the export uses) the Zstandard magic number (Blender 3.0 and later) or gzip's."""


def check_blend(path: Path) -> None:
    """Check that Blender wrote a ``.blend`` file at ``path`` (:data:`BLEND_MAGIC`; not an
    empty file).

    Raises
    ------
    BlenderError
        Naming what was found instead.
    """
    try:
        with open(path, "rb") as fh:
            head = fh.read(len(BLEND_MAGIC[0]))
    except OSError as exc:  # raised outside: the writer must not take it for its own error
        problem = exc.strerror or str(exc)
    else:
        problem = None
    if problem is not None:
        raise BlenderError(f"Blender exited normally but wrote no .blend file ({problem})")
    if not head.startswith(BLEND_MAGIC):
        found = "an empty file" if not head else f"a file starting {head!r}"
        raise BlenderError(f"Blender exited normally but wrote {found}, not a .blend file")


def write_blend(material: Path, path: Path) -> Path:
    """Save the material of the exported script ``material``, on a unit sphere under a sun
    seen by an orthographic camera (the scene of the Blender check), as the ``.blend`` file
    ``path`` (written whole or not at all).

    Raises
    ------
    BlenderError
        If no Blender interpreter is found, Blender fails, or what it wrote is not a
        ``.blend`` file (:func:`check_blend`): then nothing is written at ``path``.
    """

    def save(tmp: Path) -> None:
        job = {"kind": "blend", "shape": "sphere", "light": [-0.5, 0.5, 0.70710678]}
        # Blender saves into a folder of its own: what else it writes there (a backup
        # NAME.blend1 of a file it saves over) goes with the folder, never beside the target
        with tempfile.TemporaryDirectory(prefix="roughdiffuse-blend-") as own:
            saved = Path(own) / "scene.blend"
            run_scene(material, [{**job, "size": 256, "samples": 64, "output": str(saved)}])
            check_blend(saved)  # a child that exits 0 may still have written nothing
            shutil.copyfile(saved, tmp)

    return atomic_write(path, save)
