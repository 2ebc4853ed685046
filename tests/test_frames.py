"""Placing DH-style frames on joint axes (representations/frames.py): the geometric step every
conversion shares. Checked against the DH definition itself: a frame's x axis must be the common
normal of the two axes, crossing both at right angles."""

from __future__ import annotations

import math

import numpy as np
import pytest

from robkin import se3
from robkin.lines import closest_points
from robkin.representations.frames import (approx_dh_params, common_normal_frame, dh_params_between,
                                           frame_from_zx, is_identity, mdh_params_between, satisfies_normal)

#: rounding noise of a handful of products, with margin
EXACT = 1e-12


def unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def frame_on(p, u, x_hint=(0.3, 0.5, 0.7)) -> np.ndarray:
    return frame_from_zx(np.asarray(p, float), unit(u), np.cross(unit(u), x_hint))


def assert_frame(F: np.ndarray) -> None:
    np.testing.assert_allclose(F[:3, :3] @ F[:3, :3].T, np.eye(3), atol=EXACT)
    assert np.linalg.det(F[:3, :3]) == pytest.approx(1.0)


def on_line(point, p, u, tol=EXACT) -> bool:
    d = np.asarray(point) - p
    return bool(np.linalg.norm(d - np.dot(d, u) * u) <= tol)


# ----------------------------------------------------------------------------- parameter extraction
def test_dh_params_between_recovers_random_rows():
    rng = np.random.default_rng(0)
    prev = se3.homogeneous(se3.matrix_from_rpy(rng.uniform(-3, 3, 3)), rng.normal(size=3))
    for _ in range(200):
        row = (rng.normal(), rng.normal(), rng.uniform(-np.pi, np.pi), rng.uniform(-np.pi, np.pi))
        back = dh_params_between(prev, prev @ se3.dh_matrix(*row))
        np.testing.assert_allclose(back, row, atol=1e-11)


def test_mdh_params_between_recovers_random_rows():
    rng = np.random.default_rng(1)
    prev = se3.homogeneous(se3.matrix_from_rpy(rng.uniform(-3, 3, 3)), rng.normal(size=3))
    for _ in range(200):
        row = (rng.normal(), rng.normal(), rng.uniform(-np.pi, np.pi), rng.uniform(-np.pi, np.pi))
        back = mdh_params_between(prev, prev @ se3.mdh_matrix(*row))
        np.testing.assert_allclose(back, row, atol=1e-11)


def test_approx_dh_params_is_exact_for_reachable_targets():
    rng = np.random.default_rng(2)
    prev = se3.homogeneous(se3.matrix_from_rpy(rng.uniform(-3, 3, 3)), rng.normal(size=3))
    for _ in range(100):
        row = (rng.normal(), rng.normal(), rng.uniform(-3.1, 3.1), rng.uniform(-3.1, 3.1))
        target = prev @ se3.dh_matrix(*row)
        got = approx_dh_params(prev, target)
        np.testing.assert_allclose(se3.dh_matrix(*got), se3.dh_matrix(*row), atol=1e-10)


def test_approx_dh_params_ties_do_not_depend_on_rounding_noise():
    """Regression: a target whose x axis lies in prev's x-z plane is a tie for the sign of theta.

    The sign was read from y0 . x1 without a margin, so the same tool computed twice (read in, then
    through the GJD) got theta = +1 or -1 by rounding noise, and a written DH table did not read back
    as the same table.
    """
    prev = np.eye(4)
    # x1 in prev's x-z plane exactly, then nudged across the plane by rounding-sized amounts
    x1 = np.array([0.5403023058681398, 0.0, -0.8414709848078965])
    z1 = np.array([0.0, 1.0, 0.0])
    rows = []
    for nudge in (0.0, 1e-17, -1e-17, 1e-13, -1e-13):
        x = unit(x1 + [0.0, nudge, 0.0])
        target = se3.homogeneous(np.column_stack([x, np.cross(z1, x), z1]), [0.1, 0.0, 0.2])
        rows.append(approx_dh_params(prev, target))
    np.testing.assert_allclose(rows, np.broadcast_to(rows[0], (5, 4)), atol=1e-12)
    assert rows[0][3] > 0  # ties go to +


# ----------------------------------------------------------------------------- frame placement
def axis_pairs():
    """(p_a, u_a, p_b, u_b) for each relation, all with exact geometry."""
    ua = unit([0.2, -0.3, 1.0])
    pa = np.array([0.1, 0.2, 0.3])
    perp = unit(np.cross(ua, [1.0, 0.0, 0.0]))
    tilted = unit(ua + 1.3 * perp)
    normal = unit(np.cross(ua, tilted))
    return {
        "skew": (pa, ua, pa + 0.4 * normal + 0.2 * tilted + 0.3 * ua, tilted),
        "intersecting": (pa, ua, pa + 0.3 * ua + 0.2 * tilted, tilted),
        "parallel": (pa, ua, pa + 0.5 * perp + 0.7 * ua, ua),
        "anti-parallel": (pa, ua, pa + 0.5 * perp - 0.7 * ua, -ua),
        "coincident": (pa, ua, pa + 0.6 * ua, ua),
        "anti-coincident": (pa, ua, pa - 0.6 * ua, -ua),
    }


@pytest.mark.parametrize("relation", list(axis_pairs()))
def test_standard_dh_frame_sits_on_b_with_x_along_the_common_normal(relation):
    pa, ua, pb, ub = axis_pairs()[relation]
    prev = frame_on(pa - 0.1 * ua, ua)
    F = common_normal_frame(pa, ua, pb, ub, on="b", prev=prev, scale=1.0)
    assert_frame(F)
    np.testing.assert_allclose(F[:3, 2], ub, atol=EXACT)  # z along axis B
    assert on_line(F[:3, 3], pb, ub)  # origin on axis B
    assert satisfies_normal(F, pa, ua, 1.0)  # x crosses axis A at a right angle
    # the DH row read back from prev reproduces F exactly (F is a valid DH successor of prev)
    np.testing.assert_allclose(prev @ se3.dh_matrix(*dh_params_between(prev, F)), F, atol=EXACT)
    theta = dh_params_between(prev, F)[3]
    assert abs(theta) <= np.pi / 2 + 1e-12  # the documented sign choice of x
    if relation == "coincident":
        np.testing.assert_allclose(dh_params_between(prev, F)[2], 0.0, atol=EXACT)  # alpha = 0
    if relation == "anti-coincident":
        assert abs(dh_params_between(prev, F)[2]) == pytest.approx(np.pi)  # alpha = pi
    if relation in ("parallel", "anti-parallel"):
        assert dh_params_between(prev, F)[1] == pytest.approx(0.0, abs=EXACT)  # d = 0: normal through prev


@pytest.mark.parametrize("relation", list(axis_pairs()))
def test_modified_dh_frame_sits_on_a_with_x_towards_b(relation):
    pa, ua, pb, ub = axis_pairs()[relation]
    prev = frame_on(pa, ua)  # an MDH "previous" frame whose x crosses A (here: its origin is on A)
    F = common_normal_frame(pa, ua, pb, ub, on="a", prev=prev, scale=1.0)
    assert_frame(F)
    np.testing.assert_allclose(F[:3, 2], ua, atol=EXACT)
    assert on_line(F[:3, 3], pa, ua)
    assert satisfies_normal(F, pb, ub, 1.0)  # x crosses axis B at a right angle


def test_skew_frame_is_at_the_closest_points():
    pa, ua, pb, ub = axis_pairs()["skew"]
    prev = frame_on(pa, ua)
    F = common_normal_frame(pa, ua, pb, ub, on="b", prev=prev, scale=1.0)
    cn = closest_points(pa, ua, pb, ub)
    np.testing.assert_allclose(F[:3, 3], cn.c2, atol=EXACT)
    np.testing.assert_allclose(abs(np.dot(F[:3, 0], unit(cn.c2 - cn.c1))), 1.0, atol=EXACT)


def test_a_frame_that_already_satisfies_the_convention_is_kept():
    pa, ua, pb, ub = axis_pairs()["skew"]
    prev = frame_on(pa, ua)
    F = common_normal_frame(pa, ua, pb, ub, on="b", prev=prev, scale=1.0)
    flipped = F @ se3.rot_z(np.pi)  # x reversed: still a valid DH frame, but not the canonical sign
    kept = common_normal_frame(pa, ua, pb, ub, on="b", prev=prev, scale=1.0, keep=flipped)
    np.testing.assert_array_equal(kept, flipped)
    wrong = F @ se3.trans(0.0, 0.0, 0.1)  # slid along the axis: x no longer meets axis A
    assert not satisfies_normal(wrong, pa, ua, 1.0)
    np.testing.assert_allclose(common_normal_frame(pa, ua, pb, ub, on="b", prev=prev, scale=1.0, keep=wrong),
                               F, atol=EXACT)


def test_frame_from_zx_and_is_identity():
    F = frame_from_zx(np.array([1.0, 2, 3]), np.array([0, 0, 2.0]), np.array([1.0, 0, 5]))
    np.testing.assert_allclose(F, se3.trans(1, 2, 3), atol=EXACT)
    assert is_identity(np.eye(4), 1.0)
    assert is_identity(se3.trans(1e-13, 0, 0), 1.0)
    assert not is_identity(se3.trans(1e-13, 0, 0), 1e-3)  # relative to the robot's size
    assert not is_identity(se3.rot_z(1e-9), 1.0)
    assert math.isclose(dh_params_between(np.eye(4), np.eye(4))[3], 0.0)


def test_frame_from_zx_is_a_rotation_even_when_x_is_nearly_along_z():
    """Regression: x given ~1e-13 off z (a common-normal direction that is rounding noise, between
    coincident axes far from the base) left x . z ~ 1e-3 after one Gram-Schmidt pass; the frame was
    then no rotation and DH rows read from it broke FK by 1e-4 of the robot size."""
    rng = np.random.default_rng(3)
    worst = 0.0
    for _ in range(100):
        z = unit(rng.normal(size=3))
        x = 2429.0 * z + 1e-10 * unit(np.cross(z, rng.normal(size=3)))  # far point minus far point
        F = frame_from_zx(np.zeros(3), z, x)
        worst = max(worst, np.abs(F[:3, :3].T @ F[:3, :3] - np.eye(3)).max())
        np.testing.assert_allclose(F[:3, 2], z, atol=EXACT)
    assert worst < 1e-15  # a few roundings of unit-size numbers


@pytest.mark.parametrize("unit_length", [1e-3, 1.0, 1e3])
def test_parallel_axes_choose_the_same_x_in_any_length_unit(unit_length):
    """Regression: the sign test of x between parallel axes took the unnormalised normal, so its tie
    margin (on a cosine) was in length units: axes 1e-9 m off a tie got one sign in m, the other in mm."""
    prev = np.eye(4)
    for offset in (-1e-9, -1e-10, 1e-10, 0.0, -1e-6):
        p_b = np.array([offset, 1.0, 0.0]) * unit_length  # parallel to z, nearly along prev's y
        F = common_normal_frame(np.zeros(3), np.array([0.0, 0, 1]), p_b, np.array([0.0, 0, 1]), on="b",
                                prev=prev, scale=unit_length)
        reference = common_normal_frame(np.zeros(3), np.array([0.0, 0, 1]), p_b / unit_length,
                                        np.array([0.0, 0, 1]), on="b", prev=prev, scale=1.0)
        np.testing.assert_allclose(F[:3, :3], reference[:3, :3], atol=EXACT)
        np.testing.assert_allclose(F[:3, 3], reference[:3, 3] * unit_length, atol=EXACT * unit_length)


def test_approx_dh_params_length_signs_do_not_depend_on_rounding_noise():
    """Regression: the tie margin of the d and a signs was relative to |o1 - o0|, so a target 1e-13
    from the last frame (1e-3 from the base) had d = +-1e-13 decided by 1e-19 of rounding noise."""
    prev = se3.rot_z(-np.pi / 2) @ se3.rot_x(np.pi)
    prev[:3, 3] = [-8.414709848078966e-04, -4.596976941318603e-04, 0.0]
    rows = []
    for noise in (0.0, 1e-19, -1e-19):
        # same orientation, 1e-13 off along prev's y: the x lines are 1e-13 apart (|d| = 1e-13) and
        # the sign of d, from (o1 - o0) . z0 = 0, is a tie
        target = prev @ se3.trans(0.0, 1e-13, 0.0)
        target[2, 3] += noise
        rows.append(approx_dh_params(prev, target))
    assert abs(rows[0][1]) == pytest.approx(1e-13, rel=1e-3)
    np.testing.assert_allclose(rows, np.broadcast_to(rows[0], (3, 4)), atol=1e-18)
