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
- **real numbers only** (:func:`check_real`): complex, structured, boolean (except where a
  mask is read), date and time, text and object arrays are refused by name;
- **one shape rule for every image** (:func:`image_array`), whatever the file type: (H, W),
  (H, W, C) channels last, or (C, H, W) bands first (the FITS order, and a ``.npy`` cube)
  where the channel axis is unambiguous; an image at least 2 × 2 pixels. Anything else (a
  4-D array, a one-row image, a cube whose band axis cannot be told) is refused with its
  shape as given and how to give it;
- **short quotes**: a message quotes at most :data:`QUOTE_CHARS` characters of what it was
  given (:func:`short`), so a 100,000-character argument is not echoed back; and every
  message printed by the command line or sent by the explorer passes :func:`clip_echo`.

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
import re
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
    "check_real",
    "clip_echo",
    "check_regular",
    "image_array",
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


LONG_WORD = 240
"""A run of characters without a space longer than this is clipped in a message
(:func:`clip_echo`): longer than any real path or value, shorter than a flood."""


def clip_echo(message: str, limit: int = LONG_WORD) -> str:
    """``message`` with every run of non-space characters longer than ``limit`` cut to its
    first :data:`QUOTE_CHARS` and last 20 characters and its length: the one quoting rule of
    everything echoed back (argparse's errors, ``--param`` names and values, the explorer's
    4xx bodies), applied where each is printed or sent, so a 100,000-character argument is
    never echoed whole.

    >>> clip_echo("bad name " + "x" * 1000 + "=1")[:20]
    'bad name xxxxxxxxxxx'
    >>> len(clip_echo("bad name " + "x" * 1000 + "=1")) < 120
    True
    """
    if len(message) <= limit:
        return message

    def cut(m: re.Match[str]) -> str:
        word = m.group(0)
        return f"{word[:QUOTE_CHARS]}…{word[-20:]} ({len(word)} characters)"

    return re.sub(rf"\S{{{limit + 1},}}", cut, message)


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


_KINDS = {
    "c": "complex numbers (the imaginary part would be dropped)",
    "b": "booleans",
    "V": "a structured array (named fields)",
    "M": "dates",
    "m": "time spans",
    "O": "Python objects",
    "U": "text",
    "S": "bytes",
}


def check_real(arr: Any, what: str, *, bool_ok: bool = False) -> Any:
    """``arr`` if it holds real numbers (integers or floats; booleans where ``bool_ok``, as
    for a mask), else a ``ValueError`` naming ``what`` and what it holds.

    >>> import numpy as np
    >>> check_real(np.zeros(2, dtype=[("a", "f8")]), "image x.npy")
    Traceback (most recent call last):
    roughdiffuse._validate.ParameterError: image x.npy holds a structured array (named ...
    """
    kind = arr.dtype.kind
    if kind in "iuf" or (bool_ok and kind == "b"):
        return arr
    held = _KINDS.get(kind, f"{arr.dtype} values")
    raise ParameterError(f"{what} holds {held}; give real numbers")


def _shape_text(shape: tuple[int, ...]) -> str:
    return str(tuple(shape))  # Python's own: (8,) for one axis


def image_array(arr: Any, what: str, *, channels: tuple[int, ...] = (1, 3)) -> Any:
    """The one shape rule of every image reader: ``arr`` as (H, W) or (H, W, C), C one of
    ``channels``.

    Accepted: (H, W); (H, W, C) channels last; (C, H, W) bands first (FITS cubes, a ``.npy``
    cube), moved to channels last, where only the first axis has a channel count of
    ``channels``. A channel axis of 1 is dropped. Refused, with the shape as given and how to
    give it: fewer than 2 or more than 3 axes, an image under 2 × 2 pixels (one row or one
    column), a 3-D array whose channel axis cannot be told (both end axes, or neither, have
    an accepted count).

    >>> import numpy as np
    >>> image_array(np.zeros((3, 5, 4)), "image").shape
    (5, 4, 3)
    >>> image_array(np.zeros((1, 8)), "image")
    Traceback (most recent call last):
    roughdiffuse._validate.ParameterError: image has shape (1, 8): one row; an image needs ...
    """
    shape = tuple(int(n) for n in arr.shape)
    given = _shape_text(shape)
    counts = ", ".join(str(c) for c in channels)
    how = f"give (H, W) or (H, W, C) with C in {{{counts}}}"
    if arr.ndim == 3:
        last, first = shape[2] in channels, shape[0] in channels
        if first and not last:
            arr = arr.transpose(1, 2, 0)  # bands first (FITS order) -> channels last
        elif first and last:
            raise ParameterError(
                f"{what} has shape {given}: bands first or channels last cannot be told; "
                f"{how} (numpy.moveaxis(a, 0, -1) moves bands last)"
            )
        elif not last:
            raise ParameterError(f"{what} has shape {given}: no axis of {counts} channels; {how}")
        if arr.shape[2] == 1:
            arr = arr[..., 0]
    elif arr.ndim != 2:
        axes = f"{arr.ndim} axis" if arr.ndim == 1 else f"{arr.ndim} axes"
        raise ParameterError(f"{what} has shape {given}: {axes}; {how}")
    h, w = arr.shape[:2]
    if h < 2 or w < 2:
        which = (
            "no rows" if h == 0 else "no columns" if w == 0 else "one row" if h < 2
            else "one column"
        )  # fmt: skip
        raise ParameterError(
            f"{what} has shape {given}: {which}; an image needs at least 2 rows and 2 columns"
        )
    return arr


def load_npy(
    path: str | os.PathLike[str], what: str = "array file", *, bool_ok: bool = False
) -> Any:
    """A real-valued NumPy array from the regular ``.npy`` file ``path`` (at most
    :data:`MAX_IMAGE_BYTES`; no pickles).

    The values must be real numbers (:func:`check_real`): booleans only with ``bool_ok``
    (a mask). The shape is not checked here: an image reader applies :func:`image_array`.

    Raises
    ------
    ValueError
        For a file that is not a regular file, too large, not ``.npy``, pickled, or that
        holds complex, structured, boolean, date, text or object values (a complex image's
        imaginary part would be dropped).
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
    return check_real(arr, f"{what} {base}", bool_ok=bool_ok)
