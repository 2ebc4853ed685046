"""Batch conversions (``dh_from_robots`` / ``mdh_from_robots``): each table is the single call's table,
bit for bit, whatever the mix of robots (every axis relation, prismatic and flipped joints, joint
counts, rounded inputs with nearly parallel axes, robots read from tables of the same kind), and its FK
equals the robot's."""

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
#: FK agreement relative to the robot's size (as in test_properties: closed-form chains of ~10
#: products per joint, each rounding at ~1e-16, with margin for far common-normal feet).
FK_TOL = 1e-9


def _rounded(robot: Robot) -> Robot:
    """The robot with its frames typed to 6 decimals (in its own size): exactly parallel axes become
    ~1e-7 from parallel, the near-parallel case whose tables warn."""
    unit = robot.scale
    F = robot.frames.copy()
    F[:, :3, 3] = np.round(F[:, :3, 3] / unit, 6) * unit
    F[:, :3, :3] = np.round(F[:, :3, :3], 6)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ProjectionWarning)  # rounded rotations are projected, on purpose
        return Robot(F, robot.joints)


@st.composite
def robot_mix(draw) -> list[Robot]:
    """1-6 robots of 1-6 joints: drawn ones (every axis relation), some with rounded frames, some read
    from a DH or MDH table (whose own frames the conversion of the same kind keeps)."""
    out = []
    for _ in range(draw(st.integers(1, 6))):
        kind = draw(st.sampled_from(["drawn", "rounded", "dh", "mdh"]))
        if kind in ("drawn", "rounded"):
            robot = draw(robot_specs(max_joints=6)).robot
            out.append(_rounded(robot) if kind == "rounded" else robot)
        else:
            n = draw(st.integers(1, 6))
            table_cls = robkin.DHTable if kind == "dh" else robkin.MDHTable
            out.append(table_cls(draw(dh_rows(n)), draw(joint_lists(n))).to_robot())
    return out


def _assert_same_table(a, b, what: str) -> None:
    assert type(a) is type(b), what
    np.testing.assert_array_equal(a.rows, b.rows, err_msg=what)
    np.testing.assert_array_equal(a.base, b.base, err_msg=what)
    np.testing.assert_array_equal(a.tool, b.tool, err_msg=what)
    assert a.joints == b.joints, what


@pytest.mark.filterwarnings("ignore::robkin.errors.ConditioningWarning")
@settings(max_examples=60, **SETTINGS)
@given(robots=robot_mix())
@pytest.mark.parametrize("single, batch", [(robkin.dh_from_robot, robkin.dh_from_robots),
                                           (robkin.mdh_from_robot, robkin.mdh_from_robots)])
def test_batch_tables_are_the_single_tables_bit_for_bit(single, batch, robots):
    tables = batch(robots)
    assert len(tables) == len(robots)
    for i, (robot, table) in enumerate(zip(robots, tables)):
        _assert_same_table(table, single(robot), f"robots[{i}]")


@settings(max_examples=40, **SETTINGS)
@given(specs=st.lists(robot_specs(max_joints=6), min_size=1, max_size=5), seed=st.integers(0, 2**32 - 1))
@pytest.mark.parametrize("batch", [robkin.dh_from_robots, robkin.mdh_from_robots])
def test_batch_tables_reproduce_each_robots_fk(batch, specs, seed):
    robots = [s.robot for s in specs]
    rng = np.random.default_rng(seed)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConditioningWarning)  # drawn axes are exact: no table may warn
        tables = batch(robots)
    for robot, table in zip(robots, tables):
        Q = rng.uniform(-np.pi, np.pi, (16, robot.n))
        Q[:, ~robot.revolute] *= robot.scale / np.pi  # prismatic travel of about the robot's size
        A, B = table.fk(Q), robot.fk(Q)
        size = max(robot.scale, float(np.abs(B[:, :3, 3]).max()), float(np.abs(robot.frames[:, :3, 3]).max()))
        assert np.abs(A[:, :3, :3] - B[:, :3, :3]).max() <= FK_TOL
        assert np.abs(A[:, :3, 3] - B[:, :3, 3]).max() <= FK_TOL * size


@settings(max_examples=20, **SETTINGS)
@given(spec=robot_specs(max_joints=6), m=st.sampled_from([1, 2, 31, 33, 70]), seed=st.integers(0, 2**32 - 1))
def test_robots_fk_is_each_robots_own_fk_bit_for_bit(spec, m, seed):
    """The conversions' FK self-check walks each robot's m configurations as blocks (m across the block
    size of the kernels): the same bits as ``Robot.fk``, batch and one configuration at a time."""
    from robkin.compiled.conversions.frames import robots_fk
    from robkin.frame_stacks import local_transforms

    moved = se3.homogeneous(se3.matrix_from_rpy([0.1, -0.2, 0.3]), [0.5, 0.0, -0.1]) @ spec.robot.frames
    robots = [spec.robot, Robot(moved, spec.robot.joints)]      # two robots of the same joint count
    rng = np.random.default_rng(seed)
    Q = rng.uniform(-np.pi, np.pi, (len(robots), m, spec.robot.n))
    out = robots_fk(np.stack([local_transforms(r.frames) for r in robots]),
                    np.stack([r.revolute for r in robots]), Q)
    assert out.shape == (len(robots), m, 4, 4)
    for k, robot in enumerate(robots):
        np.testing.assert_array_equal(out[k], robot.fk(Q[k]))
        np.testing.assert_array_equal(out[k, -1], robot.fk(Q[k, -1]))


def test_a_table_read_in_comes_back_unchanged_in_a_batch():
    rows = np.array([[0.0, 0.089159, np.pi / 2, 0.0], [-0.425, 0.0, 0.0, 0.0], [-0.39225, 0.0, 0.0, 0.0],
                     [0.0, 0.10915, np.pi / 2, 0.0], [0.0, 0.09465, -np.pi / 2, 0.0], [0.0, 0.0823, 0.0, 0.0]])
    ur5 = robkin.DHTable(rows, [Joint(f"j{i + 1}") for i in range(6)])
    other = robkin.RPYTable(np.column_stack([np.full((5, 3), 0.3), np.full((5, 3), 0.2)]),
                            [Joint(f"k{i + 1}") for i in range(3)]).to_robot()
    tables = robkin.dh_from_robots([other, ur5.to_robot(), other])
    # its own frames are kept: the rows come back to rounding (1e-16 m: a - a_prev of the FK frames)
    np.testing.assert_allclose(tables[1].rows, rows, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(tables[1].base, np.eye(4))
    _assert_same_table(tables[0], tables[2], "the same robot twice")


def test_mixed_joint_counts_keep_their_order():
    robots = [robkin.DHTable(np.tile([0.1 * (n + 1), 0.2, np.pi / 2, 0.0], (n, 1)),
                             [Joint(f"j{i}") for i in range(n)]).to_robot().replace(frames_from=None)
              for n in (3, 1, 6, 3)]
    tables = robkin.mdh_from_robots(robots)
    assert [t.n for t in tables] == [3, 1, 6, 3]
    for robot, table in zip(robots, tables):
        q = np.linspace(-1.0, 1.0, robot.n)
        np.testing.assert_allclose(table.fk(q), robot.fk(q), atol=1e-12)


def test_batch_warnings_name_the_robot_and_state_its_error():
    good = robkin.DHTable([[0.3, 0.1, np.pi / 2, 0.0], [0.2, 0.0, 0.0, 0.0]],
                          [Joint("a"), Joint("b")]).to_robot().replace(frames_from=None)
    # joint 2's axis tilted 1e-9 rad towards joint 1's, in their plane: below ANGLE_TOL, so DH drops it
    frames = np.stack([np.eye(4), se3.trans(0.5, 0.0, 0.0) @ se3.rot_y(1e-9), se3.trans(1.0, 0.0, 0.0)])
    tilted = Robot(frames, [Joint("a"), Joint("b")])
    with pytest.warns(ConditioningWarning) as single:
        robkin.dh_from_robot(tilted)
    with pytest.warns(ConditioningWarning) as batch:
        robkin.dh_from_robots([good, tilted, good])
    assert len(batch) == 1 and len(single) == 1
    assert str(batch[0].message) == "robots[1]: " + str(single[0].message)
    assert "joints 1 and 2 are 1e-09 rad from parallel" in str(single[0].message)
    assert batch[0].filename == __file__  # the warning points at the caller's line


def test_batch_of_nothing_and_bad_items():
    assert robkin.dh_from_robots([]) == []
    assert robkin.mdh_from_robots(iter([])) == []
    robot = robkin.DHTable([[0.3, 0.1, 0.0, 0.0]], [Joint("a")]).to_robot()
    with pytest.raises(InputError, match=r"robots\[1\]: expected a robkin.Robot, got DHTable"):
        robkin.dh_from_robots([robot, robkin.dh_from_robot(robot)])
