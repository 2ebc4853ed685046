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

Detection runs here, once per robot; the solving runs in the compiled kernels of
``robkin.compiled.ik.closed_form_6r``, one target at a time in C.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from .. import se3
from ..lines import closest_points, perpendicular
from ..robot import Robot
from .kernel_solver import DETECT_ANGLE_TOL, DETECT_LENGTH_TOL, KernelSolver
from .limits import LIMIT_TOL, default_preference

__all__ = ["SphericalWrist6R", "ThreeParallel6R", "wrist_centre"]


def wrist_centre(points: np.ndarray, axes: np.ndarray) -> tuple[np.ndarray, float]:
    """Where lines (k, 3) points / (k, 3) unit axes meet: the midpoint (3,) of the common normal of the
    first two (which must not be parallel), and the largest distance from it to any of the lines.

    Arithmetic only (no LAPACK call, whose first use costs milliseconds): detection must stay cheap
    for one-shot commands and for pipelines that try many robots.
    """
    cn = closest_points(points[0], axes[0], points[1], axes[1])
    x = 0.5 * (cn.c1 + cn.c2)
    d = x - points
    off_axis = d - np.sum(d * axes, axis=1)[:, None] * axes
    return x, float(np.sqrt(np.sum(off_axis * off_axis, axis=1)).max())


class _Closed6R(KernelSolver):
    """What both 6R families share: the plane of the parallel axes as complex numbers and the first
    detection steps (six revolute joints, axis angles, the length tolerance). The compiled kernel
    (``robkin.compiled.ik.closed_form_6r``) is built per robot; ``messages`` explain its outcome codes."""

    e1: np.ndarray
    e2: np.ndarray
    a: complex
    b: complex

    def _complex(self, x: np.ndarray) -> complex:
        """A point (3,) as a complex coordinate in the plane spanned by e1, e2."""
        return complex(x @ self.e1, x @ self.e2)

    def _plane(self, u: np.ndarray, c: np.ndarray) -> None:
        """The plane normal to u and the planar two-link chain of axes 2, 3 (points c (3, 3))."""
        self.e1 = perpendicular(u)
        self.e2 = np.cross(u, self.e1)
        C2, C3, C4 = (self._complex(x) for x in c)
        self.C2, self.a, self.b = C2, C3 - C2, C4 - C3

    @staticmethod
    def _six_revolute(robot: Robot):
        """(z, c, length tolerance, sin of the angle between axes i and j) for a 6R robot, else None."""
        if robot.n != 6 or not robot.revolute.all():
            return None
        z, c = robot.axes, robot.points
        sines = np.linalg.norm(np.cross(z[:, None, :], z[None, :, :]), axis=-1)   # one call for all pairs

        def sin_angle(i: int, j: int) -> float:
            return float(sines[i, j])

        return z, c, DETECT_LENGTH_TOL * robot.scale, sin_angle

    def _reach_message(self, what: str) -> Callable[[float], str]:
        """The out-of-reach message quoting the distance ``what`` is from axis 2."""
        la, lb = abs(self.a), abs(self.b)
        return lambda d: (f"out of reach: {what} {d:.6g} m from axis 2, joints 2-3 reach {abs(la - lb):.6g} "
                          f"to {la + lb:.6g} m")


class SphericalWrist6R(_Closed6R):
    """All closed-form solutions of a 6R arm with axes 2 || 3 and a spherical wrist."""

    name = "spherical-wrist-6r"

    def __init__(self, robot: Robot, w0: np.ndarray) -> None:
        from ..compiled.ik.closed_form_6r import SphericalWristKernel

        z, c = robot.axes, robot.points
        self.w0 = w0
        self._plane(z[1], np.array([c[1], c[2], w0]))
        M = robot.tool
        self.w_tool = (se3.inv(M) @ np.append(w0, 1.0))[:3]  # wrist centre in tool coordinates
        sigma3 = float(np.sign(z[2] @ z[1]))
        k = float(z[1] @ w0)                                 # the plane joints 2-3 keep the wrist centre in
        self._use(SphericalWristKernel(robot._chain, default_preference(robot.limits), z, c, self.w_tool,
                                       M[:3, :3], perpendicular(z[5]), self.e1, self.e2, self.a, self.b,
                                       self.C2, robot.scale, robot.limits, LIMIT_TOL, k, sigma3))
        self.messages = (
            "",
            "singular target (wrist centre on axis 1): no solution found with the preferred joint 1 angle",
            "out of reach: no turn of joint 1 brings the wrist centre into the plane of joints 2 and 3",
            self._reach_message("the wrist centre is"),
            "the wrist cannot reach the target orientation",
            "solutions exist but violate the joint limits",
        )

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
        from ..compiled.ik.closed_form_6r import ThreeParallelKernel

        z, c = robot.axes, robot.points
        u = z[1]
        sigma = np.sign(z[1:4] @ u)                          # senses of axes 2-4 along u
        self._plane(u, c[1:4])
        M = robot.tool
        M_inv = se3.inv(M)
        self.w_tool = (M_inv @ np.append(w, 1.0))[:3]
        self._use(ThreeParallelKernel(robot._chain, default_preference(robot.limits), z, c, self.w_tool,
                                      M[:3, :3], perpendicular(z[5]), self.e1, self.e2, self.a, self.b,
                                      self.C2, robot.scale, robot.limits, LIMIT_TOL, w, sigma, M_inv))
        self.messages = (
            "",
            "singular target (a free joint): no solution found with the preferred value",
            "out of reach: no turn of joint 1 brings the wrist into the plane of joints 2-4",
            "the tool's last axis cannot point that way",
            self._reach_message("axis 4 would be"),
            "solutions exist but violate the joint limits",
        )

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
