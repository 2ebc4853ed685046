"""Inverse kinematics: closed form where the geometry allows, vectorised Levenberg-Marquardt otherwise.

``ik(robot, T)`` takes one target (4, 4) or a batch (N, 4, 4) of tool poses in the robot base frame
and returns an :class:`IKResult`. Every answer is checked by an independent forward kinematics
(``Robot.fk``) before it is called a success: ``success`` is True only if the pose is reached to
``tol_position`` (length units) and ``tol_orientation`` (radians) over the masked components, with
every joint within its limits.

Methods:

- ``'analytic'``: closed-form, all solutions (``kinematics.scara`` for SCARA-type arms,
  ``kinematics.analytic6r`` for 6R arms with parallel axes 2, 3 and a spherical wrist, and for 6R
  arms of the Universal Robots type: axes 2, 3, 4 parallel, axes 5, 6 meeting;
  ``kinematics.near_class`` for arms within calibration error of those two; ``kinematics.pieper``
  for 6R arms with three meeting axes at the wrist or the base; ``kinematics.general6r`` for every
  other revolute 6R arm, up to 16 solutions; docs/ik.md lists the conditions). Full poses only.
- ``arm_angle=psi`` (SRS arms: 7R, spherical shoulder and wrist): ``kinematics.srs``, every solution at that
  arm angle, ``q`` on ``q0``'s branch; method 'srs-arm-angle'.
- ``'numeric'``: damped least squares / Levenberg-Marquardt (``kinematics.lm``) with joint limits,
  masks and random restarts, vectorised across targets.
- ``'auto'`` (default): the closed form when one fits the robot and the mask is the full pose, else
  numeric; targets whose closed-form branches fail the forward-kinematics check, or that sit on a
  singularity where the closed form could not settle a free joint, are retried numerically.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Mapping

import numpy as np
from numpy.typing import ArrayLike

from ..checks import check_threads
from ..errors import InputError
from ..robot import Robot
from .closed_form import closed_form_solver
from .ik_methods import (SAME_SOLUTION_TOL, BranchSource, closed_form_batch, numeric_batch, preferred_starts,
                         single_closed_form)
from .ik_result import (DEFAULT_MAX_ITERATIONS, DEFAULT_RESTARTS, DEFAULT_SETTINGS, DEFAULT_TOL, METHODS, IKResult,
                        settings as checked_settings)
from .pose_error import FULL_POSE, check_mask, check_targets

__all__ = ["IKResult", "ik", "single_closed_form", "METHODS"]

def ik(robot: Robot, T: ArrayLike, *, q0: ArrayLike | None = None, mask: str | ArrayLike | None = None,
       method: str = "auto", all_solutions: bool = False, tol_position: float = DEFAULT_TOL,
       tol_orientation: float = DEFAULT_TOL, max_iterations: int = DEFAULT_MAX_ITERATIONS, restarts: int = DEFAULT_RESTARTS,
       rng: np.random.Generator | int | None = 0, threads: int | None = None,
       lock: Mapping[str, float] | None = None, arm_angle: ArrayLike | None = None,
       avoid_self_collision: bool = False) -> IKResult:
    """Joint values that put the tool at T.

    Parameters
    ----------
    robot : Robot
    T : (4, 4) or (N, 4, 4) array
        Target tool poses in the robot base frame.
    q0 : (n,) or (N, n) array, optional
        Preferred configuration, the start: the numeric solver's first attempt starts there, and the
        answer ``q`` is the solution nearest to it among those found (every closed-form branch; for the
        numeric method the first success, and with ``all_solutions`` every one found), as are free
        joints (e.g. the SCARA's redundant vertical pair). Given values are clipped into the limits.
        Default: inside every joint's limits, zero where zero is within a joint's range, else the
        midpoint of its range (``kinematics.limits.default_preference``; docs/ik.md).
    mask : 'pose' (default), 'position', or 6 values 0/1 for (x, y, z, rx, ry, rz)
        Residual components that must match (base frame). Anything but the full pose is numeric.
    method : 'auto', 'analytic' or 'numeric'
    all_solutions : bool
        Also return every distinct solution, nearest to ``q0`` first: all closed-form branches (one row
        per branch; rows closer than ``SAME_SOLUTION_TOL`` in every joint are one), or for the numeric
        method the distinct solutions reached from 1 + ``restarts`` starts run side by side (not
        guaranteed to be all of them). Where the solutions form a continuum (a redundant target: more
        joints than matched pose components, e.g. a 7-joint arm at a full pose) the numeric rows are
        kept spaced: each differs from every row before it by more than ``REDUNDANT_SPACING`` (0.5 rad)
        in some revolute joint or ``REDUNDANT_SPACING_LENGTH`` (0.1) times the robot's size in some
        prismatic joint.
    tol_position : float
        Length units (metres for metre robots).
    tol_orientation : float
        Radians.
    max_iterations : int
        Numeric: iterations per attempt before a random restart.
    restarts : int
        Numeric: random restarts per target after the first attempt.
    rng : Generator, int seed or None
        Source of random restarts; the default seed 0 makes results reproducible.
    threads : int, optional
        Batches (numeric and closed form): at most that many threads (default automatic, see
        ``robkin.threads``); the answers are the same bits whatever it is.
    lock : mapping of joint name to value, optional
        Joints held at these values (radians or length units, within the limits): the rest is solved as
        a shorter arm (``kinematics.lock``; a 7-joint arm with one joint locked gets a 6R closed form).
        Every method works with it; q, q0 and the solutions stay full length, the locked values in place.
    arm_angle : float or (N,) array, optional
        SRS arms (iiwa, ideal Gen3): the elbow's swivel angle (radians) about the shoulder-wrist line; every
        solution at that angle, q on q0's branch (``kinematics.srs``, docs/ik.md). Not with lock or mask.
    avoid_self_collision : bool
        Only solutions free of self collision (``robkin.self_collision.ik``: colliding branches dropped,
        numeric retries from collision-free starts; the model is ``self_collision_model``'s, docs/collision.md).

    Returns
    -------
    IKResult
    """
    if avoid_self_collision:
        from ..self_collision.ik import collision_free_ik

        return collision_free_ik(ik, robot, T, q0=q0, mask=mask, method=method, all_solutions=all_solutions,
                                 tol_position=tol_position, tol_orientation=tol_orientation,
                                 max_iterations=max_iterations, restarts=restarts, rng=rng, threads=threads,
                                 lock=lock, arm_angle=arm_angle, solve=solve_with_branches)
    if q0 is None and arm_angle is None and not lock:   # one target, the closed form: its one compiled call
        one = single_closed_form(robot, T, mask, method, all_solutions, tol_position, tol_orientation,
                                 max_iterations, restarts)
        if one is not None:
            return one
    return solve_with_branches(robot, T, q0=q0, mask=mask, method=method, all_solutions=all_solutions,
                               tol_position=tol_position, tol_orientation=tol_orientation,
                               max_iterations=max_iterations, restarts=restarts, rng=rng, threads=threads, lock=lock,
                               arm_angle=arm_angle)[0]


def solve_with_branches(robot: Robot, T: ArrayLike, *, q0: ArrayLike | None = None, mask: str | ArrayLike | None = None,
                        method: str = "auto", all_solutions: bool = False, tol_position: float = DEFAULT_TOL,
                        tol_orientation: float = DEFAULT_TOL, max_iterations: int = DEFAULT_MAX_ITERATIONS,
                        restarts: int = DEFAULT_RESTARTS, rng: np.random.Generator | int | None = 0,
                        threads: int | None = None, lock: Mapping[str, float] | None = None,
                        arm_angle: ArrayLike | None = None) -> tuple[IKResult, BranchSource | None]:
    """``ik`` (without ``avoid_self_collision``; the same parameters), and the closed-form branches a batch
    was solved from (``ik_methods.BranchSource``: every solution of some of its targets again without a
    second solve, for ``self_collision.ik``), or None where the answer came another way (one target, a
    lock, an arm angle, the numeric method)."""
    if arm_angle is not None:
        from .srs import ik_arm_angle

        return ik_arm_angle(robot, T, arm_angle, q0, all_solutions, tol_position, tol_orientation, mask=mask,
                            method=method, lock=lock), None
    if lock:
        from .lock import ik_locked

        return ik_locked(ik, robot, T, lock, q0, mask=mask, method=method, all_solutions=all_solutions,
                         tol_position=tol_position, tol_orientation=tol_orientation,
                         max_iterations=max_iterations, restarts=restarts, rng=rng, threads=threads), None
    if q0 is None:
        one = single_closed_form(robot, T, mask, method, all_solutions, tol_position, tol_orientation,
                                 max_iterations, restarts)
        if one is not None:
            return one, None
    targets, single = check_targets(T)
    N = len(targets)
    m = check_mask(mask)
    if method not in METHODS:
        raise InputError(f"method: '{method}' is not one of {', '.join(METHODS)}")
    q_ref = preferred_starts(robot, q0, N)
    try:
        # the defaults themselves (identity: cheap, and safe for arrays) skip even the cache's hashing
        settings = DEFAULT_SETTINGS if tol_position is DEFAULT_TOL and tol_orientation is DEFAULT_TOL and \
            max_iterations is DEFAULT_MAX_ITERATIONS and restarts is DEFAULT_RESTARTS else \
            checked_settings(tol_position, tol_orientation, max_iterations, restarts)
    except TypeError:   # unhashable (a list, an array): not a number
        raise InputError(f"tol_position, tol_orientation, max_iterations, restarts: expected numbers, got "
                         f"{tol_position!r}, {tol_orientation!r}, {max_iterations!r}, {restarts!r}") from None
    if threads is not None:
        settings = replace(settings, threads=check_threads(threads))

    solver = None
    if method != "numeric":
        full_pose = m is FULL_POSE or bool(m.all())     # the identity test spares a reduction
        solver = closed_form_solver(robot) if full_pose else None
        if solver is None and method == "analytic":
            why = "the mask is not the full pose" if not full_pose else \
                ("no closed-form solver fits this robot (SCARA-type, or six revolute joints: lock joints of "
                 "a longer arm with lock=)")
            raise InputError(f"method 'analytic': {why}; use method 'numeric'")

    if solver is not None and single:
        # One target with a preference or a checked (projected) target: the same one compiled call.
        # Only a success is answered here; a failure takes the path below for its reasons and retry.
        one = solver.nearest(targets[0], q_ref[0], settings.tol_position, settings.tol_orientation,
                             all_solutions, SAME_SOLUTION_TOL, IKResult, solver.name)
        if one is not None:
            return one, None

    if solver is not None:
        out = closed_form_batch(robot, solver, targets, q_ref, settings, all_solutions)
        used = solver.name
        if method == "auto" and out.retry is not None:
            r = np.flatnonzero(out.retry)
            sub = numeric_batch(robot, targets[r], q_ref[r], m, settings, rng, all_solutions)
            out.q[r], out.success[r] = sub.q, sub.success
            out.errors[0][r], out.errors[1][r] = sub.errors
            out.iterations[r], out.attempts[r] = sub.iterations, sub.attempts
            for j, i in enumerate(r):
                out.reasons[i] = sub.reasons[j]
                if out.solutions is not None and sub.solutions is not None:  # all_solutions: both are lists
                    out.solutions[i] = sub.solutions[j]
    else:
        out = numeric_batch(robot, targets, q_ref, m, settings, rng, all_solutions)
        used = "numeric"

    # inf where q is NaN (no closed-form solution)
    ep, eo = out.errors
    sols, iters, attempts = out.solutions, out.iterations, out.attempts
    result = IKResult._build(
        q=out.q[0] if single else out.q,
        success=bool(out.success[0]) if single else out.success,
        iterations=int(iters[0]) if single else iters,
        attempts=int(attempts[0]) if single else attempts,
        position_error=float(ep[0]) if single else ep,
        orientation_error=float(eo[0]) if single else eo,
        method=used,
        message=out.reasons[0] if single else out.reasons,
        solutions=None if sols is None else (sols[0] if single else sols),
    )
    return result, out.source
