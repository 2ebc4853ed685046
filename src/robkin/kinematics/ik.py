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

import math
from dataclasses import dataclass, replace
from functools import lru_cache
from typing import Any, Mapping

import numpy as np
from numpy.typing import ArrayLike

from ..checks import check_threads
from ..errors import InputError
from ..robot import Robot
from .closed_form import closed_form_solver
from .ik_methods import SAME_SOLUTION_TOL, closed_form_batch, numeric_batch, preferred_starts
from .lm import LMSettings
from .pose_error import FULL_POSE, check_mask, check_targets

__all__ = ["IKResult", "ik", "single_closed_form", "METHODS"]

METHODS = ("auto", "analytic", "numeric")

#: Defaults of ``ik``: 1e-9 (length units, radians) is ~1e6 times the rounding of a closed-form solve
#: and what the numeric method reliably reaches; 40 iterations per attempt and 200 restarts (see
#: ``LMSettings.restarts``).
_TOL = 1e-9
_MAX_ITERATIONS = 40
_RESTARTS = 200


@dataclass(frozen=True)
class IKResult:
    """Outcome of :func:`ik`. Scalars for one target, arrays over targets (leading N) for a batch.

    Attributes
    ----------
    q : (n,) or (N, n) array
        The solution nearest to ``q0`` where ``success``. Where not: for the numeric method the best
        configuration found (smallest residual), for the closed form NaN (no configuration exists).
    success : bool or (N,) bool array
        Reached to the tolerances over the masked components, with every joint within limits.
    iterations : int or (N,) int array
        Levenberg-Marquardt iterations over all attempts (0 for the closed form).
    attempts : int or (N,) int array
        Starts used: 1 + random restarts, including those run side by side (1 for the closed form).
    position_error : float or (N,) array
        |p_d - p| over the masked x, y, z components (length units; inf where q is NaN).
    orientation_error : float or (N,) array
        |log(R_d R^T)| over the masked components (radians; inf where q is NaN).
    method : str
        'scara', 'spherical-wrist-6r', 'three-parallel-6r', 'near-spherical-wrist-6r',
        'near-three-parallel-6r', 'pieper-6r', 'pieper-6r-reversed', 'general-6r', 'srs-arm-angle' (closed forms; targets the closed form could not settle
        are retried numerically in 'auto') or 'numeric'.
    message : str or list of str
        Why a target failed ('' where it succeeded).
    solutions : (S, n) array, list of (S_i, n) arrays, or None
        With ``all_solutions=True``: every distinct solution found, nearest to q0 first.
    """

    q: np.ndarray
    success: np.ndarray | bool
    iterations: np.ndarray | int
    attempts: np.ndarray | int
    position_error: np.ndarray | float
    orientation_error: np.ndarray | float
    method: str
    message: list[str] | str
    solutions: list[np.ndarray] | np.ndarray | None = None

    @classmethod
    def _build(cls, **fields: Any) -> "IKResult":
        """The result from every field, without the frozen dataclass's ``__init__`` (one guarded
        ``object.__setattr__`` per field: ~2.5 us, as much as the closed-form kernel of one target).
        Frozen all the same: attribute assignment still raises."""
        result = object.__new__(cls)
        result.__dict__.update(fields)
        return result

    def __str__(self) -> str:
        """One row per target (success, errors, q), or per solution for one target with solutions."""
        from ..io.tables.text import blocks_text
        from .ik_text import ik_result_blocks

        return blocks_text(ik_result_blocks(self))

    def to_dict(self) -> dict[str, Any]:
        """Every field as plain lists and numbers (JSON-ready; see ``robkin.io.files.jsontext``)."""
        from dataclasses import fields

        from ..io.files.jsontext import plain

        return {f.name: plain(getattr(self, f.name)) for f in fields(self)}


def ik(robot: Robot, T: ArrayLike, *, q0: ArrayLike | None = None, mask: str | ArrayLike | None = None,
       method: str = "auto", all_solutions: bool = False, tol_position: float = _TOL,
       tol_orientation: float = _TOL, max_iterations: int = _MAX_ITERATIONS, restarts: int = _RESTARTS,
       rng: np.random.Generator | int | None = 0, threads: int | None = None,
       lock: Mapping[str, float] | None = None, arm_angle: ArrayLike | None = None) -> IKResult:
    """Joint values that put the tool at T.

    Parameters
    ----------
    robot : Robot
    T : (4, 4) or (N, 4, 4) array
        Target tool poses in the robot base frame.
    q0 : (n,) or (N, n) array, optional
        Preferred configuration: the numeric start, and the tie-break among closed-form solutions
        (and for their free joints, e.g. the SCARA's redundant vertical pair). Default: zero, clipped
        into the limits.
    mask : 'pose' (default), 'position', or 6 values 0/1 for (x, y, z, rx, ry, rz)
        Residual components that must match (base frame). Anything but the full pose is numeric.
    method : 'auto', 'analytic' or 'numeric'
    all_solutions : bool
        Also return every distinct solution: all closed-form branches, or for the numeric method the
        distinct solutions reached from 1 + ``restarts`` starts run side by side (not guaranteed to
        be all of them).
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

    Returns
    -------
    IKResult
    """
    if arm_angle is not None:
        from .srs import ik_arm_angle

        return ik_arm_angle(robot, T, arm_angle, q0, all_solutions, tol_position, tol_orientation, mask=mask,
                            method=method, lock=lock)
    if lock:
        from .lock import ik_locked

        return ik_locked(ik, robot, T, lock, q0, mask=mask, method=method, all_solutions=all_solutions,
                         tol_position=tol_position, tol_orientation=tol_orientation,
                         max_iterations=max_iterations, restarts=restarts, rng=rng, threads=threads)
    if q0 is None:
        one = single_closed_form(robot, T, mask, method, all_solutions, tol_position, tol_orientation,
                                 max_iterations, restarts)
        if one is not None:
            return one
    targets, single = check_targets(T)
    N = len(targets)
    m = check_mask(mask)
    if method not in METHODS:
        raise InputError(f"method: '{method}' is not one of {', '.join(METHODS)}")
    q_ref = preferred_starts(robot, q0, N)
    try:
        # the defaults themselves (identity: cheap, and safe for arrays) skip even the cache's hashing
        settings = _DEFAULT_SETTINGS if tol_position is _TOL and tol_orientation is _TOL and \
            max_iterations is _MAX_ITERATIONS and restarts is _RESTARTS else \
            _settings(tol_position, tol_orientation, max_iterations, restarts)
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
            return one

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
    return IKResult._build(
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


def single_closed_form(robot: Robot, T: Any, mask: Any, method: str, all_solutions: bool, tol_position: Any,
                       tol_orientation: Any, max_iterations: Any, restarts: Any, q_ref: np.ndarray | None = None,
                       embed: tuple[np.ndarray, np.ndarray] | None = None) -> IKResult | None:
    """The single-target path of ``ik``: one compiled call checks the target (a float64 4x4 exact pose)
    and the tolerances (floats), solves, verifies and picks, and one small result is built. Anything
    else - a batch, other input kinds or settings, a failure (for its reasons and the numeric retry) -
    gives None, and the general path of ``ik`` gives the same answer. ``q_ref``: the preference (n,),
    already checked and clipped into the limits (as ``ik_methods.preferred_starts`` does), else the
    default. ``embed``: the robot is a longer arm's reduced one (``kinematics.lock``), the answer is made
    full length in the same call."""
    if mask is None and (method == "auto" or method == "analytic") \
            and max_iterations is _MAX_ITERATIONS and restarts is _RESTARTS:    # else: checked by ik
        solver = closed_form_solver(robot)
        if solver is not None:
            return solver.nearest(T, q_ref, tol_position, tol_orientation, all_solutions, SAME_SOLUTION_TOL,
                                  IKResult, solver.name, embed)
    return None


@lru_cache(maxsize=64)
def _settings(tol_position: float, tol_orientation: float, max_iterations: int, restarts: int) -> LMSettings:
    """Checked solver settings, cached: building the frozen dataclass costs as much as a closed-form
    solve, and callers repeat the same few values."""
    for name, v in (("tol_position", tol_position), ("tol_orientation", tol_orientation)):
        try:
            usable = math.isfinite(v) and v > 0
        except TypeError:
            usable = False
        if not usable:
            raise InputError(f"{name}: must be a positive number, got {v}")
    if int(max_iterations) < 1 or int(restarts) < 0:
        raise InputError(f"max_iterations must be >= 1 and restarts >= 0, got {max_iterations}, {restarts}")
    return LMSettings(tol_position=float(tol_position), tol_orientation=float(tol_orientation),
                      max_iterations=int(max_iterations), restarts=int(restarts))


_DEFAULT_SETTINGS = _settings(_TOL, _TOL, _MAX_ITERATIONS, _RESTARTS)
