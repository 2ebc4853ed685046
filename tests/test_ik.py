"""Inverse kinematics on real arms (example-robot-data URDFs, checked by pinocchio's FK), closed-form 6R
solutions (checked for completeness against the numeric solver), masks, limits, failures and the CLI."""

from __future__ import annotations

import glob
import json
import os
import sys

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import robkin
from robkin import se3
from robkin.cli import main
from robkin.errors import InputError
from robkin.kinematics.analytic6r import SphericalWrist6R, ThreeParallel6R
from robkin.kinematics.closed_form import closed_form_solver
from robkin.se3 import log_rotation as log_rotation_batch
from robkin.representations import mdh_from_robot, poe_from_robot, rpy_from_robot
from robkin.robot import Joint, default_joints

from strategies import robots

pin = pytest.importorskip("pinocchio")

ROBOTS_DIR = (glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                     "example-robot-data", "robots")) or [""])[0]
#: the default IK tolerances (1e-9 m, 1e-9 rad); pinocchio's FK of a reported solution must agree with
#: the target to 1e-8 (ten times the tolerance: pinocchio's own rounding over a 1 m chain is ~1e-15)
CHECK = 1e-8

ARMS = {  # name: (file, tip link)
    "ur5": ("ur_description/urdf/ur5_robot.urdf", "tool0"),
    "panda": ("panda_description/urdf/panda.urdf", "panda_hand_tcp"),
    "xarm7": ("xarm_description/urdf/xarm7.urdf", None),
    "kinova": ("kinova_description/robots/kinova.urdf", "j2s6s200_end_effector"),
}


def arm_file(name: str) -> str:
    path = os.path.join(ROBOTS_DIR, ARMS[name][0])
    if not os.path.isfile(path):
        pytest.skip(f"example-robot-data file {ARMS[name][0]} not installed")
    return path


def load_arm(name: str) -> tuple[robkin.Robot, object, str]:
    path = arm_file(name)
    robot = robkin.load(path, tip_link=ARMS[name][1])
    model = pin.buildModelFromUrdf(path)
    tip = ARMS[name][1] or robot_tip_frame(model)
    return robot, model, tip


def robot_tip_frame(model) -> str:
    return model.frames[len(model.frames) - 1].name


def pin_fk(model, robot: robkin.Robot, q: np.ndarray, frame: str) -> np.ndarray:
    """pinocchio's pose of ``frame`` with robkin's joint values set by joint name."""
    data = model.createData()
    qp = pin.neutral(model)
    for joint, value in zip(robot.joints, q):
        jm = model.joints[model.getJointId(joint.name)]
        if jm.nq == 2:
            qp[jm.idx_q], qp[jm.idx_q + 1] = np.cos(value), np.sin(value)
        else:
            qp[jm.idx_q] = value
    pin.framesForwardKinematics(model, data, qp)
    return data.oMf[model.getFrameId(frame)].homogeneous


# ------------------------------------------------------------------------------------------ real arms
@pytest.mark.parametrize("name, method", [("ur5", "auto"), ("ur5", "numeric"), ("panda", "auto"),
                                          ("xarm7", "auto"), ("kinova", "auto"), ("kinova", "numeric")])
def test_random_reachable_targets_on_real_arms(name, method):
    robot, model, tip = load_arm(name)
    N = 300
    Q = robot.random_q(N, rng=11)
    targets = np.array([pin_fk(model, robot, q, tip) for q in Q])   # the targets come from the peer
    res = robot.ik(targets, method=method)
    assert res.success.mean() >= 0.99
    lim = robot.limits
    for q, T, ok in zip(res.q, targets, res.success):
        if not ok:
            continue
        assert np.all((q >= lim[:, 0]) & (q <= lim[:, 1]))
        err = pin_fk(model, robot, q, tip) - T
        assert np.abs(err).max() <= CHECK
    # the errors the result reports are the true ones (within rounding), successes within tolerance
    assert np.all(res.position_error[res.success] <= 1e-9)
    assert np.all(res.orientation_error[res.success] <= 1e-9)
    expected = {"kinova": "spherical-wrist-6r", "ur5": "three-parallel-6r"}.get(name, "numeric")
    assert res.method == (expected if method == "auto" else "numeric")


def test_position_only_and_partial_masks_on_panda():
    robot, model, tip = load_arm("panda")
    Q = robot.random_q(100, rng=12)
    targets = robot.fk(Q) @ se3.rot_x(0.7)          # orientations the positions alone do not fix
    res = robot.ik(targets, mask="position")
    assert res.success.mean() >= 0.99
    for q, T in zip(res.q[res.success], targets[res.success]):
        assert np.abs(pin_fk(model, robot, q, tip)[:3, 3] - T[:3, 3]).max() <= CHECK
    assert np.all(res.orientation_error == 0.0)    # no orientation component selected
    # x, y, z and rotation about base z only
    T = robot.fk(Q[:50])
    res = robot.ik(T, mask=[1, 1, 1, 0, 0, 1])
    assert res.success.mean() >= 0.98
    rv = log_rotation_batch(T[:, :3, :3] @ np.swapaxes(robot.fk(res.q)[:, :3, :3], 1, 2))
    assert np.abs(rv[res.success, 2]).max() <= 1e-9


def test_ur5_closed_form_and_numeric_find_the_same_solutions():
    robot, model, tip = load_arm("ur5")
    assert isinstance(closed_form_solver(robot), ThreeParallel6R)
    Q = robot.random_q(8, rng=21)
    targets = robot.fk(Q)
    closed = robot.ik(targets, all_solutions=True)
    numeric = robot.ik(targets, all_solutions=True, method="numeric", restarts=60)
    assert closed.success.all() and numeric.success.all()
    for T, a, b in zip(targets, closed.solutions, numeric.solutions):
        for q in a:
            assert np.abs(pin_fk(model, robot, q, tip) - T).max() <= CHECK
        # every numeric solution is a closed-form one and (with 61 starts) the other way round
        assert all(any(same_angles(q, s) for s in a) for q in b)
        assert all(any(same_angles(q, s) for s in b) for q in a)
        # distinct: no two closer than the de-duplication tolerance
        d = np.abs(a[:, None] - a[None]).max(axis=-1)
        assert np.all(d[~np.eye(len(d), dtype=bool)] > 1e-6)


def test_ur5_wrist_singular_targets():
    # q5 = 0 lines axis 6 up with axes 2-4: phi and q6 trade off, and only some splits reach
    robot, model, tip = load_arm("ur5")
    Q = robot.random_q(300, rng=22)
    Q[::2, 4] = 0.0
    Q[1::4, 4] = 1e-9
    targets = robot.fk(Q)
    res = robot.ik(targets)
    assert res.success.all()
    for q, T in zip(res.q, targets):
        assert np.abs(pin_fk(model, robot, q, tip) - T).max() <= CHECK
    # the closed form alone never calls such a target unreachable: it solves it or says it is unsure
    alone = robot.ik(targets, method="analytic")
    assert all("reach" not in m for m in alone.message)


# ---------------------------------------------------------------------------- closed-form 6R arms
def puma560() -> robkin.Robot:
    """Puma 560 (Corke's standard DH parameters), no limits: the textbook 8-solution arm."""
    rows = [[0, 0, np.pi / 2, 0], [0.4318, 0, 0, 0], [0.0203, 0.15005, -np.pi / 2, 0],
            [0, 0.4318, np.pi / 2, 0], [0, 0, -np.pi / 2, 0], [0, 0, 0, 0]]
    return robkin.DHTable(rows, default_joints(["revolute"] * 6)).to_robot(name="puma560")


def kr16() -> robkin.Robot:
    """A KUKA KR 16-type arm: offset shoulder, elbow offset, spherical wrist, flange; vendor-like limits."""
    lim = [(-3.22, 3.22), (-2.7, 0.61), (-2.26, 2.68), (-6.1, 6.1), (-2.27, 2.27), (-6.1, 6.1)]
    rows = [[0.26, 0.675, -np.pi / 2, 0], [0.68, 0, 0, -np.pi / 2], [0.035, 0, -np.pi / 2, 0],
            [0, 0.67, np.pi / 2, 0], [0, 0, -np.pi / 2, 0], [0, 0.158, 0, 0]]
    return robkin.DHTable(rows, tuple(Joint(f"a{i + 1}", "revolute", lo, hi) for i, (lo, hi) in enumerate(lim)),
                          tool=se3.trans(0, 0, 0.1) @ se3.rot_y(0.3)).to_robot(name="kr16")


def same_angles(a: np.ndarray, b: np.ndarray, tol: float = 1e-6) -> bool:
    return bool(np.abs(np.angle(np.exp(1j * (a - b)))).max() <= tol)


def test_puma_has_eight_solutions_and_numeric_finds_no_others():
    robot = puma560()
    assert isinstance(closed_form_solver(robot), SphericalWrist6R)
    Q = robot.random_q(40, rng=13)
    targets = robot.fk(Q)
    res = robot.ik(targets, all_solutions=True)
    assert res.success.all()
    for q_true, T, sols in zip(Q, targets, res.solutions):
        assert len(sols) == 8
        assert np.abs(robot.fk(sols) - T).max() <= 1e-9
        assert any(same_angles(s, q_true) for s in sols)      # the configuration it came from
    # completeness: numeric IK from many random starts lands only on closed-form solutions
    T = targets[0]
    numeric = robot.ik(np.repeat(T[None], 60, axis=0), q0=robot.random_q(60, rng=14), method="numeric",
                       restarts=0)
    found = numeric.q[numeric.success]
    assert len(found) >= 30
    for q in found:
        assert any(same_angles(q, s) for s in res.solutions[0])


def ur5_dh() -> robkin.Robot:
    """UR5 from its published standard DH parameters, joint limits +-2 pi."""
    rows = [[0, 0.089159, np.pi / 2, 0], [-0.425, 0, 0, 0], [-0.39225, 0, 0, 0], [0, 0.10915, np.pi / 2, 0],
            [0, 0.09465, -np.pi / 2, 0], [0, 0.0823, 0, 0]]
    joints = tuple(Joint(f"j{i + 1}", "revolute", -2 * np.pi, 2 * np.pi) for i in range(6))
    return robkin.DHTable(rows, joints).to_robot(name="ur5-dh")


@pytest.mark.parametrize("make, kind", [(kr16, SphericalWrist6R), (ur5_dh, ThreeParallel6R)])
@pytest.mark.parametrize("convert", [mdh_from_robot, lambda r: poe_from_robot(r, "body"), rpy_from_robot])
def test_closed_form_detected_from_any_representation(convert, make, kind):
    robot = make()
    other = convert(robot).to_robot()
    assert isinstance(closed_form_solver(robot), kind) and isinstance(closed_form_solver(other), kind)
    targets = robot.fk(robot.random_q(30, rng=15))
    a, b = robot.ik(targets, all_solutions=True), other.ik(targets, all_solutions=True)
    assert a.success.all() and b.success.all()
    for sa, sb in zip(a.solutions, b.solutions):
        assert sa.shape == sb.shape and np.allclose(sa, sb, atol=1e-9)


def test_closed_form_respects_limits_and_checks_every_solution():
    robot = kr16()
    Q = robot.random_q(500, rng=16)
    targets = robot.fk(Q)
    res = robot.ik(targets, all_solutions=True)
    assert res.success.all() and res.method == "spherical-wrist-6r"
    lim = robot.limits
    counts = []
    for T, sols in zip(targets, res.solutions):
        assert np.all((sols >= lim[:, 0]) & (sols <= lim[:, 1]))
        assert np.abs(robot.fk(sols) - T).max() <= 1e-9
        counts.append(len(sols))
    assert max(counts) <= 8 and min(counts) >= 1


@pytest.mark.parametrize("q", [[0.3, -0.5, 0.7, 0.4, 0.0, -0.2],       # wrist singular (q5 = 0)
                               [0.3, -0.5, 0.0, 0.4, 0.8, -0.2],       # joint 3 at its zero
                               [0.0, -np.pi / 2, np.pi / 2, 0.0, 0.3, 0.0]])
def test_singular_targets_still_solve(q):
    robot = puma560()
    T = robot.fk(q)
    res = robot.ik(T, all_solutions=True)
    assert res.success
    assert np.abs(robot.fk(res.solutions) - T).max() <= 1e-9


def test_wrist_centre_on_axis_one_uses_the_preferred_angle():
    # a 6R arm with no shoulder offset: with the wrist centre on axis 1, q1 is free (shoulder singularity)
    from scipy.optimize import brentq

    rows = [[0, 0.3, np.pi / 2, 0], [0.4, 0, 0, 0], [0, 0, np.pi / 2, 0],
            [0, 0.4, -np.pi / 2, 0], [0, 0, np.pi / 2, 0], [0, 0.1, 0, 0]]
    robot = robkin.DHTable(rows, default_joints(["revolute"] * 6)).to_robot()
    solver = closed_form_solver(robot)
    assert isinstance(solver, SphericalWrist6R)

    def centre(q3: float) -> np.ndarray:
        T = robot.fk([0.0, 0.5, q3, 0.0, 0.4, 0.0])
        return T[:3, :3] @ solver.w_tool + T[:3, 3]

    q3 = brentq(lambda x: centre(x)[0], -3.0, -2.5, xtol=1e-15)   # elbow folded over the base
    assert np.hypot(*centre(q3)[:2]) < 1e-12
    T = robot.fk([0.0, 0.5, q3, 0.0, 0.4, 0.0])
    for q1 in (0.0, 0.7):
        res = robot.ik(T, q0=[q1, 0, 0, 0, 0, 0])
        assert res.success and np.abs(robot.fk(res.q) - T).max() <= 1e-9
        assert res.q[0] == pytest.approx(q1, abs=1e-9)


# ------------------------------------------------------------------------------------------ random robots
@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(robot=robots(max_joints=6), seed=st.integers(0, 2**16))
def test_random_robots_every_success_is_real(robot, seed):
    # any geometry (skew/parallel/coincident axes, prismatic joints, mm/m/km): targets from FK, so
    # reachable; whatever the method, a reported success must reach the target (independent FK) and
    # most targets must be solved
    Q = robot.random_q(10, rng=seed)
    Q = np.where(robot.revolute, Q, Q * robot.scale / np.pi)      # slides of the robot's own size
    targets = robot.fk(Q)
    # Position tolerance: the default 1e-9 length units, but never below 1e-9 of the robot's size (its
    # axis distances, or the targets' reach if larger: the numbers FK computes with). The default alone
    # is 1e-12 of a robot drawn with unit 1e3 (mm-sized numbers), below what a nearly degenerate
    # geometry allows: seen, an RRPRP whose joints 2 and 4 (and 3 and 5) move along the same line,
    # solved to 3.7e-10 of its size on every target, which the solver's damping floor (1e-12 relative,
    # a step condition number <= 1e12) cannot take further.
    size = max(1.0, robot.scale, float(np.abs(targets[:, :3, 3]).max()))
    res = robot.ik(targets, tol_position=1e-9 * size)
    ok = res.success
    err = robot.fk(np.where(ok[:, None], res.q, 0.0)) - targets
    assert np.abs(err[ok][:, :3, :3]).max(initial=0.0) <= 1e-8
    assert np.abs(err[ok][:, :3, 3]).max(initial=0.0) <= 1e-8 * size
    assert np.all(res.position_error[ok] <= 1e-9 * size) and np.all(res.orientation_error[ok] <= 1e-9)
    # 0.5: degenerate random geometries (three parallel axes and a skew slide...) have small basins;
    # the real arms above are held to 99 %
    assert ok.mean() >= 0.5


def stanford_arm(unit: float) -> robkin.Robot:
    """The Stanford arm (Corke's DH table; joint 3 prismatic), lengths in m times ``unit``."""
    rows = np.array([[0, 0.412, -np.pi / 2, 0], [0, 0.154, np.pi / 2, 0], [0.0203, 0, 0, -np.pi / 2],
                     [0, 0, -np.pi / 2, 0], [0, 0, np.pi / 2, 0], [0, 0.263, 0, 0]])
    rows[:, :2] *= unit
    types = ["revolute", "revolute", "prismatic", "revolute", "revolute", "revolute"]
    return robkin.DHTable(rows, default_joints(types)).to_robot(name="stanford")


def test_numeric_solver_works_the_same_in_every_length_unit():
    # The solver steps in radians and robot sizes; it stepped in radians and length units, so written in
    # mm the slide's steps were damped 1e6 times more: 97 % solved in 200 iterations per target on
    # average, against 100 % in 13 in m.
    runs = []
    for unit in (1.0, 1000.0):
        robot = stanford_arm(unit)
        Q = robot.random_q(40, rng=5)
        Q[:, 2] = (0.3 + np.abs(Q[:, 2]) / np.pi) * unit        # the slide out 0.3..1.3 m
        runs.append(robot.ik(robot.fk(Q), method="numeric", tol_position=1e-9 * unit))
    metre, mm = runs
    assert metre.success.all() and mm.success.all()
    # the iterations are the same up to rounding (lengths x 1000 are not exact in binary)
    assert mm.iterations.sum() <= 1.1 * metre.iterations.sum()


# ------------------------------------------------------------------------------------------ behaviour
def test_unreachable_numeric_target_is_a_failure_with_best_effort():
    robot = kr16()
    T = se3.trans(5.0, 0, 0)          # 5 m away; the arm reaches ~1.6 m
    res = robot.ik(T, method="numeric", restarts=3)
    assert not res.success and res.attempts == 4 and "no solution found from 4 start(s)" in res.message
    assert np.all(np.isfinite(res.q)) and res.position_error > 3.0
    closed = robot.ik(T)
    assert not closed.success and "out of reach" in closed.message


def test_start_at_a_solution_needs_no_iteration():
    robot = kr16()
    q = np.array([0.1, -0.8, 0.9, 0.2, 0.5, -0.3])
    res = robot.ik(robot.fk(q), q0=q, method="numeric")
    assert res.success and res.iterations == 0 and np.allclose(res.q, q, atol=1e-12)


def test_result_shapes():
    robot = kr16()
    one = robot.ik(robot.fk(np.zeros(6)))
    assert one.q.shape == (6,) and isinstance(one.success, bool) and isinstance(one.position_error, float)
    many = robot.ik(robot.fk(np.zeros((3, 6))))
    assert many.q.shape == (3, 6) and many.success.shape == (3,) and len(many.message) == 3


def test_log_rotation_matches_scipy_near_zero_and_pi():
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(17)
    axes = rng.normal(size=(60, 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    angles = np.r_[np.zeros(5), 1e-9 * np.ones(5), rng.uniform(0, np.pi, 30), np.pi - np.logspace(-12, -2, 19), np.pi]
    rv = axes * angles[:, None]
    R = Rotation.from_rotvec(rv).as_matrix()
    out = log_rotation_batch(R)
    for a, b in zip(out, rv):
        if np.linalg.norm(b) > np.pi - 1e-6:       # at pi, v and -v are the same rotation
            assert np.allclose(a, b, atol=1e-7) or np.allclose(a, -b, atol=1e-7)
        else:
            assert np.allclose(a, b, atol=1e-12)


@pytest.mark.parametrize("kwargs, match", [
    ({"mask": "orientation"}, "mask: 'orientation' is not one of pose, position"),
    ({"mask": [1, 1, 1, 0, 0]}, "mask: expected 6 values"),
    ({"mask": [0] * 6}, "selects no component"),
    ({"method": "jacobian"}, "method: 'jacobian' is not one of auto, analytic, numeric"),
    ({"tol_position": 0.0}, "tol_position: must be a positive number"),
    ({"q0": [0, 0, 0]}, "q: expected shape"),
    ({"q0": np.zeros((2, 6))}, "q0: expected shape"),
])
def test_bad_options_are_input_errors(kwargs, match):
    robot = kr16()
    with pytest.raises(InputError, match=match):
        robot.ik(robot.fk(np.zeros((3, 6))), **kwargs)


def test_bad_targets_are_input_errors():
    robot = kr16()
    with pytest.raises(InputError, match="expected a 4x4 pose"):
        robot.ik(np.eye(3))
    bad = np.stack([np.eye(4), np.diag([1.0, 1.0, -1.0, 1.0])])
    with pytest.raises(InputError, match=r"target\[1\]: rotation block has det <= 0"):
        robot.ik(bad)
    with pytest.raises(InputError, match="no closed-form solver fits"):
        robkin.DHTable([[0.3, 0, 0.2, 0]] * 6, default_joints(["revolute"] * 6)).to_robot().ik(np.eye(4),
                                                                                                method="analytic")
    with pytest.raises(InputError, match="the mask is not the full pose"):
        robot.ik(np.eye(4), method="analytic", mask="position")


def test_cli_ik_on_ur5_and_bad_input(capsys):
    path = arm_file("ur5")
    T = robkin.load(path, tip_link="tool0").fk([0.3, -1.2, 1.4, -0.5, 1.1, 0.2])
    pose = ",".join(repr(float(v)) for v in T.ravel())
    assert main(["ik", path, "--tip-link", "tool0", "--pose", pose, "--all", "--json"]) == 0
    sols = json.loads(capsys.readouterr().out)["solutions"]
    assert len(sols) >= 2
    model = pin.buildModelFromUrdf(path)
    robot = robkin.load(path, tip_link="tool0")
    for s in sols:
        assert np.abs(pin_fk(model, robot, np.array(s["q"]), "tool0") - T).max() <= CHECK
    assert main(["ik", path, "--tip-link", "tool0", "--pose", "0.3,0.1,0.2,0,0,0", "--position-only",
                 "--q0=0,-1,1,0,0,0", "--json"]) == 0
    assert len(json.loads(capsys.readouterr().out)["solutions"]) == 1
    assert main(["ik", path, "--tip-link", "tool0", "--pose", "0.3,0.1,0.2,0,0,0", "--mask", "1,1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--mask" in err
    assert main(["ik", path, "--tip-link", "tool0", "--pose", "9,0,0,0,0,0", "--restarts", "2",
                 "--method", "numeric"]) == 0
    captured = capsys.readouterr()
    assert captured.out == "" and "no solution found from 3 start(s)" in captured.err
    assert main(["ik", path, "--tip-link", "tool0", "--pose", "9,0,0,0,0,0"]) == 0
    captured = capsys.readouterr()
    assert captured.out == "" and "three-parallel-6r): out of reach" in captured.err


def test_cli_fk_jacobian_and_manipulability(capsys):
    from robkin.kinematics.jacobian import jacobian_geometric, manipulability

    path = arm_file("ur5")
    robot = robkin.load(path, tip_link="tool0")
    q = [0.3, -1.2, 1.4, -0.5, 1.1, 0.2]
    assert main(["fk", path, "--tip-link", "tool0", "--q", ",".join(map(str, q)), "--jacobian",
                 "--manipulability", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert np.allclose(out["J"], jacobian_geometric(robot, q), atol=1e-15)
    assert out["manipulability"]["manipulability_translational"] == pytest.approx(manipulability(robot, q))
    assert set(out) == {"T", "position", "rpy", "quaternion", "joints", "q", "J", "manipulability"}
    assert main(["fk", path, "--tip-link", "tool0", "--q", ",".join(map(str, q)), "--jacobian"]) == 0
    text = capsys.readouterr().out
    assert "J (geometric" in text and "shoulder_pan_joint" in text


# ------------------------------------------------------------------------ compiled solver bookkeeping
def _limited_7r() -> robkin.Robot:
    """A KUKA iiwa-like 7R arm (standard DH, metres) with +-120 / +-170 degree limits."""
    dh = [[0, 0.36, -np.pi / 2, 0], [0, 0, np.pi / 2, 0], [0, 0.42, np.pi / 2, 0], [0, 0, -np.pi / 2, 0],
          [0, 0.4, -np.pi / 2, 0], [0, 0, np.pi / 2, 0], [0, 0.126, 0, 0]]
    joints = tuple(Joint(f"a{i + 1}", lower=-lim, upper=lim)
                   for i, lim in enumerate([2.96, 2.09, 2.96, 2.09, 2.96, 2.09, 3.05]))
    return robkin.DHTable(np.array(dh), joints).to_robot()


def test_numeric_ik_is_reproducible_and_a_batch_of_one_is_a_single_call():
    robot = _limited_7r()
    targets = robot.fk(robot.random_q(20, rng=11))
    a = robot.ik(targets, method="numeric", rng=3)
    b = robot.ik(targets, method="numeric", rng=np.random.default_rng(3))   # a Generator works too
    assert a.success.all() and b.success.all()
    np.testing.assert_array_equal(a.q, robot.ik(targets, method="numeric", rng=3).q)
    one, single = robot.ik(targets[:1], method="numeric", rng=5), robot.ik(targets[0], method="numeric", rng=5)
    np.testing.assert_array_equal(one.q[0], single.q)
    assert one.iterations[0] == single.iterations and single.success
    lim = robot.limits
    assert np.all((a.q >= lim[:, 0]) & (a.q <= lim[:, 1]))
    # independent check of every answer: pinocchio-free, by the tool pose the answer gives
    err = np.abs(robot.fk(a.q) - targets).max()
    assert err < 1e-8


def test_bad_rng_is_one_clear_input_error():
    robot = _limited_7r()
    with pytest.raises(InputError, match="rng"):
        robot.ik(robot.fk(np.zeros(7)), method="numeric", rng=-1)


def test_wrap_into_limits_matches_the_turn_formula():
    """The compiled wrapping against the formula written out in numpy: the turn k nearest to the
    reference, clipped to the turns that land within the limits."""
    from robkin.kinematics.limits import LIMIT_TOL, wrap_into_limits

    rng = np.random.default_rng(0)
    lim = np.array([[-1, 1], [-np.inf, np.inf], [-4, 4], [0.5, 0.6], [-7, -6.9], [2.0, np.inf]])
    rev = np.array([1, 1, 1, 1, 0, 1], bool)
    Q = rng.uniform(-20, 20, (4000, 6))
    Q[::7, 0] = np.nan
    ref = rng.uniform(-5, 5, (4000, 6))
    two_pi = 2 * np.pi
    with np.errstate(invalid="ignore"):
        k = np.clip(np.round((ref - Q) / two_pi), np.ceil((lim[:, 0] - LIMIT_TOL - Q) / two_pi),
                    np.floor((lim[:, 1] + LIMIT_TOL - Q) / two_pi))
    expected = np.where(rev, Q + k * two_pi, Q)
    inside = np.all((expected >= lim[:, 0] - LIMIT_TOL) & (expected <= lim[:, 1] + LIMIT_TOL), axis=1)
    got, ok = wrap_into_limits(Q, lim, rev, ref)
    np.testing.assert_array_equal(got, expected)
    np.testing.assert_array_equal(ok, inside)
    got3, ok3 = wrap_into_limits(Q.reshape(40, 100, 6), lim, rev, ref.reshape(40, 100, 6))
    np.testing.assert_array_equal(got3.reshape(-1, 6), expected)
    assert ok3.shape == (40, 100)
