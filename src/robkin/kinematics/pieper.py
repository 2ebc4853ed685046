"""Closed-form IK of 6R arms with three consecutive axes meeting (Pieper's case), any other geometry.

``Pieper6R``: axes 4, 5, 6 meet (a spherical wrist) and joints 1-3 are anything - the case the general
elimination (``general6r``) degenerates on, and the shape of a 7-joint SRS arm (KUKA iiwa, Kinova Gen3)
with one joint locked. Up to 16 solutions (4 positions of the wrist centre x 2 wrists, the position
problem a degree-4 resultant); the steps are in ``robkin.compiled.ik.closed_form_pieper``. An arm whose
*first* three axes meet is solved as its reversed chain (base and tool swapped, joints in reverse
order: ``ReversedChain``), whose last three axes meet.

Detection checks the geometry (axes 4-6 meet to ``DETECT_LENGTH_TOL``; axes 4, 5 and 5, 6 not parallel)
and then that the kernel finds the generating configuration of a few random targets, as ``general6r``
does; otherwise the arm goes on to the general solver.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .. import se3
from ..lines import perpendicular
from ..robot import Robot
from .analytic6r import wrist_centre
from .kernel_solver import DETECT_ANGLE_TOL, DETECT_LENGTH_TOL, KernelSolver
from .limits import LIMIT_TOL, default_preference

__all__ = ["Pieper6R", "ReversedChain", "reversed_robot", "finds_trials"]

_TRIAL_TARGETS = 12
_FOUND_TOL = 1e-6


def finds_trials(robot: Robot, solver: Any, count: int = _TRIAL_TARGETS) -> int:
    """How many of ``count`` random configurations (within the limits, +-pi where unlimited) the solver
    finds among the branches of their own forward kinematics (a fixed seed: deterministic)."""
    rng = np.random.default_rng(20261125)
    lim = robot.limits
    lo = np.where(np.isfinite(lim[:, 0]), lim[:, 0], -np.pi)
    hi = np.where(np.isfinite(lim[:, 1]), lim[:, 1], np.pi)
    q = rng.uniform(lo, hi, (count, robot.n))
    b = solver.solve(robot.fk(q), q)
    return sum(bool(b.valid[k].any()) and float(np.abs(b.q[k][b.valid[k]] - q[k]).max(axis=1).min()) < _FOUND_TOL
               for k in range(count))


def reversed_robot(robot: Robot) -> Robot:
    """The chain read from the tool: base and tool swapped, joints in reverse order, so that its FK at
    q[::-1] is the inverse of the robot's FK at q. Joint k's frame is the original joint n+1-k's, in
    tool coordinates, turned half a turn about its x axis (the axis reversed makes the same angle turn
    the other way, as the inverse needs)."""
    M_inv = se3.inv(robot.tool)
    flip = np.diag([1.0, -1.0, -1.0, 1.0])
    frames = [M_inv @ F @ flip for F in robot.frames[-2::-1]] + [M_inv]
    return Robot(np.array(frames), tuple(reversed(robot.joints)), name=robot.name)


class ReversedChain(KernelSolver):
    """A solver of the reversed chain (``reversed_robot``) answering for the robot itself: targets
    inverted, preferences and branches reversed, inside the compiled kernel
    (``compiled.ik.closed_form_reversed``), which checks every branch on the robot's own chain."""

    def __init__(self, robot: Robot, inner: KernelSolver) -> None:
        from ..compiled.ik.closed_form_reversed import ReversedKernel

        self.robot, self.inner = robot, inner
        self.name = inner.name + "-reversed"
        self.messages = inner.messages
        self._use(ReversedKernel(robot._chain, robot.limits, robot.revolute, robot.scale, LIMIT_TOL,
                                 default_preference(robot.limits), inner._kernel))


class Pieper6R(KernelSolver):
    """All closed-form solutions of a 6R arm with a spherical wrist and any first three joints."""

    name = "pieper-6r"

    def __init__(self, robot: Robot, w0: np.ndarray) -> None:
        from ..compiled.ik.closed_form_pieper import PieperKernel

        z = robot.axes
        rng = np.random.default_rng(7)
        self._use(PieperKernel(robot._chain, robot.limits, default_preference(robot.limits), robot.scale, LIMIT_TOL,
                               robot._local, w0, robot.tool[:3, :3], z[3:], perpendicular(z[5]),
                               rng.uniform(-np.pi, np.pi, 2)))
        self.messages = (
            "",
            "no solution found: the resultant was ill-conditioned at this target (a singular configuration)",
            "out of reach: no real solution",
            "solutions exist but violate the joint limits",
        )

    @classmethod
    def _detect_one(cls, robot: Robot) -> "Pieper6R | None":
        z, c = robot.axes, robot.points
        sines = np.linalg.norm(np.cross(z[3:5], z[4:6]), axis=-1)
        if sines.min() <= DETECT_ANGLE_TOL:
            return None
        w0, miss = wrist_centre(c[3:], z[3:])
        if miss > DETECT_LENGTH_TOL * robot.scale:
            return None
        solver = cls(robot, w0)
        return solver if finds_trials(robot, solver) == _TRIAL_TARGETS else None

    @classmethod
    def detect(cls, robot: Robot) -> "KernelSolver | None":
        """A solver if the robot is 6R with axes 4-6 meeting, or axes 1-3 meeting (the reversed chain)."""
        if robot.n != 6 or not robot.revolute.all():
            return None
        found = cls._detect_one(robot)
        if found is not None:
            return found
        inner = cls._detect_one(reversed_robot(robot))
        return ReversedChain(robot, inner) if inner is not None else None
