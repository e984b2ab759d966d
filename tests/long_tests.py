"""Write ``tests/long_tests.txt``, the tests ``make test`` leaves to the full set, from the
JUnit XML of a run: ``python tests/long_tests.py RUN.xml [--over SECONDS]``.

Run the suite once with ``--junitxml=RUN.xml`` on a warm checkout (kernels compiled), then
this script: every test that took ``--over`` seconds or more (4 by default) is listed with
its time, and ``tests/conftest.py`` marks it ``slow``. ``make test`` leaves those out;
``make test SLOW=1`` (CI) and ``make test-all`` run them. A test not in the file runs in
``make test``, so a new test is in the quick set until the list is made again.
"""

from __future__ import annotations

import argparse
import xml.etree.ElementTree as ET
from pathlib import Path

LIST = Path(__file__).with_name("long_tests.txt")
HEADER = """\
# Tests that `make test` leaves to the full set (`make test SLOW=1`, CI, `make test-all`):
# each took {over:g} s or more in a warm run on 2 cores (seconds, then the pytest node id).
# Written by `python tests/long_tests.py RUN.xml --over {over:g}`; read by tests/conftest.py.
"""


def node_id(case: ET.Element) -> str:
    """The pytest node id of a JUnit ``testcase`` (pytest writes ``tests.test_x`` as the
    class name and the test's name with its parameters)."""
    module = case.get("classname", "").replace(".", "/")
    return f"{module}.py::{case.get('name')}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("junit", type=Path, help="JUnit XML of a warm run (pytest --junitxml)")
    ap.add_argument("--over", type=float, default=4.0, help="seconds (default 4)")
    args = ap.parse_args()
    rows = []
    for case in ET.parse(args.junit).iter("testcase"):
        seconds = float(case.get("time", 0))
        if seconds >= args.over and case.find("skipped") is None:
            rows.append((seconds, node_id(case)))
    rows.sort(key=lambda r: r[1])
    text = HEADER.format(over=args.over) + "".join(f"{s:7.1f}  {n}\n" for s, n in rows)
    LIST.write_text(text)
    print(f"{LIST}: {len(rows)} tests of {args.over:g} s or more")


if __name__ == "__main__":
    main()
