"""Readable tables of every representation, for a terminal or a log.

``render`` gives plain text (the same in a pipe, a file and a test). ``show`` prints the same content
as rich tables when stdout is a terminal and the optional ``rich`` package is installed (imported
lazily, only then), and as the plain text otherwise. ``NO_COLOR`` or ``ROBKIN_PLAIN`` in the
environment force plain text.
"""

from __future__ import annotations

import os
import sys
from typing import Sequence

import numpy as np

from ...robot import Robot
from .views import Block

__all__ = ["FORMATS", "fmt_num", "text_table", "matrix_text", "render", "show", "show_table", "use_rich"]

#: Representation names accepted by ``render`` (and the CLI's --to), with a one-line description.
FORMATS = {
    "dh": "standard Denavit-Hartenberg table (+ base and residual tool)",
    "mdh": "modified (Craig) Denavit-Hartenberg table (+ base and tool)",
    "hayati": "Hayati's parameters: DH with beta about y between nearly parallel axes (+ base and tool)",
    "poe": "Product of Exponentials, space frame (M and screws)",
    "poe-body": "Product of Exponentials, body frame (M and screws)",
    "rpy-xyz": "RPY-XYZ table, n+2 rows (world->base, joints, tool)",
    "gjd": "Global Joint Description: n+1 frames in the base frame at q = 0",
}


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


def blocks(robot: Robot, fmt: str, layout: str = "robkin", degrees: bool = False) -> list[Block]:
    """The robot in representation ``fmt`` (a key of FORMATS) as tables and text lines.

    ``layout='paper'`` puts a DH table in the conversion paper's n+1-row layout (row 0 is the fixed
    base row) when the base is one DH row. ``degrees`` shows the angle columns of DH, modified DH,
    Hayati and RPY-XYZ tables in degrees. Values within ``table_views.DISPLAY_ZERO`` of 0 are shown
    as 0, with a note (the display rule; files keep full precision).
    """
    from ... import representations  # each converter is imported on first use: only the one asked for
    from .views import frames_blocks, table_blocks

    title = f"{robot.name or 'robot'}: {FORMATS[fmt]}"
    if fmt in ("dh", "mdh", "hayati"):
        t = getattr(representations, f"{fmt}_from_robot")(robot)
        return table_blocks(t, title, layout, degrees, robot.scale)
    if fmt in ("poe", "poe-body"):
        return table_blocks(representations.poe_from_robot(robot, "space" if fmt == "poe" else "body"), title,
                            scale=robot.scale)
    if fmt == "rpy-xyz":
        return table_blocks(representations.rpy_from_robot(robot), title, degrees=degrees, scale=robot.scale)
    if fmt == "gjd":
        labels = [f"J{i + 1} ({j.name}, {j.type})" for i, j in enumerate(robot.joints)] + [f"J{robot.n + 1} (tool)"]
        return [title, *frames_blocks(robot.frames, labels, robot.scale)]
    raise ValueError(f"unknown format {fmt}")  # pragma: no cover - callers validate


def render(robot: Robot, fmt: str, layout: str = "robkin", degrees: bool = False) -> str:
    """The robot in representation ``fmt`` (a key of FORMATS) as plain text (see ``blocks``)."""
    from .views import blocks_text

    return blocks_text(blocks(robot, fmt, layout, degrees))


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


def show(robot: Robot, fmt: str, layout: str = "robkin", stream=None) -> None:
    """Print the robot in representation ``fmt``: rich tables on a terminal, plain text otherwise."""
    show_blocks(blocks(robot, fmt, layout), stream)


def show_table(headers: Sequence[str], rows: Sequence[Sequence[object]], title: str | None = None,
               stream=None) -> None:
    """Print one table: rich on a terminal, plain text otherwise."""
    show_blocks([(title, headers, rows)], stream)
