"""Levenberg-Marquardt inverse kinematics: the Python side of the compiled solver (``compiled.ik.lm``).

Each target is solved by one compiled loop (residual, Jacobian, damped step, limits, restarts) with no
Python per iteration; a batch loops over its targets in C. This module holds the tuning
(``LMSettings``), prepares limits and restart ranges, and returns an ``LMOutcome``.

Method (Madsen, Nielsen & Tingleff, *Methods for non-linear least squares problems*, 2004, sec. 3.2):
minimise E(q) = 1/2 |W e(q)|^2, with e the base-frame pose residual (position scaled by the robot's
size so that the problem is unit-free, orientation a rotation vector) and W the component mask. A
step h solves (J^T J + mu I) h = J^T e with J the geometric Jacobian; it is accepted when E falls,
and mu follows the gain ratio of actual to predicted decrease (Nielsen's update). The step is in
unit-free joint variables (radians, and robot sizes for prismatic joints), so the solver iterates the
same whatever length unit the robot is written in.

Joint limits: a joint already on a limit and pushed past it is frozen for that step and the step is
solved again without it; the trial is then projected onto the limits (revolute joints whose range
spans a full turn are turned back by 2 pi instead, which changes no pose). The predicted decrease is
that of the step actually taken, so the gain ratio stays honest at the limits.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np

from ..compiled.ik.lm import solve
from ..robot import Robot

__all__ = ["LMSettings", "LMOutcome", "solve_lm"]


@dataclass(frozen=True)
class LMSettings:
    """Tuning of the solver (defaults chosen on UR5, Panda, KR16-type arms; see benchmarks/).

    Attributes
    ----------
    tol_position : float
        Converged when the masked position error is below this (length units).
    tol_orientation : float
        Converged when the masked orientation error is below this (radians).
    max_iterations : int
        Iterations per attempt before a restart.
    restarts : int
        Random restarts after the first attempt.
    """

    tol_position: float = 1e-9
    tol_orientation: float = 1e-9
    max_iterations: int = 40
    #: 200: on random 6R/7R arms with 20 % near-limit and near-singular targets, 50 restarts solved
    #: 98.9 %, 100 restarts 99.8 % and 200 restarts 99.9 % (10 x 1000 targets,
    #: benchmarks/bench_ik_success.py); a solvable target almost always converges within the first
    #: few attempts, so the median time does not change, and an unreachable one costs ~4x more
    restarts: int = 200
    #: initial damping relative to the largest diagonal entry of J^T J (Madsen et al. suggest 1e-6 to
    #: 1 depending on how good the start is). 0.1 measured best end to end: iterations per solved
    #: target on UR5 / Panda / KR16-type arms 20 / 31 / 31, against 21 / 45 / 37 at 1e-3 and
    #: 21 / 38 / 35 at 1 (2000 random reachable targets each)
    tau: float = 0.1
    #: damping above this (relative to max diag of J^T J) means the model no longer predicts any
    #: decrease: the attempt is stuck (at a local minimum or against the limits) and restarts
    mu_stuck: float = 1e8
    #: an attempt that improved E by less than this fraction over the last ``stall_window``
    #: iterations is stalled; 1e-3 over 8 iterations is far slower than LM's linear convergence on
    #: any reachable target (each step gains orders of magnitude near a solution)
    stall_ratio: float = 1e-3
    stall_window: int = 8
    #: Attempts that are going nowhere are given up early and restarted. Two checks, chosen on
    #: recorded runs (UR5, Panda, KR16-type arms from random starts: iterations spent per solved
    #: target 22/88/57 with no early stop, 18/33/24 with these): after ``limit_check_iteration``
    #: iterations, still far (E = |W e|^2 / 2 above ``limit_check_E``: an error above ~14 % of the
    #: robot's size or ~0.14 rad) with a joint against a limit - where almost every failing attempt
    #: ends; after ``check_iteration``, not close (E above ``check_E``, ~0.45 % or ~0.0045 rad) - LM
    #: converges fast once near, so converging attempts are almost all closer by then. Both apply to
    #: a target's first half of attempts only; later ones run their full course.
    limit_check_iteration: int = 5
    limit_check_E: float = 1e-2
    check_iteration: int = 15
    check_E: float = 1e-5
    #: threads for a batch of targets: 0 automatic (``robkin.threads``), else at most that many; a
    #: target's answer does not depend on it (each target's restarts have their own random stream)
    threads: int = 0


@dataclass
class LMOutcome:
    """Per-target outcome of :func:`solve_lm` (arrays over the N targets)."""

    q: np.ndarray                  # (N, n) converged or best configuration found, turned into the limits
    success: np.ndarray            # (N,) bool, verified by forward kinematics (tolerances and limits)
    iterations: np.ndarray         # (N,) int, total over all attempts
    attempts: np.ndarray           # (N,) int, 1 + restarts used
    position_error: np.ndarray     # (N,) masked |p_d - p| of q (length units)
    orientation_error: np.ndarray  # (N,) masked |log(R_d R^T)| of q (radians)


def solve_lm(robot: Robot, targets: np.ndarray, q0: np.ndarray, mask: np.ndarray,
             settings: LMSettings, seed: int, ref: np.ndarray | None = None) -> LMOutcome:
    """Solve IK for targets (N, 4, 4) from starts q0 (N, n), one compiled loop per target, and check
    every answer.

    The whole of a target is compiled and runs without the GIL, split over threads for a batch: the
    attempts, then the answer's revolute joints turned by whole turns into the limits nearest ``ref``
    (``kinematics.limits.wrap_into_limits``), then an independent forward kinematics (the walk of
    ``Robot.fk``) measuring the masked errors: a target succeeds when they are within the tolerances
    and every joint within its limits.

    A stuck attempt restarts from a new configuration within the limits (unlimited revolute joints
    over +-pi, unlimited prismatic ones over +-scale, the robot's size: any reach of interest lies
    within it), up to ``settings.restarts`` times. The restarts walk the R_d low-discrepancy sequence
    (``robkin.samples``) from a random shift per target, so they cover the box of the limits evenly,
    its corners and edges included.

    Parameters
    ----------
    robot : Robot
    targets : (N, 4, 4) array
        Tool poses in the robot base frame, rotations exactly orthonormal.
    q0 : (N, n) or (1, n) array
        First-attempt starts (clipped into the limits); one row serves every target.
    mask : (6,) array of 0/1
        Residual components (x, y, z, rx, ry, rz) that count.
    settings : LMSettings
    seed : int
        64-bit seed of the random restarts: target k's come from a stream seeded by it and k (the
        same answers for a target whatever else is in the batch, for the same seed and position).
    ref : (N, n) or (1, n) array, optional
        Preferred turns of the revolute joints (default q0).

    Returns
    -------
    LMOutcome
    """
    lo, hi, rlo, rhi = _ranges(robot)
    return LMOutcome(*solve(robot._chain, targets, q0, mask, lo, hi, rlo, rhi, robot.scale, settings, seed,
                            settings.threads, ref))


#: per robot: limits and restart ranges (computed once; a single-target solve costs ~10 us)
_RANGES: "weakref.WeakKeyDictionary[Robot, tuple[np.ndarray, ...]]" = weakref.WeakKeyDictionary()


def _ranges(robot: Robot) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Lower and upper limits (n,) and the restart range (n,) each: within the limits, unlimited
    revolute joints over +-pi, unlimited prismatic ones over +-scale (the robot's size)."""
    found = _RANGES.get(robot)
    if found is None:
        lo, hi = robot.limits[:, 0], robot.limits[:, 1]
        span = np.where(robot.revolute, np.pi, robot.scale)
        found = (lo, hi, np.where(np.isfinite(lo), lo, -span), np.where(np.isfinite(hi), hi, span))
        _RANGES[robot] = found
    return found
