"""Line geometry of joint axes: closest points, common normals, and the six axis relations.

Reference values are independent of lines.py: closest points by least squares on the two line
parameters (numpy.linalg.lstsq), relations by construction.
"""

from __future__ import annotations

import numpy as np
import pytest

from robkin import se3
from robkin.lines import (ANGLE_TOL, LENGTH_TOL, AxisRelation, closest_points, common_normal, classify,
                          point_line_foot)
from robkin.robot import Robot, default_joints

#: rounding noise of a handful of products on unit-size numbers, with margin
EXACT = 1e-12


def unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def lstsq_closest(p1, u1, p2, u2):
    """Reference: minimise |p1 + t1 u1 - p2 - t2 u2| as a linear least-squares problem."""
    t, *_ = np.linalg.lstsq(np.column_stack([u1, -u2]), p2 - p1, rcond=None)
    return p1 + t[0] * u1, p2 + t[1] * u2


# ----------------------------------------------------------------------------- closest points
def test_closest_points_match_least_squares_on_random_lines():
    rng = np.random.default_rng(1)
    for _ in range(200):
        p1, p2 = rng.normal(size=3), rng.normal(size=3)
        u1, u2 = unit(rng.normal(size=3)), unit(rng.normal(size=3))
        cn = closest_points(p1, u1, p2, u2)
        c1, c2 = lstsq_closest(p1, u1, p2, u2)
        np.testing.assert_allclose(cn.c1, c1, atol=1e-9)  # lstsq on a possibly ill-conditioned 3x2
        np.testing.assert_allclose(cn.c2, c2, atol=1e-9)
        np.testing.assert_allclose(cn.c1, p1 + cn.t1 * u1, atol=EXACT)
        np.testing.assert_allclose(cn.c2, p2 + cn.t2 * u2, atol=EXACT)
        # the segment c1 -> c2 is perpendicular to both lines and as long as the reported distance
        d = cn.c2 - cn.c1
        assert abs(np.dot(d, u1)) < 1e-10 and abs(np.dot(d, u2)) < 1e-10
        assert cn.distance == pytest.approx(np.linalg.norm(c2 - c1), abs=1e-10)


def test_closest_points_of_skew_lines_known_values():
    # x axis, and a line along y through (0, 0, 2): common normal along z from the origin to (0, 0, 2)
    cn = closest_points(np.array([5.0, 0, 0]), np.array([1.0, 0, 0]), np.array([0, -3.0, 2]), np.array([0, 1.0, 0]))
    np.testing.assert_allclose(cn.c1, [0, 0, 0], atol=EXACT)
    np.testing.assert_allclose(cn.c2, [0, 0, 2], atol=EXACT)
    assert cn.t1 == pytest.approx(-5.0) and cn.t2 == pytest.approx(3.0)
    assert cn.distance == pytest.approx(2.0)


def test_closest_points_of_nearly_parallel_lines_from_a_far_anchor():
    """Regression: a point given far along line 1 must not cost accuracy in the feet.

    Nearly parallel axes have their common normal ~offset / sin away, and a DH frame placed there is
    the anchor of the next pair. The normal equations used to take dot products of that lever L and
    lose ~eps * L / sin^2 along the lines (here ~4 mm), so the x axis through the feet missed the other
    line by ~eps * L / sin (here ~1e-9 m; in the property tests 0.1 % of a rounded robot's size). The
    fix re-anchors line 1 at the foot of p2 first.
    """
    sin = 4e-7
    misses = []
    for seed in range(10):
        # generic orientations: no exact zeros in the products
        R = se3.matrix_from_rpy(np.random.default_rng(seed).uniform(-np.pi, np.pi, 3))
        u1, u2 = R @ [0.0, 0.0, 1.0], R @ unit([sin, 0.0, 1.0])
        p2 = R @ [0.0, 1e-3, 0.0]  # 1 mm off line 1; the common normal is at the origin
        far = closest_points(2.7 * u1, u1, p2, u2)  # line 1 anchored 2.7 m from the normal
        x = unit(np.cross(u1, u2))
        # distance from line 1 of the x axis through c2 (the requirement for a DH frame placed at c2)
        misses.append(closest_points(far.c2, x, np.zeros(3), u1).distance)
        np.testing.assert_allclose(far.c1, np.zeros(3), atol=1e-6)  # feet: ~eps * 1e-3 / sin^2 along the lines
        np.testing.assert_allclose(far.c2, p2, atol=1e-6)
    # eps * 1e-3 m / 4e-7 ~ 5e-13 expected; before the fix ~eps * 2.7 m / 4e-7 ~ 1e-9
    assert max(misses) < 2e-11


def test_common_normal_of_parallel_lines_passes_through_origin_point():
    p1, u1 = np.array([1.0, 2.0, 3.0]), unit([1, 1, 0])
    p2 = p1 + np.array([0, 0, 0.5]) + 7 * u1
    origin = p1 + 2.0 * u1 + np.array([0.3, -0.3, 0])  # off the line: its foot is used
    cn = common_normal(p1, u1, p2, u1, origin=origin)
    np.testing.assert_allclose(cn.c1, p1 + 2.0 * u1, atol=EXACT)
    np.testing.assert_allclose(cn.c2, p1 + 2.0 * u1 + [0, 0, 0.5], atol=EXACT)
    assert cn.distance == pytest.approx(0.5)
    # anti-parallel: same normal
    cn2 = common_normal(p1, u1, p2, -u1, origin=origin)
    np.testing.assert_allclose(cn2.c2, cn.c2, atol=EXACT)


def test_point_line_foot():
    p, u = np.array([1.0, 0, 0]), unit([0, 1, 1])
    foot = point_line_foot(np.array([3.0, 2.0, 0.0]), p, u)
    np.testing.assert_allclose(foot, [1.0, 1.0, 1.0], atol=EXACT)


# ----------------------------------------------------------------------------- relations
def six_relations(scale: float = 1.0):
    """Line pairs (p1, u1, p2, u2) with each relation, built by hand, lengths in units of ``scale``."""
    rng = np.random.default_rng(7)
    p1, u1 = rng.normal(size=3) * scale, unit(rng.normal(size=3))
    perp = unit(np.cross(u1, rng.normal(size=3)))
    tilted = unit(u1 + 0.7 * perp)
    normal = unit(np.cross(u1, tilted))
    return {
        AxisRelation.SKEW: (p1, u1, p1 + 0.3 * scale * normal + 0.2 * scale * tilted, tilted),
        AxisRelation.PARALLEL: (p1, u1, p1 + 0.4 * scale * perp + 1.5 * scale * u1, u1),
        AxisRelation.ANTI_PARALLEL: (p1, u1, p1 + 0.4 * scale * perp - 0.5 * scale * u1, -u1),
        AxisRelation.COINCIDENT: (p1, u1, p1 + 0.9 * scale * u1, u1),
        AxisRelation.ANTI_COINCIDENT: (p1, u1, p1 - 0.9 * scale * u1, -u1),
        AxisRelation.INTERSECTING: (p1, u1, p1 + 0.5 * scale * u1 + 0.25 * scale * tilted, tilted),
    }


@pytest.mark.parametrize("scale", [1.0, 1000.0, 1e-3])
def test_classify_all_six_relations(scale):
    for relation, (p1, u1, p2, u2) in six_relations(scale).items():
        assert classify(p1, u1, p2, u2, scale) is relation, relation


def test_classify_is_about_the_lines_not_the_points_on_them():
    for relation, (p1, u1, p2, u2) in six_relations().items():
        assert classify(p1 - 3 * u1, u1, p2 + 2 * u2, u2) is relation


def test_the_same_robot_in_millimetres_classifies_the_same():
    """A robot built with each relation, scaled by 1000, classifies axis pair by axis pair the same."""
    pairs = six_relations()
    frames = []
    for p1, u1, p2, u2 in pairs.values():
        for p, u in ((p1, u1), (p2, u2)):
            x = unit(np.cross(u, [0.3, 0.5, 0.7]))
            frames.append(se3.homogeneous(np.column_stack([x, np.cross(u, x), u]), p))
    frames.append(frames[-1])
    robot = Robot(np.array(frames), default_joints(["revolute"] * (len(frames) - 1)))
    F = np.array(robot.frames)
    F[:, :3, 3] *= 1000.0
    robot_mm = Robot(F, robot.joints)
    assert robot_mm.scale == pytest.approx(1000.0 * robot.scale)

    def relations(r: Robot):
        return [classify(r.points[i], r.axes[i], r.points[i + 1], r.axes[i + 1], r.scale)
                for i in range(0, r.n, 2)]

    assert relations(robot) == list(pairs) == relations(robot_mm)


@pytest.mark.parametrize("unit_length", [1.0, 1000.0])
def test_meeting_tolerance_is_relative_to_the_robot_size(unit_length):
    """Axes 1e-12 robot sizes apart meet (rounding noise); 1e-6 robot sizes apart do not, in m and mm."""
    u1, u2 = np.array([0.0, 0, 1]), np.array([1.0, 0, 0])
    for gap, expected in ((1e-12, AxisRelation.INTERSECTING), (1e-6, AxisRelation.SKEW)):
        p2 = np.array([0.0, gap * unit_length, 0.3 * unit_length])
        assert classify(np.zeros(3), u1, p2, u2, scale=unit_length) is expected
    for gap, expected in ((1e-12, AxisRelation.COINCIDENT), (1e-6, AxisRelation.PARALLEL)):
        p2 = np.array([gap * unit_length, 0.0, 0.3 * unit_length])
        assert classify(np.zeros(3), u1, p2, u1, scale=unit_length) is expected


def test_angle_tolerance_boundary():
    """Directions 1e-10 rad apart are parallel (noise); 1e-6 rad apart are not."""
    u1 = np.array([0.0, 0, 1])
    p2 = np.array([0.5, 0, 0])
    assert classify(np.zeros(3), u1, p2, unit([1e-10, 1e-10, 1]), 1.0) is AxisRelation.PARALLEL
    assert classify(np.zeros(3), u1, p2, unit([0, 1e-6, 1]), 1.0) is AxisRelation.SKEW
    assert classify(np.zeros(3), u1, p2, -unit([1e-10, 0, 1]), 1.0) is AxisRelation.ANTI_PARALLEL
    assert 1e-10 < ANGLE_TOL < 1e-6 and LENGTH_TOL < 1e-6


def test_cross_and_norm_match_numpy():
    from robkin.lines import cross, norm

    rng = np.random.default_rng(7)
    for a, b in rng.normal(size=(50, 2, 3)):
        np.testing.assert_array_equal(cross(a, b), np.cross(a, b))
        assert norm(a) == pytest.approx(float(np.linalg.norm(a)), rel=1e-15)
    np.testing.assert_array_equal(cross([1, 0, 0], [0, 1, 0]), [0.0, 0.0, 1.0])


def test_frame_with_z_is_a_rotation_along_the_direction():
    """``lines.frame_with_z``: a proper rotation whose z column is the direction normalised, the identity
    for +z, and still one for directions along or near the base x axis (where its x comes from y)."""
    from robkin.lines import frame_with_z

    assert np.array_equal(frame_with_z(np.array([0.0, 0.0, 2.0])), np.eye(3))
    rng = np.random.default_rng(3)
    for z in [np.array([1.0, 0.0, 0.0]), np.array([-3.0, 0.1, 0.0]), *rng.normal(size=(50, 3))]:
        R = frame_with_z(z)
        assert np.allclose(R.T @ R, np.eye(3), atol=1e-15) and np.isclose(np.linalg.det(R), 1.0, atol=1e-15)
        assert np.allclose(R[:, 2], z / np.linalg.norm(z), atol=1e-16)
