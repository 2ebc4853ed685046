"""Bare tables as people paste them from a paper: one row per line, turned into a robot document.

Formats (numbers may be expressions such as ``-pi/2``; separators are spaces, tabs, commas or
semicolons; ``#`` starts a comment; blank lines are ignored):

``dh-rows`` / ``mdh-rows``
    One line per joint: ``a d alpha theta [R|P]`` (standard or modified DH; the type defaults to R).
    Vendor tables often end with a fixed flange (tool) row. It is a joint unless it says otherwise:
    ending it with ``tool`` or ``flange``, or passing ``tool_row=True`` (the GUI asks), makes it the
    table's fixed tool transform instead of one more joint.
``poe-rows``
    One line per joint: ``wx wy wz vx vy vz [R|P]`` (space-frame screw axes; without R or P a screw
    with w = 0 is prismatic), then one line ``M`` followed by the 16 (or top 12) entries of the home
    tool pose, row by row.
``rpy-rows``
    n + 2 lines ``roll pitch yaw x y z``: world -> base, one per joint (the transform leading to
    joint i, which may end in joint i's type, R or P), and joint n -> tool.

The result is an ordinary robot document (dict), read by ``robkin.io.documents.reader`` like any other, so
its checks and messages apply unchanged.
"""

from __future__ import annotations

import re
from typing import Any

from ...errors import InputError, quote
from ..files.numbers import number
from ...compiled.scanners.vocabulary import MAX_JOINTS

__all__ = ["TABLE_FORMATS", "document_from_table"]

TABLE_FORMATS = ("dh-rows", "mdh-rows", "poe-rows", "rpy-rows")
_TOOL_TAGS = ("tool", "flange")
_TYPES = {"r": "revolute", "revolute": "revolute", "p": "prismatic", "prismatic": "prismatic"}
_SPLIT = re.compile(r"[\s,;]+")


def _lines(text: str) -> list[tuple[int, list[str]]]:
    out = []
    for k, line in enumerate(text.splitlines(), start=1):
        fields = [f for f in _SPLIT.split(line.split("#", 1)[0].strip()) if f]
        if fields:
            if len(out) == MAX_JOINTS + 2:  # + 2: an RPY-XYZ table's base and tool rows (a PoE's M: + 1)
                raise InputError(f"line {k}: more than {MAX_JOINTS + 2} rows; at most {MAX_JOINTS} joints (one row "
                                 f"each) are read")
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


def _tool_row(lines: list[tuple[int, list[str]]], tool_row: bool) -> bool:
    """Whether the last row is a fixed tool (flange) row: tagged so, or as the caller says."""
    for i, (k, fields) in enumerate(lines):
        if fields[-1].lower() in _TOOL_TAGS:
            if i != len(lines) - 1:
                raise InputError(f"line {k}: only the last row can be the tool ({quote(fields[-1])}) row")
            fields.pop()
            tool_row = True
    if tool_row and len(lines) < 2:
        raise InputError("input: a tool row needs at least one joint row before it")
    return tool_row


def _poe_section(lines: list[tuple[int, list[str]]]) -> tuple[dict[str, Any], tuple[str, ...]]:
    if not lines or lines[-1][1][0].upper() != "M":
        raise InputError("input: a PoE table ends with a line 'M' and the 16 entries of the home tool pose")
    k, fields = lines[-1]
    if len(fields) - 1 not in (12, 16):
        raise InputError(f"line {k}: expected M and 12 or 16 numbers (the home tool pose row by row), "
                         f"got {len(fields) - 1}")
    M = [number(f, f"line {k}") for f in fields[1:]] + ([0.0, 0.0, 0.0, 1.0] if len(fields) == 13 else [])
    if len(lines) < 2:
        raise InputError("input: no screw rows; one line per joint: wx wy wz vx vy vz [R|P] before M")
    screws, types = [], []
    for k, fields in lines[:-1]:
        tagged = fields[-1].lower() in _TYPES
        S, kind = _row(k, fields, 6, "wx wy wz vx vy vz", True)
        screws.append(S)
        # w = 0 exactly: the paste is typed by hand, a screw axis is either a rotation or not
        types.append(kind if tagged or any(S[:3]) else "prismatic")
    return {"frame": "space", "M": [M[4 * r:4 * r + 4] for r in range(4)], "screws": screws}, tuple(types)


def document_from_table(text: str, fmt: str, tool_row: bool = False) -> dict[str, Any]:
    """A robot document (dict) from a bare table in format ``fmt`` (one of TABLE_FORMATS).

    ``tool_row``: DH and modified DH rows only; the last row is the fixed tool (flange) transform,
    not a joint.
    """
    if fmt not in TABLE_FORMATS:
        raise InputError(f"format: {quote(fmt)} is not one of {', '.join(TABLE_FORMATS)}")
    lines = _lines(text)
    if fmt in ("dh-rows", "mdh-rows"):
        if not lines:
            raise InputError("input: no rows; one line per joint: a d alpha theta [R|P]")
        tool = _tool_row(lines, tool_row)
        parsed = [_row(k, f, 4, "a d alpha theta", True) for k, f in lines]
        if tool:
            from ... import se3

            link = se3.dh_matrix if fmt == "dh-rows" else se3.mdh_matrix
            (a, d, alpha, theta), _ = parsed.pop()
            section = {"tool": link(a, d, alpha, theta).tolist()}
        else:
            section = {}
        section["rows"] = [r for r, _ in parsed]
        types = tuple(t for _, t in parsed)
        key = "dh" if fmt == "dh-rows" else "mdh"
    elif fmt == "poe-rows":
        section, types = _poe_section(lines)
        key = "poe"
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
