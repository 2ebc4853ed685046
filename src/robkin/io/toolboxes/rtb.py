"""A robot as a Python file for Peter Corke's Robotics Toolbox (``robkin convert --to rtb``).

The file needs ``roboticstoolbox-python`` and numpy, not robkin. Run (or imported), it defines
``robot``, a ``DHRobot`` of ``RevoluteDH``/``PrismaticDH`` links (or the ``...MDH`` links with
``convention='mdh'``) with the table's base, tool, joint offsets and limits and each link's mass,
centre of mass and inertia in its own DH (or modified DH) frame, so that ``robot.fkine(q)`` is robkin's
FK and ``robot.rne`` / ``robot.gravload`` are its inverse dynamics and gravity torques at the same q.

No joint is written with the toolbox's ``flip``: its ``rne`` ignores ``flip`` (the torque of a flipped
joint comes out for the unflipped one; measured with roboticstoolbox-python 1.5), so a joint that moves
against its table frame's z is written instead from the table whose frames put z along every joint's
positive direction (``tables.unflipped``): the same FK and the same joint variables.

Every name and number from the input reaches the file only as a literal (``code_literals``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .code_literals import py_float, py_list, py_matrix, py_str
from .tables import LinkMassRows, link_mass_rows, toolbox_table, unflipped

if TYPE_CHECKING:  # pragma: no cover
    from ...robot import Joint, Robot

__all__ = ["rtb_from_robot", "GRAVITY"]

#: Gravity in the world frame (m/s^2), as pinocchio, MuJoCo and the Robotics Toolbox default to.
GRAVITY = np.array([0.0, 0.0, -9.81])


def _friction(joint: "Joint") -> tuple[float, float]:
    """(viscous B, Coulomb Tc) of a joint from the source (URDF damping and friction), 0 when absent."""
    return (joint.damping or 0.0), (joint.friction or 0.0)


def _link_line(i: int, joint: "Joint", row: np.ndarray, convention: str, masses: LinkMassRows | None) -> str:
    """One ``RevoluteDH(...)`` (or Prismatic/MDH) constructor call, as text."""
    a, d, alpha, theta = row
    f = f"links[{i}]"
    kind = ("Revolute" if joint.revolute else "Prismatic") + ("MDH" if convention == "mdh" else "DH")
    args = [f"a={py_float(a, f + '.a')}", f"alpha={py_float(alpha, f + '.alpha')}"]
    if joint.revolute:   # theta = q + offset; d fixed
        args += [f"d={py_float(d, f + '.d')}", f"offset={py_float(theta, f + '.theta')}"]
    else:                # d = q + offset; theta fixed
        args += [f"theta={py_float(theta, f + '.theta')}", f"offset={py_float(d, f + '.d')}"]
    if joint.lower is not None or joint.upper is not None:
        lo = -np.inf if joint.lower is None else joint.lower
        hi = np.inf if joint.upper is None else joint.upper
        args.append(f"qlim=[{py_float(lo, f + '.lower', allow_inf=True)}, "
                    f"{py_float(hi, f + '.upper', allow_inf=True)}]")
    if masses is not None:
        args += [f"m={py_float(masses.mass[i], f + '.m')}", f"r={py_list(masses.com[i], f + '.r')}",
                 f"I={py_matrix(masses.inertia[i], f + '.I')}"]
        B, Tc = _friction(joint)
        # motor inertia 0; gear ratio 1 only where the source gives joint friction (the toolbox scales
        # friction by G), else 0 as the toolbox's own default
        G = 1.0 if (B or Tc) else 0.0
        args += ["Jm=0.0", f"G={py_float(G, f + '.G')}", f"B={py_float(B, f + '.damping')}",
                 f"Tc=[{py_float(Tc, f + '.friction')}, {py_float(-Tc, f + '.friction')}]"]
    return f"    {kind}({', '.join(args)}),  # JOINT_NAMES[{i}]"


def rtb_from_robot(robot: "Robot", convention: str = "dh") -> str:
    """Text of a Python file defining ``robot``, a Robotics Toolbox ``DHRobot`` of this robot.

    Parameters
    ----------
    robot : Robot
    convention : {'dh', 'mdh'}
        Standard DH links (``RevoluteDH``) or modified DH links (``RevoluteMDH``).

    Returns
    -------
    str
        Python source. Lengths in metres (the robot's units), angles in radians, masses in kg,
        inertias in kg m^2 about each link's centre of mass.
    """
    robot = unflipped(robot)
    table = toolbox_table(robot, convention)
    masses = link_mass_rows(robot, table)
    g_base = robot.world[:3, :3].T @ GRAVITY   # gravity in the robot base frame (the toolbox's world)
    name = robot.name or "robot"
    links = "\n".join(_link_line(i, j, row, convention, masses)
                      for i, (j, row) in enumerate(zip(robot.joints, table.rows)))
    which = "modified (Craig) DH" if convention == "mdh" else "standard DH"
    mass_note = ("Mass properties: link i's mass m (kg), centre of mass r (m) and inertia I about it (kg m^2)\n"
                 "in link frame {i}" + (" (at the start of link i, on joint i's axis)" if convention == "mdh"
                                         else " (at the end of link i)") +
                 "; everything rigidly attached to a link merged into it.\n"
                 "Jm = 0; B, Tc: the source's joint damping and friction (0 when it gives none)."
                 if masses is not None else
                 "The source gives no mass properties: this robot has kinematics only (no rne / gravload).")
    return f'''"""The robot NAME as a Robotics Toolbox DHRobot ({which}), written by robkin.

Needs roboticstoolbox-python and numpy (not robkin). Defines `robot`; joint variable q_i is the source's
joint i (same sign, same zero), revolute in rad, prismatic in m. robot.fkine(q) is the tool pose in the
robot's base frame; WORLD is the source's world -> robot base transform (not part of fkine).
{mass_note}
Gravity (0, 0, -9.81) m/s^2 in the world frame, i.e. robot.gravity in the base frame.
Names from the source are string data in this file, never code.
"""

import numpy as np
from roboticstoolbox import DHRobot, PrismaticDH, PrismaticMDH, RevoluteDH, RevoluteMDH  # noqa: F401
from spatialmath import SE3

NAME = {py_str(name)}
JOINT_NAMES = [{", ".join(py_str(j.name) for j in robot.joints)}]
#: robot base -> DH frame {{0}}
BASE = {py_matrix(table.base, "base", "       ")}
#: frame {{n}} -> tool
TOOL = {py_matrix(table.tool, "tool", "       ")}
#: world -> robot base
WORLD = {py_matrix(robot.world, "world", "        ")}
#: gravity in the robot base frame (m/s^2)
GRAVITY = {py_list(g_base, "gravity")}

links = [
{links}
]

robot = DHRobot(links, name=NAME, base=SE3(np.array(BASE, dtype=float), check=False),
                tool=SE3(np.array(TOOL, dtype=float), check=False),
                gravity=GRAVITY)
'''
