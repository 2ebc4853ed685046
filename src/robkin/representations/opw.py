"""The OPW parameters of an industrial arm: the seven lengths, offsets and signs of an arm of that class
(written by ``robkin convert --to opw``, ``io.toolboxes.opw``).

Brandstoetter, Angerer and Hofbaur (2014) describe a 6R arm with an ortho-parallel basis and a spherical
wrist by seven lengths. In its own base frame, with the arm "up" at zero: joint 1 turns about z through
the origin; joint 2's axis is parallel to y at x = a1, z = c1; joint 3's axis is parallel to joint 2's,
c2 above it; the wrist centre is a2 along x and c3 along z from joint 3 and b along y from joint 1's
axis; joints 4 and 6 turn about z and joint 5 about y through the wrist centre, and the flange is c4
along joint 6's axis from it. Position C = (c2 sin q2 + c3 sin q23 + a2 cos q23 + a1, b, c2 cos q2 +
c3 cos q23 - a2 sin q23) turned by q1 about z, plus c1 along z; orientation Rz(q1) Ry(q23) Rz(q4)
Ry(q5) Rz(q6), and the flange at C + c4 times that orientation's z axis.

A real arm differs from that model only by each joint's zero (``offsets``) and direction
(``sign_corrections``), with opw_kinematics' convention q_model = sign * q - offset, and by where its
base and tool frames are: ``base`` (robot base -> model base) and ``tool`` (model flange -> robot
tool), identities for the usual URDF of such an arm. So robot FK(q) = base @ opw_fk(sign * q - offset)
@ tool. Arms outside the class are refused with the condition they fail.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .. import se3
from ..errors import InputError, quote

if TYPE_CHECKING:  # pragma: no cover
    from ..robot import Robot

__all__ = ["OPWParameters", "opw_from_robot", "opw_fk", "GEOMETRY"]

GEOMETRY = ("a1", "a2", "b", "c1", "c2", "c3", "c4")
#: How far from perpendicular / parallel (sine or cosine of the angle) and from meeting (times the robot's
#: size) axes may be and still count as the OPW class: URDFs write right angles as 1.5708 or 1.570796
#: (errors 3.7e-6, 3.3e-7), so a looser bound would take arms the model cannot reproduce; the FK error
#: that remains is measured and reported (``_check_fk``).
CLASS_TOL = 1e-6
#: Values within this of 0 or a multiple of pi/2 (lengths: times the robot's size) are written exactly;
#: 1e-12 is ~1e4 roundings of a chain of six frames, far below any real offset.
SNAP = 1e-12
#: The model's FK must reproduce the robot's to this (relative to the robot's size), as DH tables do
#: (``link_table.WARN_TOL``), or a ConditioningWarning states the error measured.
WARN_TOL = 1e-10


@dataclass(frozen=True)
class OPWParameters:
    """Seven OPW lengths (m), joint offsets (6,) rad, sign corrections (6,) of +-1, and the base and tool
    transforms (4, 4) that place the model on the robot: FK(q) = base opw_fk(sign q - offset) tool."""

    a1: float
    a2: float
    b: float
    c1: float
    c2: float
    c3: float
    c4: float
    offsets: tuple[float, ...]
    sign_corrections: tuple[int, ...]
    base: np.ndarray
    tool: np.ndarray

    def fk(self, q: np.ndarray) -> np.ndarray:
        """The robot's tool pose (4, 4) from the OPW model at robot joint values q (6,)."""
        qm = np.asarray(self.sign_corrections) * np.asarray(q, dtype=float) - np.asarray(self.offsets)
        return self.base @ opw_fk(self, qm) @ self.tool


def opw_fk(p: OPWParameters, q: np.ndarray) -> np.ndarray:
    """The OPW model's flange pose (4, 4) in its base frame at model joint values q (6,) (no offsets,
    signs, base or tool)."""
    q1, q2, q3, q4, q5, q6 = (float(v) for v in q)
    q23 = q2 + q3
    R = (se3.rot_z(q1) @ se3.rot_y(q23) @ se3.rot_z(q4) @ se3.rot_y(q5) @ se3.rot_z(q6))[:3, :3]
    cx = p.c2 * math.sin(q2) + p.c3 * math.sin(q23) + p.a2 * math.cos(q23) + p.a1
    cz = p.c2 * math.cos(q2) + p.c3 * math.cos(q23) - p.a2 * math.sin(q23) + p.c1
    C = se3.rot_z(q1)[:3, :3] @ np.array([cx, p.b, 0.0]) + np.array([0.0, 0.0, cz])
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = C + p.c4 * R[:, 2]
    return T


def _refuse(why: str) -> InputError:
    return InputError(f"--to opw: {why}; the OPW model takes 6R arms with joint 1 perpendicular to joint 2, "
                      f"joints 2 and 3 parallel, joint 4 perpendicular to both, and a spherical wrist (axes 4, "
                      f"5, 6 meet in one point, 5 perpendicular to 4 and 6)")


def _closest(p1: np.ndarray, z1: np.ndarray, p2: np.ndarray, z2: np.ndarray) -> tuple[np.ndarray, float]:
    """Midpoint of the closest points of two non-parallel lines, and their distance."""
    w = p1 - p2
    b = z1 @ z2
    d, e = z1 @ w, z2 @ w
    den = 1.0 - b * b
    t1, t2 = (b * e - d) / den, (e - b * d) / den
    a, c = p1 + t1 * z1, p2 + t2 * z2
    return (a + c) / 2, float(np.linalg.norm(a - c))


def _check_class(robot: "Robot") -> np.ndarray:
    """The wrist centre (3,) in the robot base frame, after checking the arm is of the OPW class."""
    if robot.n != 6:
        raise _refuse(f"the robot has {robot.n} joints")
    prismatic = [j.name for j in robot.joints if not j.revolute]
    if prismatic:
        raise _refuse(f"joint {quote(prismatic[0])} is prismatic")
    z, p = robot.axes, robot.points
    for i, j, want in ((0, 1, "perpendicular"), (1, 2, "parallel"), (2, 3, "perpendicular"),
                       (3, 4, "perpendicular"), (4, 5, "perpendicular")):
        c = abs(float(z[i] @ z[j]))
        off = c if want == "perpendicular" else float(np.linalg.norm(np.cross(z[i], z[j])))
        if off > CLASS_TOL:
            angle = math.degrees(math.acos(min(c, 1.0)))
            raise _refuse(f"joints {i + 1} and {j + 1} are not {want} (their axes are {angle:.6g} deg apart, "
                          f"not {90 if want == 'perpendicular' else 0})")
    gap23 = np.cross(p[2] - p[1], z[1])
    if np.linalg.norm(gap23) <= CLASS_TOL * robot.scale:
        raise _refuse("joints 2 and 3 are the same axis")
    W, d45 = _closest(p[3], z[3], p[4], z[4])
    d6 = float(np.linalg.norm(np.cross(W - p[5], z[5])))
    if max(d45, d6) > CLASS_TOL * robot.scale:
        raise _refuse(f"joints 4, 5 and 6 do not meet in one point (no spherical wrist: axis "
                      f"{4 if d45 >= d6 else 6} passes {max(d45, d6):.3g} m from the "
                      f"{'axis of joint 5' if d45 >= d6 else 'point where axes 4 and 5 meet'})")
    return W


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def _model_base(robot: "Robot") -> np.ndarray:
    """The model's base frame (4, 4) in the robot base frame: z along joint 1's axis (the robot base's
    z when parallel to it), origin on that axis at the foot of the robot base origin, x from the robot
    base's x (y where x is along the axis); the identity for the usual industrial-arm URDF."""
    z1, p1 = robot.axes[0], robot.points[0]
    ez = np.array([0.0, 0.0, 1.0])
    # the base z when joint 1's axis is along it (sine of the angle within SNAP; either way: its sign)
    z = ez if math.hypot(z1[0], z1[1]) <= SNAP else z1
    origin = p1 - (p1 @ z1) * z1
    origin[np.abs(origin) <= SNAP * robot.scale] = 0.0
    ref = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = _unit(ref - (ref @ z) * z)
    B = np.eye(4)
    B[:3, :3] = np.column_stack([x, np.cross(z, x), z])
    B[:3, 3] = origin
    return B


def _angle(x: float) -> float:
    """x wrapped to (-pi, pi], snapped to an exact multiple of pi/2 within SNAP."""
    x = math.remainder(x, 2 * math.pi)
    k = round(x / (math.pi / 2))
    x = k * (math.pi / 2) if abs(x - k * math.pi / 2) <= SNAP else x
    return math.pi if x <= -math.pi else x + 0.0


def opw_from_robot(robot: "Robot") -> OPWParameters:
    """The OPW parameters of an arm of that class, placed so that they reproduce its FK exactly.

    Joint directions are chosen to make the model's zero the robot's as nearly as possible (offsets of
    joints 1 and 4 at most pi/2 in size, c3 and c4 not negative); ``base`` and ``tool`` are the identity
    whenever the robot's base z is joint 1's axis and its tool z is joint 6's axis through the flange.

    Raises
    ------
    InputError
        One line naming the condition of the OPW class the robot fails.
    """
    W = _check_class(robot)
    B = _model_base(robot)
    Binv = se3.inv(B)
    z = robot.axes @ Binv[:3, :3].T                     # axes and points in the model base frame
    p = robot.points @ Binv[:3, :3].T + Binv[:3, 3]
    w = Binv[:3, :3] @ W + Binv[:3, 3]
    tool = Binv @ robot.tool
    # joint 1: +z of the model base; joint 2 (and 3) along +-z2, the sign that keeps |theta1| <= pi/2
    u2 = z[1] if z[1][1] >= 0 else -z[1]
    th1 = math.atan2(-u2[0], u2[1])
    P = se3.rot_z(th1)[:3, :3]                           # the arm plane's frame: y along joint 2
    pp, zp, wp = p @ P, z @ P, P.T @ w
    tp, to = P.T @ tool[:3, :3], P.T @ tool[:3, 3]
    a1, c1 = pp[1][0], pp[1][2]
    d23 = pp[2] - pp[1]
    c2 = math.hypot(d23[0], d23[2])
    th2 = math.atan2(d23[0], d23[2])
    r3w = wp - pp[2]
    u4 = zp[3] if r3w @ zp[3] >= 0 else -zp[3]          # c3 >= 0: the wrist centre ahead along joint 4
    th23 = math.atan2(u4[0], u4[2])
    Rc = se3.rot_y(th23)[:3, :3]
    a2, c3 = float(r3w @ Rc[:, 0]), float(r3w @ Rc[:, 2])
    b = float(wp[1])
    v = Rc.T @ zp[4]
    u5 = v if v[1] >= 0 else -v                           # |theta4| <= pi/2
    th4 = math.atan2(-u5[0], u5[1])
    R4 = Rc @ se3.rot_z(th4)[:3, :3]
    foot = wp + ((to - wp) @ zp[5]) * zp[5]              # the flange: the tool origin's foot on axis 6
    u6 = zp[5] if (foot - wp) @ zp[5] >= 0 else -zp[5]    # c4 >= 0
    c4 = float((foot - wp) @ u6)
    w6 = R4.T @ u6
    th5 = math.atan2(w6[0], w6[2])
    R5 = R4 @ se3.rot_y(th5)[:3, :3]
    xt = R5.T @ tp[:, 0]
    th6 = math.atan2(xt[1], xt[0]) if abs((R5.T @ tp[:, 2])[2] - 1.0) <= CLASS_TOL else 0.0
    ey, ez = np.array([0.0, 1.0, 0.0]), np.array([0.0, 0.0, 1.0])
    # the model's joint axes at its configuration theta, in the model base frame
    dirs = [ez, P @ ey, P @ ey, P @ u4, P @ R4 @ ey, P @ R5 @ ez]
    signs = tuple(1 if float(dirs[i] @ z[i]) > 0 else -1 for i in range(6))
    theta = (th1, th2, th23 - th2, th4, th5, th6)
    size = robot.scale
    lengths = dict(zip(GEOMETRY, (0.0 if abs(x) <= SNAP * size else float(x)
                                  for x in (a1, a2, b, c1, c2, c3, c4))))
    params = OPWParameters(**lengths, offsets=tuple(_angle(-t) for t in theta), sign_corrections=signs,
                           base=B, tool=np.eye(4))
    end = B @ opw_fk(params, np.array([-o for o in params.offsets]))
    E = se3.inv(end) @ robot.tool
    near = np.abs(E - np.eye(4)) <= SNAP * np.array([[1, 1, 1, size]] * 3 + [[1, 1, 1, 1]])
    E[near] = np.eye(4)[near]                             # rounding noise of an identity tool
    params = OPWParameters(**lengths, offsets=params.offsets, sign_corrections=signs, base=B, tool=E)
    _check_fk(params, robot)
    return params


def _check_fk(params: OPWParameters, robot: "Robot") -> None:
    """A ConditioningWarning with the FK error measured when the model reproduces the robot's FK only
    to more than WARN_TOL (axes within CLASS_TOL of, but not exactly, the OPW geometry)."""
    from .link_table import check_configurations

    Q = check_configurations(robot)
    ours = np.array([params.fk(q) for q in Q])
    theirs = robot.fk(Q)
    err = float(np.max(np.linalg.norm(ours[:, :3, 3] - theirs[:, :3, 3], axis=-1)
                       + np.abs(ours[:, :3, :3] - theirs[:, :3, :3]).max(axis=(1, 2)) * robot.scale))
    if err > WARN_TOL * robot.scale:
        from ..errors import ConditioningWarning

        warnings.warn(f"opw: the OPW model reproduces the robot's FK only to {err:.2g} (robot size "
                      f"{robot.scale:.3g}), because its axes are only nearly of the OPW geometry",
                      ConditioningWarning, stacklevel=3)
