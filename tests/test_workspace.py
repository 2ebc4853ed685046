"""Workspace maps (robkin.workspace, robkin workspace): the grid, the map against brute force, the
same map on any thread count and on Dask, files, base placement, the command line."""

from __future__ import annotations

import json
import math
from dataclasses import replace

import numpy as np
import pytest

import robkin
from robkin.cli import main
from robkin.errors import InputError
from robkin.examples import EXAMPLES_DIR
from robkin.workspace import (agreement, base_placement, load_map, reachability_map, save_map, sphere_directions,
                              verify)
from robkin.workspace.grid import direction_bins, reach_box
from robkin.workspace.placement import base_frame
from test_urdf import robot_file


def example_path(name: str) -> str:
    return str(EXAMPLES_DIR / name)


@pytest.fixture(scope="module")
def panda() -> robkin.Robot:
    return robkin.load(robot_file("panda_description/urdf/panda.urdf"), tip_link="panda_hand_tcp")


@pytest.fixture(scope="module")
def panda_map(panda):
    # 10 cm voxels, 20 directions, 2e6 configurations: 1/20 of the default 5 cm map's per 8 voxels
    return reachability_map(panda, 0.1, 20, samples=2_000_000, seed=7)


def test_sphere_directions_are_unit_and_near_uniform():
    d = sphere_directions(50)
    assert d.shape == (50, 3) and np.allclose(np.linalg.norm(d, axis=1), 1.0, atol=1e-14)
    # equal-area lattice: uniform random directions fall ~evenly into the bins (1e5 draws, ~2000 a bin:
    # +-10 % is > 4 standard deviations of a count, yet far below what a poor lattice gives, 2x and more)
    rng = np.random.default_rng(0)
    z = rng.normal(size=(100_000, 3))
    z /= np.linalg.norm(z, axis=1, keepdims=True)
    counts = np.bincount(direction_bins(z, d), minlength=50)
    assert counts.min() > 0.8 * 2000 and counts.max() < 1.2 * 2000
    # the bin is the nearest direction (largest dot product), checked by brute force, also right at the
    # regions' boundaries (midpoints of two directions, 1e-9 off) where the lookup table must defer
    assert np.array_equal(direction_bins(z, d), np.argmax(z @ d.T, axis=1))
    i, j = np.triu_indices(50, 1)
    mid = d[i] + d[j]
    mid = np.concatenate([mid + 1e-9 * rng.normal(size=mid.shape) for _ in range(4)])
    mid /= np.linalg.norm(mid, axis=1, keepdims=True)
    assert np.array_equal(direction_bins(mid, d), np.argmax(mid @ d.T, axis=1))
    for v in z[:20]:
        assert direction_bins(v[None], d)[0] == int(np.argmin(np.linalg.norm(d - v, axis=1)))
    assert np.array_equal(sphere_directions(1), [[0.0, 0.0, 1.0]])


@pytest.mark.parametrize("name", ["rrpr.yaml", "iiwa14.yaml", "kr6_r700.yaml", "scara.yaml"])
def test_reach_box_holds_every_tool_position(name):
    robot = robkin.load(example_path(name))
    robot = robot.replace(joints=tuple(j if j.revolute else replace(j, lower=-0.2, upper=0.5) for j in robot.joints))
    v = robot.scale / 20  # the SCARA example is in other units than metres
    origin, shape = reach_box(robot, v)
    assert np.allclose(origin / v, np.rint(origin / v))  # corners on multiples of the voxel
    lim = np.where(np.isfinite(robot.limits), robot.limits, [-math.pi, math.pi])
    q = np.random.default_rng(1).uniform(lim[:, 0], lim[:, 1], size=(20_000, robot.n))
    q[:1000] = np.where(np.random.default_rng(2).random((1000, robot.n)) < 0.5, lim[:, 0], lim[:, 1])  # corners
    p = robot.fk(q)[:, :3, 3]
    assert (p > origin).all() and (p < origin + v * np.array(shape)).all()


def test_map_marks_only_reached_voxels(panda, panda_map):
    """Every marked voxel has its witness: a configuration within the limits whose tool origin lies in
    the voxel, with that voxel's manipulability (checked against NumPy's SVD of the Jacobian)."""
    m = panda_map
    reached = np.argwhere(m.reachable > 0)
    q = m.best_q[tuple(reached.T)]
    assert np.isfinite(q).all()
    assert (q >= panda.limits[:, 0]).all() and (q <= panda.limits[:, 1]).all()
    ijk, inside = m.voxel_index(panda.fk(q)[:, :3, 3])
    assert inside.all() and np.array_equal(ijk, reached)
    J = panda.jacobian(q[:200])[:, :3]
    expected = np.prod(np.linalg.svd(J, compute_uv=False), axis=1)
    # 1e-12 relative: two factorisations of the same 3 x 7 rows agree to a few ulps
    assert np.allclose(m.manipulability[tuple(reached[:200].T)], expected, rtol=1e-12, atol=1e-15)
    assert np.isnan(m.manipulability[m.reachable == 0]).all() and np.isnan(m.best_q[m.reachable == 0]).all()
    assert m.reachable.max() <= 20 and m.reachable.dtype == np.uint16


def test_map_agrees_with_brute_force_sampling(panda, panda_map):
    """The map against an independent brute force (another seed, a quarter of the samples, binned here
    with plain NumPy): the done-when's 5 cm map (4e7 configurations by default) against 1e7 brute-force
    samples, scaled down to 10 cm voxels (8x fewer voxels) and 2e6 and 5e5 samples. At least 99 % of the voxels brute force reaches are
    in the map; the map never marks an unreached voxel (test above), so its extra voxels are ones the
    reference missed. Observed: recall 0.996, Jaccard 0.962 (fixed seeds: the same bits every run)."""
    v = 0.1
    rng = np.random.default_rng(12345)
    lo, hi = panda.limits[:, 0], panda.limits[:, 1]
    seen = set()
    for _ in range(2):
        p = panda.fk(rng.uniform(lo, hi, size=(250_000, 7)))[:, :3, 3]
        seen |= {tuple(r) for r in np.unique(np.floor(p / v).astype(np.int64), axis=0)}
    from robkin.workspace.compare import reachable_voxels

    mine = reachable_voxels(panda_map)
    recall = len(mine & seen) / len(seen)
    assert recall >= 0.99, recall


def test_same_map_on_any_thread_count_and_seeded(panda):
    a = reachability_map(panda, 0.1, 8, samples=150_000, seed=3, threads=1)
    b = reachability_map(panda, 0.1, 8, samples=150_000, seed=3, threads=3)
    _same(a, b)
    c = reachability_map(panda, 0.1, 8, samples=150_000, seed=4, threads=1)
    assert not np.array_equal(a.best_q, c.best_q, equal_nan=True)


def test_dask_path_gives_the_same_map(panda):
    distributed = pytest.importorskip("dask.distributed")
    a = reachability_map(panda, 0.1, 8, samples=300_000, seed=5, threads=1)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        b = reachability_map(panda, 0.1, 8, samples=300_000, seed=5, dask=client, tasks=3)
        c = reachability_map(panda, 0.1, 8, samples=300_000, seed=5, dask=client)
    _same(a, b)
    _same(a, c)


def _same(a, b):
    assert np.array_equal(a.origin, b.origin) and np.array_equal(a.bins, b.bins)
    assert np.array_equal(a.manipulability, b.manipulability, equal_nan=True)
    assert np.array_equal(a.best_q, b.best_q, equal_nan=True)


def test_file_round_trip_and_bad_files(panda_map, tmp_path):
    path = tmp_path / "m.npz"
    save_map(panda_map, str(path))
    back = load_map(str(path))
    _same(panda_map, back)
    assert back.joints == panda_map.joints and back.kind == "translational" and back.samples == 2_000_000
    assert agreement(panda_map, back)["jaccard"] == 1.0
    (tmp_path / "junk.npz").write_bytes(b"not a zip")
    with pytest.raises(InputError, match="junk.npz: not a workspace map"):
        load_map(str(tmp_path / "junk.npz"))
    np.savez(tmp_path / "other.npz", a=np.zeros(3))
    with pytest.raises(InputError, match="no array reachable"):
        load_map(str(tmp_path / "other.npz"))
    with np.load(path) as f:
        arrays = dict(f)
    arrays["reachable"] = arrays["reachable"] + 1
    np.savez(tmp_path / "tampered.npz", **arrays)
    with pytest.raises(InputError, match="'reachable'"):
        load_map(str(tmp_path / "tampered.npz"))


def test_bad_arguments():
    robot = robkin.load(example_path("rrpr.yaml"))
    with pytest.raises(InputError, match="voxel"):
        reachability_map(robot, 0.0)
    with pytest.raises(InputError, match="orientations"):
        reachability_map(robot, 0.1, 0)
    with pytest.raises(InputError, match="kind"):
        reachability_map(robot, 0.1, kind="volume")
    with pytest.raises(InputError, match="samples"):
        reachability_map(robot, 0.1, samples=0)
    with pytest.raises(InputError, match="joint 'joint3'.* prismatic"):  # the example's slider has no limits
        reachability_map(robot, 0.1)


def test_base_placement_finds_where_the_robot_stood(panda, panda_map):
    """Task poses made by the robot standing at B0 (on the candidate grid): from B0 the map reaches all
    of them (each is the pose of a configuration that marked its cell), and IK confirms it."""
    m = panda_map
    reached = np.argwhere(m.reachable > 0)
    pick = reached[np.random.default_rng(3).choice(len(reached), 12, replace=False)]
    q = m.best_q[tuple(pick.T)]
    B0 = base_frame(0.5, -0.3, 0.0, math.pi / 2)
    poses = B0 @ panda.fk(q)
    result = base_placement(m, poses, yaws=8)
    w = int(np.argmin(np.abs(result.yaws - math.pi / 2)))
    i, j = int(np.argmin(np.abs(result.xs - 0.5))), int(np.argmin(np.abs(result.ys + 0.3)))
    assert result.counts[w, i, j] == 12 and result.counts.max() == 12
    best = result.ranked(3)
    assert best[0]["reached"] == 12 and len(best) == 3
    assert verify(panda, poses, {"x": 0.5, "y": -0.3, "z": 0.0, "yaw": math.pi / 2}).all()
    # two poses 10 m apart: no base reaches both
    far = np.stack([base_frame(0, 0, 0.5, 0), base_frame(10, 0, 0.5, 0)])
    assert base_placement(m, far, yaws=2, step=0.5).counts.max() == 1


def test_cli_builds_plots_and_places(panda, tmp_path, capsys):
    pytest.importorskip("matplotlib")
    urdf = robot_file("panda_description/urdf/panda.urdf")
    out, pic = tmp_path / "map.npz", tmp_path / "map.png"
    assert main(["workspace", urdf, "--tip-link", "panda_hand_tcp", "-o", str(out), "--voxel", "0.1",
                 "--orientations", "10", "--samples", "2e5", "--plot", str(pic), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    m = load_map(str(out))
    assert summary["reachable_voxels"] == int((m.reachable > 0).sum()) and summary["orientations"] == 10
    assert pic.read_bytes()[:4] == b"\x89PNG"
    poses = tmp_path / "poses.csv"
    poses.write_text("x,y,z,roll,pitch,yaw\n0.5,0.2,0.3,180,0,0\n0.6,-0.1,0.2,180,0,30\n")
    assert main(["workspace", urdf, "--tip-link", "panda_hand_tcp", "--map", str(out), "--base-for", str(poses),
                 "--degrees", "--top", "2", "--verify", "--json"]) == 0
    placed = json.loads(capsys.readouterr().out)
    assert placed["poses"] == 2 and len(placed["placements"]) == 2
    assert all(p["reached"] == 2 and 0 <= p["verified"] <= 2 for p in placed["placements"])


@pytest.mark.parametrize("extra, message", [
    (["--voxel", "-1", "-o", "m.npz"], "voxel"),
    (["--plot", "m.gif"], "--plot"),
    (["-o", "m.txt"], ".npz"),
    ([], "nothing to do"),
    (["--samples", "1.5", "-o", "m.npz"], "--samples"),
])
def test_cli_bad_input_is_one_line_and_writes_nothing(extra, message, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["workspace", example_path("rrpr.yaml"), *extra]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0]
    assert list(tmp_path.iterdir()) == []


def test_cli_plot_without_matplotlib(tmp_path, capsys, monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "matplotlib", None)
    assert main(["workspace", example_path("rrpr.yaml"), "-o", str(tmp_path / "m.npz"),
                 "--plot", str(tmp_path / "m.png")]) == 2
    assert "matplotlib" in capsys.readouterr().err and list(tmp_path.iterdir()) == []


def test_cli_map_of_another_robot(panda_map, tmp_path, capsys):
    save_map(panda_map, str(tmp_path / "m.npz"))
    poses = tmp_path / "p.csv"
    poses.write_text("x,y,z,roll,pitch,yaw\n0.5,0.2,0.3,0,0,0\n")
    assert main(["workspace", example_path("rrpr.yaml"), "--map", str(tmp_path / "m.npz"),
                 "--base-for", str(poses)]) == 2
    assert "made for joints" in capsys.readouterr().err
