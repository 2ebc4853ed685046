"""--degrees on the command line: convert's tables and documents, fk's q and rpy, ik's pose and q."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import yaml

import robkin
from robkin.cli import main
from test_urdf import robot_file

UR5 = "ur_description/urdf/ur5_robot.urdf"


def test_convert_table_in_degrees(capsys):
    assert main(["convert", robot_file(UR5), "--tip-link", "tool0", "--to", "dh", "--degrees"]) == 0
    out = capsys.readouterr().out
    assert "alpha (deg)" in out
    row1 = next(line for line in out.splitlines() if line.startswith("1 "))
    assert row1.split()[-2:] == ["-90", "0"]


def test_convert_document_in_degrees_reads_back(tmp_path, capsys):
    out = tmp_path / "ur5.yaml"
    assert main(["convert", robot_file(UR5), "--tip-link", "tool0", "--to", "mdh", "--degrees", "-o", str(out)]) == 0
    doc = yaml.safe_load(out.read_text())
    assert doc["angles"] == "degrees"
    assert doc["mdh"]["rows"][1]["alpha"] == pytest.approx(-90.0, abs=1e-9)
    assert doc["joints"][0]["limits"]["upper"] == pytest.approx(360.0, abs=1e-6)  # UR's +-2 pi
    robot, back = robkin.load(robot_file(UR5), tip_link="tool0"), robkin.load(out)
    q = robot.random_q(10, rng=0)
    np.testing.assert_allclose(back.fk(q), robot.fk(q), atol=1e-12)


def test_fk_and_ik_in_degrees_agree_with_radians(capsys):
    path = robot_file(UR5)
    assert main(["fk", path, "--tip-link", "tool0", "--q", "0,-90,90,0,45,0", "--degrees", "--json"]) == 0
    T_deg = np.array(json.loads(capsys.readouterr().out)["T"])
    assert main(["fk", path, "--tip-link", "tool0", "--q", "0,-pi/2,pi/2,0,pi/4,0", "--json"]) == 0
    T_rad = np.array(json.loads(capsys.readouterr().out)["T"])
    np.testing.assert_allclose(T_deg, T_rad, atol=1e-12)
    assert main(["ik", path, "--tip-link", "tool0", "--pose", "0.4,0.1,0.3,180,0,0", "--degrees", "--all",
                 "--json"]) == 0
    q_deg = np.array([s["q"] for s in json.loads(capsys.readouterr().out)["solutions"]])
    assert main(["ik", path, "--tip-link", "tool0", "--pose", "0.4,0.1,0.3,pi,0,0", "--all", "--json"]) == 0
    q_rad = np.array([s["q"] for s in json.loads(capsys.readouterr().out)["solutions"]])
    assert q_deg.shape == q_rad.shape and len(q_rad) > 0
    np.testing.assert_allclose(np.radians(q_deg), q_rad, atol=1e-9)
    assert main(["fk", path, "--tip-link", "tool0", "--q", "0,0,0,0,0,0", "--degrees"]) == 0
    assert "in degrees" in capsys.readouterr().out
    assert math.isclose(np.degrees(q_rad).max(), q_deg.max(), abs_tol=1e-7)
