"""``--gravity`` of ``robkin fk``: the joint torques that hold the robot still at q (``Robot.gravity``)."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    import numpy as np

    from ...robot import Robot

__all__ = ["add_gravity", "gravity_extras", "print_gravity"]

EPILOG = """\
Gravity torques (--gravity): the joint torques (N m, revolute) and forces (N, prismatic) that hold the
robot still at q against gravity, from its mass properties (URDF/MJCF/SDF inertials, or m, r, I on a
robot document's rows; a robot without them is an error). Gravity is (0, 0, -9.81) m/s^2 in the world
frame (the URDF's root; robkin's Robot.world maps it to the robot base) unless --gravity-vector says
otherwise. Joints off the chain are held at 0, their links merged into the link they hang from.
"""


def add_gravity(p: argparse.ArgumentParser) -> None:
    """The ``--gravity`` and ``--gravity-vector`` options."""
    p.add_argument("--gravity", action="store_true",
                   help='also the gravity torques at q (N m / N per joint; needs mass properties); JSON key '
                        '"gravity"')
    p.add_argument("--gravity-vector", metavar="GX,GY,GZ",
                   help="gravity in the world frame, m/s^2 (default 0,0,-9.81); implies --gravity")


def gravity_extras(robot: "Robot", q: "np.ndarray", args: argparse.Namespace) -> dict[str, Any]:
    """{"gravity": torques (n,)} when asked for, else {}; InputError for a robot without masses."""
    if not (args.gravity or args.gravity_vector):
        return {}
    from .common import parse_q

    g = None if args.gravity_vector is None else parse_q(args.gravity_vector, 3, "--gravity-vector")
    return {"gravity": robot.gravity(q, gravity=g)}


def print_gravity(robot: "Robot", extra: dict[str, Any], args: argparse.Namespace) -> None:
    """The gravity torques as a table, one row per joint with its unit."""
    if "gravity" not in extra:
        return
    from ...io.tables.terminal import fmt_num, text_table

    g = "0, 0, -9.81" if args.gravity_vector is None else args.gravity_vector
    rows = [[j.name, fmt_num(t), "N m" if j.revolute else "N"] for j, t in zip(robot.joints, extra["gravity"])]
    print(text_table(["joint", "torque", "unit"], rows,
                     title=f"gravity torques holding q (g = {g} m/s^2, world frame)"))
