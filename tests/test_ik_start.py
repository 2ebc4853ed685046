"""Where IK starts and which answer it gives (issue 32, item 5).

- The default start lies inside every joint's limits, off the stops where zero is outside a range
  (zero where the range holds it, else the range's midpoint), for every example arm.
- The Panda at the issue's pose answers with the posture beside its ready pose, not a contorted one with
  joint 2 on its limit (the answer from zero clipped onto joint 4's stop).
- ``all_solutions`` on a redundant arm lists distinct postures, each more than the stated spacing from
  every other, nearest to the start first; the closed forms still give one row per branch.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import ik_arms as arms
import robkin
from robkin.cli import main
from robkin.examples import EXAMPLES_DIR
from robkin.kinematics.ik_methods import REDUNDANT_SPACING, preferred_starts
from robkin.kinematics.limits import default_preference
from robkin.se3 import homogeneous, matrix_from_rpy

#: the issue's target: 0.5 m ahead, 0.4 m up, the hand pointing down
ISSUE_POSE = [0.5, 0, 0.4, np.pi, 0, 0]
#: the Panda's ready pose (franka_ros, MoveIt's "ready"): the natural posture for a table-top target
READY = np.array([0, -np.pi / 4, 0, -3 * np.pi / 4, 0, np.pi / 2, np.pi / 4])


def _target(pose):
    return homogeneous(matrix_from_rpy(pose[3:]), pose[:3])


def _example_arms():
    out = {p.stem: robkin.load(p) for p in sorted(EXAMPLES_DIR.glob("*.yaml"))}
    for name in ("panda", "ur5", "xarm7"):
        robot = getattr(arms, name)()
        if robot is not None:
            out[name] = robot
    out["gen3"], out["jaco2"], out["xarm6"] = arms.gen3(), arms.jaco2(), arms.xarm6()
    return out


ARMS = _example_arms()


@pytest.mark.parametrize("name", sorted(ARMS))
def test_default_start_is_inside_the_limits(name):
    robot = ARMS[name]
    lower, upper = robot.limits[:, 0], robot.limits[:, 1]
    start = default_preference(robot.limits)
    assert np.all((start >= lower) & (start <= upper)), (name, start)
    # off the stops wherever the range allows it: a joint whose range holds zero starts at zero, any other
    # strictly between its limits (zero clipped would sit on a limit)
    holds_zero = (lower <= 0) & (upper >= 0)
    np.testing.assert_array_equal(start[holds_zero], 0.0)
    bounded = ~holds_zero & np.isfinite(lower) & np.isfinite(upper) & (upper > lower)
    assert np.all((start[bounded] > lower[bounded]) & (start[bounded] < upper[bounded])), (name, start)
    # what ik itself starts from without q0
    np.testing.assert_array_equal(preferred_starts(robot, None, 1)[0], start)


def test_default_start_rule_on_hand_made_limits():
    inf = np.inf
    limits = np.array([[-inf, inf], [-1.0, 2.0], [0.0, 0.5], [-3.0718, -0.0698], [0.2, 0.6], [1.0, inf],
                       [-inf, -2.0]])
    np.testing.assert_allclose(default_preference(limits), [0, 0, 0, -1.5708, 0.4, 1.0, -2.0], atol=1e-15)


@pytest.fixture(scope="module")
def panda():
    robot = arms.panda()
    if robot is None:
        pytest.skip("example-robot-data's Panda is not installed")
    return robot


def test_panda_issue_pose_answers_near_the_ready_pose(panda):
    T = _target(ISSUE_POSE)
    res = panda.ik(T)
    assert res.success
    np.testing.assert_allclose(panda.fk(res.q), T, atol=1e-9)
    lim = panda.limits
    # no joint on a stop (the old answer had joint 2 at its limit 1.7628, |q| = 4.0)
    assert np.all(res.q - lim[:, 0] > 0.05) and np.all(lim[:, 1] - res.q > 0.05), res.q
    # the posture beside the ready pose (the old answer was 3.6 rad from it)
    assert np.linalg.norm(res.q - READY) < 1.0, res.q
    # nearest the start among what all_solutions finds, to within the spacing of the rows it keeps
    start = default_preference(lim)
    every = panda.ik(T, all_solutions=True)
    nearest = np.linalg.norm(every.solutions - start, axis=1).min()
    assert np.linalg.norm(res.q - start) <= nearest + REDUNDANT_SPACING


def test_panda_issue_pose_on_the_command_line(panda, tmp_path, capsys, monkeypatch):
    import shutil

    shutil.copy(arms.os.path.join(arms.ROBOTS_DIR, "panda_description/urdf/panda.urdf"), tmp_path / "panda.urdf")
    monkeypatch.chdir(tmp_path)
    assert main(["ik", "panda.urdf", "--tip-link", "panda_hand_tcp", "--pose", "0.5,0,0.4,pi,0,0", "--json"]) == 0
    q = np.array(json.loads(capsys.readouterr().out)["solutions"][0]["q"])
    assert np.linalg.norm(q - READY) < 1.0 and abs(q[1]) < 1.0, q


def _spaced(S, unit):
    d = np.abs((S[:, None] - S[None]) / unit).max(axis=-1)
    return np.all(d[~np.eye(len(S), dtype=bool)] > REDUNDANT_SPACING)


@pytest.mark.parametrize("name, pose", [("panda", ISSUE_POSE), ("iiwa", [0.5, 0, 0.5, 0, np.pi, 0]),
                                        ("iiwa", [0.4, 0.3, 0.6, np.pi / 2, 0.3, 0])])
def test_all_solutions_of_a_redundant_arm_are_distinct_postures(name, pose):
    robot = arms.panda() if name == "panda" else arms.iiwa()
    if robot is None:
        pytest.skip("example-robot-data's Panda is not installed")
    T = _target(pose)
    res = robot.ik(T, all_solutions=True)
    S = res.solutions
    assert res.method == "numeric" and res.success and len(S) >= 3
    # every row a solution within the limits
    np.testing.assert_allclose(robot.fk(S), np.broadcast_to(T, (len(S), 4, 4)), atol=1e-9)
    assert np.all((S >= robot.limits[:, 0] - 1e-12) & (S <= robot.limits[:, 1] + 1e-12))
    # pairwise more than the stated spacing apart in some joint (before: 83 rows on the Panda, many a few
    # milliradians apart), nearest to the start first, and q the first row
    assert _spaced(S, np.ones(robot.n)), len(S)
    start = default_preference(robot.limits)
    dist = np.linalg.norm(S - start, axis=1)
    assert np.all(np.diff(dist) >= 0)
    np.testing.assert_array_equal(res.q, S[0])


def test_all_on_the_command_line_is_spaced(panda, tmp_path, capsys, monkeypatch):
    import shutil

    shutil.copy(arms.os.path.join(arms.ROBOTS_DIR, "panda_description/urdf/panda.urdf"), tmp_path / "panda.urdf")
    monkeypatch.chdir(tmp_path)
    assert main(["ik", "panda.urdf", "--tip-link", "panda_hand_tcp", "--pose", "0.5,0,0.4,pi,0,0", "--all",
                 "--json"]) == 0
    S = np.array([s["q"] for s in json.loads(capsys.readouterr().out)["solutions"]])
    assert 3 <= len(S) <= 40 and _spaced(S, np.ones(7))


def test_closed_form_all_solutions_keep_one_row_per_branch():
    """The spacing is for numeric continua only: a 6R closed form keeps branches 1e-6 apart (the UR5's
    eight, the KR6's eight at a generic pose), and a 7-joint arm with a joint locked is a 6R closed form."""
    kr6 = robkin.load(EXAMPLES_DIR / "kr6_r700.yaml")
    q = np.array([0.3, -0.5, 0.4, 0.7, 0.6, -0.2])
    res = kr6.ik(kr6.fk(q), all_solutions=True)
    assert res.method != "numeric"
    assert any(np.allclose(s, q, atol=1e-9) for s in res.solutions)
    ur5 = arms.ur5()
    if ur5 is not None:
        res = ur5.ik(ur5.fk(np.array([0.3, -1.0, 1.2, -0.4, 0.8, 0.2])), all_solutions=True)
        assert res.method == "three-parallel-6r" and len(res.solutions) == 8
