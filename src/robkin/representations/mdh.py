"""Modified (Craig) Denavit-Hartenberg tables, to and from the GJD hub.

Row i is (a, d, alpha, theta) meaning (a_{i-1}, d_i, alpha_{i-1}, theta_i), with
A_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i). Frame {i} sits on joint i's axis, so J_i is
frame {i} (turned by pi about x for a flipped joint). FK = base A_1(q_1) ... A_n(q_n) tool. This is the
extension the conversion paper names as future work; it follows from the same hub.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, ClassVar, Iterable

import numpy as np
from numpy.typing import ArrayLike

from .. import se3
from ..robot import Robot
from .link_table import LinkTable, flip_frame
from .mass_rows import table_bodies
from .placement import place_frames, tables_from_robots

__all__ = ["MDHTable", "mdh_from_robot", "mdh_from_robots", "robot_from_mdh", "mdh_frames"]


@dataclass(frozen=True, eq=False)
class MDHTable(LinkTable):
    """A modified DH description: rows (n, 4) of (a_{i-1}, d_i, alpha_{i-1}, theta_i), base, tool."""

    SECTION: ClassVar[str] = "mdh"
    link_matrix: ClassVar[Callable[..., np.ndarray]] = staticmethod(se3.mdh_matrix)

    def to_robot(self, name: str | None = None) -> Robot:
        """The robot this table describes (``robot_from_mdh``); ``name``: the robot's name (default: none)."""
        return robot_from_mdh(self, name=name)


def robot_from_mdh(table: "MDHTable | ArrayLike", name: str | None = None, *, joints: Any = None,
                   base: ArrayLike | None = None, tool: ArrayLike | None = None) -> Robot:
    """The GJD of a modified DH table: J_i = frame {i} (flip-adjusted), J_{n+1} = frame {n} tool; the
    rows' mass properties (if any) become ``bodies.inertials``.

    ``table`` may also be the rows alone, an (n, 4) array of (a(i-1), d, alpha(i-1), theta) (lengths in the
    robot's unit, angles in radians), with ``joints`` (None: all revolute; a type string such as "RRPR"; or n
    ``Joint``) and optional ``base`` / ``tool`` (4, 4); anything else raises one InputError.

    ``name``: the robot's name (default: none).
    """
    from .table_input import link_table_of

    t: MDHTable = link_table_of(MDHTable, table, "robot_from_mdh", joints, base, tool)
    F = t.link_frames()  # {0}..{n}
    frames = np.empty((t.n + 1, 4, 4))
    for i, joint in enumerate(t.joints):
        frames[i] = flip_frame(F[i + 1], joint.flip)
    frames[-1] = F[-1] @ t.tool
    return Robot(frames, t.joints, name=name, frames_from="mdh", bodies=table_bodies(t.masses, F))


def mdh_frames(robot: Robot) -> list[np.ndarray]:
    """Modified DH frames {0}..{n} (n + 1 of them, (4, 4) each) placed on the robot's axes.

    Frame {0} sits on the robot base z axis with x along the common normal to joint 1 (the base itself
    when it qualifies), or, when joint 1's axis is so nearly parallel to the base z axis that this
    would drop its tilt (sin below lines.ANGLE_TOL, above 1e-15, the rounding noise of a unit vector)
    or lie far away (beyond 10 robot sizes), on joint 1's axis at the foot of the base origin, turned
    from the base by the smallest rotation taking z onto that axis, so the tilt is kept in the base
    transform and row 1 is exact. Frames {1}..{n-1} sit on their joint axes with x along the common
    normal to the next axis; frame {n} continues frame {n-1}'s x axis (theta_n = d_n = 0), and the
    tool is what remains. The robot's own joint frames are kept (when they satisfy the convention)
    only if they are a modified DH table's frames (``robot.frames_from == 'mdh'``).
    """
    M, _ = place_frames("mdh", [robot])
    return list(M[0])


def mdh_from_robot(robot: Robot) -> MDHTable:
    """Modified DH table of a robot (frames from ``mdh_frames``); FK-identical at every q.

    Values within rounding of 0 or of a multiple of pi/2 are written exactly (``rounding.snap_rows``);
    where the table cannot reproduce FK to WARN_TOL a ConditioningWarning states the error it has.
    The same as ``mdh_from_robots([robot])[0]``.
    """
    return tables_from_robots(MDHTable, [robot], label=False)[0]


def mdh_from_robots(robots: Iterable[Robot], *, threads: int | None = None) -> list[MDHTable]:
    """Modified DH tables of many robots at once, in order; each the one ``mdh_from_robot`` gives,
    bit for bit (see ``dh.dh_from_robots``, also for ``threads``; warnings start with ``robots[i]:``)."""
    return tables_from_robots(MDHTable, list(robots), threads=threads)
