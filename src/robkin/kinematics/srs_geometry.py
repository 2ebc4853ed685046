"""The geometry of SRS arms: 7R with a spherical shoulder (axes 1-3 meet) and a spherical wrist (axes 5-7 meet).

An SRS arm (KUKA LBR iiwa, an ideal Kinova Gen3, DLR/LWR-type arms) is redundant by one degree of freedom:
with the tool pose fixed, the shoulder point S (where axes 1-3 meet, fixed in the base) and the wrist
centre W (where axes 5-7 meet, fixed in the tool) are fixed, the elbow angle q4 is fixed by the distance
|W - S|, and the elbow can still swivel about the line S-W. The **arm angle** psi is that swivel:

- the elbow point E is the point of joint 4's axis nearest to S (fixed in link 3);
- psi is the angle, right-handed about the direction S -> W, from the **reference plane** to the plane
  through S, W and E; the reference plane holds the line S-W and joint 1's axis (the base z axis of iiwa
  and Gen3), psi = 0 on the side joint 1's axis points to (elbow "up" for an upright arm);
- where S -> W is parallel to joint 1's axis the reference plane is the one holding joint 2's axis
  at q = 0 instead (psi is not continuous through that pose: no choice is).

Branches: the shoulder, elbow and wrist each come in two mirror forms, labelled +1/-1 by ``branch_of``
(the sign of the middle joint's excursion from its aligned pose: for iiwa and Gen3 the signs of q2, q4, q6).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import InputError
from ..lines import closest_points
from ..robot import Robot, check_q

__all__ = ["SRSGeometry", "srs_geometry", "srs_condition", "arm_angle_of", "branch_of", "rot"]

#: Axes meet when their distances to the common point are below this times the robot size, and are
#: not parallel when the sine of their angle is above it: the same 1e-9 as the other closed forms'
#: detection (``kernel_solver.DETECT_LENGTH_TOL``): far above rounding, far below a real offset.
_TOL = 1e-9


@dataclass(frozen=True)
class SRSGeometry:
    """What the SRS solver needs, all in the base frame at q = 0.

    Attributes
    ----------
    axes : (7, 3) unit joint axes; points : (7, 3) a point on each axis.
    S : (3,) shoulder point; W0 : (3,) wrist centre at q = 0; E0 : (3,) elbow point at q = 0;
    p4 : (3,) a point on joint 4's axis.
    w_tool : (3,) the wrist centre in tool coordinates (constant).
    R_home : (3, 3) tool orientation at q = 0.
    z_ref, z_alt : (3,) the reference direction of psi = 0 (joint 1's axis) and its stand-in.
    elbow_A, elbow_B, elbow_C0 : the elbow equation A cos q4 + B sin q4 = C0 - |W - S|^2 / 2.
    """

    axes: np.ndarray
    points: np.ndarray
    S: np.ndarray
    W0: np.ndarray
    E0: np.ndarray
    p4: np.ndarray
    w_tool: np.ndarray
    R_home: np.ndarray
    z_ref: np.ndarray
    z_alt: np.ndarray
    elbow_A: float
    elbow_B: float
    elbow_C0: float


def _meeting_point(robot: Robot, k: int, where: str) -> tuple[np.ndarray | None, str]:
    """Where axes k, k+1, k+2 meet, or None and the condition that fails."""
    a, p = robot.axes, robot.points
    size = robot.scale
    for i in (k, k + 1):
        if np.linalg.norm(np.cross(a[i], a[i + 1])) < _TOL:
            return None, f"the {where} axes {i + 1} and {i + 2} are parallel"
    cn = closest_points(p[k], a[k], p[k + 1], a[k + 1])
    x = 0.5 * (cn.c1 + cn.c2)
    d = x - p[k:k + 3]
    off = d - np.sum(d * a[k:k + 3], axis=1)[:, None] * a[k:k + 3]
    miss = np.sqrt(np.sum(off * off, axis=1))
    if miss.max() > _TOL * size:
        j = int(np.argmax(miss))
        return None, (f"the {where} axes {k + 1}-{k + 3} do not meet in one point (axis {k + j + 1} passes "
                      f"{miss[j]:.3g} from the others' meeting point)")
    return x, ""


def srs_condition(robot: Robot) -> tuple[SRSGeometry | None, str]:
    """The robot's SRS geometry, or None and the first condition that fails (a phrase)."""
    if robot.n != 7 or not bool(np.all(robot.revolute)):
        return None, f"it needs 7 revolute joints, this arm has {robot.n} joints ({', '.join(robot.types)})"
    S, why = _meeting_point(robot, 0, "shoulder")
    if S is None:
        return None, why
    W0, why = _meeting_point(robot, 4, "wrist")
    if W0 is None:
        return None, why
    a, p = robot.axes, robot.points
    size = robot.scale
    w4, p4 = a[3], p[3]
    # the elbow equation |Rot(w4, q4)(W0 - p4) + p4 - S|^2 = d^2 is A cos q4 + B sin q4 = C0 - d^2 / 2
    va, b = W0 - p4, S - p4
    va_perp = va - (va @ w4) * w4
    A, B = float(b @ va_perp), float(b @ np.cross(w4, va_perp))
    if math.hypot(A, B) < _TOL * size * size:
        return None, "the shoulder-wrist distance does not change with joint 4 (S or W lies on its axis)"
    C0 = float((va @ va + b @ b) / 2 - b @ ((va @ w4) * w4))
    E0 = p4 + ((S - p4) @ w4) * w4
    if np.linalg.norm(E0 - S) < _TOL * size:
        return None, "joint 4's axis passes through the shoulder point (no elbow to swivel)"
    tool = robot.tool
    w_tool = tool[:3, :3].T @ (W0 - tool[:3, 3])
    z_ref = a[0] / np.linalg.norm(a[0])
    z_alt = a[1] / np.linalg.norm(a[1])
    geo = SRSGeometry(axes=a.copy(), points=p.copy(), S=S, W0=W0, E0=E0, p4=p4.copy(), w_tool=w_tool, R_home=tool[:3, :3].copy(),
                      z_ref=z_ref, z_alt=z_alt, elbow_A=A, elbow_B=B, elbow_C0=C0)
    return geo, ""


_CACHE: dict[int, tuple[Any, SRSGeometry | None, str]] = {}


def srs_geometry(robot: Robot) -> SRSGeometry:
    """The SRS geometry of the robot (cached per robot); InputError naming the condition that fails."""
    import weakref

    hit = _CACHE.get(id(robot))
    if hit is None or hit[0]() is not robot:
        geo, why = srs_condition(robot)
        key = id(robot)

        def forget(_ref: Any, key: int = key) -> None:
            _CACHE.pop(key, None)

        _CACHE[key] = hit = (weakref.ref(robot, forget), geo, why)
    if hit[1] is None:
        raise InputError(f"arm_angle: {robot.name or 'this robot'} is not an SRS arm (7R, axes 1-3 meeting in a "
                         f"shoulder point and axes 5-7 in a wrist centre): {hit[2]}")
    return hit[1]


def rot(w: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Rotations (..., 3, 3) by angles q (...) about the unit axis w (3,) (Rodrigues)."""
    q = np.asarray(q, dtype=float)
    K = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    c, s = np.cos(q)[..., None, None], np.sin(q)[..., None, None]
    return np.eye(3) + s * K + (1 - c) * (K @ K)


def reference_frame(geo: SRSGeometry, w: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Unit S -> W direction (N, 3) and the in-plane directions n1 (psi = 0) and n2 (psi = pi/2)."""
    d = np.linalg.norm(w, axis=-1, keepdims=True)
    wh = w / np.where(d > 0, d, 1.0)
    n1 = geo.z_ref - (wh @ geo.z_ref)[..., None] * wh
    m = np.linalg.norm(n1, axis=-1, keepdims=True)
    # within 1e-9 of parallel the reference direction's remainder is rounding: take the stand-in axis
    alt = geo.z_alt - (wh @ geo.z_alt)[..., None] * wh
    n1 = np.where(m > 1e-9, n1, alt)
    n1 /= np.linalg.norm(n1, axis=-1, keepdims=True)
    return wh, n1, np.cross(wh, n1)


def _points_at(robot: Robot, geo: SRSGeometry, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Elbow and wrist points (N, 3) at configurations Q (N, 7)."""
    F = robot.frames_at(Q)                       # (N, 8, 4, 4), frame i after joint i's motion
    H = np.array(robot.frames)
    E = np.einsum("nij,j->ni", F[:, 2, :3, :3] @ H[2, :3, :3].T, geo.E0 - H[2, :3, 3]) + F[:, 2, :3, 3]
    W = np.einsum("nij,j->ni", F[:, 3, :3, :3] @ H[3, :3, :3].T, geo.W0 - H[3, :3, 3]) + F[:, 3, :3, 3]
    return E, W


def arm_angle_of(robot: Robot, q: Any) -> float | np.ndarray:
    """The arm angle psi (radians, in (-pi, pi]) of configurations q (7,) or (N, 7) of an SRS arm.

    NaN where the elbow lies on the shoulder-wrist line (a stretched arm: no plane, psi undefined).
    """
    geo = srs_geometry(robot)
    Q = check_q(q, robot.n)
    single = Q.ndim == 1
    Q = np.ascontiguousarray(Q.reshape(-1, robot.n))
    E, W = _points_at(robot, geo, Q)
    wh, n1, n2 = reference_frame(geo, W - geo.S)
    u = E - geo.S
    u_perp = u - np.sum(u * wh, axis=1)[:, None] * wh
    # the elbow's distance from the line, against the robot's size: below 1e-9 it is rounding
    flat = np.linalg.norm(u_perp, axis=1) < 1e-9 * robot.scale
    psi = np.where(flat, np.nan, np.arctan2(np.sum(u_perp * n2, axis=1), np.sum(u_perp * n1, axis=1)))
    return float(psi[0]) if single else psi


def branch_of(robot: Robot, q: Any) -> np.ndarray:
    """Branch labels (3,) or (N, 3) of configurations q: shoulder, elbow, wrist, each +1 or -1 (0 on the
    singular pose between the two: shoulder or wrist axes aligned, elbow stretched or folded).

    Shoulder: the sign of (axis 2 x axis 1) . (axis 3 after joint 2's motion), which is sin q2 for iiwa and
    Gen3; wrist likewise with axes 5-7 (sin q6); elbow: the sign of sin(q4 - q4s), q4s joint 4's value
    at full stretch (sin q4 for iiwa and Gen3).
    """
    geo = srs_geometry(robot)
    Q = check_q(q, robot.n)
    single = Q.ndim == 1
    Q = Q.reshape(-1, robot.n)
    a = geo.axes
    out = np.empty((len(Q), 3))
    for col, (i, j) in enumerate(((0, 1), (4, 5))):
        c = rot(a[j], Q[:, j]) @ a[j + 1]                # axis j+2 turned by joint j+1
        g = c @ np.cross(a[j], a[i])
        out[:, 2 * col] = np.where(np.abs(g) < 1e-12, 0.0, np.sign(g))  # 1e-12: rounding of unit vectors
    s = -np.sin(Q[:, 3] - math.atan2(geo.elbow_B, geo.elbow_A))   # folded at atan2(B, A)
    out[:, 1] = np.where(np.abs(s) < 1e-12, 0.0, np.sign(s))
    return out[0] if single else out
