"""``robkin convert --collision MODE``: every mode gives a model MuJoCo loads, without a penetrating contact
at home, with the collision geometry the mode promises (MuJoCo the oracle: its compiled meshes, its contacts
at home by ``mj_forward``); the options refused with one line."""

from __future__ import annotations

import os
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

from robkin.cli import main
from test_mesh_files import ROBOTS_DIR

mujoco = pytest.importorskip("mujoco")
trimesh = pytest.importorskip("trimesh")

UR5 = Path(ROBOTS_DIR) / "ur_description" / "urdf" / "ur5_robot.urdf"
PANDA = Path(ROBOTS_DIR) / "panda_description" / "urdf" / "panda.urdf"
MODES = ("source", "hull", "primitives", "none")  # decompose: test_collision_geometry (CoACD is slow)


def home(model) -> np.ndarray:
    """q = 0 clipped into each limited hinge or slide joint's range (the definition of home)."""
    q = np.array(model.qpos0)
    for j in range(model.njnt):
        if int(model.jnt_type[j]) in (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE)):
            lo, hi = model.jnt_range[j]
            q[model.jnt_qposadr[j]] = min(max(0.0, lo), hi) if model.jnt_limited[j] else 0.0
    return q


def penetrating(model) -> list[tuple[str, str, float]]:
    """Contacts with a negative distance at home: (body, body, distance)."""
    data = mujoco.MjData(model)
    data.qpos[:] = home(model)
    mujoco.mj_forward(model, data)
    return [(model.body(model.geom_bodyid[c.geom1]).name, model.body(model.geom_bodyid[c.geom2]).name, float(c.dist))
            for c in data.contact[:data.ncon] if c.dist < 0]


def convert(path: Path, out: Path, *options: str, capsys=None) -> tuple[int, str]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rc = main(["convert", str(path), "--to", "mjcf", "-o", str(out), *options])
    return rc, (capsys.readouterr().err if capsys is not None else "")


@pytest.fixture(scope="module", params=MODES)
def ur5(request, tmp_path_factory):
    if not UR5.is_file():
        pytest.skip("example-robot-data not installed")
    out = tmp_path_factory.mktemp(request.param) / "ur5.xml"
    rc, _ = convert(UR5, out, "--collision", request.param, "--tip-link", "tool0")
    assert rc == 0
    return request.param, out, mujoco.MjModel.from_xml_path(str(out))


def collision_geoms(model) -> list[int]:
    return [g for g in range(model.ngeom) if model.geom_contype[g] or model.geom_conaffinity[g]]


def test_every_mode_loads_without_penetration_at_home(ur5):
    mode, _, model = ur5
    assert penetrating(model) == []
    geoms = collision_geoms(model)
    kinds = {int(model.geom_type[g]) for g in geoms}
    mesh = int(mujoco.mjtGeom.mjGEOM_MESH)
    if mode == "none":
        assert geoms == []
    elif mode == "primitives":
        assert geoms and mesh not in kinds
        assert len(geoms) == len({model.geom_bodyid[g] for g in geoms})   # one per link
    else:  # the source's meshes (or their hulls), and its one box (ee_link)
        assert kinds == {mesh, int(mujoco.mjtGeom.mjGEOM_BOX)}


@pytest.mark.parametrize("ur5", ["hull"], indirect=True)
def test_hull_mode_writes_the_hull_mujoco_would_collide(ur5, tmp_path):
    """hull: each collision mesh is the convex hull of its source mesh (same volume as trimesh's hull of
    the source, within float32 rounding of the STL), and far fewer triangles."""
    mode, out, model = ur5
    files = sorted((out.parent / "meshes" / "collision").glob("*.stl"))
    assert len(files) == 7
    for f in files:
        hull = trimesh.load(f)
        source = trimesh.load(UR5.parent.parent / "meshes" / "ur5" / "collision" / f.name.replace("_hull", ""))
        assert hull.is_convex and hull.is_watertight
        assert hull.volume == pytest.approx(source.convex_hull.volume, rel=1e-5)   # float32 vertices
        assert len(hull.faces) <= len(source.faces)


@pytest.fixture(scope="module")
def panda(tmp_path_factory):
    """The Panda with its hand, default export: (path, model, stderr)."""
    if not PANDA.is_file():
        pytest.skip("example-robot-data not installed")
    import contextlib
    import io

    out = tmp_path_factory.mktemp("panda") / "panda.xml"
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        rc, _ = convert(PANDA, out, "--tip-link", "panda_hand_tcp")
    assert rc == 0
    return out, mujoco.MjModel.from_xml_path(str(out)), err.getvalue()


def _assets(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in folder.rglob("*.stl")}


def test_panda_fingers_and_stretched_arm_start_apart(panda):
    """The Panda's fingers touch at rest, and at home (joint 4 clipped to -0.07) link 5 reaches into link 7
    and the hand: those pairs are excluded (the note names them), so MuJoCo starts without penetration;
    without the written excludes, the same model penetrates at home (base/link1 among others: MuJoCo does
    not skip a parent welded to the world)."""
    out, model, err = panda
    assert "panda_leftfinger/panda_rightfinger" in err and "touching at home" in err
    assert penetrating(model) == []
    text = out.read_text()
    start, end = text.index("  <contact>"), text.index("  </contact>") + len("  </contact>")
    bare = mujoco.MjModel.from_xml_string(text[:start] + text[end:], _assets(out.parent))
    pairs = {tuple(sorted(p[:2])) for p in penetrating(bare)}
    assert {("panda_leftfinger", "panda_rightfinger"), ("panda_link5", "panda_link7")} <= pairs
    excluded = {tuple(sorted((model.body(int(s) >> 16).name, model.body(int(s) & 0xFFFF).name)))
                for s in model.exclude_signature}
    assert pairs <= excluded


def test_max_faces_decimates_collision_meshes(tmp_path, capsys):
    if not UR5.is_file():
        pytest.skip("example-robot-data not installed")
    pytest.importorskip("fast_simplification")
    rc, err = convert(UR5, tmp_path / "ur5.xml", "--max-faces", "300", "--tip-link", "tool0", capsys=capsys)
    assert rc == 0 and "above the face budget decimated" in err
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "ur5.xml"))
    faces = [int(model.mesh_facenum[model.geom_dataid[g]]) for g in collision_geoms(model)]
    assert faces and max(faces) <= 300
    assert penetrating(model) == []


@pytest.mark.parametrize("argv, message", [
    (["--collision", "bogus"], "argument --collision: invalid choice: 'bogus'"),
    (["--max-faces", "0"], "argument --max-faces: 0 is not 4 .. 10000000 triangles"),
    (["--max-faces", "many"], "argument --max-faces: 'many' is not a whole number"),
])
def test_bad_values_one_line_exit_2(tmp_path, capsys, argv, message):
    out = tmp_path / "x.xml"
    with pytest.raises(SystemExit) as exc:
        main(["convert", str(UR5), "--to", "mjcf", "-o", str(out), *argv])
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1
    assert not out.exists()


@pytest.mark.parametrize("argv", [["--collision", "hull"], ["--max-faces", "1000"]])
def test_options_need_a_shape_writer(tmp_path, capsys, argv):
    assert main(["convert", str(UR5), "--to", "dh", "-o", str(tmp_path / "x.yaml"), *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert argv[0] in err and "--to mjcf, urdf or usd" in err and len(err.splitlines()) == 1
    assert not list(tmp_path.iterdir())


def test_urdf_output_takes_the_collision_meshes(tmp_path):
    """--to urdf --collision hull: the URDF names the hull files relative to itself; pinocchio loads the
    folder moved elsewhere (relative names looked up in the folder), with the hulls as collision meshes."""
    if not UR5.is_file():
        pytest.skip("example-robot-data not installed")
    made = tmp_path / "made"
    made.mkdir()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["convert", str(UR5), "--to", "urdf", "-o", str(made / "ur5.urdf"), "--collision", "hull",
                     "--tip-link", "tool0"]) == 0
    text = (made / "ur5.urdf").read_text()
    assert text.count('filename="meshes/collision/') == 7
    moved = tmp_path / "moved"
    os.rename(made, moved)
    robot = pytest.importorskip("pinocchio")
    model = robot.buildModelFromUrdf(str(moved / "ur5.urdf"))
    geom = robot.buildGeomFromUrdf(model, str(moved / "ur5.urdf"), robot.GeometryType.COLLISION, None,
                                   [str(moved)])
    assert geom.ngeoms == 8   # 7 hulls and ee_link's box
    assert sum(1 for g in geom.geometryObjects if g.meshPath.endswith("_hull.stl")) == 7


def test_decompose_mode_loads_and_reports_its_fit(tmp_path, capsys, monkeypatch):
    """--collision decompose on the Panda (its collision meshes are nearly convex: CoACD takes about a
    second): MuJoCo loads it without penetration at home; every collision mesh is one of the parts, and the
    fit of each source mesh is printed. A second run takes the parts from the cache."""
    pytest.importorskip("coacd")
    if not PANDA.is_file():
        pytest.skip("example-robot-data not installed")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    for run in ("cold", "cached"):
        out = tmp_path / run / "panda.xml"
        rc, err = convert(PANDA, out, "--tip-link", "panda_hand_tcp", "--collision", "decompose", capsys=capsys)
        assert rc == 0
        assert ("0 from the cache" in err) == (run == "cold")
        fits = re.findall(r"(?m)^  \S+: (\d+) parts?, volume [+-]\d+\.\d %.*Hausdorff (\S+)$", err)
        assert len(fits) == 9 and all(int(k) >= 1 and float(h) >= 0 for k, h in fits)
        model = mujoco.MjModel.from_xml_path(str(out))
        assert penetrating(model) == []
        parts = list((out.parent / "meshes" / "collision").glob("*_part*.stl"))
        meshes = [g for g in collision_geoms(model) if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH]
        assert len(parts) >= 9 and len(meshes) >= len(parts)   # the fingers share their parts' files
