"""Modified (Craig) Denavit-Hartenberg tables, to and from the GJD hub.

Row i is (a, d, alpha, theta) meaning (a_{i-1}, d_i, alpha_{i-1}, theta_i), with
A_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i). Frame {i} sits on joint i's axis, so J_i is
frame {i} (turned by pi about x for a flipped joint). FK = base A_1(q_1) ... A_n(q_n) tool. This is the
extension the conversion paper names as future work; it follows from the same hub.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from .. import se3
from ..robot import Joint, Robot, check_pose, check_q
from .dh import check_dh_rows, flip_frame
from .frames import common_normal_frame, mdh_params_between, warn_if_far

__all__ = ["MDHTable", "mdh_from_robot", "robot_from_mdh"]


@dataclass(frozen=True, eq=False)
class MDHTable:
    """A modified DH description: rows (n, 4) of (a_{i-1}, d_i, alpha_{i-1}, theta_i), base, tool."""

    rows: np.ndarray
    joints: tuple[Joint, ...]
    base: np.ndarray = field(default_factory=lambda: np.eye(4))
    tool: np.ndarray = field(default_factory=lambda: np.eye(4))

    def __post_init__(self) -> None:
        object.__setattr__(self, "joints", tuple(self.joints))
        object.__setattr__(self, "rows", check_dh_rows(self.rows, len(self.joints), "mdh.rows"))
        object.__setattr__(self, "base", check_pose(self.base, "mdh.base"))
        object.__setattr__(self, "tool", check_pose(self.tool, "mdh.tool"))

    @property
    def n(self) -> int:
        return len(self.joints)

    def link_transforms(self, q: ArrayLike) -> np.ndarray:
        """A_i(q_i) for q (..., n) -> (..., n, 4, 4)."""
        Q = np.asarray(q, dtype=float)
        rev = np.array([j.revolute for j in self.joints])
        sign = np.array([-1.0 if j.flip else 1.0 for j in self.joints])
        a, d, alpha, theta = self.rows.T
        return se3.mdh_matrix(a, d + np.where(rev, 0.0, sign * Q), alpha, theta + np.where(rev, sign * Q, 0.0))

    def fk(self, q: ArrayLike) -> np.ndarray:
        """Tool pose: q (n,) -> (4, 4) or (N, n) -> (N, 4, 4), evaluated from the table itself."""
        Q = check_q(q, self.n)
        A = self.link_transforms(Q)
        T = np.broadcast_to(self.base, Q.shape[:-1] + (4, 4))
        for i in range(self.n):
            T = T @ A[..., i, :, :]
        return T @ self.tool

    def to_robot(self, name: str | None = None) -> Robot:
        return robot_from_mdh(self, name=name)


def robot_from_mdh(table: MDHTable, name: str | None = None) -> Robot:
    """The GJD of a modified DH table: J_i = frame {i} (flip-adjusted), J_{n+1} = frame {n} tool."""
    A = table.link_transforms(np.zeros(table.n))
    frames = np.empty((table.n + 1, 4, 4))
    T = table.base
    for i, joint in enumerate(table.joints):
        T = T @ A[i]
        frames[i] = flip_frame(T, joint.flip)
    frames[-1] = T @ table.tool
    return Robot(frames, table.joints, name=name)


def mdh_from_robot(robot: Robot) -> MDHTable:
    """Modified DH table of a robot; FK-identical at every q.

    Frame {0} sits on the robot base z axis with x along the common normal to joint 1 (the base itself
    when it already qualifies). Frames {1}..{n-1} sit on their joint axes with x along the common normal
    to the next axis; frame {n} is the given last joint frame, and the tool is what remains.
    """
    n, scale = robot.n, robot.scale
    cand = np.stack([flip_frame(robot.frames[i], j.flip) for i, j in enumerate(robot.joints)])
    zero = np.zeros(3)
    ez = np.array([0.0, 0.0, 1.0])
    # Frame {0}: on the base z line, x towards joint 1. Its "previous" frame is the base itself.
    M = [common_normal_frame(zero, ez, cand[0, :3, 3], cand[0, :3, 2], on="a", prev=np.eye(4),
                             scale=scale, keep=np.eye(4))]
    for i in range(n - 1):
        M.append(common_normal_frame(cand[i, :3, 3], cand[i, :3, 2], cand[i + 1, :3, 3], cand[i + 1, :3, 2],
                                     on="a", prev=M[-1], scale=scale, keep=cand[i]))
        warn_if_far(M[-1], scale, f"mdh: frame {{{i + 1}}} (joint {i + 1}, '{robot.joints[i].name}')")
    # Frame {n}: its x axis is free (no next axis), so the given joint frame is kept as it is.
    M.append(cand[n - 1])
    rows = np.array([mdh_params_between(M[i], M[i + 1]) for i in range(n)])
    A = se3.mdh_matrix(*rows.T)
    T = M[0]
    for i in range(n):
        T = T @ A[i]
    tool = se3.inv(T) @ robot.tool
    return MDHTable(rows, robot.joints, base=M[0], tool=tool)
