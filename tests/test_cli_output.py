"""The output conventions every command shares: one JSON style (indented, full precision, joint names
alongside values), a "wrote PATH" line per file, and a warning naming each joint outside its limits."""

from __future__ import annotations

import json
import math
import sys

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import robkin
from robkin import se3
from robkin.cli import main
from robkin.examples import EXAMPLES_DIR
from robkin.io.files.jsontext import dumps

RRPR = str(EXAMPLES_DIR / "rrpr.yaml")
SCARA = str(EXAMPLES_DIR / "scara.yaml")
Q_RRPR = "3*pi/4,-pi/4,0.3,-3*pi/4"

LIMITED = """\
robkin: 1
name: limited
joints:
  - {name: shoulder, type: revolute, limits: {lower: -1, upper: 1}}
  - {name: slide, type: prismatic, limits: {lower: 0, upper: 0.5}}
  - {name: wrist, type: revolute}
dh:
  rows: [[0, 0.2, -pi/2, 0], [0.3, 0, pi/2, 0], [0.1, 0, 0, 0]]
"""


def test_json_style_rows_on_one_line_full_precision_and_no_nan():
    text = dumps({"T": np.eye(4) * -0.0, "x": np.float64(0.1 + 0.2), "bad": [math.nan, math.inf],
                  "n": np.int64(3), "ok": np.bool_(True), "names": ("a", "b")})
    assert text.splitlines()[:3] == ["{", '  "T": [', "    [0.0, 0.0, 0.0, 0.0],"]
    back = json.loads(text)
    assert back["x"] == 0.1 + 0.2                       # the shortest repr reads back bit-exact
    assert back["bad"] == [None, None] and back["n"] == 3 and back["ok"] is True and back["names"] == ["a", "b"]
    assert dumps([-0.0], exact=True) == "[-0.0]"                 # documents keep every bit
    # a long run of numbers is split one per line instead of making one very long line
    assert len(dumps(list(np.linspace(0, 1, 40) / 3)).splitlines()) == 42


def test_every_json_output_has_the_same_style(capsys, tmp_path):
    runs = [["fk", RRPR, "--q", Q_RRPR, "--json"], ["info", RRPR, "--json"], ["check", RRPR, RRPR, "--json"],
            ["ik", SCARA, "--pose", "10,5,-2,0,0,0.5", "--json"], ["convert", RRPR, "--to", "dh", "--json"],
            ["estimate", "--pose", "0.4,0.6,0.7,pi,0,pi/2", "--joints", "4", "--json"]]
    for argv in runs:
        main(argv)
        text = capsys.readouterr().out
        json.loads(text)
        lines = text.splitlines()
        assert lines[0] == "{" and lines[1].startswith('  "'), argv
        # no line holds a bare number: numbers stay on the line of their vector / matrix row
        assert not any(line.strip().rstrip(",").replace(".", "").replace("-", "").isdigit() for line in lines), argv


def test_fk_json_adds_position_rpy_quaternion_and_joint_names(capsys):
    assert main(["fk", RRPR, "--q", Q_RRPR, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    T = np.array(out["T"])
    q = [3 * math.pi / 4, -math.pi / 4, 0.3, -3 * math.pi / 4]
    np.testing.assert_array_equal(T, robkin.load(RRPR).fk(q))
    assert out["joints"] == ["joint1", "joint2", "joint3", "joint4"] and out["q"] == q
    assert out["position"] == T[:3, 3].tolist()
    np.testing.assert_allclose(se3.matrix_from_rpy(out["rpy"]), T[:3, :3], atol=1e-15)
    x, y, z, w = Rotation.from_matrix(T[:3, :3]).as_quat()  # scipy: (x, y, z, w)
    sign = 1.0 if w >= 0 else -1.0
    assert out["quaternion"] == pytest.approx({"w": sign * w, "x": sign * x, "y": sign * y, "z": sign * z},
                                              abs=1e-15)


def test_ik_json_has_names_residuals_and_method(capsys):
    assert main(["ik", SCARA, "--pose", "10,5,-2,0,0,0.5", "--all", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    robot = robkin.load(SCARA)
    assert out["joints"] == [j.name for j in robot.joints] and out["method"] == "scara"
    assert out["success"] is True and out["reason"] is None and len(out["solutions"]) == 2
    target = se3.homogeneous(se3.matrix_from_rpy([0, 0, 0.5]), [10, 5, -2])
    for s in out["solutions"]:
        T = robot.fk(s["q"])
        assert s["position_error"] == pytest.approx(np.linalg.norm(T[:3, 3] - target[:3, 3]), abs=1e-15)
        assert 0 <= s["orientation_error"] < 1e-12 and s["position_error"] < 1e-12


def test_estimate_json_holds_dh_rows_that_reach_the_pose(capsys):
    assert main(["estimate", "--pose", "0.4,0.6,0.7,pi,0,pi/2", "--joints", "4", "--type", "D", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)["D"]
    rows = [[r["a"], r["d"], r["alpha"], r["theta"]] for r in out["dh"]["rows"]]
    T = np.eye(4)
    for row in rows:
        T = T @ se3.dh_matrix(*row)
    target = se3.homogeneous(se3.matrix_from_rpy([math.pi, 0, math.pi / 2]), [0.4, 0.6, 0.7])
    np.testing.assert_allclose(T, target, atol=1e-9)   # the documented tool is the identity here
    assert out["type"] == "D" and out["length"] > 0


def test_written_files_are_announced_on_stderr(capsys, tmp_path):
    out = tmp_path / "d.yaml"
    assert main(["estimate", "--pose", "0.4,0.6,0.7,pi,0,pi/2", "--joints", "4", "-o", str(out)]) == 0
    assert capsys.readouterr().err.splitlines()[-1] == f"wrote {out}"
    folder = tmp_path / "all"
    assert main(["estimate", "--pose", "0.4,0.6,0.7,pi,0,pi/2", "--joints", "4", "--type", "all",
                 "-o", str(folder)]) == 0
    err = capsys.readouterr().err.splitlines()
    assert [line for line in err if line.startswith("wrote")] == [f"wrote {folder / f'estimate_{k}.yaml'}"
                                                                  for k in "ABCD"]
    assert main(["convert", RRPR, "--to", "poe", "-o", str(tmp_path / "p.json")]) == 0
    assert capsys.readouterr().err == f"wrote {tmp_path / 'p.json'}\n"


def test_fk_warns_per_joint_outside_its_limits(capsys, tmp_path):
    path = tmp_path / "limited.yaml"
    path.write_text(LIMITED)
    assert main(["fk", str(path), "--q", "1.5,0.2,9"]) == 0
    err = capsys.readouterr().err.splitlines()
    assert err == ["robkin: warning: --q: joint 'shoulder' = 1.5 rad is outside its limits [-1, 1] rad"]
    assert main(["fk", str(path), "--q", "1,-0.1,0", "--json"]) == 0   # at a limit is inside
    captured = capsys.readouterr()
    assert captured.err == "robkin: warning: --q: joint 'slide' = -0.1 m is outside its limits [0, 0.5] m\n"
    json.loads(captured.out)   # stdout stays clean JSON


def test_plot_warns_at_home_outside_the_limits(capsys, tmp_path):
    pytest.importorskip("matplotlib")
    path = tmp_path / "limited.yaml"
    path.write_text(LIMITED.replace("lower: 0, upper: 0.5", "lower: 0.1, upper: 0.5"))
    out = tmp_path / "p.svg"
    assert main(["plot", str(path), "-o", str(out)]) == 0
    err = capsys.readouterr().err.splitlines()
    assert err == ["robkin: warning: home (q = 0): joint 'slide' = 0 m is outside its limits [0.1, 0.5] m",
                   f"wrote {out}"]


OPTIMIZE = ["estimate", "--pose", "0.8,0.2,0.5,0,1.57,0", "--pose", "0.8,0.4,0.5,0,1.57,0.3", "--joints", "5",
            "--type", "D", "--optimize", "length"]


def test_optimize_shows_progress_on_a_terminal_and_nothing_when_piped(capsys, monkeypatch):
    assert main(OPTIMIZE) == 0
    assert "optimising" not in capsys.readouterr().err      # stderr is not a terminal here
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    assert main(OPTIMIZE) == 0
    err = capsys.readouterr().err
    assert "optimising" in err and "1/1" in err


def test_the_panda_at_zero_is_outside_joint4s_limits(capsys):
    import glob
    import os

    found = glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                   "example-robot-data", "robots", "panda_description", "urdf", "panda.urdf"))
    if not found:
        pytest.skip("example-robot-data's panda.urdf is not installed")
    assert main(["fk", found[0], "--tip-link", "panda_hand_tcp", "--q", "0,0,0,0,0,0,0"]) == 0
    # the Panda's URDF limits joint 4 to [-3.0718, -0.0698]: its q = 0 is not reachable
    assert capsys.readouterr().err == ("robkin: warning: --q: joint 'panda_joint4' = 0 rad is outside its limits "
                                       "[-3.0718, -0.0698] rad\n")
