"""``fit ... --export TARGETS``: the exporters' targets named on the command line, and the
files written after a fit (``PREFIX_TARGET.suffix``, one set per target)."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from . import UsageError

__all__ = [
    "BLENDER_PYTHON_HELP",
    "add_blender_python",
    "export_errors",
    "export_model",
    "export_paths",
    "parse_targets",
    "quiet_backend_warnings",
    "use_blender_python_flag",
]


@contextmanager
def quiet_backend_warnings() -> Iterator[None]:
    """The exporters' backend warnings left to the summary a command prints (one line each),
    not repeated by Python's warning machinery."""
    import warnings

    from ..exporters.common import BackendWarning

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", BackendWarning)
        yield


@contextmanager
def export_errors(path: Path, option: str, target: str, write_option: str) -> Iterator[None]:
    """An exporter's refusals as one-line ``UsageError`` s: a model the target cannot hold
    (``option target: ...``), a file that cannot be written (``write_option: ...``), and a
    Blender process that failed after the script was written."""
    from ..exporters.blender_run import BlenderError

    try:
        yield
    except BlenderError as exc:
        last = str(exc).strip().splitlines()[-1]
        raise UsageError(f"{option} blender: {path} written, the .blend not: {last}") from None
    except ValueError as exc:
        raise UsageError(f"{option} {target}: {exc}") from None
    except OSError as exc:
        raise UsageError(
            f"{write_option}: cannot write {str(path)!r}: {exc.strerror or exc}") from None


def parse_targets(text: str, option: str = "--export") -> list[str]:
    """The comma-separated targets of ``text``, each one of
    :data:`roughdiffuse.exporters.TARGETS` (a ``UsageError`` naming the unknown one)."""
    from ..exporters import TARGETS
    from ._inputs import suggest

    targets = [t.strip().lower() for t in text.split(",") if t.strip()]
    if not targets:
        raise UsageError(f"{option}: name one or more of: {', '.join(TARGETS)}")
    for t in targets:
        if t not in TARGETS:
            raise UsageError(
                f"{option}: unknown target {t!r}{suggest(t, TARGETS)}; choose from: "
                f"{', '.join(TARGETS)}"
            )
    return list(dict.fromkeys(targets))


def export_paths(
    prefix: str, targets: list[str], option: str = "--export-prefix", *, force: bool = False
) -> dict:
    """The file of each target: ``PREFIX_TARGET`` with the target's suffix. Checked before
    any work: the folder (a ``UsageError`` if it is missing), and every file each target may
    write (:func:`roughdiffuse.exporters.planned_files`), none replaced unless ``force``."""
    from ..exporters import TARGETS, planned_files
    from ._checks import output_file

    base = Path(prefix)
    if base.name in ("", ".", ".."):
        raise UsageError(f"{option}: give a file name prefix (got {prefix!r})")
    if not base.parent.is_dir():
        raise UsageError(f"{option}: folder {str(base.parent)!r} does not exist")
    paths = {t: base.with_name(f"{base.name}_{t}{TARGETS[t][0]}") for t in targets}
    for target, path in paths.items():
        for file in planned_files(None, target, path):
            output_file(file, force=force, option=f"--export {target}")
    return paths


def export_model(model: Any, paths: dict, say: Callable[..., Any] = print) -> None:
    """Write ``model`` for each target in ``paths``; print each summary with ``say``."""
    from ..exporters import export

    for target, path in paths.items():
        errors = export_errors(path, "--export", target, f"--export {target}")
        with errors, quiet_backend_warnings():
            result = export(model, target, path)
        say(result.summary())


BLENDER_PYTHON_HELP = (
    "Blender's Python (with bpy) or a blender executable, for the .blend; without it: "
    "ROUGHDIFFUSE_BLENDER_PYTHON, else `python` under [blender] in "
    "~/.config/roughdiffuse/config.toml ($XDG_CONFIG_HOME), else the .venv-blender that "
    "`make install-blender` makes beside roughdiffuse (never one in the current folder)"
)


def add_blender_python(parser: Any) -> None:
    """The ``--blender-python PATH`` option of the commands that run Blender."""
    parser.add_argument("--blender-python", metavar="PATH", help=BLENDER_PYTHON_HELP)


def use_blender_python_flag(args: Any) -> None:
    """Apply ``--blender-python`` (before the files are planned: whether a ``.blend`` is
    written depends on it); a path that is not an executable file is a ``UsageError``.
    Without the flag, an earlier run's choice in this process is forgotten."""
    from ..exporters.blender_run import blender_command, use_blender_python

    path = getattr(args, "blender_python", None)
    use_blender_python(path)
    if path is None:
        return
    try:
        blender_command()
    except ValueError as exc:
        raise UsageError(str(exc)) from None
