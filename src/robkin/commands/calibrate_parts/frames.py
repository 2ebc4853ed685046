"""The frames a calibrated robot is written with: every source link kept, the marker as its own frame.

A calibration fits the chain from the robot base, as it stands in the measuring device's frame, to the
measured point (the marker, a reflector on the flange): ``CalibrationResult.robot`` has that base as
its ``world`` and the marker as its tool, so ``world @ fk(q)`` predicts a measurement.

- default (``keep_frames`` False): that robot, as the DESIGN contract says. When the tool link of the
  source is its last moving link (xArm7's ``link7``, Z1's ``link06``), no source link can sit at the
  marker (the last link turns about its own axis): a fixed link ``marker`` is added under it, so the
  writers keep every source link under its own name instead of falling back to a plain chain.
- ``keep_frames``: a drop-in replacement for the nominal file. The world transform is the nominal
  model's (the measuring frame's pose goes to the report), the tool is the calibrated flange (the
  nominal tool frame moved with the calibrated chain), and the marker is a fixed link ``marker`` under
  the tool link: ``robkin check nominal calibrated`` then compares flange with flange.
"""

from __future__ import annotations

import numpy as np

from ...bodies import Bodies
from ...body_parts import Link, LinkJoint
from ...calibration.report import CalibrationResult
from ...robot import Robot

__all__ = ["written_robot", "MARKER_LINK"]

#: Name of the link added for the marker (suffixed with '_' where the source already has one).
MARKER_LINK = "marker"


def written_robot(result: CalibrationResult, nominal: Robot, keep_frames: bool = False) -> Robot:
    """The calibrated robot as it is written (see the module doc)."""
    robot = result.robot
    marker_pose = robot.tool
    if keep_frames:
        flange = result.flange if result.flange is not None else robot.tool
        robot = robot.replace(frames=np.concatenate([robot.frames[:-1], flange[None]]), world=nominal.world,
                              frames_from=robot.frames_from)
    b = robot.bodies
    if not b.links or not b.chain:
        return robot
    tip = b.tip or b.chain[-1]
    if not keep_frames and tip != b.chain[-1]:
        return robot   # the source's tool link itself moves to the marker, as the contract says
    taken = {lk.name for lk in b.links} | {lk.joint.name for lk in b.links if lk.joint is not None}
    name = _free(MARKER_LINK, taken)
    joint = LinkJoint(_free(f"{name}_joint", taken | {name}), "fixed")
    link = Link(name, robot.n, np.array(marker_pose), parent=tip, joint=joint)
    bodies = Bodies(links=(*b.links, link), chain=b.chain, tip=tip if keep_frames else name, shapes=b.shapes,
                    inertials=b.inertials, extras=b.extras)
    return robot.replace(bodies=bodies)


def _free(name: str, taken: set[str]) -> str:
    while name in taken:
        name += "_"
    return name
