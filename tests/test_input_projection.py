"""Near-valid inputs are made exactly valid (rigid rotations, pitch-free screws) at every robot size.

Regression tests for failures the property tests found under a deeper search: a rounded table whose
rotation happened to land 1e-11 from SO(3) was kept as it was, and the body-frame PoE of that robot
(1000 mm from base to tool) was then refused for a pitch of 3.8e-8 mm.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import robkin
from robkin import se3
from robkin.errors import InputError, ProjectionWarning
from robkin.robot import Joint, check_pose


def orthonormality(R: np.ndarray) -> float:
    return float(np.abs(R.T @ R - np.eye(3)).max())


def test_rotation_just_off_so3_is_projected_silently():
    rng = np.random.default_rng(7)
    T = se3.homogeneous(se3.matrix_from_rpy([0.3, -1.1, 2.0]), [840.0, -290.0, 455.0])
    T[:3, :3] += 3e-11 * rng.standard_normal((3, 3))        # inside EXACT_TOL (1e-9): no warning
    assert orthonormality(T[:3, :3]) > 1e-11
    with warnings.catch_warnings():
        warnings.simplefilter("error", ProjectionWarning)
        A = check_pose(T, "tool")
    # the SVD projection is exact to rounding: R^T R - I within a few ulps of 1 (LAPACK's own business:
    # < 1e-15 with NumPy 2.4's OpenBLAS, 1.33e-15 with NumPy 1.24's, 2026-11-28); 4e-15 (~18 ulps) is
    # still 10^4 times below the 3e-11 the rotation was off before
    assert orthonormality(A[:3, :3]) < 4e-15
    np.testing.assert_allclose(A[:3, :3], T[:3, :3], atol=1e-9)
    np.testing.assert_array_equal(A[:3, 3], T[:3, 3])


def test_rotation_rigid_to_rounding_is_kept_bit_for_bit():
    T = se3.homogeneous(se3.matrix_from_rpy([0.3, -1.1, 2.0]), [0.1, 0.2, 0.3])
    np.testing.assert_array_equal(check_pose(T, "tool"), T)


def test_body_screws_of_a_far_tool_with_a_nearly_rigid_rotation_convert():
    # every axis passes through the tool origin, 1000 units from the base; the tool rotation is 5e-11
    # from SO(3) (as a rounded document can be). Body screws need R^-1 = R^T: before rotations were
    # projected, their pitch was ~5e-11 * 1000 and the body PoE was refused.
    rng = np.random.default_rng(3)
    tool = se3.homogeneous(se3.matrix_from_rpy([0.2, 0.4, -0.7]), [-841.47, 291.92, -454.65])
    frames = np.stack([tool, tool @ se3.rot_x(np.pi / 2), tool])
    frames[2, :3, :3] += 5e-11 * rng.standard_normal((3, 3))
    robot = robkin.Robot(frames, [Joint("j1"), Joint("j2")])
    with warnings.catch_warnings():
        warnings.simplefilter("error", ProjectionWarning)   # a valid robot converts without projection
        body = robkin.poe_from_robot(robot, "body")
    pitch = np.einsum("ij,ij->i", body.screws[:, :3], body.screws[:, 3:])
    assert np.abs(pitch).max() < 1e-12
    q = np.array([[0.4, -1.2], [2.0, 0.3]])
    np.testing.assert_allclose(body.fk(q), robot.fk(q), atol=1e-9 * 1000)


def test_body_screw_pitch_is_judged_against_the_tool_distance():
    # A body-frame PoE of an 800 mm arm whose wrist axes meet near the flange, typed to 0.1 um: the
    # pitch (8e-5 mm) is rounding at the robot's size (1e-7 of it), not at |v| (8 % of 0.001 mm)
    joints = [Joint("j1")]
    M = se3.trans(0.0, 0.0, 800.0)
    typed = [[0.0, 0.6, 0.8, 0.001, 0.0, 0.0001]]
    with pytest.warns(ProjectionWarning, match=r"poe_body.screws\[0\].*pitch"):
        poe = robkin.PoE(M, typed, joints, "body")
    assert abs(float(poe.screws[0, :3] @ poe.screws[0, 3:])) < 1e-18
    # a real pitch is still refused: 14 mm per radian is 1.75 % of this arm's size, not rounding
    with pytest.raises(InputError, match="no pitch"):
        robkin.PoE(M, [[0.0, 0.6, 0.8, 0.0, 10.0, 10.0]], joints, "body")
