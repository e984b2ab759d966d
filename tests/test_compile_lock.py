"""Numba compilations are serialised across processes (roughdiffuse.engine.cache).

Numba's disk cache numbers a new entry from the index it read, so two processes compiling
different signatures of one kernel at once can leave an index that points at the other
signature's machine code (Numba issue 4807; ``numba/core/caching.py``,
``IndexDataCacheFile.save``). The references here are the operating system's own: a lock
held by another process refuses a non-blocking ``flock``.
"""

from __future__ import annotations

import os
import subprocess
import sys
from contextlib import contextmanager

import numpy as np
import pytest

fcntl = pytest.importorskip("fcntl", reason="the lock between processes is POSIX flock")

from roughdiffuse.engine import cache  # noqa: E402


def _try_lock(path) -> bool:
    with open(path, "a+b") as handle:
        try:
            fcntl.flock(handle.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            return False
        fcntl.flock(handle.fileno(), fcntl.LOCK_UN)
        return True


def test_the_lock_excludes_another_process(tmp_path, monkeypatch):
    folder = tmp_path / "cache"
    monkeypatch.setenv("ROUGHDIFFUSE_CACHE_DIR", str(folder))
    code = ("import sys\nfrom roughdiffuse.engine.cache import compile_lock\n"
            "with compile_lock():\n    print('held', flush=True)\n    sys.stdin.readline()\n")
    child = subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE,
                             stdout=subprocess.PIPE, text=True, env=dict(os.environ))
    try:
        assert child.stdout.readline().strip() == "held"
        assert not _try_lock(folder / "compile.lock")
        child.stdin.write("\n")
        child.stdin.flush()
        assert child.wait(timeout=60) == 0
    finally:
        child.kill()
    assert _try_lock(folder / "compile.lock")


class _Kernel:
    """A stand-in for a Numba dispatcher: the types are the values' Python types."""

    def __init__(self) -> None:
        self.overloads: dict[tuple, object] = {}
        self.compiled_inside: list[bool] = []
        self.locked = False

    def typeof_pyval(self, value):
        return type(value)

    def compile(self, signature):
        self.compiled_inside.append(self.locked)
        self.overloads[signature] = object()

    def __call__(self, *args):
        return len(args)


def test_a_new_signature_is_compiled_under_the_lock_and_once(monkeypatch):
    kernel = _Kernel()

    @contextmanager
    def lock():
        kernel.locked = True
        try:
            yield
        finally:
            kernel.locked = False

    monkeypatch.setattr(cache, "compile_lock", lock)
    run = cache.Compiled(kernel)
    assert run(1.0, np.zeros(2)) == 2
    assert run(2.0, np.ones(2)) == 2  # the same types: compiled already
    assert run(1, np.ones(2)) == 2  # a new signature
    assert kernel.compiled_inside == [True, True]


def test_a_numba_kernel_runs_through_it(tmp_path, monkeypatch):
    numba = pytest.importorskip("numba")
    monkeypatch.setenv("ROUGHDIFFUSE_CACHE_DIR", str(tmp_path / "cache"))

    @numba.njit
    def total(a, b):
        return a.sum() + b

    run = cache.Compiled(total)
    assert run(np.arange(4.0), 1.5) == 7.5
    assert run(np.arange(4, dtype=np.float32), 2) == 8.0
    assert len(total.signatures) == 2  # compiled here once each, not again by the call
