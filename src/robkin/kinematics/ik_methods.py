"""The two methods of ``kinematics.ik`` on a batch of targets: verified closed-form branches and numeric
solutions, each one compiled pass over the targets (split over threads), and the preferred starts.

Both leave no per-target Python work on a success: the closed form's branch check and choice are
``compiled.ik.solutions.nearest_verified``; the numeric solve, the turn of each answer into the limits and
its forward-kinematics check are one compiled loop (``compiled.ik.lm.solve``). What stays in Python is per
batch (the arrays' checks, the result's assembly) or per failure (its message).
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..compiled.ik.lm import pose_errors
from ..compiled.ik.solutions import distinct_sorted, nearest_verified
from ..errors import InputError
from ..robot import Robot, check_q
from .closed_form import closed_form_solver
from .ik_result import DEFAULT_MAX_ITERATIONS, DEFAULT_RESTARTS, IKResult
from .kernel_solver import Branches, ClosedFormSolver
from .limits import LIMIT_TOL, default_preference
from .lm import LMSettings, solve_lm

__all__ = ["SAME_SOLUTION_TOL", "REDUNDANT_SPACING", "REDUNDANT_SPACING_LENGTH", "BranchSource", "closed_form_batch",
           "numeric_batch", "preferred_starts", "single_closed_form"]

#: Two solutions of one target are the same when no joint differs by more than this (radians, or
#: lengths relative to the robot's size): far above the ~1e-12 spread of one solution reached
#: along different branches or restarts, far below any real difference between branches.
SAME_SOLUTION_TOL = 1e-6

#: Numeric ``all_solutions`` of a redundant target (more joints than matched components: a 7-joint arm at a
#: full pose, any arm at a position-only mask) are a continuum, the self-motion manifold, and the restarts
#: land all along it. Of those, one is kept per neighbourhood: each solution kept (nearest to q0 first)
#: differs from every one kept before it by more than this in some revolute joint (radians: ~29 deg, a
#: visibly other posture) or more than REDUNDANT_SPACING_LENGTH * the robot's size in some prismatic joint.
#: (At SAME_SOLUTION_TOL the Panda's 201 restarts gave 83 rows, many a few milliradians apart.)
REDUNDANT_SPACING = 0.5
REDUNDANT_SPACING_LENGTH = 0.1


@dataclass
class _Found:
    """Internal per-batch outcome of one method."""

    q: np.ndarray                       # (N, n)
    success: np.ndarray                 # (N,) bool
    reasons: list[str]
    iterations: np.ndarray              # (N,) int
    attempts: np.ndarray                # (N,) int
    solutions: list[np.ndarray] | None  # per target (S_i, n), with all_solutions
    retry: np.ndarray | None            # (N,) bool: closed-form trouble, worth a numeric try (None: none)
    errors: tuple[np.ndarray, np.ndarray]       # (N,) position, orientation errors of q (inf where NaN)
    source: BranchSource | None = None  # the closed-form branches the batch was solved from


@dataclass(frozen=True)
class BranchSource:
    """The closed-form branches a batch of targets was solved from (``closed_form_batch``): every verified
    solution of some of its targets again, without solving them a second time (``solutions``)."""

    robot: Robot
    branches: Branches
    targets: np.ndarray      # (N, 4, 4)
    q_ref: np.ndarray        # (N, n), the preferences
    settings: LMSettings
    #: (N,) bool: the targets whose branches failed the check and were retried numerically (their closed-form
    #: list may lack the answer)
    retried: np.ndarray

    def solutions(self, rows: np.ndarray) -> list[np.ndarray]:
        """Every distinct verified solution (S_i, n) of the targets ``rows`` (indices into the batch), nearest
        the preference first: as ``ik(..., all_solutions=True)`` lists a closed form's, from the same
        branches (``compiled.ik.solutions.nearest_verified``)."""
        s, b = self.settings, self.branches
        sols = nearest_verified(self.robot._chain, b.q[rows], b.valid[rows], self.targets[rows], self.q_ref[rows],
                                self.robot.limits, self.robot.scale, s.tol_position, s.tol_orientation, LIMIT_TOL,
                                True, SAME_SOLUTION_TOL, s.threads)[2]
        return list(sols)


def _generator(rng: np.random.Generator | int | None) -> np.random.Generator:
    """A numpy Generator from a Generator, an int seed or None (fresh entropy)."""
    try:
        return rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
    except (TypeError, ValueError) as e:
        raise InputError(f"rng: expected a numpy Generator, a non-negative int seed or None ({e})") from None


def _seed(rng: np.random.Generator | int | None) -> int:
    """One 64-bit seed for the compiled solver's restart streams. An int seed is used as it is (no
    Generator built: that costs ~10 us, as much as solving an easy target)."""
    if isinstance(rng, (int, np.integer)) and not isinstance(rng, bool) and rng >= 0:
        return int(rng) & 0xFFFFFFFFFFFFFFFF
    return int(_generator(rng).integers(0, 2**63))


#: per Robot (immutable), zero clipped into its limits (1, n): the default preference, built once
_ZERO_STARTS: "weakref.WeakKeyDictionary[Robot, np.ndarray]" = weakref.WeakKeyDictionary()


def preferred_starts(robot: Robot, q0: ArrayLike | None, N: int) -> np.ndarray:
    """Preferred configurations (N, n), clipped into the limits (read-only when q0 is None)."""
    lim = robot.limits
    if q0 is None:
        zero = _ZERO_STARTS.get(robot)
        if zero is None:
            zero = default_preference(lim)[None]
            zero.setflags(write=False)
            _ZERO_STARTS[robot] = zero
        return zero if N == 1 else np.broadcast_to(zero, (N, robot.n))
    Q = check_q(q0, robot.n)
    if Q.ndim == 1:
        Q = Q[None] if N == 1 else np.broadcast_to(Q, (N, robot.n))
    elif Q.shape[0] != N:
        raise InputError(f"q0: expected shape ({robot.n},) or ({N}, {robot.n}) for {N} targets, "
                         f"got {Q.shape}")
    return clipped_into_limits(robot, Q)


def clipped_into_limits(robot: Robot, Q: np.ndarray) -> np.ndarray:
    """Checked configurations Q (..., n) clipped into the robot's limits (a new array)."""
    lim = robot.limits
    return np.minimum(np.maximum(Q, lim[:, 0]), lim[:, 1])     # np.clip, without its wrapper cost


def _joint_scale(robot: Robot) -> np.ndarray:
    """Per-joint unit for comparing solutions: 1 rad for revolute, the robot size for prismatic."""
    return np.where(robot.revolute, 1.0, robot.scale)


def closed_form_batch(robot: Robot, solver: ClosedFormSolver, targets: np.ndarray, q_ref: np.ndarray,
                      settings: LMSettings, all_solutions: bool) -> _Found:
    """Verified closed-form solutions: the one nearest q_ref (N, n) per target (N, 4, 4), and all if asked.

    The branches (``solver.solve``), their forward-kinematics check, the choice of the nearest and (for
    all_solutions) the distinct verified branches per target are compiled passes split over
    ``settings.threads`` (``compiled.ik.solutions.nearest_verified``); the answers do not depend on it.
    """
    N = len(q_ref)
    branches = solver.solve(targets, q_ref, settings.threads)
    q, success, sols, ep, eo, n_failed = nearest_verified(
        robot._chain, branches.q, branches.valid, targets, q_ref, robot.limits, robot.scale,
        settings.tol_position, settings.tol_orientation, LIMIT_TOL, all_solutions, SAME_SOLUTION_TOL,
        settings.threads)
    reasons = branches.reason       # the solver's own list, fresh per call: ours to amend
    retry = None
    if n_failed:
        failed = ~success
        retry = failed & branches.valid.any(axis=1)
        for i in np.flatnonzero(retry):
            reasons[i] = "closed-form solutions failed the forward-kinematics check (near a singularity)"
        if branches.uncertain is not None:
            retry |= failed & branches.uncertain
        if not retry.any():
            retry = None
    iterations = np.zeros(N, int)     # no iterations, one attempt (np.ones costs 4x np.zeros + 1)
    source = BranchSource(robot, branches, targets, q_ref, settings,
                          np.zeros(N, dtype=bool) if retry is None else retry)
    return _Found(q, success, reasons, iterations, iterations + 1, sols, retry, (ep, eo), source)


def numeric_batch(robot: Robot, targets: np.ndarray, q_ref: np.ndarray, mask: np.ndarray,
                  settings: LMSettings, rng: np.random.Generator | int | None, all_solutions: bool) -> _Found:
    """Numeric solutions of targets (N, 4, 4) from q_ref (N, n); where a target fails, q is the best
    configuration found. The solve, the turns into the limits and the check are ``solve_lm``'s one
    compiled loop."""
    N, n = q_ref.shape
    lim = robot.limits
    sols = None
    if all_solutions:
        scale = _joint_scale(robot)
        same = SAME_SOLUTION_TOL
        if n > int(np.count_nonzero(mask)):     # redundant: a continuum of solutions, kept spaced apart
            scale = np.where(robot.revolute, 1.0, robot.scale * (REDUNDANT_SPACING_LENGTH / REDUNDANT_SPACING))
            same = REDUNDANT_SPACING
        # 1 + restarts starts per target side by side, each one attempt; keep every distinct success
        K = 1 + settings.restarts
        span = np.where(robot.revolute, np.pi, robot.scale)
        lo = np.where(np.isfinite(lim[:, 0]), lim[:, 0], -span)
        hi = np.where(np.isfinite(lim[:, 1]), lim[:, 1], span)
        starts = _generator(rng).uniform(lo, hi, size=(N, K, n))
        starts[:, 0] = q_ref
        one = LMSettings(**{**settings.__dict__, "restarts": 0})
        out = solve_lm(robot, np.repeat(targets, K, axis=0), starts.reshape(N * K, n), mask, one, _seed(rng),
                       ref=np.repeat(q_ref, K, axis=0))
        Q = out.q.reshape(N, K, n)
        ok = out.success.reshape(N, K)
        sols = [distinct_sorted(Q[i][ok[i]], q_ref[i], scale, same) for i in range(N)]
        iters = out.iterations.reshape(N, K).sum(axis=1)
        attempts = np.full(N, K)
        E = np.hypot(out.position_error, out.orientation_error).reshape(N, K)
        success: np.ndarray = np.any(ok, axis=1)
        best = Q[np.arange(N), np.argmin(E, axis=1)]
        q = np.where(success[:, None], np.array([s[0] if len(s) else np.zeros(n) for s in sols]), best)
        errors = None
    else:
        # a preference broadcast over the batch goes in as its one row (no copy of N equal rows)
        out = solve_lm(robot, targets, q_ref[:1] if N > 1 and q_ref.strides[0] == 0 else q_ref, mask,
                       settings, _seed(rng))
        q, success, iters, attempts = out.q, out.success, out.iterations, out.attempts
        errors = (out.position_error, out.orientation_error)
    reasons = [""] * N
    for i in ([] if success.all() else np.flatnonzero(~success)):
        reasons[i] = (f"no solution found from {attempts[i]} start(s) (the target may be unreachable, "
                      f"or need more restarts)")
    if errors is None:      # all_solutions: the errors of the chosen q
        errors = pose_errors(robot._chain, q, targets, mask)
    return _Found(q, success, reasons, iters, attempts, sols, None, errors)


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
            and max_iterations is DEFAULT_MAX_ITERATIONS and restarts is DEFAULT_RESTARTS:    # else: checked by ik
        solver = closed_form_solver(robot)
        if solver is not None:
            return solver.nearest(T, q_ref, tol_position, tol_orientation, all_solutions, SAME_SOLUTION_TOL,
                                  IKResult, solver.name, embed)
    return None
