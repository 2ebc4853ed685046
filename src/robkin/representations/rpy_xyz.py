"""RPY-XYZ tables (the URDF origin convention), to and from the GJD hub.

A row is (roll, pitch, yaw, x, y, z) for the transform Trans(x, y, z) Rz(yaw) Ry(pitch) Rx(roll).
The table has n + 2 rows: row 0 is world -> robot base, row i (1..n) the partial transform from the
previous joint frame (the robot base for i = 1) to joint i's frame, whose local z the joint moves
about/along, and row n + 1 joint n's frame -> tool.

Mass properties (optional ``masses``, ``mass_rows.MassRows``): those of link i (the body joint i moves,
with everything rigidly attached to it merged in) on joint row i, in joint i's frame: the frame row i
leads to, which joint i then moves (the URDF child link frame). Rows 0 and n + 1 carry none.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from .. import se3
from ..errors import InputError
from ..robot import Joint, Robot, check_q
from ..bodies import EMPTY_BODIES
from .link_table import check_masses, flip_frame
from .mass_rows import masses_of_robot, table_bodies

if TYPE_CHECKING:  # pragma: no cover
    from .mass_rows import MassRows

__all__ = ["RPYTable", "rpy_from_robot", "robot_from_rpy", "pose_from_row", "row_from_pose"]

COLUMNS = ("roll", "pitch", "yaw", "x", "y", "z")


def pose_from_row(row: ArrayLike) -> np.ndarray:
    """(..., 6) rows (roll, pitch, yaw, x, y, z) -> (..., 4, 4) poses.

    ``row``: the rows (..., 6), angles in radians.
    """
    row = np.asarray(row, dtype=float)
    return se3.homogeneous(se3.matrix_from_rpy(row[..., :3]), row[..., 3:])


def row_from_pose(T: ArrayLike) -> np.ndarray:
    """(..., 4, 4) poses -> (..., 6) rows (roll, pitch, yaw, x, y, z).

    ``T``: the poses (..., 4, 4).
    """
    T = np.asarray(T, dtype=float)
    return np.concatenate([se3.rpy_from_matrix(T[..., :3, :3]), T[..., :3, 3]], axis=-1)


@dataclass(frozen=True, eq=False)
class RPYTable:
    """RPY-XYZ table: rows (n + 2, 6); ``masses`` of links 1..n in joint frames i (or None: unknown)."""

    rows: np.ndarray
    joints: tuple[Joint, ...]
    masses: "MassRows | None" = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "joints", tuple(self.joints))
        if self.masses is not None:
            check_masses(self.masses, len(self.joints), "rpy_xyz")
        n = len(self.joints)
        try:
            R = np.array(self.rows, dtype=float)
        except (TypeError, ValueError):
            raise InputError("rpy_xyz.rows: expected rows of 6 numbers (roll, pitch, yaw, x, y, z)") from None
        if R.ndim != 2 or R.shape[1] != 6:
            raise InputError(f"rpy_xyz.rows: expected rows of 6 numbers (roll, pitch, yaw, x, y, z), "
                             f"got shape {R.shape}")
        if R.shape[0] != n + 2:
            raise InputError(f"rpy_xyz.rows: expected n + 2 = {n + 2} rows (world->base, one per joint, "
                             f"joint {n}->tool), got {R.shape[0]}")
        bad = np.argwhere(~np.isfinite(R))
        if bad.size:
            i, j = bad[0]
            raise InputError(f"rpy_xyz.rows[{i}].{COLUMNS[j]}: must be a finite number")
        object.__setattr__(self, "rows", R)

    @property
    def n(self) -> int:
        return len(self.joints)

    def __str__(self) -> str:
        """The table as the CLI prints it (``robkin convert --to rpy-xyz``)."""
        from .presentation import table_text

        return table_text(self)

    def to_dict(self) -> dict[str, Any]:
        """A robot document (dict): ``joints`` and this table's section, as ``robkin.load`` reads it."""
        from .presentation import table_document

        return table_document(self)

    @property
    def world(self) -> np.ndarray:
        return pose_from_row(self.rows[0])

    def link_frames(self) -> np.ndarray:
        """(n + 1, 4, 4): the robot base (identity), then joint i's frame at q = 0 (rows 1..i composed),
        in the robot base frame: the frames the ``masses`` of links 1..n are expressed in."""
        P = pose_from_row(self.rows[1:-1])
        F = np.empty((self.n + 1, 4, 4))
        F[0] = np.eye(4)
        for i in range(self.n):
            F[i + 1] = F[i] @ P[i]
        return F

    def fk(self, q: ArrayLike) -> np.ndarray:
        """Tool pose in the robot base frame: q (n,) -> (4, 4), (N, n) -> (N, 4, 4)."""
        Q = check_q(q, self.n)
        P = pose_from_row(self.rows[1:])
        T = np.broadcast_to(np.eye(4), Q.shape[:-1] + (4, 4))
        for i, joint in enumerate(self.joints):
            qi = -Q[..., i] if joint.flip else Q[..., i]
            Z = se3.rot_z(qi) if joint.revolute else se3.trans(0.0, 0.0, qi)
            T = T @ P[i] @ Z
        return T @ P[-1]

    def to_robot(self, name: str | None = None) -> Robot:
        """The robot this table describes (``robot_from_rpy``); ``name``: the robot's name (default: none)."""
        return robot_from_rpy(self, name=name)


def robot_from_rpy(table: "RPYTable | ArrayLike", name: str | None = None, *, joints: Any = None) -> Robot:
    """The GJD of an RPY-XYZ table (world -> base row, one row per joint, the tool row); its ``masses``
    (if any) become ``bodies.inertials``.

    ``table`` may also be the rows alone, an (n + 2, 6) array of (roll, pitch, yaw, x, y, z), with
    ``joints`` (None: all revolute; a type string such as "RRPR"; or n ``Joint``); anything else raises
    one InputError.

    ``name``: the robot's name (default: none).
    """
    if not isinstance(table, RPYTable):
        from .table_input import joints_for, rows_array

        if hasattr(table, "SECTION") or hasattr(table, "screws"):
            raise InputError(f"robot_from_rpy: got a {type(table).__name__}; use its .to_robot()")
        R = rows_array(table, ("roll", "pitch", "yaw", "x", "y", "z"), "robot_from_rpy", extra_rows=2,
                       expected="an RPYTable or an (n + 2, 6) array of rows (roll, pitch, yaw, x, y, z): "
                                "world->base, one per joint, joint n->tool")
        table = RPYTable(R, joints_for(joints, len(R) - 2, "robot_from_rpy"))
    elif joints is not None:
        raise InputError("robot_from_rpy: joints= goes with an array of rows; the RPYTable has its own")
    P = pose_from_row(table.rows)
    frames = np.empty((table.n + 1, 4, 4))
    T = np.eye(4)
    for i, joint in enumerate(table.joints):
        T = T @ P[i + 1]
        frames[i] = flip_frame(T, joint.flip)
    frames[-1] = T @ P[-1]
    bodies = table_bodies(table.masses, table.link_frames()) if table.masses is not None else EMPTY_BODIES
    return Robot(frames, table.joints, world=P[0], name=name, bodies=bodies)


def rpy_from_robot(robot: Robot) -> RPYTable:
    """The RPY-XYZ table of a robot, with its mass properties (if any) in the joint frames."""
    F = [flip_frame(robot.frames[i], j.flip) for i, j in enumerate(robot.joints)]
    chain = [np.eye(4)] + F + [robot.tool]
    rel = [robot.world] + [se3.inv(chain[i]) @ chain[i + 1] for i in range(robot.n + 1)]
    table = RPYTable(row_from_pose(np.stack(rel)), robot.joints)
    if robot.bodies.inertials:
        table = replace(table, masses=masses_of_robot(robot, table.link_frames()))
    return table
