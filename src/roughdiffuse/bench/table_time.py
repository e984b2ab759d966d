"""Wall time and total CPU time of one ``roughdiffuse simulate --table`` run (bench/RESULTS.md).

Runs the command given after ``--`` in a subprocess and polls its whole process tree with
psutil (the Dask nanny and worker processes included) once a second, keeping each process's
last user + system CPU time; a process that ends between two polls loses at most one second.
On a shared machine the wall time is inflated by other jobs; the CPU seconds are not, and
CPU / 2 is the wall time the run would take on 2 idle cores.

Usage (the 90 × 90 × 180 all-bounce table of one σ, as measured in bench/RESULTS.md)::

    python -m roughdiffuse.bench.table_time -- roughdiffuse simulate --table /tmp/gt.npz \\
        --step 1 --delta-phi-step 1 --sigma 17.1887 --albedo 0.8 --workers 2 --no-progress
    python bench/table_time.py -- ...   # the same, from a checkout
"""

from __future__ import annotations

import json
import os
import sys
import time

import psutil

from ..programs import find_program


def main(argv: list[str]) -> int:
    if "--" not in argv:
        print(__doc__)
        return 2
    cmd = argv[argv.index("--") + 1 :]
    env = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
    start = time.perf_counter()
    program = cmd[0] if os.path.isabs(cmd[0]) else find_program(cmd[0])
    if program is None:
        print(f"table_time: {cmd[0]!r} not found on PATH")
        return 2
    proc = start([program, *cmd[1:]], env=env)
    root = psutil.Process(proc.pid)
    cpu: dict[int, tuple[str, float]] = {}
    while proc.poll() is None:
        try:
            tree = [root, *root.children(recursive=True)]
        except psutil.NoSuchProcess:
            break
        for p in tree:
            try:
                t = p.cpu_times()
                cpu[p.pid] = (" ".join(p.cmdline()[:3])[:80], t.user + t.system)
            except (psutil.NoSuchProcess, psutil.AccessDenied):
                pass
        time.sleep(1.0)
    wall = time.perf_counter() - start
    total = sum(c for _, c in cpu.values())
    print(
        json.dumps(
            {
                "command": " ".join(cmd),
                "returncode": proc.returncode,
                "wall_s": round(wall, 1),
                "cpu_s": round(total, 1),
                "cpu_s_over_2": round(total / 2, 1),
                "processes": {str(k): [n, round(c, 1)] for k, (n, c) in cpu.items()},
                "load_average_end": os.getloadavg(),
            },
            indent=1,
        )
    )
    return proc.returncode


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
