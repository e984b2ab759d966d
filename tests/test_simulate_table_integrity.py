"""Ground-truth tables lose nothing and adopt nothing: killed runs, corrupt, swapped
and NaN chunks, two runs on one table, a finished table kept, bad output paths."""

from __future__ import annotations

import hashlib
import json
import os
import signal
import subprocess
import sys
import textwrap
import warnings
from pathlib import Path

import numpy as np
import pytest

import roughdiffuse.simulate.table as table_mod
from roughdiffuse.cli import main
from roughdiffuse.simulate import compute_table, load_table
from roughdiffuse.simulate.table import TableBusyError, read_chunk

SRC = str(Path(__file__).resolve().parents[1] / "src")
TI = np.radians([0.0, 30.0, 60.0, 85.0])
TR = np.radians([10.0, 50.0, 80.0])
DP = np.radians([0.0, 180.0])
SIG = np.array([0.2, 0.4])
KW = dict(albedo=0.8, bounces=1, rows_per_chunk=1, progress=False, backend="numpy")


def _table(path, **kw):
    return compute_table(path, TI, TR, DP, SIG, **{**KW, **kw})


def _start_run_that_stops(path: Path, after: int) -> subprocess.Popen:
    """A run in another process that writes ``after`` chunks, says so, then hangs."""
    script = textwrap.dedent(
        f"""
        import sys, time
        sys.path.insert(0, {SRC!r})
        import numpy as np
        import roughdiffuse.simulate.table as t

        real, n = t._write_chunk, []

        def write(*a):
            real(*a)
            n.append(1)
            if len(n) == {after}:
                print("stopped", flush=True)
                time.sleep(120)

        t._write_chunk = write
        t.compute_table({str(path)!r}, np.array({TI.tolist()}), np.array({TR.tolist()}),
                        np.array({DP.tolist()}), np.array({SIG.tolist()}), **{KW!r})
        """
    )
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    assert proc.stdout.readline().strip() == "stopped"
    return proc


def _flip_a_bit_in_values(chunk: Path) -> None:
    """Flip one bit inside the stored values array (not in a zip header)."""
    blob = bytearray(chunk.read_bytes())
    member = blob.index(b"values.npy")
    magic = blob.index(b"\x93NUMPY", member)
    header_len = int.from_bytes(blob[magic + 8 : magic + 10], "little")
    blob[magic + 10 + header_len + 5] ^= 0x10
    chunk.write_bytes(bytes(blob))


def test_killed_corrupted_swapped_run_equals_an_uninterrupted_one(tmp_path):
    path = tmp_path / "gt.npz"
    chunks = tmp_path / "gt.npz.chunks"
    proc = _start_run_that_stops(path, after=5)
    try:
        # a second run on the same table is refused, naming the running process
        with pytest.raises(TableBusyError, match=f"process {proc.pid} "):
            _table(path)
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=30)
    finally:
        proc.kill()
        proc.wait()
    names = sorted(p.name for p in chunks.glob("s*.npz"))
    assert names == ["s000_r0000.npz", "s000_r0001.npz", "s000_r0002.npz", "s000_r0003.npz"] + [
        "s001_r0000.npz"
    ]
    assert not path.exists()
    _flip_a_bit_in_values(chunks / "s000_r0001.npz")
    a, b = chunks / "s000_r0002.npz", chunks / "s000_r0003.npz"
    a.rename(tmp_path / "swap")
    b.rename(a)
    (tmp_path / "swap").rename(b)
    spec = {"key": "x", "sigma_index": 0, "sigma": 0.2, "row": 1, "theta_i": TI[1:2]}
    with pytest.raises(ValueError, match="s000_r0001.npz is unreadable.*CRC"):
        read_chunk(chunks / "s000_r0001.npz", {**spec, "theta_r": TR, "delta_phi": DP})

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        resumed = _table(path)  # the lock of the killed run does not block
    bad = sorted(str(w.message).split()[1].rsplit("/", 1)[1] for w in caught)
    assert bad == ["s000_r0001.npz", "s000_r0002.npz", "s000_r0003.npz"]
    fresh = _table(tmp_path / "fresh.npz")
    np.testing.assert_array_equal(resumed.values, fresh.values)
    np.testing.assert_array_equal(resumed.k_difference, fresh.k_difference)
    assert np.array_equal(load_table(path).values, fresh.values)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fresh.npz", "gt.npz"]


def _rewrite_chunk(chunk: Path, values: np.ndarray, meta_changes: dict) -> None:
    with np.load(chunk) as z:
        meta = json.loads(str(z["meta"]))
        kdiff = z["k_difference"]
    meta.update(meta_changes)
    meta["sha256"] = hashlib.sha256(
        np.ascontiguousarray(values, "<f8").tobytes() + np.ascontiguousarray(kdiff, "<f8").tobytes()
    ).hexdigest()
    np.savez(chunk, values=values, k_difference=kdiff, meta=np.array(json.dumps(meta)))


def test_nan_other_albedo_and_wrong_shape_chunks_are_not_adopted(tmp_path, monkeypatch):
    path = tmp_path / "gt.npz"
    real = table_mod.compute_chunk
    n = []

    def stop(spec):
        n.append(spec["name"])
        if len(n) > 4:
            raise KeyboardInterrupt
        return real(spec)

    monkeypatch.setattr(table_mod, "compute_chunk", stop)
    with pytest.raises(KeyboardInterrupt):
        _table(path)
    monkeypatch.setattr(table_mod, "compute_chunk", real)
    chunks = path.with_name("gt.npz.chunks")
    good = np.load(chunks / "s000_r0000.npz")["values"]
    _rewrite_chunk(chunks / "s000_r0000.npz", np.full_like(good, np.nan), {})  # valid checksum
    _rewrite_chunk(chunks / "s000_r0001.npz", good[:, :1], {})  # wrong shape
    # a chunk of a run with another albedo, left without its manifest (as a crashed run leaves)
    other = tmp_path / "other.npz"
    n.clear()
    monkeypatch.setattr(table_mod, "compute_chunk", stop)
    with pytest.raises(KeyboardInterrupt):
        _table(other, albedo=0.5)
    monkeypatch.setattr(table_mod, "compute_chunk", real)
    (chunks / "s000_r0002.npz").unlink()
    (other.with_name("other.npz.chunks") / "s000_r0002.npz").rename(chunks / "s000_r0002.npz")
    (chunks / "manifest.json").unlink()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        t = _table(path)
    text = " ".join(str(w.message) for w in caught)
    assert "s000_r0000.npz holds non-finite values" in text
    assert "s000_r0001.npz has shape (1, 1, 2), expected (1, 3, 2)" in text
    assert "s000_r0002.npz belongs to a table with other settings" in text
    np.testing.assert_array_equal(t.values, _table(tmp_path / "fresh.npz").values)


def test_finished_table_is_kept_and_replaced_only_with_force(tmp_path, capsys, monkeypatch):
    path = tmp_path / "o.npz"
    real = table_mod.compute_chunk
    args = ["simulate", "--table", str(path), "--step", "45", "--delta-phi-step", "180"]
    args += ["--bounces", "1", "--backend", "numpy", "--no-progress"]
    assert main([*args, "--sigma", "10,20"]) == 0
    before = path.read_bytes()

    def fail(spec):
        raise AssertionError("a finished table was recomputed")

    monkeypatch.setattr(table_mod, "compute_chunk", fail)
    capsys.readouterr()
    assert main([*args, "--sigma", "10,20"]) == 0  # same settings: kept, nothing computed
    assert "kept" in capsys.readouterr().out and path.read_bytes() == before
    assert main([*args, "--sigma", "10"]) == 2  # a smaller table does not replace it
    err = capsys.readouterr().err
    assert "already holds a finished table with another sigma" in err and "--force" in err
    assert "Traceback" not in err and path.read_bytes() == before
    monkeypatch.setattr(table_mod, "compute_chunk", real)
    assert main([*args, "--sigma", "10", "--force"]) == 0
    assert load_table(path).values.shape == (3, 3, 2, 1)


def test_unusable_table_paths_are_refused_before_any_work(tmp_path, capsys, monkeypatch):
    def fail(spec):
        raise AssertionError("computed before checking the output path")

    monkeypatch.setattr(table_mod, "compute_chunk", fail)
    (tmp_path / "dir").mkdir()
    (tmp_path / "file").write_text("")
    for target, message in (
        (tmp_path / "dir", "is a folder"),
        (tmp_path / "file" / "t.npz", "is not a folder"),  # parent a regular file
        (tmp_path / "none" / "t.npz", "does not exist"),
    ):
        assert main(["simulate", "--table", str(target), "--step", "45", "--no-progress"]) == 2
        err = capsys.readouterr().err
        assert message in err and "Traceback" not in err
    assert sorted(os.listdir(tmp_path)) == ["dir", "file"]
