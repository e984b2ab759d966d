"""The one atomic writer (roughdiffuse.io.atomic): whole or nothing, umask, signals, bad paths."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

from roughdiffuse.io.atomic import (
    atomic_open,
    atomic_write,
    check_output_path,
    remove_stale_temporaries,
    write_bytes,
    write_text,
)
from roughdiffuse.io.images import write_npy, write_png

SRC = str(Path(__file__).resolve().parents[1] / "src")


def _with_umask(mask: int, fn):
    old = os.umask(mask)
    try:
        return fn()
    finally:
        os.umask(old)


@pytest.mark.parametrize("mask", [0o022, 0o077, 0o002])
def test_every_writer_follows_the_umask(tmp_path, mask):
    from roughdiffuse.simulate.surface import Settings
    from roughdiffuse.simulate.table import GroundTruth

    table = GroundTruth(
        *(np.zeros(1),) * 4, np.zeros((1, 1, 1, 1)), np.zeros((1, 1, 1, 1)), 1.0, 1, Settings()
    )
    writers = {
        "a.txt": lambda p: write_text(p, "x"),
        "b.npy": lambda p: write_npy(p, np.zeros((2, 2))),
        "c.png": lambda p: write_png(p, np.zeros((2, 2))),
        "d.npz": lambda p: table.save(p),
    }
    for name, write in writers.items():
        _with_umask(mask, lambda write=write, name=name: write(tmp_path / name))
        assert (tmp_path / name).stat().st_mode & 0o777 == 0o666 & ~mask, name


def test_exception_keeps_the_old_file_and_leaves_no_temporary(tmp_path):
    target = tmp_path / "keep.csv"
    target.write_text("old")

    def boom(tmp: Path) -> None:
        tmp.write_text("half")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        atomic_write(target, boom)
    with pytest.raises(RuntimeError), atomic_open(target, "w") as fh:
        fh.write("half")
        raise RuntimeError
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["keep.csv"]


def test_bad_output_paths_are_value_errors_naming_the_path(tmp_path):
    (tmp_path / "folder").mkdir()
    (tmp_path / "file").write_text("")
    with pytest.raises(ValueError, match="is a folder"):
        write_text(tmp_path / "folder", "x")
    # a parent that is a regular file: refused whatever the user (root ignores mode bits)
    with pytest.raises(ValueError, match="is not a folder"):
        write_bytes(tmp_path / "file" / "x.bin", b"x")
    with pytest.raises(ValueError, match="does not exist"):
        check_output_path(tmp_path / "nope" / "x.bin", "--table")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file", "folder"]


def _dead_pid() -> int:
    p = subprocess.Popen([sys.executable, "-c", "pass"])
    p.wait()
    return p.pid


def test_stale_temporaries_of_killed_writers_are_removed(tmp_path):
    pid = _dead_pid()
    stale = tmp_path / f".a.rdtmp-{pid}-0123abcd.txt"
    stale.write_text("")
    other = tmp_path / f".b.rdtmp-{pid}-0123abcd.txt"  # another target's: not touched
    other.write_text("")
    mine = tmp_path / f".a.rdtmp-{os.getpid()}-0123abcd.txt"  # a live process's: kept
    mine.write_text("")
    write_text(tmp_path / "a.txt", "new")
    assert not stale.exists() and other.exists() and mine.exists()
    assert remove_stale_temporaries(tmp_path / "b.txt") == [other]


def test_sigterm_during_a_write_leaves_no_temporary_file(tmp_path):
    script = textwrap.dedent(
        f"""
        import sys, time
        sys.path.insert(0, {SRC!r})
        from roughdiffuse.io.atomic import atomic_write

        def slow(tmp):
            tmp.write_bytes(b"x" * 1000)
            print("writing", flush=True)
            time.sleep(60)

        atomic_write({str(tmp_path / "out.bin")!r}, slow)
        """
    )
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().strip() == "writing"
        assert any(p.name.startswith(".out.rdtmp-") for p in tmp_path.iterdir())
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(timeout=30) == -signal.SIGTERM  # the signal still ends the process
    finally:
        proc.kill()
        proc.wait()
    time.sleep(0.05)
    assert list(tmp_path.iterdir()) == []
