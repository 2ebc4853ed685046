"""Robot construction checks every frame (and the world pose): the quick whole-stack test for valid
frames never lets a bad one through, and the frames it accepts are stored exactly as given."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import robkin
from robkin.errors import InputError, ProjectionWarning
from robkin.robot import Robot, default_joints


def frames_of_a_3r() -> np.ndarray:
    """Valid GJD frames (4, 4, 4) of a small 3R arm (rotations about x by 0.3, 0.7, 1.1 rad)."""
    F = np.tile(np.eye(4), (4, 1, 1))
    for i, a in enumerate((0.3, 0.7, 1.1)):
        c, s = np.cos(a), np.sin(a)
        F[i + 1, :3, :3] = [[1, 0, 0], [0, c, -s], [0, s, c]]
        F[i + 1, :3, 3] = [0.1 * (i + 1), 0.2, -0.05 * i]
    return F


JOINTS = default_joints(["revolute"] * 3)


def with_change(i: int, index: tuple, value: float) -> np.ndarray:
    F = frames_of_a_3r()
    F[(i, *index)] = value
    return F


@pytest.mark.parametrize("frames, match", [
    (with_change(2, (0, 3), np.inf), r"gjd.frames\[2\]: contains NaN or infinity"),
    (with_change(1, (1, 3), -np.inf), r"gjd.frames\[1\]: contains NaN or infinity"),
    (with_change(3, (2, 2), np.nan), r"gjd.frames\[3\]: contains NaN or infinity"),
    (with_change(0, (3, 2), 1e-3), r"gjd.frames\[0\]: last row must be"),
    (with_change(2, (0, 1), 0.5), r"gjd.frames\[2\]: rotation block is"),
    (np.array([f @ np.diag([1.0, 1.0, -1.0, 1.0]) for f in frames_of_a_3r()]), r"gjd.frames\[0\].*reflection"),
])
def test_every_bad_frame_is_refused_by_name(frames, match):
    with pytest.raises(InputError, match=match):
        Robot(frames, JOINTS)


def test_a_bad_world_pose_is_refused_by_name():
    world = np.eye(4)
    world[1, 3] = np.nan
    with pytest.raises(InputError, match="world: contains NaN or infinity"):
        Robot(frames_of_a_3r(), JOINTS, world=world)


def test_valid_frames_are_kept_exactly_even_far_out():
    F = frames_of_a_3r()
    F[1:3, 0, 3] = 1e308            # finite (their sum is not): valid, taken as they are, no warning
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # no projection, no warning: the frames are valid
        robot = Robot(F, JOINTS)
    np.testing.assert_array_equal(robot.frames, F)
    assert not robot.frames.flags.writeable


def test_rounding_in_the_last_row_is_cleaned_and_near_rotations_are_projected():
    F = frames_of_a_3r()
    F[2, 3, 3] = 1.0 + 1e-12        # within EXACT_TOL: accepted, stored as exactly 1
    robot = Robot(F, JOINTS)
    assert robot.frames[2, 3, 3] == 1.0
    G = frames_of_a_3r()
    G[1, 0, 0] += 1e-5              # off a rotation by more than EXACT_TOL, within PROJECTION_TOL
    with pytest.warns(ProjectionWarning, match=r"gjd.frames\[1\]"):
        robot = Robot(G, JOINTS)
    R = robot.frames[1, :3, :3]
    np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-14)


def test_duplicate_joint_names_are_refused():
    joints = (robkin.Joint("a"), robkin.Joint("b"), robkin.Joint("a"))
    with pytest.raises(InputError, match="duplicate joint name"):
        Robot(frames_of_a_3r(), joints)
