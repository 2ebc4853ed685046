"""Plain arrays as tables: what lets ``robot_from_dh(np.array(...))`` work.

Every ``robot_from_<rep>`` takes its table object or the plain numbers of one: an (n, 4) array of
DH / modified DH rows, (n, 5) Hayati rows, (n + 2, 6) RPY-XYZ rows, (n, 6) PoE screws (with ``M``).
Joints are revolute unless ``joints`` says otherwise: a sequence of ``Joint``, or a type string
such as ``"RRPR"`` (R revolute, P prismatic), one letter per row. Anything else is one InputError
naming the function and what it accepts.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from ..errors import InputError
from ..robot import Joint

__all__ = ["JointsLike", "joints_for", "rows_array"]

#: What ``joints=`` may be: None (all revolute), a type string "RRPR", or Joint objects.
JointsLike = "None | str | Sequence[Joint]"


def _kind(value: Any) -> str:
    shape = getattr(value, "shape", None)
    return f"an array of shape {tuple(shape)}" if shape is not None else f"a {type(value).__name__}"


def rows_array(value: Any, columns: Sequence[str], where: str, *, extra_rows: int = 0,
               expected: str = "") -> np.ndarray:
    """``value`` as an (m, len(columns)) float array of finite numbers, or InputError naming ``where``.

    ``extra_rows`` is how many rows a table has beyond one per joint (RPY-XYZ: 2), for the message.
    """
    want = expected or (f"an (n{f' + {extra_rows}' if extra_rows else ''}, {len(columns)}) array of rows "
                        f"({', '.join(columns)})")
    if isinstance(value, (str, bytes, dict)) or value is None:
        raise InputError(f"{where}: expected {want}, got {_kind(value)}")
    try:
        R = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{where}: expected {want} of numbers, got {_kind(value)}") from None
    if R.ndim != 2 or R.shape[1] != len(columns) or R.shape[0] <= extra_rows:
        raise InputError(f"{where}: expected {want}, got shape {R.shape}")
    bad = np.argwhere(~np.isfinite(R))
    if bad.size:
        i, j = bad[0]
        raise InputError(f"{where}: row {i} {columns[j]} must be a finite number")
    return R


def joints_for(joints: Any, n: int, where: str) -> tuple[Joint, ...]:
    """n joints from ``joints`` (None: revolute joint1..jointn; "RRPR"; or n Joint objects)."""
    if joints is None:
        return tuple(Joint(f"joint{i + 1}") for i in range(n))
    if isinstance(joints, str):
        letters = joints.replace(" ", "").upper()
        if len(letters) != n or set(letters) - {"R", "P"}:
            raise InputError(f"{where}: joints='{joints[:40]}': expected {n} letters R (revolute) or "
                             f"P (prismatic), one per row")
        return tuple(Joint(f"joint{i + 1}", "revolute" if c == "R" else "prismatic")
                     for i, c in enumerate(letters))
    try:
        out = tuple(joints)
    except TypeError:
        raise InputError(f"{where}: joints= expected a type string such as 'RRPR' or a list of Joint, "
                         f"got {_kind(joints)}") from None
    if len(out) != n or not all(isinstance(j, Joint) for j in out):
        raise InputError(f"{where}: joints= expected {n} Joint objects (one per row) or a type string, "
                         f"got {len(out)} item(s)")
    return out


def link_table_of(cls: Any, value: Any, where: str, joints: Any = None, base: Any = None,
                  tool: Any = None) -> Any:
    """``value`` when it is a ``cls`` table, else a ``cls`` built from an (n, k) array of rows.

    Parameters
    ----------
    cls : type
        DHTable, MDHTable or HayatiTable (its ``COLUMNS`` and ``SECTION``).
    value : cls or array_like (n, k)
        The table, or its rows (lengths in the robot's unit, angles in radians).
    where : str
        The calling function's name, for messages.
    joints : None, str or sequence of Joint
        See ``joints_for``; only with an array.
    base, tool : (4, 4) array_like, optional
        Only with an array; identity when absent.
    """
    if isinstance(value, cls):
        if joints is not None or base is not None or tool is not None:
            raise InputError(f"{where}: joints=, base= and tool= go with an array of rows; the "
                             f"{cls.__name__} has its own")
        return value
    section = cls.SECTION
    if hasattr(value, "SECTION") or hasattr(value, "screws"):
        other = getattr(value, "SECTION", "poe")
        raise InputError(f"{where}: got a {type(value).__name__} ({other} table); use robot_from_{other} "
                         f"or its .to_robot()")
    rows = rows_array(value, cls.COLUMNS, f"{where}", expected=f"a {cls.__name__} or an (n, {len(cls.COLUMNS)}) "
                      f"array of {section} rows ({', '.join(cls.COLUMNS)})")
    kw = {k: v for k, v in (("base", base), ("tool", tool)) if v is not None}
    return cls(rows, joints_for(joints, len(rows), where), **kw)
