"""One joint of a robot tree as the readers give it (URDF; the MJCF and SDF readers make them too)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ...compiled.conversions import pose_rows

if TYPE_CHECKING:
    from ...body_parts import Mimic

__all__ = ["UrdfJoint"]


class UrdfJoint:
    """One <joint> element, parsed: origin (4, 4), axis (3,), limits (None where absent).

    ``xyz_rpy`` are the six origin numbers as the file wrote them (so that a writer can repeat them
    exactly); effort, velocity, damping, friction, armature (MJCF: rotor inertia, kg m^2 or kg) and
    mimic are None where the file gave none.

    The URDF reader gives ``origin`` as None and ``axis`` as three floats: the (4, 4) and (3,) arrays
    are then made from ``xyz_rpy`` (the MJCF and SDF readers: from ``pose``, twelve floats) and those
    floats only when asked for; the chain reader works with
    ``pose()`` and ``axis_xyz()`` (plain floats), so a load makes no array per joint. Read-only by
    convention (the attributes are not to be changed).
    """

    __slots__ = ("name", "type", "parent", "child", "_origin", "_axis", "_pose", "lower", "upper", "mimic",
                 "effort", "velocity", "damping", "friction", "xyz_rpy", "armature")

    def __init__(self, name: str, type: str, parent: str, child: str, origin: np.ndarray | None,
                 axis: np.ndarray | tuple[float, float, float], lower: float | None, upper: float | None,
                 mimic: Mimic | None = None, effort: float | None = None, velocity: float | None = None,
                 damping: float | None = None, friction: float | None = None,
                 xyz_rpy: tuple[float, ...] | None = None, armature: float | None = None,
                 pose: pose_rows.Pose | None = None) -> None:
        if origin is None and xyz_rpy is None and pose is None:
            raise TypeError("UrdfJoint needs an origin, its pose or its xyz_rpy numbers")
        self.name, self.type, self.parent, self.child = name, type, parent, child
        self._origin, self._axis, self._pose = origin, axis, pose
        self.lower, self.upper, self.mimic = lower, upper, mimic
        self.effort, self.velocity, self.damping, self.friction = effort, velocity, damping, friction
        self.xyz_rpy, self.armature = xyz_rpy, armature

    @property
    def origin(self) -> np.ndarray:
        """Pose (4, 4) of the child link in the parent link frame at q = 0."""
        if self._origin is None:
            self._origin = pose_rows.matrix(self.pose())
        return self._origin

    def pose(self) -> pose_rows.Pose:
        """``origin`` as twelve plain floats (see ``pose_rows``; no array made for a URDF joint), made once."""
        if self._pose is None:
            if self._origin is None:
                v: tuple[float, ...] = self.xyz_rpy  # type: ignore[assignment]  # set: see __init__
                self._pose = pose_rows.from_xyz_rpy(v[:3], v[3:])
            else:
                self._pose = pose_rows.from_matrix(self._origin)
        return self._pose

    @property
    def axis(self) -> np.ndarray:
        """The axis (3,) as the file gave it (not normalised)."""
        if not isinstance(self._axis, np.ndarray):
            self._axis = np.array(self._axis, dtype=float)
        return self._axis

    def axis_xyz(self) -> tuple[float, float, float]:
        """The axis as three plain floats (no array made)."""
        x, y, z = self._axis if not isinstance(self._axis, np.ndarray) else self._axis.tolist()
        return float(x), float(y), float(z)

    def __repr__(self) -> str:
        return f"UrdfJoint({self.name!r}, {self.type!r}, parent={self.parent!r}, child={self.child!r})"
