"""One target per call (``Robot.ik(T)`` with T (4, 4)) gives exactly what the batch gives for that target.

The single-target path shares the batch's kernels and bookkeeping, so q, success, the errors, the
iteration counts and the messages must agree bit for bit: closed forms (UR5, Kinova Jaco2, the SCARA
example) against the whole batch, the numeric solver (Panda) against a batch of one (its restart
streams are seeded per position in the batch, so a target alone is compared with itself alone).
Successful answers are also checked by pinocchio's forward kinematics (independent of robkin).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import robkin

from test_ik import load_arm, pin_fk      # the arms and pinocchio's FK of them, as test_ik uses them

SCARA = Path(robkin.__file__).parent / "examples" / "scara.yaml"
#: pinocchio's FK of a reported solution agrees with the target to this: ten times the default IK
#: tolerance (1e-9), far above pinocchio's own rounding over a ~1 m chain (~1e-15)
CHECK = 1e-8


def targets_and_starts(robot: robkin.Robot, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Reachable targets (FK of random q), a few pushed out of reach, and random preferred q0."""
    T = robot.fk(robot.random_q(n, rng=seed))
    T[::5, :3, 3] *= 10.0            # every fifth target far out of reach: failures must agree too
    return T, robot.random_q(n, rng=seed + 1)


def assert_same(single, batch, i: int) -> None:
    """The single-call result equals row i of the batch result, field by field."""
    np.testing.assert_array_equal(single.q, batch.q[i])
    assert single.success == bool(batch.success[i])
    assert single.position_error == float(batch.position_error[i])
    assert single.orientation_error == float(batch.orientation_error[i])
    assert single.iterations == int(batch.iterations[i]) and single.attempts == int(batch.attempts[i])
    assert single.message == batch.message[i] and single.method == batch.method
    assert isinstance(single.success, bool) and single.q.shape == (batch.q.shape[1],)


def pinocchio_error(arm: tuple, q: np.ndarray, T: np.ndarray) -> float:
    """max |pose - target| by pinocchio's FK of the arm's URDF at q."""
    robot, model, tip = arm
    return float(np.abs(pin_fk(model, robot, q, tip) - T).max())


@pytest.mark.parametrize("name", ["ur5", "kinova"])
def test_closed_form_single_calls_equal_the_batch(name):
    arm = load_arm(name)
    robot = arm[0]
    T, q0 = targets_and_starts(robot, 40, seed=7)
    batch = robot.ik(T, q0=q0)
    assert batch.method != "numeric" and 0 < batch.success.sum() < len(T)
    for i in range(len(T)):
        single = robot.ik(T[i], q0=q0[i])
        assert_same(single, batch, i)
        if single.success:
            assert pinocchio_error(arm, single.q, T[i]) < CHECK
    # the default preference (zero, clipped into the limits) too
    plain = robot.ik(T)
    for i in (0, 1, 2):
        assert_same(robot.ik(T[i]), plain, i)


def test_scara_single_calls_equal_the_batch():
    robot = robkin.load(SCARA)
    T, q0 = targets_and_starts(robot, 30, seed=3)
    batch = robot.ik(T, q0=q0)
    assert batch.method == "scara" and 0 < batch.success.sum() < len(T)
    for i in range(len(T)):
        assert_same(robot.ik(T[i], q0=q0[i]), batch, i)
    ok = batch.success
    assert np.abs(robot.fk(batch.q[ok]) - T[ok]).max() < CHECK


def test_numeric_single_calls_equal_a_batch_of_one():
    arm = load_arm("panda")
    robot = arm[0]
    T, q0 = targets_and_starts(robot, 12, seed=5)
    T = T[1:]                        # the first target is out of reach: keep the test quick
    q0 = q0[1:]
    for i in range(len(T)):
        single = robot.ik(T[i], q0=q0[i], rng=9)
        one = robot.ik(T[i:i + 1], q0=q0[i:i + 1], rng=9)
        assert single.method == "numeric"
        assert_same(single, one, 0)
        if single.success:
            assert pinocchio_error(arm, single.q, T[i]) < CHECK


def test_single_call_results_are_the_callers_to_keep():
    """Cached defaults (start, mask) never leak into results: q is a fresh, writable array."""
    robot = load_arm("ur5")[0]
    T = robot.fk(robot.random_q(1, rng=2)[0])
    a = robot.ik(T)
    a.q[:] = 99.0
    b = robot.ik(T)
    assert b.success and np.abs(b.q).max() < 2 * np.pi


def test_single_call_results_stay_frozen_and_settings_are_still_checked():
    """The light result construction keeps IKResult immutable; the shortcut for the default settings
    neither skips the checks of other values nor changes the answer when the defaults are spelled out."""
    import dataclasses

    robot = load_arm("ur5")[0]
    T = robot.fk(robot.random_q(1, rng=4)[0])
    res = robot.ik(T)
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.success = False
    spelled = robot.ik(T, tol_position=1e-9, tol_orientation=1e-9, max_iterations=40, restarts=200)
    assert_same(spelled, robot.ik(T[None]), 0)
    np.testing.assert_array_equal(spelled.q, res.q)
    for bad in (np.array([1e-9, 1e-9]), -1.0, float("nan")):
        with pytest.raises(robkin.InputError, match="tol_position"):
            robot.ik(T, tol_position=bad)


def assert_same_solutions(single, batch, i: int) -> None:
    """With all_solutions: the single call's solutions are the batch's for target i, exactly."""
    assert_same(single, batch, i)
    np.testing.assert_array_equal(single.solutions, batch.solutions[i])
    assert single.solutions.dtype == np.float64 and single.solutions.ndim == 2


@pytest.mark.parametrize("name", ["ur5", "kinova", "scara"])
def test_single_calls_with_all_solutions_equal_the_batch(name):
    robot = robkin.load(SCARA) if name == "scara" else load_arm(name)[0]
    T, q0 = targets_and_starts(robot, 25, seed=11)
    for kw_batch, kw_single in (({"q0": q0}, lambda i: {"q0": q0[i]}), ({}, lambda i: {})):
        batch = robot.ik(T, all_solutions=True, **kw_batch)
        assert 0 < batch.success.sum() < len(T)
        for i in range(len(T)):
            single = robot.ik(T[i], all_solutions=True, **kw_single(i))
            if batch.success[i]:
                assert_same_solutions(single, batch, i)
                assert len(single.solutions) >= 1
                np.testing.assert_array_equal(single.q, single.solutions[0])    # nearest first
            else:
                assert_same(single, batch, i)


@pytest.mark.parametrize("name", ["ur5", "kinova", "scara"])
def test_the_block_check_of_all_branches_equals_the_one_by_one_check(name):
    """With all_solutions every candidate branch of a target is checked in one block FK walk, without
    it one walk per branch, nearest first, until one counts: the chosen q, success and errors must be
    the same bits (a configuration gets the same bits in a block as alone), batch and single call."""
    robot = robkin.load(SCARA) if name == "scara" else load_arm(name)[0]
    T, q0 = targets_and_starts(robot, 25, seed=17)
    every, first = robot.ik(T, q0=q0, all_solutions=True), robot.ik(T, q0=q0)
    assert 0 < first.success.sum() < len(T)
    for i in range(len(T)):
        assert_same(robot.ik(T[i], q0=q0[i], all_solutions=True), first, i)
        assert_same(robot.ik(T[i], q0=q0[i]), every, i)


def test_scara_takes_the_single_target_kernel_path():
    """The SCARA solver answers one target in one compiled call, like the 6R solvers: the kernel's
    entry gives the result itself, and Robot.ik(T) without q0 equals the batch's row."""
    from robkin.kinematics.closed_form import closed_form_solver
    from robkin.kinematics.ik import IKResult

    robot = robkin.load(SCARA)
    T = robot.fk(robot.random_q(12, rng=5))
    batch = robot.ik(T)
    solver = closed_form_solver(robot)
    assert solver.name == "scara" and batch.success.all()
    for i in range(len(T)):
        direct = solver.nearest(T[i], None, 1e-9, 1e-9, False, 1e-6, IKResult, "scara")
        assert isinstance(direct, IKResult)
        assert_same(direct, batch, i)
        assert_same(robot.ik(T[i]), batch, i)
    # out of reach: no result from the kernel's entry (the general path explains the failure)
    far = T[0].copy()
    far[:3, 3] *= 100.0
    assert solver.nearest(far, None, 1e-9, 1e-9, False, 1e-6, IKResult, "scara") is None
    assert not robot.ik(far).success and "reach" in robot.ik(far).message


@pytest.mark.filterwarnings("ignore:.*projected onto the nearest rotation")
@pytest.mark.parametrize("name", ["ur5", "scara"])
def test_inputs_the_compiled_entry_declines_give_the_same_answer(name):
    """Targets as nested lists, float32, Fortran order or nearly orthonormal (projected), and integer
    tolerances leave the one-call path; the general path must answer exactly as the batch does."""
    robot = robkin.load(SCARA) if name == "scara" else load_arm(name)[0]
    T = robot.fk(robot.random_q(1, rng=21)[0])
    reference = robot.ik(T[None])
    for variant in (T.tolist(), np.asfortranarray(T), T.astype(np.float32).astype(np.float64)):
        assert_same(robot.ik(variant), robot.ik(np.asarray(variant)[None]), 0)
    assert robot.ik(T.astype(np.float32)).success
    assert_same(robot.ik(T, tol_position=1, tol_orientation=1), robot.ik(T[None], tol_position=1,
                                                                       tol_orientation=1), 0)
    near = T.copy()
    near[:3, :3] *= 1.0 + 1e-9                  # not orthonormal to 1e-12: projected by check_pose
    assert_same(robot.ik(near), robot.ik(near[None]), 0)
    assert_same(robot.ik(T), reference, 0)


def test_batch_solutions_are_the_distinct_verified_branches():
    """nearest_verified's per-target solutions (all distinct verified branches, nearest first) equal
    distinct_sorted's definition applied to the branches that reach the target, including the
    duplicates of singular targets (wrist axes aligned: several branches coincide)."""
    from robkin.compiled.ik.solutions import distinct_sorted
    from robkin.kinematics.closed_form import closed_form_solver
    from robkin.kinematics.ik import SAME_SOLUTION_TOL
    from robkin.kinematics.limits import within_limits

    robot = load_arm("ur5")[0]
    q = robot.random_q(30, rng=13)
    q[::3, 4] = 0.0                             # axis 6 parallel to axis 4: a wrist singularity
    T = robot.fk(q)
    ref = robot.random_q(30, rng=14)
    res = robot.ik(T, q0=ref, all_solutions=True)
    branches = closed_form_solver(robot).solve(T, ref)
    unit = np.where(robot.revolute, 1.0, robot.scale)
    for i in range(len(T)):
        Q = branches.q[i][branches.valid[i] & within_limits(branches.q[i], robot.limits)]
        reached = Q[np.array([np.abs(robot.fk(x) - T[i]).max() < 1e-8 for x in Q], bool).reshape(-1)]
        expected = distinct_sorted(reached, ref[i], unit, SAME_SOLUTION_TOL)
        np.testing.assert_allclose(res.solutions[i], expected, atol=0)


def test_the_solver_cache_neither_keeps_robots_alive_nor_mixes_them_up():
    """closed_form_solver caches per robot by identity: a robot that goes away is dropped (its solver
    does not keep it alive), and a new robot gets its own solver."""
    import gc
    import weakref

    from robkin.kinematics import closed_form

    robot = robkin.load(SCARA)
    T = robot.fk(robot.random_q(1, rng=1)[0])
    assert robot.ik(T).success
    solver = closed_form.closed_form_solver(robot)
    assert closed_form.closed_form_solver(robot) is solver
    gone = weakref.ref(robot)
    gc.collect()          # robots of earlier tests awaiting collection go first: only this one is counted
    before = len(closed_form._SOLVERS)
    del robot
    gc.collect()
    assert gone() is None and len(closed_form._SOLVERS) == before - 1
    other = robkin.load(SCARA)
    assert closed_form.closed_form_solver(other) is not solver
    assert closed_form.closed_form_solver(load_arm("ur5")[0]).name == "three-parallel-6r"


def test_single_calls_from_several_threads_give_the_serial_answers():
    """The one-call path keeps no per-robot scratch: threads sharing a robot get the serial results."""
    from concurrent.futures import ThreadPoolExecutor

    robot = load_arm("ur5")[0]
    T = robot.fk(robot.random_q(200, rng=17))
    serial = [robot.ik(t, all_solutions=bool(i % 2)) for i, t in enumerate(T)]
    with ThreadPoolExecutor(4) as pool:
        threaded = list(pool.map(lambda i: robot.ik(T[i], all_solutions=bool(i % 2)), range(len(T))))
    for a, b in zip(serial, threaded):
        np.testing.assert_array_equal(a.q, b.q)
        if a.solutions is not None:
            np.testing.assert_array_equal(a.solutions, b.solutions)
