"""What the toolbox writers (Robotics Toolbox, MATLAB/Octave) share: the DH or modified DH table of a
robot, its link frames at q = 0 and the links' mass properties expressed in them."""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from ...errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    from ...representations.link_table import LinkTable
    from ...robot import Robot

__all__ = ["CONVENTIONS", "LinkMassRows", "toolbox_table", "link_frames", "link_mass_rows", "unflipped"]

#: --convention values: the table the code is written in
CONVENTIONS = ("dh", "mdh")


class LinkMassRows(NamedTuple):
    """Mass properties of links 1..n in the table's own link frames (the Robotics Toolbox's m, r, I)."""

    mass: np.ndarray     # (n,) kg
    com: np.ndarray      # (n, 3) centre of mass in link frame i, m
    inertia: np.ndarray  # (n, 3, 3) about the centre of mass, link frame i's axes, kg m^2


def unflipped(robot: "Robot") -> "Robot":
    """The robot with every joint's ``flip`` cleared: the same GJD (so the same FK at every q), but
    frame-based tables then put each joint's z axis along its positive direction."""
    if not any(j.flip for j in robot.joints):
        return robot
    return robot.replace(joints=tuple(replace(j, flip=False) for j in robot.joints), frames_from=None)


def toolbox_table(robot: "Robot", convention: str) -> "LinkTable":
    """The standard (``'dh'``) or modified (``'mdh'``) DH table of a robot, as ``robkin convert --to``
    writes it (a ConditioningWarning where it cannot be exact)."""
    if convention == "dh":
        from ...representations.dh import dh_from_robot

        return dh_from_robot(robot)
    if convention == "mdh":
        from ...representations.mdh import mdh_from_robot

        return mdh_from_robot(robot)
    raise InputError(f"--convention {convention}: expected one of {', '.join(CONVENTIONS)}")


def link_frames(table: "LinkTable") -> np.ndarray:
    """Link frames {0}..{n} (n+1, 4, 4) of a DH or modified DH table at q = 0 in the robot base frame
    (``LinkTable.link_frames``): {0} is the base transform, {i} = base A_1(0) ... A_i(0). In standard DH
    frame {i} is at the end of link i, in modified DH at its start (on joint i's axis); either way it
    moves with link i, which is where the Robotics Toolbox expects link i's centre of mass and inertia."""
    return table.link_frames()


def link_mass_rows(robot: "Robot", table: "LinkTable") -> LinkMassRows | None:
    """Mass properties of links 1..n in the table's link frames (the table's own ``masses``, made from
    the robot's by ``robkin.dynamics``: everything rigidly attached to a link at q = 0 merged into it),
    or None when the robot has no inertials at all. Body 0 (what is fixed to the base) never moves, so
    no toolbox link holds it."""
    masses = table.masses
    if masses is None and robot.bodies.inertials:  # a table made without its robot's masses
        from ...representations.mass_rows import masses_of_robot

        masses = masses_of_robot(robot, table.link_frames())
    if masses is None:
        return None
    return LinkMassRows(np.asarray(masses.mass), np.asarray(masses.com), np.asarray(masses.inertia))
