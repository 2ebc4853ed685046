"""``hayati_from_robots``: each table is ``hayati_from_robot``'s, bit for bit, whatever the mix of robots
(every axis relation, prismatic and flipped joints, joint counts, rounded inputs with nearly parallel
axes, robots read from Hayati tables), and reproduces its robot's FK, also where axes are nearly parallel."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import robkin
from robkin import se3
from robkin.errors import ConditioningWarning, InputError, ProjectionWarning
from robkin.robot import Joint, Robot

from strategies import dh_rows, joint_lists, robot_specs

SETTINGS = dict(deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
#: FK agreement relative to the robot's size (as in test_convert_batch and test_properties).
FK_TOL = 1e-9


def _rounded(robot: Robot) -> Robot:
    """The robot with its frames typed to 6 decimals: exactly parallel axes become ~1e-7 from parallel."""
    F = robot.frames.copy()
    F[:, :3, 3] = np.round(F[:, :3, 3] / robot.scale, 6) * robot.scale
    F[:, :3, :3] = np.round(F[:, :3, :3], 6)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ProjectionWarning)
        return Robot(F, robot.joints)


@st.composite
def robot_mix(draw) -> list[Robot]:
    out = []
    for _ in range(draw(st.integers(1, 6))):
        kind = draw(st.sampled_from(["drawn", "rounded", "hayati"]))
        if kind == "hayati":
            n = draw(st.integers(1, 6))
            beta = draw(st.lists(st.floats(-0.05, 0.05), min_size=n, max_size=n))
            rows = np.column_stack([draw(dh_rows(n)), beta])
            out.append(robkin.HayatiTable(rows, draw(joint_lists(n))).to_robot())
        else:
            robot = draw(robot_specs(max_joints=6)).robot
            out.append(_rounded(robot) if kind == "rounded" else robot)
    return out


@settings(max_examples=60, **SETTINGS)
@given(robots=robot_mix())
def test_batch_tables_are_the_single_tables_bit_for_bit(robots):
    with warnings.catch_warnings(record=True) as batch_warnings:
        warnings.simplefilter("always")
        tables = robkin.hayati_from_robots(robots)
    assert len(tables) == len(robots)
    single_messages = []
    for i, (robot, table) in enumerate(zip(robots, tables)):
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            single = robkin.hayati_from_robot(robot)
        single_messages += [f"robots[{i}]: {x.message}" for x in w if issubclass(x.category, ConditioningWarning)]
        assert type(table) is robkin.HayatiTable
        np.testing.assert_array_equal(table.rows, single.rows, err_msg=f"robots[{i}]")
        np.testing.assert_array_equal(table.base, single.base, err_msg=f"robots[{i}]")
        np.testing.assert_array_equal(table.tool, single.tool, err_msg=f"robots[{i}]")
        assert table.joints == robot.joints
    assert sorted(str(x.message) for x in batch_warnings
                  if issubclass(x.category, ConditioningWarning)) == sorted(single_messages)


@settings(max_examples=40, **SETTINGS)
@given(robots=robot_mix(), seed=st.integers(0, 2**32 - 1))
def test_batch_tables_reproduce_each_robots_fk(robots, seed):
    rng = np.random.default_rng(seed)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConditioningWarning)  # Hayati rows are exact at every tilt
        tables = robkin.hayati_from_robots(robots)
    for robot, table in zip(robots, tables):
        Q = rng.uniform(-np.pi, np.pi, (16, robot.n))
        Q[:, ~robot.revolute] *= robot.scale / np.pi
        A, B = table.fk(Q), robot.fk(Q)
        size = max(robot.scale, float(np.abs(B[:, :3, 3]).max()), float(np.abs(robot.frames[:, :3, 3]).max()))
        assert np.abs(A[:, :3, :3] - B[:, :3, :3]).max() <= FK_TOL
        assert np.abs(A[:, :3, 3] - B[:, :3, 3]).max() <= FK_TOL * size


def test_nearly_parallel_axes_get_short_exact_rows_in_a_batch():
    # joint 2's axis tilted 1e-9 rad from joint 1's: DH drops the tilt (and warns), Hayati keeps it in beta
    frames = np.stack([np.eye(4), se3.trans(0.5, 0.0, 0.0) @ se3.rot_y(1e-9), se3.trans(1.0, 0.0, 0.0)])
    tilted = Robot(frames, [Joint("a"), Joint("b")])
    plain = robkin.DHTable([[0.3, 0.1, np.pi / 2, 0.0], [0.2, 0.0, 0.0, 0.0]], [Joint("a"), Joint("b")]).to_robot()
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConditioningWarning)
        tables = robkin.hayati_from_robots([plain, tilted])
    assert tables[1].rows[0, 4] == pytest.approx(1e-9, rel=1e-6)  # the tilt, as beta
    assert np.abs(tables[1].rows[:, :2]).max() <= 1.0  # no common normal far away
    np.testing.assert_allclose(tables[1].fk([0.3, -0.2]), tilted.fk([0.3, -0.2]), atol=1e-15)


def test_batch_of_nothing_and_bad_items():
    assert robkin.hayati_from_robots([]) == []
    robot = robkin.DHTable([[0.3, 0.1, 0.0, 0.0]], [Joint("a")]).to_robot()
    with pytest.raises(InputError, match=r"robots\[1\]: expected a robkin.Robot, got DHTable"):
        robkin.hayati_from_robots([robot, robkin.dh_from_robot(robot)])
