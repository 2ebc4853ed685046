"""Dimensional synthesis: DH parameters of n revolute joints that reach every pose of a task, at the
least cost, found by a local optimiser (a bounded Levenberg-Marquardt, ``compiled.runtime.box_lsq``) from a
chosen start.

The estimation paper proposed its four estimates as starting points for exactly this kind of local
search; ``synthesize`` takes a start (an estimate type 'A'-'D', 'random', or explicit values) and
``bench_synthesis.py`` measures how the starts compare.

Problem (variables, residuals and costs in ``problem.py``; lengths in units of the task size R)::

    variables   z = (a (n), d (n), alpha (n), q_1 (n), ..., q_K (n))
    minimise    |c(z)|^2                    (cost residuals, see COSTS)
    subject to  FK(a, d, alpha, q_k) reaches task pose k,   k = 1..K

solved in least-squares form (``synthesize``): equality-constrained SQP (SLSQP) was tried first and
stalls here, because the cheapest designs sit at singular, fully stretched arms where the reach
constraints lose rank; damped Gauss-Newton (Levenberg-Marquardt) does not need that rank.

The result's DH table takes theta_i = q_1i, so that q = 0 reaches the first task pose.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from .. import se3
from ..errors import InputError
from ..representations.dh import DHTable
from ..robot import Robot, default_joints
from .estimate import KINDS, MIN_JOINTS, estimate
from .metrics import link_length
from .problem import COSTS, Model, Task, cost_jacobian, cost_residual, make_task

__all__ = ["Task", "make_task", "SynthesisResult", "synthesize", "synthesize_multistart", "COSTS",
           "REACH_TOL", "random_start", "estimate_start"]

#: A result reaches a pose when its position error is below REACH_TOL * R and its rotation error below
#: REACH_TOL rad: six orders above the reach phase's residual at convergence (~1e-12), six below anything
#: a user would call "reaching" (1e-6 of a 1 m arm is a micrometre).
REACH_TOL = 1e-6
#: Bounds on the design: |a|, |d| <= LENGTH_BOUND * R (no sensible structure needs links longer than
#: a few times the task size); |alpha| <= 2 pi and |q| <= 4 pi (angles need no more than a turn or two
#: of slack; the bounds only stop runaway iterates).
LENGTH_BOUND = 4.0
#: Phase 1 (reach) stops at this residual norm: well below REACH_TOL, far above rounding (~1e-15).
PHASE1_TOL = 1e-12

#: Weight of the reach residuals against the cost residuals in phase 2 (penalty form). At the penalty
#: optimum the reach error is ~ cost gradient / weight^2 ~ 1e-4 (units of R), which phase 3 removes by
#: a move of the same size (cost change ~1e-4 relative). Larger weights make the least-squares problem
#: stiffer: in trial runs (n = 6, 3 poses) none of 18 met the tolerance within 1000 evaluations with
#: weight 1e3 (and a 1e-8 tolerance), 16 of 18 did with weight 1e2 (and 1e-6).
REACH_WEIGHT = 1e2
#: Phase 2 stops when the cost changes by less than OPT_FTOL relative in a step, or the design by less
#: than OPT_XTOL relative: 1e-6 is far below any design difference that matters; tighter values only
#: add evaluations as the iterates creep towards the stretched-arm limit described at ``problem.COST_WEIGHTS``.
OPT_FTOL = 1e-6
OPT_XTOL = 1e-9


# -------------------------------------------------------------------------------------- result
@dataclass(frozen=True, eq=False)
class SynthesisResult:
    """Outcome of one local synthesis run.

    Attributes
    ----------
    start : str
        'A'..'D', 'random' or 'given'.
    table : DHTable
        Designed structure; theta offsets = the configuration reaching the first task pose.
    robot : Robot
        The same, with the task's base as ``world``.
    q : (K, n) array
        Joint values (rad) at which ``robot`` reaches each task pose (q[0] = 0).
    converged : bool
        The optimise phase met its tolerance (not its evaluation limit) and every task pose is reached
        within REACH_TOL.
    reaches : bool
        The returned design reaches every task pose within REACH_TOL (it may still not be optimal).
    reached_first : bool
        Phase 1 alone (from the start) reached every task pose.
    cost : float
        Final cost |c|^2 (see COSTS; lengths in units of R).
    length : float
        Eq. (48) length of the design (length units).
    position_error, rotation_error : float
        Largest reach errors over the task poses (length units, rad).
    reach_evaluations : int
        Residual evaluations of phase 1 (1 when the start already reaches every pose).
    iterations : int
        Residual evaluations of the optimise phase (phase 2; one per trial step).
    evaluations : int
        Residual/cost evaluations of both phases.
    seconds : float
        Wall-clock time of the optimisation.
    message : str
        The optimiser's message.
    """

    start: str
    table: DHTable
    robot: Robot
    q: np.ndarray
    converged: bool
    reaches: bool
    reached_first: bool
    cost: float
    length: float
    position_error: float
    rotation_error: float
    reach_evaluations: int
    iterations: int
    evaluations: int
    seconds: float
    message: str

    def summary(self) -> dict:
        """Plain-number record (for tables, JSON and the benchmark)."""
        return {"start": self.start, "converged": bool(self.converged), "reaches": bool(self.reaches),
                "reached_first": bool(self.reached_first),
                "cost": float(self.cost), "reach_evaluations": int(self.reach_evaluations),
                "length": float(self.length), "position_error": float(self.position_error),
                "rotation_error": float(self.rotation_error), "iterations": int(self.iterations),
                "evaluations": int(self.evaluations), "seconds": float(self.seconds)}


# ------------------------------------------------------------------------------------- starts
def estimate_start(task: Task, n: int, kind: str) -> np.ndarray:
    """Start vector z from an estimate of the first task pose (theta offsets become every q_k)."""
    est = estimate(task.base @ task.poses[0], n, kind, task.base)
    return _z_from_rows(est.rows, task)


def _z_from_rows(rows: np.ndarray, task: Task) -> np.ndarray:
    R = task.size
    K = task.poses.shape[0]
    return np.concatenate([rows[:, 0] / R, rows[:, 1] / R, rows[:, 2], np.tile(rows[:, 3], K)])


def random_start(task: Task, n: int, rng: np.random.Generator | int | None = None) -> np.ndarray:
    """Random start: a_i, d_i ~ U(-2R/n, 2R/n) (total reach of order R), alpha_i, q_ki ~ U(-pi, pi)."""
    rng = np.random.default_rng(rng)
    K = task.poses.shape[0]
    lengths = rng.uniform(-2.0 / n, 2.0 / n, size=2 * n)
    angles = rng.uniform(-math.pi, math.pi, size=n + K * n)
    return np.concatenate([lengths, angles])


# ------------------------------------------------------------------------------------ synthesize
def synthesize(task: Task, n: int, start: str | np.ndarray = "D", cost: str = "length",
               rng: np.random.Generator | int | None = None, max_iter: int = 1000) -> SynthesisResult:
    """Optimise the DH parameters of n revolute joints for ``task`` from one start.

    Three bounded least-squares phases (``compiled.runtime.box_lsq``: Levenberg-Marquardt, analytic Jacobians):

    1. reach: the reach residual alone, from the start (skipped when the start already reaches);
    2. optimise: the cost residuals plus the reach residuals weighted by REACH_WEIGHT (penalty form);
    3. polish: the reach residual alone again, which removes the penalty's small reach error.

    Parameters
    ----------
    task : Task
    n : int
        Number of joints (>= 3).
    start : {'A', 'B', 'C', 'D', 'random'} or array
        An estimate type (built for the first task pose), a random start (``rng``), or an explicit
        start vector (a, d in length units, alpha in rad, then q (rad) for every pose).
    cost : {'length', 'manipulability'}
        See ``COSTS``.
    rng : seed or Generator, for ``start='random'``.
    max_iter : int
        Limit of function evaluations of each phase.

    Returns
    -------
    SynthesisResult
    """
    from ..compiled.runtime.box_lsq import MESSAGES, solve

    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < MIN_JOINTS:
        raise InputError(f"joints: need an integer number of joints >= {MIN_JOINTS}, got {n!r}")
    if cost not in COSTS:
        raise InputError(f"cost: '{cost}' is not one of {', '.join(COSTS)}")
    n = int(n)
    model = Model(task, n)
    label, z0 = _start_vector(task, n, start, rng)
    K = task.poses.shape[0]
    hi = np.concatenate([np.full(2 * n, LENGTH_BOUND), np.full(n, 2 * math.pi), np.full(K * n, 4 * math.pi)])

    def reach(z0_: np.ndarray) -> tuple[np.ndarray, int]:
        z, _, nfev, _, _ = solve(model.residual, model.jacobian, z0_, -hi, hi, gtol=PHASE1_TOL,
                                 rtol=PHASE1_TOL, max_nfev=max_iter)
        return z, nfev

    def fun(z: np.ndarray) -> np.ndarray:
        return np.concatenate([REACH_WEIGHT * model.residual(z), cost_residual(model, cost, z, False)[0]])

    def jac(z: np.ndarray) -> np.ndarray:
        return np.vstack([REACH_WEIGHT * model.jacobian(z), cost_jacobian(model, cost, z)])

    t0 = time.perf_counter()
    z1, nfev1 = reach(z0)
    r1 = bool(np.linalg.norm(model.residual(z1)) <= REACH_TOL)
    z2, F2, nfev2, _, status = solve(fun, jac, z1, -hi, hi, ftol=OPT_FTOL, xtol=OPT_XTOL, max_nfev=max_iter)
    z3, nfev3 = reach(z2)
    seconds = time.perf_counter() - t0
    c = cost_residual(model, cost, z3, False)[0]
    design = _design(task, model, z3, label)
    rows, table, robot, q, (pos, rot) = design
    reaches = pos <= REACH_TOL * model.R and rot <= REACH_TOL
    converged = status > 0 and reaches
    message = (f"reach: {nfev1} evaluations ({'reached' if r1 else 'not reached'}); optimise: {MESSAGES[status]}; "
               f"polish: {nfev3} evaluations")
    return SynthesisResult(label, table, robot, q, converged, reaches, r1, float(c @ c), link_length(rows),
                           pos, rot, nfev1, nfev2, nfev1 + nfev2 + nfev3, seconds, message)


def _start_vector(task: Task, n: int, start, rng) -> tuple[str, np.ndarray]:
    if isinstance(start, str):
        s = start.upper() if len(start) == 1 else start.lower()
        if s in KINDS:
            return s, estimate_start(task, n, s)
        if s == "random":
            return "random", random_start(task, n, rng)
        raise InputError(f"start: '{start}' is not one of {', '.join(KINDS)}, random")
    z0 = np.asarray(start, dtype=float).ravel()
    size = 3 * n + task.poses.shape[0] * n
    if z0.shape != (size,) or not np.all(np.isfinite(z0)):
        raise InputError(f"start: expected {size} finite numbers (a, d, alpha, then q per pose), got {z0.size}")
    z0 = z0.copy()
    z0[:2 * n] /= task.size
    return "given", z0


def _reach_errors(task: Task, robot: Robot, q: np.ndarray) -> tuple[float, float]:
    T = robot.fk(q)
    pos = float(np.max(np.linalg.norm(T[:, :3, 3] - task.poses[:, :3, 3], axis=1)))
    if task.reach != "pose":
        return pos, 0.0
    rel = T[:, :3, :3] @ np.swapaxes(task.poses[:, :3, :3], 1, 2)
    return pos, float(np.max(np.linalg.norm(se3.log_rotation(rel), axis=1)))


def _design(task: Task, model: Model, z: np.ndarray, label: str):
    n, R = model.n, model.R
    a, d, alpha, Q = model.split(z)
    rows = np.column_stack([a * R, d * R, alpha, Q[0]])
    table = DHTable(rows, default_joints(["revolute"] * n))
    robot = table.to_robot(name=f"synthesis-{label}").replace(world=task.base)
    q = Q - Q[0]
    return rows, table, robot, q, _reach_errors(task, robot, q)


def synthesize_multistart(task: Task, n: int, starts: Sequence[str] = KINDS + ("random",) * 4,
                          cost: str = "length", rng: np.random.Generator | int | None = None,
                          max_iter: int = 1000) -> tuple[SynthesisResult | None, list[SynthesisResult]]:
    """Run ``synthesize`` from every start; return (best converged result or None, all results)."""
    rng = np.random.default_rng(rng)
    results = [synthesize(task, n, s, cost, rng, max_iter) for s in starts]
    ok = [r for r in results if r.converged]
    return (min(ok, key=lambda r: r.cost) if ok else None), results
