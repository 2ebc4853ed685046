"""Plain and rich text of tables and lines: the generic pieces every printed table is made of.

A ``Block`` is one piece of output: a table (title, headers, rows) or a line of text / a matrix block.
``blocks_text`` joins blocks as plain text (the same in a pipe, a file and a test); ``show_blocks``
prints them as rich tables when stdout is a terminal and the optional ``rich`` package is installed
(imported lazily, only then), and as the plain text otherwise. ``NO_COLOR`` or ``ROBKIN_PLAIN`` in
the environment force plain text. Nothing here knows a representation or a result type: the tables
(``io.tables.views``), the IK result (``kinematics.ik_text``) and the comparison
(``equivalence.report``) are laid out by the layer that owns them.
"""

from __future__ import annotations

import os
import sys
from typing import Sequence, Union

import numpy as np

__all__ = ["Block", "fmt_num", "text_table", "matrix_text", "blocks_text", "use_rich", "show_blocks", "show_table"]

#: One piece of output: a table (title, headers, rows) or a line of text / a matrix block.
Block = Union[tuple[Union[str, None], Sequence[str], Sequence[Sequence[object]]], str]


def fmt_num(x: float, digits: int = 6) -> str:
    """A number for humans: up to ``digits`` significant digits, no '-0', no noise below 1e-12."""
    x = float(x)
    if abs(x) < 1e-12:  # rounding noise of exact zeros computed through products
        return "0"
    return f"{x:.{digits}g}"


def text_table(headers: Sequence[str], rows: Sequence[Sequence[object]], title: str | None = None) -> str:
    """Columns aligned on the widest cell; numbers right-aligned, text left-aligned."""
    cells = [[c if isinstance(c, str) else fmt_num(c) for c in row] for row in rows]
    widths = [max(len(h), *(len(r[i]) for r in cells)) if cells else len(h) for i, h in enumerate(headers)]
    numeric = [all(not isinstance(row[i], str) for row in rows) for i in range(len(headers))]

    def line(items: Sequence[str]) -> str:
        return "  ".join(s.rjust(w) if num else s.ljust(w) for s, w, num in zip(items, widths, numeric)).rstrip()

    out = [title] if title else []
    out.append(line(list(headers)))
    out.append("  ".join("-" * w for w in widths))
    out.extend(line(r) for r in cells)
    return "\n".join(out)


def matrix_text(T: np.ndarray, name: str) -> str:
    """A matrix as '<name>: identity' or an aligned block."""
    T = np.asarray(T)
    if T.shape == (4, 4) and np.allclose(T, np.eye(4), atol=1e-12, rtol=0):
        return f"{name}: identity"
    body = text_table([""] * T.shape[1], [list(r) for r in T]).splitlines()[2:]
    return "\n".join([f"{name}:"] + ["  " + b for b in body])


def blocks_text(items: Sequence[Block]) -> str:
    """Blocks as plain text, one after the other."""
    return "\n".join(b if isinstance(b, str) else text_table(b[1], b[2], b[0]) for b in items)


def use_rich(stream=None) -> bool:
    """Rich tables only on a terminal, with rich installed, and not disabled by the environment."""
    stream = sys.stdout if stream is None else stream
    if os.environ.get("NO_COLOR") or os.environ.get("ROBKIN_PLAIN"):
        return False
    try:
        if not stream.isatty():
            return False
    except (AttributeError, ValueError):
        return False
    import importlib.util

    return importlib.util.find_spec("rich") is not None


def show_blocks(items: Sequence[Block], stream=None) -> None:
    """Print tables and text: rich on a terminal (see ``use_rich``), plain text otherwise."""
    stream = sys.stdout if stream is None else stream
    if not use_rich(stream):
        for b in items:
            print(b if isinstance(b, str) else text_table(b[1], b[2], b[0]), file=stream)
        return
    from rich.console import Console  # lazy: ~40 ms, only for a terminal
    from rich.table import Table

    console = Console(file=stream, highlight=False)
    for b in items:
        if isinstance(b, str):
            console.print(b, markup=False)
            continue
        title, headers, rows = b
        numeric = [bool(rows) and all(not isinstance(r[i], str) for r in rows) for i in range(len(headers))]
        table = Table(title=title, title_justify="left", header_style="bold")
        for h, num in zip(headers, numeric):
            table.add_column(h, justify="right" if num else "left", overflow="fold")
        for r in rows:
            table.add_row(*[c if isinstance(c, str) else fmt_num(c) for c in r])
        console.print(table)


def show_table(headers: Sequence[str], rows: Sequence[Sequence[object]], title: str | None = None,
               stream=None) -> None:
    """Print one table: rich on a terminal, plain text otherwise."""
    show_blocks([(title, headers, rows)], stream)
