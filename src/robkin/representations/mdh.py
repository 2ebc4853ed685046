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
from ..lines import ANGLE_TOL, cross, norm
from .frames import common_normal_frame, frame_from_zx, mdh_params_between, relative_pose, x_line_on
from .link_table import LinkTable, flip_frame, residual_tool, warn_fk_error
from .rounding import snap_rows

__all__ = ["MDHTable", "mdh_from_robot", "robot_from_mdh", "mdh_frames"]


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
    return Robot(frames, table.joints, name=name, frames_from="mdh")


def mdh_frames(robot: Robot) -> list[np.ndarray]:
    """Modified DH frames {0}..{n} (n + 1 of them, (4, 4) each) placed on the robot's axes.

    Frame {0} sits on the robot base z axis with x along the common normal to joint 1 (the base itself
    when it qualifies), or, when joint 1's axis is so nearly parallel to the base z axis that this
    would drop its tilt or lie far away, on joint 1's axis turned from the base by that tilt, so the
    tilt is kept in the base transform (see ``_base_frame``). Frames {1}..{n-1} sit on their joint
    axes with x along the common normal to the next axis; frame {n} continues frame {n-1}'s x axis
    (theta_n = d_n = 0), and the tool is what remains. The robot's own joint frames are kept (when
    they satisfy the convention) only if they are a modified DH table's frames
    (``robot.frames_from == 'mdh'``).
    """
    n, scale = robot.n, robot.scale
    cand = np.stack([flip_frame(robot.frames[i], j.flip) for i, j in enumerate(robot.joints)])
    keep = robot.frames_from == "mdh"
    M = [_base_frame(cand[0], scale)]
    for i in range(n - 1):
        M.append(common_normal_frame(cand[i, :3, 3], cand[i, :3, 2], cand[i + 1, :3, 3], cand[i + 1, :3, 2],
                                     on="a", prev=M[-1], scale=scale, keep=cand[i] if keep else None))
    if keep:
        M.append(cand[n - 1])
    else:
        # frame {n}: where frame {n-1}'s x line meets joint n's axis, with the same x (its x axis is free)
        prev = M[-1]
        origin = x_line_on(prev, cand[n - 1, :3, 3], cand[n - 1, :3, 2])
        M.append(frame_from_zx(origin, cand[n - 1, :3, 2], prev[:3, 0]))
    return M


#: sin of a tilt of joint 1 from the base z axis below which it is rounding noise of a unit vector
#: (~1e-16 per component), not geometry: no tilted base frame is made for it.
_NOISE_TILT = 1e-15
#: A frame {0} on the base z axis farther than this many robot sizes from the base comes from a
#: joint 1 axis nearly parallel to that axis (the common normal lies ~offset / tilt away): the base
#: is then tilted onto joint 1's axis instead, which keeps every length of the table short.
_FAR = 10.0


def _base_frame(joint1: np.ndarray, scale: float) -> np.ndarray:
    """Frame {0}: on the base z axis with x towards joint 1's axis (the base itself when its x does).

    When joint 1's axis is not exactly parallel to the base z axis but so nearly that this frame would
    drop the tilt (sin below lines.ANGLE_TOL) or lie far away (beyond ``_FAR`` robot sizes), frame {0}
    is instead on joint 1's axis, at the foot of the base origin, turned from the base by the smallest
    rotation that takes z onto the axis: the tilt is kept in the base transform and row 1 is exact.
    """
    ez = np.array([0.0, 0.0, 1.0])
    p, u = joint1[:3, 3], joint1[:3, 2]
    on_z = common_normal_frame(np.zeros(3), ez, p, u, on="a", prev=np.eye(4), scale=scale, keep=np.eye(4))
    s = float(norm(cross(ez, u)))
    if not (_NOISE_TILT < s and (s < ANGLE_TOL or norm(on_z[:3, 3]) > _FAR * scale)):
        return on_z
    # an anti-parallel axis is taken as the line along -u, so that frame {0}'s z stays near the base z
    w = u if u[2] > 0 else -u
    ref = se3.homogeneous(_rotation_onto(ez, w), p - np.dot(p, w) * w)
    return common_normal_frame(ref[:3, 3], w, p, u, on="a", prev=ref, scale=scale, keep=ref)


def _rotation_onto(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The smallest rotation (3, 3) taking unit a onto unit b (not opposite to a)."""
    v = cross(a, b)
    c = float(np.dot(a, b))
    K = np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])
    return np.eye(3) + K + K @ K / (1.0 + c)


def mdh_from_robot(robot: Robot) -> MDHTable:
    """Modified DH table of a robot (frames from ``mdh_frames``); FK-identical at every q.

    Values within rounding of 0 or of a multiple of pi/2 are written exactly (``rounding.snap_rows``);
    where the table cannot reproduce FK to WARN_TOL a ConditioningWarning states the error it has.
    """
    M = mdh_frames(robot)
    n = robot.n
    rows = np.array([mdh_params_between(M[i], M[i + 1]) for i in range(n)])
    if robot.frames_from != "mdh":
        rows = snap_rows(rows, robot.joints, relative_pose(M[n], robot.tool), robot.scale)
    tool = residual_tool(M[0], rows, se3.mdh_matrix, robot.tool, robot.scale)
    table = MDHTable(rows, robot.joints, base=M[0], tool=tool)
    warn_fk_error(table.fk, robot, "mdh")
    return table
