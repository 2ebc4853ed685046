"""Readable tables of every representation, for a terminal or a log.

``render`` gives plain text (the same in a pipe, a file and a test). ``show`` prints the same content
as rich tables when stdout is a terminal and the optional ``rich`` package is installed (imported
lazily, only then), and as the plain text otherwise. ``NO_COLOR`` or ``ROBKIN_PLAIN`` in the
environment force plain text.
"""

from __future__ import annotations

import os
import sys
from typing import Sequence, Union

import numpy as np

from ..robot import Robot

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


def _joint_cols(robot: Robot) -> list[list[object]]:
    return [[str(i + 1), j.name, j.type + (" (flip)" if j.flip else "")] for i, j in enumerate(robot.joints)]


#: One piece of output: a table (title, headers, rows) or a line of text / a matrix block.
Block = Union[tuple[str | None, Sequence[str], Sequence[Sequence[object]]], str]


def blocks(robot: Robot, fmt: str, layout: str = "robkin", degrees: bool = False) -> list[Block]:
    """The robot in representation ``fmt`` (a key of FORMATS) as tables and text lines.

    ``layout='paper'`` puts a DH table in the conversion paper's n+1-row layout (row 0 is the fixed
    base row) when the base is one DH row. ``degrees`` shows the angle columns of DH, modified DH,
    Hayati and RPY-XYZ tables in degrees.
    """
    from ..representations import (dh_from_robot, hayati_from_robot, mdh_from_robot, poe_from_robot,
                                   rpy_from_robot)
    from ..representations.link_table import placement_notes

    title = f"{robot.name or 'robot'}: {FORMATS[fmt]}"
    jc = _joint_cols(robot)
    unit = " (deg)" if degrees else ""
    if fmt in ("dh", "mdh", "hayati"):
        convert = {"dh": dh_from_robot, "mdh": mdh_from_robot, "hayati": hayati_from_robot}[fmt]
        t = convert(robot)
        heads = ["i", "joint", "type", "a", "d", f"alpha{unit}", f"theta{unit}"] if fmt != "mdh" else \
            ["i", "joint", "type", "a(i-1)", "d", f"alpha(i-1){unit}", f"theta{unit}"]
        if fmt == "hayati":
            heads.append(f"beta{unit}")
        table_rows = np.array(t.rows)
        base_row = t.base_row() if fmt == "dh" and layout == "paper" else None
        if base_row is not None:
            table_rows = np.vstack([base_row, table_rows])
        if degrees:
            table_rows[:, 2:] = np.degrees(table_rows[:, 2:])
        labels = ([["0", "(base)", "fixed"]] if base_row is not None else []) + jc
        out: list[Block] = [(title, heads, [c + list(r) for c, r in zip(labels, table_rows)])]
        out.append("theta (revolute) and d (prismatic) are the values at q = 0; joint i adds q_i"
                   + (" (subtracts, if flipped)" if any(j.flip for j in robot.joints) else "") + ".")
        if base_row is None:
            out.append(matrix_text(t.base, "base"))
        out.append(matrix_text(t.tool, "tool (residual T_t)" if fmt == "dh" else "tool"))
        out.extend(f"note: {line}" for line in placement_notes(t))
        return out
    if fmt in ("poe", "poe-body"):
        p = poe_from_robot(robot, "space" if fmt == "poe" else "body")
        heads = ["i", "joint", "type", "wx", "wy", "wz", "vx", "vy", "vz"]
        return [(title, heads, [c + list(s) for c, s in zip(jc, p.screws)]), matrix_text(p.M, "M")]
    if fmt == "rpy-xyz":
        rows = np.array(rpy_from_robot(robot).rows)
        if degrees:
            rows[:, :3] = np.degrees(rows[:, :3])
        labels = [["0", "world->base", ""]] + jc + [[str(robot.n + 1), "tool", ""]]
        return [(title, ["row", "frame", "type", f"roll{unit}", f"pitch{unit}", f"yaw{unit}", "x", "y", "z"],
                 [lab + list(r) for lab, r in zip(labels, rows)])]
    if fmt == "gjd":
        parts: list[Block] = [title]
        for i, F in enumerate(robot.frames):
            label = f"J{i + 1} ({robot.joints[i].name}, {robot.joints[i].type})" if i < robot.n else f"J{i + 1} (tool)"
            parts.append(matrix_text(F, label))
        return parts
    raise ValueError(f"unknown format {fmt}")  # pragma: no cover - callers validate


def render(robot: Robot, fmt: str, layout: str = "robkin", degrees: bool = False) -> str:
    """The robot in representation ``fmt`` (a key of FORMATS) as plain text (see ``blocks``)."""
    return "\n".join(b if isinstance(b, str) else text_table(b[1], b[2], b[0])
                     for b in blocks(robot, fmt, layout, degrees))


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
