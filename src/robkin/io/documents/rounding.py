"""Robot documents without rounding noise: every table value as the shortest decimal within the FK budget.

``document_from_robot`` writes every float bit-exact (``repr``), so a table computed from a URDF shows
``0.3839999999999999`` and ``-4.16e-18``. ``round_document`` replaces each value of the representation
sections by the float of its shortest decimal within ``float_text.decimal_tolerances`` (the whole
section then moves FK by at most ``rounding.SNAP_BUDGET`` of the robot's size), or by ``digits``
significant digits. Joint limits and the world transform are the user's own numbers and stay as they are.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ...representations.registry import by_section
from ..files.float_text import decimal_tolerances, digits_text, short_text

__all__ = ["round_document"]


def _kinds(key: str) -> dict[str, str]:
    """Row key -> 'length' or 'angle' (radians, or a unitless direction) of a section's columns (its
    representation's, ``robkin.representations.registry``); any other key of a row (a link's mass
    properties m, r, I) is not a table parameter and is written as it is."""
    try:
        columns = by_section(key).columns
    except KeyError:
        return {}
    return {c.key: "length" if c.kind == "length" else "angle" for c in columns}


def round_document(doc: dict[str, Any], scale: float, digits: int | None = None) -> dict[str, Any]:
    """``doc`` (from ``document_from_robot``) with its sections' values shortened, in place; returned.

    Parameters
    ----------
    doc : dict
        A robot document; angles in degrees if it says ``angles: degrees``.
    scale : float
        The robot's size (``Robot.scale``, length units).
    digits : int, optional
        Significant digits for every value instead of the FK budget.
    """
    from ...representations.rounding import SNAP_BUDGET

    degrees = doc.get("angles") == "degrees"
    for key, section in doc.items():
        if not isinstance(section, dict) or key == "metrics":
            continue
        values = _values(section, _kinds(key))
        if not values:
            continue
        lengths = [abs(v) for kind, v in values if kind == "length"]
        tol_len, tol_ang = decimal_tolerances(scale, scale + math.fsum(lengths), len(values), SNAP_BUDGET)
        if degrees:
            tol_ang = math.degrees(tol_ang)

        def text(kind: str, x: float, tol_len: float = tol_len, tol_ang: float = tol_ang) -> float:
            tol = tol_len if kind == "length" else tol_ang
            if digits is not None:  # rounding noise is 0 at any number of digits
                return 0.0 if abs(x) <= tol else float(digits_text(x, digits))
            return float(short_text(x, tol))

        _apply(section, _kinds(key), text)
    return doc


def _matrix_kinds(M: Any) -> list[tuple[str, float]]:
    return [("length" if c == 3 else "angle", float(v)) for r, row in enumerate(M[:3]) for c, v in enumerate(row)]


def _values(section: dict[str, Any], kinds: dict[str, str]) -> list[tuple[str, float]]:
    """Every value of a section with its kind ('length' or 'angle'-like: radians, unit directions)."""
    out: list[tuple[str, float]] = []
    for name in ("base", "tool", "M"):
        if name in section:
            out += _matrix_kinds(section[name])
    for row in section.get("rows", []):
        items = row.items() if isinstance(row, dict) else zip(kinds, row)
        out += [(kinds[k], float(v)) for k, v in items if k in kinds]
    for screw in section.get("screws", []):
        out += [("angle" if i < 3 else "length", float(v)) for i, v in enumerate(screw)]
    for frame in section.get("frames", []):
        out += _matrix_kinds(frame)
    return out


def _round_matrix(M: list[list[float]], text: Any) -> list[list[float]]:
    return [[text("length" if c == 3 else "angle", v) if r < 3 else float(v) for c, v in enumerate(row)]
            for r, row in enumerate(M)]


def _apply(section: dict[str, Any], kinds: dict[str, str], text: Any) -> None:
    for name in ("base", "tool", "M"):
        if name in section:
            section[name] = _round_matrix(section[name], text)
    if "rows" in section:
        rows = []
        for row in section["rows"]:
            if isinstance(row, dict):
                rows.append({k: text(kinds[k], v) if k in kinds else v for k, v in row.items()})
            else:
                rows.append([text(kind, v) for kind, v in zip(kinds.values(), row)] + list(row[len(kinds):]))
        section["rows"] = rows
    if "screws" in section:
        section["screws"] = [[text("angle" if i < 3 else "length", v) for i, v in enumerate(s)]
                             for s in np.asarray(section["screws"], dtype=float).tolist()]
    if "frames" in section:
        section["frames"] = [_round_matrix(F, text) for F in section["frames"]]
