"""Jacobians and manipulability: finite differences on random robots, pinocchio on real URDF arms, and
closed-form values for a planar two-link arm (Yoshikawa's l1 l2 |sin q2|)."""

from __future__ import annotations

import glob
import os
import sys

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import robkin
from robkin import se3
from robkin.errors import InputError
from robkin.kinematics.jacobian import (inverse_condition_number, jacobian_body, jacobian_geometric,
                                        jacobian_space, manipulability, measures, min_singular_value)
from robkin.robot import Joint

from strategies import robots

ROBOTS_DIR = (glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                     "example-robot-data", "robots")) or [""])[0]


def vee(W: np.ndarray) -> np.ndarray:
    return np.array([W[2, 1], W[0, 2], W[1, 0]])


def finite_difference_jacobians(robot: robkin.Robot, q: np.ndarray) -> tuple[np.ndarray, ...]:
    """Space (w, v), body (w, v) and geometric [v; w] Jacobians by central differences of Robot.fk."""
    T = robot.fk(q)
    Tinv = se3.inv(T)
    Js, Jb, Jg = (np.zeros((6, robot.n)) for _ in range(3))
    for i in range(robot.n):
        # step: 1e-6 rad (central differences err by ~h^2 ~ 1e-12 relative, rounding by eps/h ~ 2e-10),
        # or 1e-2 * robot size for a slide: T is affine in a prismatic q, so the difference is exact
        # but for rounding, which a long step keeps small. Both far inside the 1e-7 tolerance below.
        h = 1e-6 if robot.joints[i].revolute else 1e-2 * robot.scale
        dq = np.zeros(robot.n)
        dq[i] = h
        dT = (robot.fk(q + dq) - robot.fk(q - dq)) / (2 * h)
        S = dT @ Tinv                       # [S_i] in the space frame
        B = Tinv @ dT                       # [B_i] in the body frame
        Js[:, i] = np.r_[vee(S[:3, :3]), S[:3, 3]]
        Jb[:, i] = np.r_[vee(B[:3, :3]), B[:3, 3]]
        Jg[:, i] = np.r_[dT[:3, 3], vee(dT[:3, :3] @ T[:3, :3].T)]
    return Js, Jb, Jg


def sample_q(robot: robkin.Robot, seed: int, size: int | None = None) -> np.ndarray:
    """Random q: revolute within +-pi, prismatic within +-robot size (slides of the robot's own scale;
    random_q's +-pi default would put a millimetre robot's tool a thousand sizes away)."""
    q = robot.random_q(size, rng=seed, default_range=np.pi)
    return np.where(robot.revolute, q, q * robot.scale / np.pi)


def unit_free(J: np.ndarray, robot: robkin.Robot, v_rows: slice) -> np.ndarray:
    """J with the linear-velocity rows of revolute columns divided by the robot's size (mm, m and km
    robots alike); prismatic columns are unit-free already."""
    J = J.copy()
    J[v_rows, robot.revolute] /= robot.scale
    return J


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(robot=robots(max_joints=6), seed=st.integers(0, 2**16))
def test_jacobians_match_finite_differences(robot, seed):
    q = sample_q(robot, seed)
    fd_space, fd_body, fd_geometric = finite_difference_jacobians(robot, q)
    pairs = [(jacobian_space(robot, q), fd_space, slice(3, 6)), (jacobian_body(robot, q), fd_body, slice(3, 6)),
             (jacobian_geometric(robot, q), fd_geometric, slice(0, 3))]
    for J, ref, v_rows in pairs:
        assert np.allclose(unit_free(J, robot, v_rows), unit_free(ref, robot, v_rows), rtol=0, atol=1e-7)


@settings(max_examples=15, deadline=None)
@given(robot=robots(max_joints=5), seed=st.integers(0, 2**16))
def test_batch_equals_single(robot, seed):
    Q = sample_q(robot, seed, 4)
    for f in (jacobian_space, jacobian_body, jacobian_geometric):
        batch = f(robot, Q)
        assert batch.shape == (4, 6, robot.n)
        for k in range(4):
            assert np.allclose(batch[k], f(robot, Q[k]), rtol=0, atol=1e-12 * robot.scale)
    m = measures(robot, Q)
    for key, values in m.items():
        assert np.shape(values) == (4,)
        assert np.allclose(values, [measures(robot, q)[key] for q in Q], rtol=1e-12, atol=1e-14)


def planar_2r(l1: float = 1.0, l2: float = 1.0) -> robkin.Robot:
    """Two revolute joints about z, links l1 and l2 along x (standard DH, alpha = 0)."""
    return robkin.DHTable([[l1, 0, 0, 0], [l2, 0, 0, 0]], robkin.robot.default_joints(["revolute"] * 2)).to_robot()


def test_two_link_manipulability_is_l1_l2_sin_q2():
    # Yoshikawa (1985): for the planar 2R arm w = l1 l2 |sin q2|
    robot = planar_2r(0.7, 0.4)
    q = np.array([[0.3, 0.0], [0.3, 0.5], [-1.0, np.pi / 2], [2.0, -2.5]])
    assert np.allclose(manipulability(robot, q), 0.7 * 0.4 * np.abs(np.sin(q[:, 1])), atol=1e-15)
    assert manipulability(robot, q[1]) == pytest.approx(0.28 * np.sin(0.5))


def test_two_link_condition_at_right_angle_is_golden():
    # l1 = l2 = 1, q = (0, pi/2): J_v (xy rows) = [[-1, -1], [1, 0]], J J^T = [[2, -1], [-1, 1]] with
    # eigenvalues (3 +- sqrt 5)/2, so sigma_min = (sqrt 5 - 1)/2 and sigma_min / sigma_max = (3 - sqrt 5)/2.
    robot = planar_2r()
    q = [0.0, np.pi / 2]
    assert min_singular_value(robot, q) == pytest.approx((np.sqrt(5) - 1) / 2, abs=1e-14)
    assert inverse_condition_number(robot, q) == pytest.approx((3 - np.sqrt(5)) / 2, abs=1e-14)
    assert inverse_condition_number(robot, [0.0, 0.0]) == pytest.approx(0.0, abs=1e-15)  # stretched
    assert min_singular_value(robot, [0.0, 0.0]) == pytest.approx(0.0, abs=1e-15)


def test_spherical_wrist_rotational_measures():
    # Three orthogonal intersecting revolute axes (z, then y, then x at q = 0): J_w = [z, y', x''],
    # orthonormal at q = 0 (manipulability 1, isotropic) and singular when axes 1 and 3 align.
    frames = [np.eye(4), se3.rot_x(-np.pi / 2), se3.rot_y(np.pi / 2), se3.trans(0, 0, 0.1)]
    robot = robkin.Robot(np.array(frames), robkin.robot.default_joints(["revolute"] * 3))
    assert manipulability(robot, np.zeros(3), "rotational") == pytest.approx(1.0, abs=1e-14)
    assert inverse_condition_number(robot, np.zeros(3), "rotational") == pytest.approx(1.0, abs=1e-14)
    # axis 2 turned by pi/2 takes axis 3 onto axis 1: the wrist is singular
    assert manipulability(robot, [0.0, np.pi / 2, 0.0], "rotational") == pytest.approx(0.0, abs=1e-14)


def test_prismatic_columns_and_flip():
    # A prismatic joint with flip still moves along its GJD axis (its positive direction): column (z; 0)
    joints = (Joint("p", "prismatic", flip=True), Joint("r"))
    robot = robkin.DHTable([[0.5, 0, 0, 0], [0.3, 0, 0, 0]], joints).to_robot()
    J = jacobian_geometric(robot, [0.2, 0.4])
    assert np.allclose(J[:, 0], [0, 0, -1, 0, 0, 0])          # d = -q: the tool moves down
    assert np.allclose(J[3:, 1], [0, 0, 1])


def test_unknown_kind_is_an_input_error():
    with pytest.raises(InputError, match="not one of translational, rotational, full"):
        manipulability(planar_2r(), [0, 0], "linear")


# --------------------------------------------------------------------------------------- pinocchio
pin = pytest.importorskip("pinocchio")

ARMS = [("ur_description/urdf/ur5_robot.urdf", "tool0"),
        ("panda_description/urdf/panda.urdf", "panda_hand_tcp"),
        ("kinova_description/robots/kinova.urdf", "j2s6s200_end_effector")]


@pytest.mark.parametrize("rel, tip", ARMS)
def test_jacobians_match_pinocchio(rel, tip):
    path = os.path.join(ROBOTS_DIR, rel)
    if not os.path.isfile(path):
        pytest.skip(f"example-robot-data file {rel} not installed")
    robot = robkin.load(path, tip_link=tip)
    model = pin.buildModelFromUrdf(path)
    data = model.createData()
    fid = model.getFrameId(tip)
    for q in robot.random_q(5, rng=7):
        qp = pin.neutral(model)
        cols = []
        for joint, value in zip(robot.joints, q):
            jm = model.joints[model.getJointId(joint.name)]
            if jm.nq == 2:  # continuous joint: (cos, sin)
                qp[jm.idx_q], qp[jm.idx_q + 1] = np.cos(value), np.sin(value)
            else:
                qp[jm.idx_q] = value
            cols.append(jm.idx_v)
        pin.computeJointJacobians(model, data, qp)
        pin.updateFramePlacements(model, data)

        def pj(ref):
            return pin.getFrameJacobian(model, data, fid, ref)[:, cols]   # rows (v, w)

        swap = np.r_[3:6, 0:3]
        # 1e-12, the figure docs/benchmarks.md states (absolute: np.allclose's default rtol=1e-5 used to
        # loosen it): both are exact formulas in double precision on the same ~1 m geometry; observed
        # 6.7e-16 (2026-11-28), so 5e-15 (7.5x: another CPU or BLAS rounds differently) guards it too
        for atol in (1e-12, 5e-15):
            assert np.allclose(jacobian_geometric(robot, q), pj(pin.LOCAL_WORLD_ALIGNED), atol=atol, rtol=0)
            assert np.allclose(jacobian_space(robot, q), pj(pin.WORLD)[swap], atol=atol, rtol=0)
            assert np.allclose(jacobian_body(robot, q), pj(pin.LOCAL)[swap], atol=atol, rtol=0)


@settings(max_examples=20, deadline=None)
@given(robot=robots(max_joints=7), seed=st.integers(0, 2**16))
def test_manipulability_is_the_product_of_numpy_singular_values(robot, seed):
    """The compiled volume (Householder QR) against numpy's SVD of the same Jacobian rows, for wide,
    square and tall blocks (n below, at and above the number of rows)."""
    # the strategy sometimes draws robots whose whole geometry is rounding noise at the origin (sizes down
    # to 1e-179): their Jacobian entries square to below the smallest float, and a volume of them means nothing
    assume(robot.scale > 1e-6)
    Q = sample_q(robot, seed, 3)
    J = jacobian_geometric(robot, Q)
    for kind, rows in (("translational", slice(0, 3)), ("rotational", slice(3, 6)), ("full", slice(0, 6))):
        expected = np.prod(np.linalg.svd(J[:, rows], compute_uv=False), axis=-1)
        block = J[:, rows]
        # every singular value is at most the Frobenius norm: a bound on the product's size
        size = np.linalg.norm(block, axis=(1, 2)) ** min(block.shape[1:])
        got = manipulability(robot, Q, kind)
        # 1e-150: the QR sums squares of Jacobian entries, and entries below ~1e-154 (a tool point within
        # 1e-154 of an axis on a robot of ordinary size) square to below the smallest normal float; a
        # volume that small may come back as 0 where LAPACK's scaled norms still resolve it (e.g. 3e-169)
        assert np.allclose(got, expected, rtol=0, atol=1e-12 * size + 1e-150)
