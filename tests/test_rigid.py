"""``robkin.compiled.runtime.rigid.exact_poses``, the one test of "exact rigid transform" behind Robot
construction and IK targets, against the definition in numpy (finite, last row exactly [0, 0, 0, 1],
max |R^T R - I| <= 1e-12, det R > 0), and what a Robot does with the poses it rejects."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import robkin
from robkin.compiled.runtime.rigid import exact_poses
from robkin.errors import InputError, ProjectionWarning


def _reference(A: np.ndarray) -> np.ndarray:
    R = A[:, :3, :3]
    with np.errstate(invalid="ignore", over="ignore"):
        orth = np.abs(R.transpose(0, 2, 1) @ R - np.eye(3)).max(axis=(1, 2)) <= 1e-12
        det = np.linalg.det(np.where(np.isfinite(R), R, 0.0)) > 0
    return np.isfinite(A).all(axis=(1, 2)) & (A[:, 3] == [0, 0, 0, 1]).all(axis=1) & orth & det


def _poses(rng: np.random.Generator, n: int) -> np.ndarray:
    A = np.zeros((n, 4, 4))
    A[:, :3, :3] = Rotation.random(n, random_state=rng).as_matrix()
    A[:, :3, 3] = rng.normal(size=(n, 3)) * 10.0 ** rng.integers(-3, 4, size=(n, 1))
    A[:, 3, 3] = 1.0
    return A


def test_exact_poses_is_the_definition():
    rng = np.random.default_rng(7)
    A = _poses(rng, 400)
    k = np.arange(400)
    A[k % 8 == 1, 0, 0] += 1e-11                      # not orthonormal to 1e-12
    A[k % 8 == 2, 0, 0] += 1e-14                      # rounding: still exact
    A[k % 8 == 3, :3, 0] *= -1                        # a reflection (det -1)
    A[k % 8 == 4, 1, 3] = np.nan
    A[k % 8 == 5, 2, 1] = np.inf
    A[k % 8 == 6, 3, 2] = 1e-17                       # last row not exactly [0, 0, 0, 1]
    ok = exact_poses(A)
    assert ok.dtype == bool and ok.shape == (400,)
    np.testing.assert_array_equal(ok, _reference(A))
    assert ok[k % 8 == 0].all() and ok[k % 8 == 2].all() and not ok[k % 8 == 1].any()
    assert exact_poses(np.zeros((0, 4, 4))).shape == (0,)
    assert exact_poses(A[:5].tolist()).tolist() == ok[:5].tolist()    # any array-like of floats
    with pytest.raises(ValueError, match=r"expected shape \(N, 4, 4\)"):
        exact_poses(np.eye(4))


def test_a_robot_keeps_exact_frames_bit_for_bit_and_checks_the_rest():
    rng = np.random.default_rng(3)
    frames = _poses(rng, 4)
    joints = robkin.robot.default_joints(["revolute"] * 3)
    kept = robkin.Robot(frames, joints)
    assert np.array_equal(kept.frames, frames)
    near = frames.copy()
    near[1, :3, :3] = near[1, :3, :3] @ (np.eye(3) + 1e-6 * np.array([[0, 1, 0], [0, 0, 0], [0, 0, 0]]))
    with pytest.warns(ProjectionWarning, match=r"gjd.frames\[1\]"):
        projected = robkin.Robot(near, joints)
    R = projected.frames[1, :3, :3]
    assert np.abs(R.T @ R - np.eye(3)).max() < 1e-15 and np.linalg.det(R) > 0
    assert np.array_equal(projected.frames[[0, 2, 3]], frames[[0, 2, 3]])
    bad = frames.copy()
    bad[2, 0, 3] = np.nan
    with pytest.raises(InputError, match=r"gjd.frames\[2\]"), warnings.catch_warnings():
        warnings.simplefilter("error")
        robkin.Robot(bad, joints)
    mirrored = frames.copy()
    mirrored[3, :3, 0] *= -1
    with pytest.raises(InputError, match=r"gjd.frames\[3\]"):
        robkin.Robot(mirrored, joints)
