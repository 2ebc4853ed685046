"""Stand-in link geometry for robots that have none (a robot from a DH table or a document).

A URDF or MJCF written from a table has joints and frames but nothing to see, so a simulator shows an
empty scene. :func:`with_link_capsules` gives each body a capsule from the origin of its joint frame to
the origin of the next (the way the Robotics Toolbox and MATLAB draw a DH robot as lines between frame
origins), and each joint a short cylinder along its axis, as :class:`robkin.bodies.Shape` records on
``Robot.bodies``. The writers then write them like any shape: MJCF as capsules and cylinders, URDF
(which has no capsule) as a cylinder and two spheres per capsule, which urdfdom, pinocchio and MuJoCo
all read.

Geometry (poses in the robot base frame at q = 0; ``P_0`` is the base origin, ``P_i`` the origin of
joint frame J_i, ``P_{n+1}`` the tool origin):

* body b (0 = base, i = after joint i) carries the capsule from ``P_b`` to ``P_{b+1}``; a segment
  shorter than ``MIN_SEGMENT`` x the robot's size is a sphere of the capsule's radius instead;
* joint i's cylinder (radius 1.5 r, length 4 r, centred on ``P_i``, along the joint axis) is carried by
  the body before the joint (body i - 1), so it stays put while the joint turns, as a motor housing
  does.

Each shape is written twice, as a visual and as a collision (``roles``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Iterable, Literal

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from .bodies import Shape
    from .robot import Robot

__all__ = ["with_link_capsules", "link_capsules", "LINK_STYLES", "DEFAULT_RADIUS", "MIN_SEGMENT"]

#: ``robkin convert --link-geometry`` choices: ``capsules`` (this module) or ``none``.
LINK_STYLES = ("none", "capsules")
#: Capsule radius as a fraction of the robot's size (``Robot.scale``): 3 % is a slim arm that still
#: shows in a default camera view (the Robotics Toolbox's default line is about as wide).
DEFAULT_RADIUS = 0.03
#: A segment shorter than this fraction of the robot's size (coincident frame origins, up to the
#: rounding of the conversion that made them) is drawn as a sphere, not a zero-length capsule.
MIN_SEGMENT = 1e-6
#: The colours: links grey, joint housings blue (as the GUI draws joint axes).
_LINK_RGBA = (0.62, 0.64, 0.68, 1.0)
_JOINT_RGBA = (0.16, 0.33, 0.85, 1.0)


def _frame_along(p: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """A frame at ``p`` whose z axis is the unit vector ``direction`` (``lines.frame_with_z``: the
    identity rotation for a z-directed segment)."""
    from .lines import frame_with_z

    T = np.eye(4)
    T[:3, :3], T[:3, 3] = frame_with_z(direction), p
    return T


def link_capsules(robot: "Robot", radius: float | None = None,
                  roles: Iterable[Literal["visual", "collision"]] = ("visual", "collision")) -> tuple["Shape", ...]:
    """The stand-in shapes of ``robot`` (see the module): capsules along the links, cylinders at the joints.

    Parameters
    ----------
    robot : Robot
        Any robot; its joint frames at q = 0 place the shapes.
    radius : float, optional
        Capsule radius in the robot's length unit; default ``DEFAULT_RADIUS`` x ``robot.scale``.
    roles : iterable of 'visual', 'collision'
        Which copies to make of each shape.

    Returns
    -------
    tuple of Shape
        Poses in the robot base frame at q = 0, each on the body it moves with; ``link`` is the chain
        link name of that body when the robot came from a robot file, else ``base`` / ``link<b>``.
    """
    from .bodies import Geometry, Material, Shape
    from .errors import InputError

    size = max(float(robot.scale), 1e-9)  # a robot with every frame at the origin still gets a size
    # the default rounded to 2 significant digits: a readable number in the written file
    r = float(f"{DEFAULT_RADIUS * size:.2g}") if radius is None else float(radius)
    if not (np.isfinite(r) and r > 0):
        raise InputError(f"link radius: must be a positive number, got {r!r}")
    roles = tuple(roles)
    chain = robot.bodies.chain if len(robot.bodies.chain) == robot.n + 1 else ()
    # without a source's link names: those of the plain URDF writer (base, link1..linkN)
    link = [chain[b] if chain else ("base" if b == 0 else f"link{b}") for b in range(robot.n + 1)]
    F = np.asarray(robot.frames)  # (n+1, 4, 4): J_1..J_n, then the tool
    points = np.vstack([np.zeros(3), F[:, :3, 3]])  # P_0 .. P_{n+1}
    grey = Material(name="robkin_link", rgba=_LINK_RGBA)
    blue = Material(name="robkin_joint", rgba=_JOINT_RGBA)
    parts: list[tuple[int, str, np.ndarray, Geometry, Material]] = []
    for b in range(robot.n + 1):
        a, c = points[b], points[b + 1]
        length = float(np.linalg.norm(c - a))
        if length < MIN_SEGMENT * size:
            pose = np.eye(4)
            pose[:3, 3] = a
            parts.append((b, f"{link[b]}_link", pose, Geometry("sphere", (r,)), grey))
        else:
            parts.append((b, f"{link[b]}_link", _frame_along((a + c) / 2, c - a), Geometry("capsule", (r, length)), grey))
    for i in range(robot.n):
        parts.append((i, f"{robot.joints[i].name}_housing", _frame_along(F[i, :3, 3], F[i, :3, 2]),
                      Geometry("cylinder", (float(f"{1.5 * r:.12g}"), float(f"{4.0 * r:.12g}"))), blue))
    # collision shapes carry no material (URDF's <collision> has none)
    return tuple(Shape(link=link[b], body=b, role=role, pose=pose, geometry=g,
                       material=m if role == "visual" else None, name=name)
                 for role in roles for b, name, pose, g, m in parts)


def with_link_capsules(robot: "Robot", radius: float | None = None, replace: bool = False) -> "Robot":
    """``robot`` with the stand-in link shapes of :func:`link_capsules` added to ``robot.bodies``.

    Parameters
    ----------
    robot : Robot
    radius : float, optional
        Capsule radius (robot length unit); default 3 % of the robot's size.
    replace : bool
        Drop the shapes the robot already has (else the capsules are added to them).

    Returns
    -------
    Robot
        The same kinematics; ``bodies.shapes`` holds the new shapes (visual and collision).
    """
    from dataclasses import replace as replaced

    kept = () if replace else tuple(robot.bodies.shapes)
    return robot.replace(bodies=replaced(robot.bodies, shapes=kept + link_capsules(robot, radius)))
