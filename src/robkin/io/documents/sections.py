"""Reading one section of a robot document into a Robot, by its representation's layout.

Each registered representation (``robkin.representations.registry``) has a layout: ``link-table``
(rows of its columns, base, tool; DH, modified DH, Hayati and any LinkTable registered), ``screws``
(PoE), ``rpy`` (RPY-XYZ) or ``frames`` (GJD); ``robot_of_section`` reads a section by it, with the
document's checks and messages (``reader`` holds the document around the sections).
"""

from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np

from ...errors import InputError, quote
from ...representations.registry import Representation, by_section
from ...robot import Joint, Robot
from .masses import read_masses, split_masses
from .vocabulary import ANGLE_COLUMNS
from ..files.numbers import matrix, number, number_list

__all__ = ["AngleUnitWarning", "ANGLE_WARN", "robot_of_section", "angle"]

#: An angle in radians larger than this in magnitude draws a warning: a full turn is the most any
#: table parameter or joint limit needs in practice (UR's limits are exactly +-2 pi, hence the
#: margin of rounding), and 90 or 180 in radians is almost surely a value typed in degrees.
ANGLE_WARN = 2 * math.pi * (1 + 1e-9)

class AngleUnitWarning(UserWarning):
    """An angle read in radians is larger than a full turn: it was probably typed in degrees."""


def angle(value: float, field: str, unit: str) -> float:
    """An angle read in ``unit``, in radians; a warning naming the field for radians beyond 2 pi."""
    if unit == "degrees":
        return math.radians(value)
    if abs(value) > ANGLE_WARN:
        import warnings

        warnings.warn(f"{field}: {value:g} rad is more than a full turn; if it is meant in degrees, add "
                      f"'angles: degrees' to the document", AngleUnitWarning, stacklevel=2)
    return value


def _mapping(value: Any, key: str, allowed: tuple[str, ...]) -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise InputError(f"{key}: expected a mapping with {', '.join(allowed)}")
    extra = sorted(str(k) for k in value if k not in allowed)
    if extra:
        raise InputError(f"{key}: unknown key(s) {', '.join(extra)}; known: {', '.join(allowed)}")
    return value


def _rows(value: Any, key: str, columns: tuple[str, ...], unit: str = "radians") -> list[list[float]]:
    if not isinstance(value, list) or not value:
        raise InputError(f"{key}: expected a list of rows ({', '.join(columns)})")
    rows = []
    for i, row in enumerate(value):
        where = f"{key}[{i}]"
        if isinstance(row, Mapping):
            missing = [c for c in columns if c not in row]
            extra = sorted(str(k) for k in row if k not in columns)
            if missing or extra:
                raise InputError(f"{where}: expected keys {', '.join(columns)}"
                                 + (f"; missing {', '.join(missing)}" if missing else "")
                                 + (f"; unknown {', '.join(extra)}" if extra else ""))
            rows.append([number(row[c], f"{where}.{c}") for c in columns])
        else:
            rows.append(number_list(row, where, len(columns)))
    section = key.split(".")[0]
    for j, c in enumerate(columns):
        if c in ANGLE_COLUMNS.get(section, ()):
            for i, row in enumerate(rows):
                row[j] = angle(row[j], f"{key}[{i}].{c}", unit)
    return rows


def _pose(section: Mapping[str, Any], key: str, prefix: str) -> np.ndarray:
    if section.get(key) is None:
        return np.eye(4)
    return np.array(matrix(section[key], f"{prefix}.{key}"))


def robot_of_section(key: str, value: Any, joints: tuple[Joint, ...], name: str | None,
              unit: str = "radians") -> Robot:
    """The robot of one section, read by its representation's layout (``representations.registry``)."""
    try:
        rep = by_section(key)
    except KeyError:  # pragma: no cover - keys come from SECTIONS
        raise InputError(f"unknown section '{key}'") from None
    reader = {"link-table": _link_table_robot, "screws": _screws_robot, "rpy": _rpy_robot,
              "frames": _frames_robot}[rep.layout]
    return reader(rep, value, joints, name, unit)


def _link_table_robot(rep: Representation, value: Any, joints: tuple[Joint, ...], name: str | None,
                      unit: str) -> Robot:
    """Rows of the columns, base, tool (and masses); a paper-layout section's row 0 is its base."""
    key, n = rep.section, len(joints)
    sec = _mapping(value, key, ("base", "rows", "tool", "base_mass"))
    paper = rep.paper_layout and isinstance(sec.get("rows"), list) and len(sec["rows"]) == n + 1 \
        and sec.get("base") is None  # the paper's layout: row 0 is a fixed base row (the base body's)
    raw, masses = split_masses(sec.get("rows"), f"{key}.rows", len(rep.keys), base_row=0 if paper else None,
                               base_mass=sec.get("base_mass"))
    rows = _rows(raw, f"{key}.rows", rep.keys, unit)
    base = _pose(sec, "base", key)
    cls = rep.table_type()
    if paper:
        base = cls.link_matrix(*rows[0])
        rows = rows[1:]
    return rep.robot_of(cls(np.array(rows), joints, base=base, tool=_pose(sec, "tool", key), masses=masses),
                        name=name)


def _screws_robot(rep: Representation, value: Any, joints: tuple[Joint, ...], name: str | None,
                  unit: str) -> Robot:
    """Screws, M, frame (and masses)."""
    key, n = rep.section, len(joints)
    sec = _mapping(value, key, ("frame", "M", "screws", "masses", "base_mass"))
    frame = sec.get("frame", rep.from_robot_args[0] if rep.from_robot_args else "space")
    if frame not in ("space", "body"):
        raise InputError(f"{key}.frame: {quote(frame)} is not one of space, body")
    if sec.get("M") is None:
        raise InputError(f"{key}.M: missing; the 4x4 home pose of the tool")
    screws = sec.get("screws")
    if not isinstance(screws, list):
        raise InputError(f"{key}.screws: expected a list of [{', '.join(rep.keys)}], one per joint")
    S = [number_list(s, f"{key}.screws[{i}]", len(rep.keys)) for i, s in enumerate(screws)]
    table = rep.table_type()(np.array(matrix(sec["M"], f"{key}.M")), np.array(S).reshape(-1, len(rep.keys)),
                             joints, frame, read_masses(sec.get("masses"), f"{key}.masses", n, sec.get("base_mass")))
    return rep.robot_of(table, name=name)


def _rpy_robot(rep: Representation, value: Any, joints: tuple[Joint, ...], name: str | None,
               unit: str) -> Robot:
    """n + 2 rows: world -> base (the base body's masses), one per joint, the tool (no body)."""
    key = rep.section
    sec = _mapping(value, key, ("rows",))
    rows_in = sec.get("rows")
    tool = (len(rows_in) - 1,) if isinstance(rows_in, list) else ()  # the tool row: no body
    raw, masses = split_masses(rows_in, f"{key}.rows", len(rep.keys), tool, base_row=0)  # row 0: the base's
    table = rep.table_type()(np.array(_rows(raw, f"{key}.rows", rep.keys, unit)), joints, masses)
    return rep.robot_of(table, name=name)


def _frames_robot(rep: Representation, value: Any, joints: tuple[Joint, ...], name: str | None,
                  unit: str) -> Robot:
    """The GJD's n + 1 frames."""
    key, n = rep.section, len(joints)
    sec = _mapping(value, key, ("frames",))
    frames = sec.get("frames")
    if not isinstance(frames, list):
        raise InputError(f"{key}.frames: expected a list of n + 1 = {n + 1} 4x4 matrices")
    from importlib import import_module

    robot_from = getattr(import_module(rep.module), rep.to_robot)
    return robot_from([matrix(F, f"{key}.frames[{i}]") for i, F in enumerate(frames)], joints, name)


