"""Tables a controller can use: no length beyond ~10 robot sizes without a warning naming the axes.

The SO-100 (example-robot-data ``so100.urdf``) has joint 1 6.3e-6 rad off the base z axis and 4.5 cm
aside: the common normal of the two lines lies ~7 km away. Standard DH now turns frame {0} onto
joint 1's axis as modified DH does (d1 = 0.119 m, the shoulder height, as in modified DH), and a table
that cannot avoid a long length (nearly parallel consecutive axes in standard DH) says so.
"""

from __future__ import annotations

import math
import re
import warnings

import numpy as np
import pytest

import robkin
from robkin.errors import ConditioningWarning
from robkin.representations.rpy_xyz import RPYTable
from test_near_parallel import tilted_arm
from test_urdf import robot_file

H = math.pi / 2


def _convert(fn, robot):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        table = fn(robot)
    return table, [str(w.message) for w in caught if issubclass(w.category, ConditioningWarning)]


def _fk_error(table, robot) -> float:
    q = robot.random_q(100, rng=3)
    A, B = table.fk(q), robot.fk(q)
    return float(np.abs(A - B).max())


def test_so100_standard_dh_is_short_and_exact():
    robot = robkin.load(robot_file("so_arm_description/urdf/so100.urdf"))
    # the geometry the issue describes: joint 1 ~6.3e-6 rad off the base z axis, ~4.5 cm aside
    tilt = np.linalg.norm(np.cross([0, 0, 1], robot.axes[0]))
    assert 6e-6 < tilt < 7e-6
    dh, warned = _convert(robkin.dh_from_robot, robot)
    mdh, _ = _convert(robkin.mdh_from_robot, robot)
    assert not warned
    lengths = np.concatenate([dh.rows[:, :2].ravel(), dh.base[:3, 3], dh.tool[:3, 3]])
    assert np.abs(lengths).max() < 1.0  # was d1 = -7144 m, base z = +7144 m
    # frame {0} on joint 1's axis at the shoulder height: d1 is modified DH's d1 (0.119 m)
    assert dh.rows[0, 1] == pytest.approx(mdh.rows[0, 1], abs=1e-9)
    assert dh.rows[0, 1] == pytest.approx(0.119, abs=1e-3)
    assert np.linalg.norm(np.cross(dh.base[:3, 2], robot.axes[0])) < 1e-12
    assert _fk_error(dh, robot) < 1e-12


def test_long_length_warns_naming_the_axes_and_hayati():
    """A UR5-like arm with joints 2 and 3 1e-6 rad from parallel: standard DH's common normal is
    ~1e5 sizes out; the warning names the pair, the values with their unit, and hayati."""
    robot = tilted_arm(1e-6, "in-plane")
    dh, warned = _convert(robkin.dh_from_robot, robot)
    long = [m for m in warned if "times the robot's size" in m]
    assert np.abs(dh.rows[:, :2]).max() > 10 * robot.scale
    assert len(long) == 1, warned
    assert "joints 2 and 3" in long[0] and "hayati" in long[0] and " m" in long[0]
    assert re.search(r"\bd\d = -?[0-9.e+]+ m", long[0])
    hayati, warned_h = _convert(robkin.hayati_from_robot, robot)
    assert not [m for m in warned_h if "times the robot's size" in m]
    assert np.abs(hayati.rows[:, :2]).max() < 10 * robot.scale


def test_short_tables_do_not_warn():
    robot = robkin.load(robot_file("ur_description/urdf/ur5_robot.urdf"), base_link="base", tip_link="tool0")
    for fn in (robkin.dh_from_robot, robkin.mdh_from_robot, robkin.hayati_from_robot):
        _, warned = _convert(fn, robot)
        assert not warned
