"""Closed-form IK of 6R arms with two parallel axes (2, 3) and a spherical wrist (axes 4, 5, 6 meet).

This covers the industrial arms with an ortho-parallel base and a spherical wrist (KUKA KR, ABB IRB,
Fanuc, Puma 560 type) and more: axis 1 only has to be non-parallel to axis 2. Detection looks at the
robot's joint axes, so it works whatever representation the robot came from. Up to 8 solutions:
2 shoulders x 2 elbows x 2 wrists.

Geometry, in the space-frame product of exponentials T(q) = exp([S_1] q_1) ... exp([S_6] q_6) M,
with c_i a point on axis i and z_i its direction at q = 0:

1. The wrist centre w0 (where axes 4-6 meet) is fixed by joints 4-6, so the target puts it at
   p_w = T_d M^-1 w0.
2. Joints 2 and 3 turn about axes parallel to z_2, which keeps z_2 . x constant: joint 1 must turn
   p_w back into the plane z_2 . x = z_2 . w0 - an equation A cos q1 + B sin q1 = K (2 shoulders).
3. In that plane, joints 2 and 3 are a planar two-link chain reaching the turned-back p_w (2 elbows).
4. The wrist rotation R_w = (R_1 R_2 R_3)^T R_d R_M^T = Rot(z4, q4) Rot(z5, q5) Rot(z6, q6): q4, q5
   carry z_6 onto R_w z_6 (Paden-Kahan subproblem 2, 2 wrists), then q6 is the remaining turn.

Singular targets (wrist centre on axis 1, wrist axes 4 and 6 aligned) have infinitely many
solutions: the free joint takes its preferred value (q0) and the others follow.
"""

from __future__ import annotations

import numpy as np

from .. import se3
from ..robot import Robot
from .closed_form import DETECT_ANGLE_TOL, DETECT_LENGTH_TOL, Branches, first_reason
from .limits import wrap_into_limits
from .scara import _perpendicular
from .subproblems import angle_about, cos_sin_equation, planar_two_link, rotation_about, two_axes

__all__ = ["SphericalWrist6R", "wrist_centre"]


def wrist_centre(points: np.ndarray, axes: np.ndarray) -> tuple[np.ndarray, float]:
    """Least-squares meeting point (3,) of lines (k, 3) points / (k, 3) unit axes, and the largest
    distance from it to any of the lines."""
    P = np.eye(3) - axes[:, :, None] * axes[:, None, :]          # projectors normal to each axis
    A = P.sum(axis=0)
    b = np.einsum("kij,kj->i", P, points)
    x = np.linalg.lstsq(A, b, rcond=None)[0]
    dist = np.linalg.norm(np.einsum("kij,kj->ki", P, x - points), axis=1)
    return x, float(dist.max())


class SphericalWrist6R:
    """All closed-form solutions of a 6R arm with axes 2 || 3 and a spherical wrist."""

    name = "spherical-wrist-6r"

    def __init__(self, robot: Robot, w0: np.ndarray) -> None:
        self.robot = robot
        z, c = robot.axes, robot.points
        self.z, self.c, self.w0 = z, c, w0
        self.n2 = z[1]
        self.k = float(self.n2 @ w0)                 # the plane joints 2-3 keep the wrist centre in
        self.sigma3 = float(np.sign(z[2] @ self.n2))
        e1 = _perpendicular(self.n2)
        self.e1, self.e2 = e1, np.cross(self.n2, e1)
        C2, C3, W = (self._complex(x) for x in (c[1], c[2], w0))
        self.C2, self.a, self.b = C2, C3 - C2, W - C3
        M = robot.tool
        self.w_tool = (se3.inv(M) @ np.append(w0, 1.0))[:3]  # wrist centre in tool coordinates
        self.R_M = M[:3, :3]
        x6 = _perpendicular(z[5])
        self.x6 = x6                                   # any direction normal to axis 6

    def _complex(self, x: np.ndarray) -> np.ndarray:
        return x @ self.e1 + 1j * (x @ self.e2)

    @classmethod
    def detect(cls, robot: Robot) -> "SphericalWrist6R | None":
        """A solver if the robot is 6R with axes 2 || 3 (distinct), axis 1 not || 2, axes 4-6 meeting."""
        if robot.n != 6 or not robot.revolute.all():
            return None
        z, c = robot.axes, robot.points
        tol_len = DETECT_LENGTH_TOL * robot.scale

        def sin_angle(i: int, j: int) -> float:
            return float(np.linalg.norm(np.cross(z[i], z[j])))

        if sin_angle(1, 2) > DETECT_ANGLE_TOL:
            return None
        if sin_angle(0, 1) <= DETECT_ANGLE_TOL or sin_angle(3, 4) <= DETECT_ANGLE_TOL \
                or sin_angle(4, 5) <= DETECT_ANGLE_TOL:
            return None
        w0, miss = wrist_centre(c[3:], z[3:])
        if miss > tol_len:
            return None
        solver = cls(robot, w0)
        if abs(solver.a) <= tol_len or abs(solver.b) <= tol_len:
            return None  # axes 2 and 3 coincide, or the wrist centre is on axis 3
        return solver

    def solve(self, targets: np.ndarray, q_ref: np.ndarray) -> Branches:
        """Up to 8 branches (N, 8, 6) for targets (N, 4, 4); q_ref (N, 6) decides free joints."""
        z, c, n2 = self.z, self.c, self.n2
        N = len(targets)
        Rd, pd = targets[:, :3, :3], targets[:, :3, 3]
        lim = self.robot.limits

        # 1. wrist centre target
        pw = np.einsum("nij,j->ni", Rd, self.w_tool) + pd                        # (N, 3)

        # 2. shoulder: n2 . (c1 + Rot(z1, -q1)(pw - c1)) = k
        r = pw - c[0]
        zr = r @ z[0]
        nz = float(n2 @ z[0])
        A = r @ n2 - zr * nz
        B = -(np.cross(z[0], r) @ n2)
        K = self.k - float(n2 @ c[0]) - zr * nz
        q1, ok1 = cos_sin_equation(A / self.robot.scale, B / self.robot.scale, K / self.robot.scale,
                                   free=q_ref[:, 0])                              # (N, 2)

        # 3. elbow: planar chain of joints 2, 3 to the turned-back wrist centre
        R1inv = rotation_about(z[0], -q1)                                         # (N, 2, 3, 3)
        y = c[0] + np.einsum("nsij,nj->nsi", R1inv, r)                            # (N, 2, 3)
        d = self._complex(y) - self.C2
        x2, x3, ok23, D = planar_two_link(self.a, self.b, d, free1=q_ref[:, None, 1])  # (N, 2, 2)
        q2, q3 = x2, self.sigma3 * x3

        # 4. wrist: Rot(z4, q4) Rot(z5, q5) Rot(z6, q6) = R_w
        q1b = np.broadcast_to(q1[:, :, None], q2.shape)                           # (N, 2, 2)
        R123 = rotation_about(z[0], q1b) @ rotation_about(z[1], q2) @ rotation_about(z[2], q3)
        Rw = np.swapaxes(R123, -1, -2) @ (Rd @ self.R_M.T)[:, None, None]         # (N, 2, 2, 3, 3)
        target6 = Rw @ z[5]
        q4, q5, ok45 = two_axes(z[3], z[4], np.broadcast_to(z[5], target6.shape), target6,
                                free1=q_ref[:, None, None, 3])                    # (N, 2, 2, 2)
        R45inv = np.swapaxes(rotation_about(z[3], q4) @ rotation_about(z[4], q5), -1, -2)
        x6_target = R45inv @ (Rw[..., None, :, :] @ self.x6)[..., None]
        q6 = angle_about(z[5], np.broadcast_to(self.x6, q4.shape + (3,)), x6_target[..., 0])

        shape = q4.shape
        Q = np.stack([np.broadcast_to(q1[:, :, None, None], shape),
                      np.broadcast_to(q2[..., None], shape),
                      np.broadcast_to(q3[..., None], shape), q4, q5, q6], axis=-1).reshape(N, 8, 6)
        geometric = (np.broadcast_to(ok1[:, :, None, None], shape) & np.broadcast_to(ok23[..., None], shape)
                     & ok45).reshape(N, 8)
        Q, in_limits = wrap_into_limits(Q, lim, self.robot.revolute, q_ref[:, None, :])
        valid = geometric & in_limits

        none = ~valid.any(axis=1)
        la, lb = abs(self.a), abs(self.b)
        reasons = first_reason([
            (none & ~ok1.any(axis=1), "out of reach: no turn of joint 1 brings the wrist centre into "
                                      "the plane of joints 2 and 3"),
            (none & ~(ok1[:, :, None] & ok23).any(axis=(1, 2)),
             lambda i: f"out of reach: the wrist centre is {np.abs(d[i]).min():.6g} from axis 2, "
                       f"joints 2-3 reach {abs(la - lb):.6g} to {la + lb:.6g}"),
            (none & ~geometric.any(axis=1), "the wrist cannot reach the target orientation"),
            (none & geometric.any(axis=1), "solutions exist but violate the joint limits"),
        ], N)
        return Branches(Q, valid, reasons)
