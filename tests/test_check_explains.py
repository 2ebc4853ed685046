"""``robkin check`` that explains everything: past the first difference (row by row, as the same kind
of table), the base frame behind a half turn at joint 1, the verdict first for different joint counts,
units in every length and angle; ``info`` says what its size means.

The vendor table is Universal Robots' published DH of the UR10e; the URDF is example-robot-data's
UR10 (the previous generation), whose published DH (test_vendor_tables.UR_DH) differs from the UR10e's
in d1, a2, a3, d4, d5 and d6 - the six differences the check must name, with both values.
"""

from __future__ import annotations

import json
import math

import pytest

from robkin.cli import main
from test_urdf import robot_file
from test_vendor_tables import UR_DH

#: Universal Robots' published DH of the UR10e (a, d, alpha, theta), metres and radians
UR10E_DH = [(0, 0.1807, math.pi / 2, 0), (-0.6127, 0, 0, 0), (-0.57155, 0, 0, 0),
            (0, 0.17415, math.pi / 2, 0), (0, 0.11985, -math.pi / 2, 0), (0, 0.11655, 0, 0)]


@pytest.fixture
def vendor(tmp_path):
    path = tmp_path / "ur10e_dh.txt"
    path.write_text("".join(" ".join(repr(float(v)) for v in row) + "\n" for row in UR10E_DH))
    return str(path)


def _check(vendor, base, capsys, *extra):
    urdf = robot_file("ur_description/urdf/ur10_robot.urdf")
    argv = ["check", vendor, urdf, "--from", "dh", "--tip-link", "-", "--tip-link", "tool0", *extra]
    if base:
        argv += ["--base-link", "-", "--base-link", base]
    status = main(argv)
    return status, capsys.readouterr().out


def test_every_differing_parameter_is_named(vendor, capsys):
    status, out = _check(vendor, "base", capsys, "--json")
    assert status == 1
    doc = json.loads(out)
    assert "unchecked" not in [j["status"] for j in doc["joints"]]
    got = {p["parameter"]: (p["a"], p["b"], p["unit"]) for p in doc["parameters"]}
    ur10 = UR_DH["ur10"]
    want = {"d1": (0.1807, ur10[0][1]), "a2": (-0.6127, ur10[1][0]), "a3": (-0.57155, ur10[2][0]),
            "d4": (0.17415, ur10[3][1]), "d5": (0.11985, ur10[4][1]), "d6": (0.11655, ur10[5][1])}
    assert set(got) == set(want), got
    for name, (a, b) in want.items():
        assert got[name][0] == pytest.approx(a, abs=1e-9) and got[name][1] == pytest.approx(b, abs=1e-9)
        assert got[name][2] == "m"
    assert all(j["status"] == "differs" for j in doc["joints"][1:])


def test_text_shows_parameters_with_units(vendor, capsys):
    status, out = _check(vendor, "base", capsys)
    assert status == 1
    assert "a2 -0.6127 vs -0.612 m" in out and "d6 0.11655 vs 0.0922 m" in out
    assert "0.0534 m apart" in out


def test_half_turn_at_joint_1_names_the_base_link_option(vendor, capsys):
    status, out = _check(vendor, None, capsys)  # the URDF's base_link: ROS's base, turned by pi
    assert status == 1
    note = next(line for line in out.splitlines() if line.startswith("note:"))
    assert "--base-link 'base'" in note and "half a turn" in note
    # UR5: the published table and the URDF from base_link are the same mechanism, joint 1 offset pi
    ur5 = vendor.replace("ur10e_dh.txt", "ur5_dh.txt")
    with open(ur5, "w") as f:
        f.write("".join(" ".join(repr(float(v)) for v in row) + "\n" for row in UR_DH["ur5"]))
    assert main(["check", ur5, robot_file("ur_description/urdf/ur5_robot.urdf"), "--from", "dh", "--tip-link", "-",
                 "--tip-link", "tool0", "--json", "--tol", "1e-9"]) == 1
    doc = json.loads(capsys.readouterr().out)
    assert doc["equivalent"] and abs(abs(doc["joints"][0]["offset"]) - math.pi) < 1e-9
    assert any("--base-link 'base'" in n for n in doc["notes"])


def test_same_robot_has_no_hint(vendor, capsys):
    ur5 = vendor.replace("ur10e_dh.txt", "ur5_dh.txt")
    with open(ur5, "w") as f:
        f.write("".join(" ".join(repr(float(v)) for v in row) + "\n" for row in UR_DH["ur5"]))
    assert main(["check", ur5, robot_file("ur_description/urdf/ur5_robot.urdf"), "--from", "dh", "--base-link", "-",
                 "--base-link", "base", "--tip-link", "-", "--tip-link", "tool0", "--tol", "1e-9"]) == 0
    out = capsys.readouterr().out
    assert "note:" not in out and "verdict: same robot" in out


def test_different_joint_counts_give_the_verdict_first(vendor, capsys):
    from robkin.examples import EXAMPLES_DIR

    assert main(["check", str(EXAMPLES_DIR / "rrpr.yaml"), vendor, "--from", "dh"]) == 1
    out = capsys.readouterr().out
    assert out.splitlines()[0] == "verdict: different robots: joint counts differ: A has 4, B has 6"


def test_info_says_what_its_size_is(capsys):
    from robkin.examples import EXAMPLES_DIR

    assert main(["info", str(EXAMPLES_DIR / "rrpr.yaml")]) == 0
    out = capsys.readouterr().out
    assert "size: 0.5831 m (the largest distance of a joint axis or of the tool from the base origin" in out
    assert "position 0.3 0 0.5 m, rpy 1.571 0 0 rad" in out
