"""URDF import and export against independent peers (pinocchio, MuJoCo, yourdfpy) on real robot files.

The reference for every FK value here is a peer's FK of the *original* file: pinocchio (urdfdom
parser, its own joint models), MuJoCo (its own URDF compiler) and yourdfpy (pure-Python parser).
Robots come from example-robot-data, which ships vendor URDFs (UR, Panda, Kinova, xArm7, Z1, SO-100/101).
"""

from __future__ import annotations

import glob
import os
import sys
import warnings

import numpy as np
import pytest

from robkin import Joint, ProjectionWarning, Robot, se3
from robkin.errors import InputError
from robkin.io.urdf import axis_frame, parse_urdf, robot_from_urdf, urdf_from_robot
from robkin.representations import dh_from_robot, mdh_from_robot, poe_from_robot, rpy_from_robot

pin = pytest.importorskip("pinocchio")

ROBOTS_DIR = (glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                     "example-robot-data", "robots")) or [""])[0]

#: (file under example-robot-data/robots, base link, tip link); None = the reader's default.
CASES = [
    ("ur_description/urdf/ur3_robot.urdf", None, "tool0"),
    ("ur_description/urdf/ur5_robot.urdf", None, "tool0"),
    ("ur_description/urdf/ur10_robot.urdf", None, "ee_link"),
    ("panda_description/urdf/panda.urdf", None, "panda_hand_tcp"),
    ("panda_description/urdf/panda.urdf", "panda_link0", "panda_leftfinger"),  # 7R + prismatic finger
    ("kinova_description/robots/kinova.urdf", None, "j2s6s200_end_effector"),
    ("xarm_description/urdf/xarm7.urdf", None, None),
    ("z1_description/urdf/z1.urdf", None, "gripperMover"),
    ("so_arm_description/urdf/so100.urdf", None, None),
    ("so_arm_description/urdf/so101.urdf", None, "gripper_frame_link"),
    ("finger_edu_description/robots/finger_edu.urdf", None, None),  # axis -1 0 0
    ("double_pendulum_description/urdf/double_pendulum_continuous.urdf", None, None),
    # a humanoid's arm: base link in the middle of the tree (torso joints above it held at 0)
    ("talos_data/robots/talos_full_v2.urdf", "torso_2_link", "gripper_left_base_link"),
]

#: FK agreement promised by robkin. Observed differences are ~1e-15 (a handful of 4x4 products in
#: float64 at lengths ~1 m); 1e-9 leaves six orders of margin and still catches any modelling error.
FK_TOL = 1e-9
#: what is observed on these 13 chains (12 configurations each, this machine, 2026-11-28), relative to
#: the robot's size, so that a regression far below the promise still fails: GJD 3.3e-15, PoE and
#: PoE-body 1.7e-15, RPY-XYZ 1.6e-15 (all on the xArm7); DH and MDH 5.1e-13 on the Kinova arm (its
#: common normals run far along nearly parallel axes), 6.6e-15 and below on the other 12. The bounds
#: are 3-4x those: the data are fixed, but another CPU or BLAS rounds the products differently.
REPRESENTATION_TOL = {"gjd": 1e-14, "dh": 2e-12, "mdh": 2e-12, "poe": 1e-14, "poe-body": 1e-14,
                      "rpy-xyz": 1e-14}
#: the same for a URDF robkin wrote, read by pinocchio or yourdfpy, and for the hand-computed chain:
#: observed <= 3.2e-15 (of ~1 m: the entries are compared absolutely, the chains are 0.3-1.3 m), 3x
ROUNDING_TOL = 1e-14


def assert_fk_close(got, expected, err_msg: str = "") -> None:
    """4x4 poses equal to the promise (FK_TOL) and to the rounding level observed (ROUNDING_TOL)."""
    np.testing.assert_allclose(got, expected, rtol=0, atol=FK_TOL, err_msg=f"the promise: {err_msg}")
    np.testing.assert_allclose(got, expected, rtol=0, atol=ROUNDING_TOL, err_msg=f"observed: {err_msg}")

TILTED = """<?xml version="1.0"?>
<robot name="tilted">
  <link name="world"/><link name="base"/><link name="l1"/><link name="l2"/><link name="l3"/>
  <link name="l4"/><link name="tip"/>
  <joint name="mount" type="fixed"><parent link="world"/><child link="base"/>
    <origin xyz="0.5 -0.2 0.1" rpy="0 0 0.7"/></joint>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0.1 0.2 0.3" rpy="0.3 -0.4 1.2"/><axis xyz="0.638 0 -0.770"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="j2" type="prismatic"><parent link="l1"/><child link="l2"/>
    <origin xyz="0.0 -0.25 0.4" rpy="-1.1 0.7 0.2"/><axis xyz="0.3 0.4 0.5"/>
    <limit lower="-0.2" upper="0.3" effort="1" velocity="1"/></joint>
  <joint name="glue" type="fixed"><parent link="l2"/><child link="l3"/>
    <origin xyz="0.05 0.05 0" rpy="2.0 -0.3 0.1"/></joint>
  <joint name="j3" type="continuous"><parent link="l3"/><child link="l4"/>
    <origin xyz="0.5 0 0" rpy="0 1.5707963267948966 0"/><axis xyz="0 -1 0"/></joint>
  <joint name="f" type="fixed"><parent link="l4"/><child link="tip"/>
    <origin xyz="0 0 0.1" rpy="0.2 0.1 3.0"/></joint>
</robot>
"""


def robot_file(rel: str) -> str:
    path = os.path.join(ROBOTS_DIR, rel)
    if not os.path.isfile(path):
        pytest.skip(f"example-robot-data file {rel} not installed")
    return path


def sample_q(robot: Robot, count: int, seed: int) -> np.ndarray:
    """Random q within limits; joints whose limits are degenerate (lower == upper) get +-pi."""
    rng = np.random.default_rng(seed)
    lim = robot.limits.copy()
    bad = ~np.isfinite(lim).all(axis=1) | (lim[:, 1] - lim[:, 0] <= 0)
    lim[bad] = [-np.pi, np.pi]
    return rng.uniform(lim[:, 0], lim[:, 1], size=(count, robot.n))


def pin_fk(model, robot: Robot, q: np.ndarray, frame: str) -> np.ndarray:
    """Pinocchio's pose of ``frame`` in its root frame, with robkin's joint values set by joint name."""
    data = model.createData()
    qp = pin.neutral(model)
    for joint, value in zip(robot.joints, q):
        jm = model.joints[model.getJointId(joint.name)]
        if jm.nq == 2:  # continuous joints: (cos, sin)
            qp[jm.idx_q], qp[jm.idx_q + 1] = np.cos(value), np.sin(value)
        else:
            qp[jm.idx_q] = value
    pin.framesForwardKinematics(model, data, qp)
    return data.oMf[model.getFrameId(frame)].homogeneous


def representation_fks(robot: Robot):
    """(name, fk function) of every representation, each evaluated from its own table/screws."""
    return [("gjd", robot.fk), ("dh", dh_from_robot(robot).fk), ("mdh", mdh_from_robot(robot).fk),
            ("poe", poe_from_robot(robot, "space").fk), ("poe-body", poe_from_robot(robot, "body").fk),
            ("rpy-xyz", rpy_from_robot(robot).fk)]


@pytest.mark.filterwarnings("ignore::robkin.ConditioningWarning")  # so100: axes 1e-5 from parallel
@pytest.mark.filterwarnings("ignore:.*held at 0:UserWarning")  # talos: torso joints above the arm
@pytest.mark.parametrize("rel, base, tip", CASES, ids=[c[0].split("/")[-1] + ":" + str(c[2]) for c in CASES])
def test_every_representation_matches_pinocchio(rel, base, tip):
    path = robot_file(rel)
    robot = robot_from_urdf(path, base, tip)
    model = pin.buildModelFromUrdf(path)
    tip_frame = tip or model.frames[-1].name
    # pinocchio's FK is in the file's root link frame; robkin's in the base link frame
    Q = sample_q(robot, 12, seed=len(rel))
    expected = np.stack([pin_fk(model, robot, q, tip_frame) for q in Q])
    scale = max(robot.scale, 1.0)
    for name, fk in representation_fks(robot):
        got = robot.world @ fk(Q)
        err = np.abs(got - expected).max() / scale
        assert err < FK_TOL, f"{rel} {name}: FK differs from pinocchio by {err:.3g}"      # the promise
        assert err <= REPRESENTATION_TOL[name], f"{rel} {name}: {err:.3g}, above the rounding observed"


@pytest.mark.parametrize("rel, base, tip", CASES[:4] + CASES[6:9], ids=lambda v: str(v).split("/")[-1])
def test_exported_urdf_loads_in_pinocchio_with_same_fk(rel, base, tip, tmp_path):
    robot = robot_from_urdf(robot_file(rel), base, tip)
    out = tmp_path / "out.urdf"
    out.write_text(urdf_from_robot(robot))
    model = pin.buildModelFromUrdf(str(out))
    # the whole file is written back: joints off the chain (the Panda's fingers) too
    assert model.nq >= robot.n and model.njoints == len(pin.buildModelFromUrdf(robot_file(rel)).joints)
    Q = sample_q(robot, 8, seed=3)
    for q in Q:
        assert_fk_close(pin_fk(model, robot, q, robot.bodies.tip), robot.world @ robot.fk(q))
    # and the limits survive
    for joint in robot.joints:
        jid = model.getJointId(joint.name)
        if joint.lower is not None and model.joints[jid].nq == 1:
            assert model.lowerPositionLimit[model.joints[jid].idx_q] == joint.lower
            assert model.upperPositionLimit[model.joints[jid].idx_q] == joint.upper


def test_exported_urdf_reads_back_exactly():
    robot = robot_from_urdf(TILTED_SILENT())
    again = robot_from_urdf(urdf_from_robot(robot))
    # full-precision numbers: the frames survive to rounding of one rpy round trip
    np.testing.assert_allclose(again.frames, robot.frames, atol=1e-14, rtol=0)
    np.testing.assert_allclose(again.world, robot.world, atol=1e-14, rtol=0)
    assert again.joints == robot.joints


def TILTED_SILENT() -> str:
    """The tilted robot with unit axes (no normalisation warning)."""
    a = np.array([0.638, 0, -0.770]) / np.linalg.norm([0.638, 0, -0.770])
    b = np.array([0.3, 0.4, 0.5]) / np.linalg.norm([0.3, 0.4, 0.5])
    return (TILTED.replace('axis xyz="0.638 0 -0.770"', f'axis xyz="{float(a[0])!r} {float(a[1])!r} {float(a[2])!r}"')
            .replace('axis xyz="0.3 0.4 0.5"', f'axis xyz="{float(b[0])!r} {float(b[1])!r} {float(b[2])!r}"'))


def test_tilted_axes_and_rpy_origins_match_pinocchio_and_hand_computation():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = robot_from_urdf(TILTED)
    messages = [str(w.message) for w in caught if w.category is ProjectionWarning]
    assert len(messages) == 2 and "'j1'" in messages[0] and "'j2': axis has length 0.707107" in messages[1]
    assert [j.type for j in robot.joints] == ["revolute", "prismatic", "revolute"]
    assert robot.joints[2].lower is None  # continuous: no limits
    assert robot.joints[0].flip and not robot.joints[1].flip  # axis with negative z -> flip
    model = pin.buildModelFromXML(TILTED)
    # hand computation straight from the URDF semantics: child = parent * origin * motion(axis, q)
    def origin(xyz, rpy):
        return se3.homogeneous(se3.matrix_from_rpy(rpy), xyz)

    def rot(axis, angle):
        u = np.array(axis) / np.linalg.norm(axis)
        return se3.exp_twist(np.r_[u, 0, 0, 0], angle)

    def slide(axis, d):
        u = np.array(axis) / np.linalg.norm(axis)
        return se3.trans(*(u * d))

    for q in sample_q(robot, 10, seed=7):
        hand = (origin([0.1, 0.2, 0.3], [0.3, -0.4, 1.2]) @ rot([0.638, 0, -0.770], q[0])
                @ origin([0, -0.25, 0.4], [-1.1, 0.7, 0.2]) @ slide([0.3, 0.4, 0.5], q[1])
                @ origin([0.05, 0.05, 0], [2.0, -0.3, 0.1])
                @ origin([0.5, 0, 0], [0, np.pi / 2, 0]) @ rot([0, -1, 0], q[2])
                @ origin([0, 0, 0.1], [0.2, 0.1, 3.0]))
        world = origin([0.5, -0.2, 0.1], [0, 0, 0.7])
        np.testing.assert_allclose(robot.world, world, atol=1e-15)
        for name, fk in representation_fks(robot):
            assert_fk_close(fk(q), hand, err_msg=name)
        assert_fk_close(pin_fk(model, robot, q, "tip"), world @ hand)


def test_axis_frame_has_the_axis_as_z_and_is_a_rotation():
    rng = np.random.default_rng(11)
    axes = np.vstack([np.eye(3), -np.eye(3), rng.normal(size=(50, 3)), [[1e-12, 0, -1]]])
    for a in axes:
        a = a / np.linalg.norm(a)
        R, flip = axis_frame(a)
        np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-14)
        assert np.linalg.det(R) > 0
        np.testing.assert_allclose(R[:, 2], a, atol=1e-14)
        assert flip == (a[2] < 0)
    assert np.array_equal(axis_frame(np.array([0.0, 0.0, 1.0]))[0], np.eye(3))  # +z: link frame kept


def test_negative_z_axis_gives_rpy_rows_equal_to_urdf_origins():
    xml = """<robot name="r"><link name="a"/><link name="b"/><link name="c"/>
      <joint name="j1" type="revolute"><parent link="a"/><child link="b"/>
        <origin xyz="0 0 0.3" rpy="0.1 0.2 0.3"/><axis xyz="0 0 -1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
      <joint name="tcp" type="fixed"><parent link="b"/><child link="c"/><origin xyz="0 0 0.1"/></joint></robot>"""
    robot = robot_from_urdf(xml)
    assert robot.joints[0].flip
    rows = rpy_from_robot(robot).rows
    np.testing.assert_allclose(rows[1], [0.1, 0.2, 0.3, 0, 0, 0.3], atol=1e-15)
    np.testing.assert_allclose(rows[2], [0, 0, 0, 0, 0, 0.1], atol=1e-15)
    # and the joint still turns the right way: positive q turns about -z of the link frame
    T = robot.fk(np.array([0.4]))
    expected = se3.homogeneous(se3.matrix_from_rpy([0.1, 0.2, 0.3]), [0, 0, 0.3]) @ se3.rot_z(-0.4) @ se3.trans(0, 0, 0.1)
    np.testing.assert_allclose(T, expected, atol=1e-15)


def test_chain_selection_in_a_tree():
    path = robot_file("ur_description/urdf/ur5_robot.urdf")
    # leaves: ee_link and tool0 (base, fixed to base_link, is part of the base and not a chain's end)
    with pytest.raises(InputError, match=r"tree with 2 leaf links.*tip_link=.*tool0"):
        robot_from_urdf(path)
    robot = robot_from_urdf(path, tip_link="wrist_2_link")
    assert [j.name for j in robot.joints] == ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
                                              "wrist_1_joint", "wrist_2_joint"]
    # a base link in the middle: the links above it become the world transform (joints held at 0)
    with pytest.warns(UserWarning, match="held at 0"):
        upper = robot_from_urdf(path, base_link="upper_arm_link", tip_link="tool0")
    full = robot_from_urdf(path, tip_link="tool0")
    assert upper.n == 4
    q = np.array([0.3, -0.2, 0.5, 1.0])
    np.testing.assert_allclose(upper.world @ upper.fk(q), full.world @ full.fk(np.r_[0, 0, q]), atol=1e-12)
    with pytest.raises(InputError, match="not below base_link="):
        robot_from_urdf(path, base_link="forearm_link", tip_link="shoulder_link")


def test_world_link_becomes_robot_world():
    robot = robot_from_urdf(TILTED_SILENT())
    np.testing.assert_allclose(robot.world, se3.homogeneous(se3.matrix_from_rpy([0, 0, 0.7]), [0.5, -0.2, 0.1]))
    # FK is in the base link frame: at q = 0 the first joint frame sits at j1's origin
    np.testing.assert_allclose(robot.frames[0][:3, 3], [0.1, 0.2, 0.3])


def test_mimic_floating_planar_are_errors_naming_the_joint():
    panda = robot_file("panda_description/urdf/panda.urdf")
    with pytest.raises(InputError, match="panda_finger_joint2.*mimics"):
        robot_from_urdf(panda, tip_link="panda_rightfinger")
    for kind in ("floating", "planar"):
        xml = (f'<robot name="r"><link name="a"/><link name="b"/><joint name="free_{kind}" type="{kind}">'
               f'<parent link="a"/><child link="b"/></joint></robot>')
        with pytest.raises(InputError, match=f"free_{kind}' is {kind}"):
            robot_from_urdf(xml)


def test_meshes_and_package_uris_are_ignored():
    xml = """<robot name="r"><link name="a"><visual><geometry><mesh filename="package://nowhere/a.dae"/>
      </geometry></visual><inertial><mass value="1"/></inertial></link><link name="b"/>
      <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
      <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
      <transmission name="t"><joint name="j"><hardwareInterface>x</hardwareInterface></joint></transmission>
      </robot>"""
    robot = robot_from_urdf(xml)
    assert robot.n == 1 and (robot.joints[0].lower, robot.joints[0].upper) == (-1.0, 1.0)


def test_xacro_input(tmp_path):
    pytest.importorskip("xacro")
    (tmp_path / "arm.xacro").write_text("""<?xml version="1.0"?>
<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:property name="L" value="0.25"/>
  <xacro:macro name="seg" params="i parent">
    <link name="l${i}"/>
    <joint name="j${i}" type="revolute"><parent link="${parent}"/><child link="l${i}"/>
      <origin xyz="0 0 ${L}"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  </xacro:macro>
  <link name="base"/>
  <xacro:seg i="1" parent="base"/>
  <xacro:seg i="2" parent="l1"/>
</robot>""")
    robot = robot_from_urdf(tmp_path / "arm.xacro", allow_xacro=True)
    assert robot.n == 2 and robot.name == "arm"
    # joint 1 at z = 0.25, tool (= joint 2's link) 0.25 above it on z: turning joint 1 by pi/2 about
    # y swings the tool from (0, 0, 0.5) to (0.25, 0, 0.25)
    np.testing.assert_allclose(robot.fk(np.array([np.pi / 2, 0]))[:3, 3], [0.25, 0, 0.25], atol=1e-12)


def test_parse_urdf_lists_tree():
    model = parse_urdf(robot_file("panda_description/urdf/panda.urdf"))
    assert model.root() == "panda_link0"
    assert set(model.leaves("panda_link0")) == {"panda_hand_tcp", "panda_leftfinger", "panda_rightfinger"}


def test_export_names_do_not_collide_with_joint_names():
    F = np.stack([np.eye(4), se3.trans(0, 0, 1), se3.trans(0, 1, 1)])
    robot = Robot(F, (Joint("tool"), Joint("base_fixed")), name="x")
    text = urdf_from_robot(robot)
    model = pin.buildModelFromXML(text)
    assert model.existFrame("tool_") and model.existFrame("base_fixed_")
    back = robot_from_urdf(text, tip_link="tool_")
    assert [j.name for j in back.joints] == ["tool", "base_fixed"]
    np.testing.assert_allclose(pin_fk(model, robot, np.array([0.3, -1]), "tool_"), robot.fk([0.3, -1]), atol=1e-15)


def test_exported_urdf_loads_in_yourdfpy_with_same_fk(tmp_path):
    yourdfpy = pytest.importorskip("yourdfpy")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ProjectionWarning)
        robot = robot_from_urdf(TILTED)
    for rel, base, tip in (CASES[1], CASES[3], CASES[6]):
        robot_v = robot_from_urdf(robot_file(rel), base, tip)
        for r in (robot, robot_v):
            out = tmp_path / "y.urdf"
            out.write_text(urdf_from_robot(r))
            u = yourdfpy.URDF.load(str(out), load_meshes=False, build_scene_graph=True)
            names = [j.name for j in r.joints]
            assert set(names) <= set(u.actuated_joint_names)
            tip, root = (r.bodies.tip, r.bodies.links[0].name) if r.bodies else ("tool", "world")
            for q in sample_q(r, 4, seed=5):
                u.update_cfg(dict(zip(names, q)))
                assert_fk_close(u.get_transform(tip, root), r.world @ r.fk(q))


def test_both_xml_parsers_read_the_same_contents_and_refuse_the_same(monkeypatch):
    """The kinematic tree is read by the compiled scan; link contents are parsed on first use, by the
    standard library's parser for small files and lxml for big ones (see LXML_FROM): both agree."""
    import robkin.io.trees.xml_parse as urdf_module

    text = open(robot_file("panda_description/urdf/panda.urdf"), encoding="utf-8").read()
    seen = []
    for limit in (0, 10**9):
        monkeypatch.setattr(urdf_module, "LXML_FROM", limit)
        model = parse_urdf(text)
        seen.append(({link: model.content[link] for link in model.links}, list(model.extras)))
    (small, small_extras), (big, big_extras) = seen
    assert small.keys() == big.keys() and small_extras == big_extras
    assert sum(len(c.shapes) for c in small.values()) > 10
    for link in small:
        a, b = small[link], big[link]
        assert [(s.role, s.geometry, s.material, s.name, s.origin) for s in a.shapes] == \
            [(s.role, s.geometry, s.material, s.name, s.origin) for s in b.shapes]
        assert (a.inertial is None) == (b.inertial is None)
        if a.inertial is not None:
            assert a.inertial.mass == b.inertial.mass and a.inertial.origin == b.inertial.origin
    for bad, msg in ((text[:300], "not well-formed XML \\(line"),
                     ('<!DOCTYPE r [<!ENTITY a "b">]><robot name="&a;"/>', "refused XML construct")):
        for limit in (0, 10**9):
            monkeypatch.setattr(urdf_module, "LXML_FROM", limit)
            with pytest.raises(InputError, match=msg):
                robot_from_urdf(bad)


def test_a_model_built_by_another_reader_loads_and_writes():
    """Readers of other formats build UrdfModels by hand: positional fields, a mimic flag, no content."""
    from robkin.io.urdf import UrdfJoint, UrdfModel, robot_from_model

    joints = (UrdfJoint("j1", "revolute", "base", "l1", se3.trans(0, 0, 0.3), np.array([0.0, 0, 1]), -1.0, 1.0, False),
              UrdfJoint("fix", "fixed", "l1", "tip", se3.trans(0.2, 0, 0), np.array([1.0, 0, 0]), None, None, False))
    robot = robot_from_model(UrdfModel("m", ("base", "l1", "tip"), joints, "m.xml"))
    back = robot_from_urdf(urdf_from_robot(robot))
    assert back.bodies.tip == "tip" and [j.name for j in back.joints] == ["j1"]
    np.testing.assert_allclose(back.fk([0.5]), robot.fk([0.5]), atol=1e-15)


def test_repeated_joint_children_the_first_counts_as_in_urdfdom():
    """urdfdom (and so pinocchio) reads the first <origin>/<axis> of a joint; so does robkin's scan."""
    text = """<robot name="r"><link name="a"/><link name="b"/>
      <joint name="j" type="revolute"><parent link="a"/><child link="b"/>
        <origin xyz="0.1 0.2 0.3" rpy="0.3 0.2 0.1"/><origin xyz="9 9 9"/>
        <axis xyz="0 1 0"/><axis xyz="1 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    </robot>"""
    model = pin.buildModelFromXML(text)
    data = model.createData()
    q = np.array([0.7])
    pin.forwardKinematics(model, data, q)
    robot = robot_from_urdf(text, tip_link="b")
    np.testing.assert_allclose(robot.fk(q), data.oMi[1].homogeneous, atol=1e-15)
