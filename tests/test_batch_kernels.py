"""The compiled core's block kernels: their sin/cos, and batches against single calls and pinocchio.

FK, frames and Jacobians walk blocks of configurations together (``fk.pxd``: 64 at a time) with a
vectorisable sin/cos (``sincos.h``); one configuration is a block of one. So: the sin/cos is checked
against glibc's (``math.sin``/``math.cos``) over more than a million arguments, a batch must equal the
single calls bit for bit, and batches whose sizes sit on and around the block edges must match pinocchio,
on random chains with revolute and prismatic joints and tilted axes.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from robkin.compiled.chain.fk import sincos
from robkin.kinematics.jacobian import jacobian_body, jacobian_geometric, jacobian_space
from test_pinocchio_fk import FK_TOL, chain_urdf, random_chain, robot_by_hand

#: sizes around the block edges (64) and a multi-block batch
SIZES = (1, 2, 31, 32, 33, 63, 64, 65, 129, 1000)
JACOBIANS = (jacobian_geometric, jacobian_space, jacobian_body)


def ulp_error(got: np.ndarray, ref: np.ndarray) -> np.ndarray:
    """|got - ref| in units of the spacing of doubles at ref (0 where both are equal)."""
    return np.abs(got - ref) / np.spacing(np.abs(ref))


def test_sincos_is_within_one_ulp_of_glibc():
    rng = np.random.default_rng(7)
    near = np.arange(-63662, 63663) * (np.pi / 2)                # the doubles nearest k pi/2 and neighbours
    x = np.concatenate([
        rng.uniform(-4 * np.pi, 4 * np.pi, 1_000_000),          # joint angles
        rng.uniform(-1e5, 1e5, 100_000),                       # up to the reduction's bound
        10.0 ** rng.uniform(-300, 0, 50_000) * rng.choice([-1.0, 1.0], 50_000),   # tiny
        near, np.nextafter(near, np.inf), np.nextafter(near, -np.inf),
        np.pi / 4 * np.arange(-64, 65),                        # octant edges, where |r| is largest
    ])
    s, c = sincos(x)
    ref_s = np.array([math.sin(v) for v in x])
    ref_c = np.array([math.cos(v) for v in x])
    assert ulp_error(s, ref_s).max() <= 1.0
    assert ulp_error(c, ref_c).max() <= 1.0


def test_sincos_symmetry_special_values_and_libm_beyond_the_bound():
    rng = np.random.default_rng(8)
    x = rng.uniform(-20, 20, 10_000)
    s, c = sincos(x)
    s_neg, c_neg = sincos(-x)
    assert np.array_equal(s_neg, -s) and np.array_equal(c_neg, c)    # odd and even exactly
    assert np.all(s * s + c * c - 1.0 <= 4e-16)                     # a few roundings of numbers <= 1
    s, c = sincos(np.array([0.0, -0.0, 1e-300]))                     # (sin -0 comes out +0, unlike libm)
    assert np.array_equal(s, [0.0, 0.0, 1e-300]) and np.array_equal(c, [1.0, 1.0, 1.0])
    big = np.array([1e5 + 0.5, -3e5, 1e22, 2.0**60])                  # beyond 1e5: libm's values
    s, c = sincos(big)
    assert np.array_equal(s, [math.sin(v) for v in big]) and np.array_equal(c, [math.cos(v) for v in big])
    s, c = sincos(np.array([np.inf, -np.inf, np.nan]))
    assert np.isnan(s).all() and np.isnan(c).all()


def test_sincos_patches_one_far_argument_in_any_lane():
    """The libm patch runs only when the vectorised loop flagged an argument beyond the bound: one such
    argument (or a non-finite one) in any lane of a call, vector body or remainder, is still patched,
    and its neighbours keep their values."""
    rng = np.random.default_rng(9)
    for size in (1, 2, 3, 4, 5, 7, 8, 9, 31, 32, 33):       # sincos calls the kernel on 32 at a time
        x = rng.uniform(-4, 4, size)
        s0, c0 = sincos(x)
        for lane in range(size):
            for far in (3e5, -1e22, np.inf, np.nan):
                y = x.copy()
                y[lane] = far
                s, c = sincos(y)
                others = np.arange(size) != lane
                assert np.array_equal(s[others], s0[others]) and np.array_equal(c[others], c0[others])
                if np.isfinite(far):
                    assert s[lane] == math.sin(far) and c[lane] == math.cos(far)
                else:
                    assert np.isnan(s[lane]) and np.isnan(c[lane])


@pytest.fixture(scope="module", params=[(3, 7), (11, 5), (23, 9)], ids=["7 joints", "5 joints", "9 joints"])
def chain(request):
    """A random URDF chain (revolute and prismatic joints, tilted axes) in robkin and in pinocchio."""
    pin = pytest.importorskip("pinocchio")
    seed, n = request.param
    rng = np.random.default_rng(seed)
    origins, axes, types, tool = random_chain(rng, n, 1.0)
    types[1] = "prismatic"                                     # at least one of each kind
    types[2] = "revolute"
    model = pin.buildModelFromXML(chain_urdf(origins, axes, types, tool))
    return robot_by_hand(origins, axes, types, tool), model, rng


def test_batches_equal_single_calls_bit_for_bit(chain):
    robot, _, rng = chain
    Q = rng.uniform(-4, 4, size=(max(SIZES), robot.n))
    Q[5, 0] = 2e5                                              # one angle past sincos' bound: libm's path
    T, F = robot.fk(Q), robot.frames_at(Q)
    Js = [f(robot, Q) for f in JACOBIANS]
    for k in (0, 5, 31, 32, 63, 64, 65, 999):
        assert np.array_equal(T[k], robot.fk(Q[k]))
        assert np.array_equal(F[k], robot.frames_at(Q[k]))
        for f, J in zip(JACOBIANS, Js):
            assert np.array_equal(J[k], f(robot, Q[k])), f.__name__
    for N in SIZES:                                            # every block length and remainder
        assert np.array_equal(robot.fk(Q[:N]), T[:N])
        assert np.array_equal(robot.frames_at(Q[:N]), F[:N])
        for f, J in zip(JACOBIANS, Js):
            assert np.array_equal(f(robot, Q[:N]), J[:N]), f.__name__


@pytest.mark.parametrize("N", SIZES)
def test_batches_at_the_block_edges_match_pinocchio(chain, N):
    pin = pytest.importorskip("pinocchio")
    robot, model, rng = chain
    data = model.createData()
    tool_id = model.getFrameId("tool")
    Q = rng.uniform(-4, 4, size=(N, robot.n))
    T, F = robot.fk(Q), robot.frames_at(Q)
    J = [f(robot, Q) for f in JACOBIANS]
    swap = np.r_[3:6, 0:3]                                     # pinocchio's rows are (v, w); space/body (w, v)
    references = ((pin.LOCAL_WORLD_ALIGNED, slice(None)), (pin.WORLD, swap), (pin.LOCAL, swap))
    lever = robot.scale + float(np.abs(F[..., :3, 3]).max())   # linear rows scale with the lever arms
    for k in range(0, N, max(1, N // 40)):
        pin.computeJointJacobians(model, data, Q[k])
        pin.updateFramePlacements(model, data)
        np.testing.assert_allclose(T[k], data.oMf[tool_id].homogeneous, rtol=0, atol=FK_TOL * lever)
        for i in range(robot.n):
            np.testing.assert_allclose(F[k, i, :3, 3], data.oMi[i + 1].translation, rtol=0, atol=FK_TOL * lever)
        for Jk, (frame, rows) in zip(J, references):
            ref = pin.getFrameJacobian(model, data, tool_id, frame)[rows]
            np.testing.assert_allclose(Jk[k], ref, rtol=0, atol=FK_TOL * lever)
