"""The GJD itself as a representation: n + 1 poses in the robot base frame at q = 0."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..robot import Joint, Robot

__all__ = ["robot_from_gjd", "gjd_from_robot"]


def robot_from_gjd(frames: ArrayLike, joints: tuple[Joint, ...], name: str | None = None) -> Robot:
    try:
        F = np.array(frames, dtype=float)
    except (TypeError, ValueError):
        raise InputError("gjd.frames: expected n+1 4x4 matrices of numbers") from None
    return Robot(F, joints, name=name)


def gjd_from_robot(robot: Robot) -> np.ndarray:
    """The GJD frames (n + 1, 4, 4)."""
    return np.array(robot.frames)
