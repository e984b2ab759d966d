"""``python -m build`` makes a wheel and an sdist; the wheel holds the explorer's static
files, the GLSL and the sample data, and, installed into a fresh virtual environment, runs the
command line.

The fresh environment resolves the dependencies offline from the running interpreter's
site-packages (a ``.pth`` line naming them, after the environment's own site-packages), and
the wheel is installed with ``--no-deps``; the tests run outside the checkout so that
``roughdiffuse`` can only come from the wheel. Marked ``packaging``.
"""

from __future__ import annotations

import os
import site
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import pytest

pytest.importorskip("build")
pytestmark = pytest.mark.packaging
ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def dist(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("dist")
    # --no-isolation: nothing downloaded, the build backend (setuptools) from this environment
    proc = subprocess.run(
        [sys.executable, "-m", "build", "--no-isolation", "--sdist", "--wheel",
         "--outdir", str(out), str(ROOT)],
        capture_output=True, text=True, timeout=600,
    )
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    return out


def _wheel(dist: Path) -> Path:
    (wheel,) = dist.glob("roughdiffuse-*.whl")
    return wheel


def test_wheel_and_sdist_are_built(dist: Path) -> None:
    import tomllib

    version = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    assert _wheel(dist).name.startswith(f"roughdiffuse-{version}-py3-none-any")
    assert list(dist.glob(f"roughdiffuse-{version}.tar.gz"))


def test_wheel_holds_static_files_glsl_and_data(dist: Path) -> None:
    names = set(zipfile.ZipFile(_wheel(dist)).namelist())
    src = ROOT / "src"
    expected = [
        p.relative_to(src).as_posix()
        for folder in ("roughdiffuse/explorer/static", "roughdiffuse/data")
        for p in (src / folder).rglob("*")
        if p.is_file() and "__pycache__" not in p.parts
    ]
    assert any(n.endswith(".glsl") or "/glsl/" in n for n in expected)
    missing = sorted(set(expected) - names)
    assert not missing, missing


@pytest.fixture(scope="module")
def venv(dist: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    env_dir = tmp_path_factory.mktemp("venv") / "env"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(env_dir)], check=True,
                   timeout=120)
    py = env_dir / "bin" / "python"
    purelib = subprocess.run(
        [str(py), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
        capture_output=True, text=True, check=True,
    ).stdout.strip()
    clean = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    proc = subprocess.run(
        [sys.executable, "-m", "pip", "--python", str(py), "install", "--no-deps",
         "--no-index", "--ignore-installed", str(_wheel(dist))],
        capture_output=True, text=True, timeout=300, env=clean,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert list(Path(purelib).glob("roughdiffuse-*.dist-info")), proc.stdout[-2000:]
    # dependencies from this interpreter's site-packages (plain path lines: its .pth files,
    # e.g. an editable install of the checkout, are not run)
    deps = [sysconfig.get_paths()["purelib"], *site.getsitepackages()]
    Path(purelib, "_roughdiffuse_test_deps.pth").write_text(
        "\n".join(dict.fromkeys(deps)) + "\n", encoding="utf-8"
    )
    return env_dir


def _run(venv: Path, *args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    env["MPLBACKEND"] = "Agg"
    return subprocess.run([str(venv / "bin" / "roughdiffuse"), *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=600)


def test_installed_wheel_runs_the_command_line(venv: Path, tmp_path: Path) -> None:
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    where = subprocess.run(
        [str(venv / "bin" / "python"), "-c",
         "import roughdiffuse, roughdiffuse.data as d; print(roughdiffuse.__file__); "
         "print(d.path('samples.csv').is_file())"],
        cwd=tmp_path, env=env, capture_output=True, text=True, check=True,
    ).stdout.split()
    assert where[0].startswith(str(venv)), where  # the wheel's copy, not the checkout
    assert where[1] == "True"

    models = _run(venv, "models", cwd=tmp_path)
    assert models.returncode == 0 and "oren-nayar-full" in models.stdout, models.stderr
    explore = _run(venv, "explore", "--help", cwd=tmp_path)
    assert explore.returncode == 0 and "usage" in explore.stdout
    figures = _run(venv, "figures", "--only", "1", "--no-progress", "-o", str(tmp_path / "f"),
                   cwd=tmp_path)
    assert figures.returncode == 0, figures.stderr[-2000:]
    assert list((tmp_path / "f").glob("*.png"))
