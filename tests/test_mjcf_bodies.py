"""MJCF geoms and inertials as ``Robot.bodies``, checked by MuJoCo itself.

Reference: MuJoCo's compiler and ``mj_kinematics`` on the same file. A shape's world pose at q must be
the geom's ``geom_xpos``/``geom_xmat`` (for a mesh, MuJoCo's geom frame sits at the mesh's centre of
mass, ``mesh_pos``/``mesh_quat`` in the file's coordinates, which the test undoes), its size MuJoCo's
``geom_size``, and an inertial's world centre of mass and tensor MuJoCo's ``xipos``/``ximat`` with
``body_inertia``.
"""

from __future__ import annotations

import re
import shutil
import warnings
from pathlib import Path

import numpy as np
import pytest

from robkin.bodies import body_motions, shape_poses
from robkin.io import load
from robkin.io.mjcf.reader import robot_from_mjcf
from robkin.io.urdf import urdf_from_robot
from test_urdf import robot_file

mujoco = pytest.importorskip("mujoco")

#: Same promise as the kinematics (test_mjcf_read.FK_TOL): observed ~1e-15, products of a few
#: 4x4 matrices at ~1 m; anything modelled wrong is off by far more.
POSE_TOL = 1e-9

#: An off-centre tetrahedron (MuJoCo moves its geom frame to the centre of mass: the test undoes it).
TETRA_OBJ = "v 0.1 0.2 0.3\nv 0.5 0.2 0.3\nv 0.1 0.7 0.3\nv 0.1 0.2 0.9\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"

HAND_WRITTEN = """<mujoco model="shapes">
<compiler angle="radian" meshdir="assets" boundmass="0.1" boundinertia="0.01"/>
<asset><mesh name="tet" file="tet.obj" scale="1 2 0.5"/><material name="red" rgba="1 0 0 1"/></asset>
<default><geom contype="1"/>
  <default class="visual"><geom group="2" contype="0" conaffinity="0"/></default>
  <default class="collision"><geom group="3"/></default></default>
<worldbody>
 <geom name="floor" type="plane" size="1 1 0.1"/>
 <geom name="pedestal" type="cylinder" size="0.1 0.05" pos="0 0 -0.05" class="visual"/>
 <body name="b1" pos="0.1 0.2 0.3" euler="0.1 0.2 0.3">
  <joint name="j1" pos="0.05 0 0.1" axis="0 1 1"/>
  <geom name="g_box" type="box" size="0.1 0.2 0.3" pos="0.1 0 0" quat="1 0.2 0.3 0.4" material="red"/>
  <geom name="g_cyl" type="cylinder" fromto="0 0 0 0.3 0.2 0.1" size="0.05" class="visual"/>
  <frame pos="0 0.1 0" axisangle="1 0 0 0.5">
   <geom name="g_cap" type="capsule" size="0.04 0.2" xyaxes="0 1 0 -1 0 0" class="collision"/>
  </frame>
  <inertial pos="0.01 0.02 0.03" quat="0.9 0.1 0.2 0.3" mass="2" diaginertia="0.2 0.25 0.3"/>
  <body name="b2" pos="0.3 0 0">
   <joint name="j2" type="slide" axis="1 0 0" ref="0.1"/>
   <geom name="g_sph" size="0.05" pos="0 0 0.1" rgba="0 1 0 1"/>
   <geom name="g_mesh" type="mesh" mesh="tet" pos="0.1 0.1 0" zaxis="1 1 0" class="visual"/>
   <geom name="g_cap2" type="capsule" fromto="0 0 0 0 0 -0.2" size="0.03"/>
   <geom name="g_box2" type="box" fromto="0 0 0 0.1 0.1 0.2" size="0.03 0.04"/>
   <inertial pos="0 0 0" mass="1" fullinertia="0.2 0.25 0.3 0.01 0.02 0.03"/>
   <body name="b3" pos="0 0 0.2" zaxis="0 1 0">
    <joint name="j3" pos="0 0.1 0" axis="1 0 0" ref="0.3"/>
    <geom name="g_ell" type="ellipsoid" size="0.1 0.2 0.3"/>
    <geom name="g_sph3" size="0.02" pos="0.1 0 0"/>
    <site name="tip" pos="0 0 0.2"/>
   </body>
  </body>
 </body>
</worldbody></mujoco>"""


def _write(folder: Path, xml: str, name: str = "model.xml") -> Path:
    (folder / "assets").mkdir(exist_ok=True)
    (folder / "assets" / "tet.obj").write_text(TETRA_OBJ)
    path = folder / name
    path.write_text(xml)
    return path


def _mat(quat) -> np.ndarray:
    M = np.zeros(9)
    mujoco.mju_quat2Mat(M, np.asarray(quat, dtype=float))
    return M.reshape(3, 3)


def _set_q(model, data, robot, q) -> None:
    data.qpos[:] = 0.0
    for j, v in zip(robot.joints, q):
        data.qpos[model.jnt_qposadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, j.name)]] = v
    mujoco.mj_kinematics(model, data)


def _geom_world(model, data, g: int) -> np.ndarray:
    """World pose of the frame MuJoCo draws geom g's file or primitive in."""
    G = np.eye(4)
    G[:3, :3], G[:3, 3] = data.geom_xmat[g].reshape(3, 3), data.geom_xpos[g]
    if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH:
        m = model.geom_dataid[g]
        O = np.eye(4)
        O[:3, :3], O[:3, 3] = _mat(model.mesh_quat[m]), model.mesh_pos[m]
        G = G @ np.linalg.inv(O)
    return G


def _mj_size(model, g: int, kind: str) -> tuple[float, ...]:
    """MuJoCo's geom_size in robkin's Geometry.size convention (full boxes, full lengths)."""
    s = model.geom_size[g]
    return {"sphere": (s[0],), "box": tuple(2 * s), "cylinder": (s[0], 2 * s[1]), "capsule": (s[0], 2 * s[1])}[kind]


def test_every_geom_type_matches_mujoco_at_random_q(tmp_path):
    path = _write(tmp_path, HAND_WRITTEN)
    robot = robot_from_mjcf(path, tip_link="tip")
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    shapes = robot.bodies.shapes
    # roles by MuJoCo's flags: class visual -> visual only, class collision (group 3) -> collision only,
    # defaults (group 0, contype 1) -> both; plane and ellipsoid skipped
    roles = {}
    for s in shapes:
        roles.setdefault(s.name, []).append(s.role)
    assert roles == {"pedestal": ["visual"], "g_box": ["visual", "collision"], "g_cyl": ["visual"],
                     "g_cap": ["collision"], "g_sph": ["visual", "collision"], "g_mesh": ["visual"],
                     "g_cap2": ["visual", "collision"], "g_box2": ["visual", "collision"],
                     "g_sph3": ["visual", "collision"]}
    by_name = {s.name: s for s in robot.bodies.visuals()}
    assert by_name["g_box"].material.rgba == (1.0, 0.0, 0.0, 1.0)  # the material's colour
    assert by_name["g_sph"].material.rgba == (0.0, 1.0, 0.0, 1.0)  # the geom's own
    assert by_name["g_mesh"].geometry.filename == "assets/tet.obj"
    assert by_name["g_mesh"].geometry.size == (1.0, 2.0, 0.5)
    assert [s.body for s in shapes if s.role == "visual"] == [0, 1, 1, 2, 2, 2, 2, 3]
    rng = np.random.default_rng(7)
    for q in rng.uniform(-1.5, 1.5, (6, robot.n)):
        _set_q(model, data, robot, q)
        P = robot.world @ shape_poses(robot, q)
        for s, T in zip(shapes, P):
            g = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, s.name)
            err = np.abs(_geom_world(model, data, g) - T).max()
            assert err < POSE_TOL, f"{s.name} ({s.role}) is {err:.3g} off MuJoCo's pose at q = {q}"
            if s.geometry.kind != "mesh":
                np.testing.assert_allclose(s.geometry.size, _mj_size(model, g, s.geometry.kind), rtol=1e-12)


def test_inertials_match_mujoco(tmp_path):
    path = _write(tmp_path, HAND_WRITTEN)
    robot = robot_from_mjcf(path, tip_link="tip")
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    # b3 has no <inertial>: MuJoCo gives it the mass of its geoms (density 1000), and so does robkin
    assert [(i.link, i.body) for i in robot.bodies.inertials] == [("b1", 1), ("b2", 2), ("b3", 3)]
    assert [i.mass for i in robot.bodies.inertials][:2] == [2.0, 1.0]
    for q in np.random.default_rng(8).uniform(-1.5, 1.5, (4, robot.n)):
        _set_q(model, data, robot, q)
        M = body_motions(robot, q)
        for inertial in robot.bodies.inertials:
            b = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, inertial.link)
            T = robot.world @ M[inertial.body] @ inertial.pose
            np.testing.assert_allclose(T[:3, 3], data.xipos[b], atol=POSE_TOL)
            R, Rm = T[:3, :3], data.ximat[b].reshape(3, 3)
            # the same tensor in the world frame (MuJoCo stores it diagonalised, in its principal axes)
            np.testing.assert_allclose(R @ inertial.inertia @ R.T, Rm @ np.diag(model.body_inertia[b]) @ Rm.T,
                                       atol=1e-9)
            assert inertial.mass == pytest.approx(model.body_mass[b], rel=1e-15)


def test_urdf_written_from_mjcf_keeps_the_shapes_where_mujoco_has_them(tmp_path):
    path = _write(tmp_path, HAND_WRITTEN)
    robot = robot_from_mjcf(path, tip_link="tip")
    out = tmp_path / "out.urdf"  # next to the MJCF: the mesh's relative name still finds it
    out.write_text(urdf_from_robot(robot))
    text = out.read_text()
    # g_cap2: URDF has no capsule, so its cylinder (0.2 between the cap centres) and two spheres
    assert '<cylinder radius="0.03" length="0.2"/>' in text and 'name="g_cap2_cap1"' in text
    assert '<material name="rgba 0 1 0 1"><color rgba="0 1 0 1"/></material>' in text  # URDF needs a name
    back = load(out, tip_link="tip")
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    q = np.array([0.4, 0.05, -0.7])
    _set_q(model, data, robot, q)
    for s, T in zip(back.bodies.shapes, back.world @ shape_poses(back, q)):
        g = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, s.name)
        W = _geom_world(model, data, g) if g >= 0 else None
        if g < 0:  # a cap sphere of a capsule: at one end of MuJoCo's capsule, along its z axis
            name, _, k = s.name.rpartition("_cap")
            g = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, name)
            end = np.eye(4)
            end[2, 3] = (-1 if k == "1" else 1) * model.geom_size[g, 1]  # MuJoCo's size: radius, half-length
            W = _geom_world(model, data, g) @ end
        assert np.abs(W - T).max() < POSE_TOL, s.name
    pin = pytest.importorskip("pinocchio")
    geoms = pin.buildGeomFromUrdf(pin.buildModelFromUrdf(str(out)), str(out), pin.GeometryType.VISUAL,
                                  package_dirs=[str(tmp_path)])
    capsules = sum(v.geometry.kind == "capsule" for v in robot.bodies.visuals())
    assert len(robot.bodies.visuals()) == 8 and capsules == 1
    assert len(geoms.geometryObjects) == 8 + 2 * capsules  # none dropped by urdfdom; a capsule is 3 shapes


def _ur5_mjcf(folder: Path) -> Path:
    """MuJoCo's URDF -> MJCF compile of example-robot-data's UR5, its collision meshes in folder/meshes."""
    urdf = Path(robot_file("ur_description/urdf/ur5_robot.urdf"))
    (folder / "meshes").mkdir()
    for stl in (urdf.parent.parent / "meshes" / "ur5" / "collision").glob("*.stl"):
        shutil.copy(stl, folder / "meshes")
    text = re.sub(r"(<robot\b[^>]*>)", r'\1<mujoco><compiler fusestatic="false" discardvisual="true" '
                  r'meshdir="meshes" strippath="true"/></mujoco>', urdf.read_text(), count=1)
    (folder / "ur5.urdf").write_text(text)
    out = folder / "ur5.xml"
    mujoco.mj_saveLastXML(str(out), mujoco.MjModel.from_xml_path(str(folder / "ur5.urdf")))
    return out


def test_mujoco_compiled_arm_meshes_match_mujoco_and_are_served(tmp_path):
    path = _ur5_mjcf(tmp_path)
    robot = load(path, tip_link="tool0")
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    visuals = robot.bodies.visuals()
    # every geom is a visual (group 0), in MuJoCo's order (bodies depth first, geoms in file order)
    assert len(visuals) == model.ngeom
    assert [s.link for s in visuals] == [model.body(model.geom_bodyid[g]).name for g in range(model.ngeom)]
    meshes = [(g, s) for g, s in enumerate(visuals) if s.geometry.kind == "mesh"]
    assert [Path(s.geometry.filename).stem for _, s in meshes] == \
        [model.mesh(model.geom_dataid[g]).name for g, _ in meshes] and len(meshes) == 7
    for q in np.random.default_rng(9).uniform(-np.pi, np.pi, (6, robot.n)):
        _set_q(model, data, robot, q)
        for g, T in enumerate(robot.world @ shape_poses(robot, q, visuals)):
            assert np.abs(_geom_world(model, data, g) - T).max() < POSE_TOL, visuals[g]

    from robkin.viz.meshes import MeshRegistry

    reg = MeshRegistry.of(robot, path)
    assert reg.missing == [] and len(reg.visuals) == model.ngeom and len(reg.files) == 7
    for item in (v for v in reg.visuals if v["kind"] == "mesh"):
        data_bytes, mime = reg.read(item["mesh"])
        assert mime == "model/stl" and data_bytes == reg.files[item["mesh"]].read_bytes()
        assert reg.files[item["mesh"]].parent == (tmp_path / "meshes").resolve()


@pytest.mark.parametrize("meshdir, file, named", [("../outside", "tet.obj", "../outside/tet.obj"),
                                                  ("assets", "../../outside/tet.obj", "assets/../../outside/tet.obj"),
                                                  ("", "OUT/tet.obj", "OUT/tet.obj"), ("OUT", "tet.obj", "OUT/tet.obj"),
                                                  ("link", "tet.obj", "link/tet.obj")])
def test_mesh_files_outside_the_folder_are_kept_and_said_once(tmp_path, meshdir, file, named):
    """MuJoCo loads a mesh anywhere: the reader keeps its name (meshdir joined as MuJoCo joins it);
    finding the files says once, in one line, that files outside the model's folder are used."""
    from robkin.io.meshes.files import resolve_meshes

    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "tet.obj").write_text(TETRA_OBJ)
    inner = tmp_path / "model"
    inner.mkdir()
    (inner / "link").symlink_to(outside)  # a symbolic link leading out counts as outside
    meshdir, file, named = (x.replace("OUT", str(outside)) for x in (meshdir, file, named))
    geoms = "".join(f'<geom name="g{k}" type="mesh" mesh="m"/>' for k in range(5))
    xml = (f'<mujoco><compiler meshdir="{meshdir}"/><asset><mesh name="m" file="{file}"/></asset><worldbody>'
           f'<body name="a"><joint name="j"/>{geoms}<geom name="ok" size="0.1"/></body></worldbody></mujoco>')
    (inner / "m.xml").write_text(xml)
    robot = robot_from_mjcf(inner / "m.xml")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        visuals = robot.bodies.visuals()
        found = resolve_meshes(robot, inner / "m.xml")
    assert [s.name for s in visuals] == [f"g{k}" for k in range(5)] + ["ok"]
    assert visuals[0].geometry.filename == named
    assert found[named].path == (outside / "tet.obj").resolve()
    (line,) = [str(w.message) for w in caught]
    assert line.startswith(f"{str(inner / 'm.xml')[:60]}") and "\n" not in line
    assert ": 1 mesh file(s) outside the model's folder are used: " in line and named[-7:] in line


def test_text_input_keeps_mesh_names_as_joined():
    xml = ('<mujoco><compiler meshdir="meshes"/><asset><mesh file="arm/link1.stl"/><mesh name="x" file="../y.stl"/>'
           '<mesh name="v" vertex="0 0 0 1 0 0 0 1 0 0 0 1"/></asset><worldbody><body name="a"><joint name="j"/>'
           '<geom type="mesh" mesh="link1"/><geom name="out" type="mesh" mesh="x"/><geom type="mesh" mesh="v"/>'
           '</body></worldbody></mujoco>')
    robot = robot_from_mjcf(xml)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        # the mesh given by vertices has no file to draw: skipped without a word
        assert [s.geometry.filename for s in robot.bodies.visuals()] == ["meshes/arm/link1.stl", "meshes/../y.stl"]
    # the only word: text input has no folder to read the mesh files from for the mass MuJoCo would give 'a'
    assert [str(w.message).split(": ", 1)[1][:40] for w in caught] == ["the mass MuJoCo gives 1 body(ies) from t"]


def test_gui_lists_and_serves_the_meshes_of_an_mjcf_file(tmp_path):
    """``robkin gui ur5.xml``: the page's start data lists the visuals, and each mesh is served by its id."""
    import urllib.request

    from robkin.viz.gui import make_server

    path = _ur5_mjcf(tmp_path)
    srv = make_server(port=0, text=path.read_text(), fmt="mjcf", tip_link="tool0", source=str(path))
    srv.serve_in_thread()
    try:
        start = srv.start_payload
        meshes = [v for v in start["visuals"] if v["kind"] == "mesh"]
        assert start["missing_meshes"] == [] and len(meshes) == 7
        assert sorted({v["mesh"] for v in meshes}) == [f"m{i}" for i in range(7)]
        for v in meshes:
            with urllib.request.urlopen(srv.url + "api/mesh/" + v["mesh"], timeout=10) as r:
                assert r.headers["Content-Type"] == "model/stl"
                assert r.read() == srv.meshes.files[v["mesh"]].read_bytes()
    finally:
        srv.shutdown()
        srv.server_close()


@pytest.mark.parametrize("geom, message", [
    ('type="mesh" mesh="nope"', r"geom 'g' \(body 'a'\): mesh 'nope' is not a <mesh> of the <asset>s"),
    ('type="cone"', r"geom 'g' \(body 'a'\): type 'cone' is not one of sphere, box"),
    ('size="1 2 3 4"', r"geom 'g' \(body 'a'\): size: '1 2 3 4' has 4 numbers; expected 1 to 3"),
    ('group="two"', r"geom 'g' \(body 'a'\): group: 'two' is not a whole number"),
    ('size="nan"', r"geom 'g' \(body 'a'\): size"),
])
def test_bad_geoms_are_one_clear_line_from_the_cli(tmp_path, capsys, geom, message):
    from robkin.cli import main

    path = tmp_path / "bad.xml"
    path.write_text(f'<mujoco><worldbody><body name="a"><joint name="j"/><geom name="g" {geom}/></body>'
                    f'</worldbody></mujoco>')
    out = tmp_path / "out.urdf"
    assert main(["convert", str(path), "--to", "urdf", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert re.search(message, err) and len(err.strip().splitlines()) == 1 and not out.exists()
