"""Batch IK on several threads: the same bits as one thread and as single calls (numeric and closed form).

The numeric batch (solve, turn into the limits, forward-kinematics check) and the closed-form batch
(branches, their check and choice) are compiled loops split over threads (issue 24). A target's answer
must not depend on the thread count nor on where it falls among the chunks the threads take (closed
form: chunks of 32 targets), and a batch row must be what a single call on that target gives.
"""

from __future__ import annotations

import os
import warnings

import numpy as np
import pytest

import robkin
from robkin.kinematics.closed_form import closed_form_solver
from robkin.kinematics.limits import default_preference
from robkin.kinematics.lock import locked_robot

import ik_arms as arms
from test_urdf import robot_file

FIELDS = ("q", "success", "iterations", "attempts", "position_error", "orientation_error")
#: rows at the edges of the closed-form kernels' chunks of 32 targets, and the last one
EDGES = (0, 1, 31, 32, 33, 63, 64, 299)


def same(a: robkin.IKResult, b: robkin.IKResult) -> None:
    """Every field of two batch results bit for bit (NaN where NaN)."""
    for name in FIELDS:
        assert np.array_equal(getattr(a, name), getattr(b, name), equal_nan=True), name
    assert a.method == b.method and a.message == b.message
    if a.solutions is not None or b.solutions is not None:
        assert len(a.solutions) == len(b.solutions)
        for x, y in zip(a.solutions, b.solutions):
            assert np.array_equal(x, y)


def targets_with_trouble(robot: robkin.Robot, N: int, seed: int) -> np.ndarray:
    """N targets: FK of random joint values, every 37th pushed out of reach, every 11th at a
    configuration with joints 3 and n-1 at zero (an elbow or wrist singularity on most arms)."""
    rng = np.random.default_rng(seed)
    Q = robot.random_q(N, rng)
    Q[::11, 2] = 0.0
    Q[::11, -2] = 0.0
    T = robot.fk(Q)
    T[::37, :3, 3] *= 3.0
    return T


@pytest.fixture(scope="module")
def panda() -> robkin.Robot:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return robkin.load(robot_file("panda_description/urdf/panda.urdf"), tip_link="panda_hand_tcp")


def test_numeric_batch_is_the_same_on_any_threads_with_restarts_and_failures(panda):
    T = targets_with_trouble(panda, 60, seed=1)
    one = panda.ik(T, method="numeric", restarts=20, threads=1)
    assert (~one.success).sum() >= 2 and (one.attempts > 1).sum() >= 2      # restarts and failures happen
    for t in (2, 3, None):
        same(panda.ik(T, method="numeric", restarts=20, threads=t), one)
    # masks and all_solutions (1 + restarts starts per target side by side) too
    same(panda.ik(T, mask="position", threads=2), panda.ik(T, mask="position", threads=1))
    few = T[:9]
    same(panda.ik(few, method="numeric", all_solutions=True, restarts=8, threads=2),
         panda.ik(few, method="numeric", all_solutions=True, restarts=8, threads=1))


def test_numeric_batch_rows_are_single_calls(panda):
    # the first attempt starts from the preference, whatever the row: a row solved by it (attempts 1)
    # is the single call bit for bit; row 0 is in every case (its restart stream is the single call's)
    T = targets_with_trouble(panda, 40, seed=2)
    batch = panda.ik(T, method="numeric", threads=2)
    rows = [0, *np.flatnonzero(batch.attempts == 1)[:12]]
    assert len(rows) >= 10
    for k in rows:
        one = panda.ik(T[k], method="numeric")
        assert np.array_equal(one.q, batch.q[k]) and one.success == batch.success[k]
        assert one.position_error == batch.position_error[k] and one.orientation_error == batch.orientation_error[k]
        assert one.iterations == batch.iterations[k] and one.message == batch.message[k]


def test_numeric_broadcast_preference_is_the_explicit_one(panda):
    # q0 omitted: one preference row serves every target (no copy); the same bits as N explicit rows
    T = targets_with_trouble(panda, 30, seed=3)
    q0 = np.tile(default_preference(panda.limits), (30, 1))
    same(panda.ik(T, method="numeric", restarts=10, threads=2), panda.ik(T, q0=q0, method="numeric", restarts=10))


def _closed_form_arms() -> dict:
    here = os.path.join(os.path.dirname(robkin.__file__), "examples")
    found = {"kr6 (spherical wrist)": robkin.load(os.path.join(here, "kr6_r700.yaml")),
             "scara": robkin.load(os.path.join(here, "scara.yaml")),
             "generic 6R (general)": arms.generic_6r(1),
             # the first three axes meet: the compiled reversed chain (closed_form_reversed)
             "iiwa, joint 7 locked (pieper reversed)": locked_robot(arms.iiwa(), (6,), (0.1,))}
    ur5 = arms.ur5()
    if ur5 is not None:
        found["ur5 (three parallel)"] = ur5
        found["ur5 calibrated (near class)"] = arms.perturbed(ur5, 1e-6, seed=0)
    return found


CLOSED = _closed_form_arms()


@pytest.mark.parametrize("name", sorted(CLOSED))
def test_closed_form_batch_is_the_same_on_any_threads_and_as_single_calls(name):
    robot = CLOSED[name]
    assert closed_form_solver(robot) is not None
    N = 300
    T = targets_with_trouble(robot, N, seed=4)
    one = robot.ik(T, threads=1)
    assert one.method != "numeric" and not one.success.all()   # some unreachable: NaN rows and messages
    for t in (2, 3, None):
        same(robot.ik(T, threads=t), one)
    every = robot.ik(T[:70], all_solutions=True, threads=1)
    same(robot.ik(T[:70], all_solutions=True, threads=2), every)
    # the batch's compiled passes alone, on two threads against one
    solver = closed_form_solver(robot)
    ref = np.tile(default_preference(robot.limits), (N, 1))
    a, b = solver.solve(T, ref, 1), solver.solve(T, ref, 2)
    assert np.array_equal(a.q, b.q, equal_nan=True) and np.array_equal(a.valid, b.valid) and a.reason == b.reason
    # rows at the chunks' edges against single calls (closed-form answers: no iterations)
    for k in EDGES:
        if one.success[k] and one.iterations[k] == 0:
            single = robot.ik(T[k])
            assert np.array_equal(single.q, one.q[k]) and single.position_error == one.position_error[k]
            assert single.orientation_error == one.orientation_error[k]
            s = robot.ik(T[k], all_solutions=True)
            assert np.array_equal(s.solutions, every.solutions[k]) if k < 70 else len(s.solutions) >= 1
