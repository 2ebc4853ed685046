"""The synthesis optimiser and the sweep runner (local processes, Dask)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from robkin import se3
from robkin.errors import InputError
from robkin.synthesis import optimize
from robkin.synthesis import problem as opt
from robkin.synthesis.optimize import REACH_TOL, make_task, random_start, synthesize
from robkin.synthesis.sweep import (Job, make_jobs, progress_bar, random_task_poses, run_job, run_sweep,
                                    summarize)

T1 = se3.trans(-0.6, 0.5, 0.7) @ se3.rot_z(0.4) @ se3.rot_y(2.0) @ se3.rot_x(-0.3)
T2 = T1 @ se3.trans(0.1, 0.05, -0.08) @ se3.rot_x(0.25)


def _fd(f, z, h=1e-6):
    cols = []
    for j in range(z.size):
        e = np.zeros_like(z)
        e[j] = h
        cols.append((f(z + e) - f(z - e)) / (2 * h))
    return np.stack(cols, axis=-1)


@pytest.mark.parametrize("reach", ["pose", "position"])
def test_reach_jacobian_matches_finite_differences(reach):
    task = make_task([T1, T2], reach=reach)
    model = opt.Model(task, 5)
    z = random_start(task, 5, 3)
    # central differences, h = 1e-6 on O(1) variables: truncation ~1e-12, rounding ~1e-10
    np.testing.assert_allclose(model.jacobian(z), _fd(model.residual, z), atol=1e-8)


def test_left_jacobian_inverse_is_the_derivative_of_log():
    rng = np.random.default_rng(0)
    for angle in (1e-6, 0.3, 2.0, 3.0):
        axis = rng.normal(size=3)
        phi = axis / np.linalg.norm(axis) * angle
        R = se3.exp_twist(np.r_[phi / angle, 0, 0, 0], angle)[:3, :3]
        w = rng.normal(size=3) * 1e-7
        Rw = se3.exp_twist(np.r_[w / np.linalg.norm(w), 0, 0, 0], np.linalg.norm(w))[:3, :3]
        dphi = se3.log_rotation(Rw @ R) - se3.log_rotation(R)
        predicted = opt.left_jacobian_inverse(phi[None])[0] @ w
        # first-order check: the error is O(|w|^2) ~ 1e-14 plus log rounding ~1e-16 / angle
        np.testing.assert_allclose(dphi, predicted, atol=1e-12)


def test_log_of_an_exact_half_turn():
    """diag(1, -1, -1) etc. have a skew part of exactly 0 (synthesis meets them when an estimate's tool is
    turned by exactly pi from a target): the rotation vector is pi times the axis, without a warning
    (the test run turns warnings into errors)."""
    for axis in np.eye(3):
        R = 2.0 * np.outer(axis, axis) - np.eye(3)
        np.testing.assert_allclose(np.abs(se3.log_rotation(R)), math.pi * axis, atol=1e-15)


def test_length_and_dexterity_gradients():
    task = make_task([T1, T2])
    model = opt.Model(task, 4)
    z = random_start(task, 4, 1)
    h, Jh = opt.link_lengths(model, z)
    np.testing.assert_allclose(Jh, _fd(lambda x: opt.link_lengths(model, x)[0], z), atol=1e-8)
    c, Jc = opt.cost_residual(model, "manipulability", z)
    assert c.shape == (4 + 2,) and np.all(np.isfinite(c))


@pytest.mark.parametrize("reach, n", [("pose", 6), ("pose", 4), ("pose", 8), ("position", 2), ("position", 5)])
def test_dexterity_matches_singular_values_of_the_chain_jacobian(reach, n):
    """The compiled dexterity (DH chain + Householder QR) against numpy's SVD of the same scaled
    Jacobian built from the model's frames: square, wide and tall Jacobians, one design and a batch."""
    task = make_task([T1, T2], reach=reach)
    model = opt.Model(task, n)
    Z = np.stack([random_start(task, n, seed) for seed in range(3)])
    o, zs, _, _ = model.chain(Z)
    L = np.sum(np.hypot(Z[:, :n], Z[:, n:2 * n]), axis=1) + opt.LENGTH_EPS
    Jv = np.cross(zs[..., :-1, :], o[..., -1:, :] - o[..., :-1, :]) / L[:, None, None, None]
    J = np.concatenate([Jv, zs[..., :-1, :]], axis=-1) if reach == "pose" else Jv
    expected = -np.log(np.prod(np.linalg.svd(J, compute_uv=False), axis=-1) + opt.MANIP_FLOOR)
    # both are backward-stable factorisations of the same O(1) matrices: agreement to ~1e-14 relative
    np.testing.assert_allclose(opt.dexterity(model, Z), expected, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(opt.dexterity(model, Z[1]), expected[1], rtol=1e-12, atol=1e-12)


def test_dexterity_gradient_matches_one_design_at_a_time():
    """The batched finite differences equal differences of single-design evaluations."""
    task = make_task([T1, T2])
    model = opt.Model(task, 6)
    z = random_start(task, 6, 2)
    _, Jc = opt.cost_residual(model, "manipulability", z)
    wd = opt.COST_WEIGHTS["manipulability"][1]
    np.testing.assert_allclose(Jc[6:], wd * _fd(lambda x: opt.dexterity(model, x), z), rtol=0, atol=1e-9)


def test_single_pose_from_pose_estimates_needs_no_reach_phase():
    task = make_task(T1)
    for start in "CD":
        res = synthesize(task, 4, start, max_iter=400)
        assert res.reach_evaluations == 1 and res.reached_first
        assert res.reaches
        # the result reaches at q = 0 (theta offsets = the configuration for the first pose)
        T = res.robot.fk(np.zeros(4))
        assert np.linalg.norm(T[:3, 3] - T1[:3, 3]) <= REACH_TOL * task.size
        assert np.allclose(T[:3, :3], T1[:3, :3], atol=1e-5)


def test_two_poses_reached_and_cost_not_worse_than_start():
    task = make_task([T1, T2])
    res = synthesize(task, 5, "D")
    assert res.converged and res.reaches, res.message
    assert np.all(res.q[0] == 0)
    T = res.robot.fk(res.q)  # independent of the optimiser's own residual
    for k, target in enumerate((T1, T2)):
        assert np.linalg.norm(T[k, :3, 3] - target[:3, 3]) < 1e-6 * task.size
        rel = target[:3, :3].T @ T[k, :3, :3]
        assert math.acos(np.clip((np.trace(rel) - 1) / 2, -1, 1)) < 1e-5
    # the start (estimate D of the first pose) has links summing to its eq. 48 length; the optimum's
    # sum of squared links (the 'length' cost) must not be larger than the start's
    from robkin.synthesis.estimate import estimate

    start_rows = estimate(T1, 5, "D").rows
    start_cost = float(np.sum((start_rows[:, 0] ** 2 + start_rows[:, 1] ** 2))) / task.size ** 2
    assert res.cost <= start_cost + 1e-9
    assert res.length == pytest.approx(np.sum(np.hypot(res.table.rows[:, 0], res.table.rows[:, 1])))


def test_position_task_and_world_base():
    B = se3.trans(0.2, 0.1, 0.0) @ se3.rot_z(0.5)
    task = make_task([B @ T1, B @ T2], base=B, reach="position")
    res = synthesize(task, 4, "A", max_iter=400)
    assert res.reaches
    np.testing.assert_allclose(res.robot.world, B)
    T = res.robot.fk(res.q)  # in the robot base frame: the task poses are B^-1 (B T_k) = T_k
    assert np.linalg.norm(T[1, :3, 3] - T2[:3, 3]) < 1e-6 * task.size


def test_manipulability_cost_improves_dexterity():
    task = make_task(T1)
    model = opt.Model(task, 4)
    by_cost = {c: synthesize(task, 4, "D", c, max_iter=300) for c in ("length", "manipulability")}
    for r in by_cost.values():
        assert r.reaches
    dex = {c: float(opt.dexterity(model, optimize._z_from_rows(r.table.rows, task))[0]) for c, r in by_cost.items()}
    # -log(dimensionless manipulability): smaller is more dexterous
    assert dex["manipulability"] < dex["length"]
    sq = {c: float(np.sum(r.table.rows[:, 0] ** 2 + r.table.rows[:, 1] ** 2)) for c, r in by_cost.items()}
    assert sq["length"] < sq["manipulability"]  # what the 'length' cost minimises: sum of squared links


def test_random_start_is_reproducible_and_given_start_checked():
    task = make_task([T1, T2])
    z1, z2 = random_start(task, 4, 7), random_start(task, 4, 7)
    assert np.array_equal(z1, z2) and z1.shape == (3 * 4 + 2 * 4,)
    with pytest.raises(InputError, match="start"):
        synthesize(task, 4, np.zeros(5))
    with pytest.raises(InputError, match="start"):
        synthesize(task, 4, "E")


def test_bad_inputs():
    with pytest.raises(InputError, match="reach"):
        make_task(T1, reach="orientation")
    with pytest.raises(InputError, match="poses"):
        make_task(np.eye(4))
    with pytest.raises(InputError, match="poses"):
        make_task(np.zeros((2, 3, 3)))
    task = make_task(T1)
    with pytest.raises(InputError, match="joints"):
        synthesize(task, 2)
    with pytest.raises(InputError, match="cost"):
        synthesize(task, 4, cost="speed")


# ---------------------------------------------------------------------------------- sweeps


def _small_jobs():
    rng = np.random.default_rng(2)
    tasks = [random_task_poses(rng, 2, step=0.1, turn=0.2) for _ in range(2)]
    return make_jobs(tasks, 4, ["D", "random"], seed=1, max_iter=150)


def test_random_task_poses_shape_and_steps():
    rng = np.random.default_rng(0)
    P = random_task_poses(rng, 4, step=0.3, turn=0.5)
    assert P.shape == (4, 4, 4)
    steps = np.linalg.norm(np.diff(P[:, :3, 3], axis=0), axis=1)
    np.testing.assert_allclose(steps, 0.3)
    assert 0.5 <= np.linalg.norm(P[0, :3, 3]) <= 1.5


def test_sweep_serial_and_processes_agree():
    jobs = _small_jobs()
    serial = run_sweep(jobs, workers=1, progress=False)
    parallel = run_sweep(jobs, workers=2, progress=False)
    assert [r["task_id"] for r in parallel] == [j.task_id for j in jobs]
    for a, b in zip(serial, parallel):
        assert a["start"] == b["start"] and a["converged"] == b["converged"]
        assert a["cost"] == pytest.approx(b["cost"], rel=1e-9)  # same code, same seed


def test_sweep_on_dask_local_cluster():
    distributed = pytest.importorskip("dask.distributed")
    jobs = _small_jobs()[:2]
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        recs = run_sweep(jobs, scheduler=client, progress=False)
    direct = [run_job(j) for j in jobs]
    assert [r["cost"] for r in recs] == pytest.approx([r["cost"] for r in direct], rel=1e-9)


def test_sweep_bad_workers():
    with pytest.raises(InputError, match="workers"):
        run_sweep(_small_jobs()[:1] * 2, workers=0, progress=False)


def test_summarize_counts():
    recs = [
        dict(task_id=0, start="D", converged=True, reached_first=True, cost=1.0, length=2.0,
             reach_evaluations=1, evaluations=10, seconds=0.1),
        dict(task_id=0, start="random", converged=True, reached_first=False, cost=2.0, length=3.0,
             reach_evaluations=5, evaluations=20, seconds=0.2),
        dict(task_id=0, start="random", converged=False, reached_first=False, cost=0.5, length=1.0,
             reach_evaluations=5, evaluations=30, seconds=0.3),
        dict(task_id=1, start="D", converged=False, reached_first=True, cost=9.0, length=9.0,
             reach_evaluations=1, evaluations=40, seconds=0.4),
        dict(task_id=1, start="random", converged=True, reached_first=True, cost=3.0, length=4.0,
             reach_evaluations=7, evaluations=50, seconds=0.5),
    ]
    rows = {r["start"]: r for r in summarize(recs, random_group=2)}
    assert rows["D"]["converged_rate"] == 0.5 and rows["D"]["reach_rate"] == 1.0
    assert rows["D"]["cost"] == 1.0 and rows["D"]["best_rate"] == 0.5  # wins task 0 only
    assert rows["random"]["runs"] == 3 and rows["random"]["converged_rate"] == pytest.approx(2 / 3)
    assert rows["random"]["best_rate"] == 0.5  # wins task 1 only
    best_random = rows["best of 2 random"]
    assert best_random["runs"] == 2 and best_random["converged_rate"] == 1.0
    assert best_random["evaluations"] == pytest.approx(np.median([20 + 30, 50]))


def test_progress_bar_fallback_and_tqdm(capsys):
    bar = progress_bar(3, enabled=False)
    bar.update(2)
    bar.close()
    assert capsys.readouterr().err == ""
    bar = progress_bar(2, desc="t", enabled=True)
    bar.update(2)
    bar.close()


def test_job_record_fields():
    job = Job(0, np.stack([T1]), 4, "C", max_iter=100)
    rec = run_job(job)
    assert rec["reach_evaluations"] == 1 and rec["reached_first"]
    assert {"converged", "cost", "length", "evaluations", "seconds", "n", "K"} <= set(rec)


def test_reaches_the_estimation_papers_three_poses_within_bounds():
    """The paper's Poses (1)-(3) (Huczala et al. 2021, eqs. 8-10; Pose (2) projected onto SO(3)) as one
    task for a 6-joint arm: every estimate start converges, and an independent FK of the returned robot
    reaches each pose; the design stays inside the optimiser's bounds."""
    P1 = np.array([[-0.5005, -0.1800, -0.8468, -1.0], [-0.0654, 0.9832, -0.1704, 0.9],
                   [0.8633, -0.0299, -0.5039, 0.8], [0, 0, 0, 1]])
    P2 = np.array([[0.81, -0.34, -0.46, -0.4], [0.48, -0.02, 0.87, 0.6], [-0.30, -0.93, 0.14, 0.7], [0, 0, 0, 1]])
    P3 = np.array([[0, 1, 0, 0.4], [1, 0, 0, 0.6], [0, 0, -1, 0.7], [0, 0, 0, 1.0]])
    poses = np.stack([P1, P2, P3])
    for T in poses:
        T[:3, :3] = se3.nearest_rotation(T[:3, :3])
    task = make_task(poses)
    for start in "ABCD":
        res = synthesize(task, 6, start, "manipulability")
        assert res.converged and res.reaches, (start, res.message)
        T = res.robot.fk(res.q)
        for k in range(3):
            assert np.linalg.norm(T[k, :3, 3] - poses[k, :3, 3]) < REACH_TOL * task.size
            rel = poses[k, :3, :3].T @ T[k, :3, :3]
            assert math.acos(np.clip((np.trace(rel) - 1) / 2, -1, 1)) < 1e-5
        assert np.all(np.abs(res.table.rows[:, :2]) <= optimize.LENGTH_BOUND * task.size)
        assert np.all(np.abs(res.table.rows[:, 2]) <= 2 * math.pi)
