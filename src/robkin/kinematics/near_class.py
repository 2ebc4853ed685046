"""Arms within calibration error of a closed-form class: the class's closed form, polished.

A calibrated Universal Robots arm (or a URDF typed with 1.5708 for pi/2) is not exactly of its class:
its axes 2-4 are parallel only to ~1e-6, so the exact detectors (``analytic6r``, tolerance 1e-9) refuse
it. ``NearClass.detect`` snaps such an arm onto its *ideal* arm - nearly parallel axes made parallel,
nearly meeting axes made to meet, each joint frame moved as little as possible, the tool frame kept -
and takes that arm's closed form when the snap moved nothing by more than ``NEAR_TOL`` (relative to
the robot's size for lengths, radians for angles). Every branch of the ideal arm is then polished by
Newton steps on the real arm's exact forward kinematics (``compiled.ik.polish_branches.polish``)
and verified on the real arm like every closed-form answer.

The solutions are the class's branches carried over to the real arm (up to 8). A perturbed arm is a
general 6R in principle, and may have further real solutions far from those branches (the other roots
of its degree-16 polynomial come in from infinity); ``General6R`` would find them at ~5x the cost.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..compiled.ik.solutions import nearest_verified
from ..lines import closest_points
from ..robot import Robot
from .kernel_solver import Branches, KernelSolver, embedded
from .limits import LIMIT_TOL

__all__ = ["NearClass", "NEAR_TOL"]

#: How far (radians; lengths relative to the robot's size) an arm may be from a class to be solved by
#: its closed form and polished: 1e-4 covers calibrated arms (identified offsets ~0.1 mm, ~1e-4 rad)
#: and tables typed with 4-5 digits, and keeps the ideal branches within the Newton polish's quadratic
#: convergence (1e-4 -> 1e-8 -> 1e-16 in two steps).
NEAR_TOL = 1e-4


def _turn_frame(frame: np.ndarray, z_new: np.ndarray) -> np.ndarray:
    """The frame (4, 4) turned by the smallest rotation that carries its z axis onto unit z_new."""
    z = frame[:3, 2]
    v = np.cross(z, z_new)
    s, c = np.linalg.norm(v), float(z @ z_new)
    out = frame.copy()
    if s > 0.0:
        k = v / s
        K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
        R = np.eye(3) + s * K + (1 - c) * K @ K
        out[:3, :3] = R @ frame[:3, :3]
    return out


def _parallel(frames: np.ndarray, ref: int, others: tuple[int, ...]) -> float:
    """Make the axes of ``others`` parallel to axis ``ref`` (in place); the largest angle moved."""
    u = frames[ref, :3, 2]
    moved = 0.0
    for i in others:
        z = frames[i, :3, 2]
        target = u if z @ u >= 0 else -u
        moved = max(moved, float(np.linalg.norm(np.cross(z, target))))
        frames[i] = _turn_frame(frames[i], target)
    return moved


def _meet(frames: np.ndarray, axes: tuple[int, ...]) -> float:
    """Move the axes (two or three) to pass through one point (in place): the midpoint of the common
    normal of the first two; returns the largest distance an axis moved (inf when the first two are
    within 1e-3 rad of parallel: their meeting point is then ill-defined, and no class has them so)."""
    i, j = axes[0], axes[1]
    if np.linalg.norm(np.cross(frames[i, :3, 2], frames[j, :3, 2])) < 1e-3:   # (nearly) parallel: no
        return np.inf                                                          # meeting point to snap to
    cn = closest_points(frames[i, :3, 3], frames[i, :3, 2], frames[j, :3, 3], frames[j, :3, 2])
    w = 0.5 * (cn.c1 + cn.c2)
    moved = 0.0
    for k in axes:
        z, p = frames[k, :3, 2], frames[k, :3, 3]
        d = (w - p) - ((w - p) @ z) * z            # from the axis to w, normal to it
        moved = max(moved, float(np.linalg.norm(d)))
        frames[k, :3, 3] = p + d
    return moved


class NearClass(KernelSolver):
    """A class's closed form on the ideal arm, polished on the real one (see the module docstring)."""

    def __init__(self, robot: Robot, ideal: KernelSolver) -> None:
        self.robot, self.ideal = robot, ideal
        self.name = "near-" + ideal.name
        self.messages = ideal.messages
        self.nearest = self._nearest            # type: ignore[assignment]

    @classmethod
    def detect(cls, robot: Robot) -> "NearClass | None":
        """The solver if the robot is 6R and within ``NEAR_TOL`` of a spherical-wrist or
        three-parallel arm (but not exactly one: the exact detectors come first), else None."""
        if robot.n != 6 or not robot.revolute.all():
            return None
        from .analytic6r import SphericalWrist6R, ThreeParallel6R

        tol_len = NEAR_TOL * robot.scale
        for snap, klass in ((lambda F: (_parallel(F, 1, (2,)), _meet(F, (3, 4, 5))), SphericalWrist6R),
                            (lambda F: (_parallel(F, 1, (2, 3)), _meet(F, (4, 5))), ThreeParallel6R)):
            frames = np.array(robot.frames)
            angle, length = snap(frames)
            if angle > NEAR_TOL or length > tol_len:
                continue
            ideal = robot.replace(frames=frames)
            solver = klass.detect(ideal)
            if solver is not None:
                return cls(robot, solver)
        return None

    def solve(self, targets: np.ndarray, q_ref: np.ndarray, threads: int = 0) -> Branches:
        """The ideal arm's branches (N, 8, 6), polished on the real arm (invalid where they do not
        converge; limits and the FK check are the caller's, on the real arm)."""
        from ..compiled.ik.polish_branches import polish

        b = self.ideal.solve(targets, q_ref, threads)
        Q = np.ascontiguousarray(b.q)
        # every finite branch, not only the ideal arm's valid ones: at a reach boundary (a stretched
        # elbow) the real arm may reach where the ideal one misses by ~1e-6, and the ideal kernel's
        # clamped branch then polishes onto the real solution; the check on the real arm decides
        valid = np.isfinite(Q).all(axis=-1)
        polish(self.robot._chain, Q, valid, targets, self.robot.scale, threads)
        return Branches(Q, valid, b.reason, b.uncertain)

    def _nearest(self, target: Any, q_ref: np.ndarray | None, tol_position: Any, tol_orientation: Any,
                 every: bool, same_tol: float, result_type: type, method: str,
                 embed: tuple[np.ndarray, np.ndarray] | None = None) -> Any:
        """One target: the finished result, or None (the caller's general path then decides); with
        ``embed`` full length, as the compiled kernels' ``nearest``."""
        if not (isinstance(target, np.ndarray) and target.shape == (4, 4) and isinstance(tol_position, float)
                and isinstance(tol_orientation, float)):
            return None
        robot = self.robot
        ref = (np.zeros(6) if q_ref is None else np.asarray(q_ref, dtype=float)).reshape(1, 6)
        if q_ref is None:
            from .limits import default_preference
            ref = default_preference(robot.limits)[None]
        T = np.ascontiguousarray(target, dtype=float)[None]
        b = self.solve(T, ref)
        q, ok, sols, ep, eo, failed = nearest_verified(robot._chain, b.q, b.valid, T, ref, robot.limits,
                                                       robot.scale, tol_position, tol_orientation, LIMIT_TOL,
                                                       every, same_tol)
        if failed:
            return None
        q, sols = q[0], sols[0] if every else None
        if embed is not None:
            q, sols = embedded(q, embed), None if sols is None else embedded(sols, embed)
        return result_type._build(q=q, success=True, iterations=0, attempts=1,
                                  position_error=float(ep[0]), orientation_error=float(eo[0]), method=method,
                                  message="", solutions=sols)
