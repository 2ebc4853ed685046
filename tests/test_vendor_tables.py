"""The DH tables vendors publish, from their robots' URDFs: row for row, base identity, zero offsets.

The published tables are held here as data (metres, radians) and compared with what robkin writes
from the URDF; FK of every table is also compared with the URDF's own FK (pinocchio's, where the test
can load it) so that a table which matched the published numbers but not the robot would still fail.

- Universal Robots' DH parameter page (UR3, UR5, UR10; the controller's base frame is the URDF's
  ``base`` link, the flange is ``tool0``).
- Franka Emika's Panda, which Franka publishes as modified (Craig) DH with a flange row d = 0.107.
- KUKA's LBR iiwa 14 R820 (0.36 / 0.42 / 0.4 / 0.126 m), from a URDF fixture written from KUKA's
  published dimensions in the link-frame layout of the common ROS description.
"""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

import robkin
from robkin import se3
from test_urdf import robot_file

H = math.pi / 2

#: Universal Robots' published DH parameters (a, d, alpha, theta).
UR_DH = {
    "ur3": [(0, 0.1519, H, 0), (-0.24365, 0, 0, 0), (-0.21325, 0, 0, 0),
            (0, 0.11235, H, 0), (0, 0.08535, -H, 0), (0, 0.0819, 0, 0)],
    "ur5": [(0, 0.089159, H, 0), (-0.425, 0, 0, 0), (-0.39225, 0, 0, 0),
            (0, 0.10915, H, 0), (0, 0.09465, -H, 0), (0, 0.0823, 0, 0)],
    "ur10": [(0, 0.1273, H, 0), (-0.612, 0, 0, 0), (-0.5723, 0, 0, 0),
             (0, 0.163941, H, 0), (0, 0.1157, -H, 0), (0, 0.0922, 0, 0)],
}
#: Franka's published modified DH of the Panda (a_{i-1}, d_i, alpha_{i-1}, theta_i) and its flange.
PANDA_MDH = [(0, 0.333, 0, 0), (0, 0, -H, 0), (0, 0.316, H, 0), (0.0825, 0, H, 0),
             (-0.0825, 0.384, -H, 0), (0, 0, H, 0), (0.088, 0, H, 0)]
PANDA_FLANGE_D = 0.107
#: KUKA LBR iiwa 14 R820, standard DH (a, d, alpha, theta).
IIWA14_DH = [(0, 0.36, -H, 0), (0, 0, H, 0), (0, 0.42, H, 0), (0, 0, -H, 0),
             (0, 0.4, -H, 0), (0, 0, H, 0), (0, 0.126, 0, 0)]
IIWA14_URDF = os.path.join(os.path.dirname(__file__), "data", "iiwa14.urdf")

#: The UR URDFs write pi/2 as 1.57079632679 (4.9e-12 off) and pi as 3.14159265359: the geometry
#: they describe is that far from the published one, so the tables agree to this, not to rounding.
UR_TOL = 1e-10
#: Files written with full-precision angles: the tables agree to rounding of the frame algebra.
EXACT = 1e-12


def load_ur(name: str) -> robkin.Robot:
    """The UR arm from its URDF with UR's controller base frame (the ``base`` link) and ``tool0``."""
    path = robot_file(f"ur_description/urdf/{name}_robot.urdf")
    return robkin.load(path, base_link="base", tip_link="tool0")  # `base` is fixed above base_link


def assert_rows(got: np.ndarray, published, tol: float) -> None:
    np.testing.assert_allclose(got, np.array(published, dtype=float), rtol=0, atol=tol)


@pytest.mark.parametrize("name", list(UR_DH))
def test_universal_robots_dh_from_urdf(name):
    robot = load_ur(name)
    table = robkin.dh_from_robot(robot)
    assert_rows(table.rows, UR_DH[name], UR_TOL)
    np.testing.assert_array_equal(table.base, np.eye(4))  # d1 in row 1, not in a base transform
    np.testing.assert_array_equal(table.tool, np.eye(4))  # tool0 is UR's flange frame {6}
    q = robot.random_q(50, rng=1)
    np.testing.assert_allclose(table.fk(q), robot.fk(q), atol=EXACT)


def test_franka_panda_mdh_from_urdf():
    robot = robkin.load(robot_file("panda_description/urdf/panda.urdf"), tip_link="panda_link8")
    table = robkin.mdh_from_robot(robot)
    assert_rows(table.rows, PANDA_MDH, EXACT)
    assert np.all(table.rows[:, 3] == 0.0)  # zero offsets, exactly
    np.testing.assert_array_equal(table.base, np.eye(4))
    np.testing.assert_allclose(table.tool, se3.trans(0, 0, PANDA_FLANGE_D), atol=EXACT)
    q = robot.random_q(50, rng=2)
    np.testing.assert_allclose(table.fk(q), robot.fk(q), atol=EXACT)


def test_kuka_iiwa14_dh_from_urdf():
    robot = robkin.load(IIWA14_URDF)
    table = robkin.dh_from_robot(robot)
    assert_rows(table.rows, IIWA14_DH, EXACT)
    assert np.all(table.rows[:, [0, 3]] == 0.0)  # a and theta are exactly 0, not rounding noise
    np.testing.assert_array_equal(table.base, np.eye(4))
    np.testing.assert_array_equal(table.tool, np.eye(4))
    q = robot.random_q(50, rng=3)
    np.testing.assert_allclose(table.fk(q), robot.fk(q), atol=EXACT)


def test_iiwa14_fixture_agrees_with_pinocchio():
    """The fixture is a valid URDF of the published geometry: pinocchio's FK of it equals FK of the
    published table at random configurations."""
    pin = pytest.importorskip("pinocchio")
    model = pin.buildModelFromUrdf(IIWA14_URDF)
    data = model.createData()
    tip = model.getFrameId("iiwa_link_ee")
    published = robkin.DHTable(np.array(IIWA14_DH, dtype=float), [robkin.Joint(f"j{i + 1}") for i in range(7)])
    for q in np.random.default_rng(4).uniform(-2, 2, size=(20, 7)):
        pin.framesForwardKinematics(model, data, q)
        np.testing.assert_allclose(published.fk(q), data.oMf[tip].homogeneous, atol=EXACT)


def test_urdf_frames_are_not_kept():
    """A URDF joint frame that happens to satisfy the DH rule (UR5's wrist 1, turned by pi) is not
    copied into the table: the canonical frame gives theta = 0 where the URDF frame gave pi."""
    robot = load_ur("ur5")
    assert robot.frames_from is None
    assert np.all(np.abs(robkin.dh_from_robot(robot).rows[:, 3]) < UR_TOL)


def test_dh_table_frames_are_kept_so_tables_round_trip():
    """A DH table with a theta offset of pi (legal, though not canonical) reads back unchanged."""
    rows = np.array(UR_DH["ur5"], dtype=float)
    rows[3, 3] = math.pi
    table = robkin.DHTable(rows, [robkin.Joint(f"j{i + 1}") for i in range(6)])
    robot = table.to_robot()
    assert robot.frames_from == "dh"
    np.testing.assert_allclose(robkin.dh_from_robot(robot).rows, rows, atol=EXACT)
    # the same frames without their origin are placed canonically: theta back to 0
    plain = robot.replace(frames=robot.frames.copy())
    assert plain.frames_from is None
    assert abs(robkin.dh_from_robot(plain).rows[3, 3]) < EXACT


def test_table_output_notes_why_a_base_or_tool_is_needed():
    from robkin.io.tables.terminal import render

    text = render(robkin.load(IIWA14_URDF), "dh")
    assert "base: identity" in text and "note: base" not in text and "note: tool" not in text
    shifted = robkin.load(IIWA14_URDF)
    shifted = robkin.Robot(se3.trans(0.1, 0, 0) @ shifted.frames, shifted.joints)
    text = render(shifted, "dh")
    assert "note: base: joint 1's axis is not the robot base z axis" in text
    panda = robkin.load(robot_file("panda_description/urdf/panda.urdf"), tip_link="panda_link8")
    assert "note: tool: the tool frame is not the table's last frame" in render(panda, "mdh")


def test_cli_table_of_ur5_has_d1_in_row_1_and_no_base(capsys):
    from robkin.cli import main

    assert main(["convert", robot_file("ur_description/urdf/ur5_robot.urdf"), "--tip-link", "tool0",
                 "--to", "dh"]) == 0
    out = capsys.readouterr().out
    row1 = next(line for line in out.splitlines() if line.startswith("1 "))
    assert row1.split()[3:5] == ["0", "0.089159"]  # a, d of row 1
    assert "base: identity" in out and "tool (residual T_t): identity" in out
