"""The GJD itself as a representation: n + 1 poses in the robot base frame at q = 0."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..robot import Robot

__all__ = ["robot_from_gjd", "gjd_from_robot"]


def robot_from_gjd(frames: ArrayLike, joints: Any = None, name: str | None = None) -> Robot:
    """The robot of n + 1 frames (n + 1, 4, 4) in the base frame at q = 0 (joint frames, then the tool).

    ``joints``: None (all revolute), a type string such as "RRPR", or n ``Joint``.

    ``frames``: the GJD frames (n + 1, 4, 4); ``name``: the robot's name (default: none).
    """
    from .table_input import joints_for

    try:
        F = np.array(frames, dtype=float)
    except (TypeError, ValueError):
        raise InputError("gjd.frames: expected n+1 4x4 matrices of numbers") from None
    if joints is None or isinstance(joints, str):  # the joints follow from the frames' count
        if F.ndim != 3 or F.shape[1:] != (4, 4) or len(F) < 2:
            raise InputError(f"robot_from_gjd: expected an (n + 1, 4, 4) array of frames (n >= 1), got shape "
                             f"{F.shape}")
        joints = joints_for(joints, len(F) - 1, "robot_from_gjd")
    return Robot(F, joints, name=name)


def gjd_from_robot(robot: Robot) -> np.ndarray:
    """The GJD frames (n + 1, 4, 4).

    ``robot``: any Robot; its frames J_1..J_n (joint i's axis along z) and J_{n+1} (the tool) at q = 0, in its
    base frame.
    """
    return np.array(robot.frames)
