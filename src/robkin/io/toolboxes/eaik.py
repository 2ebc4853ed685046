"""A robot as the H and P that EAIK takes (``robkin convert --to eaik``), as JSON or a small Python file.

EAIK (Ostermeier et al., closed-form IK by subproblem decomposition) describes a revolute chain at
q = 0 by the joint axes H (n, 3: unit vectors, the joints' positive directions, in the robot base frame)
and the offsets P (n+1, 3): P[0] from the base origin to a point on axis 1, P[i] from that point of
axis i to the one of axis i+1, P[n] from axis n's point to the tool origin; plus the tool orientation
at q = 0 (``R6T``). The points are the robot's GJD frame origins. q means the same configuration as in
every other robkin output.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ...errors import InputError, quote
from .code_literals import check_finite, py_matrix, py_str

if TYPE_CHECKING:  # pragma: no cover
    from ...robot import Robot

__all__ = ["eaik_parameters", "eaik_json", "eaik_python"]


def eaik_parameters(robot: "Robot") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(H (n, 3), P (n+1, 3), R6T (3, 3)) of a revolute robot, in the robot base frame at q = 0.

    Raises
    ------
    InputError
        For a prismatic joint (EAIK's subproblems are for revolute joints).
    """
    prismatic = [j.name for j in robot.joints if not j.revolute]
    if prismatic:
        raise InputError(f"--to eaik: joint {quote(prismatic[0])} is prismatic; EAIK takes revolute joints only")
    H = np.array(robot.axes)
    points = np.vstack([np.zeros(3), robot.points, robot.tool[:3, 3]])
    P = np.diff(points, axis=0)
    return (check_finite(H, "eaik.H"), check_finite(P, "eaik.P"),
            check_finite(robot.tool[:3, :3], "eaik.R6T"))


def eaik_json(robot: "Robot") -> str:
    """The EAIK parameters as a JSON object: name, joint_names, H, P, R6T (floats that read back
    bit-exact) and a note on their meaning."""
    H, P, R = eaik_parameters(robot)
    doc = {"name": robot.name or "robot", "joint_names": [j.name for j in robot.joints],
           "frame": "robot base frame at q = 0; lengths in metres",
           "H": H.tolist(), "P": P.tolist(), "R6T": R.tolist(),
           "usage": "eaik.pybindings.EAIK.Robot(np.array(H).T, np.array(P).T, np.array(R6T), [], True)"}
    from ..documents.writer import dump

    return dump(doc, "json")


def eaik_python(robot: "Robot") -> str:
    """Text of a Python file (numpy; EAIK only when ``eaik_robot()`` is called) defining ``H``, ``P``,
    ``R6T``, ``NAME``, ``JOINT_NAMES`` and ``eaik_robot(fixed_axes=())``, EAIK's solver."""
    H, P, R = eaik_parameters(robot)
    name = robot.name or "robot"
    return f'''"""The joint axes H and offsets P that EAIK takes for the robot NAME, written by robkin.

Needs numpy (and EAIK for eaik_robot()), not robkin. Robot base frame at q = 0, metres. q_i is the
source's joint i (same sign, same zero). Names from the source are string data here, never code.

    solver = eaik_robot()
    solutions = solver.calculate_IK(T)     # T: 4x4 tool pose in the robot base frame
    solutions.Q, solutions.is_LS           # joint vectors; True where only a least-squares fit
"""

import numpy as np

NAME = {py_str(name)}
JOINT_NAMES = [{", ".join(py_str(j.name) for j in robot.joints)}]
#: joint axes (n, 3): unit vectors along each joint's positive direction
H = np.array({py_matrix(H, "eaik.H", "             ")}, dtype=float)
#: offsets (n+1, 3): base origin -> point on axis 1 -> ... -> point on axis n -> tool origin
P = np.array({py_matrix(P, "eaik.P", "             ")}, dtype=float)
#: tool orientation at q = 0
R6T = np.array({py_matrix(R, "eaik.R6T", "               ")}, dtype=float)


def eaik_robot(fixed_axes=()):
    """EAIK's solver for this robot; fixed_axes: (joint index from 0, value) pairs to hold (a 7-joint arm
    needs one held to be solved in closed form, e.g. a Panda's joint 4: [(3, q4)])."""
    from eaik.pybindings.EAIK import Robot

    return Robot(H.T, P.T, R6T, list(fixed_axes), True)
'''
