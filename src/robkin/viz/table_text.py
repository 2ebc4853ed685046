"""Bare tables as people paste them from a paper: one row per line, turned into a robot document.

Formats (numbers may be expressions such as ``-pi/2``; separators are spaces, tabs, commas or
semicolons; ``#`` starts a comment; blank lines are ignored):

``dh-rows`` / ``mdh-rows``
    One line per joint: ``a d alpha theta [R|P]`` (standard or modified DH; the type defaults to R).
``rpy-rows``
    n + 2 lines ``roll pitch yaw x y z``: world -> base, one per joint (the transform leading to
    joint i, which may end in joint i's type, R or P), and joint n -> tool.

The result is an ordinary robot document (dict), read by ``robkin.io.document`` like any other, so
its checks and messages apply unchanged.
"""

from __future__ import annotations

import re
from typing import Any

from ..errors import InputError
from ..io.numbers import number

__all__ = ["TABLE_FORMATS", "document_from_table"]

TABLE_FORMATS = ("dh-rows", "mdh-rows", "rpy-rows")
_TYPES = {"r": "revolute", "revolute": "revolute", "p": "prismatic", "prismatic": "prismatic"}
_SPLIT = re.compile(r"[\s,;]+")


def _lines(text: str) -> list[tuple[int, list[str]]]:
    out = []
    for k, line in enumerate(text.splitlines(), start=1):
        fields = [f for f in _SPLIT.split(line.split("#", 1)[0].strip()) if f]
        if fields:
            out.append((k, fields))
    return out


def _row(line_no: int, fields: list[str], width: int, what: str, allow_type: bool) -> tuple[list[float], str]:
    kind = "revolute"
    if allow_type and fields and fields[-1].lower() in _TYPES:
        kind = _TYPES[fields.pop().lower()]
    if len(fields) != width:
        extra = " and optionally R or P" if allow_type else ""
        raise InputError(f"line {line_no}: expected {width} numbers ({what}){extra}, got {len(fields)} fields")
    return [number(f, f"line {line_no}") for f in fields], kind


def document_from_table(text: str, fmt: str) -> dict[str, Any]:
    """A robot document (dict) from a bare table in format ``fmt`` (one of TABLE_FORMATS)."""
    if fmt not in TABLE_FORMATS:
        raise InputError(f"format: '{fmt}' is not one of {', '.join(TABLE_FORMATS)}")
    lines = _lines(text)
    if fmt in ("dh-rows", "mdh-rows"):
        if not lines:
            raise InputError("input: no rows; one line per joint: a d alpha theta [R|P]")
        rows, types = zip(*(_row(k, f, 4, "a d alpha theta", True) for k, f in lines))
        section = {"rows": [list(r) for r in rows]}
        key = "dh" if fmt == "dh-rows" else "mdh"
    else:
        if len(lines) < 3:
            raise InputError(f"input: {len(lines)} rows; an RPY-XYZ table has n + 2 rows (world->base, one per "
                             f"joint, joint n->tool), so at least 3")
        parsed = [_row(k, f, 6, "roll pitch yaw x y z", 0 < i < len(lines) - 1) for i, (k, f) in enumerate(lines)]
        section = {"rows": [r for r, _ in parsed]}
        types = tuple(t for _, t in parsed[1:-1])
        key = "rpy_xyz"
    joints = [{"name": f"joint{i + 1}", "type": t} for i, t in enumerate(types)]
    return {"robkin": 1, "name": "pasted", "joints": joints, key: section}
