"""Geometric subproblems of closed-form IK, vectorised over any leading batch shape.

- ``rotation_about``: Rodrigues' formula for a rotation about a unit axis.
- ``angle_about``: the angle that turns p onto q about an axis (Paden-Kahan subproblem 1).
- ``two_axes``: two rotations about intersecting axes that carry p onto q (subproblem 2).
- ``cos_sin_equation``: the solutions of A cos x + B sin x = K.
- ``planar_two_link``: both elbow solutions of a planar two-link chain, points as complex numbers.

Unit-free tolerances here are on cosines (dimensionless); callers verify every assembled solution by
forward kinematics, so a slack here never turns into a wrong answer reported as right.
"""

from __future__ import annotations

import numpy as np

__all__ = ["cross", "rotation_about", "angle_about", "two_axes", "cos_sin_equation", "planar_two_link",
           "COS_SLACK", "DEGENERATE"]

#: A cosine beyond +-1 by less than this is rounding of a boundary case (a stretched arm, a tangent
#: solution) and is clamped; it moves the reached point by ~COS_SLACK * link length, well below the
#: 1e-9 the caller verifies. Beyond it the case has no real solution.
COS_SLACK = 1e-9
#: Norms below this (relative to 1: inputs are unit vectors, or lengths divided by the robot's size)
#: mean a direction is undefined (a point on the rotation axis): the angle is free and the caller's
#: preferred value is used. 1e-12 is ~1e4 ulps: rounding of exact coincidences stays below it.
DEGENERATE = 1e-12


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a x b over the last axis (broadcast): np.cross without its axis juggling (~5x faster on the
    small arrays of a single target)."""
    a1, a2, a3 = a[..., 0], a[..., 1], a[..., 2]
    b1, b2, b3 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a2 * b3 - a3 * b2, a3 * b1 - a1 * b3, a1 * b2 - a2 * b1], axis=-1)


def rotation_about(axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Rotation matrices (..., 3, 3) about unit axes (..., 3) (broadcast) by angles (...)."""
    axis = np.asarray(axis, dtype=float)
    angle = np.asarray(angle, dtype=float)
    shape = np.broadcast_shapes(axis.shape[:-1], angle.shape)
    x, y, z = (np.broadcast_to(axis[..., i], shape) for i in range(3))
    c, s = np.cos(angle), np.sin(angle)
    t = 1.0 - c
    R = np.empty(shape + (3, 3))
    R[..., 0, 0] = c + t * x * x
    R[..., 0, 1] = t * x * y - s * z
    R[..., 0, 2] = t * x * z + s * y
    R[..., 1, 0] = t * x * y + s * z
    R[..., 1, 1] = c + t * y * y
    R[..., 1, 2] = t * y * z - s * x
    R[..., 2, 0] = t * x * z - s * y
    R[..., 2, 1] = t * y * z + s * x
    R[..., 2, 2] = c + t * z * z
    return R


def angle_about(axis: np.ndarray, p: np.ndarray, q: np.ndarray, free: np.ndarray | float = 0.0
                ) -> np.ndarray:
    """Angle x with Rot(axis, x) p = q, where p and q have equal components along the axis.

    Where p (or q) lies on the axis every angle works and ``free`` is returned.
    """
    pp = p - axis * np.sum(axis * p, axis=-1, keepdims=True)
    qq = q - axis * np.sum(axis * q, axis=-1, keepdims=True)
    sin_part = np.sum(axis * cross(pp, qq), axis=-1)
    cos_part = np.sum(pp * qq, axis=-1)
    on_axis = np.linalg.norm(pp, axis=-1) * np.linalg.norm(qq, axis=-1) < DEGENERATE
    return np.where(on_axis, free, np.arctan2(sin_part, cos_part))


def two_axes(w1: np.ndarray, w2: np.ndarray, p: np.ndarray, q: np.ndarray,
             free1: np.ndarray | float = 0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Angles (x1, x2) with Rot(w1, x1) Rot(w2, x2) p = q, for unit vectors p, q: two branches.

    w1 and w2 are unit, non-parallel axes through the origin. Returns x1, x2 of shape (..., 2) and a
    validity mask (..., 2) (False where no rotation pair reaches q). Where the intermediate vector lies
    on w1 (a wrist singularity) x1 is free and ``free1`` is used.
    """
    b = np.sum(w1 * w2, axis=-1)[..., None]
    w12 = cross(w1, w2)
    denom = b * b - 1.0
    w2p = np.sum(w2 * p, axis=-1)[..., None]
    w1q = np.sum(w1 * q, axis=-1)[..., None]
    alpha = (b * w2p - w1q) / denom
    beta = (b * w1q - w2p) / denom
    pn2 = np.sum(p * p, axis=-1)[..., None]
    g2 = (pn2 - alpha * alpha - beta * beta - 2.0 * alpha * beta * b) / np.sum(w12 * w12, axis=-1)[..., None]
    valid = g2 >= -COS_SLACK
    gamma = np.sqrt(np.maximum(g2, 0.0)) * np.array([1.0, -1.0])          # (..., 2)
    c = (alpha[..., None] * w1[..., None, :] + beta[..., None] * w2[..., None, :]
         + gamma[..., None] * w12[..., None, :])                              # (..., 2, 3)
    x2 = angle_about(w2[..., None, :], p[..., None, :], c)
    x1 = angle_about(w1[..., None, :], c, q[..., None, :], np.asarray(free1)[..., None]
                     if np.ndim(free1) else free1)
    return x1, x2, np.broadcast_to(valid, x1.shape)


def cos_sin_equation(A: np.ndarray, B: np.ndarray, K: np.ndarray, free: np.ndarray | float = 0.0
                     ) -> tuple[np.ndarray, np.ndarray]:
    """Solutions x (..., 2) of A cos x + B sin x = K and their validity (..., 2).

    Where A = B = 0 (relative to |K| + 1e-300) the equation holds for every x if K = 0 (``free`` is
    returned, valid) and for none otherwise.
    """
    rho = np.hypot(A, B)
    degenerate = rho < DEGENERATE
    ratio = K / np.where(degenerate, 1.0, rho)
    base = np.arctan2(B, A)
    delta = np.arccos(np.clip(ratio, -1.0, 1.0))
    x = base[..., None] + delta[..., None] * np.array([1.0, -1.0])
    valid = np.abs(ratio) <= 1.0 + COS_SLACK
    x = np.where(degenerate[..., None], np.asarray(free)[..., None] if np.ndim(free) else free, x)
    valid = np.where(degenerate, np.abs(K) < DEGENERATE, valid)
    return x, np.broadcast_to(valid[..., None], x.shape)


def planar_two_link(a: complex, b: complex, d: np.ndarray, free1: np.ndarray | float = 0.0
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Both elbow solutions of a planar two-link chain, all points as complex numbers.

    The chain turns by x1 about the first axis and x2 about the second: the point that sits at
    (first axis + a + b) when x1 = x2 = 0 goes to first axis + e^{i x1} (a + e^{i x2} b). Given the
    wanted offsets d (...) from the first axis, returns x1, x2 (..., 2) (the two elbows), a validity
    mask (..., 2) and the cosine D (...) of the elbow equation (|D| > 1: out of reach).

    ``a`` and ``b`` must be non-zero. Where d = 0 (only possible if |a| = |b|) x1 is free: ``free1``.
    """
    la, lb = abs(a), abs(b)
    dd = np.abs(d)
    D = (dd * dd - la * la - lb * lb) / (2.0 * la * lb)
    beta = np.angle(b) - np.angle(a)
    delta = np.arccos(np.clip(D, -1.0, 1.0))
    x2 = -beta + delta[..., None] * np.array([1.0, -1.0])
    reach = a + np.exp(1j * x2) * b                                   # (..., 2): elbow vector sum
    free = np.asarray(free1)[..., None] if np.ndim(free1) else free1
    scale = la + lb
    at_axis = (dd < DEGENERATE * scale)[..., None] | (np.abs(reach) < DEGENERATE * scale)
    x1 = np.where(at_axis, free, np.angle(d[..., None]) - np.angle(reach))
    valid = np.broadcast_to((np.abs(D) <= 1.0 + COS_SLACK)[..., None], x1.shape)
    return x1, x2, valid, D
