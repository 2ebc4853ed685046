"""Dimensional synthesis: DH parameters of n revolute joints that reach every pose of a task, at the
least cost, found by a local optimiser (scipy's least_squares) from a chosen start.

The estimation paper proposed its four estimates as starting points for exactly this kind of local
search; ``synthesize`` takes a start (an estimate type 'A'-'D', 'random', or explicit values) and
``bench_synthesis.py`` measures how the starts compare.

Problem (all lengths divided by the task's size R, the largest base-target distance, so that the
tolerances and the cost are unit-free)::

    variables   z = (a (n), d (n), alpha (n), q_1 (n), ..., q_K (n))
    minimise    |c(z)|^2                    (cost residuals, see COSTS)
    subject to  FK(a, d, alpha, q_k) reaches task pose k,   k = 1..K

solved in least-squares form (``synthesize``): equality-constrained SQP (SLSQP) was tried first and
stalls here, because the cheapest designs sit at singular, fully stretched arms where the reach
constraints lose rank; Gauss-Newton with trust regions does not need that rank.

FK is the standard DH chain A_i = Rz(q_ki) Tz(d_i) Tx(a_i) Rx(alpha_i); the joint offsets theta_i are
not separate variables (they are interchangeable with q), and the result's DH table takes
theta_i = q_1i, so that q = 0 reaches the first task pose. The reach constraints are the position
error / R (3 per pose) and, for ``reach='pose'``, the rotation vector of R R*^T (3 more); their
Jacobian is analytic: every DH parameter moves the tool by a unit twist about/along a known axis.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike

from .. import se3
from ..errors import InputError
from ..representations.dh import DHTable
from ..robot import Robot, check_pose, default_joints
from .estimate import KINDS, MIN_JOINTS, estimate
from .metrics import link_length

__all__ = ["Task", "make_task", "SynthesisResult", "synthesize", "synthesize_multistart", "COSTS",
           "REACH_TOL", "random_start", "estimate_start"]

#: A result reaches a pose when its position error is below REACH_TOL * R and its rotation error below
#: REACH_TOL rad: six orders above the reach phase's residual at convergence (~1e-12), six below anything
#: a user would call "reaching" (1e-6 of a 1 m arm is a micrometre).
REACH_TOL = 1e-6
#: Length smoothing: sqrt(a^2 + d^2 + eps^2) with eps = LENGTH_EPS (relative to R) has a gradient at
#: a = d = 0 and overstates each link by at most eps, i.e. n * 1e-4 relative in total.
LENGTH_EPS = 1e-4
#: Floor under the dimensionless manipulability inside the log of the dexterity cost: keeps it finite
#: at singular structures (-log 1e-12 = 27.6, far above any regular structure's value, ~0 to 8).
MANIP_FLOOR = 1e-12
#: Bounds on the design: |a|, |d| <= LENGTH_BOUND * R (no sensible structure needs links longer than
#: a few times the task size); |alpha| <= 2 pi and |q| <= 4 pi (angles need no more than a turn or two
#: of slack; the bounds only stop runaway iterates).
LENGTH_BOUND = 4.0
#: Phase 1 (reach) stops at this residual norm: well below REACH_TOL, far above rounding (~1e-15).
PHASE1_TOL = 1e-12


# ------------------------------------------------------------------------------------------ task
@dataclass(frozen=True, eq=False)
class Task:
    """Poses to reach, in the robot base frame.

    Attributes
    ----------
    poses : (K, 4, 4) array
        Target poses in the robot base frame (``base^-1 @ pose_world``).
    base : (4, 4) array
        Robot base frame in the world.
    reach : {'pose', 'position'}
        Whether orientation must be reached too.
    """

    poses: np.ndarray
    base: np.ndarray = field(default_factory=lambda: np.eye(4))
    reach: str = "pose"

    @property
    def size(self) -> float:
        """R: the largest distance of a target from the base origin (length units; > 0)."""
        return float(np.max(np.linalg.norm(self.poses[:, :3, 3], axis=1)))

    @property
    def world_poses(self) -> np.ndarray:
        return self.base @ self.poses


def make_task(poses: ArrayLike, base: ArrayLike | None = None, reach: str = "pose") -> Task:
    """A Task from world poses (4, 4) or (K, 4, 4), an optional base (4, 4) and 'pose' | 'position'."""
    P = np.asarray(poses, dtype=float)
    if P.ndim == 2:
        P = P[None]
    if P.ndim != 3 or P.shape[1:] != (4, 4) or P.shape[0] < 1:
        raise InputError(f"poses: expected one 4x4 pose or a list of them, got shape {P.shape}")
    if reach not in ("pose", "position"):
        raise InputError(f"reach: '{reach}' is not one of pose, position")
    B = np.eye(4) if base is None else check_pose(base, "base")
    local = np.stack([se3.inv(B) @ check_pose(T, f"poses[{k}]") for k, T in enumerate(P)])
    if float(np.max(np.linalg.norm(local[:, :3, 3], axis=1))) == 0.0:
        raise InputError("poses: every target sits at the base origin; give at least one away from it")
    return Task(local, B, reach)


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
        Function evaluations of the optimise phase (phase 2; trf evaluates about once per iteration).
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


# ------------------------------------------------------------------------------ kinematic model
class _Model:
    """Batch DH forward kinematics over the K task poses, the reach residual and its Jacobian.

    Everything is in units of R (positions divided by the task size).
    """

    def __init__(self, task: Task, n: int) -> None:
        self.n, self.K = n, task.poses.shape[0]
        self.R = task.size
        self.target_p = task.poses[:, :3, 3] / self.R
        self.target_R = task.poses[:, :3, :3]
        self.pose = task.reach == "pose"
        self.m = 6 if self.pose else 3

    def split(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """a, d, alpha (..., n) and the joint values (..., K, n) of designs z (..., 3n + K n)."""
        n = self.n
        return (z[..., :n], z[..., n:2 * n], z[..., 2 * n:3 * n],
                z[..., 3 * n:].reshape(z.shape[:-1] + (self.K, n)))

    def chain(self, z: np.ndarray):
        """Frames for every pose of a design z (3n + K n), or of designs z (B, 3n + K n): origins o
        ([B,] K, n+1, 3) and z axes ([B,] K, n+1, 3) of frames {0}..{n}, x axes xs ([B,] K, n, 3) of
        each row's x_i, and the tool rotation ([B,] K, 3, 3). Compiled (``compiled.dh_chain``)."""
        from ..compiled.dh_chain import dh_frames

        a, d, alpha, Q = self.split(np.atleast_2d(z))
        frames = dh_frames(a, d, alpha, Q)
        return tuple(f[0] for f in frames) if z.ndim == 1 else frames

    def residual(self, z: np.ndarray) -> np.ndarray:
        o, _, _, Rt = self.chain(z)
        return self._residual(o[:, -1], Rt).ravel()

    def _residual(self, p: np.ndarray, Rt: np.ndarray) -> np.ndarray:
        r = [p - self.target_p]
        if self.pose:
            r.append(se3.log_rotation(Rt @ np.swapaxes(self.target_R, -1, -2)))
        return np.concatenate(r, axis=1)  # (K, m)

    def jacobian(self, z: np.ndarray) -> np.ndarray:
        """d residual / d z, (K * m, 3n + K n), analytic."""
        o, zs, xs, Rt = self.chain(z)
        K, n, m = self.K, self.n, self.m
        a, d, alpha, _ = self.split(z)
        p = o[:, -1]  # tool origin (K, 3)
        # twists (w, v) of each parameter, per pose: theta_i (= q) about z_{i-1} through o_{i-1};
        # d_i along z_{i-1}; a_i along x_i; alpha_i about x_i through o_i.
        z_prev, o_prev = zs[:, :-1], o[:, :-1]
        dp_theta = np.cross(z_prev, p[:, None] - o_prev)
        dp_d = z_prev
        dp_a = xs
        dp_alpha = np.cross(xs, p[:, None] - o[:, 1:])
        J = np.zeros((K, m, 3 * n + K * n))
        J[:, :3, :n] = np.swapaxes(dp_a, 1, 2)
        J[:, :3, n:2 * n] = np.swapaxes(dp_d, 1, 2)
        J[:, :3, 2 * n:3 * n] = np.swapaxes(dp_alpha, 1, 2)
        for k in range(K):
            J[k, :3, 3 * n + k * n:3 * n + (k + 1) * n] = dp_theta[k].T
        if self.pose:
            phi = se3.log_rotation(Rt @ np.swapaxes(self.target_R, -1, -2))
            Jl = _left_jacobian_inverse(phi)  # (K, 3, 3): d phi = Jl^-1 w
            w_alpha = Jl @ np.swapaxes(xs, 1, 2)  # (K, 3, n)
            w_theta = Jl @ np.swapaxes(z_prev, 1, 2)
            J[:, 3:, 2 * n:3 * n] = w_alpha
            for k in range(K):
                J[k, 3:, 3 * n + k * n:3 * n + (k + 1) * n] = w_theta[k]
        return J.reshape(K * m, -1)


def _left_jacobian_inverse(phi: np.ndarray) -> np.ndarray:
    """J_l^-1(phi) (K, 3, 3): d log(exp([phi]) ) = J_l^-1 w for a space-frame perturbation exp([w])."""
    th = np.linalg.norm(phi, axis=-1)
    W = se3.skew(phi)
    W2 = W @ W
    # coefficient of [phi]^2: (1/th^2)(1 - th sin th / (2 (1 - cos th))); its series 1/12 + th^2/720
    # below 1e-4 rad, where the closed form loses ~8 digits to cancellation.
    small = th < 1e-4
    ths = np.where(small, 1.0, th)
    c = np.where(small, 1.0 / 12.0 + th ** 2 / 720.0,
                 (1.0 - ths * np.sin(ths) / (2.0 * (1.0 - np.cos(ths)))) / ths ** 2)
    return np.eye(3) - 0.5 * W + c[:, None, None] * W2


# ------------------------------------------------------------------------------------- costs
def _link_lengths(model: _Model, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Link lengths l_i = sqrt(a_i^2 + d_i^2 + eps^2) (n,) in units of R, and d l / d z (n, size)."""
    n = model.n
    a, d = z[:n], z[n:2 * n]
    h = np.sqrt(a * a + d * d + LENGTH_EPS ** 2)
    J = np.zeros((n, z.size))
    J[np.arange(n), np.arange(n)] = a / h
    J[np.arange(n), n + np.arange(n)] = d / h
    return h, J


def _dexterity(model: _Model, z: np.ndarray) -> np.ndarray:
    """-log of the dimensionless manipulability at each task configuration: (K,) for a design z, or
    (B, K) for designs z (B, size).

    The Jacobian is the geometric one at the tool origin with its linear-velocity rows divided by the
    structure's length L (so the measure does not grow by merely scaling the arm up); all six rows for
    pose tasks, the three linear ones for position tasks. It is 0 when the product of the singular values
    is 1 and grows without bound towards a singular arm (floored at MANIP_FLOOR).
    """
    from ..compiled.dh_chain import dh_volumes

    n = model.n
    Z = np.atleast_2d(z)
    a, d, alpha, Q = model.split(Z)
    L = np.sum(np.hypot(a, d), axis=-1) + LENGTH_EPS
    volume = dh_volumes(a, d, alpha, Q, L, model.pose)   # product of the singular values, (B, K)
    out = -np.log(volume + MANIP_FLOOR)
    return out[0] if z.ndim == 1 else out


#: Weight of the reach residuals against the cost residuals in phase 2 (penalty form). At the penalty
#: optimum the reach error is ~ cost gradient / weight^2 ~ 1e-4 (units of R), which phase 3 removes by
#: a move of the same size (cost change ~1e-4 relative). Larger weights make the least-squares problem
#: stiffer: in trial runs (n = 6, 3 poses) none of 18 met the tolerance within 1000 evaluations with
#: weight 1e3 (and a 1e-8 tolerance), 16 of 18 did with weight 1e2 (and 1e-6).
REACH_WEIGHT = 1e2
#: Phase 2 stops when the cost changes by less than OPT_FTOL relative in a step, or the design by less
#: than OPT_XTOL relative: 1e-6 is far below any design difference that matters; tighter values only
#: add evaluations as the iterates creep towards the stretched-arm limit described at COST_WEIGHTS.
OPT_FTOL = 1e-6
OPT_XTOL = 1e-9
#: Cost presets: weights (length, dexterity) of the least-squares cost residuals next to the weighted
#: reach residuals. The cost is |c|^2 with c = (w_l * l_i / R for every link, w_d * dex_k for every
#: task pose), i.e. the sum of squared link lengths (short, even links) plus the squared log-dexterity
#: (``_dexterity``, gradient by finite differences, so about 5x slower).
#: Length alone drives designs towards fully stretched (singular) arms, the shortest that reach;
#: 'manipulability' keeps them away from that (its small length weight stops the arm from growing
#: without bound, which the scale-free dexterity term alone would allow).
COST_WEIGHTS = {"length": (1.0, 0.0), "manipulability": (0.3, 1.0)}
COSTS = tuple(COST_WEIGHTS)


def _cost_residual(model: _Model, cost: str, z: np.ndarray, jacobian: bool = True
                   ) -> tuple[np.ndarray, np.ndarray | None]:
    """Cost residuals c(z) and (if ``jacobian``) their Jacobian (``_cost_jacobian``); the cost is |c|^2."""
    wl, wd = COST_WEIGHTS[cost]
    h, _ = _link_lengths(model, z)
    c = wl * h if wd == 0.0 else np.concatenate([wl * h, wd * _dexterity(model, z)])
    return c, (_cost_jacobian(model, cost, z) if jacobian else None)


def _cost_jacobian(model: _Model, cost: str, z: np.ndarray) -> np.ndarray:
    """d c / d z (n [+ K], size) of the cost residuals, without evaluating c itself (the optimiser asks
    for the values and the Jacobian at different times)."""
    wl, wd = COST_WEIGHTS[cost]
    _, Jh = _link_lengths(model, z)
    if wd == 0.0:
        return wl * Jh
    return np.vstack([wl * Jh, wd * _fd_jacobian(lambda x: _dexterity(model, x), z)])


def _fd_jacobian(f: Callable[[np.ndarray], np.ndarray], z: np.ndarray) -> np.ndarray:
    """Central differences (m, size) of f, which maps designs (B, size) to values (B, m) in one call."""
    # step 1e-6 (variables are O(1) in units of R / rad): truncation ~1e-12, rounding ~1e-16 / 1e-6 =
    # 1e-10, both far below what the least-squares steps resolve.
    h = 1e-6
    step = h * np.eye(z.size)
    F = f(np.concatenate([z + step, z - step]))     # every perturbed design in one batched call
    return ((F[:z.size] - F[z.size:]) / (2 * h)).T


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

    Three least-squares phases (scipy ``least_squares``, trust-region reflective, analytic Jacobians):

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
    from ..compiled.box_lsq import MESSAGES, solve

    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < MIN_JOINTS:
        raise InputError(f"joints: need an integer number of joints >= {MIN_JOINTS}, got {n!r}")
    if cost not in COSTS:
        raise InputError(f"cost: '{cost}' is not one of {', '.join(COSTS)}")
    n = int(n)
    model = _Model(task, n)
    label, z0 = _start_vector(task, n, start, rng)
    K = task.poses.shape[0]
    hi = np.concatenate([np.full(2 * n, LENGTH_BOUND), np.full(n, 2 * math.pi), np.full(K * n, 4 * math.pi)])

    def reach(z0_: np.ndarray) -> tuple[np.ndarray, int]:
        z, _, nfev, _, _ = solve(model.residual, model.jacobian, z0_, -hi, hi, gtol=PHASE1_TOL,
                                 rtol=PHASE1_TOL, max_nfev=max_iter)
        return z, nfev

    def fun(z: np.ndarray) -> np.ndarray:
        return np.concatenate([REACH_WEIGHT * model.residual(z), _cost_residual(model, cost, z, False)[0]])

    def jac(z: np.ndarray) -> np.ndarray:
        return np.vstack([REACH_WEIGHT * model.jacobian(z), _cost_jacobian(model, cost, z)])

    t0 = time.perf_counter()
    z1, nfev1 = reach(z0)
    r1 = bool(np.linalg.norm(model.residual(z1)) <= REACH_TOL)
    z2, _, nfev2, _, status = solve(fun, jac, z1, -hi, hi, ftol=OPT_FTOL, xtol=OPT_XTOL, max_nfev=max_iter)
    z3, nfev3 = reach(z2)
    seconds = time.perf_counter() - t0
    c = _cost_residual(model, cost, z3, False)[0]
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


def _design(task: Task, model: _Model, z: np.ndarray, label: str):
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
