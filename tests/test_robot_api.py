"""The Robot methods a user reaches first: ``robot.jacobian(q, frame=...)`` and
``robot.manipulability(q, kind=...)``, checked against pinocchio on a real arm and against the planar
two-link arm's closed form (Yoshikawa: l1 l2 |sin q2|)."""

from __future__ import annotations

import glob
import os
import sys

import numpy as np
import pytest

import robkin
from robkin.errors import InputError
from robkin.robot import default_joints

ROBOTS_DIR = (glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                     "example-robot-data", "robots")) or [""])[0]


def planar_2r(l1: float = 1.0, l2: float = 0.5) -> robkin.Robot:
    M = np.eye(4)
    M[0, 3] = l1 + l2
    screws = np.array([[0, 0, 1, 0, 0, 0], [0, 0, 1, 0, -l1, 0]], dtype=float)
    return robkin.PoE(M, screws, default_joints(["revolute"] * 2)).to_robot()


def test_manipulability_is_l1_l2_sin_q2_for_one_q_and_a_batch():
    robot = planar_2r()
    assert robot.manipulability([0.3, 0.7]) == pytest.approx(0.5 * abs(np.sin(0.7)), rel=1e-12)
    Q = np.array([[0.1, 0.2], [0.0, -1.2], [2.0, 0.0]])
    np.testing.assert_allclose(robot.manipulability(Q), 0.5 * np.abs(np.sin(Q[:, 1])), rtol=1e-12, atol=1e-15)
    # the rotational rows of a planar arm are (0, 0, 1) per joint: singular values sqrt(2) and 0
    assert robot.manipulability([0.3, 0.7], kind="rotational") == pytest.approx(0.0, abs=1e-15)


def test_planar_jacobian_in_every_frame():
    robot = planar_2r()
    q = np.array([np.pi / 2, 0.0])     # arm along +y: the tool at (0, 1.5)
    J = robot.jacobian(q)
    # v = w x (p_tool - p_axis): joint 1 at the origin, joint 2 at (0, 1)
    np.testing.assert_allclose(J[:3], [[-1.5, -0.5], [0, 0], [0, 0]], atol=1e-15)
    np.testing.assert_allclose(J[3:], [[0, 0], [0, 0], [1, 1]], atol=1e-15)
    # tool axes are the base axes turned by pi/2 about z: base -x is tool +y... -(-x) -> tool y = -x_base
    np.testing.assert_allclose(robot.jacobian(q, "tool")[:3], [[0, 0], [1.5, 0.5], [0, 0]], atol=1e-15)
    # space Jacobian (w, v): v = -w x p_axis (the velocity of the point at the base origin)
    np.testing.assert_allclose(robot.jacobian(q, "space"), [[0, 0], [0, 0], [1, 1], [0, 1], [0, 0], [0, 0]],
                               atol=1e-15)
    np.testing.assert_allclose(robot.jacobian(q, "body"), robot.jacobian(q, "tool")[[3, 4, 5, 0, 1, 2]])
    assert robot.jacobian(np.zeros((3, 2)), "space").shape == (3, 6, 2)


def test_unknown_frame_and_kind_name_the_choices():
    robot = planar_2r()
    with pytest.raises(InputError, match="frame: 'world' is not one of base, tool, space, body"):
        robot.jacobian([0, 0], frame="world")
    with pytest.raises(InputError, match="translational"):
        robot.manipulability([0, 0], kind="linear")


pin = pytest.importorskip("pinocchio")


def test_jacobian_frames_match_pinocchio_on_the_panda():
    path = os.path.join(ROBOTS_DIR, "panda_description/urdf/panda.urdf")
    if not os.path.isfile(path):
        pytest.skip("example-robot-data's panda.urdf is not installed")
    tip = "panda_hand_tcp"
    robot = robkin.load(path, tip_link=tip)
    model = pin.buildModelFromUrdf(path)
    data = model.createData()
    fid = model.getFrameId(tip)
    swap = np.r_[3:6, 0:3]   # pinocchio's rows are (v, w)
    for q in robot.random_q(3, rng=11):
        qp = pin.neutral(model)
        cols = []
        for joint, value in zip(robot.joints, q):
            jm = model.joints[model.getJointId(joint.name)]
            qp[jm.idx_q] = value
            cols.append(jm.idx_v)
        pin.computeJointJacobians(model, data, qp)
        pin.updateFramePlacements(model, data)
        pj = {ref: pin.getFrameJacobian(model, data, fid, ref)[:, cols]
              for ref in (pin.LOCAL_WORLD_ALIGNED, pin.LOCAL, pin.WORLD)}
        # 1e-12, the figure docs/benchmarks.md states (absolute; assert_allclose's default rtol=1e-7 used to
        # loosen it): both are exact formulas in double precision on the same ~1 m geometry; observed
        # 5.0e-16 (2026-11-28), so 5e-15 (10x: another CPU or BLAS rounds differently) guards it too
        for atol in (1e-12, 5e-15):
            np.testing.assert_allclose(robot.jacobian(q), pj[pin.LOCAL_WORLD_ALIGNED], atol=atol, rtol=0)
            np.testing.assert_allclose(robot.jacobian(q, "tool"), pj[pin.LOCAL], atol=atol, rtol=0)
            np.testing.assert_allclose(robot.jacobian(q, "space"), pj[pin.WORLD][swap], atol=atol, rtol=0)
            np.testing.assert_allclose(robot.jacobian(q, "body"), pj[pin.LOCAL][swap], atol=atol, rtol=0)
        Jv = pj[pin.LOCAL_WORLD_ALIGNED][:3]
        assert robot.manipulability(q) == pytest.approx(np.sqrt(np.linalg.det(Jv @ Jv.T)), rel=1e-9)


def test_errors_name_keywords_in_python_and_flags_on_the_command_line(tmp_path, capsys):
    from robkin.cli import main
    from robkin.messages import render_options

    urdf = tmp_path / "tree.urdf"
    urdf.write_text("""<robot name="tree"><link name="base"/><link name="a"/><link name="b"/>
      <joint name="ja" type="revolute"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/>
        <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
      <joint name="jb" type="revolute"><parent link="base"/><child link="b"/><axis xyz="0 0 1"/>
        <limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>""")
    with pytest.raises(InputError, match=r"pick the chain's end with tip_link=, one of: a, b"):
        robkin.load(urdf)
    with pytest.raises(InputError, match=r"tip_link='nope' is not a link of the file"):
        robkin.load(urdf, tip_link="nope")
    assert main(["fk", str(urdf), "--q", "0"]) == 2
    assert "pick the chain's end with --tip-link, one of: a, b" in capsys.readouterr().err
    assert main(["info", str(urdf), "--tip-link", "nope"]) == 2
    assert "--tip-link 'nope' is not a link of the file" in capsys.readouterr().err
    # only the names given are rendered; fields, comparisons and XML attributes are left alone
    names = {"tip_link": "--tip-link", "base_link": "--base-link"}
    assert render_options("base_link=/tip_link= apply; a.tip_link=1, x==y, xyz=\"0\"", names) == \
        "--base-link/--tip-link apply; a.tip_link=1, x==y, xyz=\"0\""


RRPR = os.path.join(os.path.dirname(robkin.__file__), "examples", "rrpr.yaml")


@pytest.mark.parametrize("make", [robkin.dh_from_robot, robkin.mdh_from_robot, robkin.rpy_from_robot,
                                  lambda r: robkin.poe_from_robot(r, "space"),
                                  lambda r: robkin.poe_from_robot(r, "body")])
def test_tables_print_as_the_cli_and_to_dict_reads_back(make, capsys):
    import json

    from robkin.cli import main
    from robkin.io.documents.reader import parse_document
    from robkin.io.files.jsontext import dumps

    robot = robkin.load(RRPR)
    table = make(robot)
    text = str(table)
    for name in ("joint1", "joint2", "joint3", "joint4"):
        assert name in text
    # str() is the CLI's table: the same lines after the CLI's title
    fmt = {"DHTable": "dh", "MDHTable": "mdh", "RPYTable": "rpy-xyz"}.get(type(table).__name__)
    fmt = fmt or ("poe" if table.frame == "space" else "poe-body")
    assert main(["convert", RRPR, "--to", fmt]) == 0
    assert capsys.readouterr().out.splitlines()[1:] == text.splitlines()[1:]
    # to_dict is a robot document: it reads back as the same robot
    doc = table.to_dict()
    back = parse_document(dumps(doc), "json")
    Q = robot.random_q(20, rng=3)
    np.testing.assert_allclose(back.fk(Q), robot.fk(Q), atol=1e-12)
    assert json.loads(dumps(doc)) == doc


def test_ik_result_and_comparison_are_readable():
    import json

    from robkin.equivalence import compare
    from robkin.io.files.jsontext import dumps

    robot = robkin.load(RRPR)
    targets = robot.fk(robot.random_q(3, rng=2))
    res = robot.ik(targets)
    lines = str(res).splitlines()
    assert lines[0] == f"IK ({res.method}): {int(np.sum(res.success))} of 3 reached" and len(lines) == 6
    d = res.to_dict()
    assert set(d) >= {"q", "success", "position_error", "orientation_error", "method", "message"}
    assert np.array(d["q"]).shape == (3, 4) and json.loads(dumps(d))["method"] == res.method
    c = compare(robot, robkin.load(os.path.join(os.path.dirname(RRPR), "scara.yaml")))
    assert repr(c) == ("Comparison(same=False, equivalent=False, "
                       "first_difference='joint counts differ: A has 4, B has 5')")
    assert str(c).splitlines()[0] == "verdict: different robots: joint counts differ: A has 4, B has 5"  # first
    assert "type revolute in A, prismatic in B" in str(c)


def test_a_large_ik_batch_prints_a_screenful():
    from robkin.kinematics.ik_text import MAX_ROWS

    robot = robkin.load(RRPR)
    res = robot.ik(robot.fk(robot.random_q(MAX_ROWS + 5, rng=4)))
    lines = str(res).splitlines()
    assert len(lines) == 3 + MAX_ROWS + 1 and lines[-1].startswith("... 5 more targets")
