"""The display rule of the text tables: values closer to 0 than 1e-9 (angles, unitless entries; lengths
times the robot's size) are shown as 0 with a note, while files and JSON keep every digit.

The case behind the rule: Universal Robots' URDFs write pi/2 as 1.57079632679, a real 4.9e-12 rad tilt
that conversions rightly keep, and that a table printed as ``-4.89657e-12`` where UR's published table
has 0.
"""

from __future__ import annotations

import json

import numpy as np

from robkin import Joint
from robkin.cli import main
from robkin.io.tables.views import DISPLAY_NOTE
from robkin.representations import DHTable, dh_from_robot

from test_urdf import robot_file
from test_vendor_tables import UR_DH

UR5 = "ur_description/urdf/ur5_robot.urdf"


def table_rows(text: str, n: int) -> list[list[str]]:
    """The cells of the n joint rows of the first table printed (after its title, header and rule)."""
    lines = text.splitlines()
    rule = next(i for i, line in enumerate(lines) if set(line.replace(" ", "")) == {"-"})
    return [line.split() for line in lines[rule + 1:rule + 1 + n]]


def test_ur5_dh_table_shows_zero_where_the_vendor_table_has_zero(capsys):
    path = robot_file(UR5)
    assert main(["convert", path, "--base-link", "base", "--tip-link", "tool0", "--to", "dh"]) == 0
    out = capsys.readouterr().out
    rows = table_rows(out, 6)
    for cells, published in zip(rows, UR_DH["ur5"]):
        for cell, value in zip(cells[3:7], published):  # a, d, alpha, theta
            if value == 0:
                assert cell == "0", cells
            else:
                assert abs(float(cell) - value) < 1e-5, cells  # 6 significant digits shown
    assert DISPLAY_NOTE in out.splitlines()
    assert "e-12" not in out


def test_ur5_written_document_and_json_keep_the_exact_tilt(tmp_path, capsys):
    path = robot_file(UR5)
    args = ["convert", path, "--base-link", "base", "--tip-link", "tool0", "--to", "dh"]
    assert main(args + ["--json"]) == 0
    rows = json.loads(capsys.readouterr().out)["dh"]["rows"]
    theta2 = rows[1]["theta"]
    # the URDF's 1.57079632679 is 4.9e-12 short of pi/2: the conversion keeps it, not the display's 0
    assert theta2 != 0 and abs(theta2) < 1e-11
    target = tmp_path / "ur5_dh.json"
    assert main(args + ["-o", str(target)]) == 0
    assert json.loads(target.read_text())["dh"]["rows"][1]["theta"] == theta2


def _one_joint_table(d: float, theta: float, a: float) -> DHTable:
    return DHTable(np.array([[a, d, 0.0, theta]]), [Joint("j1", "revolute")])


def test_values_above_the_threshold_are_shown_and_no_note_is_added():
    text = str(_one_joint_table(d=0.5, theta=2e-9, a=3e-9))
    cells = table_rows(text, 1)[0]
    assert float(cells[6]) == 2e-9 and float(cells[3]) == 3e-9
    assert DISPLAY_NOTE not in text


def test_angles_below_the_threshold_are_shown_as_zero_with_the_note():
    text = str(_one_joint_table(d=0.5, theta=5e-10, a=0.0))
    assert table_rows(text, 1)[0][6] == "0"
    assert DISPLAY_NOTE in text.splitlines()


def test_lengths_are_judged_relative_to_the_robot_size():
    # the same 2e-7 offset is noise on a robot 1000 units long (millimetres) and real on one 0.5 long
    big = str(_one_joint_table(d=1000.0, theta=0.0, a=2e-7))
    small = str(_one_joint_table(d=0.5, theta=0.0, a=2e-7))
    assert table_rows(big, 1)[0][3] == "0" and DISPLAY_NOTE in big
    assert float(table_rows(small, 1)[0][3]) == 2e-7 and DISPLAY_NOTE not in small


def test_rounding_noise_fmt_num_already_hides_adds_no_note():
    text = str(_one_joint_table(d=0.5, theta=1e-17, a=0.0))
    assert table_rows(text, 1)[0][6] == "0"
    assert DISPLAY_NOTE not in text


def test_table_object_keeps_the_exact_values_it_displays_as_zero():
    table = dh_from_robot(_one_joint_table(d=0.5, theta=5e-10, a=0.0).to_robot())
    assert table.rows[0, 3] == 5e-10
    assert table.to_dict()["dh"]["rows"][0]["theta"] == 5e-10


def test_every_ur5_text_table_hides_the_urdf_noise_and_says_so(capsys):
    path = robot_file(UR5)
    for fmt in ("mdh", "hayati", "poe", "poe-body", "rpy-xyz", "gjd"):
        assert main(["convert", path, "--base-link", "base", "--tip-link", "tool0", "--to", fmt]) == 0
        out = capsys.readouterr().out
        assert "e-12" not in out and "e-11" not in out, fmt
        assert DISPLAY_NOTE in out.splitlines(), fmt
