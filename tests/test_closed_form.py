"""Closed-form IK (the compiled kernels) against independent peers: every solution set compared with EAIK's
on random targets, every solution re-checked by pinocchio's forward kinematics, joint limits, and the
edge cases (wrist and shoulder singular, stretched elbow, out of reach) without NaN."""

from __future__ import annotations

import numpy as np
import pytest

import robkin
from robkin.kinematics.analytic6r import SphericalWrist6R, ThreeParallel6R
from robkin.kinematics.closed_form import closed_form_solver
from robkin.robot import Joint

from test_ik import CHECK, arm_file, load_arm, pin_fk, puma560

pin = pytest.importorskip("pinocchio")
eaik = pytest.importorskip("eaik.pybindings.EAIK")

#: Two solutions are the same when every joint agrees to this modulo 2 pi (radians). The closed forms
#: land at ~1e-12; at wrist singularities both peers split a free angle sum differently, so such
#: targets are compared by the pose they reach, not here.
SAME = 1e-6


def pin_geometry(model, robot: robkin.Robot, tip: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """From pinocchio alone: joint axes (6, 3), a point on each (6, 3) and the tool pose (4, 4) at q = 0."""
    data = model.createData()
    q = pin.neutral(model)
    pin.computeJointJacobians(model, data, q)
    pin.framesForwardKinematics(model, data, q)
    H, P = [], []
    for joint in robot.joints:
        jid = model.getJointId(joint.name)
        col = pin.getJointJacobian(model, data, jid, pin.ReferenceFrame.WORLD)[:, model.joints[jid].idx_v]
        v, w = col[:3], col[3:]                 # twist of a unit joint speed: v = -w x p
        H.append(w)
        P.append(np.cross(w, v))                # the point of the axis nearest the origin
    return np.array(H), np.array(P), data.oMf[model.getFrameId(tip)].homogeneous


def eaik_robot(H: np.ndarray, P: np.ndarray, M: np.ndarray):
    """EAIK's solver for axes H through points P with tool pose M at q = 0."""
    offsets = np.vstack([P[0], np.diff(P, axis=0), M[:3, 3] - P[-1]])
    return eaik.Robot(H.T, offsets.T, M[:3, :3], [], True)


def eaik_exact(solver, T: np.ndarray) -> np.ndarray:
    """EAIK's exact (not least-squares) solutions (S, 6) of target T."""
    sol = solver.calculate_IK(T)
    return np.asarray(sol.Q).reshape(-1, 6)[~np.asarray(sol.is_LS, bool)]


def same(a: np.ndarray, b: np.ndarray) -> bool:
    return bool(np.abs(np.angle(np.exp(1j * (a - b)))).max() <= SAME)


def fits_limits(q: np.ndarray, lim: np.ndarray) -> bool:
    """Whether some whole turns of each angle put q within the limits."""
    k = np.ceil((lim[:, 0] - q) / (2 * np.pi))
    return bool(np.all(q + 2 * np.pi * k <= lim[:, 1] + 1e-12))


def compare_with_eaik(robot, model, tip, solver, targets) -> int:
    """Assert robkin's solution set equals EAIK's (within the limits) for each target; both re-checked
    by pinocchio. Returns how many solutions were compared."""
    res = robot.ik(targets, all_solutions=True)
    assert res.success.all()
    lim = robot.limits
    compared = 0
    for T, ours in zip(targets, res.solutions):
        theirs = [q for q in eaik_exact(solver, T) if fits_limits(q, lim)]
        for q in ours:
            assert np.all((q >= lim[:, 0]) & (q <= lim[:, 1]))
            assert np.abs(pin_fk(model, robot, q, tip) - T).max() <= CHECK
            assert any(same(q, p) for p in theirs)
        for p in theirs:
            assert np.abs(pin_fk(model, robot, p, tip) - T).max() <= 1e-6   # EAIK's own accuracy
            assert any(same(q, p) for q in ours)
        compared += len(ours)
    return compared


@pytest.mark.parametrize("name, kind", [("ur5", ThreeParallel6R), ("kinova", SphericalWrist6R)])
def test_solution_sets_match_eaik_on_real_arms(name, kind):
    robot, model, tip = load_arm(name)
    assert isinstance(closed_form_solver(robot), kind)
    solver = eaik_robot(*pin_geometry(model, robot, tip))
    Q = robot.random_q(150, rng=31)
    targets = np.array([pin_fk(model, robot, q, tip) for q in Q])        # targets from the peer
    assert compare_with_eaik(robot, model, tip, solver, targets) >= 150 * 4


def test_puma_solution_sets_match_eaik_with_and_without_limits():
    from eaik.IK_DH import DhRobot

    robot = puma560()
    solver = DhRobot(np.array([np.pi / 2, 0, -np.pi / 2, np.pi / 2, -np.pi / 2, 0]),
                     np.array([0, 0.4318, 0.0203, 0, 0, 0]), np.array([0, 0, 0.15005, 0.4318, 0, 0]))._robot
    q = robot.random_q(5, rng=32)
    assert np.abs(np.array([solver.fwdkin(x) for x in q]) - robot.fk(q)).max() < 1e-12   # same arm
    limited = robot.replace(joints=tuple(Joint(f"j{i + 1}", "revolute", lo, hi) for i, (lo, hi) in enumerate(
        [(-2.8, 2.8), (-3.9, 0.8), (-0.8, 3.9), (-1.9, 2.9), (-1.7, 1.7), (-4.6, 4.6)])))
    targets = robot.fk(limited.random_q(150, rng=33))
    for arm in (robot, limited):
        res = arm.ik(targets, all_solutions=True)
        assert res.success.all()
        for T, ours in zip(targets, res.solutions):
            theirs = [p for p in eaik_exact(solver, T) if fits_limits(p, arm.limits)]
            assert np.abs(arm.fk(ours) - T).max() <= 1e-9
            assert np.all((ours >= arm.limits[:, 0]) & (ours <= arm.limits[:, 1]))
            assert len(ours) == len(theirs)
            assert all(any(same(q, p) for p in theirs) for q in ours)


def test_limits_choose_the_turn_nearest_q0():
    # UR5 joints 1, 2, 4-6 span +-2 pi: each angle has two turns within the limits, and q0 picks one
    robot, model, tip = load_arm("ur5")
    q = np.array([0.4, -1.1, 1.3, -0.6, 0.9, 0.2])
    T = robot.fk(q)
    for shift in ([0, 0, 0, 0, 0, 0], [-2 * np.pi, 0, 0, 2 * np.pi, 0, -2 * np.pi]):
        q0 = q + np.array(shift)
        res = robot.ik(T, q0=q0)
        assert res.success and np.allclose(res.q, q0, atol=1e-9)


# ------------------------------------------------------------------------------------------ edge cases
def edge_configurations() -> np.ndarray:
    return np.array([
        [0.3, -1.0, 1.2, -0.4, 0.0, 0.7],           # wrist singular: axis 6 along axes 2-4
        [0.3, -1.0, 1.2, -0.4, 1e-10, 0.7],         # just next to it
        [0.3, -1.0, 0.0, -0.4, 0.8, 0.7],           # stretched elbow
        [0.3, -1.0, np.pi, -0.4, 0.8, 0.7],         # folded elbow
        [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],             # home: stretched and wrist singular at once
        [0.3, -np.pi / 2, 0.0, -np.pi / 2, 0.0, 0.0],  # upright, wrist singular
    ])


@pytest.mark.parametrize("name", ["ur5", "kinova"])
def test_singular_and_boundary_targets_solve_without_nan(name):
    robot, model, tip = load_arm(name)
    Q = np.clip(edge_configurations(), robot.limits[:, 0], robot.limits[:, 1])
    targets = np.array([pin_fk(model, robot, q, tip) for q in Q])
    branches = closed_form_solver(robot).solve(targets, np.zeros((len(Q), 6)))
    assert np.isfinite(branches.q).all()
    res = robot.ik(targets, all_solutions=True)
    assert res.success.all()
    for T, sols in zip(targets, res.solutions):
        for q in sols:
            assert np.abs(pin_fk(model, robot, q, tip) - T).max() <= CHECK


def test_shoulder_singular_target_on_ur5():
    # the point where axes 5 and 6 meet is on axis 1 only if the shoulder offset is cancelled, which a
    # UR5 cannot do; its nearest case is that point closest to axis 1, where q1 is still determined
    robot, model, tip = load_arm("ur5")
    solver = closed_form_solver(robot)
    q = np.array([0.2, -np.pi / 2, 0.0, 0.0, 0.5, 0.0])
    T = pin_fk(model, robot, q, tip)
    b = solver.solve(T[None], np.zeros((1, 6)))
    assert np.isfinite(b.q).all() and b.valid.any()


def test_out_of_reach_targets_have_reasons_and_no_nan():
    robot, model, tip = load_arm("ur5")
    solver = closed_form_solver(robot)
    T = pin_fk(model, robot, np.zeros(6), tip)
    far, below = T.copy(), T.copy()
    far[:3, 3] *= 5.0
    below[:3, 3] = [1.0, 2.0, -5.0]
    b = solver.solve(np.stack([far, below]), np.zeros((2, 6)))
    assert not b.valid.any() and np.isfinite(b.q).all()
    assert all(r.startswith("out of reach") for r in b.reason)
    res = robot.ik(np.stack([far, below]), method="analytic")
    assert not res.success.any() and np.isnan(res.q).all()
    # far away on axis 1 itself: joint 1 is free there, so "no solution" is not claimed as proven
    on_axis = T.copy()
    on_axis[:3, 3] = [0.0, 0.0, -5.0]
    b = solver.solve(on_axis[None], np.zeros((1, 6)))
    assert not b.valid.any() and b.uncertain.all() and b.reason[0].startswith("singular target")


def test_limits_rejecting_every_branch_are_reported():
    robot = puma560()
    tight = robot.replace(joints=tuple(Joint(f"j{i + 1}", "revolute", -0.1, 0.1) for i in range(6)))
    T = robot.fk([1.0, -0.5, 0.7, 0.3, 0.6, -0.4])
    b = closed_form_solver(tight).solve(T[None], np.zeros((1, 6)))
    assert not b.valid.any() and b.reason == ["solutions exist but violate the joint limits"]


def test_batch_equals_single_calls():
    robot, _, _ = load_arm("ur5")
    solver = closed_form_solver(robot)
    Q = robot.random_q(20, rng=34)
    targets, ref = robot.fk(Q), robot.random_q(20, rng=35)
    batch = solver.solve(targets, ref)
    for i in range(20):
        one = solver.solve(targets[i:i + 1], ref[i:i + 1])
        assert np.array_equal(one.q[0], batch.q[i]) and np.array_equal(one.valid[0], batch.valid[i])


# ------------------------------------------------------------------------------------ random arms
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from robkin import se3  # noqa: E402
from robkin.robot import default_joints  # noqa: E402

_sign = st.sampled_from([1.0, -1.0])
_length = st.floats(0.1, 0.8).flatmap(lambda x: _sign.map(lambda s: s * x))     # a non-zero link
_any_length = st.one_of(st.just(0.0), _length)


@st.composite
def family_tables(draw, kind: str, offsets: bool) -> np.ndarray:
    """Standard DH rows (a, d, alpha, theta) of a random arm of one closed-form family.

    spherical wrist: alpha_1 = +-pi/2, alpha_2 = 0 (axes 2 || 3), a_4 = a_5 = d_5 = 0 (axes 4-6 meet);
    three parallel: alpha_1 = +-pi/2, alpha_2 = alpha_3 = 0 (axes 2 || 3 || 4), alpha_4 = +-pi/2,
    a_5 = 0 (axes 5 and 6 meet), d_5 != 0 (so not also a spherical wrist). Other lengths random; the
    joint offsets theta random if asked.
    """
    s = [draw(_sign) * np.pi / 2 for _ in range(4)]
    if kind == "spherical":
        a = [draw(_any_length), draw(_length), draw(_any_length), 0.0, 0.0, 0.0]
        d = [draw(_any_length), draw(_any_length), draw(_any_length), draw(_length), 0.0, draw(_any_length)]
        alpha = [s[0], 0.0, s[1], s[2], s[3], 0.0]
    else:
        a = [draw(_any_length), draw(_length), draw(_length), draw(_any_length), 0.0, 0.0]
        d = [draw(_any_length), draw(_any_length), draw(_any_length), draw(_any_length), draw(_length),
             draw(_any_length)]
        alpha = [s[0], 0.0, 0.0, s[1], s[2], 0.0]
    theta = [draw(st.floats(-np.pi, np.pi)) if offsets else 0.0 for _ in range(6)]
    return np.column_stack([a, d, alpha, theta])


def family_robot(rows: np.ndarray, tool: np.ndarray | None = None) -> robkin.Robot:
    return robkin.DHTable(rows, default_joints(["revolute"] * 6), tool=np.eye(4) if tool is None else tool
                          ).to_robot()


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(kind=st.sampled_from(["spherical", "parallel"]), data=st.data(), seed=st.integers(0, 2**16))
def test_random_arms_of_both_families_match_eaik(kind, data, seed):
    from eaik.IK_DH import DhRobot

    rows = data.draw(family_tables(kind, offsets=False))
    robot = family_robot(rows)
    assert isinstance(closed_form_solver(robot), SphericalWrist6R if kind == "spherical" else ThreeParallel6R)
    solver = DhRobot(rows[:, 2], rows[:, 0], rows[:, 1])._robot
    targets = robot.fk(robot.random_q(8, rng=seed))
    assert np.abs(np.array([solver.fwdkin(q) for q in robot.random_q(3, rng=seed)])
                  - robot.fk(robot.random_q(3, rng=seed))).max() < 1e-12      # the same arm in both
    res = robot.ik(targets, all_solutions=True)
    assert res.success.all()
    for T, ours in zip(targets, res.solutions):
        assert np.abs(robot.fk(ours) - T).max() <= 1e-9
        theirs = eaik_exact(solver, T)
        theirs = theirs[np.abs(np.array([solver.fwdkin(p) for p in theirs]) - T).max(axis=(1, 2)) <= 1e-9] \
            if len(theirs) else theirs
        assert all(any(same(q, p) for q in ours) for p in theirs)    # every exact EAIK solution is ours
        assert all(any(same(q, p) for p in theirs) for q in ours)    # and the other way round


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(kind=st.sampled_from(["spherical", "parallel"]), data=st.data(), seed=st.integers(0, 2**16))
def test_random_arms_with_offsets_and_tools_find_the_generating_configuration(kind, data, seed):
    rows = data.draw(family_tables(kind, offsets=True))
    tool = se3.trans(*data.draw(st.lists(st.floats(-0.3, 0.3), min_size=3, max_size=3))) \
        @ se3.rot_y(data.draw(st.floats(-np.pi, np.pi))) @ se3.rot_z(data.draw(st.floats(-np.pi, np.pi)))
    robot = family_robot(rows, tool)
    assert closed_form_solver(robot) is not None
    Q = robot.random_q(8, rng=seed)
    targets = robot.fk(Q)
    res = robot.ik(targets, all_solutions=True)
    assert res.success.all()
    for q, T, sols in zip(Q, targets, res.solutions):
        assert 1 <= len(sols) <= 8
        assert np.abs(robot.fk(sols) - T).max() <= 1e-9
        assert any(same(q, s) for s in sols)


# ------------------------------------------------------------------------------------ bookkeeping
@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**16), k=st.integers(0, 12), n=st.integers(1, 7))
def test_distinct_sorted_matches_its_definition(seed, k, n):
    from robkin.compiled.ik.solutions import distinct_sorted

    rng = np.random.default_rng(seed)
    base = rng.uniform(-3, 3, size=(max(k // 2, 1), n))
    Q = base[rng.integers(0, len(base), size=k)] + rng.choice([0.0, 1e-9, 1e-3], size=(k, n))  # near-twins
    ref, scale = rng.uniform(-1, 1, n), rng.choice([1.0, 0.5], n)
    out = distinct_sorted(Q, ref, scale, 1e-6)
    # the definition, spelled out: nearest first (ties in input order), drop rows within 1e-6 of a kept one
    order = sorted(range(k), key=lambda i: np.linalg.norm((Q[i] - ref) / scale))
    keep: list[np.ndarray] = []
    for i in order:
        if all(np.max(np.abs(Q[i] - kq) / scale) > 1e-6 for kq in keep):
            keep.append(Q[i])
    assert out.shape == (len(keep), n)
    assert np.array_equal(out, np.array(keep).reshape(-1, n))


@st.composite
def scara_arms(draw) -> robkin.Robot:
    """A random SCARA-type arm (standard DH, every alpha 0 or pi): 2 or 3 revolute joints (the first two
    with links 0.1-0.8 long) and 0-2 prismatic joints in random places, offsets, flips and limits."""
    n_rev = draw(st.sampled_from([2, 3]))
    types = ["revolute"] * n_rev + ["prismatic"] * draw(st.integers(0, 2))
    order = draw(st.permutations(types))
    rev_seen = 0
    rows, joints = [], []
    for i, kind in enumerate(order):
        link = draw(_length) if kind == "revolute" and rev_seen < 2 else draw(_any_length)
        rev_seen += kind == "revolute"
        rows.append([link, draw(st.floats(-0.3, 0.3)), draw(st.sampled_from([0.0, np.pi])),
                     draw(st.floats(-np.pi, np.pi))])
        lo = draw(st.floats(-3.0, -0.5)) if kind == "revolute" else draw(st.floats(-0.5, 0.0))
        joints.append(Joint(f"j{i + 1}", kind, lo, lo + draw(st.floats(1.0, 6.0)), flip=draw(st.booleans())))
    return robkin.DHTable(rows, tuple(joints)).to_robot()


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(robot=scara_arms(), seed=st.integers(0, 2**16))
def test_random_scara_arms_reach_their_targets_within_limits(robot, seed):
    from hypothesis import assume

    from robkin.kinematics.scara import ScaraSolver

    solver = closed_form_solver(robot)
    assume(isinstance(solver, ScaraSolver))        # not when the second link or the wrist offset is 0
    Q = robot.random_q(10, rng=seed)
    targets = robot.fk(Q)
    res = robot.ik(targets, all_solutions=True)
    assert res.success.all() and res.method == "scara"
    lim, rev = robot.limits, robot.revolute
    for q, T, sols in zip(Q, targets, res.solutions):
        assert 1 <= len(sols) <= 2
        assert np.abs(robot.fk(sols) - T).max() <= 1e-9
        assert np.all((sols >= lim[:, 0] - 1e-12) & (sols <= lim[:, 1] + 1e-12))
        if (~rev).sum() <= 1:                       # no redundant vertical pair: q itself is a solution
            assert any(same(q, s) for s in sols)
