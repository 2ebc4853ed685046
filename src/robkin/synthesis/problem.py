"""The synthesis problem: a task (poses to reach), the reach residuals of a DH design and the costs,
with their Jacobians. ``optimize.synthesize`` minimises them.

Variables (all lengths divided by the task's size R, the largest base-target distance, so that the
tolerances and the cost are unit-free)::

    z = (a (n), d (n), alpha (n), q_1 (n), ..., q_K (n))

FK is the standard DH chain A_i = Rz(q_ki) Tz(d_i) Tx(a_i) Rx(alpha_i); the joint offsets theta_i are
not separate variables (they are interchangeable with q). The reach residuals are the position error / R
(3 per pose) and, for ``reach='pose'``, the rotation vector of R R*^T (3 more); their Jacobian is
analytic: every DH parameter moves the tool by a unit twist about/along a known axis.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike

from .. import se3
from ..errors import InputError
from ..robot import check_pose

__all__ = ["Task", "make_task", "Model", "COSTS", "COST_WEIGHTS", "cost_residual", "cost_jacobian", "dexterity",
           "link_lengths", "left_jacobian_inverse", "fd_jacobian", "LENGTH_EPS", "MANIP_FLOOR"]

#: Length smoothing: sqrt(a^2 + d^2 + eps^2) with eps = LENGTH_EPS (relative to R) has a gradient at
#: a = d = 0 and overstates each link by at most eps, i.e. n * 1e-4 relative in total.
LENGTH_EPS = 1e-4
#: Floor under the dimensionless manipulability inside the log of the dexterity cost: keeps it finite
#: at singular structures (-log 1e-12 = 27.6, far above any regular structure's value, ~0 to 8).
MANIP_FLOOR = 1e-12


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


# ------------------------------------------------------------------------------ kinematic model
class Model:
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
        each row's x_i, and the tool rotation ([B,] K, 3, 3). Compiled (``compiled.chain.dh_chain``)."""
        from ..compiled.chain.dh_chain import dh_frames

        a, d, alpha, Q = self.split(np.atleast_2d(z))
        frames = dh_frames(a, d, alpha, Q)
        return tuple(f[0] for f in frames) if z.ndim == 1 else frames

    def _at(self, z: np.ndarray):
        """``chain(z)`` of one design and its orientation residual (K, 3) (None for position tasks),
        kept for the last z: the optimiser asks for the residual and the Jacobian at the same point."""
        key = z.tobytes()
        if getattr(self, "_last_key", None) != key:
            o, zs, xs, Rt = self.chain(z)
            phi = se3.log_rotation(Rt @ np.swapaxes(self.target_R, -1, -2)) if self.pose else None
            self._last_key, self._last = key, (o, zs, xs, Rt, phi)
        return self._last

    def residual(self, z: np.ndarray) -> np.ndarray:
        o, _, _, _, phi = self._at(z)
        r = o[:, -1] - self.target_p
        return (r if phi is None else np.concatenate([r, phi], axis=1)).ravel()  # (K * m,)

    def jacobian(self, z: np.ndarray) -> np.ndarray:
        """d residual / d z, (K * m, 3n + K n), analytic."""
        o, zs, xs, Rt, phi = self._at(z)
        K, n, m = self.K, self.n, self.m
        a, d, alpha, _ = self.split(z)
        p = o[:, -1]  # tool origin (K, 3)
        # twists (w, v) of each parameter, per pose: theta_i (= q) about z_{i-1} through o_{i-1};
        # d_i along z_{i-1}; a_i along x_i; alpha_i about x_i through o_i.
        z_prev, o_prev = zs[:, :-1], o[:, :-1]
        dp_theta = se3.cross(z_prev, p[:, None] - o_prev)
        dp_d = z_prev
        dp_a = xs
        dp_alpha = se3.cross(xs, p[:, None] - o[:, 1:])
        J = np.zeros((K, m, 3 * n + K * n))
        J[:, :3, :n] = np.swapaxes(dp_a, 1, 2)
        J[:, :3, n:2 * n] = np.swapaxes(dp_d, 1, 2)
        J[:, :3, 2 * n:3 * n] = np.swapaxes(dp_alpha, 1, 2)
        for k in range(K):
            J[k, :3, 3 * n + k * n:3 * n + (k + 1) * n] = dp_theta[k].T
        if self.pose:
            Jl = left_jacobian_inverse(phi)  # (K, 3, 3): d phi = Jl^-1 w
            w_alpha = Jl @ np.swapaxes(xs, 1, 2)  # (K, 3, n)
            w_theta = Jl @ np.swapaxes(z_prev, 1, 2)
            J[:, 3:, 2 * n:3 * n] = w_alpha
            for k in range(K):
                J[k, 3:, 3 * n + k * n:3 * n + (k + 1) * n] = w_theta[k]
        return J.reshape(K * m, -1)


def left_jacobian_inverse(phi: np.ndarray) -> np.ndarray:
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
def link_lengths(model: Model, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Link lengths l_i = sqrt(a_i^2 + d_i^2 + eps^2) (n,) in units of R, and d l / d z (n, size)."""
    n = model.n
    a, d = z[:n], z[n:2 * n]
    h = np.sqrt(a * a + d * d + LENGTH_EPS ** 2)
    J = np.zeros((n, z.size))
    J[np.arange(n), np.arange(n)] = a / h
    J[np.arange(n), n + np.arange(n)] = d / h
    return h, J


def dexterity(model: Model, z: np.ndarray) -> np.ndarray:
    """-log of the dimensionless manipulability at each task configuration: (K,) for a design z, or
    (B, K) for designs z (B, size).

    The Jacobian is the geometric one at the tool origin with its linear-velocity rows divided by the
    structure's length L (so the measure does not grow by merely scaling the arm up); all six rows for
    pose tasks, the three linear ones for position tasks. It is 0 when the product of the singular values
    is 1 and grows without bound towards a singular arm (floored at MANIP_FLOOR).
    """
    from ..compiled.chain.dh_chain import dh_volumes

    n = model.n
    Z = np.atleast_2d(z)
    a, d, alpha, Q = model.split(Z)
    L = np.sum(np.hypot(a, d), axis=-1) + LENGTH_EPS
    volume = dh_volumes(a, d, alpha, Q, L, model.pose)   # product of the singular values, (B, K)
    out = -np.log(volume + MANIP_FLOOR)
    return out[0] if z.ndim == 1 else out


#: Cost presets: weights (length, dexterity) of the least-squares cost residuals next to the weighted
#: reach residuals. The cost is |c|^2 with c = (w_l * l_i / R for every link, w_d * dex_k for every
#: task pose), i.e. the sum of squared link lengths (short, even links) plus the squared log-dexterity
#: (``dexterity``, gradient by finite differences, so about 5x slower).
#: Length alone drives designs towards fully stretched (singular) arms, the shortest that reach;
#: 'manipulability' keeps them away from that (its small length weight stops the arm from growing
#: without bound, which the scale-free dexterity term alone would allow).
COST_WEIGHTS = {"length": (1.0, 0.0), "manipulability": (0.3, 1.0)}
COSTS = tuple(COST_WEIGHTS)


def cost_residual(model: Model, cost: str, z: np.ndarray, jacobian: bool = True
                   ) -> tuple[np.ndarray, np.ndarray | None]:
    """Cost residuals c(z) and (if ``jacobian``) their Jacobian (``cost_jacobian``); the cost is |c|^2."""
    wl, wd = COST_WEIGHTS[cost]
    h, _ = link_lengths(model, z)
    c = wl * h if wd == 0.0 else np.concatenate([wl * h, wd * dexterity(model, z)])
    return c, (cost_jacobian(model, cost, z) if jacobian else None)


def cost_jacobian(model: Model, cost: str, z: np.ndarray) -> np.ndarray:
    """d c / d z (n [+ K], size) of the cost residuals, without evaluating c itself (the optimiser asks
    for the values and the Jacobian at different times)."""
    wl, wd = COST_WEIGHTS[cost]
    _, Jh = link_lengths(model, z)
    if wd == 0.0:
        return wl * Jh
    return np.vstack([wl * Jh, wd * fd_jacobian(lambda x: dexterity(model, x), z)])


def fd_jacobian(f: Callable[[np.ndarray], np.ndarray], z: np.ndarray) -> np.ndarray:
    """Central differences (m, size) of f, which maps designs (B, size) to values (B, m) in one call."""
    # step 1e-6 (variables are O(1) in units of R / rad): truncation ~1e-12, rounding ~1e-16 / 1e-6 =
    # 1e-10, both far below what the least-squares steps resolve.
    h = 1e-6
    step = h * np.eye(z.size)
    F = f(np.concatenate([z + step, z - step]))     # every perturbed design in one batched call
    return ((F[:z.size] - F[z.size:]) / (2 * h)).T
