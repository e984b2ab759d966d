"""The ``roughdiffuse`` command: exit codes and messages, through a subprocess."""

from __future__ import annotations

import math
import subprocess
import sys

import pytest


def run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "roughdiffuse", *args], capture_output=True, text=True, timeout=120
    )


def test_version_and_help():
    out = run("--version")
    assert out.returncode == 0 and out.stdout.startswith("roughdiffuse ")
    out = run("--help")
    assert out.returncode == 0 and "examples:" in out.stdout and "eval" in out.stdout


def test_eval_prints_lecture_value():
    """Head-on Oren-Nayar: f = ρ A / π with A = 1 - 0.5 σ²/(σ² + 0.33)."""
    out = run("eval", "--model", "oren-nayar", "--sigma", "30", "--albedo", "0.8")
    assert out.returncode == 0, out.stderr
    s2 = math.radians(30) ** 2
    expected = 0.8 * (1 - 0.5 * s2 / (s2 + 0.33)) / math.pi
    line = next(x for x in out.stdout.splitlines() if x.startswith("brdf"))
    assert float(line.split(":")[1]) == pytest.approx(expected, abs=1e-6)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["eval", "--model", "phong"], "unknown model 'phong'"),
        (["eval", "--sigma", "120"], "--sigma must be in [0, 90] degrees"),
        (["eval", "--albedo", "1.5"], "albedo must be in [0, 1]"),
        (["eval", "--albedo", "0.1,0.2"], "albedo must have 1 or 3 values"),
        (["eval", "--theta-i", "95"], "--theta-i must be in [0, 90] degrees"),
        # a value just beyond the range is shown as given, not rounded into it
        (["eval", "--theta-i", "90.0000001"], "(got 90.0000001)"),
        (["eval", "--model", "eon", "--roughness", "2"], "roughness must be in [0, 1]"),
        (["frobnicate"], "invalid choice"),
    ],
)
def test_bad_arguments_exit_2_without_traceback(args, message):
    out = run(*args)
    assert out.returncode == 2
    assert message in out.stderr
    assert "Traceback" not in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1
