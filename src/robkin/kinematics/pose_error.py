"""Inverse-kinematics inputs: target checks and residual masks.

The residual of a current pose T towards a target T_d is the 6-vector (e_p, e_o) in the robot base
frame: e_p = p_d - p (length units) and e_o = log(R_d R^T) (a rotation vector, radians), computed by
the compiled core (``compiled.ik.lm``: the solver and ``pose_errors``). A *mask*
selects which of the six components (x, y, z, rx, ry, rz) count, as in the estimation paper's
position-only structures: 'pose' is all six, 'position' the first three.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..compiled.runtime.rigid import exact_poses
from ..errors import InputError
from ..robot import check_pose

__all__ = ["check_targets", "check_mask", "MASKS", "FULL_POSE"]

#: named masks over the residual components (x, y, z, rx, ry, rz)
MASKS: dict[str, tuple[float, ...]] = {
    "pose": (1.0, 1.0, 1.0, 1.0, 1.0, 1.0),
    "position": (1.0, 1.0, 1.0, 0.0, 0.0, 0.0),
}


def _read_only(values: tuple[float, ...]) -> np.ndarray:
    a = np.array(values)
    a.setflags(write=False)
    return a


#: the named masks as read-only arrays, built once (a single IK call should not pay for them)
_MASK_ARRAYS = {name: _read_only(values) for name, values in MASKS.items()}
FULL_POSE = _MASK_ARRAYS["pose"]


def check_mask(mask: str | ArrayLike | None) -> np.ndarray:
    """A mask (6,) of 0/1 over (x, y, z, rx, ry, rz) from a name ('pose', 'position') or 6 values.

    Named masks (and None, the full pose) come back as shared read-only arrays (``FULL_POSE`` for the
    full pose), values as a new array."""
    if mask is None:
        return FULL_POSE
    if isinstance(mask, str):
        if mask not in MASKS:
            raise InputError(f"mask: '{mask}' is not one of {', '.join(MASKS)} (or give 6 values 0/1 "
                             f"for x, y, z, rx, ry, rz)")
        return _MASK_ARRAYS[mask]
    try:
        m = np.array(mask, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InputError("mask: expected 6 values 0/1 for x, y, z, rx, ry, rz") from None
    if m.shape != (6,) or not np.all((m == 0) | (m == 1)):
        raise InputError(f"mask: expected 6 values 0/1 for x, y, z, rx, ry, rz, got {m.tolist()}")
    if not m.any():
        raise InputError("mask: selects no component; at least one of x, y, z, rx, ry, rz must be 1")
    return m


def check_targets(T: ArrayLike, field_name: str = "target") -> tuple[np.ndarray, bool]:
    """Targets as (N, 4, 4) with exactly orthonormal rotations, and whether the input was one (4, 4) pose."""
    try:
        A = np.asarray(T, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{field_name}: expected a 4x4 pose or an (N, 4, 4) array of poses") from None
    single = A.shape == (4, 4)
    if single:
        A = A[None]
    elif A.ndim != 3 or A.shape[1:] != (4, 4):
        raise InputError(f"{field_name}: expected a 4x4 pose or an (N, 4, 4) array of poses, got shape {A.shape}")
    # Fast path: exact rotations (the usual case: targets from FK) pass unchanged, checked by a
    # compiled loop; the others go through check_pose one by one for its projection and messages
    # (the first non-finite pose raises there). Targets are only read, never written.
    ok = exact_poses(A)
    if ok[0] if single else ok.all():      # one pose: indexing costs far less than a reduction
        return A, single
    out = A.copy()
    for i in np.flatnonzero(~ok):
        out[i] = check_pose(A[i], field_name if single else f"{field_name}[{i}]")
    return out, single
