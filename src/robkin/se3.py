"""Small SE(3)/SO(3) helpers on plain numpy arrays.

Every function accepts a single element or a batch with leading dimensions: a pose is ``(..., 4, 4)``,
a rotation ``(..., 3, 3)``, an angle ``(...)``. Angles are radians, lengths any consistent unit.

Hand-written rather than taken from a library: the kernels here are a dozen lines each, sit on the hot
path of batch forward kinematics, and must broadcast over arbitrary batch shapes without per-element
Python calls (``scipy.spatial.transform.Rotation`` covers rotations only and its batch API allocates
objects; pytransform3d is not vectorised over batches for most functions).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "rot_x", "rot_y", "rot_z", "trans", "homogeneous", "inv", "cross", "skew",
    "matrix_from_rpy", "rpy_from_matrix", "quaternion_from_matrix", "exp_twist", "adjoint", "log_rotation",
    "nearest_rotation", "rotation_error", "dh_matrix", "mdh_matrix",
]

Array = NDArray[np.float64]


def _axis_rotation(angle: ArrayLike, i: int, j: int) -> Array:
    """Rotation by ``angle`` in the (i, j) coordinate plane as (..., 4, 4)."""
    angle = np.asarray(angle, dtype=float)
    c, s = np.cos(angle), np.sin(angle)
    out = np.zeros(angle.shape + (4, 4))
    out[..., 0, 0] = out[..., 1, 1] = out[..., 2, 2] = out[..., 3, 3] = 1.0
    out[..., i, i] = c
    out[..., j, j] = c
    out[..., i, j] = -s
    out[..., j, i] = s
    return out


def rot_x(angle: ArrayLike) -> Array:
    """Homogeneous rotation about x, shape (..., 4, 4)."""
    return _axis_rotation(angle, 1, 2)


def rot_y(angle: ArrayLike) -> Array:
    """Homogeneous rotation about y, shape (..., 4, 4)."""
    return _axis_rotation(angle, 2, 0)


def rot_z(angle: ArrayLike) -> Array:
    """Homogeneous rotation about z, shape (..., 4, 4)."""
    return _axis_rotation(angle, 0, 1)


def trans(x: ArrayLike = 0.0, y: ArrayLike = 0.0, z: ArrayLike = 0.0) -> Array:
    """Homogeneous translation, shape (..., 4, 4) broadcast over x, y, z."""
    x, y, z = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x, y, z)))
    out = np.zeros(x.shape + (4, 4))
    out[..., 0, 0] = out[..., 1, 1] = out[..., 2, 2] = out[..., 3, 3] = 1.0
    out[..., 0, 3], out[..., 1, 3], out[..., 2, 3] = x, y, z
    return out


def homogeneous(R: ArrayLike, p: ArrayLike) -> Array:
    """Pose from rotation (..., 3, 3) and translation (..., 3) -> (..., 4, 4)."""
    R = np.asarray(R, dtype=float)
    p = np.asarray(p, dtype=float)
    shape = np.broadcast_shapes(R.shape[:-2], p.shape[:-1])
    out = np.zeros(shape + (4, 4))
    out[..., :3, :3] = R
    out[..., :3, 3] = p
    out[..., 3, 3] = 1.0
    return out


def inv(T: ArrayLike) -> Array:
    """Inverse of rigid transforms (..., 4, 4), using R^T rather than a general inverse."""
    T = np.asarray(T, dtype=float)
    Rt = np.swapaxes(T[..., :3, :3], -1, -2)
    return homogeneous(Rt, -np.einsum("...ij,...j->...i", Rt, T[..., :3, 3]))


def cross(a: ArrayLike, b: ArrayLike) -> Array:
    """Cross products of 3-vectors (..., 3) x (..., 3) -> (..., 3), broadcasting.

    The same values as ``numpy.cross``, written out: numpy's moves axes and checks shapes on every
    call, which costs ~10x the arithmetic for the small arrays of the synthesis loops.
    """
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=-1)


def skew(w: ArrayLike) -> Array:
    """Skew-symmetric matrix [w] of (..., 3) vectors -> (..., 3, 3), so that [w] v = w x v."""
    w = np.asarray(w, dtype=float)
    out = np.zeros(w.shape[:-1] + (3, 3))
    out[..., 0, 1], out[..., 0, 2] = -w[..., 2], w[..., 1]
    out[..., 1, 0], out[..., 1, 2] = w[..., 2], -w[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -w[..., 1], w[..., 0]
    return out


def matrix_from_rpy(rpy: ArrayLike) -> Array:
    """Rotation R = Rz(yaw) Ry(pitch) Rx(roll) (the URDF convention) from (..., 3) -> (..., 3, 3)."""
    rpy = np.asarray(rpy, dtype=float)
    r, p, y = rpy[..., 0], rpy[..., 1], rpy[..., 2]
    return (rot_z(y) @ rot_y(p) @ rot_x(r))[..., :3, :3]


def rpy_from_matrix(R: ArrayLike) -> Array:
    """(roll, pitch, yaw) with R = Rz(yaw) Ry(pitch) Rx(roll), from (..., 3, 3) -> (..., 3).

    pitch is in [-pi/2, pi/2]. At gimbal lock (|pitch| = pi/2 to rounding) roll is set to 0 and yaw
    carries the whole rotation about the common axis. At every pitch the angles rebuild R to rounding.
    """
    R = np.asarray(R, dtype=float)
    # pitch from -R20 via atan2 with the norm of the first column: accurate near +-pi/2, unlike asin.
    cos_pitch = np.hypot(R[..., 0, 0], R[..., 1, 0])
    pitch = np.arctan2(-R[..., 2, 0], cos_pitch)
    # Gimbal lock: roll is set to 0 and yaw carries the rotation about the common axis. Setting roll
    # to 0 costs an error ~cos(pitch) in the rebuilt R, so the lock is taken only where that is
    # rounding noise (4 eps); everywhere else the general formulas below reproduce R to rounding.
    locked = cos_pitch < 4 * np.finfo(float).eps
    roll = np.where(locked, 0.0, np.arctan2(R[..., 2, 1], R[..., 2, 2]))
    # yaw from what is left once roll and pitch are undone, Rz(yaw) = R Rx(roll)^T Ry(pitch)^T, rather
    # than from R's first column: near gimbal lock roll carries an error ~eps / cos(pitch), and a yaw
    # read independently would not compensate it (R rebuilt from the angles was off by ~1e-7 at
    # cos(pitch) = 1e-9). Read from the residual, yaw absorbs the roll error about the near-common
    # axis, and the angles reproduce R to rounding at every pitch.
    undo = np.swapaxes((rot_y(pitch) @ rot_x(roll))[..., :3, :3], -1, -2)
    Rz = R @ undo
    yaw = np.arctan2(Rz[..., 1, 0], Rz[..., 0, 0])
    return np.stack([roll, pitch, yaw], axis=-1)


def quaternion_from_matrix(R: ArrayLike) -> Array:
    """Unit quaternion (w, x, y, z) with w >= 0 of a rotation (..., 3, 3) -> (..., 4).

    Shepperd's method: the largest of |w|, |x|, |y|, |z| comes from a square root of a sum of diagonal
    terms (at least 1/2 of the norm, so no cancellation), the others from off-diagonal sums divided by
    it; every component is then accurate to rounding. Of the two quaternions of R, the one with w >= 0.
    """
    R = np.asarray(R, dtype=float)
    r00, r11, r22 = R[..., 0, 0], R[..., 1, 1], R[..., 2, 2]
    diag = np.stack([r00 + r11 + r22, r00 - r11 - r22, r11 - r00 - r22, r22 - r00 - r11], axis=-1)
    k = np.argmax(diag, axis=-1)[..., None]
    s = 2.0 * np.sqrt(1.0 + np.take_along_axis(diag, k, axis=-1))[..., 0]  # 4 * the largest component, >= 2
    a, b = R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0]     # 4 w x, 4 w y
    c, d = R[..., 1, 0] - R[..., 0, 1], R[..., 0, 1] + R[..., 1, 0]     # 4 w z, 4 x y
    e, f = R[..., 0, 2] + R[..., 2, 0], R[..., 1, 2] + R[..., 2, 1]     # 4 x z, 4 y z
    q4 = np.stack([np.stack([s * s / 4, a, b, c], axis=-1),             # 4 * largest * (w, x, y, z)
                   np.stack([a, s * s / 4, d, e], axis=-1),
                   np.stack([b, d, s * s / 4, f], axis=-1),
                   np.stack([c, e, f, s * s / 4], axis=-1)], axis=-2)
    quat = np.take_along_axis(q4, k[..., None], axis=-2)[..., 0, :] / s[..., None]
    return np.where(quat[..., :1] < 0, -quat, quat)


def exp_twist(S: ArrayLike, q: ArrayLike) -> Array:
    """Matrix exponential exp([S] q) of unit screws S = (w, v) (..., 6) times q (...) -> (..., 4, 4).

    Revolute screws have |w| = 1, prismatic ones w = 0 and |v| = 1 (Modern Robotics, eq. 3.88).
    """
    S = np.asarray(S, dtype=float)
    q = np.asarray(q, dtype=float)
    w, v = S[..., :3], S[..., 3:]
    W = skew(w)
    W2 = W @ W
    s, c = np.sin(q)[..., None, None], np.cos(q)[..., None, None]
    qq = q[..., None, None]
    eye = np.eye(3)
    R = eye + s * W + (1 - c) * W2
    G = eye * qq + (1 - c) * W + (qq - s) * W2
    # for a prismatic screw W = 0, so R = I and G = q I: exp = translation by v q
    return homogeneous(R, np.einsum("...ij,...j->...i", G, v))


def adjoint(T: ArrayLike) -> Array:
    """Adjoint Ad_T (..., 6, 6) of T (..., 4, 4) acting on twists ordered (w, v)."""
    T = np.asarray(T, dtype=float)
    R, p = T[..., :3, :3], T[..., :3, 3]
    out = np.zeros(T.shape[:-2] + (6, 6))
    out[..., :3, :3] = R
    out[..., 3:, 3:] = R
    out[..., 3:, :3] = skew(p) @ R
    return out


#: Below this angle theta/sin(theta) is replaced by its series 1 + theta^2/6: the series error
#: (theta^4 * 7/360 ~ 2e-18 at 1e-4) is far below rounding, and the direct quotient loses digits there.
_SMALL_ANGLE = 1e-4
#: Beyond this cosine (angle within ~0.14 rad of pi) the axis is taken from the symmetric part of R,
#: because sin(theta) -> 0 makes the skew part lose relative accuracy (error ~ eps / sin(theta)).
_NEAR_PI_COS = -0.99


def log_rotation(R: ArrayLike) -> Array:
    """Rotation vectors (axis * angle, angle in [0, pi]) of rotations (..., 3, 3) -> (..., 3).

    Vectorised without scipy (which builds Rotation objects per call) because this sits inside the IK
    and synthesis loops. Accurate to ~1e-15 rad over the whole range, including angles near 0 and pi.
    """
    R = np.asarray(R, dtype=float)
    v = 0.5 * np.stack([R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0],
                        R[..., 1, 0] - R[..., 0, 1]], axis=-1)  # sin(theta) * axis
    s = np.linalg.norm(v, axis=-1)
    c = np.clip(0.5 * (R[..., 0, 0] + R[..., 1, 1] + R[..., 2, 2] - 1.0), -1.0, 1.0)
    theta = np.arctan2(s, c)
    small = theta < _SMALL_ANGLE
    # s = 0 beyond the small angles only at an exact half turn, which the near-pi branch below handles
    factor = np.where(small, 1.0 + theta * theta / 6.0, theta / np.where(small | (s == 0.0), 1.0, s))
    out = factor[..., None] * v
    near_pi = c < _NEAR_PI_COS
    if np.any(near_pi):
        Rn, cn, vn, tn = R[near_pi], c[near_pi], v[near_pi], theta[near_pi]
        # (R + R^T)/2 - cos(theta) I = (1 - cos(theta)) a a^T: take the column with the largest diagonal
        B = 0.5 * (Rn + np.swapaxes(Rn, -1, -2)) - cn[:, None, None] * np.eye(3)
        k = np.argmax(np.diagonal(B, axis1=-2, axis2=-1), axis=-1)
        col = B[np.arange(len(k)), :, k]
        axis = col / np.linalg.norm(col, axis=-1, keepdims=True)
        # the symmetric part fixes the axis up to sign; the skew part (sin(theta) a) fixes the sign
        sign = np.where(np.einsum("ij,ij->i", axis, vn) < 0, -1.0, 1.0)
        out[near_pi] = (sign * tn)[:, None] * axis
    return out


def nearest_rotation(M: ArrayLike) -> Array:
    """The rotation closest to M in the Frobenius norm (SVD projection), (..., 3, 3)."""
    M = np.asarray(M, dtype=float)
    U, _, Vt = np.linalg.svd(M)
    D = np.ones(M.shape[:-1])
    D[..., -1] = np.sign(np.linalg.det(U @ Vt))
    return (U * D[..., None, :]) @ Vt


def rotation_error(M: ArrayLike) -> Array:
    """Frobenius distance from M (..., 3, 3) to the nearest rotation; inf if det(M) <= 0."""
    M = np.asarray(M, dtype=float)
    err = np.linalg.norm(M - nearest_rotation(M), axis=(-2, -1))
    return np.where(np.linalg.det(M) > 0, err, np.inf)


def dh_matrix(a: ArrayLike, d: ArrayLike, alpha: ArrayLike, theta: ArrayLike) -> Array:
    """Standard DH link transform Rz(theta) Tz(d) Tx(a) Rx(alpha), broadcast -> (..., 4, 4)."""
    a, d, alpha, theta = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (a, d, alpha, theta)))
    ct, st, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha), np.sin(alpha)
    out = np.zeros(a.shape + (4, 4))
    out[..., 0, :] = np.stack([ct, -st * ca, st * sa, a * ct], -1)
    out[..., 1, :] = np.stack([st, ct * ca, -ct * sa, a * st], -1)
    out[..., 2, 1], out[..., 2, 2], out[..., 2, 3] = sa, ca, d
    out[..., 3, 3] = 1.0
    return out


def mdh_matrix(a: ArrayLike, d: ArrayLike, alpha: ArrayLike, theta: ArrayLike) -> Array:
    """Modified (Craig) DH link transform Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i) -> (..., 4, 4).

    ``a``, ``d`` (lengths), ``alpha``, ``theta`` (radians): arrays of one shape (...), or numbers.
    """
    a, d, alpha, theta = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (a, d, alpha, theta)))
    ct, st, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha), np.sin(alpha)
    out = np.zeros(a.shape + (4, 4))
    out[..., 0, :] = np.stack([ct, -st, np.zeros_like(ct), a], -1)
    out[..., 1, :] = np.stack([st * ca, ct * ca, -sa, -sa * d], -1)
    out[..., 2, :] = np.stack([st * sa, ct * sa, ca, ca * d], -1)
    out[..., 3, 3] = 1.0
    return out
