"""URDF -> robkin -> URDF keeps the file: names, limits, mimic, shapes and inertials, checked by peers.

For every example-robot-data arm the tests load, the written file is read by pinocchio (urdfdom),
yourdfpy and MuJoCo, and compared with the *original* file read by the same peer: joints and links by
name, limits, effort, velocity and mimic; FK of the tip at random q; and the world pose of every
visual at random q (yourdfpy: link pose times visual origin, for both files).
"""

from __future__ import annotations

import warnings
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from robkin import Joint, Robot, se3
from robkin.bodies import Link, shape_poses
from robkin.cli import main
from robkin.io.urdf import parse_urdf, robot_from_urdf, urdf_from_robot

from test_urdf import CASES, pin_fk, robot_file, sample_q

pin = pytest.importorskip("pinocchio")

#: example-robot-data chains: those of test_urdf plus vendor base frames and more arms
ROUND_TRIP = CASES + [
    ("ur_description/urdf/ur5_robot.urdf", "base", "tool0"),  # UR's controller base frame
    ("ur_description/urdf/ur10_robot.urdf", "base", "tool0"),
    ("ur_description/urdf/ur5_gripper.urdf", None, "tool0"),
    ("baxter_description/urdf/baxter.urdf", "torso", "left_gripper"),
    ("tiago_description/robots/tiago.urdf", "torso_lift_link", "arm_tool_link"),
]
IDS = [f"{c[0].split('/')[-1]}:{c[1]}:{c[2]}" for c in ROUND_TRIP]
#: visual poses of the original and the written file agree to this (metres): both are products of a
#: handful of 4x4 transforms in float64 (~1e-16 each) at robot sizes ~1 m.
POSE_TOL = 1e-12


def _load(rel, base, tip):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # held torso joints, near-parallel axes: not the point here
        return robot_from_urdf(robot_file(rel), base, tip)


@pytest.fixture(scope="module", params=ROUND_TRIP, ids=IDS)
def trip(request, tmp_path_factory):
    rel, base, tip = request.param
    robot = _load(rel, base, tip)
    out = tmp_path_factory.mktemp("rt") / "out.urdf"
    out.write_text(urdf_from_robot(robot))
    return rel, base, tip, robot, out


def test_names_limits_and_mimic_are_kept(trip):
    rel, base, tip, robot, out = trip
    a, b = parse_urdf(robot_file(rel)), parse_urdf(out)
    assert set(a.links) == set(b.links)
    ja, jb = {j.name: j for j in a.joints}, {j.name: j for j in b.joints}
    assert set(ja) == set(jb)
    for name, j in ja.items():
        k = jb[name]
        assert (k.type, k.parent, k.child) == (j.type, j.parent, j.child), name
        assert (k.lower, k.upper, k.effort, k.velocity) == (j.lower, j.upper, j.effort, j.velocity), name
        assert (k.damping, k.friction) == (j.damping, j.friction), name
        assert (k.mimic is None) == (j.mimic is None), name
        if j.mimic is not None:
            assert (k.mimic.joint, k.mimic.multiplier, k.mimic.offset) == (j.mimic.joint, j.mimic.multiplier,
                                                                            j.mimic.offset)


def test_transmissions_and_gazebo_tags_are_kept(trip):
    rel, base, tip, robot, out = trip
    tags = lambda path: sorted(c.tag for c in ET.parse(path).getroot() if c.tag not in ("link", "joint",  # noqa: E731
                                                                                        "material", "mujoco"))
    assert tags(out) == tags(robot_file(rel))
    # as the source wrote them: the same elements, attributes and text
    strip = lambda path: [ET.tostring(c) for c in ET.parse(path).getroot() if c.tag == "transmission"]  # noqa: E731
    assert [b"".join(s.split()) for s in strip(out)] == [b"".join(s.split()) for s in strip(robot_file(rel))]


def test_robkin_check_calls_it_the_same_robot(trip, capsys):
    rel, base, tip, robot, out = trip
    argv = ["check", robot_file(rel), str(out)] + (["--base-link", base] if base else []) + \
        (["--tip-link", tip] if tip else [])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(argv) == 0, capsys.readouterr().out
    again = _load(str(out), base, tip)
    assert again.joints == robot.joints and again.bodies.tip == robot.bodies.tip
    np.testing.assert_allclose(again.world, robot.world, atol=POSE_TOL)


def test_pinocchio_reads_the_same_tree_and_fk(trip):
    rel, base, tip, robot, out = trip
    m0, m1 = pin.buildModelFromUrdf(robot_file(rel)), pin.buildModelFromUrdf(str(out))
    assert [m1.names[i] for i in range(m1.njoints)] == [m0.names[i] for i in range(m0.njoints)]
    assert m1.nq == m0.nq
    np.testing.assert_array_equal(m1.lowerPositionLimit, m0.lowerPositionLimit)
    np.testing.assert_array_equal(m1.upperPositionLimit, m0.upperPositionLimit)
    np.testing.assert_array_equal(m1.velocityLimit, m0.velocityLimit)
    np.testing.assert_array_equal(m1.effortLimit, m0.effortLimit)
    frame = robot.bodies.tip
    for q in sample_q(robot, 4, seed=11):
        np.testing.assert_allclose(pin_fk(m1, robot, q, frame), pin_fk(m0, robot, q, frame), atol=POSE_TOL)


def _visual_poses(path, cfg: dict) -> list[np.ndarray]:
    yourdfpy = pytest.importorskip("yourdfpy")
    u = yourdfpy.URDF.load(str(path), load_meshes=False, build_scene_graph=True)
    u.update_cfg({k: v for k, v in cfg.items() if k in u.actuated_joint_names})
    root = u.base_link
    out = []
    for link in sorted(u.link_map):
        T = u.get_transform(link, root)
        for v in u.link_map[link].visuals:
            out.append(T @ (np.eye(4) if v.origin is None else v.origin))
    return out


def test_visuals_sit_at_the_same_world_poses_at_random_q(trip):
    rel, base, tip, robot, out = trip
    for q in sample_q(robot, 3, seed=12):
        cfg = dict(zip([j.name for j in robot.joints], q))
        a, b = _visual_poses(robot_file(rel), cfg), _visual_poses(out, cfg)
        assert len(a) == len(b) > 0
        np.testing.assert_allclose(np.stack(b), np.stack(a), atol=POSE_TOL)


def test_mujoco_compiles_the_output(trip, tmp_path):
    mujoco = pytest.importorskip("mujoco")
    rel, base, tip, robot, out = trip

    def bare(path, name):
        # mesh files are package:// references that MuJoCo cannot resolve (neither for the original):
        # compile the file without its shapes, as one would after setting up mesh paths
        tree = ET.parse(path)
        for link in tree.getroot().iter("link"):
            for el in link.findall("visual") + link.findall("collision"):
                link.remove(el)
        tree.write(tmp_path / name)
        return mujoco.MjModel.from_xml_path(str(tmp_path / name))

    try:
        bare(robot_file(rel), "original.urdf")
    except ValueError as exc:
        pytest.skip(f"MuJoCo refuses the original file too: {str(exc).splitlines()[0]}")
    model = bare(out, "bare.urdf")
    data = mujoco.MjData(model)
    body = model.body(robot.bodies.tip).id
    names = [model.joint(i).name for i in range(model.njnt)]
    for q in sample_q(robot, 3, seed=13):
        data.qpos[:] = 0
        for j, v in zip(robot.joints, q):
            data.qpos[model.jnt_qposadr[names.index(j.name)]] = v
        mujoco.mj_kinematics(model, data)
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = data.xmat[body].reshape(3, 3), data.xpos[body]
        # MuJoCo's world is the file's root link; robkin's FK is in the base link frame
        np.testing.assert_allclose(T, robot.world @ robot.fk(q), atol=1e-9)


def test_ur5_controller_base_frame_and_tool0():
    path = robot_file("ur_description/urdf/ur5_robot.urdf")
    robot = robot_from_urdf(path, base_link="base", tip_link="tool0")
    model = pin.buildModelFromUrdf(path)
    data = model.createData()
    for q in sample_q(robot, 5, seed=14):
        pin.framesForwardKinematics(model, data, q)
        base = data.oMf[model.getFrameId("base")].homogeneous
        tool0 = data.oMf[model.getFrameId("tool0")].homogeneous
        np.testing.assert_allclose(robot.world, base, atol=1e-15)
        np.testing.assert_allclose(robot.fk(q), np.linalg.inv(base) @ tool0, atol=1e-12)
    # 'base' is base_link turned by pi about z: joint 1's axis is still the base z axis
    np.testing.assert_allclose(robot.world[:3, :3], np.diag([-1.0, -1.0, 1.0]), atol=1e-11)
    np.testing.assert_allclose(robot.axes[0], [0, 0, 1], atol=1e-11)


def test_a_base_above_a_moving_joint_is_refused_with_the_joint_named():
    path = robot_file("ur_description/urdf/ur5_robot.urdf")
    from robkin.errors import InputError

    with pytest.raises(InputError, match="climbs through joint 'elbow_joint', which moves"):
        robot_from_urdf(path, base_link="forearm_link", tip_link="upper_arm_link")


def test_moved_link_frames_are_re_expressed(tmp_path):
    """A link frame that no longer fits its joint (moved off the axis) is replaced by robkin's joint
    frame, and what hangs on it (shapes, child joints) is re-expressed: same world poses at any q."""
    rel = "ur_description/urdf/ur5_robot.urdf"
    robot = _load(rel, None, "tool0")
    moved = tuple(Link(k.name, k.body, k.pose @ np.array([[1, 0, 0, 0.05], [0, 1, 0, 0.02], [0, 0, 1, 0], [0, 0, 0, 1]])
                       if k.body > 0 and k.name in robot.bodies.chain else k.pose, k.parent, k.joint)
                  for k in robot.bodies.links)
    from dataclasses import replace

    shifted = robot.replace(bodies=replace(robot.bodies, links=moved))
    out = tmp_path / "moved.urdf"
    out.write_text(urdf_from_robot(shifted))
    back = _load(str(out), None, "tool0")
    Q = sample_q(robot, 4, seed=15)
    np.testing.assert_allclose(back.fk(Q), robot.fk(Q), atol=POSE_TOL)
    np.testing.assert_allclose(shape_poses(back, Q), shape_poses(robot, Q), atol=POSE_TOL)
    for q in Q:
        cfg = dict(zip([j.name for j in robot.joints], q))
        np.testing.assert_allclose(np.stack(_visual_poses(out, cfg)), np.stack(_visual_poses(robot_file(rel), cfg)),
                                   atol=POSE_TOL)


def test_limit_free_joints_give_pinocchio_nq_equal_n():
    # a robot from a table has no 'continuous' to keep: its unlimited revolute joints are written as
    # revolute with +-1e10 limits, one coordinate each in pinocchio (continuous would take two)
    from robkin import load
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the example's 3-decimal numbers are projected
        robot = load(__import__("robkin").__path__[0] + "/examples/arbitrary_3r.yaml")
    assert all(j.lower is None for j in robot.joints)
    text = urdf_from_robot(robot)
    model = pin.buildModelFromXML(text)
    assert model.nq == robot.n
    back = robot_from_urdf(text)
    assert all(j.lower is None and j.upper is None for j in back.joints)
    # a URDF's continuous joint stays continuous
    path = robot_file("double_pendulum_description/urdf/double_pendulum_continuous.urdf")
    again = robot_from_urdf(urdf_from_robot(robot_from_urdf(path)))
    assert pin.buildModelFromXML(urdf_from_robot(again)).nq == pin.buildModelFromUrdf(path).nq


SHAPED = """<robot name="shaped">
  <material name="blue"><color rgba="0 0 1 1"/></material>
  <link name="a"><visual name="v"><origin xyz="0 0 0.1" rpy="0 0.2 0"/><geometry><box size="0.1 0.2 0.3"/></geometry>
    <material name="blue"/></visual>
    <collision><geometry><cylinder radius="0.05" length="0.2"/></geometry></collision>
    <inertial><origin xyz="0 0 0.05"/><mass value="1.5"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.3"/>
    </inertial></link>
  <link name="b"><visual><geometry><sphere radius="0.04"/></geometry></visual>
    <visual><geometry><mesh filename="package://x/m.stl" scale="0.001 0.001 0.001"/></geometry></visual></link>
  <joint name="j" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0 0 0.4"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="10" velocity="2"/><dynamics damping="0.5" friction="0.1"/></joint>
</robot>"""


def test_shapes_materials_and_inertials_are_read_and_written_back():
    robot = robot_from_urdf(SHAPED)
    b = robot.bodies
    kinds = [(s.link, s.role, s.geometry.kind, s.geometry.size, s.geometry.filename) for s in b.shapes]
    assert kinds == [("a", "visual", "box", (0.1, 0.2, 0.3), None), ("a", "collision", "cylinder", (0.05, 0.2), None),
                     ("b", "visual", "sphere", (0.04,), None),
                     ("b", "visual", "mesh", (0.001, 0.001, 0.001), "package://x/m.stl")]
    assert b.shapes[0].material.rgba == (0.0, 0.0, 1.0, 1.0) and b.shapes[0].name == "v"
    (m,) = b.inertials
    assert m.mass == 1.5 and m.inertia[2, 2] == 0.3
    j = robot.joints[0]
    assert (j.effort, j.velocity, j.damping, j.friction) == (10.0, 2.0, 0.5, 0.1)
    again = robot_from_urdf(urdf_from_robot(robot))
    assert [(s.link, s.role, s.geometry, s.name) for s in again.bodies.shapes] == \
        [(s.link, s.role, s.geometry, s.name) for s in b.shapes]
    assert again.bodies.shapes[0].material.rgba == (0.0, 0.0, 1.0, 1.0)
    assert again.joints == robot.joints
    q = np.array([[0.7], [-0.3]])
    np.testing.assert_allclose(shape_poses(again, q), shape_poses(robot, q), atol=POSE_TOL)


def test_a_broken_shape_fails_only_what_needs_shapes(tmp_path, capsys):
    bad = tmp_path / "bad.urdf"
    bad.write_text(SHAPED.replace('<sphere radius="0.04"/>', '<sphere radius="x"/>'))
    # kinematics never looks at shapes
    assert main(["convert", str(bad), "--to", "dh"]) == 0
    capsys.readouterr()
    out = tmp_path / "out.urdf"
    assert main(["convert", str(bad), "--to", "urdf", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "link 'b' visual #1: sphere radius: 'x' is not a number" in err and not out.exists()


from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

_NASTY = ["nan", "-inf", "1e400", "x", "", "1 2", "0 0 0 0", "<", "&amp;", '"', "9" * 400, "-1e300"]


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.data())
def test_shape_parsing_fuzz_reads_or_says_why(data):
    """Every number of SHAPED replaced by junk: the whole file is read and written, or one InputError."""
    from robkin.errors import InputError

    import re

    spans = [m.span() for m in re.finditer(r'="[^"]*"', SHAPED)]
    text = SHAPED
    for _ in range(data.draw(st.integers(1, 3))):
        i, k = data.draw(st.sampled_from(spans))
        text = text[:i] + '="' + data.draw(st.sampled_from(_NASTY)) + '"' + text[k:]
        spans = [m.span() for m in re.finditer(r'="[^"]*"', text)]
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            robot = robot_from_urdf(text)
            urdf_from_robot(robot)
    except InputError as exc:
        assert "\n" not in str(exc)


def test_what_pinocchio_and_mujoco_make_of_each_limit_free_encoding():
    """The README's statement: continuous -> pinocchio nq 2 (cos, sin), MuJoCo unlimited hinge;
    revolute with +-1e10 (robkin's encoding of 'no limit') -> pinocchio nq 1, MuJoCo hinge whose range
    never binds."""
    mujoco = pytest.importorskip("mujoco")
    robot = Robot(np.stack([np.eye(4), se3.trans(0, 0, 0.5), se3.trans(0, 0.3, 0.5)]),
                  (Joint("free"), Joint("cont")))
    text = urdf_from_robot(robot)
    assert text.count('type="revolute"') == 2 and text.count('lower="-10000000000" upper="10000000000"') == 2
    head, block = text.split('<joint name="cont" type="revolute">')
    block = block.replace('<limit lower="-10000000000" upper="10000000000" effort="0" velocity="0"/>', "", 1)
    cont = head + '<joint name="cont" type="continuous">' + block
    m = pin.buildModelFromXML(text)
    assert m.nq == 2 and m.upperPositionLimit[0] == 1e10
    mc = pin.buildModelFromXML(cont)
    assert mc.nq == 3 and mc.nv == 2  # the continuous joint takes (cos, sin)
    mj = mujoco.MjModel.from_xml_string(text)
    assert mj.nq == 2 and list(mj.jnt_limited) == [1, 1] and mj.jnt_range[0][1] == 1e10
    mjc = mujoco.MjModel.from_xml_string(cont)
    assert mjc.nq == 2 and mjc.jnt_limited[mjc.joint("cont").id] == 0
