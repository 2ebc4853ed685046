"""MJCF export, checked by MuJoCo itself: the site ``tool`` at qpos = q is world @ fk(q).

References: MuJoCo's own kinematics of the exported model, and pinocchio's FK of the original vendor
URDF, so a mistake in robkin's URDF reading and in its MJCF writing are both caught.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings

from robkin import Joint, Robot, se3
from robkin.io.mjcf import mjcf_from_robot
from robkin.io.mjcf.format import quat_from_matrix
from robkin.bodies import Bodies
from robkin.io.urdf import robot_from_urdf, urdf_from_robot
from strategies import robots
from test_urdf import CASES, FK_TOL, TILTED_SILENT, pin, pin_fk, robot_file, sample_q

mujoco = pytest.importorskip("mujoco")


def mujoco_pose(model, data, q: np.ndarray, *, site: str | None = None, body: str | None = None) -> np.ndarray:
    data.qpos[:] = 0  # joints off the chain (a gripper's fingers) at 0; the chain's joints come first
    data.qpos[:len(q)] = q
    mujoco.mj_kinematics(model, data)
    T = np.eye(4)
    if site is not None:
        i = model.site(site).id
        T[:3, :3], T[:3, 3] = data.site_xmat[i].reshape(3, 3), data.site_xpos[i]
    else:
        i = model.body(body).id
        T[:3, :3], T[:3, 3] = data.xmat[i].reshape(3, 3), data.xpos[i]
    return T


@pytest.mark.filterwarnings("ignore::robkin.ConditioningWarning")
@pytest.mark.filterwarnings("ignore:.*held at 0:UserWarning")
@pytest.mark.parametrize("rel, base, tip", CASES, ids=[c[0].split("/")[-1] + ":" + str(c[2]) for c in CASES])
def test_mjcf_of_vendor_urdf_matches_pinocchio_of_the_original(rel, base, tip):
    path = robot_file(rel)
    robot = robot_from_urdf(path, base, tip)
    model = mujoco.MjModel.from_xml_string(mjcf_from_robot(robot, mesh_files={}))
    data = mujoco.MjData(model)
    assert model.nq >= robot.n and [model.joint(i).name for i in range(robot.n)] == [j.name for j in robot.joints]
    pmodel = pin.buildModelFromUrdf(path)
    tip_frame = tip or pmodel.frames[-1].name
    assert robot.bodies.tip == tip_frame
    for q in sample_q(robot, 6, seed=2):  # the site is named as the tip link
        np.testing.assert_allclose(mujoco_pose(model, data, q, site=tip_frame), pin_fk(pmodel, robot, q, tip_frame),
                                   atol=FK_TOL, rtol=0)


def test_mjcf_limits_and_joint_kinds():
    frames = np.stack([np.eye(4), se3.trans(0, 0, 0.5) @ se3.rot_x(0.3), se3.trans(0.2, 0, 0.9)])
    robot = Robot(frames, (Joint("r", "revolute", -1.5, 2.0), Joint("p", "prismatic", None, 0.4, flip=True)))
    model = mujoco.MjModel.from_xml_string(mjcf_from_robot(robot))
    assert list(model.jnt_type) == [mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE]
    np.testing.assert_array_equal(model.jnt_range[0], [-1.5, 2.0])  # radians, not degrees
    assert model.jnt_range[1][1] == 0.4 and model.jnt_range[1][0] <= -1e9
    data = mujoco.MjData(model)
    for q in ([0.0, 0.0], [1.0, 0.3], [-1.2, -0.7]):
        np.testing.assert_allclose(mujoco_pose(model, data, np.array(q), site="tool"), robot.fk(q), atol=FK_TOL)


def test_exported_urdf_loads_in_mujoco_with_same_fk(tmp_path):
    robot = robot_from_urdf(TILTED_SILENT())
    for r in (robot, robot_from_urdf(robot_file(CASES[3][0]), CASES[3][1], CASES[3][2])):
        out = tmp_path / "m.urdf"
        out.write_text(urdf_from_robot(r.replace(bodies=Bodies())))  # the plain chain (no meshes to find)
        model = mujoco.MjModel.from_xml_path(str(out))
        data = mujoco.MjData(model)
        assert model.nq == r.n
        for q in sample_q(r, 5, seed=9):
            np.testing.assert_allclose(mujoco_pose(model, data, q, body="tool"), r.world @ r.fk(q), atol=FK_TOL)


def test_quaternion_of_every_kind_of_rotation():
    rng = np.random.default_rng(4)
    mats = [np.eye(3), se3.rot_x(np.pi)[:3, :3], se3.rot_y(np.pi)[:3, :3], se3.rot_z(np.pi)[:3, :3],
            se3.rot_z(np.pi - 1e-9)[:3, :3]] + [se3.matrix_from_rpy(rng.uniform(-4, 4, 3)) for _ in range(40)]
    for R in mats:
        q = quat_from_matrix(R)
        back = np.zeros(9)
        mujoco.mju_quat2Mat(back, q)  # MuJoCo's own conversion as the reference
        np.testing.assert_allclose(back.reshape(3, 3), R, atol=1e-15)
        assert q[0] >= 0 and abs(np.linalg.norm(q) - 1) < 1e-15


def test_tool_rotation_far_below_mujocos_site_rounding_survives():
    """The tool is a body: a 1e-9 rad tool rotation (MuJoCo rounds a site's own tiny rotation away)
    reaches MuJoCo intact, as does every joint frame's."""
    frames = np.stack([np.eye(4), se3.trans(0, 0, 0.3) @ se3.rot_y(np.pi / 2),
                       se3.trans(0.4, 0, 0.3) @ se3.rot_y(np.pi / 2) @ se3.rot_x(1e-9) @ se3.rot_z(-2e-9)])
    robot = Robot(frames, (Joint("a", "revolute"), Joint("b", "revolute")))
    model = mujoco.MjModel.from_xml_string(mjcf_from_robot(robot))
    data = mujoco.MjData(model)
    for q in ([0.0, 0.0], [0.4, -1.1]):
        T = mujoco_pose(model, data, np.array(q), body="tool")
        np.testing.assert_allclose(T, robot.fk(q), atol=1e-15)
        np.testing.assert_allclose(mujoco_pose(model, data, np.array(q), site="tool"), T, atol=0)


def test_urdf_limit_without_bounds_is_exported_locked():
    """URDF's <limit effort velocity/> means lower = upper = 0 (urdfdom, pinocchio): the joint is held
    at 0 by a joint equality, since MuJoCo refuses range="0 0"."""
    urdf = """<robot name="r"><link name="a"/><link name="b"/>
      <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
        <limit effort="10" velocity="2"/></joint></robot>"""
    with pytest.warns(UserWarning, match="equal lower and upper limits"):
        robot = robot_from_urdf(urdf)
    assert robot.joints[0].lower == robot.joints[0].upper == 0
    text = mjcf_from_robot(robot)
    assert 'range="0 0"' not in text and '<joint joint1="j" polycoef="0 0 0 0 0"/>' in text
    model = mujoco.MjModel.from_xml_string(text)
    assert not model.jnt_limited[0] and model.neq == 1 and model.eq_type[0] == mujoco.mjtEq.mjEQ_JOINT


@pytest.mark.filterwarnings("ignore::robkin.ConditioningWarning")
@settings(max_examples=40, deadline=None)
@given(robots(max_joints=7))
def test_export_of_any_robot_loads_in_mujoco_and_reads_back(robot):
    """MuJoCo loads every MJCF robkin writes, with FK equal to 1e-12 of the robot's size, and
    robkin's MJCF reader gives back the same FK."""
    from robkin.io.mjcf.reader import robot_from_mjcf

    text = mjcf_from_robot(robot)
    model = mujoco.MjModel.from_xml_string(text)
    data = mujoco.MjData(model)
    back = robot_from_mjcf(text, tip_link="tool")
    tol = 1e-12 * max(1.0, robot.scale, float(np.abs(robot.world[:3, 3]).max()))
    for q in np.random.default_rng(0).uniform(-1, 1, (4, robot.n)):
        T = robot.world @ robot.fk(q)
        np.testing.assert_allclose(mujoco_pose(model, data, q, body="tool"), T, atol=tol, rtol=0)
        np.testing.assert_allclose(back.world @ back.fk(q), T, atol=tol, rtol=0)
    assert [j.name for j in back.joints] == [j.name for j in robot.joints]
    np.testing.assert_array_equal(back.limits, robot.limits)
