"""Batches of the dynamics kernels (blocks of 32 configurations, threads, portable and AVX2 builds) give
every configuration the very bits of its single call, on a 7R arm with a prismatic finger, the UR5 and a
random chain of revolute and prismatic joints with flipped axes and random inertials."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import robkin
from robkin import Joint, Robot, se3
from robkin.compiled.chain import kernels
from robkin.compiled.runtime import threads as compiled_threads
from test_dynamics import random_inertials
from test_urdf import robot_file

RUNS_AVX2 = kernels.cpu_has_avx2() and kernels.avx2_built()


def mixed_chain(prismatic_base: bool = False) -> Robot:
    """Six joints R P R R P R (P P R R P R with ``prismatic_base``: the mass matrix's last step down to
    the base is then the prismatic one), every other one flipped, random frames and two random
    inertials a body."""
    rng = np.random.default_rng(7)
    kinds = ["prismatic" if prismatic_base else "revolute", "prismatic", "revolute", "revolute", "prismatic",
             "revolute"]
    joints = tuple(Joint(f"j{i + 1}", kind, flip=i % 2 == 1) for i, kind in enumerate(kinds))
    frames = np.stack([se3.homogeneous(se3.matrix_from_rpy(rng.uniform(-3, 3, 3)), rng.normal(scale=0.3, size=3))
                       for _ in range(len(joints) + 1)])
    return random_inertials(Robot(frames, joints), rng)


@pytest.fixture(scope="module", params=["panda+finger", "ur5", "mixed", "mixed, prismatic base"])
def robot(request) -> Robot:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if request.param == "panda+finger":   # 7R + a prismatic finger
            return robkin.load(robot_file("panda_description/urdf/panda.urdf"), base_link="panda_link0",
                               tip_link="panda_leftfinger")
        if request.param == "ur5":
            return robkin.load(robot_file("ur_description/urdf/ur5_robot.urdf"), tip_link="tool0")
    return mixed_chain(prismatic_base=request.param == "mixed, prismatic base")


@pytest.fixture
def restore_kernels():
    before = kernels.active()
    yield
    kernels.use(before)


def batches(robot: Robot, N: int, seed: int, threads: int | None = 1) -> tuple[np.ndarray, ...]:
    rng = np.random.default_rng(seed)
    Q, QD, QDD = rng.uniform(-4, 4, size=(3, N, robot.n))
    return (Q, QD, QDD, robot.mass_matrix(Q, threads=threads), robot.gravity(Q, threads=threads),
            robot.inverse_dynamics(Q, QD, QDD, threads=threads))


@pytest.mark.parametrize("N", [1, 6, 31, 32, 33, 65])
def test_every_configuration_of_a_batch_equals_its_single_call(robot, N):
    """At and around the block edges, every row (not a sample) of every kernel's batch. The mass
    matrix's walk (crba_walk.h) takes a block's lanes 4 at a time, then the rest one by one (6 and 31: a lane
    group and 2 or 3 lanes left over)."""
    Q, QD, QDD, M, g, tau = batches(robot, N, N)
    assert M.shape == (N, robot.n, robot.n) and g.shape == tau.shape == (N, robot.n)
    for k in range(N):
        assert np.array_equal(M[k], robot.mass_matrix(Q[k])), k
        assert np.array_equal(g[k], robot.gravity(Q[k])), k
        assert np.array_equal(tau[k], robot.inverse_dynamics(Q[k], QD[k], QDD[k])), k
    # the composite bodies are merged in each lane as in a single call: M stays exactly symmetric
    assert np.array_equal(M, np.swapaxes(M, 1, 2))


@pytest.mark.skipif(not compiled_threads.compiled_with_openmp(), reason="built without OpenMP")
@pytest.mark.parametrize("N", [65, 1000])
def test_two_threads_give_the_bits_of_one(robot, N):
    one = batches(robot, N, 11, threads=1)
    two = batches(robot, N, 11, threads=2)
    for a, b in zip(one[3:], two[3:]):
        assert np.array_equal(a, b)


@pytest.mark.skipif(not RUNS_AVX2, reason="this CPU or build has no AVX2 kernels")
@pytest.mark.parametrize("N", [33, 257])
def test_avx2_and_portable_builds_give_the_same_bits(robot, restore_kernels, N):
    kernels.use("portable")
    portable = batches(robot, N, 13)
    kernels.use("avx2")
    avx2 = batches(robot, N, 13)
    for a, b in zip(portable[3:], avx2[3:]):
        assert np.array_equal(a, b), np.max(np.abs(a - b))
