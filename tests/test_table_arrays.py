"""``robot_from_<rep>`` with plain arrays: the numbers of a table are a table (revolute by default),
and anything else is one InputError naming the function and what it takes."""

from __future__ import annotations

import math

import numpy as np
import pytest

import robkin
from robkin.errors import InputError

H = math.pi / 2
#: UR5's published standard DH (a, d, alpha, theta), metres and radians
UR5 = np.array([(0, 0.089159, H, 0), (-0.425, 0, 0, 0), (-0.39225, 0, 0, 0),
                (0, 0.10915, H, 0), (0, 0.09465, -H, 0), (0, 0.0823, 0, 0)])


def test_dh_array_is_the_table():
    robot = robkin.robot_from_dh(UR5)
    table = robkin.DHTable(UR5, [robkin.Joint(f"j{i}") for i in range(6)])
    q = np.random.default_rng(1).uniform(-3, 3, (20, 6))
    np.testing.assert_allclose(robot.fk(q), table.fk(q), atol=1e-14)
    assert all(j.revolute for j in robot.joints)
    # UR5 at q = 0: tool at x = -(0.425 + 0.39225), y = -(0.10915 + 0.0823), z = 0.089159 - 0.09465
    np.testing.assert_allclose(robot.fk(np.zeros(6))[:3, 3], [-0.81725, -0.19145, -0.005491], atol=1e-12)


def test_other_arrays_and_joint_types():
    assert [j.type for j in robkin.robot_from_mdh(UR5[:4], joints="RRPR").joints] == \
        ["revolute", "revolute", "prismatic", "revolute"]
    hay = robkin.robot_from_hayati(np.hstack([UR5, np.zeros((6, 1))]))
    np.testing.assert_allclose(hay.fk(np.zeros(6)), robkin.robot_from_dh(UR5).fk(np.zeros(6)), atol=1e-14)
    poe = robkin.robot_from_poe([[0, 0, 1, 0, 0, 0], [0, 0, 0, 0, 0, 1]], M=np.eye(4))
    assert poe.joints[1].type == "prismatic"  # a screw without rotation
    np.testing.assert_allclose(poe.fk([0.0, 0.25])[:3, 3], [0, 0, 0.25], atol=1e-15)
    assert robkin.robot_from_rpy(np.zeros((5, 6))).n == 3
    assert robkin.robot_from_gjd(np.stack([np.eye(4)] * 3), "RP").joints[1].type == "prismatic"
    base = np.eye(4)
    base[2, 3] = 1.0
    assert robkin.robot_from_dh(UR5, base=base).fk(np.zeros(6))[2, 3] == pytest.approx(1 - 0.005491, abs=1e-12)


@pytest.mark.parametrize("fn, bad, words", [
    (robkin.robot_from_dh, "0 0 0 0", "got a str"),
    (robkin.robot_from_dh, np.zeros((3, 3)), "(n, 4) array"),
    (robkin.robot_from_dh, [[0, 0, 0, "x"]], "of numbers"),
    (robkin.robot_from_dh, [[0, np.inf, 0, 0]], "row 0 d must be a finite number"),
    (robkin.robot_from_mdh, {"rows": []}, "got a dict"),
    (robkin.robot_from_hayati, UR5, "(n, 5) array"),
    (robkin.robot_from_poe, np.zeros((2, 4)), "(n, 6) array of screws"),
    (robkin.robot_from_rpy, np.zeros((2, 6)), "(n + 2, 6)"),
    (robkin.robot_from_gjd, np.zeros((3, 3)), "(n + 1, 4, 4)"),
])
def test_bad_arrays_are_one_line_input_errors(fn, bad, words):
    with pytest.raises(InputError) as exc:
        fn(bad)
    msg = str(exc.value)
    assert words in msg and fn.__name__ in msg and "\n" not in msg


def test_wrong_table_kind_and_joint_string():
    mdh = robkin.mdh_from_robot(robkin.robot_from_dh(UR5))
    with pytest.raises(InputError, match="robot_from_mdh"):
        robkin.robot_from_dh(mdh)
    with pytest.raises(InputError, match="letters R"):
        robkin.robot_from_dh(UR5, joints="RRRRRX")
    with pytest.raises(InputError, match="array of rows"):
        robkin.robot_from_dh(robkin.dh_from_robot(robkin.robot_from_dh(UR5)), joints="RRRRRR")
