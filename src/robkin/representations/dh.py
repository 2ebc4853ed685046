"""Standard Denavit-Hartenberg tables, to and from the GJD hub.

Row i is (a_i, d_i, alpha_i, theta_i) with A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i); joint i moves
about/along z_{i-1}. theta_i (revolute) or d_i (prismatic) in the table is the value at q = 0 and the
joint adds q_i (or subtracts it, for a joint with ``flip``). FK = base A_1(q_1) ... A_n(q_n) tool.

Frame {i-1} is joint i's GJD frame J_i (turned by pi about x when the joint is flipped), so the GJD of
a DH table is its frames {0}..{n-1} plus the tool.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from .. import se3
from ..errors import InputError
from ..robot import Joint, Robot, check_pose, check_q
from .frames import approx_dh_params, is_identity, warn_if_far, common_normal_frame, dh_params_between, satisfies_normal

__all__ = ["DHTable", "dh_from_robot", "robot_from_dh", "check_dh_rows", "flip_frame"]

COLUMNS = ("a", "d", "alpha", "theta")
_FLIP = se3.rot_x(np.pi)


def flip_frame(frame: np.ndarray, flip: bool) -> np.ndarray:
    """A joint frame turned by pi about x when the joint moves against its frame's z (``flip``)."""
    return frame @ _FLIP if flip else frame


def check_dh_rows(rows: ArrayLike, n: int | None = None, field_name: str = "dh.rows") -> np.ndarray:
    """Validate a DH/MDH table as an (n, 4) float array of (a, d, alpha, theta)."""
    try:
        R = np.array(rows, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{field_name}: expected rows of 4 numbers (a, d, alpha, theta)") from None
    if R.ndim != 2 or R.shape[1] != 4:
        raise InputError(f"{field_name}: expected rows of 4 numbers (a, d, alpha, theta), got shape {R.shape}")
    if n is not None and R.shape[0] != n:
        raise InputError(f"{field_name}: expected {n} rows (one per joint), got {R.shape[0]}")
    bad = np.argwhere(~np.isfinite(R))
    if bad.size:
        i, j = bad[0]
        raise InputError(f"{field_name}[{i}].{COLUMNS[j]}: must be a finite number")
    return R


@dataclass(frozen=True, eq=False)
class DHTable:
    """A standard DH description: rows (n, 4) of (a, d, alpha, theta), base and tool (4, 4).

    ``tool`` is the residual T_t of the conversion paper when the tool is not DH-expressible
    (identity when it is).
    """

    rows: np.ndarray
    joints: tuple[Joint, ...]
    base: np.ndarray = field(default_factory=lambda: np.eye(4))
    tool: np.ndarray = field(default_factory=lambda: np.eye(4))

    def __post_init__(self) -> None:
        object.__setattr__(self, "joints", tuple(self.joints))
        object.__setattr__(self, "rows", check_dh_rows(self.rows, len(self.joints)))
        object.__setattr__(self, "base", check_pose(self.base, "dh.base"))
        object.__setattr__(self, "tool", check_pose(self.tool, "dh.tool"))

    @property
    def n(self) -> int:
        return len(self.joints)

    def _signed(self) -> tuple[np.ndarray, np.ndarray]:
        rev = np.array([j.revolute for j in self.joints])
        sign = np.array([-1.0 if j.flip else 1.0 for j in self.joints])
        return rev, sign

    def link_transforms(self, q: ArrayLike) -> np.ndarray:
        """A_i(q_i) for q (..., n) -> (..., n, 4, 4)."""
        Q = np.asarray(q, dtype=float)
        rev, sign = self._signed()
        a, d, alpha, theta = self.rows.T
        theta_q = theta + np.where(rev, sign * Q, 0.0)
        d_q = d + np.where(rev, 0.0, sign * Q)
        return se3.dh_matrix(a, d_q, alpha, theta_q)

    def fk(self, q: ArrayLike) -> np.ndarray:
        """Tool pose: q (n,) -> (4, 4) or (N, n) -> (N, 4, 4), evaluated from the table itself."""
        Q = check_q(q, self.n)
        A = self.link_transforms(Q)
        T = np.broadcast_to(self.base, Q.shape[:-1] + (4, 4))
        for i in range(self.n):
            T = T @ A[..., i, :, :]
        return T @ self.tool

    def base_row(self, tol: float = 1e-9) -> tuple[float, float, float, float] | None:
        """The base as a fixed DH row (the paper's n+1-row layout), or None if it is not one."""
        row = dh_params_between(np.eye(4), self.base)
        if np.allclose(se3.dh_matrix(*row), self.base, atol=tol * max(1.0, np.abs(self.base[:3, 3]).max())):
            return row
        return None

    def to_robot(self, name: str | None = None) -> Robot:
        return robot_from_dh(self, name=name)


def robot_from_dh(table: DHTable, name: str | None = None) -> Robot:
    """The GJD of a DH table: J_i = frame {i-1} (flip-adjusted), J_{n+1} = frame {n} tool."""
    A = table.link_transforms(np.zeros(table.n))
    frames = np.empty((table.n + 1, 4, 4))
    T = table.base
    for i, joint in enumerate(table.joints):
        frames[i] = flip_frame(T, joint.flip)
        T = T @ A[i]
    frames[-1] = T @ table.tool
    return Robot(frames, table.joints, name=name)


def dh_frames(robot: Robot) -> tuple[np.ndarray, np.ndarray]:
    """DH frames {0}..{n-1} (n, 4, 4) placed on the robot's axes, and the last frame {n} (4, 4).

    Axis directions follow each joint's ``flip``. Frame {0} is measured from the robot base z axis,
    so the base is always one fixed DH row. Given frames that already satisfy the convention are
    kept (see ``frames.common_normal_frame``).
    """
    n, scale = robot.n, robot.scale
    cand = np.stack([flip_frame(robot.frames[i], j.flip) for i, j in enumerate(robot.joints)])
    F = np.empty((n, 4, 4))
    prev = np.eye(4)
    for i in range(n):
        F[i] = common_normal_frame(prev[:3, 3], prev[:3, 2], cand[i, :3, 3], cand[i, :3, 2],
                                   on="b", prev=prev, scale=scale, keep=cand[i])
        warn_if_far(F[i], scale, f"dh: frame {{{i}}} (joint {i + 1}, '{robot.joints[i].name}')")
        prev = F[i]
    tool = robot.tool
    if satisfies_normal(tool, prev[:3, 3], prev[:3, 2], scale):
        last = tool
    else:
        last = prev @ se3.dh_matrix(*approx_dh_params(prev, tool))
    return F, last


def dh_from_robot(robot: Robot) -> DHTable:
    """Standard DH table (+ base, + residual tool) of a robot; FK-identical at every q."""
    F, last = dh_frames(robot)
    chain = list(F) + [last]
    rows = np.array([dh_params_between(chain[i], chain[i + 1]) for i in range(robot.n)])
    # Re-read the frames from the rows so that base * rows * tool reproduces the GJD tool exactly.
    A = se3.dh_matrix(*rows.T)
    T = F[0]
    for i in range(robot.n):
        T = T @ A[i]
    tool = se3.inv(T) @ robot.tool
    if is_identity(tool, robot.scale):
        tool = np.eye(4)  # DH-expressible tool: the residual is rounding noise
    return DHTable(rows, robot.joints, base=F[0], tool=tool)
