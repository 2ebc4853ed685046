"""The one JSON style of every robkin output: ``dumps(obj)``.

- Indented by two spaces, keys in the order given.
- A list or object whose items are all scalars goes on one line when that line is short (a matrix row,
  a joint vector, ``{"name": "joint1", "type": "revolute"}``), so a 4x4 matrix is four lines, not 24.
- Floats at full precision: Python's ``repr``, the shortest text that reads back to the same double.
  ``-0.0`` is written ``0.0`` for people, and kept for documents (``exact=True``, every bit read
  back); NaN and infinities (not JSON) are written ``null``.
- NumPy scalars and arrays are accepted and written as the numbers and lists they hold.
"""

from __future__ import annotations

import json
import math
from typing import Any

__all__ = ["dumps", "plain"]

#: A run of scalars longer than this is split one item per line (a long vector stays readable).
LINE_WIDTH = 120
_INDENT = "  "


def plain(obj: Any) -> Any:
    """``obj`` with NumPy arrays and scalars turned into lists, floats, ints and bools (recursively)."""
    if isinstance(obj, dict):
        return {str(k): plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [plain(v) for v in obj]
    if isinstance(obj, float):
        return float(obj)  # also numpy.float64, a float subclass whose repr is not JSON
    if isinstance(obj, (str, bool, int)) or obj is None:
        return obj
    tolist = getattr(obj, "tolist", None)  # numpy arrays and numpy scalars
    if tolist is not None:
        return plain(tolist())
    raise TypeError(f"cannot write {type(obj).__name__} as JSON")


def _scalar(x: Any, exact: bool) -> str:
    if isinstance(x, float):
        if not math.isfinite(x):
            return "null"
        return repr(x if exact else x + 0.0)  # + 0.0 turns -0.0 into 0.0
    return json.dumps(x)


def _is_scalar(x: Any) -> bool:
    return x is None or isinstance(x, (str, bool, int, float))


def _dump(obj: Any, level: int, exact: bool) -> str:
    pad, inner = _INDENT * level, _INDENT * (level + 1)
    if isinstance(obj, dict):
        if not obj:
            return "{}"
        items = [(json.dumps(k), v) for k, v in obj.items()]
        if all(_is_scalar(v) for _, v in items):
            flat = "{" + ", ".join(f"{k}: {_scalar(v, exact)}" for k, v in items) + "}"
            if len(flat) + len(pad) <= LINE_WIDTH:
                return flat
        body = ",\n".join(f"{inner}{k}: {_dump(v, level + 1, exact)}" for k, v in items)
        return "{\n" + body + "\n" + pad + "}"
    if isinstance(obj, list):
        if not obj:
            return "[]"
        if all(_is_scalar(v) for v in obj):
            flat = "[" + ", ".join(_scalar(v, exact) for v in obj) + "]"
            if len(flat) + len(pad) <= LINE_WIDTH:
                return flat
        body = ",\n".join(inner + _dump(v, level + 1, exact) for v in obj)
        return "[\n" + body + "\n" + pad + "]"
    return _scalar(obj, exact)


def dumps(obj: Any, *, exact: bool = False) -> str:
    """``obj`` (dicts, lists, numbers, strings, NumPy arrays) as JSON text in robkin's style (no final
    newline). ``exact=True`` keeps the sign of -0.0, so that every float reads back bit for bit."""
    return _dump(plain(obj), 0, exact)
