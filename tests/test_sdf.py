"""SDF import, checked against pinocchio's FK of the same robots written as URDF by hand.

Each ``tests/data/sdf/X.sdf`` has a twin ``X.urdf`` whose frames were worked out on paper (comments
in the files say how), so the SDF rules (relative_to, expressed_in, the 1.4 model-frame axis,
use_parent_model_frame, nested models, frames, the world joint) are judged independently of robkin.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import robots

from robkin import se3

from robkin.errors import InputError
from robkin.io import load
from robkin.io.sdf.reader import robot_from_sdf

pin = pytest.importorskip("pinocchio")

DATA = Path(__file__).parent / "data" / "sdf"
#: Observed differences ~3e-16 (a few 4x4 products); 1e-12 still catches any frame mistake.
FK_TOL = 1e-12


def pin_pose(model, q_by_name: dict[str, float], frame: str) -> np.ndarray:
    data = model.createData()
    qp = pin.neutral(model)
    for name, v in q_by_name.items():
        joint = model.joints[model.getJointId(name)]
        if joint.nq == 2:  # continuous: (cos, sin)
            qp[joint.idx_q:joint.idx_q + 2] = [np.cos(v), np.sin(v)]
        else:
            qp[joint.idx_q] = v
    pin.framesForwardKinematics(model, data, qp)
    return data.oMf[model.getFrameId(frame)].homogeneous


@pytest.mark.parametrize("name, tip, joints", [
    ("arm", "tcp", ["shoulder", "elbow", "wrist"]),
    ("nested", "tool::finger", ["j1", "mount", "tool::slide"]),
    ("v14", "c", ["j", "k"]),
])
def test_sdf_matches_its_hand_written_urdf_twin(name, tip, joints):
    robot = load(DATA / f"{name}.sdf", tip_link=tip)
    assert [j.name for j in robot.joints] == joints
    urdf_twin = load(DATA / f"{name}.urdf", tip_link=tip)
    np.testing.assert_array_equal(robot.limits, urdf_twin.limits)
    model = pin.buildModelFromUrdf(str(DATA / f"{name}.urdf"))
    for q in np.random.default_rng(5).uniform(-1, 1, (8, robot.n)):
        np.testing.assert_allclose(robot.world @ robot.fk(q), pin_pose(model, dict(zip(joints, q)), tip),
                                   atol=FK_TOL, rtol=0)
    # and robkin's MJCF of it: MuJoCo's FK of the tool body (named as the tip link) is the same
    mujoco = pytest.importorskip("mujoco")
    from robkin.io.mjcf import mjcf_from_robot

    mj = mujoco.MjModel.from_xml_string(mjcf_from_robot(robot))
    data = mujoco.MjData(mj)
    for q in np.random.default_rng(6).uniform(-1, 1, (8, robot.n)):
        data.qpos[:] = 0
        data.qpos[:robot.n] = q  # the chain's joints first
        mujoco.mj_kinematics(mj, data)
        tool = mj.body(tip).id
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = data.xmat[tool].reshape(3, 3), data.xpos[tool]
        np.testing.assert_allclose(T, robot.world @ robot.fk(q), atol=FK_TOL, rtol=0)


def test_axis_frame_depends_on_the_version():
    """The same file read as 1.5 takes the axis in the joint frame: another robot."""
    text = (DATA / "v14.sdf").read_text()
    old, new = robot_from_sdf(text), robot_from_sdf(text.replace('version="1.4"', 'version="1.5"'))
    np.testing.assert_allclose(old.axes[0], [0, 1, 0], atol=1e-15)  # model y, the GJD is in a's frame
    np.testing.assert_allclose(new.axes[0], [0, np.cos(0.5), np.sin(0.5)], atol=1e-15)  # y of b's frame


def test_sdf_limits_default_and_continuous():
    robot = load(DATA / "nested.sdf", tip_link="tool::finger")
    assert robot.joints[0].lower is None  # +-1e16 is SDF's "no limit"
    assert (robot.joints[1].lower, robot.joints[1].upper) == (-1.0, 1.0)


SIMPLE = """<sdf version="1.9"><model name="m"><link name="a"/><link name="b"><pose>0 0 1 0 0 0</pose></link>
  <joint name="j" type="{type}"><parent>a</parent><child>b</child><axis><xyz>0 1 0</xyz></axis></joint>
  </model></sdf>"""


def test_quaternion_poses_and_world_placement():
    text = """<sdf version="1.9"><model name="m"><pose rotation_format="quat_xyzw">1 0 0 0 0 0.7071067811865476 0.7071067811865476</pose>
      <link name="a"/><joint name="w" type="fixed"><parent>world</parent><child>a</child></joint>
      <link name="b"><pose degrees="true">0 0 1 90 0 0</pose></link>
      <joint name="j" type="revolute"><parent>a</parent><child>b</child><axis><xyz>0 0 1</xyz></axis></joint>
      </model></sdf>"""
    robot = robot_from_sdf(text, tip_link="b")
    np.testing.assert_allclose(robot.world[:3, :], [[0, -1, 0, 1], [1, 0, 0, 0], [0, 0, 1, 0]], atol=1e-15)
    np.testing.assert_allclose(robot.fk(np.zeros(1))[:3, :], [[1, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 1]], atol=1e-15)


def test_other_joint_kinds_refused_on_the_chain():
    with pytest.raises(InputError, match="joint 'j' is a ball joint; only revolute, continuous, prismatic"):
        robot_from_sdf(SIMPLE.format(type="ball"))
    assert robot_from_sdf(SIMPLE.format(type="prismatic")).joints[0].type == "prismatic"


@pytest.mark.parametrize("text, message", [
    ('<sdf version="1.9"><model name="m"><link name="a"><pose>0 0 x 0 0 0</pose></link></model></sdf>',
     "link 'a': <pose>: '0 0 x 0 0 0' is not 6 numbers"),
    (SIMPLE.format(type="revolute").replace("<child>b</child>", ""), "joint 'j': missing <child>"),
    (SIMPLE.format(type="revolute").replace("<child>b</child>", "<child>zz</child>"), "child 'zz' is not a link"),
    (SIMPLE.format(type="hinge"), "joint 'j': type 'hinge' is not one of"),
    (SIMPLE.format(type="revolute").replace("<xyz>0 1 0</xyz>", "<xyz>0 0 0</xyz>"), "axis xyz is zero"),
    (SIMPLE.format(type="revolute").replace('<link name="a"/>', '<link name="a"><pose relative_to="b"/></link>')
     .replace("<pose>0 0 1 0 0 0</pose>", '<pose relative_to="a"/>'), "relative_to form a loop"),
    (SIMPLE.format(type="revolute").replace("<pose>", '<pose relative_to="nowhere">'),
     "frame 'nowhere' is not a link, joint, frame or model"),
    ('<sdf version="1.3"><model name="m"/></sdf>', "SDFormat 1.3 is not read"),
    ('<sdf><model name="m"/></sdf>', "no version attribute"),
    ('<sdf version="1.9"/>', "holds 0 <model> elements"),
    ('<robot name="r"/>', "root element is <robot>; an SDF file has <sdf>"),
    ('<sdf version="1.9"><model name="m"><include><uri>model://x</uri></include></model></sdf>',
     "<include> (a model from a URI) is not read"),
    ('<!DOCTYPE sdf [<!ENTITY a "aaaa">]><sdf version="1.9"/>', "refused XML construct"),
])
def test_bad_sdf_is_one_clear_line(text, message):
    with pytest.raises(InputError, match=None) as info:
        robot_from_sdf(text)
    assert message in str(info.value) and "\n" not in str(info.value)
    assert str(info.value).startswith("<sdf string>")


def test_intermediate_links_only_where_a_joint_frame_is_off_its_child():
    from robkin.io.sdf.reader import model_from_sdf

    tree, _ = model_from_sdf(DATA / "arm.sdf")
    # only the wrist has a <pose> of its own; explicit frames are links too
    assert tree.links == ("base", "upper", "fore", "hand", "elbow_frame", "tcp", "hand@wrist")


def _sdf_of(robot, choices: list[tuple[bool, bool]]) -> str:
    """A robot written as SDF 1.9 by this test: link i at joint frame i, its pose either in the model
    frame or relative_to the previous link; the axis either "0 0 1" in the joint frame or the world
    direction expressed_in the model frame; the tool as an explicit frame."""
    def pose(T, rel=None):
        rpy = se3.rpy_from_matrix(T[:3, :3])
        attr = f' relative_to="{rel}"' if rel else ""
        return f"<pose{attr}>{' '.join(repr(float(v)) for v in [*T[:3, 3], *rpy])}</pose>"

    out = ['<sdf version="1.9"><model name="r"><link name="L0"/>']
    prev = np.eye(4)
    for i, (joint, (relative, in_model)) in enumerate(zip(robot.joints, choices), start=1):
        D = robot.frames[i - 1]
        out.append(f'<link name="L{i}">{pose(se3.inv(prev) @ D, f"L{i - 1}") if relative else pose(D)}</link>')
        axis = D[:3, 2] if in_model else np.array([0.0, 0.0, 1.0])
        expressed = ' expressed_in="__model__"' if in_model else ""
        kind = "revolute" if joint.revolute else "prismatic"
        out.append(f'<joint name="{joint.name}" type="{kind}"><parent>L{i - 1}</parent><child>L{i}</child>'
                   f'<axis><xyz{expressed}>{" ".join(repr(float(v)) for v in axis)}</xyz></axis></joint>')
        prev = D
    out.append(f'<frame name="tool" attached_to="L{robot.n}">{pose(se3.inv(prev) @ robot.tool)}</frame>')
    return "".join(out + ["</model></sdf>"])


@pytest.mark.filterwarnings("ignore::robkin.ConditioningWarning")
@settings(max_examples=40, deadline=None)
@given(robots(max_joints=6), st.data())
def test_any_robot_written_as_sdf_reads_back_with_the_same_fk(robot, data):
    choices = data.draw(st.lists(st.tuples(st.booleans(), st.booleans()), min_size=robot.n, max_size=robot.n))
    back = robot_from_sdf(_sdf_of(robot, choices), tip_link="tool")
    tol = 1e-12 * max(1.0, robot.scale)  # repr'd numbers: only the products' rounding remains
    for q in np.random.default_rng(2).uniform(-1, 1, (4, robot.n)):
        np.testing.assert_allclose(back.fk(q), robot.fk(q), atol=tol, rtol=0)
