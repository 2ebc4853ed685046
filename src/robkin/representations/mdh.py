"""Modified (Craig) Denavit-Hartenberg tables, to and from the GJD hub.

Row i is (a, d, alpha, theta) meaning (a_{i-1}, d_i, alpha_{i-1}, theta_i), with
A_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i). Frame {i} sits on joint i's axis, so J_i is
frame {i} (turned by pi about x for a flipped joint). FK = base A_1(q_1) ... A_n(q_n) tool. This is the
extension the conversion paper names as future work; it follows from the same hub.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, ClassVar

import numpy as np

from .. import se3
from ..robot import Robot
from .frames import common_normal_frame, mdh_params_between, warn_if_far
from .link_table import LinkTable, flip_frame, residual_tool

__all__ = ["MDHTable", "mdh_from_robot", "robot_from_mdh"]


@dataclass(frozen=True, eq=False)
class MDHTable(LinkTable):
    """A modified DH description: rows (n, 4) of (a_{i-1}, d_i, alpha_{i-1}, theta_i), base, tool."""

    SECTION: ClassVar[str] = "mdh"
    link_matrix: ClassVar[Callable[..., np.ndarray]] = staticmethod(se3.mdh_matrix)

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
    tool = residual_tool(M[0], rows, se3.mdh_matrix, robot.tool, robot.scale)
    return MDHTable(rows, robot.joints, base=M[0], tool=tool)
