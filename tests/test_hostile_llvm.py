"""A fresh machine with only an old libLLVM: Mitsuba's llvm variants are refused with one
line naming DRJIT_LIBLLVM_PATH and the version needed, never a process abort."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from roughdiffuse.integrations.drjit_llvm import LLVM_NEEDED, llvm_problem, require_llvm

OLD_LLVM = Path("/usr/lib/x86_64-linux-gnu/libLLVM-15.so.1")


@pytest.mark.parametrize("version", [(14, 0, 6), (15, 0, 6), (18, 1, 8)])
def test_an_old_libllvm_is_refused_by_its_version(version):
    message = llvm_problem(version, "/usr/lib/libLLVM-old.so.1")
    assert message is not None and "\n" not in message
    assert "DRJIT_LIBLLVM_PATH" in message and f"libLLVM {LLVM_NEEDED}" in message
    assert ".".join(map(str, version)) in message and "/usr/lib/libLLVM-old.so.1" in message


@pytest.mark.parametrize("version", [(19, 1, 7), (20, 0, 0)])
def test_a_recent_libllvm_passes(version):
    assert llvm_problem(version) is None


def test_no_libllvm_at_all_names_the_variable(monkeypatch):
    from roughdiffuse.integrations import drjit_llvm

    monkeypatch.setattr(drjit_llvm, "drjit_llvm", lambda: (None, None))
    with pytest.raises(ValueError, match="DRJIT_LIBLLVM_PATH") as info:
        require_llvm("llvm_ad_rgb")
    assert "found none" in str(info.value)
    require_llvm("scalar_rgb")  # the scalar and cuda variants do not need it
    require_llvm("cuda_ad_rgb")
    require_llvm(None)


_SCRIPT = """
import sys
import mitsuba as mi
from roughdiffuse.integrations.mitsuba import register
from roughdiffuse.stereo.mitsuba_render import render_mitsuba
mi.set_variant("llvm_ad_rgb")
for attempt in (register, lambda: render_mitsuba({"type": "diffuse"}, [[0, 0, 1]], size=4, spp=1)):
    try:
        attempt()
    except ValueError as exc:
        print(exc)
    else:
        sys.exit("not refused")
"""


@pytest.mark.skipif(not OLD_LLVM.is_file(), reason=f"no old libLLVM here ({OLD_LLVM})")
def test_libllvm_15_refuses_the_plugins_and_stereo_renders_instead_of_aborting(tmp_path):
    """Dr.Jit pointed at libLLVM 15 (which aborts on its first kernel): the plugins' register
    and stereo's Mitsuba render each refuse in one line, and the process exits normally."""
    pytest.importorskip("mitsuba")
    src = str(Path(__file__).resolve().parent.parent / "src")
    env = {**os.environ, "DRJIT_LIBLLVM_PATH": str(OLD_LLVM), "PYTHONPATH": src}
    done = subprocess.run(
        [sys.executable, "-P", "-c", _SCRIPT],
        env=env, cwd=tmp_path, capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
    lines = done.stdout.strip().splitlines()
    assert len(lines) == 2
    for line in lines:
        assert "DRJIT_LIBLLVM_PATH" in line and "15.0" in line and f"libLLVM {LLVM_NEEDED}" in line


@pytest.mark.slow  # the gallery's render in scalar_rgb: about a minute of CPU
@pytest.mark.skipif(not OLD_LLVM.is_file(), reason=f"no old libLLVM here ({OLD_LLVM})")
def test_the_gallerys_mitsuba_example_builds_on_libllvm_15(tmp_path):
    """`make docs` on a machine with only libLLVM 15: the one page that runs Mitsuba (the
    gallery's scene) asks first, renders with scalar_rgb and ends normally (it aborted)."""
    pytest.importorskip("mitsuba")
    root = Path(__file__).resolve().parent.parent
    env = {**os.environ, "DRJIT_LIBLLVM_PATH": str(OLD_LLVM), "PYTHONPATH": str(root / "src"),
           "MPLBACKEND": "Agg"}  # fmt: skip
    done = subprocess.run(
        [sys.executable, "-P", str(root / "docs" / "gallery" / "plot_mitsuba_scene.py")],
        env=env, cwd=tmp_path, capture_output=True, text=True, timeout=900,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
    assert "variant scalar_rgb, image (64, 96)" in done.stdout
    assert "DRJIT_LIBLLVM_PATH" in done.stdout.splitlines()[0]
