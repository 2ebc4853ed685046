"""SDF visuals, collisions and inertials as ``Robot.bodies``.

Reference: a hand-written URDF twin (tests/data/sdf/shapes.urdf: the ``relative_to`` poses worked out
by hand into link origins) read by pinocchio, whose ``updateGeometryPlacements`` gives each visual's
and collision's world pose at q; the twin's inertials read by robkin's URDF reader (checked against
pinocchio in test_urdf).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from robkin.bodies import body_motions, shape_poses
from robkin.io import load
from robkin.io.sdf.reader import robot_from_sdf
from test_sdf import DATA

pin = pytest.importorskip("pinocchio")

#: Observed ~3e-16 (a few 4x4 products); the twin's origins are typed with 16 digits (pi/2 to ~1e-16).
POSE_TOL = 1e-12
JOINTS = ["shoulder", "elbow", "wrist"]


def _pin_q(model, q) -> np.ndarray:
    qp = pin.neutral(model)
    for name, v in zip(JOINTS, q):
        joint = model.joints[model.getJointId(name)]
        qp[joint.idx_q:joint.idx_q + joint.nq] = [np.cos(v), np.sin(v)] if joint.nq == 2 else [v]
    return qp


def test_sdf_shapes_match_pinocchio_on_the_urdf_twin():
    robot = load(DATA / "shapes.sdf", tip_link="tcp")
    shapes = robot.bodies.shapes
    assert [(s.name, s.role, s.geometry.kind) for s in shapes] == [
        ("base_vis", "visual", "box"), ("upper_vis", "visual", "sphere"), ("upper_col", "collision", "cylinder"),
        ("fore_vis", "visual", "cylinder"), ("hand_vis", "visual", "box")]  # the ellipsoid is skipped
    assert [s.body for s in shapes] == [0, 1, 1, 2, 3]
    colours = {s.name: s.material.rgba for s in robot.bodies.visuals() if s.material}
    assert colours == {"upper_vis": (0.0, 0.0, 1.0, 1.0), "fore_vis": (1.0, 0.0, 0.0, 1.0)}
    urdf = str(DATA / "shapes.urdf")
    model = pin.buildModelFromUrdf(urdf)
    data = model.createData()
    geoms = {role: pin.buildGeomFromUrdf(model, urdf, kind) for role, kind in
             (("visual", pin.GeometryType.VISUAL), ("collision", pin.GeometryType.COLLISION))}
    index = {}  # pinocchio names a link's k-th visual (collision) LINK_k
    for s in shapes:
        k = sum(1 for t in shapes if t.link == s.link and t.role == s.role and t is not s and
                shapes.index(t) < shapes.index(s))
        index[s] = geoms[s.role].getGeometryId(f"{s.link}_{k}")
    for q in np.random.default_rng(11).uniform(-1, 1, (8, robot.n)):
        P = robot.world @ shape_poses(robot, q)
        for role, gm in geoms.items():
            gd = pin.GeometryData(gm)
            pin.forwardKinematics(model, data, _pin_q(model, q))
            pin.updateGeometryPlacements(model, data, gm, gd)
            for s, T in zip(shapes, P):
                if s.role == role:
                    np.testing.assert_allclose(T, gd.oMg[index[s]].homogeneous, atol=POSE_TOL, rtol=0,
                                               err_msg=s.name)


def test_sdf_inertials_match_the_urdf_twin():
    robot = load(DATA / "shapes.sdf", tip_link="tcp")
    twin = load(DATA / "shapes.urdf", tip_link="tcp")
    (a,), (b,) = robot.bodies.inertials, twin.bodies.inertials
    assert (a.link, a.body, a.mass) == (b.link, b.body, b.mass) == ("base", 0, 3.0)
    np.testing.assert_array_equal(a.inertia, b.inertia)
    q = np.array([0.3, -0.2, 0.05])
    np.testing.assert_allclose(robot.world @ body_motions(robot, q)[0] @ a.pose,
                               twin.world @ body_motions(twin, q)[0] @ b.pose, atol=POSE_TOL)


def test_sdf_inertia_defaults_are_sdformats():
    """SDFormat's defaults: mass 1 and the identity inertia, each element on its own and <inertia> absent."""
    text = ('<sdf version="1.9"><model name="m"><link name="a"><inertial><inertia><ixy>0.5</ixy><iyy>2</iyy></inertia>'
            '</inertial></link><link name="b"><inertial><mass>4</mass></inertial></link><joint name="j" '
            'type="revolute"><parent>a</parent><child>b</child><axis><xyz>0 0 1</xyz></axis></joint></model></sdf>')
    a, b = robot_from_sdf(text).bodies.inertials
    assert (a.mass, b.mass) == (1.0, 4.0)
    np.testing.assert_array_equal(a.inertia, [[1, 0.5, 0], [0.5, 2, 0], [0, 0, 1]])
    np.testing.assert_array_equal(b.inertia, np.eye(3))


def _mesh_sdf(uri: str) -> str:
    return (f'<sdf version="1.9"><model name="m"><link name="a"/><link name="b"><visual name="v"><geometry>'
            f'<mesh><uri>{uri}</uri><scale>1 2 3</scale></mesh></geometry></visual></link>'
            f'<joint name="j" type="revolute"><parent>a</parent><child>b</child><axis><xyz>0 0 1</xyz></axis>'
            f'</joint></model></sdf>')


@pytest.mark.parametrize("uri", ["model://m/meshes/b.dae", "meshes/b.stl", "package://pkg/b.stl"])
def test_mesh_uris_are_kept(tmp_path, uri):
    path = tmp_path / "m.sdf"
    path.write_text(_mesh_sdf(uri))
    (v,) = robot_from_sdf(path).bodies.visuals()
    assert v.geometry.filename == uri and v.geometry.size == (1.0, 2.0, 3.0)


@pytest.mark.parametrize("uri", ["../outside/b.stl", "OUT/b.stl", "file://OUT/b.stl", "meshes/../../outside/b.stl"])
def test_mesh_uris_outside_the_folder_are_kept_and_said_once(tmp_path, uri):
    from robkin.io.meshes.files import resolve_meshes

    (tmp_path / "outside").mkdir()
    (tmp_path / "outside" / "b.stl").write_bytes(b"solid b\nendsolid b\n")
    (tmp_path / "model").mkdir()
    uri = uri.replace("OUT", str(tmp_path / "outside"))
    path = tmp_path / "model" / "m.sdf"
    path.write_text(_mesh_sdf(uri))
    robot = robot_from_sdf(path)
    (v,) = robot.bodies.visuals()
    assert v.geometry.filename == uri
    with pytest.warns(UserWarning, match=r"m.sdf: 1 mesh file\(s\) outside the model's folder are used: "):
        found = resolve_meshes(robot, path)
    assert found[uri].path == (tmp_path / "outside" / "b.stl").resolve()


def test_gui_serves_sdf_model_meshes(tmp_path):
    from robkin.viz.meshes import MeshRegistry

    folder = tmp_path / "models" / "m"
    (folder / "meshes").mkdir(parents=True)
    (folder / "meshes" / "b.stl").write_bytes(b"solid b\nendsolid b\n")
    path = folder / "model.sdf"
    path.write_text(_mesh_sdf("model://m/meshes/b.stl"))
    reg = MeshRegistry.of(robot_from_sdf(path), path)
    assert reg.missing == [] and [v["mesh"] for v in reg.visuals] == ["m0"]
    assert reg.read("m0") == (b"solid b\nendsolid b\n", "model/stl")
    assert Path(reg.files["m0"]).parent == (folder / "meshes").resolve()
