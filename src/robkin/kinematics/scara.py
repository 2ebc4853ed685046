"""Closed-form IK of SCARA-type arms: every joint axis parallel to one direction u.

Fits any robot (from any representation) whose joint axes are all parallel or anti-parallel to one
direction u, with two or three revolute joints (a planar two-link core, plus an optional wrist
rotation) and any number of prismatic joints along u - the 5-DOF inverted SCARA of
Jimenez-Nixon et al.'s 5-DOF inverted SCARA paper (P R R R P, both prismatic joints flipped) among them.

The geometry, in the space-frame product of exponentials T(q) = prod_i exp([S_i] q_i) M:

- a translation along u commutes with a rotation about any axis parallel to u, so every prismatic
  joint can be pulled to the front: T = Trans(u h) R_chain M with h = sum_p s_p q_p (s_p = +-1 the
  sense of joint p along u) - the vertical travel;
- rotations about parallel axes add: the tool orientation is Rot(u, phi) R_M with phi = sum of the
  signed revolute angles; the target must therefore be a rotation about u away from R_M;
- in the plane normal to u the revolute joints are a planar chain: with a wrist (three revolute
  joints) the point on the wrist axis is fixed in the tool, so the target fixes where it must be,
  the first two joints reach it (two elbow solutions) and the wrist takes the remaining angle; with
  two revolute joints the tool origin is the point and the orientation must come out right.

Policy for redundant vertical joints (the seed SCARA's P1 and P5 both move along u): of all the splits
of h between the prismatic joints, the one nearest (Euclidean) to the preferred values q_ref (the
solver's ``q0``, zero by default) within the joint limits. With no limits and q_ref = 0 that is the
equal split; to pin one joint, give it as q0 and a narrow limit.
"""

from __future__ import annotations

import numpy as np

from .. import se3
from ..lines import perpendicular
from ..robot import Robot
from .closed_form import DETECT_ANGLE_TOL, DETECT_LENGTH_TOL, Branches, first_reason
from .limits import wrap_into_limits
from .subproblems import COS_SLACK, planar_two_link

__all__ = ["ScaraSolver", "split_travel"]

#: Target orientation must be a rotation about u to this (|R u - u|, radians); a looser target has
#: no exact solution. 1e-9: rounding of targets computed by FK is ~1e-15, and the IK verifies to 1e-9.
ORIENTATION_SLACK = 1e-9


def split_travel(h: np.ndarray, s: np.ndarray, ref: np.ndarray, lo: np.ndarray, hi: np.ndarray
                 ) -> np.ndarray:
    """The q (N, m) nearest to ref (N, m) with s . q = h (N,) and lo <= q <= hi.

    The solution of the projection is q = clip(ref + lam * s, lo, hi) for one scalar lam per target.
    Joints that hit a limit stay there as lam moves on (the sum is monotone in lam), so fixing them
    and re-spreading the remainder over the others converges in at most m rounds.
    """
    N, m = ref.shape
    q = ref.copy()
    free = np.ones((N, m), bool)
    for _ in range(m):
        fixed = np.sum(np.where(free, 0.0, s * q), axis=1)
        nfree = np.maximum(np.sum(free * s * s, axis=1), 1e-300)
        lam = (h - fixed - np.sum(np.where(free, s * ref, 0.0), axis=1)) / nfree
        trial = ref + lam[:, None] * s
        q = np.where(free, trial, q)
        over = free & ((q < lo) | (q > hi))
        if not over.any():
            break
        q = np.where(over, np.clip(q, lo, hi), q)
        free &= ~over
    return q


class ScaraSolver:
    """All closed-form solutions (two elbows) of a SCARA-type arm; see the module docstring."""

    name = "scara"

    def __init__(self, robot: Robot, u: np.ndarray) -> None:
        self.robot = robot
        self.u = u
        z, c = robot.axes, robot.points
        self.ridx = np.flatnonzero(robot.revolute)
        self.pidx = np.flatnonzero(~robot.revolute)
        self.sigma = np.sign(z[self.ridx] @ u)                  # revolute sense along u (+-1)
        self.s = z[self.pidx] @ u                               # prismatic sense along u (+-1)
        e1 = perpendicular(u)
        self.e1, self.e2 = e1, np.cross(u, e1)
        C = self._complex(c[self.ridx])
        M = robot.tool
        if len(self.ridx) == 3:
            # the wrist axis point, in tool coordinates: it moves rigidly with the tool
            self.point_in_tool = (se3.inv(M) @ np.append(c[self.ridx[2]], 1.0))[:3]
            home = C[2]
        else:
            self.point_in_tool = np.zeros(3)                    # the tool origin itself
            home = self._complex(M[:3, 3])
        self.C1 = C[0]
        self.a = C[1] - C[0]
        self.b = home - C[1]

    @classmethod
    def detect(cls, robot: Robot) -> "ScaraSolver | None":
        """A solver if every joint axis is parallel to one direction and 2 or 3 joints are revolute."""
        rev = robot.revolute
        if rev.sum() not in (2, 3):
            return None
        z = robot.axes
        u = z[np.flatnonzero(rev)[0]]
        if np.max(np.linalg.norm(np.cross(z, u), axis=1)) > DETECT_ANGLE_TOL:
            return None
        solver = cls(robot, u)
        tol = DETECT_LENGTH_TOL * robot.scale
        if abs(solver.a) <= tol or abs(solver.b) <= tol:
            return None  # coincident axes (or tool on the second axis): a one-link chain, not a SCARA
        return solver

    def _complex(self, x: np.ndarray) -> np.ndarray:
        """Points (..., 3) in the plane normal to u as complex numbers."""
        return x @ self.e1 + 1j * (x @ self.e2)

    def solve(self, targets: np.ndarray, q_ref: np.ndarray) -> Branches:
        """Both elbow branches for targets (N, 4, 4); q_ref (N, n) decides the free choices."""
        robot, u = self.robot, self.u
        N, n = len(targets), robot.n
        R_M, p_M = robot.tool[:3, :3], robot.tool[:3, 3]
        Rd, pd = targets[:, :3, :3], targets[:, :3, 3]
        lim = robot.limits

        # orientation: Rot(u, phi) R_M
        rel = Rd @ R_M.T
        tilt = np.linalg.norm(rel @ u - u, axis=1)
        orient_ok = tilt <= ORIENTATION_SLACK
        phi = np.arctan2(rel @ self.e1 @ self.e2, rel @ self.e1 @ self.e1)

        # vertical travel, split among the prismatic joints
        h = (pd - p_M) @ u
        qp = split_travel(h, np.broadcast_to(self.s, (N, len(self.pidx))), q_ref[:, self.pidx],
                          lim[self.pidx, 0], lim[self.pidx, 1])
        # the split meets h exactly unless the limits cut it short; a shortfall within rounding of
        # the robot's size (COS_SLACK relative) is still a solution, and FK checks it afterwards
        vert_ok = np.abs(qp @ self.s - h) <= COS_SLACK * robot.scale

        # planar chain: the first two revolute joints bring the wrist point (or tool origin) there
        point = np.einsum("nij,j->ni", Rd, self.point_in_tool) + pd
        d = self._complex(point) - self.C1
        r0 = self.ridx[0]
        x1, x2, reach_ok, D = planar_two_link(self.a, self.b, d, free1=self.sigma[0] * q_ref[:, r0])
        if len(self.ridx) == 3:
            x3 = phi[:, None] - x1 - x2
            angles = np.stack([x1, x2, x3], axis=-1)
            wrist_ok = np.ones_like(reach_ok)
        else:
            miss = np.angle(np.exp(1j * (phi[:, None] - x1 - x2)))
            wrist_ok = np.abs(miss) <= ORIENTATION_SLACK
            angles = np.stack([x1, x2], axis=-1)

        Q = np.empty((N, 2, n))
        Q[:, :, self.ridx] = angles * self.sigma
        Q[:, :, self.pidx] = qp[:, None, :]
        Q, in_limits = wrap_into_limits(Q, lim, robot.revolute, q_ref[:, None, :])
        geometric = reach_ok & wrist_ok & orient_ok[:, None] & vert_ok[:, None]
        valid = geometric & in_limits

        none = ~valid.any(axis=1)
        la, lb = abs(self.a), abs(self.b)
        reasons = first_reason([
            (none & ~orient_ok, lambda i: f"the target orientation is tilted {tilt[i]:.3g} rad away from "
                                          f"a rotation about the joint axes' common direction {_vec(u)}; "
                                          f"this arm can only turn its tool about that direction"),
            (none & ~vert_ok, lambda i: f"the travel along {_vec(u)} ({h[i]:.6g}) is outside what the "
                                        f"prismatic joints reach within their limits"),
            (none & ~reach_ok.any(axis=1), lambda i: f"out of reach in the plane: the point is "
                                                     f"{abs(d[i]):.6g} from the first axis, the arm "
                                                     f"reaches {abs(la - lb):.6g} to {la + lb:.6g}"),
            (none & ~wrist_ok.any(axis=1), "the orientation about the common axis does not match the "
                                           "position (this arm has no wrist joint)"),
            (none & geometric.any(axis=1), "solutions exist but violate the joint limits"),
        ], N)
        return Branches(Q, valid, reasons)


def _vec(v: np.ndarray) -> str:
    return "(" + ", ".join(f"{x:.6g}" for x in v + 0.0) + ")"
