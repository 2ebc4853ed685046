"""The calibrated robot as a drop-in replacement (issue 32, item 6) and the outputs for a controller
(issue 34, item 4): every source link name kept, --keep-frames, joint offsets, the table in the source's
convention, filtered targets."""

from __future__ import annotations

import csv
import re

import numpy as np
import pytest

import robkin
from robkin import se3
from robkin.calibration import simulate, write_measurements_csv
from robkin.calibration.simulation import perturbed
from robkin.cli import main
from test_urdf import robot_file

XARM7 = "xarm_description/urdf/xarm7.urdf"
Z1 = "z1_description/urdf/z1.urdf"
UR5 = "ur_description/urdf/ur5_robot.urdf"
PANDA = "panda_description/urdf/panda.urdf"


def _links(text: str) -> list[str]:
    return re.findall(r'<link name="([^"]+)"', re.sub(r"<!--.*?-->", "", text, flags=re.S))


def _measure(tmp_path, path, tip, seed=1, poses=60):
    robot = robkin.load(path, tip_link=tip)
    sim = simulate(robot, poses, seed=seed, noise=10e-6)
    csv_path = tmp_path / "m.csv"
    write_measurements_csv(csv_path, robot, sim.q, sim.positions)
    return robot, sim, csv_path


@pytest.mark.parametrize("rel, tip", [(XARM7, "link7"), (Z1, "link06"), (Z1, None)])
def test_calibrated_urdf_keeps_every_source_link_name(tmp_path, capsys, rel, tip):
    """Before: the tool link being the last moving link sent the writer to a plain chain (world, base,
    link1.., tool): xArm7's link_base and link_eef and every Z1 link were renamed or dropped."""
    path = robot_file(rel)
    robot, sim, m = _measure(tmp_path, path, tip)
    out = tmp_path / "cal.urdf"
    assert main(["calibrate", path, str(m), "-o", str(out)] + (["--tip-link", tip] if tip else [])) == 0
    capsys.readouterr()
    source = _links(open(path).read())
    written = _links(out.read_text())
    assert written[:len(source)] == source and written[len(source):] == ["marker"]
    # the default contract holds: world @ fk(tool) predicts the measurements, the tool being the marker link
    cal = robkin.load(out, tip_link="marker")
    pred = (cal.world @ cal.fk(sim.q))[:, :3, 3]
    assert np.sqrt(np.mean(np.sum((pred - sim.positions) ** 2, axis=1))) < 30e-6   # noise 10 um: observed ~15 um


@pytest.mark.parametrize("rel, tip", [(UR5, "tool0"), (XARM7, "link_eef"), (XARM7, "link7")])
def test_keep_frames_is_a_drop_in_replacement(tmp_path, capsys, rel, tip):
    """--keep-frames: the nominal world, the tool link at the calibrated flange (millimetres from the
    nominal one, not the 30-70 mm of the marker), the marker its own link predicting the measurements
    through the base pose the report gives."""
    import json

    path = robot_file(rel)
    robot, sim, m = _measure(tmp_path, path, tip)
    out = tmp_path / "cal.urdf"
    assert main(["calibrate", path, str(m), "-o", str(out), "--tip-link", tip, "--keep-frames", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    names = _links(out.read_text())
    assert names[:-1] == _links(open(path).read()) and names[-1] == "marker"
    cal = robkin.load(out, tip_link=tip)
    assert np.allclose(cal.world, robot.world, atol=1e-12)
    q0 = robot.home()
    # observed 1.6-3.2 mm (the truth's +-1 mm per joint frame, accumulated); the marker sits 20-80 mm off
    assert np.linalg.norm(cal.fk(q0)[:3, 3] - robot.fk(q0)[:3, 3]) < 0.008
    marker = robkin.load(out, tip_link="marker")
    W = np.array(report["world"]) @ se3.inv(cal.world)   # the measuring frame -> the written world
    pred = (W @ cal.world @ marker.fk(sim.q))[:, :3, 3]
    assert np.sqrt(np.mean(np.sum((pred - sim.positions) ** 2, axis=1))) < 30e-6
    # check compares like with like: the same world, every joint named, the largest difference a calibration's
    assert main(["check", path, str(out), "--tip-link", tip]) == 1
    text = capsys.readouterr().out
    assert "world: same" in text          # before: the base stood in the measuring frame, metres away


def test_joint_offsets_file_gives_the_zero_offsets_of_the_truth(tmp_path, capsys):
    """A truth whose only errors are joint zero offsets: the offsets file gives them (joint 1's goes to the
    free base and the last joint's to the free marker: written 0, identified false)."""
    path = robot_file(PANDA)
    robot = robkin.load(path, tip_link="panda_link8")
    motions = np.zeros((robot.n, 6))
    motions[:, 5] = np.radians([0.1, -0.2, 0.15, 0.05, -0.1, 0.2, 0.3])
    truth = perturbed(robot, motions)
    q = robot.random_q(60, rng=3)
    W = se3.homogeneous(se3.matrix_from_rpy([0.1, 0.2, 0.3]), [1.0, 0.5, 0.2])
    marker = se3.trans(0.01, 0.02, 0.05)
    pos = (W @ truth.fk(q) @ marker)[:, :3, 3] + np.random.default_rng(0).normal(0, 5e-6, (60, 3))
    m = tmp_path / "m.csv"
    write_measurements_csv(m, robot, q, pos)
    offsets = tmp_path / "offsets.csv"
    assert main(["calibrate", path, str(m), "-o", str(tmp_path / "c.yaml"), "--tip-link", "panda_link8",
                 "--offsets", str(offsets)]) == 0
    capsys.readouterr()
    rows = list(csv.DictReader(offsets.open()))
    assert [r["joint"] for r in rows] == [j.name for j in robot.joints]
    assert {r["unit"] for r in rows} == {"rad"}
    got = {r["joint"]: (float(r["offset"]), r["identified"]) for r in rows}
    for i in range(1, robot.n - 1):
        value, identified = got[robot.joints[i].name]
        assert identified == "true"
        # observed: within 3e-6 rad for joints 2-5 (standard deviations 2-7e-6), 3e-5 for joint 6 (4e-5: the
        # wrist's short lever); the offsets are 1-3.5e-3 rad
        assert value == pytest.approx(motions[i, 5], abs=3e-5 if i < 5 else 1.5e-4)


def test_table_in_the_source_convention_and_filtered_targets(tmp_path, capsys):
    panda = robot_file(PANDA)
    dh = tmp_path / "panda_dh.yaml"
    assert main(["convert", panda, "--tip-link", "panda_link8", "--to", "dh", "-o", str(dh)]) == 0
    robot, sim, m = _measure(tmp_path, str(dh), None, seed=3)
    T = robot.fk(robot.random_q(6, rng=5))
    targets = tmp_path / "targets.csv"
    with targets.open("w") as f:
        f.write("x,y,z,qw,qx,qy,qz\n")
        for Ti in T:
            f.write(",".join(repr(float(v)) for v in [*Ti[:3, 3], *se3.quaternion_from_matrix(Ti[:3, :3])]) + "\n")
    table, cmd, out = tmp_path / "cal_dh.csv", tmp_path / "cmd.csv", tmp_path / "cal.yaml"
    assert main(["calibrate", str(dh), str(m), "-o", str(out), "--keep-frames", "--table", str(table),
                 "--filter", str(targets), "--filtered", str(cmd)]) == 0
    capsys.readouterr()
    kept = robkin.load(out)
    tab = robkin.load(table)
    assert tab.frames_from == "dh"                      # the source's convention
    q = robot.random_q(8, rng=6)
    assert np.allclose(tab.fk(q), kept.fk(q), atol=1e-12)
    rows = list(csv.DictReader(cmd.open()))
    assert len(rows) == len(T)
    for Ti, r in zip(T, rows):
        qc = np.array([float(r[j.name]) for j in robot.joints])
        assert r["reached"] == "true" and float(r["error"]) < 1e-8
        assert np.allclose(kept.fk(qc), Ti, atol=1e-8)          # the calibrated robot reaches the target
        pose = robot.fk(qc)                                      # the filtered pose: the nominal FK of qc
        assert np.allclose([float(r[c]) for c in "xyz"], pose[:3, 3], atol=1e-12)
        # the filter's correction is a calibration's: millimetres, not zero
        assert 1e-5 < np.linalg.norm(pose[:3, 3] - Ti[:3, 3]) < 0.02


def test_table_of_a_urdf_needs_a_convention(tmp_path, capsys):
    path = robot_file(UR5)
    robot, sim, m = _measure(tmp_path, path, "tool0", poses=30)
    assert main(["calibrate", path, str(m), "-o", str(tmp_path / "c.yaml"), "--tip-link", "tool0",
                 "--table", str(tmp_path / "t.csv")]) == 2
    err = capsys.readouterr().err
    assert "no table convention of its own" in err and "Traceback" not in err
    assert not (tmp_path / "c.yaml").exists() and not (tmp_path / "t.csv").exists()
    assert main(["calibrate", path, str(m), "-o", str(tmp_path / "c.yaml"), "--tip-link", "tool0",
                 "--table", str(tmp_path / "t.csv"), "--to", "hayati"]) == 0
    assert robkin.load(tmp_path / "t.csv").n == 6
