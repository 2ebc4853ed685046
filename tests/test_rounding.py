"""Near-round table values (representations/rounding.py): written round only when FK allows it."""

from __future__ import annotations

import math

import numpy as np

import robkin
from robkin.representations.rounding import SNAP_BUDGET, snap_rows

H = math.pi / 2
JOINTS = [robkin.Joint(f"j{i + 1}") for i in range(3)]


def fk_change(before: np.ndarray, after: np.ndarray) -> float:
    """Largest tool displacement between two DH tables, at many configurations (independent of the
    bound that snap_rows uses)."""
    q = np.random.default_rng(0).uniform(-np.pi, np.pi, size=(500, 3))
    A = robkin.DHTable(before, JOINTS).fk(q)
    B = robkin.DHTable(after, JOINTS).fk(q)
    return float(np.abs(A - B).max())


def test_rounding_noise_becomes_exact_and_fk_barely_moves():
    rows = np.array([[3e-17, 0.3, H + 2e-16, -1e-16], [0.4, 1e-16, -1e-15, 0.0], [0.2, 0.0, 0.0, math.pi - 4e-16]])
    out = snap_rows(rows, JOINTS, np.eye(4), scale=0.9)
    np.testing.assert_array_equal(out, [[0, 0.3, H, 0], [0.4, 0, 0, 0], [0.2, 0, 0, math.pi]])
    assert fk_change(rows, out) <= SNAP_BUDGET * 0.9


def test_real_geometry_is_not_rounded_away():
    """A tilt of 1e-10 rad on a 0.9 m arm moves the tool by ~1e-10 m: far above the budget, kept."""
    rows = np.array([[0.0, 0.3, H, 0.0], [0.4, 0.0, 1e-10, 0.0], [0.2, 0.0, 0.0, 0.0]])
    out = snap_rows(rows, JOINTS, np.eye(4), scale=0.9)
    np.testing.assert_array_equal(out, rows)
    assert fk_change(rows, np.where(np.abs(rows) < 1e-9, 0.0, rows)) > SNAP_BUDGET * 0.9


def test_minus_pi_is_written_as_pi():
    out = snap_rows(np.array([[0.0, 0.1, -math.pi, 0.0]]), JOINTS[:1], np.eye(4), scale=0.1)
    assert out[0, 2] == math.pi


def test_unlimited_prismatic_joint_downstream_blocks_angle_rounding():
    """Angles upstream of a prismatic joint without limits have an unbounded lever: not rounded."""
    joints = [robkin.Joint("j1"), robkin.Joint("j2", "prismatic")]
    rows = np.array([[0.1, 0.0, H + 1e-15, 0.0], [0.0, 0.2, 0.0, 0.0]])
    assert snap_rows(rows, joints, np.eye(4), scale=0.3)[0, 2] == rows[0, 2]
    limited = [robkin.Joint("j1"), robkin.Joint("j2", "prismatic", -0.5, 0.5)]
    assert snap_rows(rows, limited, np.eye(4), scale=0.3)[0, 2] == H
