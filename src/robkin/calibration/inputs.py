"""The checked inputs of a calibration: joint values, measured points and orientations, the hold-out
split, a known base pose or marker. Bad values raise one ``InputError`` naming the argument and pose."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .. import se3
from ..errors import InputError
from ..robot import Robot

__all__ = ["check_measured", "split_holdout", "check_pose", "check_marker"]


def check_measured(robot: Robot, q: ArrayLike, positions: ArrayLike, orientations: ArrayLike | None
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    Q = np.asarray(q, dtype=float)
    P = np.asarray(positions, dtype=float)
    if Q.ndim != 2 or Q.shape[1] != robot.n:
        raise InputError(f"q: expected shape (N, {robot.n}) (one column per joint), got {Q.shape}")
    if P.shape != (len(Q), 3):
        raise InputError(f"positions: expected shape ({len(Q)}, 3), got {P.shape}")
    if len(Q) < 3:
        raise InputError(f"measurements: {len(Q)} poses; calibration needs many more (see the guide: 30-100)")
    for name, v in (("q", Q), ("positions", P)):
        bad = np.argwhere(~np.isfinite(v))
        if bad.size:
            raise InputError(f"{name}: pose {bad[0][0] + 1} holds a value that is not a finite number")
    if orientations is None:
        return Q, P, None
    O = np.asarray(orientations, dtype=float)
    if O.shape == (len(Q), 4):
        norms = np.linalg.norm(O, axis=1)
        off = np.flatnonzero(~(np.abs(norms - 1.0) < 1e-3))  # 3-4 digits typed: beyond, not a unit quaternion
        if off.size:
            raise InputError(f"orientations: pose {off[0] + 1}: quaternion (qw, qx, qy, qz) has norm "
                             f"{norms[off[0]]:.6g}, not 1")
        O = _matrix_from_quaternion(O / norms[:, None])
    elif O.shape == (len(Q), 3, 3):
        err = se3.rotation_error(O)
        off = np.flatnonzero(~(err < 1e-6))   # rotation matrices typed or computed to ~1e-9 and better
        if off.size:
            raise InputError(f"orientations: pose {off[0] + 1} is not a rotation matrix")
    else:
        raise InputError(f"orientations: expected ({len(Q)}, 4) quaternions (w, x, y, z) or ({len(Q)}, 3, 3) "
                         f"rotations, got {O.shape}")
    return Q, P, O


def _matrix_from_quaternion(qt: np.ndarray) -> np.ndarray:
    w, x, y, z = qt.T
    return np.stack([np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
                     np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
                     np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], -2)


def split_holdout(N: int, holdout: float | ArrayLike | None, seed: int) -> tuple[np.ndarray, np.ndarray]:
    if holdout is None:
        return np.arange(N), np.arange(0)
    h = np.asarray(holdout)
    if h.ndim == 0:
        f = float(h)
        if not 0 <= f < 1:
            raise InputError(f"holdout: {f} is not a fraction in [0, 1)")
        k = int(round(f * N))
        mask = np.zeros(N, dtype=bool)
        mask[np.random.default_rng(seed).choice(N, size=k, replace=False)] = True
    else:
        if h.shape != (N,) or h.dtype != bool:
            raise InputError(f"holdout: expected a fraction or a boolean mask of {N} poses")
        mask = h
    if N - mask.sum() < 3:
        raise InputError("holdout: leaves fewer than 3 poses to fit")
    return np.flatnonzero(~mask), np.flatnonzero(mask)


def check_pose(T: ArrayLike, name: str) -> np.ndarray:
    from ..robot import check_pose as checked

    return checked(T, name)


def check_marker(m: ArrayLike, full_pose: bool) -> np.ndarray:
    a = np.asarray(m, dtype=float)
    if a.shape == (3,) and np.all(np.isfinite(a)):
        return a
    if a.shape == (4, 4):
        return check_pose(a, "marker")
    raise InputError("marker: expected a point (x, y, z) in the tool frame or a 4x4 pose")
