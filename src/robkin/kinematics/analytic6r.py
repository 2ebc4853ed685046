"""Closed-form IK of two families of 6R arms, detected from the joint axes (any representation).

- ``SphericalWrist6R``: axes 2 and 3 parallel and a spherical wrist (axes 4, 5, 6 meet) - the
  industrial arms with an ortho-parallel base and a spherical wrist (KUKA KR, ABB IRB, Fanuc, Puma 560,
  Kinova Jaco "s" type) and more: axis 1 only has to be non-parallel to axis 2.
- ``ThreeParallel6R``: axes 2, 3, 4 parallel and axes 5, 6 meeting - the Universal Robots type.

Each returns up to 8 solutions (2 shoulders x 2 elbows x 2 wrists).

Spherical wrist, in the space-frame product of exponentials T(q) = exp([S_1] q_1) ... exp([S_6] q_6) M,
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
from ..lines import perpendicular
from ..robot import Robot
from .closed_form import DETECT_ANGLE_TOL, DETECT_LENGTH_TOL, Branches, first_reason
from .limits import wrap_into_limits
from .subproblems import angle_about, cos_sin_equation, cross, planar_two_link, rotation_about, two_axes

__all__ = ["SphericalWrist6R", "ThreeParallel6R", "wrist_centre", "NEAR_SINGULAR"]

#: Within this (relative) distance of a singularity - the wrist point on axis 1, axis 6 along the
#: parallel axes - the closed form's angles are only known to ~sqrt(eps) (arccos near +-1): a target
#: left without a branch there is flagged uncertain (``ik`` retries it numerically), not unreachable.
NEAR_SINGULAR = 1e-6


def wrist_centre(points: np.ndarray, axes: np.ndarray) -> tuple[np.ndarray, float]:
    """Least-squares meeting point (3,) of lines (k, 3) points / (k, 3) unit axes, and the largest
    distance from it to any of the lines."""
    P = np.eye(3) - axes[:, :, None] * axes[:, None, :]          # projectors normal to each axis
    A = P.sum(axis=0)
    b = np.einsum("kij,kj->i", P, points)
    x = np.linalg.lstsq(A, b, rcond=None)[0]
    dist = np.linalg.norm(np.einsum("kij,kj->ki", P, x - points), axis=1)
    return x, float(dist.max())


class _Closed6R:
    """What both 6R families share: the plane of the parallel axes as complex numbers, and the first
    detection steps (six revolute joints, axis angles, the length tolerance)."""

    e1: np.ndarray
    e2: np.ndarray

    def _complex(self, x: np.ndarray) -> np.ndarray:
        """Points (..., 3) as complex coordinates in the plane spanned by e1, e2."""
        return x @ self.e1 + 1j * (x @ self.e2)

    @staticmethod
    def _six_revolute(robot: Robot):
        """(z, c, length tolerance, sin of the angle between axes i and j) for a 6R robot, else None."""
        if robot.n != 6 or not robot.revolute.all():
            return None
        z, c = robot.axes, robot.points

        def sin_angle(i: int, j: int) -> float:
            return float(np.linalg.norm(cross(z[i], z[j])))

        return z, c, DETECT_LENGTH_TOL * robot.scale, sin_angle


class SphericalWrist6R(_Closed6R):
    """All closed-form solutions of a 6R arm with axes 2 || 3 and a spherical wrist."""

    name = "spherical-wrist-6r"

    def __init__(self, robot: Robot, w0: np.ndarray) -> None:
        self.robot = robot
        z, c = robot.axes, robot.points
        self.z, self.c, self.w0 = z, c, w0
        self.n2 = z[1]
        self.k = float(self.n2 @ w0)                 # the plane joints 2-3 keep the wrist centre in
        self.sigma3 = float(np.sign(z[2] @ self.n2))
        e1 = perpendicular(self.n2)
        self.e1, self.e2 = e1, cross(self.n2, e1)
        C2, C3, W = (self._complex(x) for x in (c[1], c[2], w0))
        self.C2, self.a, self.b = C2, C3 - C2, W - C3
        M = robot.tool
        self.w_tool = (se3.inv(M) @ np.append(w0, 1.0))[:3]  # wrist centre in tool coordinates
        self.R_M = M[:3, :3]
        x6 = perpendicular(z[5])
        self.x6 = x6                                   # any direction normal to axis 6

    @classmethod
    def detect(cls, robot: Robot) -> "SphericalWrist6R | None":
        """A solver if the robot is 6R with axes 2 || 3 (distinct), axis 1 not || 2, axes 4-6 meeting."""
        six = cls._six_revolute(robot)
        if six is None:
            return None
        z, c, tol_len, sin_angle = six
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
        B = -(cross(z[0], r) @ n2)
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
        # wrist centre (nearly) on axis 1: q1 is free or ill-determined; not proven unreachable
        uncertain = none & (np.hypot(A, B) / self.robot.scale < NEAR_SINGULAR)
        la, lb = abs(self.a), abs(self.b)
        reasons = first_reason([
            (uncertain, "singular target (wrist centre on axis 1): no solution found with the "
                        "preferred joint 1 angle"),
            (none & ~ok1.any(axis=1), "out of reach: no turn of joint 1 brings the wrist centre into "
                                      "the plane of joints 2 and 3"),
            (none & ~(ok1[:, :, None] & ok23).any(axis=(1, 2)),
             lambda i: f"out of reach: the wrist centre is {np.abs(d[i]).min():.6g} from axis 2, "
                       f"joints 2-3 reach {abs(la - lb):.6g} to {la + lb:.6g}"),
            (none & ~geometric.any(axis=1), "the wrist cannot reach the target orientation"),
            (none & geometric.any(axis=1), "solutions exist but violate the joint limits"),
        ], N)
        return Branches(Q, valid, reasons, uncertain)


class ThreeParallel6R(_Closed6R):
    """All closed-form solutions of a 6R arm with axes 2, 3, 4 parallel and axes 5, 6 meeting.

    The Universal Robots geometry (UR3/5/10/e, and the cobots built like them). Up to 8 solutions:
    2 shoulders x 2 wrists x 2 elbows. With u the common direction of axes 2-4 and w the point where
    axes 5 and 6 meet (fixed by joints 5 and 6):

    1. joints 2-4 keep u . x constant, so joint 1 must turn p_w = T_d M^-1 w back into the plane
       u . x = u . w (as for the spherical wrist: A cos q1 + B sin q1 = K, 2 shoulders);
    2. they also keep u . v for directions: the tool's axis-6 direction, turned back by joint 1, fixes
       u . Rot(z5, q5) z6 - another cos/sin equation (2 wrists);
    3. joints 2-4 together turn about u by phi: phi and q6 follow from the remaining rotation
       Rot(u, phi) Rot(z5, q5) Rot(z6, q6) = R_1^T R_d R_M^T (two subproblem-1 angles);
    4. the point on axis 4 is then known, and joints 2, 3 reach it as a planar chain (2 elbows);
       q4 takes the rest of phi.

    Where joint 6's axis lines up with u (the wrist singularity of these arms) phi is free and takes
    the preferred value from q0.
    """

    name = "three-parallel-6r"

    def __init__(self, robot: Robot, w: np.ndarray) -> None:
        self.robot = robot
        z, c = robot.axes, robot.points
        self.z, self.c, self.w = z, c, w
        self.u = z[1]
        self.sigma = np.sign(z[1:4] @ self.u)                    # senses of axes 2-4 along u
        e1 = perpendicular(self.u)
        self.e1, self.e2 = e1, cross(self.u, e1)
        C2, C3, C4 = (self._complex(x) for x in (c[1], c[2], c[3]))
        self.C2, self.a, self.b = C2, C3 - C2, C4 - C3
        M = robot.tool
        self.M_inv = se3.inv(M)
        self.w_tool = (self.M_inv @ np.append(w, 1.0))[:3]
        self.R_M = M[:3, :3]
        self.x6 = perpendicular(z[5])

    @classmethod
    def detect(cls, robot: Robot) -> "ThreeParallel6R | None":
        """A solver if the robot is 6R, axes 2 || 3 || 4 (distinct), axes 1 and 5 not || 2, 5 and 6 meet."""
        six = cls._six_revolute(robot)
        if six is None:
            return None
        z, c, tol_len, sin_angle = six
        if sin_angle(1, 2) > DETECT_ANGLE_TOL or sin_angle(1, 3) > DETECT_ANGLE_TOL:
            return None
        if min(sin_angle(0, 1), sin_angle(4, 1), sin_angle(4, 5)) <= DETECT_ANGLE_TOL:
            return None
        w, miss = wrist_centre(c[4:], z[4:])
        if miss > tol_len:
            return None
        solver = cls(robot, w)
        if abs(solver.a) <= tol_len or abs(solver.b) <= tol_len:
            return None  # coincident parallel axes: not a planar two-link chain
        return solver

    def _rest(self, phi, R1, R5, W, Rd, pd, q2_ref):
        """q6, the planar joints 2-3 (both elbows) and the reach check for given phi (...), with R1,
        R5, W, Rd (..., 3, 3) and pd (..., 3) broadcast to phi's shape."""
        z, c, u = self.z, self.c, self.u
        R6 = np.swapaxes(R5, -1, -2) @ np.swapaxes(rotation_about(u, phi), -1, -2) @ W
        q6 = angle_about(z[5], np.broadcast_to(self.x6, np.shape(phi) + (3,)), R6 @ self.x6)
        # the point on axis 4, moved by joints 2 and 3 only: Y = E1^-1 T_d M^-1 E6^-1 E5^-1 c4
        x = c[4] + np.einsum("...ij,j->...i", np.swapaxes(R5, -1, -2), c[3] - c[4])
        x = c[5] + np.einsum("...ij,...j->...i", rotation_about(z[5], -q6), x - c[5])
        x = x @ self.M_inv[:3, :3].T + self.M_inv[:3, 3]
        x = np.einsum("...ij,...j->...i", Rd, x) + pd
        Y = c[0] + np.einsum("...ji,...j->...i", R1, x - c[0])
        d = self._complex(Y) - self.C2
        psi2, psi3, ok23, _ = planar_two_link(self.a, self.b, d, free1=self.sigma[0] * q2_ref)
        return q6, psi2, psi3, ok23.copy(), d

    def solve(self, targets: np.ndarray, q_ref: np.ndarray) -> Branches:
        """Up to 8 branches (N, 8, 6) for targets (N, 4, 4); q_ref (N, 6) decides free joints."""
        z, c, u, sig = self.z, self.c, self.u, self.sigma
        N = len(targets)
        Rd, pd = targets[:, :3, :3], targets[:, :3, 3]
        scale = self.robot.scale

        # 1. shoulder, from the point where axes 5 and 6 meet
        pw = np.einsum("nij,j->ni", Rd, self.w_tool) + pd
        r = pw - c[0]
        zr = r @ z[0]
        nz = float(u @ z[0])
        A = r @ u - zr * nz
        B = -(cross(z[0], r) @ u)
        K = float(u @ self.w) - float(u @ c[0]) - zr * nz
        q1, ok1 = cos_sin_equation(A / scale, B / scale, K / scale, free=q_ref[:, 0])      # (N, 2)
        R1 = rotation_about(z[0], q1)                                                     # (N, 2, 3, 3)

        # 2. wrist: u . Rot(z5, q5) g = u . (R1^T z6_target), g = z6 at q = 0
        g = z[5]
        Rt = Rd @ self.R_M.T                                                              # R(q) at target
        z6t = Rt @ g                                                                      # (N, 3)
        lhs = np.einsum("nsji,nj->nsi", R1, z6t) @ u                                      # (N, 2)
        zg, uz = float(z[4] @ g), float(u @ z[4])
        q5, ok5 = cos_sin_equation(np.full_like(lhs, u @ g - zg * uz), np.full_like(lhs, u @ cross(z[4], g)),
                                   lhs - zg * uz, free=q_ref[:, None, 4])                 # (N, 2, 2)

        # 3. phi (joints 2-4 about u) and q6 from W = R1^T R_d R_M^T = Rot(u, phi) R5 R6
        W = np.swapaxes(R1, -1, -2) @ Rt[:, None]                                         # (N, 2, 3, 3)
        W = np.broadcast_to(W[:, :, None], q5.shape + (3, 3))
        R5 = rotation_about(z[4], q5)                                                     # (N, 2, 2, 3, 3)
        phi_ref = np.broadcast_to((q_ref[:, 1:4] @ sig)[:, None, None], q5.shape)
        a5 = R5 @ g
        phi = angle_about(u, a5, W @ g, free=phi_ref)                                     # (N, 2, 2)
        R1b = np.broadcast_to(R1[:, :, None], q5.shape + (3, 3))
        Rdb = np.broadcast_to(Rd[:, None, None], q5.shape + (3, 3))
        pdb = np.broadcast_to(pd[:, None, None], q5.shape + (3,))
        q6, psi2, psi3, ok23, d = self._rest(phi, R1b, R5, W, Rdb, pdb, q_ref[:, 1, None, None])

        # Wrist singularity (axis 6 along u): phi and q6 trade off, but the point on axis 4 - and with
        # it the reach of joints 2-3 - depends on the split. Take the preferred phi if it reaches, else
        # the reaching phi nearest to it on a 1-degree grid (any reaching phi is an exact solution).
        # Near it q5 is known only to ~sqrt(eps), which leaves phi ill-determined too: within
        # NEAR_SINGULAR phi is searched like this, and targets still without a branch are flagged.
        free = np.linalg.norm(a5 - np.multiply.outer(a5 @ u, u), axis=-1) < NEAR_SINGULAR
        for i in np.argwhere(free & ~ok23.any(axis=-1)):
            i = tuple(i)
            steps = np.arange(1, 181)
            cand = phi_ref[i] + np.radians(np.r_[0, np.ravel(np.column_stack([steps, -steps]))])
            m = len(cand)
            c6, c2, c3, cok, cd = self._rest(cand, np.broadcast_to(R1b[i], (m, 3, 3)),
                                             np.broadcast_to(R5[i], (m, 3, 3)), np.broadcast_to(W[i], (m, 3, 3)),
                                             np.broadcast_to(Rdb[i], (m, 3, 3)), np.broadcast_to(pdb[i], (m, 3)),
                                             np.full(m, q_ref[i[0], 1]))
            hit = np.flatnonzero(cok.any(axis=-1))
            if hit.size:
                k = hit[0]
                phi[i], q6[i], psi2[i], psi3[i], ok23[i], d[i] = cand[k], c6[k], c2[k], c3[k], cok[k], cd[k]
        psi4 = phi[..., None] - psi2 - psi3                                               # (N, 2, 2, 2)

        shape = psi2.shape
        Q = np.stack([np.broadcast_to(q1[:, :, None, None], shape), sig[0] * psi2, sig[1] * psi3,
                      sig[2] * psi4, np.broadcast_to(q5[..., None], shape),
                      np.broadcast_to(q6[..., None], shape)], axis=-1).reshape(N, 8, 6)
        geometric = (np.broadcast_to(ok1[:, :, None, None], shape) & np.broadcast_to(ok5[..., None], shape)
                     & ok23).reshape(N, 8)
        Q, in_limits = wrap_into_limits(Q, self.robot.limits, self.robot.revolute, q_ref[:, None, :])
        valid = geometric & in_limits

        none = ~valid.any(axis=1)
        # free joints set to preferred values (wrist point on axis 1; axis 6 along u): not proven
        q1_free = np.hypot(A, B) / scale < NEAR_SINGULAR
        uncertain = none & (q1_free | free.any(axis=(1, 2)))
        la, lb = abs(self.a), abs(self.b)
        reasons = first_reason([
            (uncertain, "singular target (a free joint): no solution found with the preferred value"),
            (none & ~ok1.any(axis=1), "out of reach: no turn of joint 1 brings the wrist into the "
                                      "plane of joints 2-4"),
            (none & ~(ok1[:, :, None] & ok5).any(axis=(1, 2)), "the tool's last axis cannot point that way"),
            (none & ~geometric.any(axis=1),
             lambda i: f"out of reach: axis 4 would be {np.abs(d[i]).min():.6g} from axis 2, joints 2-3 "
                       f"reach {abs(la - lb):.6g} to {la + lb:.6g}"),
            (none & geometric.any(axis=1), "solutions exist but violate the joint limits"),
        ], N)
        return Branches(Q, valid, reasons, uncertain)
