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

Detection runs here, once per robot; the solving runs in the compiled kernel of
``robkin.compiled.ik.closed_form_scara``, one target at a time in C.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from .. import se3
from ..lines import perpendicular
from ..robot import Robot
from .kernel_solver import DETECT_ANGLE_TOL, DETECT_LENGTH_TOL, KernelSolver
from .limits import LIMIT_TOL, default_preference

__all__ = ["ScaraSolver", "split_travel"]


def split_travel(h: np.ndarray, s: np.ndarray, ref: np.ndarray, lo: np.ndarray, hi: np.ndarray
                 ) -> np.ndarray:
    """The q (N, m) nearest to ref (N, m) with s . q = h (N,) and lo <= q <= hi (m,); s is (m,) or (N, m).

    The policy that splits a SCARA's travel along u among its prismatic joints (compiled; see
    ``robkin.compiled.ik.closed_form_scara``).
    """
    from ..compiled.ik.closed_form_scara import split_travel as kernel

    return kernel(h, s, ref, lo, hi)


class ScaraSolver(KernelSolver):
    """All closed-form solutions (two elbows) of a SCARA-type arm; see the module docstring."""

    name = "scara"

    def __init__(self, robot: Robot, u: np.ndarray) -> None:
        from ..compiled.ik.closed_form_scara import ScaraKernel

        self.u = u
        z, c = robot.axes, robot.points
        ridx = np.flatnonzero(robot.revolute)
        pidx = np.flatnonzero(~robot.revolute)
        sigma = np.sign(z[ridx] @ u)                            # revolute sense along u (+-1)
        s = z[pidx] @ u                                         # prismatic sense along u (+-1)
        e1 = perpendicular(u)
        self.e1, self.e2 = e1, np.cross(u, e1)
        C = [self._complex(x) for x in c[ridx]]
        M = robot.tool
        if len(ridx) == 3:
            # the wrist axis point, in tool coordinates: it moves rigidly with the tool
            point_in_tool = (se3.inv(M) @ np.append(c[ridx[2]], 1.0))[:3]
            home = C[2]
        else:
            point_in_tool = np.zeros(3)                         # the tool origin itself
            home = self._complex(M[:3, 3])
        self.a = C[1] - C[0]
        self.b = home - C[1]
        self._use(ScaraKernel(robot._chain, default_preference(robot.limits), u, self.e1, self.e2, M[:3, :3],
                              M[:3, 3], point_in_tool, self.a, self.b, C[0], robot.scale, ridx, pidx, sigma, s,
                              robot.limits, robot.revolute, LIMIT_TOL))
        la, lb = abs(self.a), abs(self.b)
        #: per kernel outcome code (see ``robkin.compiled.ik.closed_form_scara``), the message for a failure
        self.messages: tuple[str | Callable[[float], str], ...] = (
            "",
            lambda tilt: (f"the target orientation is tilted {tilt:.3g} rad away from a rotation about the "
                          f"joint axes' common direction {_vec(u)}; this arm can only turn its tool about "
                          f"that direction"),
            lambda h: (f"the travel along {_vec(u)} ({h:.6g} m) is outside what the prismatic joints reach "
                       f"within their limits"),
            lambda d: (f"out of reach in the plane: the point is {d:.6g} m from the first axis, the arm "
                       f"reaches {abs(la - lb):.6g} to {la + lb:.6g} m"),
            "the orientation about the common axis does not match the position (this arm has no wrist joint)",
            "solutions exist but violate the joint limits",
        )

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

    def _complex(self, x: np.ndarray) -> complex:
        """A point (3,) in the plane normal to u as a complex number."""
        return complex(x @ self.e1, x @ self.e2)


def _vec(v: np.ndarray) -> str:
    return "(" + ", ".join(f"{x:.6g}" for x in v + 0.0) + ")"
