"""The two builds of the batch block kernels (portable and AVX2, ``robkin.compiled.chain.kernels``): the same
bits on random batches for every batch kernel, and the choice made at import from the CPU."""

from __future__ import annotations

import os
import subprocess
import sys
import warnings

import numpy as np
import pytest

import robkin
from robkin.compiled.chain import kernels
from test_urdf import robot_file

RUNS_AVX2 = kernels.cpu_has_avx2() and kernels.avx2_built()


@pytest.fixture(scope="module")
def panda() -> robkin.Robot:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return robkin.load(robot_file("panda_description/urdf/panda.urdf"), base_link="panda_link0",
                           tip_link="panda_leftfinger")      # 7R + a prismatic finger


@pytest.fixture
def restore_kernels():
    before = kernels.active()
    yield
    kernels.use(before)


def batch_results(robot: robkin.Robot, N: int, seed: int) -> list[np.ndarray]:
    """Every batch kernel on one thread at N random configurations (angles beyond +-pi included, so
    every quadrant of the sine/cosine reduction is hit)."""
    rng = np.random.default_rng(seed)
    Q = rng.uniform(-7.0, 7.0, (N, robot.n))
    QD, QDD = (rng.normal(size=(N, robot.n)) for _ in range(2))
    return [robot.fk(Q, threads=1), robot.frames_at(Q, threads=1), robot.jacobian(Q, threads=1),
            robot.jacobian(Q, "space", threads=1), robot.jacobian(Q, "body", threads=1),
            robot.inverse_dynamics(Q, QD, QDD, threads=1), robot.gravity(Q, threads=1),
            robot.mass_matrix(Q, threads=1), Q]


@pytest.mark.skipif(not RUNS_AVX2, reason="this CPU or build has no AVX2 kernels")
@pytest.mark.parametrize("N, seed", [(2, 0), (33, 1), (1000, 2)])   # a short block, a tail of one, many
def test_avx2_and_portable_kernels_give_the_same_bits(panda, restore_kernels, N, seed):
    kernels.use("portable")
    portable = batch_results(panda, N, seed)
    kernels.use("avx2")
    avx2 = batch_results(panda, N, seed)
    names = ["fk", "frames", "jacobian", "space jacobian", "body jacobian", "inverse dynamics", "gravity",
             "mass matrix"]
    for name, a, b in zip(names, portable, avx2):
        assert a.shape == b.shape and a.shape[0] == N, name
        assert np.array_equal(a, b), f"{name}: the builds differ by {np.max(np.abs(a - b))}"
    Q = portable[-1]
    for k in (0, N - 1):         # and the single calls (inlined portable path) agree with both
        assert np.array_equal(panda.fk(Q[k]), avx2[0][k])
        assert np.array_equal(panda.jacobian(Q[k], "body"), avx2[4][k])
        assert np.array_equal(panda.mass_matrix(Q[k]), avx2[7][k])


@pytest.mark.skipif(not RUNS_AVX2, reason="this CPU or build has no AVX2 kernels")
def test_threads_and_builds_together_give_the_same_bits(panda, restore_kernels):
    Q = panda.random_q(3000, rng=5)
    kernels.use("portable")
    one = panda.jacobian(Q, threads=1)
    kernels.use("avx2")
    assert np.array_equal(panda.jacobian(Q, threads=2), one)


def test_choice_falls_back_to_portable_without_avx2():
    # a CPU without AVX2, simulated: whatever was asked, the portable kernels run
    assert kernels.choose("auto", cpu_avx2=False, built=True) == ("portable", None)
    chosen, why = kernels.choose("avx2", cpu_avx2=False, built=True)
    assert chosen == "portable" and "this CPU has no AVX2" in why
    chosen, why = kernels.choose("avx2", cpu_avx2=True, built=False)
    assert chosen == "portable" and "built without" in why
    assert kernels.choose("auto", cpu_avx2=True, built=False) == ("portable", None)
    # with AVX2 and the build: AVX2 unless the portable build is asked for
    assert kernels.choose("", cpu_avx2=True, built=True) == ("avx2", None)
    assert kernels.choose(" AVX2 ", cpu_avx2=True, built=True) == ("avx2", None)
    assert kernels.choose("portable", cpu_avx2=True, built=True) == ("portable", None)
    chosen, why = kernels.choose("sse9", cpu_avx2=False, built=True)
    assert chosen == "portable" and "'sse9' is not one of auto, portable, avx2" in why


def test_import_on_a_cpu_without_avx2_runs_the_portable_kernels(panda, restore_kernels, monkeypatch):
    """The import-time choice (``_from_environment``) with the CPU check answering no, as on a CPU
    without AVX2: the portable kernels, a warning when AVX2 was asked for, and the same batch results."""
    Q = panda.random_q(100, rng=9)
    expected = panda.jacobian(Q, threads=1)
    monkeypatch.setattr(kernels, "cpu_has_avx2", lambda: False)
    monkeypatch.setenv("ROBKIN_KERNELS", "auto")
    assert kernels._from_environment() == "portable" == kernels.active()
    monkeypatch.setenv("ROBKIN_KERNELS", "avx2")
    with pytest.warns(RuntimeWarning, match="this CPU has no AVX2: using the portable kernels"):
        assert kernels._from_environment() == "portable" == kernels.active()
    assert np.array_equal(panda.jacobian(Q, threads=1), expected)
    with pytest.raises(RuntimeError, match="this CPU has no AVX2"):
        kernels.use("avx2")


def test_use_checks_its_argument(restore_kernels):
    with pytest.raises(ValueError, match="expected one of auto, portable, avx2"):
        kernels.use("fast")
    assert kernels.use("portable") == "portable" == kernels.active()
    if RUNS_AVX2:
        assert kernels.use("auto") == "avx2"
    else:
        with pytest.raises(RuntimeError, match="using the portable kernels"):
            kernels.use("avx2")


def run_with(value: str) -> subprocess.CompletedProcess:
    code = "from robkin.compiled.chain import kernels; print(kernels.active())"
    env = {**os.environ, "ROBKIN_KERNELS": value}
    return subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)


def test_environment_variable_is_read_at_import():
    assert run_with("portable").stdout.strip() == "portable"
    expected = "avx2" if RUNS_AVX2 else "portable"
    assert run_with("auto").stdout.strip() == expected
    bad = run_with("sse9")
    assert bad.stdout.strip() == expected and "ROBKIN_KERNELS='sse9' is not one of" in bad.stderr
