"""Validation of the numbers a Robot is made of: rigid transforms and joint vectors.

``check_pose`` / ``check_poses`` accept a 4x4 (or 3x4) rigid transform, project one that is within
``PROJECTION_TOL`` of a rotation (with a ProjectionWarning naming the field) and refuse the rest with
one line; ``check_q`` checks joint vectors (n,) or (N, n). Kept apart from ``robot.py`` so that the hub
module holds the Robot itself; ``robkin.robot`` re-exports every name here.
"""

from __future__ import annotations

from typing import Callable

import numpy as np
from numpy.typing import ArrayLike

from .errors import InputError, ProjectionWarning, quote
from . import se3

__all__ = ["PROJECTION_TOL", "EXACT_TOL", "check_pose", "check_poses", "check_q"]

#: An input rotation farther than this (Frobenius norm) from SO(3), or a unit vector whose norm is
#: farther than this from 1, is an error; closer than this it is projected with a warning. 1e-2 admits
#: matrices typed with 3 decimals (error up to ~sqrt(9) * 5e-4 ~ 1.5e-3, plus cross-terms) with margin,
#: while anything visibly wrong (a typo in one entry of 0.1) is still refused.
PROJECTION_TOL = 1e-2
#: Below this the input is taken as valid without a warning (rounding noise of float64 products; a
#: rotation is still projected onto SO(3), see ``check_pose``); between this and PROJECTION_TOL it is
#: projected and a warning names the field.
EXACT_TOL = 1e-9


def check_pose(T: ArrayLike, field_name: str, *, warn: bool = True) -> np.ndarray:
    """Validate and normalise one 4x4 rigid transform.

    Returns a float array whose rotation block is exactly orthonormal (projected if the input was
    within PROJECTION_TOL, with a ProjectionWarning naming ``field_name`` if it was farther than
    EXACT_TOL; kept bit for bit if it is rigid to rounding). Raises InputError otherwise.
    """
    import warnings

    try:
        A = np.array(T, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{field_name}: expected a 4x4 matrix of numbers") from None
    if A.shape == (3, 4):
        A = np.vstack([A, [0.0, 0.0, 0.0, 1.0]])
    if A.shape != (4, 4):
        raise InputError(f"{field_name}: expected a 4x4 matrix, got shape {A.shape}")
    if not np.all(np.isfinite(A)):
        raise InputError(f"{field_name}: contains NaN or infinity")
    if np.max(np.abs(A[3] - [0, 0, 0, 1])) > EXACT_TOL:
        raise InputError(f"{field_name}: last row must be [0, 0, 0, 1], got {A[3].tolist()}")
    A[3] = [0.0, 0.0, 0.0, 1.0]
    err = float(se3.rotation_error(A[:3, :3]))
    if err > PROJECTION_TOL:
        what = "has det <= 0 (a reflection)" if not np.isfinite(err) else f"is {err:.3g} from a rotation"
        raise InputError(f"{field_name}: rotation block {what}; a rotation matrix is needed "
                         f"(tolerance {PROJECTION_TOL})")
    if err > EXACT_TOL and warn:
        warnings.warn(f"{field_name}: rotation block is {err:.2g} from orthonormal; projected onto "
                      f"the nearest rotation", ProjectionWarning, stacklevel=3)
    if err > _ROTATION_ROUNDING_TOL:
        # below EXACT_TOL silently, but projected all the same: a rotation 1e-10 from SO(3) (a rounded
        # table that happens to land close) is not rigid, and everything that relies on R^-1 = R^T
        # (se3.inv, adjoints, a PoE's body screws) is then off by that much times the robot's size
        A[:3, :3] = se3.nearest_rotation(A[:3, :3])
    return A


#: A rotation within this (Frobenius norm) of SO(3) is kept bit for bit: frames computed by robkin
#: itself (a chain of ~10 rounded products per joint) are orthonormal to ~1e-15, and documents robkin
#: wrote must read back unchanged. Farther than this, the input was not made by rotations in float64.
_ROTATION_ROUNDING_TOL = 1e-12


_LAST_ROW = np.array([0.0, 0.0, 0.0, 1.0])
_LAST_ROW.setflags(write=False)


def check_poses(A: np.ndarray, field_name: Callable[[int], str]) -> np.ndarray:
    """``check_pose`` for a stack (m, 4, 4) of float poses, in one compiled pass for the usual valid case.

    Poses that are exact rigid transforms to rounding (finite, last row exactly [0, 0, 0, 1], rotation
    orthonormal to 1e-12 with det > 0: ``robkin.compiled.runtime.rigid``, the test IK targets pass too) are
    taken as they are; a rotation that close is within ~1e-12 of SO(3), far inside EXACT_TOL, and frames
    computed by robkin itself are orthonormal to ~1e-15. Any other pose goes through ``check_pose``
    (named ``field_name(i)``) for its projection, warning or error. Returns a new array.
    """
    from .compiled.runtime.rigid import exact_poses  # ~0.1 ms once; `import robkin` itself loads no compiled code

    out = np.array(A, dtype=float)
    ok = exact_poses(out)
    if ok.all():
        return out
    out[:, 3] = _LAST_ROW
    for i in np.flatnonzero(~ok):
        out[i] = check_pose(A[i], field_name(int(i)))
    return out


def check_q(q: ArrayLike, n: int, name: str = "q") -> np.ndarray:
    """Joint values as float array (n,) or (N, n); InputError (naming ``name``) for wrong shapes or
    non-finite values."""
    try:
        Q = np.asarray(q, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{name}: expected {n} numbers") from None
    if Q.ndim == 0 or Q.shape[-1] != n or Q.ndim > 2:
        raise InputError(f"{name}: expected shape ({n},) or (N, {n}), got {Q.shape}")
    if not np.all(np.isfinite(Q)):
        raise InputError(f"{name}: contains NaN or infinity")
    return Q


def check_threads(threads: object) -> int:
    """A thread count given by the user: a whole number >= 1 (returned as int); InputError otherwise.

    ``None`` (automatic) is the callers' business: they pass 0 to the kernels for it.
    """
    if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or threads < 1:
        raise InputError(f"threads: expected a whole number >= 1 (or None for automatic), got {quote(repr(threads))}")
    return int(threads)


def check_out(out: object, shape: tuple[int, ...]) -> np.ndarray:
    """An output array given by the user (``out=``): a writeable C-contiguous float64 ndarray of exactly
    ``shape``; InputError naming what would be valid otherwise."""
    ok = (isinstance(out, np.ndarray) and out.dtype == np.float64 and out.flags.c_contiguous
          and out.flags.writeable and out.shape == shape)
    if not ok:
        got = (f"{out.dtype} array of shape {out.shape}" if isinstance(out, np.ndarray) else type(out).__name__)
        raise InputError(f"out: expected a writeable C-contiguous float64 array of shape {shape}, got {got}")
    return out  # type: ignore[return-value]
