"""Where two robots differ, the parameters that differ: both written as the same kind of table.

``equivalence.compare`` finds the first joint whose axis cannot be matched. Past it the joint-by-joint
walk has no mapping to go on with, but the two robots can still be compared parameter by parameter:
written by the same frame rules as the same kind of table (standard DH, or modified DH / Hayati when
one of them came from such a table), every row whose numbers differ names what differs and by how
much ("a2 = -0.6127 m in A, -0.612 m in B"). The frame rules are canonical (they depend only on the
axes), so rows of the same geometry agree and a difference in one joint does not spill into the rows
of the others (a length between two axes sits in one row).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..robot import Robot

__all__ = ["ParameterDifference", "parameter_differences", "table_kind"]


@dataclass(frozen=True)
class ParameterDifference:
    """One table value that differs: joint (1-based; 0 for the base, n + 1 for the tool), the
    parameter's name ('a2', 'theta1', 'base x'), its value in A and in B, and its unit ('m' or 'rad')."""

    joint: int
    parameter: str
    a: float
    b: float
    unit: str

    def text(self) -> str:
        from ..io.files.float_text import distinct_texts

        a, b = distinct_texts(self.a, self.b)  # 6 digits, or as many more as show the difference
        return f"{self.parameter} {a} vs {b} {self.unit}"

    def to_dict(self) -> dict[str, Any]:
        return {"joint": self.joint, "parameter": self.parameter, "a": self.a, "b": self.b, "unit": self.unit}


def table_kind(a: Robot, b: Robot) -> str:
    """The table both are written as: the kind either came from (modified DH, Hayati), else standard DH."""
    for kind in ("mdh", "hayati"):
        if kind in (a.frames_from, b.frames_from):
            return kind
    return "dh"


def _table(robot: Robot, kind: str) -> Any:
    from ..representations import dh_from_robot, hayati_from_robot, mdh_from_robot

    fn = {"dh": dh_from_robot, "mdh": mdh_from_robot, "hayati": hayati_from_robot}[kind]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # conditioning notes belong to a conversion, not to a check
        return fn(robot)


def _angle_gap(x: float, y: float) -> float:
    """|x - y| on the circle (radians)."""
    return abs(math.remainder(x - y, 2 * math.pi))


def parameter_differences(a: Robot, b: Robot, scale: float, tol: float) -> tuple[str, list[ParameterDifference]]:
    """(table kind, the values that differ) of two robots with the same joint count.

    Lengths are compared to ``tol * scale`` (metres, or the robots' unit), angles to ``tol`` radians
    (on the circle: pi and -pi are the same angle). The base and tool transforms are compared by their
    translation (x, y, z) and rotation (angle in rad).
    """
    kind = table_kind(a, b)
    ta, tb = _table(a, kind), _table(b, kind)
    names = list(ta.COLUMNS)
    prev = kind == "mdh"  # Craig's a and alpha belong to the previous link: a0, alpha0 in row 1
    out: list[ParameterDifference] = []
    for i, (ra, rb) in enumerate(zip(np.asarray(ta.rows), np.asarray(tb.rows))):
        for name, x, y in zip(names, ra, rb):
            angle = name not in ("a", "d")
            index = i if prev and name in ("a", "alpha") else i + 1
            gap = _angle_gap(x, y) if angle else abs(x - y)
            if gap > (tol if angle else tol * scale):
                out.append(ParameterDifference(i + 1, f"{name}{index}", float(x), float(y), "rad" if angle else "m"))
    for label, Ta, Tb, joint in (("base", ta.base, tb.base, 0), ("tool", ta.tool, tb.tool, a.n + 1)):
        for axis, x, y in zip("xyz", Ta[:3, 3], Tb[:3, 3]):
            if abs(x - y) > tol * scale:
                out.append(ParameterDifference(joint, f"{label} {axis}", float(x), float(y), "m"))
        ra, rb = _rotation_angle(Ta[:3, :3]), _rotation_angle(Tb[:3, :3])
        turn = _rotation_angle(Ta[:3, :3].T @ Tb[:3, :3])
        if turn > tol:
            out.append(ParameterDifference(joint, f"{label} rotation", ra, rb, "rad"))
    return kind, out


def _rotation_angle(R: np.ndarray) -> float:
    return math.acos(max(-1.0, min(1.0, (float(np.trace(R)) - 1.0) / 2.0)))
