"""Blender's Python from an explicit setting only: ``--blender-python``, then
``ROUGHDIFFUSE_BLENDER_PYTHON``, then the user's configuration file (XDG), then beside the
installed package. The configuration file's path must be absolute, and neither the file nor
the program is ever looked for in the current folder."""

from __future__ import annotations

import stat
from pathlib import Path

import pytest

from roughdiffuse.cli import main
from roughdiffuse.exporters import blender_run
from roughdiffuse.user_config import config_path


def _planted(path: Path, marker: Path) -> Path:
    """An executable script at ``path`` that creates ``marker`` when run, and exits 0."""
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(f"#!/bin/sh\ntouch '{marker}'\n")
    path.chmod(path.stat().st_mode | stat.S_IXUSR)
    return path


@pytest.fixture
def home(tmp_path, monkeypatch):
    """A machine with no setting: HOME and XDG_CONFIG_HOME in tmp_path, no variable, nothing
    beside the package; the current folder is tmp_path/here."""
    home = tmp_path / "home"
    home.mkdir()
    monkeypatch.setenv("HOME", str(home))
    monkeypatch.delenv("XDG_CONFIG_HOME", raising=False)
    monkeypatch.delenv(blender_run.ENV, raising=False)
    monkeypatch.setattr(blender_run, "_beside_package", lambda: [])
    (tmp_path / "here").mkdir()
    monkeypatch.chdir(tmp_path / "here")
    blender_run.use_blender_python(None)
    yield home
    blender_run.use_blender_python(None)


def _configure(folder: Path, text: str) -> Path:
    path = folder / "roughdiffuse" / "config.toml"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


def test_the_config_file_is_in_the_xdg_config_home(home, tmp_path, monkeypatch):
    assert config_path() == home / ".config" / "roughdiffuse" / "config.toml"
    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path / "xdg"))
    assert config_path() == tmp_path / "xdg" / "roughdiffuse" / "config.toml"
    monkeypatch.setenv("XDG_CONFIG_HOME", "cfg")  # relative: ignored, as the XDG spec says
    assert config_path() == home / ".config" / "roughdiffuse" / "config.toml"


def test_blender_python_from_the_config_file(home, tmp_path):
    exe = _planted(tmp_path / "opt" / "python", tmp_path / "ran")
    _configure(home / ".config", f'[blender]\npython = "{exe}"\n')
    assert blender_run.blender_command() == [str(exe)]
    assert not (tmp_path / "ran").exists()  # found, not run


def test_a_relative_config_file_in_the_current_folder_is_never_read(home, tmp_path, monkeypatch):
    marker = tmp_path / "ran"
    exe = _planted(tmp_path / "here" / "evil" / "python", marker)
    _configure(tmp_path / "here" / "cfg", f'[blender]\npython = "{exe}"\n')
    monkeypatch.setenv("XDG_CONFIG_HOME", "cfg")
    assert blender_run.blender_command() is None
    monkeypatch.setenv("HOME", ".")  # a home that is not absolute: no config file at all
    monkeypatch.delenv("XDG_CONFIG_HOME")
    assert config_path() is None


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ('[blender]\npython = "evil/python"\n', ("[blender] python", "absolute")),
        ('[blender]\npython = "/nonexistent/python"\n', ("is not an executable file",)),
        ("[blender]\npython = 3\n", ("[blender] python must be a string",)),
        ("[blender\npython = 'x'\n", ("not a valid TOML file",)),
    ],
)
def test_a_bad_config_file_is_refused_naming_it(home, capsys, text, words):
    path = _configure(home / ".config", text)
    with pytest.raises(ValueError) as info:
        blender_run.blender_command()
    for w in (str(path), *words):
        assert w in str(info.value), info.value
    status = main(["export", "--model", "eon", "--to", "blender", "-o", "m.py"])
    err = capsys.readouterr().err
    assert status == 2 and len(err.strip().splitlines()) == 1 and str(path) in err, err
    assert not Path("m.py").exists()


def test_the_flag_comes_before_the_variable_and_the_variable_before_the_file(home, tmp_path,
                                                                            monkeypatch):
    marker = tmp_path / "ran"
    in_file, in_env, in_flag = (
        _planted(tmp_path / name / "python", marker) for name in ("file", "env", "flag")
    )
    _configure(home / ".config", f'[blender]\npython = "{in_file}"\n')
    assert blender_run.blender_command() == [str(in_file)]
    monkeypatch.setenv(blender_run.ENV, str(in_env))
    assert blender_run.blender_command() == [str(in_env)]
    blender_run.use_blender_python(in_flag)
    assert blender_run.blender_command() == [str(in_flag)]
    assert not marker.exists()


def test_export_runs_the_python_the_flag_names(home, tmp_path, capsys):
    """The named program runs (it leaves its marker); it writes no .blend, which the export
    reports in one line (exit 2)."""
    marker = tmp_path / "ran"
    exe = _planted(tmp_path / "opt" / "python", marker)
    out = tmp_path / "m.py"
    argv = ["export", "--model", "eon", "--to", "blender", "-o", str(out)]
    status = main([*argv, "--blender-python", str(exe)])
    err = capsys.readouterr().err
    assert marker.exists()
    assert status == 2 and "the .blend not" in err and len(err.strip().splitlines()) == 1, err
    assert not out.with_suffix(".blend").exists()
    # the next run without the flag does not inherit it: no Blender, the .py alone
    marker.unlink()
    assert main([*argv, "--force"]) == 0
    assert not marker.exists()


def test_a_flag_that_names_no_program_is_one_line(home, capsys):
    status = main(["export", "--model", "eon", "--to", "blender", "-o", "m.py",
                   "--blender-python", "./nothere"])  # fmt: skip
    err = capsys.readouterr().err
    assert status == 2 and "--blender-python" in err and "not an executable file" in err, err
    assert not Path("m.py").exists()


def test_the_flag_applies_only_where_blender_runs(home, capsys):
    for argv in (
        ["export", "--model", "eon", "--to", "mitsuba", "-o", "m.xml"],
        ["fit", "data:samples.csv", "--model", "eon"],
    ):
        try:
            status = main([*argv, "--blender-python", "/bin/sh"])
        except SystemExit as stop:
            status = stop.code
        err = capsys.readouterr().err
        assert status == 2 and "--blender-python" in err, err
