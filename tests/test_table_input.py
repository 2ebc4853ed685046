"""Tables as input: CSV files robkin wrote read back (property test over random robots and every table
representation), bare rows as pasted from a paper, --from where the file does not say, and one clear
line for every bad file."""

from __future__ import annotations

import math
import os
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import robkin
from robkin.cli import main
from robkin.errors import InputError
from robkin.io.documents.reader import robot_from_data
from robkin.io.tables.files import render_table
from robkin.io.tables.reader import table_document
from strategies import robots
from test_urdf import robot_file

SCALE = int(os.environ.get("ROBKIN_PROPERTY_SCALE", "1"))
H = math.pi / 2
#: the file says which table it is, except a PoE's frame
HINT = {"poe": "poe", "poe-body": "poe-body"}
WRITERS = {"dh": robkin.dh_from_robot, "mdh": robkin.mdh_from_robot, "hayati": robkin.hayati_from_robot,
           "poe": lambda r: robkin.poe_from_robot(r, "space"), "poe-body": lambda r: robkin.poe_from_robot(r, "body"),
           "rpy-xyz": robkin.rpy_from_robot, "gjd": lambda r: r}


@settings(max_examples=40 * SCALE, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(robots(max_joints=6), st.sampled_from(sorted(WRITERS)), st.booleans())
def test_csv_round_trip(robot, rep, pi):
    """What convert --format csv writes reads back as the same table: the same joints (names, types,
    flips) and, at random q, the FK of the table that was written, to rounding of its own lengths."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        written = WRITERS[rep](robot)
        text = render_table(robot, rep, "csv", pi=pi)
        back = robot_from_data(table_document(text, HINT.get(rep)))
    assert [(j.name, j.type, j.flip) for j in back.joints] == [(j.name, j.type, j.flip) for j in robot.joints]
    q = robot.random_q(8, rng=5)
    want = written.fk(q)
    # the rows are read back bit for bit; FK through the frames they make rounds like the table's
    # own lengths (a DH table of nearly parallel axes carries lengths far beyond the robot's size)
    size = max(robot.scale, float(np.abs(want[:, :3, 3]).max()),
               *(float(np.abs(t).max()) for t in _lengths(written)))
    got = back.fk(q)
    np.testing.assert_allclose(got[:, :3, 3], want[:, :3, 3], rtol=0, atol=1e-9 * size)
    np.testing.assert_allclose(got[:, :3, :3], want[:, :3, :3], rtol=0, atol=1e-9)  # unitless


def _lengths(table):
    rows = getattr(table, "rows", None)
    out = [] if rows is None or not hasattr(table, "base") else [rows[:, :2], table.base[:3, 3], table.tool[:3, 3]]
    return out or [np.zeros(1)]


UR5_ROWS = """# UR5, Universal Robots' published DH
0 0.089159 pi/2 0
-0.425 0 0 0
-0.39225 0 0 0
0 0.10915 pi/2 0
0 0.09465 -pi/2 0
0 0.0823 0 0
"""


def test_bare_rows_need_from_and_match_the_urdf(tmp_path, capsys):
    path = tmp_path / "ur5.txt"
    path.write_text(UR5_ROWS)
    assert main(["fk", str(path), "--q", "0,0,0,0,0,0", "--json"]) == 2
    err = capsys.readouterr().err
    assert "--from dh, mdh" in err and err.count("\n") == 1
    urdf = robot_file("ur_description/urdf/ur5_robot.urdf")
    assert main(["check", str(path), urdf, "--from", "dh", "--base-link", "-", "--base-link", "base",
                 "--tip-link", "-", "--tip-link", "tool0", "--tol", "1e-9"]) == 0


def test_header_says_and_from_must_agree(tmp_path, capsys):
    path = tmp_path / "two.csv"
    path.write_text("a,d,alpha,theta\n0,0.3,pi/2,0\n0.4,0,0,0\n")
    dh = robkin.load(path)
    mdh = robkin.load(path, representation="mdh")
    T = robkin.se3.dh_matrix(0, 0.3, H, 0.2) @ robkin.se3.dh_matrix(0.4, 0, 0, -0.1)
    np.testing.assert_allclose(dh.fk([0.2, -0.1]), T, atol=1e-15)
    assert not np.allclose(mdh.fk([0.2, -0.1]), T)
    with pytest.raises(InputError, match="does not fit the header"):
        robkin.load(path, representation="poe")
    csv_mdh = tmp_path / "m.csv"
    csv_mdh.write_text("i,joint,type,a(i-1),d,alpha(i-1),theta\n1,j1,prismatic,0,0.3,0,0\n")
    assert robkin.load(csv_mdh).joints[0].type == "prismatic"
    with pytest.raises(InputError, match="does not fit"):
        robkin.load(csv_mdh, representation="dh")


@pytest.mark.parametrize("text, words", [
    ("", "no rows"),
    ("a,d,alpha,theta\n", "no rows after the header"),
    ("p,q,r\n1,2,3\n", "names no table's columns"),
    ("a,d,alpha,theta\n0,0.3,pi/2\n", "line 2: expected 4 columns"),
    ("a,d,alpha,theta\n0,0.3,pi/2,x\n", "line 2, column theta"),
    ("a,d,alpha,theta\n0,0.3,0,0\n\ntransform,m11\nbase,1,0\n", "expected its name and 12 numbers"),
    ("a,d,alpha,theta\n0,0.3,0,0\n\nM,1,0,0,0,0,1,0,0,0,0,1,0\n", "transform 'M' does not belong"),
    ("i,joint,type,a,d,alpha,theta\n1,j,spherical,0,0,0,0\n", "type 'spherical'"),
    ("wx,wy,wz,vx,vy,vz\n0,0,1,0,0,0\n", "which frame"),
])
def test_bad_tables_are_one_line(tmp_path, capsys, text, words):
    path = tmp_path / "t.csv"
    path.write_text(text)
    assert main(["info", str(path)]) == 2
    err = capsys.readouterr().err
    assert words in err and str(path) in err and err.count("\n") == 1, err


def test_from_is_for_tables_only(capsys):
    assert main(["fk", "rrpr.yaml", "--from", "dh", "--q", "0,0,0,0"]) == 2
    assert "applies to table files" in capsys.readouterr().err
