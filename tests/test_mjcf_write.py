"""What the MJCF writer keeps, checked by MuJoCo's compiler on small hand-written URDFs: link names as
bodies and sites, joint properties, geoms and their classes, exact inertials, fused fixed links, mimic
joints, actuators and their ranges, the home keyframe, repairs of non-physical inertials; and MJCF ->
MJCF round trips.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from robkin import Joint, Robot, se3
from robkin.bodies import Bodies
from robkin.body_parts import Inertial
from robkin.cli import main
from robkin.dynamics import link_masses
from robkin.io.mjcf import mjcf_from_robot
from robkin.io.mjcf.reader import robot_from_mjcf
from robkin.io.urdf import robot_from_urdf
from strategies import robots
from test_properties import SCALE as PROPERTY_SCALE

mujoco = pytest.importorskip("mujoco")

#: Same promise as the dynamics tests: observed ~1e-16 (one eigen-decomposition, products of poses).
TOL = 1e-12

ARM = """<robot name="arm">
  <material name="blue"><color rgba="0 0 1 1"/></material>
  <link name="base_link">
    <inertial><origin xyz="0 0 0.05"/><mass value="2"/><inertia ixx="0.01" iyy="0.01" izz="0.02" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><geometry><cylinder radius="0.1" length="0.1"/></geometry><material name="blue"/></visual>
    <collision><geometry><cylinder radius="0.1" length="0.1"/></geometry></collision>
  </link>
  <link name="upper">
    <inertial><origin xyz="0.1 0.02 0.2" rpy="0.3 -0.2 0.1"/><mass value="1.5"/>
      <inertia ixx="0.03" iyy="0.02" izz="0.015" ixy="0.001" ixz="-0.002" iyz="0.003"/></inertial>
    <visual name="v"><origin xyz="0 0 0.2"/><geometry><box size="0.1 0.08 0.4"/></geometry>
      <material name="red"><color rgba="1 0 0 1"/></material></visual>
    <collision name="v"><origin xyz="0 0 0.2"/><geometry><box size="0.1 0.08 0.4"/></geometry></collision>
  </link>
  <link name="flange">
    <inertial><origin xyz="0 0 0.01"/><mass value="0.3"/><inertia ixx="0.001" iyy="0.001" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><geometry><sphere radius="0.03"/></geometry></visual>
  </link>
  <link name="fore">
    <inertial><origin xyz="0.15 0 0"/><mass value="1"/><inertia ixx="0.002" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><sphere radius="0.05"/></geometry></collision>
  </link>
  <link name="finger_a"><inertial><mass value="0.05"/><inertia ixx="1e-5" iyy="1e-5" izz="1e-5" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="finger_b"><inertial><mass value="0.05"/><inertia ixx="1e-5" iyy="1e-5" izz="1e-5" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="tool0"/>
  <joint name="shoulder" type="revolute"><parent link="base_link"/><child link="upper"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="40" velocity="2"/>
    <dynamics damping="0.5" friction="0.1"/></joint>
  <joint name="mount" type="fixed"><parent link="upper"/><child link="flange"/><origin xyz="0 0 0.4" rpy="0 0.3 0"/></joint>
  <joint name="elbow" type="revolute"><parent link="flange"/><child link="fore"/>
    <origin xyz="0 0 0.02"/><axis xyz="0 1 0"/><limit lower="-1.5" upper="1.5" effort="20" velocity="3"/></joint>
  <joint name="grip" type="prismatic"><parent link="fore"/><child link="finger_a"/>
    <origin xyz="0.3 0 0"/><axis xyz="0 1 0"/><limit lower="0" upper="0.04" effort="10" velocity="0.1"/></joint>
  <joint name="grip_mimic" type="prismatic"><parent link="fore"/><child link="finger_b"/>
    <origin xyz="0.3 0 0"/><axis xyz="0 -1 0"/><limit lower="0" upper="0.04" effort="10" velocity="0.1"/>
    <mimic joint="grip" multiplier="1" offset="0"/></joint>
  <joint name="tool" type="fixed"><parent link="fore"/><child link="tool0"/><origin xyz="0.35 0 0"/></joint>
</robot>"""


def _arm() -> Robot:
    return robot_from_urdf(ARM, tip_link="tool0")


def _load(text: str):
    model = mujoco.MjModel.from_xml_string(text)
    return model, mujoco.MjData(model)


def _pose(model, data, kind: str, name: str) -> np.ndarray:
    T = np.eye(4)
    if kind == "site":
        i = model.site(name).id
        T[:3, :3], T[:3, 3] = data.site_xmat[i].reshape(3, 3), data.site_xpos[i]
    else:
        i = model.body(name).id
        T[:3, :3], T[:3, 3] = data.xmat[i].reshape(3, 3), data.xpos[i]
    return T


def test_links_joints_geoms_and_inertials_as_the_source_says():
    robot = _arm()
    model, data = _load(mjcf_from_robot(robot))
    names = [model.body(i).name for i in range(1, model.nbody)]
    assert names == ["base_link", "upper", "flange", "fore", "tool0", "finger_a", "finger_b"]
    assert model.site("tool0").bodyid == model.body("tool0").id      # tip: a body with a site
    assert [model.joint(i).name for i in range(model.njnt)] == ["shoulder", "elbow", "grip", "grip_mimic"]
    sh = model.joint("shoulder")
    assert sh.damping[0] == 0.5 and sh.frictionloss[0] == 0.1 and list(sh.range) == [-2, 2]
    # visual geoms: group 2, no contact; collision geoms: group 3; no mass from the shapes
    vis, col = model.geom_group == 2, model.geom_group == 3
    assert vis.sum() == 3 and col.sum() == 3
    assert not model.geom_contype[vis].any() and not model.geom_conaffinity[vis].any()
    assert model.geom_contype[col].all()
    assert model.geom("v").group == 2 and model.geom("v_2").group == 3   # unique names
    np.testing.assert_allclose(model.mat_rgba[model.geom_matid[model.geom("v").id]], [1, 0, 0, 1])
    np.testing.assert_allclose(model.mat("blue").rgba, [0, 0, 1, 1])
    # exact inertials: every body's world centre and inertia at q as robkin's merged ones
    masses = link_masses(robot)
    for q in ([0.0, 0.0], [0.7, -0.4]):
        data.qpos[:] = 0
        data.qpos[:2] = q
        mujoco.mj_forward(model, data)
        assert abs(model.body_subtreemass[model.body("base_link").id] - masses.total_mass) <= TOL
        np.testing.assert_allclose(data.subtree_com[0], _com(robot, np.array(q)), atol=TOL)
    keys = model.key("home")
    assert list(keys.qpos) == [0.0] * model.nq


def _com(robot: Robot, q: np.ndarray) -> np.ndarray:
    from robkin.bodies import body_motions

    m = link_masses(robot)
    M = body_motions(robot, q)
    c = np.einsum("kij,kj->ki", M[:, :3, :3], m.com) + M[:, :3, 3]
    return robot.world[:3, :3] @ (m.mass @ c / m.total_mass) + robot.world[:3, 3]


def test_mimic_joint_follows_through_an_equality_and_is_not_actuated():
    model, data = _load(mjcf_from_robot(_arm()))
    assert model.neq == 1 and model.eq_type[0] == mujoco.mjtEq.mjEQ_JOINT
    assert model.joint(model.eq_obj1id[0]).name == "grip_mimic" and model.joint(model.eq_obj2id[0]).name == "grip"
    np.testing.assert_allclose(model.eq_data[0][:5], [0, 1, 0, 0, 0])
    assert [model.joint(model.actuator_trnid[a, 0]).name for a in range(model.nu)] == ["shoulder", "elbow", "grip"]
    # simulated: the mimic finger follows the driven one
    data.ctrl[2] = 5.0
    for _ in range(400):
        mujoco.mj_step(model, data)
    assert data.qpos[2] > 0.01 and abs(data.qpos[3] - data.qpos[2]) < 1e-3


@pytest.mark.parametrize("kind", ["motor", "position", "velocity", "none"])
def test_actuator_kinds_and_ranges(kind):
    model, _ = _load(mjcf_from_robot(_arm(), actuators=kind, kp=200.0, kv=20.0))
    if kind == "none":
        assert model.nu == 0
        return
    sh = model.actuator("shoulder")
    if kind == "motor":
        assert list(sh.ctrlrange) == [-40, 40] and not sh.forcelimited
    elif kind == "position":
        assert list(sh.ctrlrange) == [-2, 2] and list(sh.forcerange) == [-40, 40]
        assert sh.gainprm[0] == 200 and list(sh.biasprm[:3]) == [0, -200, -20]
    else:
        assert list(sh.ctrlrange) == [-2, 2] and list(sh.forcerange) == [-40, 40]   # +-velocity, +-effort
        assert sh.gainprm[0] == 20 and list(sh.biasprm[:3]) == [0, 0, -20]


def test_unknown_effort_leaves_the_range_open():
    frames = np.stack([np.eye(4), se3.trans(0, 0, 0.5)])
    model, _ = _load(mjcf_from_robot(Robot(frames, (Joint("j"),))))
    assert model.nu == 1 and not model.actuator_ctrllimited[0]


def test_fuse_fixed_merges_mass_exactly_and_keeps_names_as_sites():
    robot = _arm()
    model, data = _load(mjcf_from_robot(robot, fuse_fixed=True))
    names = {model.body(i).name for i in range(1, model.nbody)}
    assert "flange" not in names and model.site("flange").bodyid == model.body("upper").id
    assert "tool0" in names    # the tip stays a body (with its site)
    plain, pdata = _load(mjcf_from_robot(robot))
    for q in ([0.3, -0.8], [-1.0, 1.2]):
        for m, d in ((model, data), (plain, pdata)):
            d.qpos[:] = 0
            d.qpos[:2] = q
            mujoco.mj_forward(m, d)
        Mf, Mp = np.zeros((model.nv, model.nv)), np.zeros((plain.nv, plain.nv))
        mujoco.mj_fullM(model, data, Mf)
        mujoco.mj_fullM(plain, pdata, Mp)
        np.testing.assert_allclose(Mf, Mp, atol=TOL)
        np.testing.assert_allclose(data.qfrc_bias, pdata.qfrc_bias, atol=TOL)
        np.testing.assert_allclose(_pose(model, data, "site", "tool0"), _pose(plain, pdata, "site", "tool0"), atol=TOL)
        np.testing.assert_allclose(_pose(model, data, "site", "flange"), _pose(plain, pdata, "body", "flange"), atol=TOL)


def test_non_physical_and_massless_inertials_load_with_one_warning_each():
    bad = ARM.replace('ixx="0.002" iyy="0.01" izz="0.01"', 'ixx="0.002" iyy="0.01" izz="0.03"')   # C > A + B
    bad = bad.replace('<link name="finger_a"><inertial><mass value="0.05"/><inertia ixx="1e-5" iyy="1e-5" izz="1e-5" '
                      'ixy="0" ixz="0" iyz="0"/></inertial></link>', '<link name="finger_a"/>')
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        text = mjcf_from_robot(robot_from_urdf(bad, tip_link="tool0"))
    lines = [str(w.message) for w in caught]
    assert sum("not physical" in s and "fore" in s for s in lines) == 1
    assert sum("finger_a" in s and "without mass" in s for s in lines) == 1
    model, _ = _load(text)
    A, B, C = sorted(model.body_inertia[model.body("fore").id])
    assert A + B >= C and np.isclose(C, 0.012)   # the largest moment clipped to the sum of the others


def test_robot_from_a_table_with_inertials_is_base_link1_tool():
    frames = np.stack([np.eye(4), se3.trans(0, 0, 0.4) @ se3.rot_x(-np.pi / 2), se3.trans(0.3, 0, 0.4)])
    inertials = (Inertial("link1", 1, se3.trans(0, 0, 0.2), 2.0, np.diag([0.02, 0.02, 0.01])),
                 Inertial("link2", 2, se3.trans(0.15, 0, 0.4), 1.0, np.diag([0.001, 0.01, 0.01])))
    robot = Robot(frames, (Joint("a"), Joint("b")), bodies=Bodies(inertials=inertials))
    text = mjcf_from_robot(robot)
    assert "no link names" in text.splitlines()[1]
    model, data = _load(text)
    assert [model.body(i).name for i in range(1, model.nbody)] == ["base", "link1", "link2", "tool"]
    assert model.body_mass.sum() == 3.0
    data.qpos[:] = [0.4, -0.3]
    mujoco.mj_kinematics(model, data)
    np.testing.assert_allclose(_pose(model, data, "site", "tool"), robot.fk([0.4, -0.3]), atol=TOL)


def test_mjcf_round_trips_through_robkin(tmp_path):
    """robkin's MJCF read by robkin and written again: the same bodies, joints, geoms and inertials."""
    robot = _arm()
    first = mjcf_from_robot(robot)
    back = robot_from_mjcf(first, "base_link", "tool0")
    assert [j.name for j in back.joints] == ["shoulder", "elbow"]
    second = mjcf_from_robot(back)
    m1, _ = _load(first)
    m2, d2 = _load(second)
    for attr in ("body_mass", "body_inertia", "body_ipos", "body_pos", "geom_size", "geom_group", "jnt_range",
                 "dof_damping", "dof_frictionloss"):
        np.testing.assert_allclose(getattr(m2, attr), getattr(m1, attr), atol=TOL, err_msg=attr)
    assert [m2.body(i).name for i in range(m2.nbody)] == [m1.body(i).name for i in range(m1.nbody)]
    assert m2.nu == m1.nu and m2.neq == m1.neq


@pytest.mark.parametrize("argv, message", [
    (["--to", "urdf", "--fuse-fixed"], "--fuse-fixed: applies to --to mjcf only"),
    (["--to", "mjcf", "--actuators", "velocity", "--kp", "10"], "--kp: applies to --actuators position"),
    (["--to", "mjcf", "--kp", "-1"], "--kp -1: a gain is a number >= 0"),
    (["--to", "mjcf", "--kv", "fast"], "--kv fast: a gain is a number >= 0"),
    (["--to", "mjcf", "--actuators", "motor", "--kv", "3"], "--kv: applies to --actuators position or velocity"),
])
def test_bad_mjcf_options_are_one_clear_line(tmp_path, capsys, argv, message):
    src = tmp_path / "arm.urdf"
    src.write_text(ARM)
    out = tmp_path / ("x.xml" if "mjcf" in argv else "x.urdf")
    assert main(["convert", str(src), "--tip-link", "tool0", *argv, "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0]
    assert not out.exists()


def test_cli_writes_checks_and_reports(tmp_path, capsys):
    src = tmp_path / "arm.urdf"
    src.write_text(ARM)
    out = tmp_path / "sim" / "arm.xml"
    out.parent.mkdir()
    assert main(["convert", str(src), "--tip-link", "tool0", "--to", "mjcf", "--actuators", "position", "-o",
                 str(out)]) == 0
    err = capsys.readouterr().err
    assert "FK and mass properties equal the source's" in err
    model = mujoco.MjModel.from_xml_path(str(out))
    assert model.nu == 3 and model.actuator_gainprm[0, 0] == 100   # the default kp


def _physical_inertials(robot: Robot, rng: np.random.Generator, parts: int = 2) -> Robot:
    """The robot with ``parts`` random inertials on every body, each physical: principal moments
    (b + c, a + c, a + b) of second moments a, b, c > 0 of a mass distribution, at a random pose."""
    records = []
    for body in range(robot.n + 1):
        for k in range(parts):
            a, b, c = rng.uniform(0.001, 0.5, 3)
            Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
            pose = se3.homogeneous(se3.matrix_from_rpy(rng.uniform(-3, 3, 3)), rng.normal(size=3))
            records.append(Inertial(f"l{body}_{k}", body, pose, float(rng.uniform(0.1, 3.0)),
                                    Q @ np.diag([b + c, a + c, a + b]) @ Q.T))
    return robot.replace(bodies=Bodies(inertials=tuple(records)))


@pytest.mark.filterwarnings("ignore::robkin.ConditioningWarning")
@settings(max_examples=25 * PROPERTY_SCALE, deadline=None)
@given(robots(max_joints=7), st.integers(0, 2**32 - 1), st.booleans())
def test_any_robot_with_inertials_simulates_with_robkins_dynamics(robot, seed, fuse):
    """MuJoCo's M(q) and gravity torques of robkin's MJCF of any robot with random inertials (several on
    a body, merged exactly) equal robkin's own dynamics (tested against pinocchio in test_dynamics)."""
    rng = np.random.default_rng(seed)
    robot = _physical_inertials(robot, rng)
    model, data = _load(mjcf_from_robot(robot, fuse_fixed=fuse))
    n = robot.n
    for q in rng.uniform(-2, 2, size=(2, n)):
        data.qpos[:] = q
        mujoco.mj_forward(model, data)
        M = np.zeros((n, n))
        mujoco.mj_fullM(model, data, M)
        Mr, gr = robot.mass_matrix(q), robot.gravity(q)
        np.testing.assert_allclose(M, Mr, atol=1e-9 * np.abs(Mr).max())
        np.testing.assert_allclose(data.qfrc_bias, gr, atol=1e-9 * max(np.abs(gr).max(), np.abs(Mr).max()))


SDF = """<sdf version="1.9"><model name="s">
  <link name="a"><inertial><mass>2</mass><inertia><ixx>0.1</ixx><iyy>0.1</iyy><izz>0.1</izz></inertia></inertial></link>
  <link name="b"><pose>0 0 0.3 0 0 0</pose>
    <inertial><pose>0.1 0 0 0 0 0</pose><mass>1</mass><inertia><ixx>0.01</ixx><iyy>0.02</iyy><izz>0.02</izz></inertia></inertial>
    <collision name="c"><geometry><box><size>0.1 0.2 0.3</size></box></geometry></collision></link>
  <joint name="j" type="revolute"><parent>a</parent><child>b</child>
    <axis><xyz>0 1 0</xyz><limit><lower>-2</lower><upper>2</upper><effort>30</effort><velocity>4</velocity></limit>
      <dynamics><damping>0.7</damping><friction>0.2</friction></dynamics></axis></joint>
</model></sdf>"""


def test_sdf_joint_dynamics_and_limits_reach_mjcf_and_urdf(tmp_path):
    from robkin.io.sdf.reader import robot_from_sdf
    from robkin.io.urdf import urdf_from_robot

    robot = robot_from_sdf(SDF)
    j = robot.joints[0]
    assert (j.effort, j.velocity, j.damping, j.friction) == (30, 4, 0.7, 0.2)
    model, _ = _load(mjcf_from_robot(robot, actuators="velocity"))
    assert model.joint("j").damping[0] == 0.7 and model.joint("j").frictionloss[0] == 0.2
    assert list(model.actuator("j").ctrlrange) == [-4, 4] and list(model.actuator("j").forcerange) == [-30, 30]
    assert int((model.geom_group == 3).sum()) == 1 and model.body_mass.sum() == 3
    back = robot_from_urdf(urdf_from_robot(robot))
    assert back.joints[0] == j


def test_stl_beyond_mujocos_triangle_limit_becomes_obj(tmp_path, monkeypatch):
    """MuJoCo refuses an STL of more than 200 000 triangles (detailed COLLADA visuals converted to STL
    have more): such a copy is rewritten as OBJ, which MuJoCo loads (the limit lowered to 10 here)."""
    trimesh = pytest.importorskip("trimesh")
    from robkin.io.mjcf import meshes as mjcf_meshes

    monkeypatch.setattr(mjcf_meshes, "MUJOCO_STL_MAX_FACES", 10)
    (tmp_path / "meshes").mkdir()
    box = trimesh.creation.box((0.1, 0.2, 0.3))   # 12 triangles
    (tmp_path / "meshes" / "box.stl").write_bytes(trimesh.exchange.stl.export_stl(box))
    out = mjcf_meshes.fit_for_mujoco({"package://x/box.stl": "meshes/box.stl"}, tmp_path, set())
    assert out == {"package://x/box.stl": "meshes/box.obj"} and not (tmp_path / "meshes" / "box.stl").exists()
    xml = (f'<mujoco><asset><mesh name="b" file="{out["package://x/box.stl"]}"/></asset>'
           '<worldbody><geom type="mesh" mesh="b"/></worldbody></mujoco>')
    (tmp_path / "m.xml").write_text(xml)
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "m.xml"))
    assert model.mesh_facenum[0] == 12


def test_batch_keeps_each_robots_meshes_apart(tmp_path):
    """UR3 and UR5 both name their meshes base.stl, shoulder.stl...: in one output folder each model
    gets its own mesh folder, so neither is drawn with the other's meshes."""
    import re

    from test_urdf import robot_file

    files = [robot_file("ur_description/urdf/ur3_robot.urdf"), robot_file("ur_description/urdf/ur5_robot.urdf")]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["convert", *files, "--tip-link", "tool0", "--to", "mjcf", "-o", str(tmp_path / "out")]) == 0
    for src in files:
        stem = src.rsplit("/", 1)[1].removesuffix(".urdf")
        text = (tmp_path / "out" / f"{stem}.xml").read_text()
        written = re.findall(r'<mesh name="[^"]*" file="([^"]*)"', text)
        assert written and all(f.startswith(f"meshes/{stem}/") for f in written)
        # one file per mesh of this robot, in its own folder
        assert sorted(p.name for p in (tmp_path / "out" / "meshes" / stem).iterdir()) == \
            sorted(f.rsplit("/", 1)[1] for f in written)
    a, b = (tmp_path / "out" / "meshes" / "ur3_robot"), (tmp_path / "out" / "meshes" / "ur5_robot")
    common = {p.name for p in a.iterdir()} & {p.name for p in b.iterdir()}
    assert common and all((a / n).read_bytes() != (b / n).read_bytes() for n in common)


def test_python_write_mjcf_takes_the_meshes_along(tmp_path):
    """robkin.io.mjcf.files.write_mjcf: the Python form of convert --to mjcf -o (meshes copied beside)."""
    from robkin.io import load
    from robkin.io.mjcf.files import write_mjcf
    from test_urdf import robot_file

    src = robot_file("so_arm_description/urdf/so100.urdf")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = load(src)
        path = write_mjcf(robot, tmp_path / "so100.xml", source=src, actuators="position")
    model = mujoco.MjModel.from_xml_path(str(path))
    assert model.nmesh > 0 and all((tmp_path / "meshes").iterdir())
    # the rule's gains (robkin.simulation.servos): the shoulder pan's kp = I (2 pi 5 Hz)^2 (no friction)
    from robkin.simulation import servo_plan

    assert model.nu == robot.n and model.actuator_gainprm[0, 0] == servo_plan(robot)["shoulder_pan"].kp


def test_collada_visual_is_drawn_in_its_own_colours(tmp_path):
    """UR5's shoulder.dae holds three materials (grey, black, blue cap): three STL parts with those
    colours, together the very triangles of the single converted mesh."""
    pytest.importorskip("trimesh")
    from robkin.io.meshes.files import copy_meshes, resolve_meshes
    from robkin.io.mjcf.mesh_parts import visual_mesh_parts
    from robkin.io import load
    from test_urdf import robot_file

    src = robot_file("ur_description/urdf/ur5_robot.urdf")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = load(src, tip_link="tool0")
        resolved = {k: m for k, m in resolve_meshes(robot, src).items() if k.endswith("visual/shoulder.dae")}
    (name, mesh), = resolved.items()
    single = copy_meshes(resolved, tmp_path / "one")[name]
    parts = visual_mesh_parts({name: mesh.path}, tmp_path / "parts", "meshes")[name]
    colours = {rgba for _, rgba in parts}
    assert len(parts) == 3 == len(colours) and any(b > r + 0.1 for r, g, b, a in colours)   # a blue cap
    model = lambda files: mujoco.MjModel.from_xml_string(   # noqa: E731
        "<mujoco><asset>" + "".join(f'<mesh name="m{k}" file="{f}"/>' for k, f in enumerate(files))
        + "</asset><worldbody>" + "".join(f'<geom type="mesh" mesh="m{k}"/>' for k in range(len(files)))
        + "</worldbody></mujoco>")
    one = model([str(tmp_path / "one" / single)])
    split = model([str(tmp_path / "parts" / f) for f, _ in parts])
    assert split.mesh_facenum.sum() == one.mesh_facenum.sum()


def test_a_primitive_of_size_zero_is_left_out_with_a_warning():
    """pybullet's Laikago has visual spheres of radius 0: MuJoCo refuses the whole model for one
    ("size 0 must be positive in geom"), so the writer leaves such shapes out and says which."""
    urdf = """<robot name="r">
      <link name="base"><visual><geometry><sphere radius="0"/></geometry></visual>
        <inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <link name="arm"><visual><geometry><box size="0.1 0.1 0.4"/></geometry></visual>
        <collision><geometry><cylinder radius="0.0" length="0.3"/></geometry></collision>
        <inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <joint name="j" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
        <limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
    </robot>"""
    robot = robot_from_urdf(urdf)
    with pytest.warns(UserWarning, match=r"2 shape\(s\) of size zero left out of the MJCF .*base: visual sphere"):
        xml = mjcf_from_robot(robot)
    model = mujoco.MjModel.from_xml_string(xml)   # loads: the zero-size shapes are gone
    assert model.ngeom == 1 and model.geom_type[0] == mujoco.mjtGeom.mjGEOM_BOX
