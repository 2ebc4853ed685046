"""A robot's joints: name, type, limits, Corke's flip, and what robot files say about them.

Kept apart from ``robkin.robot`` (the GJD hub), which re-exports everything here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Iterable, Literal, Sequence

import numpy as np
from numpy.typing import ArrayLike

from .errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    from .body_parts import Mimic

__all__ = ["Joint", "JointType", "JOINT_TYPES", "default_joints", "home_configuration"]

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
    stiffness: float | None = None

    def __post_init__(self) -> None:
        if self.type not in JOINT_TYPES:
            raise InputError(f"joint '{self.name}': type '{self.type}' is not one of {', '.join(JOINT_TYPES)}")
        for bound in ("lower", "upper"):
            v = getattr(self, bound)
            if v is not None and math.isnan(v):
                raise InputError(f"joint '{self.name}': limits.{bound} is NaN")
        if self.stiffness is not None and not (math.isfinite(self.stiffness) and self.stiffness > 0):
            raise InputError(f"joint '{self.name}': stiffness {self.stiffness} is not a positive number "
                             f"(N m/rad, or N/m for a prismatic joint)")
        if self.lower is not None and self.upper is not None and self.lower > self.upper:
            raise InputError(f"joint '{self.name}': limits.lower {self.lower} > limits.upper {self.upper}")

    @property
    def revolute(self) -> bool:
        return self.type == "revolute"


def default_joints(types: Iterable[str]) -> tuple[Joint, ...]:
    """Joints named joint1..jointN with the given types."""
    return tuple(Joint(f"joint{i + 1}", t) for i, t in enumerate(types))  # type: ignore[arg-type]


#: How far (rad or length units) a given home may lie outside a joint's limits and still count as on
#: them: the rounding of limits written in decimal (a home typed as the limit's printed value).
HOME_LIMIT_TOL = 1e-9


def home_configuration(joints: Sequence[Joint], q: ArrayLike | None = None) -> np.ndarray:
    """The robot's home: q = 0 clipped into each joint's limits, or a given ``q`` checked against them.

    This is the one definition every consumer shares: the MJCF writer's keyframe ``home`` (and its
    servos' ``ctrl``), the GUI's "home" button, the USD writer's initial state. A joint whose range
    excludes 0 (the Panda's joint 4, [-3.07, -0.07]) is homed on its nearest limit.

    Parameters
    ----------
    joints : sequence of Joint (n,)
    q : (n,) array_like, optional
        A home of the caller's (``robkin convert --home``): n finite numbers, each within its joint's
        limits (``HOME_LIMIT_TOL`` of rounding allowed, and clipped onto the limit).

    Returns
    -------
    (n,) float array

    Raises
    ------
    InputError
        ``q`` of the wrong length, not finite, or outside a joint's limits (the message names it).
    """
    lower = np.array([-np.inf if j.lower is None else j.lower for j in joints], dtype=float)
    upper = np.array([np.inf if j.upper is None else j.upper for j in joints], dtype=float)
    if q is None:
        return np.clip(np.zeros(len(joints)), lower, upper)
    try:
        v = np.asarray(q, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InputError(f"home: expected {len(joints)} numbers (one per joint)") from None
    if v.shape != (len(joints),):
        raise InputError(f"home: expected {len(joints)} numbers (one per joint), got {v.size}")
    if not np.all(np.isfinite(v)):
        raise InputError("home: expected finite numbers")
    for j, x, lo, hi in zip(joints, v, lower, upper):
        if not lo - HOME_LIMIT_TOL <= x <= hi + HOME_LIMIT_TOL:
            raise InputError(f"home: joint '{j.name}' at {x:g} is outside its limits [{lo:g}, {hi:g}]")
    return np.clip(v, lower, upper)
