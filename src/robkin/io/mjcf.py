"""MJCF (MuJoCo's XML format) export: a Robot as a chain of nested bodies with one joint each.

Layout: ``worldbody`` holds body ``base`` at the world->base transform; inside it, one body per joint
placed at the joint frame (relative to the previous one, flip-adjusted) with a ``hinge`` or ``slide``
joint along local z (``0 0 -1`` when flipped), and a body ``tool`` at the tool frame holding a site
``tool`` at its origin. The tool is a body because MuJoCo rounds away a site's own rotation when it is
below ~1e-6 rad; a site at the identity of a body is exact. Angles are
radians (``compiler angle="radian"``); orientations are unit quaternions (w, x, y, z) written with
``repr`` (full precision). Kinematics only: massless bodies get MuJoCo's ``boundmass``/``boundinertia``
placeholders so that the model compiles; they carry no physical meaning.
"""

from __future__ import annotations

import numpy as np

from .. import se3
from .xmltext import quoteattr
from ..robot import Robot

__all__ = ["mjcf_from_robot", "quat_from_matrix", "matrix_from_quat"]


def matrix_from_quat(q: np.ndarray) -> np.ndarray:
    """Rotation matrix (3, 3) of a unit quaternion (w, x, y, z) (MuJoCo's order)."""
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def quat_from_matrix(R: np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z), w >= 0, of a rotation matrix (3, 3).

    Shepperd's method: take the square root of the largest of the four diagonal combinations, so no
    division by a small number happens (accurate to rounding for every rotation).
    """
    R = np.asarray(R, dtype=float)
    tr = R[0, 0] + R[1, 1] + R[2, 2]
    k = int(np.argmax([tr, R[0, 0], R[1, 1], R[2, 2]]))
    if k == 0:
        s = 2.0 * np.sqrt(1.0 + tr)
        q = [0.25 * s, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s]
    elif k == 1:
        s = 2.0 * np.sqrt(1.0 + R[0, 0] - R[1, 1] - R[2, 2])
        q = [(R[2, 1] - R[1, 2]) / s, 0.25 * s, (R[0, 1] + R[1, 0]) / s, (R[0, 2] + R[2, 0]) / s]
    elif k == 2:
        s = 2.0 * np.sqrt(1.0 + R[1, 1] - R[0, 0] - R[2, 2])
        q = [(R[0, 2] - R[2, 0]) / s, (R[0, 1] + R[1, 0]) / s, 0.25 * s, (R[1, 2] + R[2, 1]) / s]
    else:
        s = 2.0 * np.sqrt(1.0 + R[2, 2] - R[0, 0] - R[1, 1])
        q = [(R[1, 0] - R[0, 1]) / s, (R[0, 2] + R[2, 0]) / s, (R[1, 2] + R[2, 1]) / s, 0.25 * s]
    out = np.array(q)
    out /= np.linalg.norm(out)
    return out if out[0] >= 0 else -out


def _num(x: float) -> str:
    x = float(x)
    return "0" if x == 0 else repr(x)


def _place(T: np.ndarray) -> str:
    """pos/quat attributes of a pose relative to the parent body."""
    return (f'pos="{" ".join(_num(v) for v in T[:3, 3])}" '
            f'quat="{" ".join(_num(v) for v in quat_from_matrix(T[:3, :3]))}"')


def mjcf_from_robot(robot: Robot) -> str:
    """MJCF text of the robot; MuJoCo's body (and site) ``tool`` at qpos = q is world @ robot.fk(q).

    Parameters
    ----------
    robot : Robot
        n joints; revolute -> ``hinge``, prismatic -> ``slide``. Limits become ``range`` (a joint
        limited on one side only gets +-1e10 on the other, as in URDF export); unlimited joints, and
        joints whose lower limit equals the upper one (a URDF ``<limit>`` without bounds; MuJoCo
        refuses an empty range), are ``limited="false"``.

    Returns
    -------
    str
        The MJCF document (one qpos entry per joint, in robot joint order).
    """
    from .. import __version__
    from ..representations.dh import flip_frame
    from .urdf import NO_LIMIT

    D = [flip_frame(robot.frames[i], j.flip) for i, j in enumerate(robot.joints)]
    out = ['<?xml version="1.0"?>',
           f"<!-- written by robkin {__version__}: kinematics only; masses are MuJoCo placeholders -->",
           f"<mujoco model={quoteattr(robot.name or 'robot')}>",
           '  <compiler angle="radian" boundmass="1e-06" boundinertia="1e-12"/>',
           "  <worldbody>",
           f"    <body name=\"base\" {_place(robot.world)}>"]
    prev = np.eye(4)
    indent = "      "
    for i, j in enumerate(robot.joints):
        rel = se3.inv(prev) @ D[i]
        kind = "hinge" if j.revolute else "slide"
        if (j.lower is None and j.upper is None) or j.lower == j.upper:
            limit = 'limited="false"'
        else:
            lo = -NO_LIMIT if j.lower is None else j.lower
            hi = NO_LIMIT if j.upper is None else j.upper
            limit = f'limited="true" range="{_num(lo)} {_num(hi)}"'
        out.append(f"{indent}<body name={quoteattr(f'link{i + 1}')} {_place(rel)}>")
        out.append(f"{indent}  <joint name={quoteattr(j.name)} type=\"{kind}\" "
                   f"axis=\"0 0 {'-1' if j.flip else '1'}\" {limit}/>")
        indent += "  "
        prev = D[i]
    out.append(f"{indent}<body name=\"tool\" {_place(se3.inv(prev) @ robot.tool)}>")
    out.append(f"{indent}  <site name=\"tool\"/>")
    out.append(f"{indent}</body>")
    for _ in range(robot.n + 1):
        indent = indent[:-2]
        out.append(f"{indent}</body>")
    out += ["  </worldbody>", "</mujoco>", ""]
    return "\n".join(out)
