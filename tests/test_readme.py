"""Every snippet of the README runs as written.

The README's fenced blocks are extracted and run in a fresh temporary folder, each in its own
subprocess with this checkout's ``src`` first on ``PYTHONPATH``:

* a ``python`` block runs as a script; a block preceded by the comment ``<!-- continues -->``
  continues the previous ``python`` block (they run together, as one script, in the order
  they appear);
* a ``sh`` block runs line by line; every command in it must be a ``roughdiffuse ...``
  command (run as ``python -m roughdiffuse ...``) and must exit with status 0;
* a block preceded by ``<!-- not run: REASON -->`` is not run (``make``, ``pip install``, a
  server that runs until Ctrl-C); the reason must be stated;
* a block preceded by ``<!-- needs: mitsuba -->`` is skipped when Mitsuba 3 is missing.

A failure shows the block's first line and the process's output.
"""

from __future__ import annotations

import importlib.util
import os
import re
import shlex
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
_FENCE = re.compile(
    r"(?:^<!--[ \t]*(?P<marker>[^\n]*?)[ \t]*-->\n)?^```(?P<lang>\w*)\n(?P<body>.*?)^```",
    re.M | re.S,
)


@dataclass
class Block:
    lang: str
    body: str
    line: int
    marker: str = ""
    parts: list[str] = field(default_factory=list)  # a python chain: its blocks in order

    @property
    def label(self) -> str:
        first = self.body.strip().splitlines()[0] if self.body.strip() else ""
        return f"README.md:{self.line} {first[:50]}"


def _blocks() -> list[Block]:
    text = README.read_text(encoding="utf-8")
    out = []
    for m in _FENCE.finditer(text):
        line = text.count("\n", 0, m.start("body"))
        out.append(Block(m["lang"], m["body"], line, (m["marker"] or "").strip()))
    return out


def _runnable() -> list[Block]:
    """Python chains (continued blocks merged into the block they continue) and sh blocks."""
    out: list[Block] = []
    last_python: Block | None = None
    for b in _blocks():
        if b.lang == "python":
            if b.marker == "continues":
                assert last_python is not None, f"{b.label}: continues nothing"
                last_python.parts.append(b.body)
                continue
            b.parts = [b.body]
            last_python = b
            out.append(b)
        elif b.lang in ("sh", "bash", "shell"):
            out.append(b)
    return out


BLOCKS = _runnable()


def _env() -> dict[str, str]:
    path = os.pathsep.join(filter(None, [str(ROOT / "src"), os.environ.get("PYTHONPATH")]))
    return {**os.environ, "PYTHONPATH": path, "MPLBACKEND": "Agg",
            "ROUGHDIFFUSE_NO_BROWSER": "1"}


def _skip_if_marked(block: Block) -> None:
    if block.marker.startswith("not run"):
        reason = block.marker.partition(":")[2].strip()
        assert reason, f"{block.label}: a block that is not run must say why"
        pytest.skip(f"not run: {reason}")
    if block.marker.startswith("needs:"):
        for module in block.marker.partition(":")[2].split(","):
            if importlib.util.find_spec(module.strip()) is None:
                pytest.skip(f"{module.strip()} is not installed")
    elif block.marker and block.marker != "continues":
        pytest.fail(f"{block.label}: unknown marker <!-- {block.marker} -->")


def _commands(body: str) -> list[str]:
    """The commands of a shell block: continuation lines joined, comments dropped."""
    joined = re.sub(r"\\\n", " ", body)
    cmds = []
    for line in joined.splitlines():
        words = shlex.split(line, comments=True)
        if words:
            cmds.append(words)
    return cmds


@pytest.mark.parametrize("block", BLOCKS, ids=[b.label for b in BLOCKS])
def test_snippet_runs(block: Block, tmp_path: Path) -> None:
    _skip_if_marked(block)
    if block.lang == "python":
        script = tmp_path / "snippet.py"
        script.write_text("\n".join(block.parts), encoding="utf-8")
        proc = subprocess.run([sys.executable, str(script)], cwd=tmp_path, env=_env(),
                              capture_output=True, text=True, timeout=300)
        assert proc.returncode == 0, f"{block.label}\n{proc.stdout[-2000:]}{proc.stderr[-4000:]}"
        return
    for words in _commands(block.body):
        assert words[0] == "roughdiffuse", (
            f"{block.label}: '{' '.join(words)}' is not a roughdiffuse command; run it here or "
            "mark the block <!-- not run: REASON -->"
        )
        proc = subprocess.run([sys.executable, "-m", "roughdiffuse", *words[1:]], cwd=tmp_path,
                              env=_env(), capture_output=True, text=True, timeout=300)
        assert proc.returncode == 0, (
            f"{block.label}: {' '.join(words)} exited {proc.returncode}\n{proc.stderr[-3000:]}"
        )


def test_blocks_are_found_and_marked() -> None:
    """The extraction sees the README's blocks: at least the snippets this test must run, and
    every block that is not run says why (so a new block is run unless someone says why not)."""
    blocks = _blocks()
    langs = [b.lang for b in blocks]
    assert langs.count("python") >= 4 and langs.count("sh") >= 3, langs
    for b in blocks:
        assert b.lang in ("python", "sh", "bash", "shell"), f"{b.label}: language {b.lang!r}"
        if b.marker.startswith("not run"):
            assert b.marker.partition(":")[2].strip(), b.label
    assert any(b.marker == "continues" for b in blocks)


def test_readme_has_the_newcomers_sections() -> None:
    text = README.read_text(encoding="utf-8")
    for heading in ("## Two commands", "## Install", "## The command line", "## The explorer",
                    "## Ground truth", "## Photometric stereo", "## Documentation"):
        assert f"\n{heading}\n" in text, heading
    # the stereo measurement (Lambertian against rough angular errors) stays in the README
    assert "Lambertian: mean angular error" in text
    for link in re.findall(r"\]\(((?!https?:)[^)#]+)", text):
        assert (ROOT / link).exists(), f"README links to a missing file: {link}"
