"""Hayati's parameters (representations/hayati.py): the link transform against its definition, exact
conversions where DH is exact, round trips, and rows that stay short between nearly parallel axes."""

from __future__ import annotations

import math

import numpy as np
import pytest

import robkin
from robkin import se3
from robkin.representations.hayati import HAYATI_COLUMNS, hayati_matrix, hayati_params_between
from robkin.representations.rpy_xyz import RPYTable
from test_urdf import robot_file

EXACT = 1e-12


def test_link_transform_is_rz_tz_tx_rx_ry():
    rng = np.random.default_rng(0)
    for a, d, alpha, theta, beta in rng.uniform(-3, 3, size=(50, 5)):
        expected = se3.rot_z(theta) @ se3.trans(0, 0, d) @ se3.trans(a, 0, 0) @ se3.rot_x(alpha) @ se3.rot_y(beta)
        np.testing.assert_allclose(hayati_matrix(a, d, alpha, theta, beta), expected, atol=1e-15)


def test_params_between_recover_rows_of_the_built_branch():
    """Rows with |theta| <= pi/2 (the branch the converter builds) are recovered exactly."""
    rng = np.random.default_rng(1)
    prev = se3.homogeneous(se3.matrix_from_rpy(rng.uniform(-3, 3, 3)), rng.normal(size=3))
    for _ in range(200):
        row = (rng.normal(), rng.normal(), rng.uniform(-3.1, 3.1), rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5))
        back = hayati_params_between(prev, prev @ hayati_matrix(*row))
        np.testing.assert_allclose(back, row, atol=1e-11)


def test_ur5_hayati_is_its_dh_table_with_beta_zero():
    """Between UR5's parallel axes (2, 3, 4) Hayati's rows have d = 0 and beta = 0: they are the DH rows."""
    robot = robkin.load(robot_file("ur_description/urdf/ur5_robot.urdf"), tip_link="tool0")
    hay, dh = robkin.hayati_from_robot(robot), robkin.dh_from_robot(robot)
    np.testing.assert_allclose(hay.rows[:, :4], dh.rows, atol=EXACT)
    assert np.all(hay.rows[:, 4] == 0.0)
    q = robot.random_q(50, rng=2)
    np.testing.assert_allclose(hay.fk(q), robot.fk(q), atol=EXACT)


def test_written_hayati_table_reads_back_unchanged():
    rows = np.array([[0.0, 0.3, math.pi / 2, 0.0, 0.0],
                     [0.4, 0.0, 2e-9, 0.1, -3e-9],  # a Hayati row: axes 2 and 3 nearly parallel
                     [0.3, 0.0, 0.0, 0.0, 1e-7],
                     [0.0, 0.1, 0.0, 0.0, 0.0]])
    table = robkin.HayatiTable(rows, [robkin.Joint(f"j{i + 1}") for i in range(4)])
    robot = robkin.robot_from_hayati(table)
    assert robot.frames_from == "hayati"
    back = robkin.hayati_from_robot(robot)
    np.testing.assert_allclose(back.rows, rows, atol=EXACT)
    q = robot.random_q(20, rng=3)
    np.testing.assert_allclose(back.fk(q), table.fk(q), atol=EXACT)


def test_hayati_section_in_documents_and_cli(tmp_path, capsys):
    from robkin.cli import main

    urdf = robot_file("ur_description/urdf/ur5_robot.urdf")
    out = tmp_path / "ur5_hayati.yaml"
    assert main(["convert", urdf, "--tip-link", "tool0", "--to", "hayati", "-o", str(out)]) == 0
    import yaml

    doc = yaml.safe_load(out.read_text())
    assert set(doc["hayati"]) == {"base", "rows", "tool", "base_mass"}  # UR5 base_link's mass: base_mass
    assert list(doc["hayati"]["rows"][0]) == [*HAYATI_COLUMNS, "m", "r", "I"]  # UR5's mass properties
    back, robot = robkin.load(out), robkin.load(urdf, tip_link="tool0")
    q = robot.random_q(20, rng=4)
    np.testing.assert_allclose(back.fk(q), robot.fk(q), atol=EXACT)
    capsys.readouterr()
    assert main(["convert", urdf, "--tip-link", "tool0", "--to", "hayati"]) == 0
    text = capsys.readouterr().out
    assert "beta" in text and "Hayati" in text


@pytest.mark.parametrize("tilt", [1e-2, 1e-4, 1e-6, 1e-8, 1e-10])
def test_nearly_parallel_rows_stay_short_and_exact(tilt):
    """Two parallel axes 0.4 apart, one tilted towards the other: DH's common normal lies ~0.4 / tilt
    away; Hayati's row stays 0.4 long and carries the tilt in beta (or alpha)."""
    rows = np.array([[0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0.3], [math.pi / 2, 0, 0, 0, 0, 0],
                     [0, tilt, 0, 0.4, 0, 0], [0, 0, 0, 0.3, 0, 0], [0, 0, 0, 0.1, 0, 0]], dtype=float)
    robot = RPYTable(rows, [robkin.Joint(f"j{i + 1}") for i in range(4)]).to_robot()
    table = robkin.hayati_from_robot(robot)
    q = robot.random_q(100, rng=5)
    np.testing.assert_allclose(table.fk(q), robot.fk(q), atol=EXACT * robot.scale)
    assert np.abs(table.rows[:, :2]).max() <= 0.4 + EXACT
    assert abs(table.rows[1, 4]) == pytest.approx(tilt, rel=1e-6)  # the tilt is beta of row 2
