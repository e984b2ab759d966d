"""The benchmark script and its CLI entry (structure and agreement only, no timing)."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def test_bench_run_writes_results_and_checks_agreement(tmp_path, monkeypatch):
    monkeypatch.setenv("ROUGHDIFFUSE_CACHE_DIR", str(tmp_path / "cache"))
    cmd = [
        sys.executable,
        str(ROOT / "bench" / "run.py"),
        "--sizes", "10",
        "--repeat", "1",
        "--no-first-call",
        "--no-render",
        "--memory-log2", "0",
        "--output-dir", str(tmp_path),
    ]  # fmt: skip
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    data = json.loads((tmp_path / "results.json").read_text())
    labels = [r["model"] for r in data["results"]]
    for name in ("Lambert", "qualitative", "full", "Fujii", "EON", "Torrance"):
        assert any(name in x for x in labels)
    for r in data["results"]:
        errors = r["max_rel_error_vs_reference"]
        assert errors["fast"] < 1e-4  # the fast path computes the reference's values
        assert errors["numpy"] == 0.0
        if shutil.which("gcc"):
            assert errors["c"] < 2e-3  # the C transcription is the same formula
            assert r["fast_over_c"] > 0
        assert r["fast"]["runs"] == 1
    text = (tmp_path / "RESULTS.md").read_text()
    assert "| 2^10 | Oren–Nayar qualitative |" in text
    assert "bench/run.py --sizes 10" in text


def test_cli_bench_rejects_bad_sizes_in_one_line():
    proc = subprocess.run(
        [sys.executable, "-m", "roughdiffuse", "bench", "--sizes", "99"],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=120,
    )
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "--sizes" in lines[0]


@pytest.mark.parametrize("bad", [["--repeat", "0"], ["--models", "nosuchmodel"]])
def test_bench_run_rejects_bad_options(bad):
    proc = subprocess.run(
        [sys.executable, str(ROOT / "bench" / "run.py"), *bad],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 2
    assert proc.stderr.strip().startswith("bench/run.py: error:")
