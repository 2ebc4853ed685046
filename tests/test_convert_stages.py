"""The compiled stages of the DH / MDH conversions (``robkin.compiled.conversions.frames.convert_tables`` and
``check_tables``) against the NumPy functions they replaced (``rounding.snap_many``,
``link_table.residual_tool``, ``sample_configurations``, ``pose_difference``), bit for bit, and the
batch conversions on several threads against one thread, bit for bit."""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import robkin
from robkin import se3
from robkin.compiled.conversions.frames import check_tables, convert_tables, placement, robots_fk, tables_fk
from robkin.frame_stacks import frame_scales, local_transforms
from robkin.representations.frames import relative_pose
from robkin.representations.link_table import (_CHECK_SAMPLES, FLIP_X, pose_difference, residual_tool,
                                               sample_configurations)
from robkin.representations.rounding import snap_many, travel
from robkin.samples import unit_sample

from strategies import robot_specs

SETTINGS = dict(deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


def _numpy_matmul_is_an_fma_chain() -> bool:
    """Does this machine's NumPy ``@`` of 4x4 matrices sum each entry as a chain of fused multiply-adds
    (what the compiled residual tool reproduces; x86-64 OpenBLAS on FMA hardware)? Probed with values
    where a plain sum and a fused one differ."""
    a = np.zeros((4, 4))
    b = np.zeros((4, 4))
    a[0, :2] = [1.0, 1.0 + 2.0 ** -30]
    b[:2, 0] = [-1.0, 1.0 - 2.0 ** -30]
    # -1 + (1 - 2^-60): a plain product rounds the second term to 1 first, giving 0; a fused
    # multiply-add onto -1 keeps -2^-60
    return bool((a @ b)[0, 0] != 0.0)


def _numpy_stages(modified: bool, robots: list[robkin.Robot]):
    """The conversions' stages as NumPy computed them before they were compiled (placement.py)."""
    section = "mdh" if modified else "dh"
    frames = np.stack([r.frames for r in robots])
    scale = frame_scales(frames)
    revolute = np.stack([r.revolute for r in robots])
    limits = np.stack([r.limits for r in robots])
    flip = np.array([[j.flip for j in r.joints] for r in robots])
    cand = frames[:, :-1].copy()
    if flip.any():
        cand[flip] = cand[flip] @ FLIP_X
    F, rows = placement(modified, cand, frames[:, -1], scale, np.array([r.frames_from == section for r in robots]))
    base, last, tool_pose = F[:, 0], F[:, -1], frames[:, -1]
    snap = np.array([r.frames_from != section for r in robots])
    if snap.any():
        rows[snap] = snap_many(rows[snap], travel(revolute[snap], limits[snap]),
                               relative_pose(last[snap], tool_pose[snap]), scale[snap])
    tool = residual_tool(base, rows, se3.mdh_matrix if modified else se3.dh_matrix, tool_pose, scale)
    Q = sample_configurations(revolute, limits, scale)
    err = pose_difference(tables_fk(modified, base, rows, tool, revolute, np.where(flip, -1.0, 1.0), Q),
                          robots_fk(local_transforms(frames), revolute, Q), scale)
    lengths = np.maximum(np.abs(rows[..., :2]).max(axis=(1, 2)),
                         np.maximum(np.linalg.norm(base[:, :3, 3], axis=1), np.linalg.norm(tool[:, :3, 3], axis=1)))
    return rows, base, tool, err, lengths


def _compiled_stages(modified: bool, robots: list[robkin.Robot], threads: int = 1):
    section = "mdh" if modified else "dh"
    frames = np.stack([r.frames for r in robots])
    scale = frame_scales(frames)
    J = np.array([[(j.revolute, j.flip, -np.inf if j.lower is None else j.lower,
                    np.inf if j.upper is None else j.upper) for j in r.joints] for r in robots], dtype=float)
    rows, base, tool = convert_tables(modified, frames, J, [r.frames_from == section for r in robots],
                                      [r.frames_from != section for r in robots], scale, FLIP_X, threads)
    err, lengths = check_tables(modified, base, rows, tool, local_transforms(frames), J, scale,
                                unit_sample(_CHECK_SAMPLES, rows.shape[1]), threads)
    return rows, base, tool, err, lengths


def _limited(spec) -> robkin.Robot:
    """The drawn robot with limits on some joints (the check's sample and the rounding's travel use
    them), and read back as a DH table for some (its frames then kept, its rows not rounded)."""
    robot = spec.robot
    joints = [dataclasses.replace(j, lower=-0.5 * (i + 1), upper=0.3 * (i + 1)) if i % 2 else j
              for i, j in enumerate(robot.joints)]
    return robot.replace(joints=tuple(joints))


@pytest.mark.filterwarnings("ignore::robkin.errors.ConditioningWarning")
@settings(max_examples=60, **SETTINGS)
@given(specs=st.integers(1, 6).flatmap(lambda n: st.lists(robot_specs(min_joints=n, max_joints=n), min_size=1,
                                                             max_size=4)),
       modified=st.booleans(), tables=st.booleans())
def test_compiled_stages_match_numpys(specs, modified, tables):
    robots = [_limited(s) for s in specs]
    if tables:  # robots read from a table of the same kind: frames kept, nothing rounded
        convert = robkin.mdh_from_robot if modified else robkin.dh_from_robot
        robots = [convert(r).to_robot() for r in robots]
    want = _numpy_stages(modified, robots)
    got = _compiled_stages(modified, robots)
    names = ("rows", "base", "tool", "err", "lengths")
    scale = frame_scales(np.stack([r.frames for r in robots]))  # (N,) the robots' sizes
    for name, w, g in zip(names, want, got):
        if name in ("tool", "err", "lengths"):
            # NumPy's matrix products go through its BLAS, which sums each entry in an order of its own,
            # fused or not, per kernel, version, CPU and shape (OpenBLAS with AVX-512 gives 4.45e-36 where
            # the compiled stage gives 0.0, although its 4x4 probe above sees a chain of FMAs): the same
            # values to rounding, not the same bits, so lengths are compared relative to the robot's
            # size. 1e-13: ~500 ulps, above the rounding of a chain of at most 8 pose products, far below
            # any real difference of a tool pose. err (already relative to the size) is itself rounding
            # noise of FK through the table, so two summation orders agree on it only to the size of that
            # noise (observed: 1.79e-12 vs 1.63e-12 with NumPy 2.4's OpenBLAS; 6.78e-12 vs 5.56e-12 with
            # NumPy 1.24's, on a robot 2000 long, 2026-11-28): 5e-12 there, 4x the largest difference seen
            # and 20 times below the 1e-10 at which the conversion warns (link_table.WARN_TOL). Bit for
            # bit is kept between robkin's own paths (threads, batches: the tests below).
            w, g = np.array(w, dtype=float), np.array(g, dtype=float)
            if name == "tool":
                w[:, :3, 3] /= scale[:, None]
                g[:, :3, 3] /= scale[:, None]
            elif name == "lengths":
                w, g = w / scale, g / scale
            np.testing.assert_allclose(g, w, rtol=1e-13, atol=5e-12 if name == "err" else 1e-13, err_msg=name)
        else:
            # rows and base: bit for bit with this machine's OpenBLAS (its FMA kernels), but OpenBLAS's
            # Nehalem and Sandybridge kernels (no FMA; 2026-11-28) put the NumPy side 1 ulp off in a base
            # entry of 2.6e-33: compared as the tool, lengths (rows' first two columns, the base's
            # translation) relative to the robot's size, at 1e-13 (~500 ulps).
            w, g = np.array(w, dtype=float), np.array(g, dtype=float)
            if name == "rows":
                w[..., :2] /= scale[:, None, None]
                g[..., :2] /= scale[:, None, None]
            else:
                w[:, :3, 3] /= scale[:, None]
                g[:, :3, 3] /= scale[:, None]
            np.testing.assert_allclose(g, w, rtol=1e-13, atol=1e-13, err_msg=name)


def test_the_probe_tells_the_two_sums_apart():
    """The probe's values separate a plain sum from a fused one, and NumPy's product is one of the two.
    Which one is the BLAS's business (OpenBLAS's Haswell and SkylakeX kernels fuse; its Prescott, Nehalem
    and Sandybridge kernels, chosen by OPENBLAS_CORETYPE or on an older CPU, do not; 2026-11-28): nothing
    here asserts which."""
    a = np.array([1.0, 1.0 + 2.0 ** -30])
    b = np.array([-1.0, 1.0 - 2.0 ** -30])
    assert a[0] * b[0] + a[1] * b[1] == 0.0  # the plain sum loses the 2^-60
    A, B = np.zeros((4, 4)), np.zeros((4, 4))
    A[0, :2], B[:2, 0] = a, b
    assert (A @ B)[0, 0] in (0.0, -2.0 ** -60)
    assert _numpy_matmul_is_an_fma_chain() == ((A @ B)[0, 0] == -2.0 ** -60)


def _random_robots(count: int, n: int, seed: int) -> list[robkin.Robot]:
    rng = np.random.default_rng(seed)
    joints = [robkin.Joint(f"j{i + 1}", "prismatic" if i == 2 else "revolute", flip=i == 1) for i in range(n)]
    return [robkin.RPYTable(np.column_stack([rng.uniform(-3, 3, (n + 2, 3)), rng.uniform(-0.5, 0.5, (n + 2, 3))]),
                            joints).to_robot() for _ in range(count)]


@pytest.mark.parametrize("batch", [robkin.dh_from_robots, robkin.mdh_from_robots, robkin.hayati_from_robots])
def test_batches_on_two_threads_are_one_threads_bit_for_bit(batch):
    robots = _random_robots(150, 6, seed=3) + _random_robots(40, 3, seed=4)  # past the per-thread minimum
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # random axes may be nearly parallel: not the point here
        one, two = batch(robots, threads=1), batch(robots, threads=2)
    for a, b in zip(one, two):
        np.testing.assert_array_equal(a.rows, b.rows)
        np.testing.assert_array_equal(a.base, b.base)
        np.testing.assert_array_equal(a.tool, b.tool)


@pytest.mark.parametrize("batch", [robkin.dh_from_robots, robkin.mdh_from_robots, robkin.hayati_from_robots])
@pytest.mark.parametrize("threads", [0, -1, 1.5, True, "2"])
def test_a_bad_thread_count_is_one_clear_error(batch, threads):
    with pytest.raises(robkin.InputError, match="threads"):
        batch(_random_robots(1, 2, seed=0), threads=threads)


def _numpy_frame_stacks(frames: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``Robot.scale`` and ``Robot._local`` as the NumPy expressions of ``robkin.frame_stacks`` give them."""
    p, z = frames[:, :-1, :3, 3], frames[:, :-1, :3, 2]
    feet = p - np.einsum("bij,bij->bi", p, z)[..., None] * z
    s = np.maximum(np.linalg.norm(frames[:, -1, :3, 3], axis=-1), np.linalg.norm(feet, axis=-1).max(axis=-1))
    origins = np.linalg.norm(frames[:, :, :3, 3], axis=-1).max(axis=-1)
    s = np.where(s <= 1e-9 * origins, origins, s)
    s = np.maximum(s, 1e-3 * origins)
    L = np.empty_like(frames)
    L[:, 0] = frames[:, 0]
    L[:, 1:] = se3.inv(frames[:, :-1]) @ frames[:, 1:]
    return np.where(s > 0, s, 1.0), L


@settings(max_examples=60, **SETTINGS)
@given(specs=st.integers(1, 7).flatmap(lambda n: st.lists(robot_specs(min_joints=n, max_joints=n), min_size=1,
                                                             max_size=3)))
def test_compiled_frame_stacks_match_numpys(specs):
    frames = np.stack([s.robot.frames for s in specs])
    scale, L = _numpy_frame_stacks(frames)
    np.testing.assert_array_equal(frame_scales(frames), scale)  # no BLAS on either side: the same sums
    # L's NumPy side is a BLAS product (``@``): bit for bit with the compiled chain of fused multiply-adds
    # where OpenBLAS's kernel fuses too (Haswell, SkylakeX), not where it does not (Prescott, Nehalem,
    # Sandybridge: up to 2.3e-14 of the robot's size on 300 random robots, 2026-11-28). 1e-12 of the
    # size: ~40x that, far below any real difference of a link transform.
    np.testing.assert_allclose(local_transforms(frames), L, rtol=0, atol=1e-12 * float(scale.max()))
    np.testing.assert_array_equal(local_transforms(frames[0]), local_transforms(frames)[0])  # any leading shape
    assert specs[0].robot.scale == scale[0]
