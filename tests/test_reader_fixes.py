"""Reader fixes found by a cross-check against MuJoCo, pinocchio and libsdformat: MJCF includes whose
top element is <mujocoinclude>, SDF models holding several unconnected trees, and URDF joints with
equal lower and upper limits (one meaning everywhere)."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import robkin
from robkin.cli import main
from robkin.io.trees.joint_limits import locked_joints, mjcf_lock_equalities

# ---------------------------------------------------------------------------------- MJCF <mujocoinclude>
#: The structure of gymnasium-robotics' Adroit hand and Franka kitchen: a main model that includes
#: its assets/defaults and its kinematic chain from files whose top element is <mujocoinclude>, one
#: of them including another.
MAIN = """<mujoco model="adroit_like">
  <include file="resources/assets.xml"/>
  <worldbody>
    <body name="forearm" pos="0 0 0.1">
      <include file="resources/chain.xml"/>
    </body>
  </worldbody>
</mujoco>"""
ASSETS = """<mujocoinclude>
  <compiler angle="radian"/>
  <default><joint damping="0.5" frictionloss="0.1"/><default class="wrist"><joint damping="2"/></default></default>
</mujocoinclude>"""
CHAIN = """<mujocoinclude>
  <body name="wrist" pos="0 0.02 0.3" euler="0.1 0 0">
    <joint name="WRJ1" class="wrist" axis="0 1 0" range="-0.5 0.2"/>
    <geom size="0.02"/>
    <include file="resources/finger.xml"/>
  </body>
</mujocoinclude>"""
FINGER = """<anything>
  <body name="knuckle" pos="0.03 0 0.1" quat="0.9 0 0.1 0.3">
    <joint name="FFJ1" axis="1 0 0" range="-0.4 1.6"/>
    <geom size="0.01"/>
    <body name="tip" pos="0 0 0.05"><joint name="FFJ0" axis="1 0 0" range="0 1.6"/><geom size="0.01"/>
    <site name="tip_site" pos="0 0 0.02"/></body>
  </body>
</anything>"""


def _adroit_like(tmp_path: Path) -> Path:
    (tmp_path / "resources").mkdir()
    for name, text in (("assets", ASSETS), ("chain", CHAIN), ("finger", FINGER)):
        (tmp_path / "resources" / f"{name}.xml").write_text(text)
    path = tmp_path / "model.xml"
    path.write_text(MAIN)
    return path


def test_included_files_with_any_top_element_load_as_mujoco_loads_them(tmp_path):
    mujoco = pytest.importorskip("mujoco")
    path = _adroit_like(tmp_path)
    robot = robkin.load(path, tip_link="tip_site")
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    assert [j.name for j in robot.joints] == [model.joint(i).name for i in range(model.njnt)]
    # the included <compiler angle="radian"> applies: the ranges are MuJoCo's, not read as degrees
    dof = {model.joint(i).name: i for i in range(model.njnt)}
    for j in robot.joints:
        assert (j.lower, j.upper) == tuple(model.jnt_range[dof[j.name]])
        # the included file's defaults (top level and class "wrist") as MuJoCo applies them
        k = model.jnt_dofadr[dof[j.name]]
        assert (j.damping, j.friction) == (model.dof_damping[k], model.dof_frictionloss[k]) == \
            ((2.0, 0.1) if j.name == "WRJ1" else (0.5, 0.1))
    site = model.site("tip_site").id
    for q in np.random.default_rng(4).uniform(-0.4, 0.2, (5, robot.n)):
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        T = robot.world @ robot.fk(q)
        # 1e-12: the same float64 products in another order
        assert np.abs(T[:3, 3] - data.site_xpos[site]).max() < 1e-12
        assert np.abs(T[:3, :3] - data.site_xmat[site].reshape(3, 3)).max() < 1e-12


def test_an_include_file_given_as_the_model_says_what_it_is(tmp_path, capsys):
    _adroit_like(tmp_path)
    assert main(["info", str(tmp_path / "resources" / "chain.xml")]) == 2
    err = capsys.readouterr().err
    assert "root element is <mujocoinclude>; an MJCF file has <mujoco> (this file is meant for <include file> in " \
           "a model: load the model that includes it)" in err and err.count("\n") == 1


# ---------------------------------------------------------------------------------- SDF unconnected trees
TWO_TREES = """<sdf version="1.9"><model name="two">
  <link name="a"/><link name="b"><pose>0 0 1 0 0 0</pose></link>
  <joint name="j" type="revolute"><parent>a</parent><child>b</child><axis><xyz>0 0 1</xyz></axis></joint>
  <link name="c"><pose>2 0 0 0 0 0</pose></link><link name="d"><pose>2 0 1 0 0 0</pose></link>
  <joint name="k" type="revolute"><parent>c</parent><child>d</child><axis><xyz>0 1 0</xyz></axis></joint>
</model></sdf>"""
ARM_AND_TABLE = """<sdf version="1.9"><model name="scene">
  <model name="table"><link name="top"><pose>1 0 0.7 0 0 0</pose></link></model>
  <model name="arm"><link name="a"/><link name="b"><pose>0 0 1 0 0 0</pose></link>
    <joint name="j" type="revolute"><parent>a</parent><child>b</child><axis><xyz>0 1 0</xyz></axis></joint></model>
</model></sdf>"""


@pytest.fixture()
def two(tmp_path):
    path = tmp_path / "two.sdf"
    path.write_text(TWO_TREES)
    return path


def test_sdf_with_two_moving_trees_asks_which(two, tmp_path, capsys):
    out = tmp_path / "out.urdf"
    assert main(["convert", str(two), "--to", "urdf", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "the model's links form 2 unconnected trees, 2 of them with moving joints: 'a' (1 moving joint(s), " \
           "--tip-link 'b'); 'c' (1 moving joint(s), --tip-link 'd'); pick the chain with --tip-link" in err
    assert err.count("\n") == 1 and not out.exists()
    assert main(["convert", str(two), "--to", "urdf", "--base-link", "c", "--tip-link", "b", "-o", str(out)]) == 2
    assert "are in different unconnected trees of the model (rooted at 'c' and 'a')" in capsys.readouterr().err
    assert not out.exists()


def test_sdf_tree_picked_by_the_tip_converts_to_urdf(two, tmp_path, capsys):
    pin = pytest.importorskip("pinocchio")
    out = tmp_path / "d.urdf"
    assert main(["convert", str(two), "--to", "urdf", "--tip-link", "d", "-o", str(out)]) == 0
    err = capsys.readouterr().err
    assert "2 link(s) not connected to the chain's tree (rooted at 'c') are left out: 'a', 'b'" in err
    with pytest.warns(UserWarning, match="left out"):
        robot = robkin.load(two, tip_link="d")
    assert [j.name for j in robot.joints] == ["k"] and robot.bodies.chain == ("c", "d")
    model = pin.buildModelFromUrdf(str(out))
    assert [model.names[i] for i in range(1, model.njoints)] == ["k"]
    data = model.createData()
    for q in (0.3, -1.1):  # k has no limits: continuous, pinocchio's q is (cos, sin)
        pin.forwardKinematics(model, data, np.array([np.cos(q), np.sin(q)]))
        pin.updateFramePlacements(model, data)
        T = data.oMf[model.getFrameId("d")].homogeneous
        assert np.abs(T - robot.fk([q])).max() < 1e-12  # both compose the same two transforms


def test_sdf_with_one_moving_tree_takes_it_and_says_what_is_left_out(tmp_path):
    path = tmp_path / "scene.sdf"
    path.write_text(ARM_AND_TABLE)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = robkin.load(path)
    assert [j.name for j in robot.joints] == ["arm::j"]
    (line,) = [str(w.message) for w in caught]
    assert line.endswith("1 link(s) not connected to the chain's tree (rooted at 'arm::a') are left out: "
                         "'table::top'")
    text = robkin.io.urdf.urdf_from_robot(robot)
    assert "table::top" not in text and 'link name="arm::b"' in text


def test_info_lists_the_chains_of_every_tree(two, capsys):
    assert main(["info", str(two)]) == 0
    out = capsys.readouterr().out
    assert "\nb " in out and "\nd " in out


# ---------------------------------------------------------------------------------- equal limits
ZERO = """<robot name="z">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="l3"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
    <limit lower="0" upper="0" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0 0 1"/><axis xyz="0 1 0"/>
    <limit effort="1" velocity="1"/></joint>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/><origin xyz="0 0 1"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>"""


@pytest.fixture()
def zero(tmp_path):
    path = tmp_path / "zero.urdf"
    path.write_text(ZERO)
    return path


def test_equal_limits_mean_locked_as_urdfdom_and_pinocchio_read_them(zero):
    pin = pytest.importorskip("pinocchio")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = robkin.load(zero)
    (line,) = [str(w.message) for w in caught]
    assert "joint(s) 'j1', 'j2' have equal lower and upper limits" in line and "locked" in line
    model = pin.buildModelFromUrdf(str(zero))
    assert [(j.lower, j.upper) for j in robot.joints] == \
        list(zip(model.lowerPositionLimit.tolist(), model.upperPositionLimit.tolist()))
    assert locked_joints(robot.joints) == [("j1", 0.0), ("j2", 0.0)]
    # IK keeps the locked joints where they are: a pose only j1 could reach has no solution
    assert not robot.ik(robot.fk([0.5, 0.0, 0.3])).success
    res = robot.ik(robot.fk([0.0, 0.0, 0.3]))
    assert res.success and res.q[:2].tolist() == [0.0, 0.0]
    # the URDF writer repeats the limits, so pinocchio reads the same locked range back
    text = robkin.io.urdf.urdf_from_robot(robot)
    again = pin.buildModelFromXML(text)
    assert again.lowerPositionLimit.tolist() == [0.0, 0.0, -1.0]
    # the MJCF holds them with joint equalities (MuJoCo refuses an empty range)
    mujoco = pytest.importorskip("mujoco")
    from robkin.io.mjcf import mjcf_from_robot

    with pytest.warns(UserWarning, match="move without mass"):  # the file has no inertials
        mj = mujoco.MjModel.from_xml_string(mjcf_from_robot(robot))
    assert mj.neq == 2 and [mj.joint(mj.eq_obj1id[k]).name for k in range(2)] == ["j1", "j2"]
    assert again.upperPositionLimit.tolist() == [0.0, 0.0, 1.0]


def test_mjcf_holds_a_locked_joint_with_an_equality(zero):
    mujoco = pytest.importorskip("mujoco")
    from xml.sax.saxutils import quoteattr

    joints = [type("J", (), {"name": "j1", "lower": 0.25, "upper": 0.25})(),
              type("J", (), {"name": "j2", "lower": -1.0, "upper": 1.0})()]
    eq = mjcf_lock_equalities(joints, quoteattr, repr)
    assert eq == ['<joint joint1="j1" polycoef="0.25 0 0 0 0"/>']
    for equality, held in (f"<equality>{''.join(eq)}</equality>", True), ("", False):
        xml = ('<mujoco><compiler angle="radian"/><worldbody><body><joint name="j1" axis="0 1 0"/>'
               '<geom size="0.05" pos="0.3 0 0"/><body pos="0.6 0 0"><joint name="j2" axis="0 1 0"/>'
               f'<geom size="0.05" pos="0.3 0 0"/></body></body></worldbody>{equality}</mujoco>')
        model = mujoco.MjModel.from_xml_string(xml)
        data = mujoco.MjData(model)
        data.qpos[:] = [0.25, 0.0]
        for _ in range(500):  # 1 s under gravity: the free arm falls by more than a radian
            mujoco.mj_step(model, data)
        # 0.02 rad: the equality is a soft constraint (MuJoCo's default solref), it sags a little
        assert (abs(data.qpos[0] - 0.25) < 0.02) == held and abs(data.qpos[1]) > 0.5


# ---------------------------------------------------------------------------------- MJCF in -> MJCF/URDF out
KEEPS = """<mujoco model="keeps">
  <compiler angle="radian"/>
  <default>
    <joint damping="0.3" frictionloss="0.05" armature="0.01"/>
    <default class="big"><joint damping="4" armature="0.2"/></default>
  </default>
  <asset><material name="blue" rgba="0.1 0.2 0.9 1"/></asset>
  <worldbody>
    <body name="base">
      <inertial pos="0 0 0.05" mass="3" diaginertia="0.02 0.03 0.04"/>
      <body name="upper" pos="0 0 0.1">
        <joint name="shoulder" class="big" axis="0 0 1" range="-2 2"/>
        <inertial pos="0.01 0.02 0.15" quat="0.9 0.1 0.3 0.2" mass="2.5" diaginertia="0.05 0.04 0.01"/>
        <geom type="capsule" fromto="0 0 0 0 0 0.3" size="0.04" material="blue"/>
        <body name="lower" pos="0 0 0.3">
          <joint name="elbow" axis="0 1 0" range="-1.5 1.5" frictionloss="0.2"/>
          <inertial pos="0 0 0.1" mass="1.2" fullinertia="0.02 0.021 0.005 0.001 -0.0005 0.0008"/>
          <geom type="box" size="0.03 0.03 0.1" pos="0 0 0.1" rgba="0.9 0.4 0.1 1"/>
          <site name="hand" pos="0 0 0.2"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>"""


def _mj_bodies(model, names):
    """name -> (mass, inertia tensor in the world frame at qpos 0, centre of mass in the world frame)."""
    import mujoco

    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    out = {}
    for name in names:
        b = model.body(name).id
        Ri = data.ximat[b].reshape(3, 3)  # the principal axes in the world frame
        out[name] = (model.body_mass[b], Ri @ np.diag(model.body_inertia[b]) @ Ri.T, data.xipos[b].copy())
    return out


def test_mjcf_in_mjcf_and_urdf_out_keep_masses_dynamics_and_colours(tmp_path):
    mujoco = pytest.importorskip("mujoco")
    pin = pytest.importorskip("pinocchio")
    from robkin.io.mjcf import mjcf_from_robot
    from robkin.io.urdf import urdf_from_robot

    path = tmp_path / "keeps.xml"
    path.write_text(KEEPS)
    robot = robkin.load(path, tip_link="hand")
    source = mujoco.MjModel.from_xml_path(str(path))
    dof = {source.joint(i).name: source.jnt_dofadr[i] for i in range(source.njnt)}
    for j in robot.joints:  # the defaults and classes resolved as MuJoCo resolves them
        k = dof[j.name]
        assert (j.damping, j.friction, j.armature) == (source.dof_damping[k], source.dof_frictionloss[k],
                                                       source.dof_armature[k])
    visuals = {s.link: s.material.rgba for s in robot.bodies.visuals()}
    assert visuals == {"upper": (0.1, 0.2, 0.9, 1.0), "lower": (0.9, 0.4, 0.1, 1.0)}
    again = mujoco.MjModel.from_xml_string(mjcf_from_robot(robot))
    names = ("base", "upper", "lower")
    a, b = _mj_bodies(source, names), _mj_bodies(again, names)
    for name in names:  # 1e-9: MuJoCo's own float64 diagonalisation of the same tensors
        assert a[name][0] == pytest.approx(b[name][0], rel=1e-12)
        assert np.abs(a[name][1] - b[name][1]).max() < 1e-9 and np.abs(a[name][2] - b[name][2]).max() < 1e-12
    dof2 = {again.joint(i).name: again.jnt_dofadr[i] for i in range(again.njnt)}
    for name, k in dof.items():
        k2 = dof2[name]
        assert (again.dof_damping[k2], again.dof_frictionloss[k2], again.dof_armature[k2]) == \
            (source.dof_damping[k], source.dof_frictionloss[k], source.dof_armature[k])
    # URDF out, read by pinocchio: the same masses and inertias (URDF has no armature: left out)
    model = pin.buildModelFromXML(urdf_from_robot(robot))
    assert sum(i.mass for i in model.inertias) == pytest.approx(source.body_mass.sum(), rel=1e-12)
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    for name in ("upper", "lower"):
        jid = model.getJointId({"upper": "shoulder", "lower": "elbow"}[name])
        Y = model.inertias[jid]
        R = data.oMi[jid].rotation
        assert Y.mass == pytest.approx(a[name][0], rel=1e-12)
        assert np.abs(R @ Y.inertia @ R.T - a[name][1]).max() < 1e-9
        assert np.abs(data.oMi[jid].act(Y.lever) - a[name][2]).max() < 1e-12


# ---------------------------------------------------------------------------------- SDF in -> MJCF/URDF out
KEEPS_SDF = """<sdf version="1.9"><model name="keeps">
  <link name="base"><inertial><mass>3</mass><pose>0 0 0.05 0 0 0</pose>
    <inertia><ixx>0.02</ixx><iyy>0.03</iyy><izz>0.04</izz></inertia></inertial></link>
  <link name="upper"><pose>0 0 0.1 0 0 0</pose>
    <inertial><mass>2.5</mass><pose>0.01 0.02 0.15 0.3 -0.2 0.5</pose>
      <inertia><ixx>0.045</ixx><ixy>0.001</ixy><ixz>-0.002</ixz><iyy>0.04</iyy><iyz>0.0005</iyz><izz>0.01</izz></inertia>
    </inertial>
    <visual name="v"><pose>0 0 0.15 0 0 0</pose><geometry><cylinder><radius>0.04</radius><length>0.3</length></cylinder>
      </geometry><material><diffuse>0.1 0.2 0.9 1</diffuse></material></visual></link>
  <joint name="shoulder" type="revolute"><parent>base</parent><child>upper</child>
    <axis><xyz>0 0 1</xyz><limit><lower>-2</lower><upper>2</upper><effort>30</effort><velocity>2</velocity></limit>
      <dynamics><damping>4</damping><friction>0.05</friction></dynamics></axis></joint>
  <link name="lower"><pose>0 0 0.4 0 0 0</pose>
    <inertial><mass>1.2</mass><pose>0 0 0.1 0 0 0</pose>
      <inertia><ixx>0.02</ixx><iyy>0.021</iyy><izz>0.005</izz></inertia></inertial></link>
  <joint name="elbow" type="revolute"><parent>upper</parent><child>lower</child>
    <axis><xyz>0 1 0</xyz><limit><lower>-1.5</lower><upper>1.5</upper></limit>
      <dynamics><damping>0.3</damping><friction>0.2</friction></dynamics></axis></joint>
</model></sdf>"""


def _sdf_expected():
    """name -> (mass, inertia in the model frame, centre in the model frame), from the SDF's numbers."""
    from robkin import se3

    def full(xx, yy, zz, xy=0.0, xz=0.0, yz=0.0):
        return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])

    R = se3.matrix_from_rpy([0.3, -0.2, 0.5])
    return {"base": (3.0, full(0.02, 0.03, 0.04), np.array([0, 0, 0.05])),
            "upper": (2.5, R @ full(0.045, 0.04, 0.01, 0.001, -0.002, 0.0005) @ R.T, np.array([0.01, 0.02, 0.25])),
            "lower": (1.2, full(0.02, 0.021, 0.005), np.array([0, 0, 0.5]))}


def test_sdf_in_mjcf_and_urdf_out_keep_masses_dynamics_and_colours(tmp_path):
    mujoco = pytest.importorskip("mujoco")
    pin = pytest.importorskip("pinocchio")
    from robkin.io.mjcf import mjcf_from_robot
    from robkin.io.urdf import urdf_from_robot

    path = tmp_path / "keeps.sdf"
    path.write_text(KEEPS_SDF)
    robot = robkin.load(path)
    assert [(j.name, j.damping, j.friction) for j in robot.joints] == [("shoulder", 4.0, 0.05), ("elbow", 0.3, 0.2)]
    assert [s.material.rgba for s in robot.bodies.visuals()] == [(0.1, 0.2, 0.9, 1.0)]
    expected = _sdf_expected()
    mj = mujoco.MjModel.from_xml_string(mjcf_from_robot(robot))
    got = _mj_bodies(mj, expected)
    for name, (m, inertia, com) in expected.items():  # 1e-12: float64 products; 1e-9: MuJoCo's eigen-solver
        assert got[name][0] == pytest.approx(m, rel=1e-12), name
        assert np.abs(got[name][1] - inertia).max() < 1e-9, name
        assert np.abs(got[name][2] - com).max() < 1e-12, name
    dof = {mj.joint(i).name: mj.jnt_dofadr[i] for i in range(mj.njnt)}
    assert [(mj.dof_damping[dof[n]], mj.dof_frictionloss[dof[n]]) for n in ("shoulder", "elbow")] == \
        [(4.0, 0.05), (0.3, 0.2)]
    (g,) = [g for g in range(mj.ngeom) if mj.geom_type[g] == mujoco.mjtGeom.mjGEOM_CYLINDER]
    assert mj.geom_rgba[g].tolist() == pytest.approx([0.1, 0.2, 0.9, 1.0], abs=1e-7)  # float32 in MuJoCo
    model = pin.buildModelFromXML(urdf_from_robot(robot))
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    for name, joint in (("upper", "shoulder"), ("lower", "elbow")):
        jid = model.getJointId(joint)
        Y, M = model.inertias[jid], data.oMi[jid]
        assert Y.mass == pytest.approx(expected[name][0], rel=1e-12)
        assert np.abs(M.rotation @ Y.inertia @ M.rotation.T - expected[name][1]).max() < 1e-12
        assert np.abs(M.act(Y.lever) - expected[name][2]).max() < 1e-12
    assert model.damping.tolist() == [4.0, 0.3] and model.friction.tolist() == [0.05, 0.2]


def test_kitchen_like_includes_from_a_sibling_folder(tmp_path):
    """gymnasium-robotics' Franka kitchen: kitchen_assets/kitchen_env_model.xml includes
    ../franka_assets/{assets,chain}.xml (<mujocoinclude>): read as MuJoCo reads them, said once."""
    mujoco = pytest.importorskip("mujoco")
    (tmp_path / "franka_assets").mkdir()
    (tmp_path / "kitchen_assets").mkdir()
    (tmp_path / "franka_assets" / "assets.xml").write_text(ASSETS)
    (tmp_path / "franka_assets" / "chain.xml").write_text(
        CHAIN.replace('<include file="resources/finger.xml"/>', '<site name="ee" pos="0 0 0.1"/>'))
    path = tmp_path / "kitchen_assets" / "kitchen.xml"
    path.write_text('<mujoco><include file="../franka_assets/assets.xml"/><worldbody><body name="table">'
                    '<geom size="0.1"/><include file="../franka_assets/chain.xml"/></body></worldbody></mujoco>')
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = robkin.load(path, tip_link="ee")
    assert [str(w.message) for w in caught] == [
        f"{path}: 2 included file(s) outside the model's folder are read: ../franka_assets/assets.xml, "
        f"../franka_assets/chain.xml"]
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    data.qpos[:] = [0.15]
    mujoco.mj_kinematics(model, data)
    T = robot.world @ robot.fk([0.15])
    assert np.abs(T[:3, 3] - data.site_xpos[model.site("ee").id]).max() < 1e-12
    assert robot.joints[0].damping == model.dof_damping[0] == 2.0  # the included class "wrist"


def test_a_joint_held_by_an_mjcf_equality_reads_back_locked(zero, tmp_path):
    """URDF (equal limits) -> MJCF (joint equality) -> robkin: the same locked joints, and the URDF
    written from that MJCF has pinocchio's same limits."""
    pin = pytest.importorskip("pinocchio")
    from robkin.io.mjcf import mjcf_from_robot
    from robkin.io.urdf import urdf_from_robot

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = robkin.load(zero)
        mjcf = tmp_path / "zero.xml"
        mjcf.write_text(mjcf_from_robot(robot))
        mjcf.write_text(mjcf.read_text().replace('polycoef="0 0 0 0 0"', 'polycoef="0.25 0 0 0 0"', 1))
    with pytest.warns(UserWarning, match=r"joint\(s\) 'j1', 'j2' have equal lower and upper limits"):
        back = robkin.load(mjcf, tip_link="l3")
    assert [(j.name, j.lower, j.upper) for j in back.joints] == [("j1", 0.25, 0.25), ("j2", 0.0, 0.0),
                                                                  ("j3", -1.0, 1.0)]
    model = pin.buildModelFromXML(urdf_from_robot(back))
    assert model.lowerPositionLimit.tolist() == [0.25, 0.0, -1.0]
    assert model.upperPositionLimit.tolist() == [0.25, 0.0, 1.0]
