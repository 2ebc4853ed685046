"""Joints whose lower limit equals the upper one: locked, one meaning in every reader and writer.

A URDF ``<limit lower="0" upper="0">`` (also a ``<limit>`` without ``lower``/``upper``, which the URDF
specification defaults to 0) gives a joint an empty range. urdfdom (and so ROS, KDL, MoveIt),
pinocchio and yourdfpy all read the range as written: the joint cannot leave that value (pinocchio's
``lowerPositionLimit == upperPositionLimit``, its random configurations hold it there). MuJoCo's URDF
compiler alone ignores such a limit ("equal lower and upper limits, limit ignored") and lets the joint
turn freely. robkin follows the shared reading: IK and sampling hold the joint at its value, the GUI's
slider cannot move it, the URDF writer repeats the limit, and an MJCF (MuJoCo refuses an empty
``range``) holds it with a joint equality (``polycoef`` = the value). Reading one says so in one line.
"""

from __future__ import annotations

import warnings
from typing import Any, Callable, Iterable

__all__ = ["locked_value", "locked_joints", "warn_locked", "mjcf_lock_equalities"]


def locked_value(lower: float | None, upper: float | None) -> float | None:
    """The value a joint is held at when its limits are equal, else None.

    ``lower``, ``upper``: the joint's limits (None where there is none).
    """
    return lower if lower is not None and upper is not None and lower == upper else None


def locked_joints(joints: Iterable[Any]) -> list[tuple[str, float]]:
    """(name, value) of each joint (anything with ``name``, ``lower``, ``upper``: ``Joint``,
    ``UrdfJoint``, the MJCF writer's plans) whose lower limit equals its upper one, in order.

    ``joints``: the joints, in order.
    """
    out = []
    for j in joints:
        v = locked_value(j.lower, j.upper)
        if v is not None:
            out.append((j.name, v))
    return out


def warn_locked(source: str, joints: Iterable[Any]) -> None:
    """One warning line naming the joints with equal limits, if any (see the module doc).

    ``source``: the file the warning names; ``joints``: the joints, as ``locked_joints`` takes them.
    """
    locked = locked_joints(joints)
    if not locked:
        return
    names = ", ".join(f"'{n}'" for n, _ in locked[:6]) + (f" and {len(locked) - 6} more" if len(locked) > 6 else "")
    warnings.warn(f"{source}: joint(s) {names} have equal lower and upper limits (a URDF <limit> without lower/upper "
                  f"is 0 0): read as locked at that value, as urdfdom and pinocchio read it (MuJoCo's "
                  f"URDF compiler ignores such limits); give a range, or type continuous, for a joint that moves",
                  UserWarning, stacklevel=3)


def mjcf_lock_equalities(joints: Iterable[Any], quoteattr: Callable[[str], str],
                         number: Callable[[float], str]) -> list[str]:
    """MJCF ``<joint>`` equality elements holding each locked joint at its value (for ``<equality>``).

    ``quoteattr`` quotes an attribute value, ``number`` writes a float (the writer's own helpers).

    ``joints``: the joints, as ``locked_joints`` takes them.
    """
    return [f"<joint joint1={quoteattr(name)} polycoef=\"{number(v)} 0 0 0 0\"/>" for name, v in locked_joints(joints)]
