"""The parts of ``robkin.collision`` against independent computations: trimesh's volumes, hulls and
closest points; CoACD's decomposition and its cache (hostile contents refused); flat meshes that MuJoCo
would refuse, written so that it loads them; a model whose visuals were all dropped, refused."""

from __future__ import annotations

import os
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import robkin
from robkin.cli import main
from robkin.collision.hull import convex_hull, hull_volume
from robkin.collision.mesh_data import read_mesh, stl_bytes
from robkin.collision.primitives import fit_primitive, fit_report, primitive_volume
from robkin.collision.tessellate import convex_distance, primitive_mesh, surface_samples
from test_mesh_files import ROBOTS_DIR, TET_DAE

trimesh = pytest.importorskip("trimesh")

UR5_MESHES = Path(ROBOTS_DIR) / "ur_description" / "meshes" / "ur5" / "collision"


def _ur5_mesh(name: str) -> tuple[np.ndarray, np.ndarray]:
    path = UR5_MESHES / name
    if not path.is_file():
        pytest.skip("example-robot-data not installed")
    return read_mesh(path)


def test_hull_and_volume_equal_trimeshs():
    V, F = _ur5_mesh("upperarm.stl")
    hv, hf = convex_hull(V)
    ref = trimesh.Trimesh(V, F).convex_hull
    assert hull_volume(hv, hf) == pytest.approx(ref.volume, rel=1e-12)
    assert trimesh.Trimesh(hv, hf).is_convex and trimesh.Trimesh(hv, hf).is_winding_consistent
    assert len(hv) == len(ref.vertices)


@pytest.mark.parametrize("kind, size", [("box", (0.1, 0.2, 0.3)), ("sphere", (0.1,)), ("cylinder", (0.1, 0.4)),
                                        ("capsule", (0.1, 0.4))])
def test_primitive_meshes_close_and_match_their_volume(kind, size):
    """Tessellated primitives are closed, face outwards, and hold their analytic volume less the chord error
    (32 segments: at most 1.3 % for a sphere)."""
    V, F = primitive_mesh(kind, size)
    m = trimesh.Trimesh(V, F, process=False)
    assert m.is_watertight and m.volume > 0
    assert m.volume == pytest.approx(primitive_volume(kind, size), rel=0.02 if kind != "box" else 1e-12)


@pytest.fixture(scope="module")
def upperarm_fit():
    V, F = _ur5_mesh("upperarm.stl")
    hv, hf = convex_hull(V)
    prim = fit_primitive(hv, np.eye(3))
    return V, F, hv, hf, prim, fit_report("upper_arm_link", prim, [(hv, hf)])


def _inside(prim, P: np.ndarray) -> np.ndarray:
    """Whether points are inside the analytic primitive (independent of its tessellation)."""
    local = (P - prim.pose[:3, 3]) @ prim.pose[:3, :3]
    s = prim.size
    if prim.kind == "box":
        return (np.abs(local) <= np.asarray(s) / 2 * (1 + 1e-9) + 1e-12).all(axis=1)
    if prim.kind == "sphere":
        return np.linalg.norm(local, axis=1) <= s[0] * (1 + 1e-9)
    radial = np.linalg.norm(local[:, :2], axis=1)
    if prim.kind == "cylinder":
        return (radial <= s[0] * (1 + 1e-9)) & (np.abs(local[:, 2]) <= s[1] / 2 * (1 + 1e-9))
    z = np.clip(local[:, 2], -s[1] / 2, s[1] / 2)
    return np.linalg.norm(local - np.c_[np.zeros((len(z), 2)), z], axis=1) <= s[0] * (1 + 1e-9)


def test_fitted_primitive_encloses_the_link_and_reports_its_fit(upperarm_fit):
    """The primitive holds every vertex of the mesh; its reported volume error is against trimesh's hull
    volume, and its Hausdorff distance is the largest of trimesh's exact closest-point distances from the
    same surface points (outside the hull) to the hull."""
    V, F, hv, hf, prim, report = upperarm_fit
    assert _inside(prim, V).all()
    hull = trimesh.Trimesh(V, F).convex_hull
    assert report.hull_volume == pytest.approx(hull.volume, rel=1e-9)
    assert report.volume == pytest.approx(primitive_volume(prim.kind, prim.size), rel=1e-12)
    assert report.volume_error == pytest.approx(report.volume / hull.volume - 1, rel=1e-9)
    assert 0 < report.volume_error < 1.0     # a long arm link: observed capsule +35 %
    pv, pf = primitive_mesh(prim.kind, prim.size)
    samples = surface_samples(pv, pf, 2000) @ prim.pose[:3, :3].T + prim.pose[:3, 3]
    _, dist, _ = trimesh.proximity.closest_point(hull, samples)
    dist[hull.contains(samples)] = 0.0
    assert report.hausdorff == pytest.approx(dist.max(), rel=1e-9, abs=1e-12)


def test_convex_distance_is_exact():
    V, F = _ur5_mesh("forearm.stl")
    hv, hf = convex_hull(V)
    hull = trimesh.Trimesh(hv, hf)
    P = hv.mean(axis=0) + np.random.default_rng(3).normal(size=(400, 3)) * 0.15
    ours = convex_distance(P, hv, hf)
    _, ref, _ = trimesh.proximity.closest_point(hull, P)
    ref[hull.contains(P)] = 0.0
    np.testing.assert_allclose(ours, ref, rtol=0, atol=1e-12)


def test_decimate_keeps_the_budget_and_the_shape():
    pytest.importorskip("fast_simplification")
    from robkin.collision.decimate import decimate

    V, F = _ur5_mesh("upperarm.stl")
    Vd, Fd = decimate(V, F, 400)
    assert 0 < len(Fd) <= 400
    full, small = trimesh.Trimesh(V, F), trimesh.Trimesh(Vd, Fd)
    assert small.convex_hull.volume == pytest.approx(full.convex_hull.volume, rel=0.05)


def _l_shape() -> tuple[np.ndarray, np.ndarray]:
    """A closed L of two boxes (concave): CoACD should cut it in two or more convex parts."""
    a = trimesh.creation.box((0.3, 0.1, 0.1), trimesh.transformations.translation_matrix((0.1, 0, 0)))
    b = trimesh.creation.box((0.1, 0.3, 0.1), trimesh.transformations.translation_matrix((0, 0.1, 0)))
    m = trimesh.boolean.union([a, b], engine="manifold")
    return np.asarray(m.vertices), np.asarray(m.faces)


@pytest.fixture()
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    pytest.importorskip("coacd")
    pytest.importorskip("manifold3d")
    from robkin.collision.decompose import cache_dir

    return cache_dir()


def test_decompose_cuts_a_concave_mesh_and_caches_it(cache):
    from robkin.collision.decompose import decompose

    V, F = _l_shape()
    parts, cached = decompose(V, F)
    assert not cached and len(parts) >= 2
    volume = trimesh.Trimesh(V, F).volume
    for pv, pf in parts:
        assert trimesh.Trimesh(pv).convex_hull.volume > 0
    union = sum(trimesh.Trimesh(pv).convex_hull.volume for pv, _ in parts)
    assert union == pytest.approx(volume, rel=0.25)     # convex parts of an L: observed within a few %
    files = list(cache.glob("*.npz"))
    assert len(files) == 1 and oct(cache.stat().st_mode & 0o777) == "0o700"
    again, cached = decompose(V, F)
    assert cached and all(np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1]) for a, b in zip(parts, again))


@pytest.mark.parametrize("hostile", ["garbage", "outside", "pickle", "symlink", "too_many"])
def test_hostile_cache_contents_are_decomposed_again(cache, tmp_path, hostile):
    """A cache file that is not what robkin wrote (damaged, geometry outside the mesh, a pickle, a symbolic
    link, too many parts) is never used: the mesh is decomposed again and the file replaced."""
    import io

    from robkin.collision.decompose import MAX_PARTS, decompose

    V, F = _l_shape()
    decompose(V, F)
    path = next(cache.glob("*.npz"))
    tet = (np.eye(4)[:, :3] * 0.01, np.array([[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]]))
    if hostile == "garbage":
        path.write_bytes(b"PK\x03\x04 not a zip")
    elif hostile == "outside":
        buf = io.BytesIO()
        np.savez(buf, count=np.array(1), v0=tet[0] + 100.0, f0=tet[1])
        path.write_bytes(buf.getvalue())
    elif hostile == "pickle":
        buf = io.BytesIO()
        np.savez(buf, count=np.array(1), v0=np.array([object()], dtype=object), f0=tet[1])
        path.write_bytes(buf.getvalue())
    elif hostile == "symlink":
        target = tmp_path / "elsewhere.npz"
        target.write_bytes(path.read_bytes())
        path.unlink()
        path.symlink_to(target)
    else:
        buf = io.BytesIO()
        arrays = {"count": np.array(MAX_PARTS + 1)}
        for k in range(MAX_PARTS + 1):
            arrays[f"v{k}"], arrays[f"f{k}"] = tet
        np.savez(buf, **arrays)
        path.write_bytes(buf.getvalue())
    parts, cached = decompose(V, F)
    assert not cached and len(parts) >= 2


def _flat_robot(folder: Path) -> Path:
    """A one-joint URDF whose link's visual and collision mesh is a flat square (no volume)."""
    V = np.array([[0, 0, 0], [0.1, 0, 0], [0.1, 0.1, 0], [0, 0.1, 0]], dtype=float)
    (folder / "flat.stl").write_bytes(stl_bytes(V, np.array([[0, 1, 2], [0, 2, 3]])))
    cube = trimesh.creation.box((0.05, 0.05, 0.05))
    (folder / "cube.stl").write_bytes(stl_bytes(np.asarray(cube.vertices), np.asarray(cube.faces)))
    link = ('<link name="l1"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" '
            'ixz="0" iyz="0"/></inertial><visual><geometry><mesh filename="flat.stl"/></geometry></visual>'
            '<visual><geometry><mesh filename="cube.stl"/></geometry></visual>'
            '<collision><geometry><mesh filename="flat.stl"/></geometry></collision></link>')
    path = folder / "flat.urdf"
    path.write_text(f'<robot name="flat"><link name="base"/>{link}<joint name="j1" type="revolute"><parent '
                    f'link="base"/><child link="l1"/><origin xyz="0 0 0.2"/><axis xyz="0 0 1"/><limit lower="-1" '
                    f'upper="1" effort="1" velocity="1"/></joint></robot>')
    return path


@pytest.mark.parametrize("mode", ["source", "hull", "primitives"])
def test_a_flat_mesh_is_written_so_that_mujoco_loads_it(tmp_path, capsys, mode):
    """MuJoCo refuses a flat mesh twice: as a visual ('mesh volume is too small') and as a collision
    ('coplanar vertices'). The visual is written with inertia="shell", the collision as a thin box."""
    mujoco = pytest.importorskip("mujoco")
    src = tmp_path / "src"
    src.mkdir()
    out = tmp_path / "out" / "flat.xml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["convert", str(_flat_robot(src)), "--to", "mjcf", "-o", str(out), "--collision", mode]) == 0
    err = capsys.readouterr().err
    model = mujoco.MjModel.from_xml_path(str(out))
    boxes = [g for g in range(model.ngeom) if model.geom_group[g] == 3]
    assert len(boxes) == 1 and model.geom_type[boxes[0]] == mujoco.mjtGeom.mjGEOM_BOX
    assert "inertia=\"shell\"" in out.read_text()
    if mode != "primitives":
        assert "flat collision mesh(es)" in err


def test_puma560_of_the_robotics_toolbox_loads(tmp_path):
    """The Robotics Toolbox's Puma 560 (xacro, COLLADA visuals with flat decals): MuJoCo loads the MJCF."""
    mujoco = pytest.importorskip("mujoco")
    pytest.importorskip("xacro")
    rtbdata = pytest.importorskip("rtbdata")
    xacro = Path(rtbdata.__file__).parent / "xacro" / "unimation_puma560_description" / "urdf" / "puma560_robot.urdf.xacro"
    if not xacro.is_file():
        pytest.skip("rtbdata has no Puma 560")
    out = tmp_path / "puma.xml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["convert", str(xacro), "--allow-xacro", "--to", "mjcf", "-o", str(out)]) == 0
        robot = robkin.load(xacro, allow_xacro=True)
    model = mujoco.MjModel.from_xml_path(str(out))
    assert int((model.geom_group == 2).sum()) >= len(robot.bodies.visuals())   # COLLADA split by colour
    assert int((model.geom_group == 3).sum()) == len(robot.bodies.collisions())
    from test_collision_modes import penetrating

    assert penetrating(model) == []


def test_a_model_whose_visuals_are_all_dropped_is_refused(tmp_path, capsys, monkeypatch):
    """Without trimesh, COLLADA visuals cannot be converted: the MJCF would show nothing (its collision
    geoms are hidden), so convert refuses with one line naming the extra, exit 2, and leaves nothing."""
    src = tmp_path / "src"
    src.mkdir()
    (src / "tet.dae").write_text(TET_DAE)
    (src / "r.urdf").write_text(
        '<robot name="r"><link name="base"/><link name="l1"><visual><geometry><mesh filename="tet.dae"/>'
        '</geometry></visual></link><joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>'
        '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>')
    monkeypatch.setitem(sys.modules, "trimesh", None)   # import trimesh -> ImportError
    out = tmp_path / "out"
    out.mkdir()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["convert", str(src / "r.urdf"), "--to", "mjcf", "-o", str(out / "r.xml")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith("robkin: error:") and "render empty" in err[-1] and "robkin[meshes]" in err[-1]
    assert list(out.iterdir()) == []
    _ = os


@pytest.mark.parametrize("data, reason", [
    (b"\0" * 80 + (4_000_000_000).to_bytes(4, "little") + b"\0" * 50, "not a binary STL"),
    (b"", "no triangles"),
])
def test_hostile_stl_is_refused_with_a_reason(tmp_path, data, reason):
    """A binary STL header claiming 4e9 triangles is never believed (its size disagrees: read as ASCII by
    trimesh, which finds nothing); an empty file has no triangles. One short reason each, no traceback."""
    from robkin.collision.mesh_data import MeshError

    path = tmp_path / "bad.stl"
    path.write_bytes(data)
    with pytest.raises(MeshError) as exc:
        read_mesh(path)
    assert "\n" not in str(exc.value) and len(str(exc.value)) < 120


def test_nan_vertex_is_refused(tmp_path):
    from robkin.collision.mesh_data import MeshError

    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, np.nan]], dtype=float)
    path = tmp_path / "nan.stl"
    path.write_bytes(stl_bytes(V, np.array([[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]])))
    with pytest.raises(MeshError, match="NaN or infinite"):
        read_mesh(path)


def test_without_mujoco_only_adjacent_pairs_are_excluded(monkeypatch):
    """The touching pairs need MuJoCo; without it the parent-child pairs are still excluded (the world's
    welded bodies included) and the note says what was not checked."""
    from robkin.collision.exclusions import contact_excludes

    text = """<mujoco><worldbody>
      <body name="base"><geom class="collision" type="box" size="1 1 1"/>
        <body name="mount"><geom class="collision" type="box" size="1 1 1"/>
          <body name="l1"><joint name="j1"/><geom class="collision" type="box" size="1 1 1"/>
            <body name="l2"><joint name="j2"/><geom class="visual" type="box" size="1 1 1"/>
              <body name="l3"><joint name="j3"/><geom class="collision" type="box" size="1 1 1"/></body>
            </body>
          </body>
        </body>
      </body></worldbody></mujoco>"""
    monkeypatch.setitem(sys.modules, "mujoco", None)
    pairs, note = contact_excludes(text, None, 1.0)
    assert sorted(pairs) == [("base", "l1"), ("l1", "mount")]   # l2 has no collision geom: l2/l3 not needed
    assert "not checked (MuJoCo is not installed)" in note


def test_decomposition_report_against_manifold_and_trimesh(cache):
    """The report's union volume (Monte Carlo) against manifold3d's exact union, within 1 % of the mesh's
    volume (observed 0.1-0.4 %); its Hausdorff distance is the largest of trimesh's closest-point distances
    from the same part surface points that lie outside the mesh (trimesh's contains)."""
    from robkin.collision.decompose import decompose
    from robkin.collision.decompose_fit import SAMPLES, decomposition_report

    V, F = _l_shape()
    parts, _ = decompose(V, F)
    hulls = [convex_hull(pv) for pv, _ in parts]
    report = decomposition_report("l", V, F, hulls)
    mesh = trimesh.Trimesh(V, F)
    union = trimesh.boolean.union([trimesh.Trimesh(*h) for h in hulls], engine="manifold").volume
    assert report.reference == "mesh" and report.parts == len(hulls)
    assert report.volume_error == pytest.approx(union / mesh.volume - 1, abs=0.01)
    assert report.hull_volume_error == pytest.approx(mesh.convex_hull.volume / mesh.volume - 1, rel=1e-9)
    samples = np.vstack([surface_samples(pv, pf, SAMPLES, seed=k) for k, (pv, pf) in enumerate(hulls)])
    outside = ~mesh.contains(samples)
    _, dist, _ = trimesh.proximity.closest_point(mesh, samples[outside])
    assert report.hausdorff == pytest.approx(dist.max() if outside.any() else 0.0, rel=1e-6, abs=1e-9)


def test_cached_fit_numbers_are_checked(cache, tmp_path):
    """The fit report's numbers beside a cached decomposition are used only when sound: five finite
    float64, the same count of parts, a reference of 0 or 1, a distance >= 0, a regular file."""
    from robkin.collision.decompose import _fit_path, cached_fit, remember_fit

    V, F = _l_shape()
    good = (2.0, 0.05, 0.4, 1.0, 0.001)
    remember_fit(V, F, good)
    assert cached_fit(V, F, 2).tolist() == list(good)
    assert cached_fit(V, F, 3) is None                       # another count of parts
    path = _fit_path(V, F)
    for bad in (np.array([2.0, np.nan, 0.4, 1.0, 0.0]), np.array([2.0, 0.05, 0.4, 0.5, 0.0]),
                np.array([2.0, 0.05, 0.4, 1.0, -1.0]), np.zeros(6)):
        path.write_bytes(bad.astype("<f8").tobytes())
        assert cached_fit(V, F, 2) is None
    target = tmp_path / "fit"
    target.write_bytes(np.array(good).astype("<f8").tobytes())
    path.unlink()
    path.symlink_to(target)
    assert cached_fit(V, F, 2) is None


def test_a_refused_conversion_leaves_no_collision_files(tmp_path, capsys, monkeypatch):
    """--collision hull writes the hulls before the model; when the model is then refused (its COLLADA
    visuals cannot be converted without trimesh), the hull files and the folders made for them go too."""
    src = tmp_path / "src"
    src.mkdir()
    (src / "tet.dae").write_text(TET_DAE)
    cube = trimesh.creation.box((0.05, 0.05, 0.05))
    (src / "cube.stl").write_bytes(stl_bytes(np.asarray(cube.vertices), np.asarray(cube.faces)))
    (src / "r.urdf").write_text(
        '<robot name="r"><link name="base"/><link name="l1"><visual><geometry><mesh filename="tet.dae"/>'
        '</geometry></visual><collision><geometry><mesh filename="cube.stl"/></geometry></collision></link>'
        '<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>')
    monkeypatch.setitem(sys.modules, "trimesh", None)
    out = tmp_path / "out"
    out.mkdir()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["convert", str(src / "r.urdf"), "--to", "mjcf", "-o", str(out / "r.xml"),
                     "--collision", "hull"]) == 2
    err = capsys.readouterr().err
    assert "1 mesh(es) -> 1 convex mesh file(s)" in err and "render empty" in err   # written, then refused
    assert list(out.rglob("*")) == []
