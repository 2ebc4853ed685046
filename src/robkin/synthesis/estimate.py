"""Initial kinematic structures that reach a target: the four estimators (types A-D) of the
estimation paper (Huczala et al., Appl. Sci. 2021), for any number of joints n >= 3.

Inputs are a base frame and a target TCP pose (both (4, 4), in the same world frame) and n. All four
place n revolute joints and return a standard DH table; unlike the paper, which left the joint offsets
theta_i to a later inverse kinematics, the tables here carry the theta offsets with which q = 0 reaches
the target: its position (types A and B) or its full pose (types C and D).

- A (nearest distance): joint 1 on the base z axis; d_1 climbs to the target height, then n equal links
  a_i cover the horizontal distance; alpha_i alternates +-pi/4 (0 for the last joint when n is odd) so
  that the alphas sum to zero. theta_1 turns the arm towards the target.
- B (Bezier): joints at n equal parameter steps of the cubic Bezier curve from the base to the target
  (``bezier.py``); each joint frame is turned about its z axis towards the next joint and about its new
  x axis so that the next-but-one joint lies in its xz plane, which is what DH needs. The last joint
  sits on the target origin; the tool row turns its z axis onto the target's z axis (theta_n, alpha_n),
  and, when that axis is already parallel to the target's z, its x onto the target's x (full pose).
- C (common perpendicular): the joints divide the common perpendicular of the base and target z axes
  into n - 1 equal links and the angle between the axes into n - 1 equal twists; the last row slides
  along the target z axis to the target origin and turns x onto the target's x axis.
- D (Bezier + common perpendicular): joints 1..n-1 as in B (on a curve sampled at n points), and
  joint n on the common perpendicular of joint n-1's axis and the target z axis, with its z axis along
  the target's, so the full pose is reached.

Degenerate inputs (all documented in ``Estimate.notes`` when they occur, never NaN):

- target position at the base origin: InputError (no structure has anything to reach).
- parallel (or anti-parallel) base and target z axes (C, and D's last step): the common perpendicular is
  not unique; the one through the base origin (C) or through joint n-1's origin (D) is used.
- axes that meet (zero-length perpendicular): its direction is taken as z_1 x z_2, or, when the axes
  also coincide, the previous x axis (a = 0, alpha = 0 or pi).
- target on the base z axis (A): a_i = 0 and the joints stack on the base axis (theta_1 = 0); for B and
  D a point that lies on the current z (or x) axis gives theta (or alpha) = 0 instead of an undefined
  angle.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Iterable

import numpy as np
from numpy.typing import ArrayLike

from .. import se3
from ..errors import InputError
from ..lines import ANGLE_TOL, LENGTH_TOL, common_normal
from ..representations.dh import DHTable
from ..representations.frames import dh_params_between
from ..robot import Robot, check_pose, default_joints
from .bezier import curve_points
from .metrics import Metrics, structure_metrics

__all__ = ["KINDS", "REACHES", "MIN_JOINTS", "Estimate", "estimate", "estimate_all", "reach_error"]

KINDS: tuple[str, ...] = ("A", "B", "C", "D")
#: What q = 0 of each estimate reaches exactly.
REACHES = {"A": "position", "B": "position", "C": "pose", "D": "pose"}
MIN_JOINTS = 3
#: Type A's alternating twist (the paper's choice, rad).
TYPE_A_TWIST = math.pi / 4
#: The target must be farther than this (relative to the coordinates' magnitude) from the base origin;
#: closer than that the base-target direction is rounding noise of the frame transforms (~1e-16 relative).
COINCIDENT_TOL = 1e-9


@dataclass(frozen=True, eq=False)
class Estimate:
    """One estimated structure.

    Attributes
    ----------
    kind : {'A', 'B', 'C', 'D'}
    table : DHTable
        Rows (n, 4) [a, d, alpha, theta] in the robot base frame (DH base and tool are the identity).
    robot : Robot
        The same structure as a robot; ``robot.world`` is the given base frame.
    target : (4, 4) array
        The target pose in the robot base frame (base^-1 pose).
    metrics : Metrics
        Length (eq. 48) and Yoshikawa manipulability at q = 0.
    notes : tuple of str
        Fallbacks taken for degenerate input (empty for a general pose).
    """

    kind: str
    table: DHTable
    robot: Robot
    target: np.ndarray
    metrics: Metrics
    notes: tuple[str, ...] = field(default=())

    @property
    def n(self) -> int:
        return self.table.n

    @property
    def reaches(self) -> str:
        """'position' (types A, B) or 'pose' (types C, D)."""
        return REACHES[self.kind]

    @property
    def rows(self) -> np.ndarray:
        return self.table.rows

    def reach_error(self) -> tuple[float, float]:
        """(position error, rotation error in rad) of the tool at q = 0 against the target."""
        return reach_error(self.robot.fk(np.zeros(self.n)), self.target)


def reach_error(T: np.ndarray, target: np.ndarray) -> tuple[float, float]:
    """Distance between the origins and angle between the orientations of two poses (4, 4)."""
    dp = float(np.linalg.norm(T[:3, 3] - target[:3, 3]))
    Rrel = target[:3, :3].T @ T[:3, :3]
    c = np.clip((np.trace(Rrel) - 1.0) / 2.0, -1.0, 1.0)
    s = np.linalg.norm([Rrel[2, 1] - Rrel[1, 2], Rrel[0, 2] - Rrel[2, 0], Rrel[1, 0] - Rrel[0, 1]]) / 2.0
    return dp, float(math.atan2(s, c))


# ----------------------------------------------------------------------------------------- public
def estimate(pose: ArrayLike, n: int, kind: str = "D", base: ArrayLike | None = None) -> Estimate:
    """Estimate a structure of ``n`` revolute joints whose q = 0 reaches ``pose``.

    Parameters
    ----------
    pose : (4, 4) array
        Target TCP pose in the world frame (lengths in any unit, used consistently).
    n : int
        Number of joints, >= 3.
    kind : {'A', 'B', 'C', 'D'}
        Estimator (module docstring). A and B reach the position, C and D the full pose.
    base : (4, 4) array, optional
        Robot base frame in the world frame (identity if omitted).

    Returns
    -------
    Estimate
    """
    kind = _check_kind(kind)
    n = _check_n(n)
    B = np.eye(4) if base is None else check_pose(base, "base")
    T = check_pose(pose, "pose")
    target = se3.inv(B) @ T
    dist = float(np.linalg.norm(target[:3, 3]))
    mag = max(float(np.linalg.norm(B[:3, 3])), float(np.linalg.norm(T[:3, 3])))
    if dist == 0.0 or dist <= COINCIDENT_TOL * mag:
        raise InputError(f"pose: the target origin coincides with the base origin (distance {dist:.3g}); "
                         "give a target away from the base")
    notes: list[str] = []
    builder = {"A": _type_a, "B": _type_b, "C": _type_c, "D": _type_d}[kind]
    rows = builder(target, n, dist, notes)
    joints = default_joints(["revolute"] * n)
    table = DHTable(rows, joints)
    robot = table.to_robot(name=f"estimate-{kind}").replace(world=B)
    return Estimate(kind, table, robot, target, structure_metrics(robot, rows), tuple(notes))


def estimate_all(pose: ArrayLike, n: int, base: ArrayLike | None = None,
                 kinds: Iterable[str] = KINDS) -> dict[str, Estimate]:
    """All (or the given) estimate types for one target, keyed by type letter.

    ``pose``, ``n``, ``base``: as for ``estimate`` (the target pose (4, 4) in the world frame, the number of
    joints, the base pose, default identity); ``kinds``: the types among 'A', 'B', 'C', 'D'.
    """
    return {k: estimate(pose, n, k, base) for k in (_check_kind(k) for k in kinds)}


def _check_kind(kind: str) -> str:
    k = str(kind).upper()
    if k not in KINDS:
        raise InputError(f"type: '{kind}' is not one of {', '.join(KINDS)}")
    return k


def _check_n(n: object) -> int:
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < MIN_JOINTS:
        raise InputError(f"joints: need an integer number of joints >= {MIN_JOINTS}, got {n!r}")
    return int(n)


# ------------------------------------------------------------------------------------- geometry
def _angle_about(axis: np.ndarray, v_from: np.ndarray, v_to: np.ndarray) -> float:
    """Signed angle (rad) turning v_from onto v_to about ``axis`` (both perpendicular to it)."""
    return math.atan2(float(np.dot(np.cross(v_from, v_to), axis)), float(np.dot(v_from, v_to)))


def _perpendicular(P: np.ndarray, Q: np.ndarray, z1: np.ndarray, z2: np.ndarray, x_prev: np.ndarray,
                   tol: float, notes: list[str], what: str) -> np.ndarray:
    """Unit direction of the common perpendicular from P (on axis z1) to Q (on axis z2).

    Zero-length perpendicular: z1 x z2 when the axes meet at an angle, else x_prev (coincident axes).
    """
    PQ = Q - P
    length = float(np.linalg.norm(PQ))
    if length > tol:
        return PQ / length
    c = np.cross(z1, z2)
    if np.linalg.norm(c) >= ANGLE_TOL:
        notes.append(f"{what}: the axes meet; the common perpendicular has zero length and points along "
                     "z1 x z2")
        u = c / np.linalg.norm(c)
        return u if np.dot(u, x_prev) >= 0 else -u
    notes.append(f"{what}: the axes coincide; the previous x axis is kept (a = 0)")
    return x_prev


def _normal(P: np.ndarray, zp: np.ndarray, Q: np.ndarray, zq: np.ndarray, notes: list[str], what: str):
    """Common normal feet of the lines (P, zp) and (Q, zq); notes the parallel fallback."""
    if np.linalg.norm(np.cross(zp, zq)) < ANGLE_TOL:
        notes.append(f"{what}: the axes are parallel, so the common perpendicular is not unique; the one "
                     "through the first axis' frame origin is used")
    return common_normal(P, zp, Q, zq)


def _aim_on_curve(prev: np.ndarray, point: np.ndarray, next_point: np.ndarray, tol: float) -> np.ndarray:
    """Frame of the next joint (types B and D): prev turned about z towards ``point``, moved onto it,
    and turned about its new x so that ``next_point`` lies in its xz plane with z >= 0 (eqs. 18-30).

    A point on the z axis (or x axis) leaves theta (or alpha) at 0 instead of an undefined angle.
    """
    local = se3.inv(prev) @ np.append(point, 1.0)
    theta = math.atan2(local[1], local[0]) if math.hypot(local[0], local[1]) > tol else 0.0
    J = prev @ se3.rot_z(theta)
    J[:3, 3] = point
    nxt = se3.inv(J) @ np.append(next_point, 1.0)
    alpha = math.atan2(-nxt[1], nxt[2]) if math.hypot(nxt[1], nxt[2]) > tol else 0.0
    return J @ se3.rot_x(alpha)


def _rows_between(frames: list[np.ndarray]) -> np.ndarray:
    return np.array([dh_params_between(frames[i], frames[i + 1]) for i in range(len(frames) - 1)])


# ----------------------------------------------------------------------------------- estimators
def _type_a(target: np.ndarray, n: int, dist: float, notes: list[str]) -> np.ndarray:
    x, y, z = target[:3, 3]
    h = math.hypot(x, y)
    if h > LENGTH_TOL * dist:
        theta1 = math.atan2(y, x)
    else:
        theta1, h = 0.0, 0.0
        notes.append("target on the base z axis: a_i = 0, the joints stack on the base axis")
    rows = np.zeros((n, 4))
    rows[:, 0] = h / n
    rows[0, 1] = z
    alphas = [TYPE_A_TWIST * (1 if i % 2 == 0 else -1) for i in range(n)]
    if n % 2:
        alphas[-1] = 0.0  # keeps the sum of the twists zero
    rows[:, 2] = alphas
    rows[0, 3] = theta1
    return rows


def _type_b(target: np.ndarray, n: int, dist: float, notes: list[str]) -> np.ndarray:
    tol = LENGTH_TOL * dist
    pts = curve_points(np.eye(4), target, n)
    frames = [np.eye(4)]
    for i in range(1, n):
        nxt = pts[i + 1] if i + 1 < n else target[:3, 3]
        frames.append(_aim_on_curve(frames[-1], pts[i], nxt, tol))
    last = frames[-1]
    # tool row (d = a = 0): turn z_n onto the target's z axis where a twist about a common normal can.
    zl, zt = last[:3, 2], target[:3, 2]
    c = np.cross(zl, zt)
    if np.linalg.norm(c) >= ANGLE_TOL:
        u = c / np.linalg.norm(c)
        u = u if np.dot(u, last[:3, 0]) >= 0 else -u  # |theta_n| <= pi/2
    else:
        # z_n already along +-z_target: theta_n is free, so it turns x onto the target's x and the
        # full pose is reached (alpha_n = 0 or pi keeps x).
        u = target[:3, 0]
        notes.append("the last joint axis is parallel to the target z axis: the tool row also turns x onto "
                     "the target's x, so q = 0 reaches the full pose")
    theta = _angle_about(zl, last[:3, 0], u)
    tool = last @ se3.rot_z(theta)
    tool = tool @ se3.rot_x(_angle_about(u, zl, zt))
    tool[:3, 3] = target[:3, 3]
    frames.append(tool)
    return _rows_between(frames)


def _type_c(target: np.ndarray, n: int, dist: float, notes: list[str]) -> np.ndarray:
    zb, xb = np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])
    tp, zp, xp = target[:3, 3], target[:3, 2], target[:3, 0]
    cn = _normal(np.zeros(3), zb, tp, zp, notes, "base and target z axes")
    u = _perpendicular(cn.c1, cn.c2, zb, zp, xb, LENGTH_TOL * dist, notes, "base and target z axes")
    alpha_sum = _angle_about(u, zb, zp)
    m = n - 1
    rows = np.zeros((n, 4))
    rows[:m, 0] = cn.distance / m
    rows[:m, 2] = alpha_sum / m
    rows[0, 1] = float(np.dot(cn.c1, zb))
    rows[0, 3] = _angle_about(zb, xb, u)
    rows[-1, 1] = float(np.dot(tp - cn.c2, zp))
    rows[-1, 3] = _angle_about(zp, u, xp)
    return rows


def _type_d(target: np.ndarray, n: int, dist: float, notes: list[str]) -> np.ndarray:
    tol = LENGTH_TOL * dist
    pts = curve_points(np.eye(4), target, n)
    frames = [np.eye(4)]
    for i in range(1, n - 1):
        frames.append(_aim_on_curve(frames[-1], pts[i], pts[i + 1], tol))
    prev = frames[-1]
    o, z, x = prev[:3, 3], prev[:3, 2], prev[:3, 0]
    tp, zp = target[:3, 3], target[:3, 2]
    what = f"joint {n - 1} axis and target z axis"
    cn = _normal(o, z, tp, zp, notes, what)
    u = _perpendicular(cn.c1, cn.c2, z, zp, x, tol, notes, what)
    J = prev @ se3.rot_z(_angle_about(z, x, u))
    J = J @ se3.rot_x(_angle_about(u, z, zp))
    J[:3, 3] = cn.c2
    frames += [J, target]
    return _rows_between(frames)
