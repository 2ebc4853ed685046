"""Standard Denavit-Hartenberg tables, to and from the GJD hub.

Row i is (a_i, d_i, alpha_i, theta_i) with A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i); joint i moves
about/along z_{i-1}. theta_i (revolute) or d_i (prismatic) in the table is the value at q = 0 and the
joint adds q_i (or subtracts it, for a joint with ``flip``). FK = base A_1(q_1) ... A_n(q_n) tool.

Frame {i-1} is joint i's GJD frame J_i (turned by pi about x when the joint is flipped), so the GJD of
a DH table is its frames {0}..{n-1} plus the tool.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, ClassVar, Iterable

import numpy as np
from numpy.typing import ArrayLike

from .. import se3
from ..robot import Robot
from .frames import dh_params_between
from .link_table import COLUMNS, LinkTable, check_dh_rows, flip_frame
from .mass_rows import table_bodies
from .placement import place_frames, tables_from_robots

__all__ = ["DHTable", "dh_from_robot", "dh_from_robots", "robot_from_dh", "check_dh_rows", "flip_frame",
           "COLUMNS"]


@dataclass(frozen=True, eq=False)
class DHTable(LinkTable):
    """A standard DH description: rows (n, 4) of (a, d, alpha, theta), base and tool (4, 4).

    ``tool`` is the residual T_t of the conversion paper when the tool is not DH-expressible
    (identity when it is).
    """

    SECTION: ClassVar[str] = "dh"
    link_matrix: ClassVar[Callable[..., np.ndarray]] = staticmethod(se3.dh_matrix)

    def base_row(self, tol: float = 1e-9) -> tuple[float, float, float, float] | None:
        """The base as a fixed DH row (the paper's n+1-row layout), or None if it is not one.

        ``tol``: how far (in the robot's length unit and radians) the base may be from a DH row and still
        count as one.
        """
        row = dh_params_between(np.eye(4), self.base)
        if np.allclose(se3.dh_matrix(*row), self.base, atol=tol * max(1.0, np.abs(self.base[:3, 3]).max())):
            return row
        return None

    def to_robot(self, name: str | None = None) -> Robot:
        """The robot this table describes (``robot_from_dh``); ``name``: the robot's name (default: none)."""
        return robot_from_dh(self, name=name)


def robot_from_dh(table: "DHTable | ArrayLike", name: str | None = None, *, joints: Any = None,
                  base: ArrayLike | None = None, tool: ArrayLike | None = None) -> Robot:
    """The GJD of a DH table: J_i = frame {i-1} (flip-adjusted), J_{n+1} = frame {n} tool.

    ``table`` may also be the rows alone, an (n, 4) array of (a, d, alpha, theta) (lengths in the robot's unit,
    angles in radians), with ``joints`` (None: all revolute; a type string such as "RRPR"; or n
    ``Joint``) and optional ``base`` / ``tool`` (4, 4); anything else raises one InputError.

    ``name``: the robot's name (default: none).
    """
    from .table_input import link_table_of

    return robot_from_links(link_table_of(DHTable, table, "robot_from_dh", joints, base, tool), "dh", name)


def robot_from_links(table: LinkTable, frames_from: str, name: str | None = None) -> Robot:
    """The GJD of a table whose joint i moves frame {i-1}'s z (standard DH, Hayati): J_i = frame {i-1}
    (flip-adjusted), J_{n+1} = frame {n} tool; the Robot remembers which table its frames are, and
    carries the rows' mass properties (if any) as ``bodies.inertials``."""
    F = table.link_frames()  # {0}..{n}
    frames = np.empty((table.n + 1, 4, 4))
    for i, joint in enumerate(table.joints):
        frames[i] = flip_frame(F[i], joint.flip)
    frames[-1] = F[-1] @ table.tool
    return Robot(frames, table.joints, name=name, frames_from=frames_from,
                 bodies=table_bodies(table.masses, F))


def dh_frames(robot: Robot) -> tuple[np.ndarray, np.ndarray]:
    """DH frames {0}..{n-1} (n, 4, 4) placed on the robot's axes, and the last frame {n} (4, 4).

    Axis directions follow each joint's ``flip``. Frame {0} is placed from the robot base z axis like
    any other frame (where that axis meets joint 1's axis, x from the base x), so the base is always
    one fixed DH row, and the identity when joint 1's axis is the base z axis. The robot's own frames
    are kept (when they satisfy the convention) only if they are a DH table's frames
    (``robot.frames_from == 'dh'``), so a DH table read in comes back unchanged; frames from any
    other input are placed by the canonical rules of ``frames.common_normal_frame``. The last frame
    is the tool when its x axis crosses joint n's axis at a right angle, else the paper's
    approximating row (``frames.approx_dh_params``) from frame {n-1}.
    """
    F, _ = place_frames("dh", [robot])
    return F[0, :-1], F[0, -1]


def dh_from_robot(robot: Robot) -> DHTable:
    """Standard DH table (+ base, + residual tool) of a robot; FK-identical at every q.

    Values within rounding of 0 or of a multiple of pi/2 are written exactly (``rounding.snap_rows``);
    where the table cannot reproduce FK to WARN_TOL (nearly parallel axes) a ConditioningWarning
    states the error it has. The same as ``dh_from_robots([robot])[0]``.
    """
    return tables_from_robots(DHTable, [robot], label=False)[0]


def dh_from_robots(robots: Iterable[Robot], *, threads: int | None = None) -> list[DHTable]:
    """Standard DH tables of many robots at once (e.g. the candidates of a synthesis run), in order.

    Each table is the one ``dh_from_robot`` gives for that robot, bit for bit; converted together, the
    robots cost a fraction of one call each (robots with the same joint count go through every stage
    as whole arrays). A table that reproduces its robot's FK only to more than WARN_TOL gets a
    ConditioningWarning starting with ``robots[i]:``.

    Parameters
    ----------
    robots : iterable of Robot
        Any joint counts.
    threads : int >= 1, optional
        At most this many threads for the compiled stages (default: automatic, ``robkin.threads``: one
        below a few dozen robots per thread); the tables are the same bits with any number.

    Returns
    -------
    list of DHTable
        One per robot, in the order given.
    """
    return tables_from_robots(DHTable, list(robots), threads=threads)
