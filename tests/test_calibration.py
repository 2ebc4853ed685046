"""Kinematic calibration: simulated truth for UR5, Panda, iiwa and xArm7, judged on fresh configurations.

The truth moves every joint frame by ~1 mm and ~1 mrad (zero offsets included), stands 1-2 m from the
measuring frame at a random rotation and carries a marker 2-8 cm off the flange; 60 poses with 20 um
(and 0.005 deg) noise. The yardstick is ``reference_fit``: Gauss-Newton over the very parameterisation
that made the truth (independent of ``calibrate``'s models, Jacobians and solver), whose error is what
the noise allows. The calibrated model must come within 1.5x of it and beat the nominal model (with
its own best base and marker) 20-fold. The benchmark (benchmarks/bench_calibration.py) evaluates on
1000 configurations; 300 here give the RMS to ~4 % (enough for a 1.5x bound).
"""

from __future__ import annotations

import numpy as np
import pytest

import robkin
from robkin.calibration.parameters import build_model
from robkin.calibration.simulation import prediction_error, random_configurations, reference_fit, simulate
from robkin.io.urdf import robot_from_urdf
from test_urdf import robot_file

ROBOTS = {
    "ur5": ("ur_description/urdf/ur5_robot.urdf", "tool0"),
    "panda": ("panda_description/urdf/panda.urdf", "panda_link8"),
    "iiwa": (None, None),   # tests/data/iiwa14.urdf (example-robot-data has no iiwa)
    "xarm7": ("xarm_description/urdf/xarm7.urdf", None),
}
#: the simulated noise: 20 um per coordinate, 0.005 deg per axis; their ratio is the orientation weight
#: a maximum-likelihood fit uses (metres per radian)
NOISE, ANGLE_NOISE = 20e-6, np.radians(0.005)


def load(name: str) -> robkin.Robot:
    rel, tip = ROBOTS[name]
    if rel is None:
        import os

        return robot_from_urdf(os.path.join(os.path.dirname(__file__), "data", "iiwa14.urdf"))
    return robot_from_urdf(robot_file(rel), tip_link=tip)


def rms(model: robkin.Robot, truth: robkin.Robot, Q: np.ndarray) -> float:
    return float(np.sqrt(np.mean(prediction_error(model, truth, Q) ** 2)))


@pytest.mark.parametrize("kind", ["hayati", "mdh", "poe"])
@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_error_model_reproduces_fk_and_its_jacobian_matches_finite_differences(name, kind):
    robot = load(name)
    rng = np.random.default_rng(1)
    Q = rng.uniform(-2, 2, (4, robot.n))
    mdl = build_model(robot, kind, full_pose=True)
    T, _ = mdl.poses(mdl.nominal, Q)
    np.testing.assert_allclose(T, robot.fk(Q), atol=1e-12)
    p = mdl.nominal + rng.normal(0, 1e-3, mdl.size)
    T, J = mdl.poses(p, Q, jacobian=True)
    moved = mdl.robot_at(p)   # the robot the parameters describe: world @ fk is the chain's pose
    np.testing.assert_allclose(moved.world @ moved.fk(Q), T, atol=1e-12)
    h = 1e-6
    for k in range(mdl.size):
        e = np.zeros(mdl.size)
        e[k] = h
        Tp, Tm = mdl.poses(p + e, Q)[0], mdl.poses(p - e, Q)[0]
        dp = (Tp[:, :3, 3] - Tm[:, :3, 3]) / (2 * h)
        dw = robkin.se3.log_rotation(Tp[:, :3, :3] @ np.swapaxes(Tm[:, :3, :3], 1, 2)) / (2 * h)
        # central differences: truncation ~h^2 = 1e-12 times unit-size derivatives, rounding ~1e-16 / h
        np.testing.assert_allclose(J[:, :3, k], dp, atol=1e-8, err_msg=mdl.names[k])
        np.testing.assert_allclose(J[:, 3:, k], dw, atol=1e-8, err_msg=mdl.names[k])


@pytest.mark.parametrize("full", [False, True], ids=["positions", "full-poses"])
@pytest.mark.parametrize("name", list(ROBOTS))
def test_calibration_reaches_the_noise_limit(name, full):
    robot = load(name)
    sim = simulate(robot, 60, seed=11)
    ori = sim.orientations if full else None
    res = robkin.calibrate(robot, sim.q, sim.positions, ori)
    nominal = robkin.calibrate(robot, sim.q, sim.positions, ori, kinematics=False)
    ref = reference_fit(robot, sim.q, sim.positions, ori, nominal.robot, orientation_weight=NOISE / ANGLE_NOISE)
    Q = random_configurations(robot, 300, np.random.default_rng(5))
    got, limit, before = rms(res.robot, sim.truth, Q), rms(ref, sim.truth, Q), rms(nominal.robot, sim.truth, Q)
    assert got <= 1.5 * limit, f"{name}: {got * 1e6:.1f} um, noise limit {limit * 1e6:.1f} um"
    assert before >= 20 * got, f"{name}: only {before / got:.1f}x better than the nominal model"
    # world @ fk(q) predicts the measurement: the fit residuals are at the noise (20 um per coordinate)
    assert res.after_fit["position_rms"] < 2 * np.sqrt(3) * NOISE
    if full:
        assert res.after_fit["orientation_rms"] < 2 * np.sqrt(3) * ANGLE_NOISE
        # the estimated weight of orientation against position is the ratio of the noises
        assert 0.5 < res.orientation_weight / (NOISE / ANGLE_NOISE) < 2


@pytest.mark.parametrize("kind", ["hayati", "mdh", "poe"])
def test_ur5_parallel_axes_give_no_runaway_lengths(kind):
    robot = load("ur5")
    sim = simulate(robot, 60, seed=3)
    res = robkin.calibrate(robot, sim.q, sim.positions, model=kind)
    cal = res.robot
    size = robot.scale
    assert np.abs(cal.frames[:, :3, 3]).max() < 10 * size
    table = robkin.hayati_from_robot(cal)
    assert np.abs(table.rows[:, :2]).max() < 10 * size
    Q = random_configurations(robot, 200, np.random.default_rng(2))
    if kind == "mdh":
        # a modified DH row cannot tilt an axis out of the plane of its parallel neighbour (the reason
        # Hayati's rows exist): the fit stays bounded but cannot reach the noise
        assert rms(cal, sim.truth, Q) > 100e-6
        assert any("shoulder_lift_joint-elbow_joint" in w and "cannot represent" in w for w in res.warnings)
    else:
        assert rms(cal, sim.truth, Q) < 60e-6


def test_redundant_parameters_are_reported_in_words():
    robot = load("ur5")
    sim = simulate(robot, 40, seed=4)
    res = robkin.calibrate(robot, sim.q, sim.positions)
    text = " | ".join(res.unidentifiable)
    # the first joint's zero offset is a turn of the base about the same (vertical) axis
    assert "shoulder_pan_joint zero offset" in text and "base rz" in text
    assert "from positions alone" in text
    held = {p.name for p in res.parameters if not p.identified}
    assert len(held) == len(res.unidentifiable)
    assert all(p.std is not None and p.std > 0 for p in res.parameters if p.identified)


def test_outliers_are_rejected_and_listed_by_row():
    robot = load("panda")
    sim = simulate(robot, 60, seed=5)
    pos = sim.positions.copy()
    pos[17] += [0.004, 0.0, -0.003]
    rows = list(range(2, 62))   # file line numbers, header on line 1
    res = robkin.calibrate(robot, sim.q, pos, rows=rows)
    assert [r for r, _ in res.outliers] == [19]
    clean = robkin.calibrate(robot, sim.q, sim.positions)
    Q = random_configurations(robot, 200, np.random.default_rng(3))
    assert rms(res.robot, sim.truth, Q) < 1.3 * rms(clean.robot, sim.truth, Q)
    # plain least squares is dragged by the bad pose
    plain = robkin.calibrate(robot, sim.q, pos, loss="linear")
    assert rms(plain.robot, sim.truth, Q) > 3 * rms(res.robot, sim.truth, Q)


def test_known_base_and_marker_are_kept():
    robot = load("iiwa")
    sim = simulate(robot, 60, seed=6)
    marker = sim.marker[:3, 3]
    res = robkin.calibrate(robot, sim.q, sim.positions, world=sim.truth.world, marker=marker)
    np.testing.assert_array_equal(res.robot.world, sim.truth.world)
    assert not [p for p in res.parameters if p.group in ("base", "marker") and p.identified]
    Q = random_configurations(robot, 200, np.random.default_rng(4))
    assert rms(res.robot, sim.truth, Q) < 60e-6


def test_holdout_and_too_few_poses_warn():
    robot = load("ur5")
    sim = simulate(robot, 60, seed=7)
    res = robkin.calibrate(robot, sim.q, sim.positions, holdout=0.25)
    assert res.poses_fit == 45 and res.poses_holdout == 15
    assert res.after_holdout["position_rms"] < 0.1 * res.before_holdout["position_rms"]
    few = robkin.calibrate(robot, sim.q[:8], sim.positions[:8])
    assert any("measured values for" in w for w in few.warnings)
    Q = sim.q.copy()
    Q[:, 2] = 0.3 + 0.01 * np.sin(np.arange(60))   # the elbow barely moves
    T = sim.truth.world @ sim.truth.fk(Q)
    still = robkin.calibrate(robot, Q, T[:, :3, 3])
    assert any("elbow_joint moved over only" in w for w in still.warnings)


def test_bad_arguments_are_input_errors():
    robot = load("ur5")
    sim = simulate(robot, 10, seed=8)
    with pytest.raises(robkin.InputError, match="q: expected shape"):
        robkin.calibrate(robot, sim.q[:, :5], sim.positions)
    with pytest.raises(robkin.InputError, match="model 'dh2'"):
        robkin.calibrate(robot, sim.q, sim.positions, model="dh2")
    bad = sim.positions.copy()
    bad[3, 1] = np.nan
    with pytest.raises(robkin.InputError, match="positions: pose 4"):
        robkin.calibrate(robot, sim.q, bad)
    quats = np.tile([1.0, 0.0, 0.0, 0.0], (10, 1))
    quats[2] = [2.0, 0, 0, 0]
    with pytest.raises(robkin.InputError, match="pose 3: quaternion"):
        robkin.calibrate(robot, sim.q, sim.positions, quats)
    with pytest.raises(robkin.InputError, match="holdout"):
        robkin.calibrate(robot, sim.q, sim.positions, holdout=1.5)
