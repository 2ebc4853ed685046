"""``scene.xml``: a floor, a light and sky around a written robot, for MuJoCo's viewer.

``robkin convert X --to mjcf -o DIR/robot.xml --scene`` writes ``DIR/scene.xml`` with it: the robot
file is included (``<include file="robot.xml"/>``), so the folder opens in MuJoCo's viewer
(``python -m mujoco.viewer --mjcf DIR/scene.xml``) ready to press play, and the robot file stays the
model to load in code. The floor lies at z = 0, or lower where the robot reaches below it at home: under
the lowest point of its geoms when the caller measured it (``robkin.simulation.ground``, with MuJoCo),
else under its lowest link origin. A mid-tree base (a humanoid's torso) keeps its legs above it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..files.float_text import float_text as _num
from ..files.xmltext import quoteattr

if TYPE_CHECKING:  # pragma: no cover
    from ...robot import Robot

__all__ = ["scene_text", "floor_height"]


def floor_height(robot: Robot) -> float:
    """The floor's z (world frame, robot units): 0, or the lowest link origin at q = 0 if below 0."""
    world = np.asarray(robot.world, dtype=float)
    z = [float((world @ robot.frames[i])[2, 3]) for i in range(robot.n + 1)]
    z += [float((world @ lk.pose)[2, 3]) for lk in robot.bodies.links]
    return min(0.0, min(z))


#: the floor's distance below the lowest geom point (relative to the robot's size): no touching contact at
#: home (MuJoCo's default contact margin is 0; 1 mm on a 1 m arm is invisible in the viewer)
FLOOR_GAP = 1e-3


def scene_text(robot: Robot, model_file: str, lowest: float | None = None) -> str:
    """The scene's MJCF text, including ``model_file`` (a name relative to the scene's folder);
    ``lowest``: the lowest z of the model's geoms at home, if measured (the floor goes under it)."""
    z = floor_height(robot)
    if lowest is not None and np.isfinite(lowest):
        z = min(z, lowest - FLOOR_GAP * max(robot.scale, 1.0))
    size = max(2.0, 4.0 * robot.scale)
    return "\n".join([
        '<?xml version="1.0"?>',
        "<!-- written by robkin: the robot on a floor, for MuJoCo's viewer (press play) -->",
        f"<mujoco model={quoteattr((robot.name or 'robot') + ' scene')}>",
        f"  <include file={quoteattr(model_file)}/>",
        '  <visual><global azimuth="135" elevation="-25"/></visual>',
        "  <asset>",
        '    <texture name="robkin_sky" type="skybox" builtin="gradient" rgb1="0.45 0.6 0.75" rgb2="0.05 0.05 0.1" '
        'width="512" height="512"/>',
        '    <texture name="robkin_floor" type="2d" builtin="checker" mark="edge" rgb1="0.25 0.28 0.32" '
        'rgb2="0.18 0.2 0.24" markrgb="0.7 0.7 0.7" width="256" height="256"/>',
        '    <material name="robkin_floor" texture="robkin_floor" texuniform="true" texrepeat="4 4" reflectance="0.1"/>',
        "  </asset>",
        "  <worldbody>",
        '    <light name="robkin_scene_light" pos="1 1 3" dir="-0.3 -0.3 -1" castshadow="true"/>',
        f'    <geom name="floor" type="plane" pos="0 0 {_num(z)}" size="{_num(size)} {_num(size)} 0.05" '
        'material="robkin_floor"/>',
        "  </worldbody>",
        "</mujoco>",
        ""])
