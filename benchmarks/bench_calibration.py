"""Kinematic calibration: robkin against robotkinecal and pybotics on the same simulated measurements.

Robots: UR5, Franka Panda, xArm7 (example-robot-data) and KUKA LBR iiwa 14 (tests/data/iiwa14.urdf).
The truth (``robkin.calibration.simulation``): every joint's axis moved and its zero shifted (~1 mm,
~1 mrad per component), the robot standing 1-2 m from the measuring frame at a random rotation, a
marker 2-8 cm off the flange at a random orientation; 60 poses uniform in the joint limits, noise 20 um
per coordinate (and 0.005 deg per axis for full poses). Judged on 1000 fresh configurations: RMS
distance between the model's and the truth's predicted marker point in the measuring frame.

- robkin: ``robkin.calibrate`` from the raw measurements (base and marker unknown), default Hayati model.
- reference: ``simulation.reference_fit``, Gauss-Newton over the very parameterisation that made the
  truth, weighted by the true noise ratio: the noise limit.
- nominal: the nominal model with its best base and marker (``calibrate(..., kinematics=False)``).
- robotkinecal 0.1 (Li et al. 2016 POE, 4 parameters per joint): it has no measuring frame, so it
  gets the measurements in the robot base frame (mapped by the *true* base pose: a head start robkin
  does not get) and, for full poses, the true marker orientation as its start.
- pybotics 3.1 (modified DH, ``optimize_accuracy`` with scipy's least squares, positions only): the
  same head start; world, tool position and every MDH parameter free.

Times: CPU seconds of one calibration (median of interleaved rounds, one thread).
pybotics declares numpy < 2 but runs with numpy 2: ``pip install --no-deps pybotics``.

Run: ``python benchmarks/bench_calibration.py [--rounds 3] [--robots ur5,panda]``. Exit status 0.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")  # one thread each: before numpy is imported

import argparse  # noqa: E402
import contextlib  # noqa: E402
import io  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402

import robkin  # noqa: E402
from robkin import se3  # noqa: E402
from robkin.calibration.simulation import prediction_error, random_configurations, reference_fit, simulate  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_fk import robots_dir  # noqa: E402

ROBOTS = {"ur5": ("ur_description/urdf/ur5_robot.urdf", "tool0"),
          "panda": ("panda_description/urdf/panda.urdf", "panda_link8"),
          "iiwa": (None, None),
          "xarm7": ("xarm_description/urdf/xarm7.urdf", None)}
NOISE, ANGLE_NOISE = 20e-6, np.radians(0.005)


def load(name: str) -> robkin.Robot | None:
    rel, tip = ROBOTS[name]
    if rel is None:
        path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "data", "iiwa14.urdf")
    else:
        path = os.path.join(robots_dir(), rel)
    return robkin.load(path, tip_link=tip) if os.path.isfile(path) else None


def timed(fn, rounds: int):
    """(result, median CPU seconds) of fn over ``rounds`` calls."""
    times, out = [], None
    for _ in range(rounds):
        t0 = time.thread_time()
        out = fn()
        times.append(time.thread_time() - t0)
    return out, float(np.median(times))


def robotkinecal_fit(robot, q, pos_base, rot_base, marker_rot):
    """robotkinecal's calibration; returns a predictor of marker points in the robot base frame."""
    import roboticstoolbox as rtb
    from robotkinecal import SerialRobotKineCal
    from spatialmath import SE3

    # an ETS robot: the fixed transform to each joint frame, then the joint about its z (robotkinecal 0.1's
    # PoERobot path counts rtb's base and end links as joints, so the ETS path is the one that works)
    L = robot._local
    T0 = L[-1] @ (se3.homogeneous(marker_rot, np.zeros(3)) if rot_base is not None else np.eye(4))
    ets = rtb.ETS()
    for i in range(robot.n):
        ets = ets * rtb.ET.SE3(SE3(L[i], check=False)) * rtb.ET.Rz()
    model = rtb.Robot(ets * rtb.ET.SE3(SE3(T0, check=False)))
    cal = SerialRobotKineCal(model, ee_name=model.links[-1].name)
    obs = [p for p in pos_base] if rot_base is None else \
        [SE3(se3.homogeneous(R, p), check=False) for R, p in zip(rot_base, pos_base)]
    np.random.seed(0)   # robotkinecal draws random bases for its parameterisation
    cal.set_observations([x for x in q], obs)
    with contextlib.redirect_stdout(io.StringIO()):
        cal.solve()
    S = np.array([np.r_[s[3:], s[:3]] for s in cal.joint_screw_axis])   # spatialmath (v, w) -> (w, v)
    M = np.asarray(cal.zero_conf_EE_pose.A)

    def predict(Q):
        T = np.broadcast_to(np.eye(4), (len(Q), 4, 4))
        for i in range(len(S)):
            T = T @ se3.exp_twist(np.broadcast_to(S[i], (len(Q), 6)), Q[:, i])
        return (T @ M)[:, :3, 3]
    return predict


def pybotics_fit(robot, q, pos_base):
    """pybotics' calibration (positions only); returns a predictor of marker points in the base frame."""
    from pybotics.kinematic_chain import MDHKinematicChain
    from pybotics.optimization import OptimizationHandler, optimize_accuracy
    from pybotics.robot import Robot as PRobot
    from pybotics.tool import Tool
    from scipy.optimize import least_squares

    table = robkin.mdh_from_robot(robot)
    chain = MDHKinematicChain(np.array([[r[2], r[0], r[3], r[1]] for r in table.rows]))   # alpha, a, theta, d
    model = PRobot(chain, tool=Tool(table.tool.copy()), world_frame=table.base.copy())
    handler = OptimizationHandler(robot=model, kinematic_chain_mask=True, tool_mask=[True] * 3 + [False] * 3,
                                  world_mask=True)
    x0 = handler.generate_optimization_vector()
    res = least_squares(optimize_accuracy, x0, args=(handler, q, pos_base))
    handler.apply_optimization_vector(res.x)
    fitted = handler.robot
    return lambda Q: np.array([fitted.fk(x)[:3, 3] for x in Q])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3, help="timed rounds per method (median)")
    parser.add_argument("--robots", default=",".join(ROBOTS), help="comma-separated: " + ", ".join(ROBOTS))
    parser.add_argument("--evaluate", type=int, default=1000, help="fresh configurations to judge on")
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    have = {}
    for peer in ("robotkinecal", "pybotics"):
        try:
            __import__(peer)
            have[peer] = True
        except ImportError:
            have[peer] = False
            print(f"{peer} is not installed: left out")
    robkin.calibrate  # noqa: B018 - import the calibration modules (and scipy) before timing
    print(f"{'robot':<7} {'data':<10} {'method':<13} {'RMS um':>9} {'x noise lim':>11} {'max um':>9} "
          f"{'time s':>8}")
    for name in args.robots.split(","):
        robot = load(name)
        if robot is None:
            print(f"{name}: robot file not installed")
            continue
        sim = simulate(robot, 60, seed=2026)
        Qe = random_configurations(robot, args.evaluate, np.random.default_rng(7))
        truth_pts = (sim.truth.world @ sim.truth.fk(Qe))[:, :3, 3]
        W = sim.truth.world
        pos_base = (sim.positions - W[:3, 3]) @ W[:3, :3]
        rot_base = np.einsum("ji,njk->nik", W[:3, :3], sim.orientations)
        for full in (False, True):
            ori = sim.orientations if full else None
            rows = []
            res, t = timed(lambda: robkin.calibrate(robot, sim.q, sim.positions, ori), args.rounds)
            rows.append(("robkin", prediction_error(res.robot, sim.truth, Qe), t))
            nominal = robkin.calibrate(robot, sim.q, sim.positions, ori, kinematics=False)
            ref, t = timed(lambda: reference_fit(robot, sim.q, sim.positions, ori, nominal.robot,
                                                 orientation_weight=NOISE / ANGLE_NOISE), 1)
            rows.append(("reference", prediction_error(ref, sim.truth, Qe), t))
            rows.append(("nominal", prediction_error(nominal.robot, sim.truth, Qe), float("nan")))
            if have["robotkinecal"]:
                pred, t = timed(lambda: robotkinecal_fit(robot, sim.q, pos_base, rot_base if full else None,
                                                          sim.marker[:3, :3]), args.rounds)
                rows.append(("robotkinecal", np.linalg.norm((pred(Qe) @ W[:3, :3].T + W[:3, 3]) - truth_pts, axis=1), t))
            if have["pybotics"] and not full:
                pred, t = timed(lambda: pybotics_fit(robot, sim.q, pos_base), 1)
                rows.append(("pybotics", np.linalg.norm((pred(Qe) @ W[:3, :3].T + W[:3, 3]) - truth_pts, axis=1), t))
            limit = float(np.sqrt(np.mean(rows[1][1] ** 2)))
            for method, err, t in rows:
                r = float(np.sqrt(np.mean(err ** 2)))
                print(f"{name:<7} {'full pose' if full else 'positions':<10} {method:<13} {r * 1e6:9.2f} "
                      f"{r / limit:11.2f} {err.max() * 1e6:9.1f} {t:8.3f}", flush=True)
            big = np.abs(res.robot.frames[:, :3, 3]).max() / robot.scale
            print(f"{'':<7} {'':<10} robkin: largest frame origin {big:.2f} robot sizes; "
                  f"{sum(p.identified for p in res.parameters)} parameters identified", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
