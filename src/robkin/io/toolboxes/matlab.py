"""A robot as a MATLAB / GNU Octave script (``robkin convert --to matlab``).

Run, the script defines the struct ``robot`` (name, joint names and types, the standard or modified DH
table, flip signs, limits, base, tool, world, gravity and the links' mass properties in their own link
frames) and ``robot_fk``, a function handle: ``T = robot_fk(q)`` is the 4x4 tool pose in the robot base
frame, exactly robkin's FK. Only anonymous functions (each one expression, continued with ``...``), so
the same file runs in MATLAB (which wants a script's local functions at its end) and Octave (which wants
them before their use).

Every name and number from the input reaches the file only as a literal (``code_literals.m_str`` and
``m_float``): MATLAB's single-quoted strings have one escape (a doubled quote), so anything else
outside printable ASCII is written as ``char(code)``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .code_literals import m_float, m_matrix, m_row, m_str
from .rtb import GRAVITY
from .tables import link_mass_rows, toolbox_table

if TYPE_CHECKING:  # pragma: no cover
    from ...robot import Robot

__all__ = ["matlab_from_robot"]

_LINKS = {
    "dh": ("standard DH: A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i); joint i moves about/along z_{i-1}",
           "robot_link = @(a, d, alpha, theta) [cos(theta), -sin(theta)*cos(alpha), sin(theta)*sin(alpha), "
           "a*cos(theta); ...\n    sin(theta), cos(theta)*cos(alpha), -cos(theta)*sin(alpha), a*sin(theta); ...\n"
           "    0, sin(alpha), cos(alpha), d; ...\n    0, 0, 0, 1];"),
    "mdh": ("modified (Craig) DH: A_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i); columns a, alpha hold "
            "a_{i-1}, alpha_{i-1}",
            "robot_link = @(a, d, alpha, theta) [cos(theta), -sin(theta), 0, a; ...\n"
            "    sin(theta)*cos(alpha), cos(theta)*cos(alpha), -sin(alpha), -sin(alpha)*d; ...\n"
            "    sin(theta)*sin(alpha), cos(theta)*sin(alpha), cos(alpha), cos(alpha)*d; ...\n    0, 0, 0, 1];"),
}


def _fk_handle(robot: "Robot") -> str:
    """``robot_fk = @(q) robot.base * robot_link(...) * ... * robot.tool;`` unrolled over the joints."""
    terms = []
    for i, joint in enumerate(robot.joints, start=1):
        move = f"robot.sign({i})*q({i})"
        if joint.revolute:
            terms.append(f"robot_link(robot.dh({i}, 1), robot.dh({i}, 2), robot.dh({i}, 3), robot.dh({i}, 4) + {move})")
        else:
            terms.append(f"robot_link(robot.dh({i}, 1), robot.dh({i}, 2) + {move}, robot.dh({i}, 3), robot.dh({i}, 4))")
    return "robot_fk = @(q) robot.base * ...\n    " + " * ...\n    ".join(terms) + " * ...\n    robot.tool;"


def matlab_from_robot(robot: "Robot", convention: str = "dh") -> str:
    """Text of a MATLAB/Octave script defining ``robot`` (a struct) and ``robot_fk`` (a function handle).

    Parameters
    ----------
    robot : Robot
    convention : {'dh', 'mdh'}
        The table in the script (``robot.dh`` holds its rows either way; ``robot.convention`` says which).

    Returns
    -------
    str
        MATLAB source. Lengths in metres (the robot's units), angles in radians, masses in kg,
        inertias in kg m^2.
    """
    table = toolbox_table(robot, convention)
    masses = link_mass_rows(robot, table)
    name = robot.name or "robot"
    what, link = _LINKS[convention]
    lo = [-np.inf if j.lower is None else j.lower for j in robot.joints]
    hi = [np.inf if j.upper is None else j.upper for j in robot.joints]
    g_base = robot.world[:3, :3].T @ GRAVITY
    lines = [
        "% A robot for MATLAB and GNU Octave, written by robkin (robot.name says which).",
        "% Run this script to define the struct `robot` and the function handle `robot_fk`:",
        "%   T = robot_fk(q)   % tool pose (4x4) in the robot base frame; q: n joint values (rad, m)",
        "% q_i is the source's joint i (same sign, same zero). robot_fk keeps the values robot held when the",
        "% script ran. Names from the source are string data here, never code.",
        f"% Table: {what}.",
        "robot = struct();",
        f"robot.name = {m_str(name)};",
        f"robot.convention = {m_str(convention)};",
        "robot.joint_names = {" + ", ".join(m_str(j.name) for j in robot.joints) + "};",
        "robot.joint_types = {" + ", ".join(m_str(j.type) for j in robot.joints) + "};",
        "% rows: a (m), d (m), alpha (rad), theta (rad) at q = 0; a revolute joint adds sign*q to theta,",
        "% a prismatic one to d",
        f"robot.dh = {m_matrix(table.rows, 'dh.rows', '    ')};",
        "% -1 where a joint moves against its frame's z axis (flip)",
        f"robot.sign = [{m_row([-1.0 if j.flip else 1.0 for j in robot.joints], 'sign')}];",
        "% joint limits [lower upper] (rad or m); -Inf / Inf: none given",
        f"robot.qlim = {m_matrix(np.column_stack([lo, hi]), 'limits', '    ', allow_inf=True)};",
        "% robot base -> frame {0}, frame {n} -> tool, world -> robot base (world is not part of robot_fk)",
        f"robot.base = {m_matrix(table.base, 'base', '    ')};",
        f"robot.tool = {m_matrix(table.tool, 'tool', '    ')};",
        f"robot.world = {m_matrix(robot.world, 'world', '    ')};",
        "% gravity (m/s^2) in the robot base frame",
        f"robot.gravity = [{m_row(g_base, 'gravity')}];",
    ]
    if masses is None:
        lines.append("% the source gives no mass properties (unknown, not zero): robot.mass etc. are empty")
        lines += ["robot.mass = zeros(0, 1);", "robot.com = zeros(0, 3);", "robot.inertia = zeros(0, 6);"]
    else:
        where = "at the start of link i, on joint i's axis" if convention == "mdh" else "at the end of link i"
        I6 = masses.inertia[:, [0, 1, 2, 0, 1, 0], [0, 1, 2, 1, 2, 2]]
        lines += [
            f"% link i's mass properties in its frame {{i}} ({where}), everything rigidly attached merged in:",
            "% mass (kg), centre of mass (m), inertia about it (kg m^2): Ixx Iyy Izz Ixy Iyz Ixz",
            f"robot.mass = [{m_row(masses.mass, 'mass')}]';",
            f"robot.com = {m_matrix(masses.com, 'com', '    ')};",
            f"robot.inertia = {m_matrix(I6, 'inertia', '    ')};",
        ]
    lines += [f"% the link transform ({convention})", link, _fk_handle(robot), ""]
    return "\n".join(lines)
