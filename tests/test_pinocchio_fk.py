"""Forward kinematics against an independent peer: pinocchio, fed URDF strings written here.

Each random chain is written as URDF text (joint origins with xyz/rpy, arbitrary unit axes, revolute
and prismatic joints, a fixed tool joint) and loaded with ``pinocchio.buildModelFromXML``. The same
robot is built in robkin by composing the URDF transforms by hand (not with robkin's URDF reader,
tested elsewhere), and both FKs are compared at random q, then again after converting the robot to
every representation.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import robkin
from robkin import se3
from robkin.robot import Joint, Robot

pin = pytest.importorskip("pinocchio")

#: pinocchio and robkin both compose ~n 4x4 products in float64: rounding noise, with margin; the
#: same 1e-9 (relative to the robot's size) that robkin promises between its own representations
FK_TOL = 1e-9
#: what is observed, so that a regression far below the promise still fails: over ~770 random chains
#: (1-8 joints, mm / m / km; this file's draws and 700 more, 2026-11-28) the largest difference was
#: 1.04e-14 (a prismatic column of a Jacobian, a direction; FK 7.7e-15; rotation entries and directions
#: absolute, lengths relative to the robot's size); 5e-14 is ~5x that, because hypothesis's search keeps reaching new
#: tails and another CPU or BLAS rounds the products differently.
ROUNDING_TOL = 5e-14


def assert_fk_close(got, expected, size: float = 1.0, err_msg: str = "") -> None:
    """got == expected to the promise (FK_TOL) and to the rounding level observed (ROUNDING_TOL), both
    absolute and times ``size`` (the robot's size for lengths, 1 for rotation entries and directions)."""
    np.testing.assert_allclose(got, expected, rtol=0, atol=FK_TOL * size, err_msg=f"the promise: {err_msg}")
    np.testing.assert_allclose(got, expected, rtol=0, atol=ROUNDING_TOL * size,
                               err_msg=f"the rounding level observed: {err_msg}")


def _f(x: float) -> str:
    return repr(float(x))  # shortest exact round-trip text of a float64


def chain_urdf(origins: list[tuple[np.ndarray, np.ndarray]], axes: list[np.ndarray], types: list[str],
               tool: tuple[np.ndarray, np.ndarray]) -> str:
    """URDF text of a serial chain base -> link1 -> ... -> linkN -> tool."""
    parts = ['<?xml version="1.0"?>', '<robot name="drawn">', '  <link name="base"/>']
    parent = "base"
    for i, ((rpy, xyz), axis, kind) in enumerate(zip(origins, axes, types), start=1):
        limits = '<limit lower="-4" upper="4" effort="1" velocity="1"/>'
        parts += [f'  <link name="link{i}"/>',
                  f'  <joint name="joint{i}" type="{kind}">',
                  f'    <parent link="{parent}"/><child link="link{i}"/>',
                  f'    <origin xyz="{" ".join(map(_f, xyz))}" rpy="{" ".join(map(_f, rpy))}"/>',
                  f'    <axis xyz="{" ".join(map(_f, axis))}"/>',
                  f'    {limits}',
                  '  </joint>']
        parent = f"link{i}"
    rpy, xyz = tool
    parts += ['  <link name="tool"/>',
              '  <joint name="tool_joint" type="fixed">',
              f'    <parent link="{parent}"/><child link="tool"/>',
              f'    <origin xyz="{" ".join(map(_f, xyz))}" rpy="{" ".join(map(_f, rpy))}"/>',
              '  </joint>', '</robot>']
    return "\n".join(parts)


def robot_by_hand(origins, axes, types, tool) -> Robot:
    """The GJD of the URDF chain: J_i = (product of the origins up to joint i) @ (a frame whose z is
    the joint axis), tool = product of all origins. URDF joints move about/along their axis in the
    joint frame, so any rotation taking z to the axis gives a valid GJD frame."""
    T = np.eye(4)
    frames = []
    for (rpy, xyz), axis in zip(origins, axes):
        T = T @ se3.homogeneous(se3.matrix_from_rpy(rpy), xyz)
        z = axis / np.linalg.norm(axis)
        x = np.cross(z, [0.3, -0.5, 0.7])
        x /= np.linalg.norm(x)
        frames.append(T @ se3.homogeneous(np.column_stack([x, np.cross(z, x), z]), np.zeros(3)))
    rpy, xyz = tool
    frames.append(T @ se3.homogeneous(se3.matrix_from_rpy(rpy), xyz))
    joints = tuple(Joint(f"joint{i + 1}", kind) for i, kind in enumerate(types))
    return Robot(np.array(frames), joints)


def pinocchio_fk(model, data, tool_id: int, q: np.ndarray) -> np.ndarray:
    pin.framesForwardKinematics(model, data, q)
    return data.oMf[tool_id].homogeneous


def random_chain(rng: np.random.Generator, n: int, unit: float):
    origins = [(rng.uniform(-np.pi, np.pi, 3), rng.uniform(-1, 1, 3) * unit) for _ in range(n)]
    axes = []
    for _ in range(n):
        kind = rng.integers(3)
        if kind == 0:  # a coordinate axis, either sign (the common URDF case)
            a = np.zeros(3)
            a[rng.integers(3)] = rng.choice([-1.0, 1.0])
        else:  # tilted
            a = rng.normal(size=3)
            a /= np.linalg.norm(a)
        axes.append(a)
    types = [str(rng.choice(["revolute", "prismatic"])) for _ in range(n)]
    tool = (rng.uniform(-np.pi, np.pi, 3), rng.uniform(-1, 1, 3) * unit)
    return origins, axes, types, tool


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 8), unit=st.sampled_from([1e-3, 1.0, 1e3]))
def test_fk_matches_pinocchio_on_random_urdf_chains(seed: int, n: int, unit: float):
    rng = np.random.default_rng(seed)
    origins, axes, types, tool = random_chain(rng, n, unit)
    model = pin.buildModelFromXML(chain_urdf(origins, axes, types, tool))
    assert model.nq == n  # one configuration variable per joint, in chain order
    data = model.createData()
    tool_id = model.getFrameId("tool")
    robot = robot_by_hand(origins, axes, types, tool)
    Q = rng.uniform(-3, 3, size=(6, n)) * np.where(robot.revolute, 1.0, unit)
    expected = np.stack([pinocchio_fk(model, data, tool_id, q) for q in Q])
    scale = max(robot.scale, float(np.abs(expected[:, :3, 3]).max()))
    for got in (robot.fk(Q), np.stack([robot.fk(q) for q in Q])):
        assert_fk_close(got[:, :3, :3], expected[:, :3, :3])
        assert_fk_close(got[:, :3, 3], expected[:, :3, 3], scale)
    # and through every representation robkin writes
    reps = [robkin.dh_from_robot(robot), robkin.mdh_from_robot(robot), robkin.poe_from_robot(robot, "space"),
            robkin.poe_from_robot(robot, "body"), robkin.rpy_from_robot(robot)]
    for rep in reps:
        got = rep.fk(Q)
        assert_fk_close(got[:, :3, :3], expected[:, :3, :3], err_msg=type(rep).__name__)
        assert_fk_close(got[:, :3, 3], expected[:, :3, 3], scale, err_msg=type(rep).__name__)


def test_zero_configuration_is_the_tool_pose():
    rng = np.random.default_rng(5)
    origins, axes, types, tool = random_chain(rng, 6, 1.0)
    model = pin.buildModelFromXML(chain_urdf(origins, axes, types, tool))
    data = model.createData()
    robot = robot_by_hand(origins, axes, types, tool)
    np.testing.assert_allclose(pinocchio_fk(model, data, model.getFrameId("tool"), np.zeros(6)), robot.tool,
                               atol=1e-12)


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 8), unit=st.sampled_from([1e-3, 1.0, 1e3]))
def test_compiled_frames_and_jacobians_match_pinocchio(seed: int, n: int, unit: float):
    """The compiled core against pinocchio on random URDF chains (revolute and prismatic joints,
    tilted axes, mm to km): the frames along the chain (joint i's origin and axis after its motion)
    and the geometric, space and body Jacobians at the tool, for one q, a batch and a batch of one."""
    from robkin.kinematics.jacobian import jacobian_body, jacobian_geometric, jacobian_space

    rng = np.random.default_rng(seed)
    origins, axes, types, tool = random_chain(rng, n, unit)
    model = pin.buildModelFromXML(chain_urdf(origins, axes, types, tool))
    data = model.createData()
    tool_id = model.getFrameId("tool")
    robot = robot_by_hand(origins, axes, types, tool)
    Q = rng.uniform(-3, 3, size=(5, n)) * np.where(robot.revolute, 1.0, unit)
    size = max(robot.scale, unit)
    swap = np.r_[3:6, 0:3]                  # pinocchio's rows are (v, w); robkin's space/body (w, v)
    frames = robot.frames_at(Q)
    J = {"geometric": jacobian_geometric(robot, Q), "space": jacobian_space(robot, Q),
         "body": jacobian_body(robot, Q)}
    for k, q in enumerate(Q):
        pin.computeJointJacobians(model, data, q)
        pin.updateFramePlacements(model, data)
        for i in range(n):
            placement = data.oMi[i + 1]
            assert_fk_close(frames[k, i, :3, 3], placement.translation, size)
            assert_fk_close(frames[k, i, :3, 2], placement.rotation @ axes[i])
        tool_pose = data.oMf[tool_id].homogeneous
        assert_fk_close(frames[k, n, :3, :3], tool_pose[:3, :3])            # rotation: no unit
        assert_fk_close(frames[k, n, :3, 3], tool_pose[:3, 3], size)        # a length
        expected = {kind: np.reshape(pin.getFrameJacobian(model, data, tool_id, frame), (6, n))[rows]
                    for kind, frame, rows in (("geometric", pin.LOCAL_WORLD_ALIGNED, slice(None)),
                                              ("space", pin.WORLD, swap), ("body", pin.LOCAL, swap))}
        single = {"geometric": jacobian_geometric(robot, q), "space": jacobian_space(robot, q),
                  "body": jacobian_body(robot, q)}
        one = {"geometric": jacobian_geometric(robot, Q[k:k + 1]), "space": jacobian_space(robot, Q[k:k + 1]),
               "body": jacobian_body(robot, Q[k:k + 1])}
        v_rows = {"geometric": slice(0, 3), "space": slice(3, 6), "body": slice(3, 6)}
        for kind, ref in expected.items():
            # linear-velocity rows of revolute columns scale with the robot (and, for the space
            # Jacobian, with the distance of the base from the axes): compare them relative to it
            lever = size + float(np.abs(frames[k, :, :3, 3]).max())
            # (a prismatic column's linear rows are its unit direction: no length, compared as such)
            rev = robot.revolute
            for got in (J[kind][k], single[kind], one[kind][0]):
                v = v_rows[kind]
                assert_fk_close(got[v][:, rev], ref[v][:, rev], lever, err_msg=kind)
                assert_fk_close(got[v][:, ~rev], ref[v][:, ~rev], err_msg=kind)
                w_rows = slice(3, 6) if kind == "geometric" else slice(0, 3)
                assert_fk_close(got[w_rows], ref[w_rows], err_msg=kind)
