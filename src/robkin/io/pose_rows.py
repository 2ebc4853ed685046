"""Rigid transforms as twelve plain floats, for the robot-file readers' walks along a tree.

A pose is the tuple (r00, r01, r02, x, r10, r11, r12, y, r20, r21, r22, z): the top three rows of the
(4, 4) matrix [[R, p], [0, 0, 0, 1]], row by row. A reader composes one such pose per joint of a
chain; on (4, 4) arrays each product costs a numpy call and an array, which was most of the time of
loading a small URDF, while the same twelve sums of products in plain floats cost a fraction of it.
``matrices`` turns many poses into one (m, 4, 4) array at the end.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

__all__ = ["Pose", "IDENTITY", "from_xyz_rpy", "from_matrix", "compose", "inverse", "matrix", "matrices"]

#: (r00, r01, r02, x, r10, r11, r12, y, r20, r21, r22, z)
Pose = tuple[float, float, float, float, float, float, float, float, float, float, float, float]

IDENTITY: Pose = (1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0)
_LAST_ROW = (0.0, 0.0, 0.0, 1.0)


def from_xyz_rpy(xyz: Sequence[float], rpy: Sequence[float]) -> Pose:
    """A URDF origin: translation xyz, rotation Rz(yaw) Ry(pitch) Rx(roll) (angles in rad)."""
    x, y, z = xyz
    roll, pitch, yaw = rpy
    if roll == 0 and pitch == 0 and yaw == 0:
        return (1.0, 0.0, 0.0, x, 0.0, 1.0, 0.0, y, 0.0, 0.0, 1.0, z)
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cy, sy = math.cos(yaw), math.sin(yaw)
    return (cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr, x,
            sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr, y,
            -sp, cp * sr, cp * cr, z)


def from_matrix(T: np.ndarray) -> Pose:
    """The pose of a (4, 4) rigid transform (its last row is not read)."""
    return tuple(T[:3].ravel().tolist())


def compose(A: Pose, B: Pose) -> Pose:
    """A B: the pose B given in frame A."""
    a, b, c, x, d, e, f, y, g, h, i, z = A
    A_, B_, C_, X, D_, E_, F_, Y, G_, H_, I_, Z = B
    return (a * A_ + b * D_ + c * G_, a * B_ + b * E_ + c * H_, a * C_ + b * F_ + c * I_, a * X + b * Y + c * Z + x,
            d * A_ + e * D_ + f * G_, d * B_ + e * E_ + f * H_, d * C_ + e * F_ + f * I_, d * X + e * Y + f * Z + y,
            g * A_ + h * D_ + i * G_, g * B_ + h * E_ + i * H_, g * C_ + h * F_ + i * I_, g * X + h * Y + i * Z + z)


def inverse(A: Pose) -> Pose:
    """A^-1 of a rigid transform: (R^T, -R^T p)."""
    a, b, c, x, d, e, f, y, g, h, i, z = A
    return (a, d, g, -(a * x + d * y + g * z),
            b, e, h, -(b * x + e * y + h * z),
            c, f, i, -(c * x + f * y + i * z))


def matrices(poses: Sequence[Pose]) -> np.ndarray:
    """The poses as one array (m, 4, 4) (made in one call: each numpy call costs more than the copying)."""
    return np.array([p + _LAST_ROW for p in poses], dtype=float).reshape(len(poses), 4, 4)


def matrix(pose: Pose) -> np.ndarray:
    """The pose as an array (4, 4)."""
    return np.array(pose + _LAST_ROW).reshape(4, 4)
