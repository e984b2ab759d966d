"""The one bounded reader of users' files and request bodies.

Every file a user names (images, masks, normal maps, ``lights.json``, CSV samples, MERL
files, DiLiGenT lists) and every body the explorer receives is read through this module:

- **a regular file** (:func:`check_regular`): not a folder, FIFO, device (``/dev/zero``)
  or socket, which could be read without end or block;
- **a stated size limit**: the file's size is checked before it is read, and no more than
  the limit is read even if the file grows meanwhile (:func:`read_bytes`);
- **bounded structure**: JSON nested deeper than :data:`MAX_JSON_DEPTH` is refused before it
  is parsed (:func:`loads_json`; Python's parser would recurse until RecursionError), a CSV
  line longer than :data:`MAX_CSV_LINE` characters is refused
  (:func:`roughdiffuse.fit.csv_from_text`);
- **short quotes**: a message quotes at most :data:`QUOTE_CHARS` characters of what it was
  given (:func:`short`), so a 100,000-character argument is not echoed back.

A refusal is a ``ValueError`` naming the file and the limit (the CLI prints it on one line
and exits 2; the explorer answers 400 or 413).

>>> short("x" * 1000)
"'xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx…' (1000 characters)"
>>> loads_json("[" * 100 + "]" * 100, "request")
Traceback (most recent call last):
roughdiffuse._validate.ParameterError: request: JSON nested deeper than 64 levels
"""

from __future__ import annotations

import json
import os
import stat
from typing import Any

from .._validate import ParameterError

__all__ = [
    "MAX_CSV_BYTES",
    "MAX_CSV_LINE",
    "MAX_JSON_BYTES",
    "MAX_JSON_DEPTH",
    "MAX_IMAGE_BYTES",
    "MAX_LIST_BYTES",
    "QUOTE_CHARS",
    "check_regular",
    "load_npy",
    "loads_json",
    "read_bytes",
    "read_json",
    "read_text",
    "short",
]

QUOTE_CHARS = 60
"""Characters of a user's input that an error message quotes."""

MAX_JSON_BYTES = 10_000_000
"""Largest JSON file read (``lights.json``: a few hundred bytes per light)."""

MAX_JSON_DEPTH = 64
"""Deepest nesting of arrays and objects in a JSON file or request body."""

MAX_CSV_BYTES = 1_000_000_000
"""Largest CSV sample file the CLI reads (the explorer's uploads have their own, smaller,
limit)."""

MAX_CSV_LINE = 100_000
"""Longest line of a CSV sample file, in characters (a sample's line is well under 1 kB;
the csv module's own field limit, 131072, is never reached)."""

MAX_IMAGE_BYTES = 4_000_000_000
"""Largest image, mask or normal map read (a 16k x 16k RGB float64 image is 6 GB: too big)."""

MAX_LIST_BYTES = 1_000_000
"""Largest small text list (DiLiGenT ``filenames.txt`` and light matrices)."""


def short(text: object, n: int = QUOTE_CHARS) -> str:
    """``repr`` of ``text``, cut to its first ``n`` characters with its length when longer."""
    s = str(text)
    if len(s) <= n:
        return repr(s)
    return f"{s[:n]!r}"[:-1] + f"…' ({len(s)} characters)"


def check_regular(path: str | os.PathLike[str], what: str = "file") -> int:
    """Return the size of ``path`` after checking that it is a regular file (links followed).

    Raises
    ------
    ValueError
        If it does not exist, or is a folder, device, FIFO or socket.
    """
    name = os.fspath(path)
    try:
        st = os.stat(name)
    except FileNotFoundError:
        raise ParameterError(f"{what} {short(name)} does not exist") from None
    except OSError as exc:
        raise ParameterError(f"cannot read {what} {short(name)}: {exc.strerror}") from None
    if stat.S_ISDIR(st.st_mode):
        raise ParameterError(f"{what} {short(name)} is a folder, not a file")
    if not stat.S_ISREG(st.st_mode):
        raise ParameterError(
            f"{what} {short(name)} is not a regular file (a device, FIFO or socket)"
        )
    return st.st_size


def read_bytes(path: str | os.PathLike[str], limit: int, what: str = "file") -> bytes:
    """The bytes of the regular file ``path``, refused beyond ``limit`` bytes."""
    size = check_regular(path, what)
    name = os.fspath(path)
    if size > limit:
        raise ParameterError(f"{what} {short(name)} has {size} bytes; at most {limit} are read")
    with open(name, "rb") as fh:
        data = fh.read(limit + 1)
    if len(data) > limit:  # it grew after the check
        raise ParameterError(f"{what} {short(name)} has more than {limit} bytes; at most {limit}")
    return data


def read_text(path: str | os.PathLike[str], limit: int, what: str = "file") -> str:
    """UTF-8 text (a leading BOM dropped) of the regular file ``path``, at most ``limit``
    bytes."""
    data = read_bytes(path, limit, what)
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ParameterError(
            f"{what} {short(os.fspath(path))}: not UTF-8 text (byte 0x{data[exc.start]:02x} at "
            f"offset {exc.start})"
        ) from None


def _depth(text: str) -> int:
    """Deepest nesting of ``[`` and ``{`` outside strings (a linear scan, no recursion)."""
    depth = deepest = 0
    in_string = escaped = False
    for ch in text:
        if in_string:
            if escaped:
                escaped = False
            elif ch == "\\":
                escaped = True
            elif ch == '"':
                in_string = False
        elif ch == '"':
            in_string = True
        elif ch in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif ch in "]}":
            depth -= 1
    return deepest


def loads_json(text: str, what: str, max_depth: int = MAX_JSON_DEPTH) -> Any:
    """Parse JSON ``text`` nested at most ``max_depth`` deep; ``NaN`` and ``Infinity`` (not
    JSON) are refused too.

    Raises
    ------
    ValueError
        Naming ``what`` and the problem.
    """
    if _depth(text) > max_depth:
        raise ParameterError(f"{what}: JSON nested deeper than {max_depth} levels")

    def constant(name: str) -> Any:
        raise ParameterError(f"{what}: {name} is not JSON (write a number or null)")

    try:
        return json.loads(text, parse_constant=constant)
    except json.JSONDecodeError as exc:
        raise ParameterError(f"{what}: not valid JSON ({exc.msg} at line {exc.lineno})") from None
    except RecursionError:  # pragma: no cover - the depth check comes first
        raise ParameterError(f"{what}: JSON nested too deeply") from None


def read_json(path: str | os.PathLike[str], what: str = "JSON file") -> Any:
    """Read the regular file ``path`` as JSON (at most :data:`MAX_JSON_BYTES` bytes and
    :data:`MAX_JSON_DEPTH` levels)."""
    name = os.fspath(path)
    text = read_text(name, MAX_JSON_BYTES, what)
    return loads_json(text, f"{what} {short(os.path.basename(name))}")


def load_npy(path: str | os.PathLike[str], what: str = "array file") -> Any:
    """A real-valued NumPy array from the regular ``.npy`` file ``path`` (at most
    :data:`MAX_IMAGE_BYTES`; no pickles).

    Raises
    ------
    ValueError
        For a file that is not a regular file, too large, not ``.npy``, pickled, or that
        holds complex, text or object values (a complex image's imaginary part would be
        dropped).
    """
    import numpy as np

    name = os.fspath(path)
    size = check_regular(name, what)
    if size > MAX_IMAGE_BYTES:
        raise ParameterError(f"{what} {short(name)} has {size} bytes; at most {MAX_IMAGE_BYTES}")
    base = short(os.path.basename(name))
    try:
        arr = np.load(name, allow_pickle=False)
    except Exception as exc:  # noqa: BLE001 - any unreadable file is one message
        raise ParameterError(f"{what} {base}: not a readable .npy file ({exc})") from None
    if not isinstance(arr, np.ndarray):
        raise ParameterError(f"{what} {base}: an .npz archive, not one .npy array")
    if arr.dtype.kind not in "biuf":
        kind = "complex numbers" if arr.dtype.kind == "c" else f"{arr.dtype} values"
        raise ParameterError(f"{what} {base} holds {kind}; give real numbers")
    return arr
