"""Mesh files a robot file names: found like ROS and Gazebo find them, refused when hostile, said once
when outside the model's folder, copied (and converted for MuJoCo) beside an output."""

from __future__ import annotations

import builtins
import glob
import io
import os
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import robkin
from robkin.cli import main
from robkin.io.meshes.files import (MeshFile, copy_meshes, missing_line, parse_package_path, resolve_mesh_file,
                                    resolve_meshes)

ROBOTS_DIR = (glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                     "example-robot-data", "robots")) or [""])[0]
UR5 = Path(ROBOTS_DIR) / "ur_description" / "urdf" / "ur5_robot.urdf"
STL = b"solid x\nendsolid x\n"
#: a tetrahedron as ASCII STL (vertices (0,0,0) (0.1,0,0) (0,0.1,0) (0,0,0.1))
TET_STL = "solid t\n" + "".join(
    f"facet normal 0 0 0\nouter loop\n{''.join(f'vertex {v}' + chr(10) for v in tri)}endloop\nendfacet\n"
    for tri in (("0 0 0", "0 0.1 0", "0.1 0 0"), ("0 0 0", "0.1 0 0", "0 0 0.1"), ("0 0 0", "0 0 0.1", "0 0.1 0"),
                ("0.1 0 0", "0 0.1 0", "0 0 0.1"))) + "endsolid t\n"
#: a tetrahedron in millimetres (COLLADA unit 0.001 m), vertices (0,0,0) (100,0,0) (0,200,0) (0,0,300)
TET_DAE = """<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="millimeter" meter="0.001"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries><geometry id="tet"><mesh>
    <source id="p"><float_array id="pa" count="12">0 0 0 100 0 0 0 200 0 0 0 300</float_array>
      <technique_common><accessor source="#pa" count="4" stride="3"><param name="X" type="float"/>
        <param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
    <triangles count="4"><input semantic="VERTEX" source="#v" offset="0"/><p>0 2 1 0 1 3 0 3 2 1 2 3</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s"><node id="n"><instance_geometry url="#tet"/></node></visual_scene>
  </library_visual_scenes><scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
"""


def _urdf(*meshes: str, visuals_per_mesh: int = 1) -> str:
    links, joints = ['<link name="base"/>'], []
    for k, name in enumerate(m for m in meshes for _ in range(visuals_per_mesh)):
        links.append(f'<link name="l{k}"><visual><geometry><mesh filename="{name}"/></geometry></visual></link>')
        joints.append(f'<joint name="j{k}" type="revolute"><parent link="{"base" if k == 0 else f"l{k - 1}"}"/>'
                      f'<child link="l{k}"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>'
                      f'<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>')
    return f'<robot name="r">{"".join(links)}{"".join(joints)}</robot>'


@pytest.fixture()
def package(tmp_path):
    """ws/my_robot/{meshes/link.stl, urdf/}: a ROS package in a workspace."""
    pkg = tmp_path / "ws" / "my_robot"
    (pkg / "meshes").mkdir(parents=True)
    (pkg / "urdf").mkdir()
    (pkg / "meshes" / "link.stl").write_bytes(STL)
    return pkg


def test_mesh_files_resolve_like_ros_and_gazebo(package, tmp_path, monkeypatch):
    for var in ("ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH", "GAZEBO_MODEL_PATH", "GZ_SIM_RESOURCE_PATH"):
        monkeypatch.delenv(var, raising=False)
    stl = (package / "meshes" / "link.stl").resolve()
    robot_file = package / "urdf" / "r.urdf"
    for name in ("package://my_robot/meshes/link.stl", "../meshes/link.stl", f"file://{stl}", str(stl),
                 "..\\meshes\\link.stl", "package://my_robot/./urdf/../meshes/link.stl",
                 "package:///my_robot/meshes/link.stl"):  # three slashes: example-robot-data's Talos
        assert resolve_mesh_file(name, robot_file) == MeshFile(name, stl, None), name
    elsewhere = tmp_path / "other" / "r.urdf"
    missing = resolve_mesh_file("package://my_robot/meshes/link.stl", elsewhere)
    assert missing.path is None and "package 'my_robot' not found" in missing.reason
    assert "--package-path my_robot=DIR" in missing.reason
    assert resolve_mesh_file("package://my_robot/meshes/link.stl", elsewhere, {"my_robot": package}).path == stl
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(tmp_path / "ws"))
    assert resolve_mesh_file("package://my_robot/meshes/link.stl", elsewhere).path == stl
    monkeypatch.delenv("ROS_PACKAGE_PATH")
    share = tmp_path / "install" / "share"
    share.mkdir(parents=True)
    (share / "my_robot").symlink_to(package)  # colcon --symlink-install
    monkeypatch.setenv("AMENT_PREFIX_PATH", str(tmp_path / "install"))
    assert resolve_mesh_file("package://my_robot/meshes/link.stl", elsewhere).path == stl
    monkeypatch.setenv("GAZEBO_MODEL_PATH", str(tmp_path / "ws"))
    assert resolve_mesh_file("model://my_robot/meshes/link.stl", elsewhere).path == stl
    gone = resolve_mesh_file("package://my_robot/meshes/nothere.stl", robot_file)
    assert gone.path is None and gone.reason.startswith("not in package 'my_robot' (no such file")


@pytest.mark.parametrize("name, reason", [
    ("package://../../etc/passwd", "not a mesh file type"),
    ("package://../etc/passwd.stl", "'..' is not a package name"),
    ("package://my_robot/../../../etc/passwd.stl", "leads outside package 'my_robot'"),
    ("package://my_robot/meshes/../../../secret.stl", "leads outside package 'my_robot'"),
    ("model://my_robot/../x.stl", "leads outside model 'my_robot'"),
    ("/etc/passwd", "not a mesh file type"),
    ("file:///etc/shadow", "not a mesh file type"),
    ("file://evil.example/x.stl", "names another machine"),
    ("http://evil.example/x.stl", "nothing is fetched"),
    ("https://evil.example/x.stl", "nothing is fetched"),
    ("ftp://evil.example/x.stl", "nothing is fetched"),
    ("passwd.stl", "leads to passwd, not a mesh file"),           # a symbolic link to a non-mesh file
    ("folder.stl", "is not a regular file"),
    ("big.stl", "larger than 64 MB"),
    ("", "no file name"),
    ("x" * 5000 + ".stl", "longer than 4096 characters"),
    ("package://my_robot/", "not a mesh file type"),
    ("package:///../x.stl", "'..' is not a package name"),
    ("a\x00b.stl", "cannot be used (ValueError)"),
    ("package://my_robot/meshes/link%00.stl", "cannot be used (ValueError)"),
    ("%2e%2e/%2e%2e/x.stl", "no such file"),  # a plain path is not URL-decoded: no file of that name
    ("package:///my_robot/../../x.stl", "leads outside package 'my_robot'"),
])
def test_hostile_mesh_names_are_refused_with_a_reason(package, monkeypatch, name, reason):
    robot_file = package / "urdf" / "r.urdf"
    (package / "urdf" / "passwd.stl").symlink_to("/etc/passwd")
    (package / "urdf" / "folder.stl").mkdir()
    with open(package / "urdf" / "big.stl", "wb") as f:  # sparse: no disk used
        f.truncate(64 * 1024 * 1024 + 1)
    found = resolve_mesh_file(name, robot_file)
    assert found.path is None and reason in found.reason and "\n" not in found.reason


def test_resolving_opens_no_file(package, monkeypatch):
    """Names and sizes only: a robot file cannot make resolution read anything."""
    robot_file = package / "urdf" / "r.urdf"
    robot_file.write_text(_urdf("package://my_robot/meshes/link.stl", "../meshes/link.stl", "/etc/passwd"))
    robot = robkin.load(robot_file)

    def refuse(*args, **kwargs):
        raise AssertionError(f"opened {args[:1]}")

    monkeypatch.setattr(builtins, "open", refuse)
    monkeypatch.setattr(os, "open", refuse)
    monkeypatch.setattr(io, "open", refuse)
    with pytest.warns(UserWarning, match="1 mesh file.s. outside the model's folder"):
        found = resolve_meshes(robot, robot_file)
    monkeypatch.undo()
    assert [m.path is not None for m in found.values()] == [True, True, False]


def test_files_outside_the_folder_are_said_once_for_all_shapes(tmp_path):
    """28 visuals naming 4 files outside the model's folder: one warning line, not 28."""
    (tmp_path / "meshes").mkdir()
    names = []
    for k in range(4):
        (tmp_path / "meshes" / f"f{k}.stl").write_bytes(STL)
        names.append(f"../meshes/f{k}.stl")
    (tmp_path / "model").mkdir()
    path = tmp_path / "model" / "hand.urdf"
    path.write_text(_urdf(*names, visuals_per_mesh=7))
    robot = robkin.load(path)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert len(robot.bodies.visuals()) == 28
        found = resolve_meshes(robot, path)
    assert len(found) == 4 and all(m.path is not None for m in found.values())
    (line,) = [str(w.message) for w in caught]
    assert ": 4 mesh file(s) outside the model's folder are used: ../meshes/f0.stl, ../meshes/f1.stl and 2 more" \
        in line


def test_missing_line_groups_reasons(tmp_path):
    path = tmp_path / "r.urdf"
    path.write_text(_urdf("package://nowhere/a.stl", "package://nowhere/b.stl", "c.stl", "http://x/d.stl"))
    found = resolve_meshes(robkin.load(path), path)
    line = missing_line(found, "r.urdf")
    assert line.startswith("r.urdf: 4 of 4 mesh files not found, drawn without them: package://nowhere/a.stl and "
                           "1 more: package 'nowhere' not found")
    assert "c.stl: no such file" in line and "http://x/d.stl: a http:// address" in line and "\n" not in line
    assert missing_line({}, "r.urdf") is None


def test_package_path_option():
    with pytest.raises(ValueError, match="is not NAME=DIR"):
        parse_package_path("nodir")
    with pytest.raises(ValueError, match="is not NAME=DIR"):
        parse_package_path("../x=/tmp")
    with pytest.raises(ValueError, match="is not a folder"):
        parse_package_path("pkg=/nonexistent/folder")
    assert parse_package_path(" pkg =/tmp") == ("pkg", Path("/tmp"))


def test_package_path_bad_value_exits_2(capsys, tmp_path):
    assert _exit(["plot", str(tmp_path / "r.urdf"), "--package-path", "x", "-o", str(tmp_path / "r.html")]) == 2
    err = capsys.readouterr().err
    assert "--package-path: 'x' is not NAME=DIR" in err and "Traceback" not in err


def _exit(argv):
    try:
        return main(argv)
    except SystemExit as exc:
        return exc.code


def test_copy_meshes_unique_names_and_never_overwrites_the_model(tmp_path):
    (tmp_path / "meshes" / "visual").mkdir(parents=True)
    (tmp_path / "meshes" / "base.stl").write_bytes(b"solid collision\nendsolid\n")
    (tmp_path / "meshes" / "visual" / "base.stl").write_bytes(b"solid visual\nendsolid\n")
    (tmp_path / "meshes" / "base_2.stl").write_bytes(b"solid other\nendsolid\n")
    path = tmp_path / "r.urdf"
    path.write_text(_urdf("meshes/base.stl", "meshes/visual/base.stl", "meshes/base_2.stl", "./meshes/base.stl",
                          "meshes/none.stl"))
    found = resolve_meshes(robkin.load(path), path)
    elsewhere = copy_meshes(found, tmp_path / "out")
    assert elsewhere == {"meshes/base.stl": "meshes/base.stl", "meshes/visual/base.stl": "meshes/base_2.stl",
                         "meshes/base_2.stl": "meshes/base_2_2.stl", "./meshes/base.stl": "meshes/base.stl"}
    for source, copied in elsewhere.items():
        assert (tmp_path / "out" / copied).read_bytes() == found[source].path.read_bytes()
    # the output beside the model: its own files stay as they are and are used in place
    before = {p: p.read_bytes() for p in (tmp_path / "meshes").rglob("*.stl")}
    here = copy_meshes(found, tmp_path)
    assert {p: p.read_bytes() for p in before} == before
    assert here["meshes/base.stl"] == "meshes/base.stl" and here["meshes/base_2.stl"] == "meshes/base_2.stl"
    assert (tmp_path / here["meshes/visual/base.stl"]).read_bytes() == b"solid visual\nendsolid\n"


def test_collada_is_converted_for_mujoco_with_its_unit(tmp_path):
    mujoco = pytest.importorskip("mujoco")
    pytest.importorskip("trimesh")
    pytest.importorskip("collada")
    (tmp_path / "tet.dae").write_text(TET_DAE)
    path = tmp_path / "r.urdf"
    path.write_text(_urdf("tet.dae"))
    copied = copy_meshes(resolve_meshes(robkin.load(path), path), tmp_path / "out")
    assert copied == {"tet.dae": "meshes/tet.stl"}
    xml = ('<mujoco><compiler meshdir="meshes"/><asset><mesh name="t" file="tet.stl"/></asset><worldbody>'
           '<body name="b"><geom type="mesh" mesh="t" density="1000"/></body></worldbody></mujoco>')
    (tmp_path / "out" / "m.xml").write_text(xml)
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "out" / "m.xml"))
    # volume 0.1 * 0.2 * 0.3 / 6 m^3 at 1000 kg/m^3: 1 kg (read in millimetres it would be 1e9 kg)
    assert model.nmeshvert == 4 and model.body_mass[1] == pytest.approx(1.0, rel=1e-5)


def test_without_trimesh_unreadable_formats_are_skipped_in_one_line(tmp_path, monkeypatch):
    (tmp_path / "a.dae").write_text(TET_DAE)
    (tmp_path / "b.dae").write_text(TET_DAE)
    (tmp_path / "c.stl").write_bytes(STL)
    path = tmp_path / "r.urdf"
    path.write_text(_urdf("a.dae", "b.dae", "c.stl"))
    found = resolve_meshes(robkin.load(path), path)
    monkeypatch.setitem(sys.modules, "trimesh", None)
    with pytest.warns(UserWarning) as record:
        copied = copy_meshes(found, tmp_path / "out")
    assert copied == {"c.stl": "meshes/c.stl"}
    (line,) = [str(w.message) for w in record]
    assert line.startswith("2 mesh file(s) left out: a.dae (converting .dae needs trimesh: pip install "
                           "'robkin[meshes]'); b.dae")
    assert copy_meshes(found, tmp_path / "urdf_out", readable=None) == {"a.dae": "meshes/a.dae",
                                                                       "b.dae": "meshes/b.dae", "c.stl": "meshes/c.stl"}


def test_a_broken_collada_file_is_named_not_fatal(tmp_path):
    pytest.importorskip("trimesh")
    (tmp_path / "bad.dae").write_text("<COLLADA><not-closed>")
    path = tmp_path / "r.urdf"
    path.write_text(_urdf("bad.dae"))
    with pytest.warns(UserWarning, match=r"1 mesh file\(s\) left out: bad.dae \(cannot be converted"):
        assert copy_meshes(resolve_meshes(robkin.load(path), path), tmp_path / "out") == {}


@pytest.mark.skipif(not UR5.is_file(), reason="example-robot-data is not installed")
def test_ur5_meshes_travel(tmp_path):
    """example-robot-data's UR5: 7 COLLADA visuals and 7 STL collisions, found through the package
    folder above the file; copied so that MuJoCo loads every one of them from the output folder."""
    mujoco = pytest.importorskip("mujoco")
    pytest.importorskip("trimesh")
    robot = robkin.load(UR5, tip_link="tool0")
    found = resolve_meshes(robot, UR5)
    assert len(found) == 14 and all(m.path is not None for m in found.values())
    copied = copy_meshes(found, tmp_path)
    assert sorted(copied.values()) == sorted({f"meshes/{n}{s}.stl" for n in ("base", "shoulder", "upperarm",
                                                                          "forearm", "wrist1", "wrist2", "wrist3")
                                              for s in ("", "_2")})
    assets = "".join(f'<mesh name="m{k}" file="{f}"/>' for k, f in enumerate(sorted(set(copied.values()))))
    geoms = "".join(f'<geom type="mesh" mesh="m{k}"/>' for k in range(14))
    (tmp_path / "m.xml").write_text(f"<mujoco><asset>{assets}</asset><worldbody>{geoms}</worldbody></mujoco>")
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "m.xml"))
    assert model.nmesh == 14
    # the converted visual of the upper arm spans what its collision mesh spans (to 5 mm: two meshes)
    import trimesh

    visual, collision = (trimesh.load(tmp_path / f"meshes/upperarm{s}.stl") for s in ("", "_2"))
    assert copied[next(n for n in copied if n.endswith("visual/upperarm.dae"))] == "meshes/upperarm.stl"
    assert visual.bounds == pytest.approx(collision.bounds, abs=5e-3)


def test_collada_cannot_pull_other_files_in(tmp_path):
    """An external entity is never expanded (its numbers would make a mesh), and a texture the file
    names is not needed: the geometry converts without it."""
    pytest.importorskip("trimesh")
    (tmp_path / "secret.txt").write_text("0 0 0 100 0 0 0 200 0 0 0 300")
    xxe = TET_DAE.replace('<?xml version="1.0" encoding="utf-8"?>',
                          '<?xml version="1.0"?><!DOCTYPE COLLADA [<!ENTITY xxe SYSTEM "secret.txt">]>') \
        .replace(">0 0 0 100 0 0 0 200 0 0 0 300<", ">&xxe;<")
    (tmp_path / "xxe.dae").write_text(xxe)
    textured = TET_DAE.replace("<library_geometries>", '<library_images><image id="i"><init_from>/etc/passwd'
                               '</init_from></image></library_images><library_geometries>')
    (tmp_path / "tex.dae").write_text(textured)
    path = tmp_path / "r.urdf"
    path.write_text(_urdf("xxe.dae", "tex.dae"))
    with pytest.warns(UserWarning, match=r"1 mesh file\(s\) left out: xxe.dae \(cannot be converted"):
        copied = copy_meshes(resolve_meshes(robkin.load(path), path), tmp_path / "out")
    assert copied == {"tex.dae": "meshes/tex.stl"}


@pytest.mark.parametrize("rel", ["talos_data/robots/talos_full_v2.urdf", "allegro_hand_description/urdf/"
                                 "allegro_right_hand.urdf", "g1_description/urdf/g1_29dof_with_hand_rev_1_0.urdf",
                                 "so_arm_description/urdf/so100.urdf", "panda_description/urdf/panda.urdf"])
def test_every_mesh_of_real_robots_is_found(rel):
    """example-robot-data as installed: every mesh found through the package folder above the file
    (Talos writes package:///example-robot-data/..., with three slashes)."""
    from robkin.io.urdf import parse_urdf
    from robkin.io.urdf.chain import chains_of

    path = Path(ROBOTS_DIR) / rel
    if not path.is_file():
        pytest.skip(f"example-robot-data's {rel} is not installed")
    base, tip, _ = chains_of(parse_urdf(path))[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the files' own oddities (projected axes, equal limits)
        robot = robkin.load(path, base_link=base, tip_link=tip)
    found = resolve_meshes(robot, path)
    assert len(found) >= 7 and [m for m in found.values() if m.path is None] == []
    assert all(m.path.is_relative_to(Path(ROBOTS_DIR).resolve().parent) for m in found.values())


def test_convert_to_urdf_takes_relative_meshes_along(tmp_path):
    """An MJCF's meshes (relative to its meshdir) travel with a URDF written elsewhere: copied beside
    it and named relative to it, so that yourdfpy loads every one from a moved copy of the folder;
    package:// names are kept as written."""
    yourdfpy = pytest.importorskip("yourdfpy")
    import shutil

    src = tmp_path / "model"
    (src / "assets").mkdir(parents=True)
    (src / "assets" / "tet.dae").write_text(TET_DAE)
    (src / "assets" / "link.stl").write_text(TET_STL)
    (src / "m.xml").write_text(
        '<mujoco model="m"><compiler meshdir="assets" angle="radian"/><asset><mesh name="a" file="tet.dae"/>'
        '<mesh name="b" file="link.stl"/></asset><worldbody><body name="b1"><joint name="j1" axis="0 0 1"/>'
        '<geom type="mesh" mesh="a" contype="0" conaffinity="0"/><body name="b2" pos="0 0 0.5">'
        '<joint name="j2" axis="0 1 0"/><geom type="mesh" mesh="b" pos="0 0 0.1" contype="0" conaffinity="0"/>'
        '<site name="tip" pos="0 0 0.3"/></body></body></worldbody></mujoco>')
    out = tmp_path / "out"
    out.mkdir()
    assert main(["convert", str(src / "m.xml"), "--tip-link", "tip", "--to", "urdf", "-o", str(out / "m.urdf")]) == 0
    text = (out / "m.urdf").read_text()
    assert 'filename="meshes/tet.dae"' in text and 'filename="meshes/link.stl"' in text
    moved = shutil.move(str(out), str(tmp_path / "elsewhere"))
    shutil.rmtree(src)
    urdf = yourdfpy.URDF.load(str(Path(moved) / "m.urdf"))
    assert sorted(len(g.vertices) for g in urdf.scene.geometry.values()) == [4, 4]  # both tetrahedra
    ur5 = tmp_path / "ur5.urdf"
    if UR5.is_file():
        assert main(["convert", str(UR5), "--tip-link", "tool0", "--to", "urdf", "-o", str(ur5)]) == 0
        assert ur5.read_text().count('filename="package://example-robot-data/') == 14
        assert not (tmp_path / "meshes").exists()
