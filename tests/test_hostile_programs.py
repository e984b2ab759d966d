"""No code runs from an untrusted place: every program roughdiffuse starts is found by an
explicit setting or beside the installed package, never in the current folder."""

from __future__ import annotations

import ast
import os
import stat
import sys
from pathlib import Path

import pytest

import roughdiffuse
from roughdiffuse import programs
from roughdiffuse.cli import main
from roughdiffuse.exporters import blender_run

SRC = Path(roughdiffuse.__file__).parent


def _planted(folder: Path, relative: str, marker: Path) -> Path:
    """An executable script at ``folder/relative`` that creates ``marker`` when run."""
    exe = folder / relative
    exe.parent.mkdir(parents=True, exist_ok=True)
    exe.write_text(f"#!/bin/sh\ntouch '{marker}'\n")
    exe.chmod(exe.stat().st_mode | stat.S_IXUSR)
    return exe


def test_export_to_blender_never_runs_the_current_folders_venv(tmp_path, monkeypatch, capsys):
    marker = tmp_path / "ran"
    _planted(tmp_path, ".venv-blender/bin/python", marker)
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv(blender_run.ENV, raising=False)
    monkeypatch.setattr(blender_run, "_beside_package", lambda: [])  # no installed Blender
    assert blender_run.blender_command() is None
    code = main(["export", "--model", "eon", "--to", "blender", "-o", str(tmp_path / "m.py")])
    assert code == 0
    assert not marker.exists()
    assert not (tmp_path / "m.blend").exists()


def test_the_venv_beside_the_package_is_found_but_not_the_one_here(tmp_path, monkeypatch):
    marker = tmp_path / "ran"
    here, installed = tmp_path / "here", tmp_path / "installed"
    _planted(here, ".venv-blender/bin/python", marker)
    exe = _planted(installed, ".venv-blender/bin/python", marker)
    monkeypatch.chdir(here)
    monkeypatch.delenv(blender_run.ENV, raising=False)
    monkeypatch.setattr(blender_run, "_beside_package", lambda: [installed])
    assert blender_run.blender_command() == [str(exe)]


def test_a_bare_program_name_is_not_found_through_a_relative_path_entry(tmp_path, monkeypatch):
    marker = tmp_path / "ran"
    _planted(tmp_path, "evilpython", marker)
    _planted(tmp_path, "bin/evilpython2", marker)
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("PATH", os.pathsep.join(["", ".", "bin", "/usr/bin", "/bin"]))
    assert programs.find_program("evilpython") is None
    assert programs.find_program("evilpython2") is None
    monkeypatch.setenv(blender_run.ENV, "evilpython")
    with pytest.raises(ValueError, match=blender_run.ENV):
        blender_run.blender_command()
    # named with its folder, it is the user's explicit choice (made absolute)
    monkeypatch.setenv(blender_run.ENV, "./evilpython")
    assert blender_run.blender_command() == [str(tmp_path / "evilpython")]
    assert not marker.exists()


def test_run_refuses_a_relative_program_and_gives_the_child_absolute_path_entries(
    tmp_path, monkeypatch
):
    monkeypatch.setenv("PATH", os.pathsep.join([".", "", "/usr/bin", "/bin", "rel/bin"]))
    with pytest.raises(ValueError, match="absolute path"):
        programs.run(["python3", "-c", "pass"])
    with pytest.raises(ValueError, match="absolute path"):
        programs.run(["./python3", "-c", "pass"])
    done = programs.run(
        [*programs.PYTHON, "-c", "import os, sys; print(os.environ['PATH']); print(sys.path[0])"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )
    path, first = done.stdout.splitlines()
    assert path == "/usr/bin:/bin"
    assert first != "" and Path(first) != tmp_path  # -P: the folder is not on sys.path


def test_the_browser_is_looked_up_on_absolute_path_entries_only(monkeypatch):
    seen = {}

    def fake_open(url):
        seen["PATH"] = os.environ["PATH"]
        return True

    import webbrowser

    from roughdiffuse.commands.explore import _open_browser

    monkeypatch.setattr(webbrowser, "open", fake_open)
    monkeypatch.setenv("DISPLAY", ":0")
    monkeypatch.setenv("PATH", os.pathsep.join([".", "/usr/bin"]))
    _open_browser("http://127.0.0.1:1/")
    assert seen["PATH"] == "/usr/bin"
    assert os.environ["PATH"] == os.pathsep.join([".", "/usr/bin"])  # restored


def test_no_module_starts_a_program_except_through_programs():
    """Every subprocess goes through roughdiffuse.programs (absolute program, trusted PATH):
    no other module imports subprocess or calls os.system/popen/exec*/spawn* or shutil.which."""
    banned_modules = {"subprocess", "pty"}
    banned_calls = {("os", "system"), ("os", "popen"), ("shutil", "which")}
    offenders = []
    for path in SRC.rglob("*.py"):
        if path == SRC / "programs.py" or path.name == "blender_scene.py":
            continue  # blender_scene runs inside Blender and starts nothing
        for node in ast.walk(ast.parse(path.read_text("utf-8"))):
            names = []
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                names = [node.module or ""]
            if any(n.split(".")[0] in banned_modules for n in names):
                offenders.append(f"{path.relative_to(SRC)}:{node.lineno}")
            if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name):
                pair = (node.value.id, node.attr)
                if pair in banned_calls or (
                    node.value.id == "os" and node.attr.startswith(("exec", "spawn", "posix_spawn"))
                ):
                    offenders.append(f"{path.relative_to(SRC)}:{node.lineno} {'.'.join(pair)}")
    assert offenders == []


def test_python_children_start_without_the_current_folder():
    assert programs.PYTHON == [sys.executable, "-P"]
