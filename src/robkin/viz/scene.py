"""What a picture of a robot shows, as plain numbers: the geometry behind ``plot`` and the GUI.

A :class:`Scene` is one representation of a robot at one configuration q, in the robot base frame:
the link polyline (base origin, then each joint frame's origin before and after its own motion, then
the tool origin), every joint axis (a point and the positive direction), the joint frames and the tool
pose. Keeping this separate from matplotlib lets tests check the drawn numbers against independent
references, and lets the browser GUI draw the very same geometry.

Overlaying representations (the conversion paper's figures 1-3) means: convert the robot to each
representation, rebuild a robot from that representation alone, and draw its scene. The frames differ
(a DH table rebuilt from PoE screws puts its frames elsewhere on the same axes), but the joint axes and
the tool pose must coincide; :func:`overlay_scenes` measures by how much they do.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Callable, Mapping, Sequence

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..representations.registry import LiveMapping
from ..robot import Robot, check_q

__all__ = ["Scene", "REPRESENTATIONS", "build_scene", "rebuild", "overlay_scenes", "disagreement"]


def _overlays() -> dict[str, tuple[str, Callable[[Robot], object] | None]]:
    """Registered representations offered as overlays (``robkin.representations.registry.overlays``):
    the GJD (the robot itself, no converter) first, then the others in registration order."""
    from ..representations.registry import overlays

    return {r.name: (r.overlay_label, None if r.layout == "frames" else r.table_of) for r in overlays()}


#: Representation name (as on the command line) -> (label, converter robot -> representation object):
#: a live view of the registry. "gjd" is the robot itself (for a URDF, its joint frames).
REPRESENTATIONS: Mapping[str, tuple[str, Callable[[Robot], object] | None]] = LiveMapping(_overlays)


@dataclass(frozen=True)
class Scene:
    """Geometry of one representation of a robot at one configuration, in the robot base frame.

    Attributes
    ----------
    label : str
        Legend text, e.g. "DH" or "DH rebuilt from PoE (space)".
    q : (n,) array
        Joint values (rad for revolute, length units for prismatic).
    links : (k, 3) array
        Polyline of the links: base origin, each joint frame origin (before and, for prismatic
        joints, after its slide), and the tool origin.
    axis_points : (n, 3) array
        A point on each joint axis at q (the joint frame's origin after its own motion).
    axis_dirs : (n, 3) array
        Unit direction of each joint axis at q, pointing in the joint's positive direction.
    frames : (n, 4, 4) array
        Joint frames at q (after their own motion).
    tool : (4, 4) array
        Tool pose at q.
    joint_names : tuple of str
    prismatic : (n,) bool array
    scale : float
        Characteristic length of the robot (largest frame-origin distance from the base at home).
    """

    label: str
    q: np.ndarray
    links: np.ndarray
    axis_points: np.ndarray
    axis_dirs: np.ndarray
    frames: np.ndarray
    tool: np.ndarray
    joint_names: tuple[str, ...]
    prismatic: np.ndarray
    scale: float

    def points(self) -> np.ndarray:
        """Every point the picture draws (links, axes, tool), (m, 3): for equal-scaled axis limits."""
        return np.vstack([self.links, self.axis_points, self.tool[None, :3, 3]])

    def to_json(self) -> dict:
        """Plain lists, for the browser GUI."""
        return {"label": self.label, "q": self.q.tolist(), "links": self.links.tolist(),
                "axis_points": self.axis_points.tolist(), "axis_dirs": self.axis_dirs.tolist(),
                "frames": self.frames.tolist(), "tool": self.tool.tolist(), "joint_names": list(self.joint_names),
                "prismatic": self.prismatic.tolist(), "scale": self.scale}


def build_scene(robot: Robot, q: ArrayLike | None = None, label: str = "GJD") -> Scene:
    """The scene of ``robot`` at configuration ``q`` (default: home, all zeros).

    Parameters
    ----------
    robot : Robot
    q : (n,) array-like, optional
        Joint values; rad for revolute joints, length units for prismatic ones.
    label : str
        Legend text.
    """
    Q = np.zeros(robot.n) if q is None else check_q(q, robot.n)
    if Q.ndim != 1:
        raise InputError(f"q: expected one configuration of {robot.n} numbers, got shape {Q.shape}")
    F = robot.frames_at(Q)  # (n+1, 4, 4): joint frames after their motion, then the tool
    joints = F[:-1]
    prismatic = ~robot.revolute
    pts = [np.zeros(3)]
    for i in range(robot.n):
        origin, z = joints[i, :3, 3], joints[i, :3, 2]
        if prismatic[i]:
            pts.append(origin - Q[i] * z)  # where the slide starts: the frame before its own motion
        pts.append(origin)
    pts.append(F[-1, :3, 3])
    return Scene(label=label, q=Q.copy(), links=np.array(pts), axis_points=joints[:, :3, 3].copy(),
                 axis_dirs=joints[:, :3, 2].copy(), frames=joints.copy(), tool=F[-1].copy(),
                 joint_names=tuple(j.name for j in robot.joints), prismatic=prismatic.copy(),
                 scale=robot.scale)


def rebuild(robot: Robot, representation: str) -> tuple[Robot, object | None]:
    """Convert ``robot`` to ``representation`` and rebuild a Robot from that representation alone.

    Returns the rebuilt robot and the representation object (None for "gjd").
    """
    if representation not in REPRESENTATIONS:
        # overlay= as the callers (plot_robot, the GUI API) name it; the CLI renders it as --overlay
        raise InputError(f"unknown representation '{representation}' in overlay=; one of "
                         f"{', '.join(REPRESENTATIONS)}")
    _, convert = REPRESENTATIONS[representation]
    if convert is None:
        return robot, None
    rep = convert(robot)
    return rep.to_robot(name=robot.name), rep  # type: ignore[attr-defined]


def overlay_scenes(robot: Robot, q: ArrayLike | None, representations: Sequence[str]) -> list[Scene]:
    """Scenes of ``robot`` rebuilt from each representation, all at the same q.

    The tool of each scene is evaluated with the representation's own forward kinematics (the DH
    product, the exponentials, ...), not through the rebuilt robot, so that overlaying them checks
    the conversion rather than assuming it.
    """
    Q = np.zeros(robot.n) if q is None else check_q(q, robot.n)
    scenes = []
    for name in representations:
        rebuilt, rep = rebuild(robot, name)
        scene = build_scene(rebuilt, Q, label=REPRESENTATIONS[name][0])
        if rep is not None:
            scene = _with_tool(scene, rep.fk(Q))  # type: ignore[attr-defined]
        scenes.append(scene)
    return scenes


def _with_tool(scene: Scene, tool: np.ndarray) -> Scene:
    links = scene.links.copy()
    links[-1] = tool[:3, 3]
    return replace(scene, tool=tool, links=links)


def disagreement(scenes: Sequence[Scene]) -> tuple[float, float, float]:
    """How far apart the scenes' tools and joint axes are (0 for perfect agreement).

    Returns
    -------
    position : float
        Largest distance between tool origins (length units).
    rotation : float
        Largest difference between tool rotation matrices (max abs entry, dimensionless).
    axes : float
        Largest distance between corresponding joint axes as lines: the angle between their
        directions (rad) plus, for revolute joints, the distance of one axis point from the other
        line divided by scale. A prismatic joint is only a direction (its line has no kinematic
        meaning; PoE does not keep it), so only its direction is compared.
    """
    if len(scenes) < 2:
        return 0.0, 0.0, 0.0
    ref = scenes[0]
    pos = rot = ax = 0.0
    for s in scenes[1:]:
        pos = max(pos, float(np.linalg.norm(s.tool[:3, 3] - ref.tool[:3, 3])))
        rot = max(rot, float(np.max(np.abs(s.tool[:3, :3] - ref.tool[:3, :3]))))
        # atan2(|u x v|, u.v) keeps full precision near 0, where arccos(u.v) loses half the digits.
        angle = np.arctan2(np.linalg.norm(np.cross(s.axis_dirs, ref.axis_dirs), axis=1),
                           np.sum(s.axis_dirs * ref.axis_dirs, axis=1))
        d = s.axis_points - ref.axis_points
        off = np.linalg.norm(d - np.sum(d * ref.axis_dirs, axis=1)[:, None] * ref.axis_dirs, axis=1)
        off = np.where(ref.prismatic, 0.0, off)
        if len(angle):
            ax = max(ax, float(np.max(angle + off / ref.scale)))
    return pos, rot, ax
