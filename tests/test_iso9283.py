"""ISO 9283 pose accuracy and repeatability (robkin check MODEL MEASUREMENTS --report iso9283 | html).

The figures are checked against a hand computation from the standard's formulas (ISO 9283:1998, 7.2.1
and 7.2.2) on a small example, and against the distribution of Gaussian noise on a simulated robot.
"""

from __future__ import annotations

import json
import re
import sys

import numpy as np
import pytest

import robkin
from robkin.calibration import write_measurements_csv
from robkin.calibration.iso9283 import clusters, iso9283, pose_figures
from robkin.calibration.simulation import random_configurations
from robkin.cli import main
from test_urdf import robot_file

UR5 = "ur_description/urdf/ur5_robot.urdf"


def rot(axis: int, deg: float) -> np.ndarray:
    c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
    i, j = ((1, 2), (2, 0), (0, 1))[axis]
    R = np.eye(3)
    R[i, i] = R[j, j] = c
    R[i, j], R[j, i] = -s, s
    return R


def test_figures_match_a_hand_computation_from_the_standard():
    """Four attained positions (mm) around a barycentre at the origin, command (1, 2, 2):
    AP_p = |(0, 0, 0) - (1, 2, 2)| = 3; AP_x, AP_y, AP_z = -1, -2, -2.
    l_j = 0, 3, 6, sqrt(45) = 6.70820; l_bar = 15.70820 / 4 = 3.92705;
    S_l = sqrt(((-3.92705)^2 + (-0.92705)^2 + 2.07295^2 + 2.78115^2) / 3) = sqrt(28.31300 / 3) = 3.07208;
    RP_l = 3.92705 + 3 * 3.07208 = 13.14330.
    Orientations Rx(0.1, 0.2, 0.3, 0.4 deg) against a command Rx(0): AP_a = 0.25 deg, AP_b = AP_c = 0;
    S_a = sqrt((0.15^2 + 0.05^2 + 0.05^2 + 0.15^2) / 3) = 0.129099 deg, RP_a = 0.387298 deg."""
    P = np.array([(0.0, 0.0, 0.0), (3.0, 0.0, 0.0), (0.0, 6.0, 0.0), (-3.0, -6.0, 0.0)])
    R = np.stack([rot(0, a) for a in (0.1, 0.2, 0.3, 0.4)])
    f = pose_figures(np.array([1.0, 2.0, 2.0]), P, np.eye(3), R)
    assert f.n == 4
    assert f.ap_p == pytest.approx(3.0, abs=1e-12)
    assert f.ap_xyz == pytest.approx([-1.0, -2.0, -2.0], abs=1e-12)
    assert f.l_bar == pytest.approx(3.92705, abs=1e-5)
    assert f.s_l == pytest.approx(3.07208, abs=1e-5)
    assert f.rp_l == pytest.approx(13.14330, abs=1e-5)
    assert np.degrees(f.ap_abc) == pytest.approx([0.25, 0.0, 0.0], abs=1e-9)
    assert np.degrees(f.rp_abc) == pytest.approx([0.387298, 0.0, 0.0], abs=1e-6)


def test_orientation_accuracy_wraps_at_half_a_turn():
    """Command Rz(179 deg), attained Rz(-179) and Rz(179): the deviations are +2 and 0 deg, AP_c = 1 deg
    (averaging the angles themselves would give 0 - 179 = -179 deg)."""
    f = pose_figures(np.zeros(3), np.zeros((2, 3)), rot(2, 179.0), np.stack([rot(2, -179.0), rot(2, 179.0)]))
    assert np.degrees(f.ap_abc) == pytest.approx([0.0, 0.0, 1.0], abs=1e-9)
    assert np.degrees(f.rp_abc[2]) == pytest.approx(3 * np.sqrt(2.0), abs=1e-9)   # 3 * sqrt((1 + 1) / 1)


def test_one_measurement_has_accuracy_but_no_repeatability():
    f = pose_figures(np.zeros(3), np.array([[0.0, 3.0, 4.0]]))
    assert f.ap_p == pytest.approx(5.0) and f.rp_l is None and f.s_l is None


def test_clusters_group_equal_joint_values_in_order_of_first_appearance():
    q = np.array([[1.0, 2.0], [0.0, 0.0], [1.0, 2.0], [0.0, 0.0], [5.0, 5.0], [1.0, 2.0]])
    got = [c.tolist() for c in clusters(q)]
    assert got == [[0, 2, 5], [1, 3], [4]]


@pytest.fixture(scope="module")
def repeated():
    """A UR5 measured as its own model (only the base and marker unknown), 6 poses x 30 cycles, 20 um
    Gaussian noise per coordinate."""
    robot = robkin.load(robot_file(UR5), tip_link="tool0")
    rng = np.random.default_rng(4)
    q = np.repeat(random_configurations(robot, 6, rng), 30, axis=0)
    world = np.eye(4)
    world[:3, 3] = (1.2, -0.4, 0.3)
    marker = np.array([0.01, 0.02, 0.05])
    T = world @ robot.fk(q)
    pos = T[:, :3, :3] @ marker + T[:, :3, 3] + rng.normal(0.0, 20e-6, (len(q), 3))
    return robot, q, pos


def test_noise_alone_gives_the_repeatability_of_its_distribution(repeated):
    """With isotropic Gaussian noise s per coordinate, l_j / s follows the chi distribution with 3 degrees
    of freedom: mean 2 sqrt(2 / pi) = 1.5958, standard deviation sqrt(3 - 1.5958^2) = 0.6734, so RP_l
    tends to (1.5958 + 3 * 0.6734) s = 3.616 s; AP_p (the barycentre's error, s / sqrt(30) per
    coordinate, plus the base fit's) stays within a few micrometres."""
    robot, q, pos = repeated
    rep = iso9283(robot, q, pos)
    assert len(rep.poses) == 6 and all(p.n == 30 for p in rep.poses)
    rp = np.array([p.rp_l for p in rep.poses])
    assert np.mean(rp) == pytest.approx(3.616 * 20e-6, rel=0.15)   # 6 x 30 samples: ~6 % scatter observed
    assert max(p.ap_p for p in rep.poses) < 15e-6
    assert rep.stats["position_rms"] == pytest.approx(np.sqrt(3) * 20e-6, rel=0.15)


def test_cli_iso9283_json_and_text(repeated, tmp_path, capsys):
    robot, q, pos = repeated
    f = tmp_path / "m.csv"
    write_measurements_csv(f, robot, q, pos)
    path = robot_file(UR5)
    assert main(["check", path, str(f), "--tip-link", "tool0", "--report", "iso9283", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert len(d["poses"]) == 6 and d["poses"][1]["rows"] == list(range(32, 62))   # header on line 1
    ref = iso9283(robot, *read(f, robot))
    assert d["poses"][0]["RP_l"] == pytest.approx(ref.poses[0].rp_l, rel=1e-9)
    assert main(["check", path, str(f), "--tip-link", "tool0", "--report", "iso9283"]) == 0
    text = capsys.readouterr().out
    assert "AP_p mm" in text and "RP_l = l_bar + 3 S_l" in text and re.search(r"^P6 ", text, re.M)


def read(f, robot):
    from robkin.calibration import read_measurements

    m = read_measurements(f, robot)
    return m.q, m.positions


def test_cli_html_report_stands_alone_and_escapes_names(repeated, tmp_path, capsys):
    pytest.importorskip("matplotlib")
    robot, q, pos = repeated
    f = tmp_path / "a<b>&c.csv"
    write_measurements_csv(f, robot, q, pos + np.where(np.arange(len(q))[:, None] < 30, 1e-3, 0.0))
    out = tmp_path / "report.html"
    assert main(["check", robot_file(UR5), str(f), "--tip-link", "tool0", "--report", "html", "-o", str(out)]) == 1
    html = out.read_text()
    assert html.count("data:image/png;base64,") == 2           # per pose and per joint, embedded
    assert "a&lt;b&gt;&amp;c.csv" in html and "<b>" not in html
    assert "src=\"http" not in html and "<script" not in html   # nothing fetched, nothing run
    assert "RP_l mm" in html and "model vs measurements" in html   # the table and the diagnosis


def test_cli_html_without_matplotlib_is_one_line(repeated, tmp_path, capsys, monkeypatch):
    robot, q, pos = repeated
    f = tmp_path / "m.csv"
    write_measurements_csv(f, robot, q[:40], pos[:40])
    monkeypatch.setitem(sys.modules, "matplotlib", None)   # import matplotlib raises ImportError
    out = tmp_path / "r.html"
    assert main(["check", robot_file(UR5), str(f), "--tip-link", "tool0", "--report", "html", "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert "matplotlib" in err and len(err.splitlines()) == 1 and not out.exists()


@pytest.mark.parametrize("extra, message", [
    (["--report", "html"], "--report html: give -o REPORT.html"),
    (["-o", "r.html"], "-o: only --report html writes a file"),
    (["--report", "html", "-o", "r.txt"], "the report is written as .html"),
])
def test_cli_bad_report_options(repeated, tmp_path, capsys, extra, message):
    robot, q, pos = repeated
    f = tmp_path / "m.csv"
    write_measurements_csv(f, robot, q[:40], pos[:40])
    assert main(["check", robot_file(UR5), str(f), "--tip-link", "tool0"] + extra) == 2
    assert message in capsys.readouterr().err


def test_cli_report_needs_measurements(capsys):
    path = robot_file(UR5)
    assert main(["check", path, path, "--report", "iso9283"]) == 2
    assert "applies to a model against measurements" in capsys.readouterr().err
