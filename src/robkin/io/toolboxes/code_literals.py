"""Text and numbers from a robot file as literals of the programs robkin writes (Python, MATLAB/Octave).

Generated code is data: a name or number that came from an input file reaches a ``.py`` or ``.m``
file only through these functions (never in a comment or docstring), which return a literal that the language reads back as exactly
that value and nothing else. Strings are written in pure ASCII (every other character as an escape or a
character code), so no quote, line break, comment marker or Unicode trick in a name can end the literal
or start a statement; numbers are written as the shortest text that reads back to the same float, and a
non-finite number is refused (``InputError`` naming the field) except where infinity means "no limit"
and the caller says so.
"""

from __future__ import annotations

import math
from typing import Iterable, Sequence

import numpy as np

from ...errors import InputError
from ..files.float_text import float_text

__all__ = ["py_str", "py_float", "py_list", "py_matrix", "m_str", "m_float", "m_row", "m_matrix",
           "check_finite"]


def check_finite(values: object, field: str) -> np.ndarray:
    """``values`` as a float array; InputError naming ``field`` (and the index) if one is NaN or infinite."""
    a = np.asarray(values, dtype=float)
    bad = np.argwhere(~np.isfinite(a))
    if bad.size:
        where = "".join(f"[{i}]" for i in bad[0])
        raise InputError(f"{field}{where}: {a[tuple(bad[0])]} is not a finite number; generated code holds "
                         f"finite numbers only")
    return a


def _number(x: float, field: str, allow_inf: bool) -> float:
    x = float(x)
    if math.isnan(x) or (math.isinf(x) and not allow_inf):
        raise InputError(f"{field}: {x} is not a finite number; generated code holds finite numbers only")
    return x


# ---------------------------------------------------------------------------------------------- Python
def py_str(text: str) -> str:
    """A Python string literal of ``text`` in pure ASCII (``ascii``: quotes, backslashes and every
    non-ASCII or unprintable character escaped), so it reads back as ``text`` and is never code."""
    return ascii(str(text))


def py_float(x: float, field: str, *, allow_inf: bool = False) -> str:
    """A Python float literal that reads back to ``x`` bit for bit; ``float('inf')`` / ``-float('inf')``
    for infinities only when ``allow_inf``."""
    x = _number(x, field, allow_inf)
    if math.isinf(x):
        return "float('inf')" if x > 0 else "-float('inf')"
    return float_text(x)


def py_list(values: Iterable[float], field: str) -> str:
    """A flat Python list literal of finite floats."""
    return "[" + ", ".join(py_float(v, f"{field}[{i}]") for i, v in enumerate(values)) + "]"


def py_matrix(M: Sequence[Sequence[float]], field: str, indent: str | None = None) -> str:
    """A nested Python list literal of a matrix of finite floats: one line, or with ``indent`` one row a
    line after the first (indented by ``indent`` plus one space)."""
    rows = [py_list(row, f"{field}[{i}]") for i, row in enumerate(np.asarray(M, dtype=float))]
    return "[" + (", " if indent is None else ",\n" + indent + " ").join(rows) + "]"


# ---------------------------------------------------------------------------------------------- MATLAB
def m_str(text: str) -> str:
    """A MATLAB/Octave char-array expression of ``text``: printable ASCII inside single quotes (a quote
    doubled, the only escape single-quoted strings have; backslashes are literal there), every other
    character as ``char(code)`` concatenated in brackets. Reads back as ``text`` in MATLAB (UTF-16 code
    units) and is never code in either language."""
    text = str(text)
    parts: list[str] = []
    run: list[str] = []
    for c in text:
        if " " <= c <= "~":
            run.append("''" if c == "'" else c)
            continue
        if run:
            parts.append("'" + "".join(run) + "'")
            run = []
        units = [ord(c)] if ord(c) < 0x10000 else list(_utf16_units(c))
        parts.append("char([" + " ".join(str(u) for u in units) + "])")
    if run or not parts:
        parts.append("'" + "".join(run) + "'")
    return parts[0] if len(parts) == 1 else "[" + " ".join(parts) + "]"


def _utf16_units(c: str) -> tuple[int, int]:
    v = ord(c) - 0x10000
    return 0xD800 + (v >> 10), 0xDC00 + (v & 0x3FF)


def m_float(x: float, field: str, *, allow_inf: bool = False) -> str:
    """A MATLAB/Octave number that reads back to ``x`` (17 significant digits); ``Inf`` / ``-Inf`` only
    when ``allow_inf``."""
    x = _number(x, field, allow_inf)
    if math.isinf(x):
        return "Inf" if x > 0 else "-Inf"
    return float_text(x)


def m_row(values: Iterable[float], field: str, *, allow_inf: bool = False) -> str:
    """The numbers of one matrix row, separated by commas (no brackets: ``[a -b]`` and ``[a - b]`` differ
    in MATLAB, a comma never misleads)."""
    return ", ".join(m_float(v, f"{field}[{i}]", allow_inf=allow_inf) for i, v in enumerate(values))


def m_matrix(M: Sequence[Sequence[float]], field: str, indent: str = "    ", *, allow_inf: bool = False) -> str:
    """A MATLAB matrix literal, one row a line (``[r1; ...]``); ``zeros(0, k)`` for no rows."""
    A = np.asarray(M, dtype=float)
    if A.shape[0] == 0:
        return f"zeros(0, {A.shape[1] if A.ndim == 2 else 0})"
    rows = [m_row(row, f"{field}[{i}]", allow_inf=allow_inf) for i, row in enumerate(A)]
    return "[" + (";\n" + indent).join(rows) + "]"
