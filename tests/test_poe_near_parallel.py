"""A PoE whose first axis is nearly parallel to the base z axis (SO-100's: 6.3e-6 rad, from rounded rpy) gives
a GJD robot whose FK equals the product of exponentials to rounding: its first frame is not placed where the
common normal meets the axes (~7 km away), which cost 6e-12 of the robot's size (the zoo's PoE row)."""

from __future__ import annotations

import numpy as np

from robkin.representations.poe import PoE, robot_from_poe


def test_nearly_parallel_first_axis_keeps_fk_to_rounding():
    tilt = 6.32679489666847e-06
    w1 = np.array([0.0, np.sin(tilt), np.cos(tilt)])
    p1 = np.array([0.0, -0.0452, 0.0])          # a point of axis 1, 4.5 cm off the base z axis
    w2 = np.array([1.0, 0.0, 0.0])
    p2 = np.array([0.0, -0.03, 0.12])
    screws = np.array([np.r_[w1, -np.cross(w1, p1)], np.r_[w2, -np.cross(w2, p2)]])
    M = np.eye(4)
    M[:3, 3] = (0.0, 0.05, 0.25)
    poe = PoE(M, screws, robot_from_poe(screws, M=M).joints, "space")
    robot = robot_from_poe(poe)
    assert np.abs(robot.frames[:, :3, 3]).max() < 1.0      # no frame kilometres away
    qs = np.random.default_rng(0).uniform(-3, 3, (200, 2))
    err = max(np.abs(robot.fk(q) - poe.fk(q)).max() for q in qs)
    assert err < 1e-14   # rounding of a 0.25 m robot (it was 1.5e-12 with the frame 7 km out)
