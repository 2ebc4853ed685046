"""A robot's joints: name, type, limits, Corke's flip, and what robot files say about them.

Kept apart from ``robkin.robot`` (the GJD hub), which re-exports everything here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Iterable, Literal

from .errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    from .body_parts import Mimic

__all__ = ["Joint", "JointType", "JOINT_TYPES", "default_joints"]

JointType = Literal["revolute", "prismatic"]
JOINT_TYPES: tuple[str, ...] = ("revolute", "prismatic")


@dataclass(frozen=True)
class Joint:
    """One joint: name, type, optional limits (rad or length units) and Corke's ``flip`` flag.

    ``flip`` means the joint moves opposite to the z axis of its frame in frame-based representations
    (DH, modified DH, RPY-XYZ). The GJD and PoE always use the positive direction, so for them flip
    only decides how frame-based tables are written.

    ``effort`` (N or N m), ``velocity`` (m/s or rad/s), ``damping``, ``friction`` and ``mimic`` are
    kept from robot files and written back; kinematics never uses them. ``armature`` (MJCF: a rotor's
    reflected inertia, kg m^2 or kg; None elsewhere) is added to ``Robot.mass_matrix`` and
    ``Robot.inverse_dynamics``.
    """

    name: str
    type: JointType = "revolute"
    lower: float | None = None
    upper: float | None = None
    flip: bool = False
    effort: float | None = None
    velocity: float | None = None
    damping: float | None = None
    friction: float | None = None
    armature: float | None = None
    mimic: Mimic | None = None

    def __post_init__(self) -> None:
        if self.type not in JOINT_TYPES:
            raise InputError(f"joint '{self.name}': type '{self.type}' is not one of {', '.join(JOINT_TYPES)}")
        for bound in ("lower", "upper"):
            v = getattr(self, bound)
            if v is not None and math.isnan(v):
                raise InputError(f"joint '{self.name}': limits.{bound} is NaN")
        if self.lower is not None and self.upper is not None and self.lower > self.upper:
            raise InputError(f"joint '{self.name}': limits.lower {self.lower} > limits.upper {self.upper}")

    @property
    def revolute(self) -> bool:
        return self.type == "revolute"


def default_joints(types: Iterable[str]) -> tuple[Joint, ...]:
    """Joints named joint1..jointN with the given types."""
    return tuple(Joint(f"joint{i + 1}", t) for i, t in enumerate(types))  # type: ignore[arg-type]
