"""Pose planning (``robkin calibrate --plan N``): its time, and what 30 planned poses gain over 30 random ones.

Robots: UR5 and Franka Panda (example-robot-data), KUKA LBR iiwa 14 (tests/data/iiwa14.urdf). The truth
(``robkin.calibration.simulation.simulate``, the issue's set-up): every joint frame moved by ~1 mm and
~0.1 deg per component (zero offsets included), the base 1-2 m from the tracker at a random rotation, a
marker 2-8 cm off the flange, 10 um of noise per coordinate. Per draw: ``plan_poses`` (2000 random
candidates, D-optimal, the marker's position given) and the simulator's own 30 random configurations,
both measured on the same truth and calibrated by ``robkin.calibrate`` (positions, base and marker
unknown); hold-out error = RMS distance between the calibrated and the true marker point on 1000 fresh
configurations.

Expected error from noise alone (the identification covariance, ``planning.expected_error``) on 2000
fresh configurations: the plan, the best design an exchange algorithm finds (``planning.best_design``:
I-optimal Fedorov exchange from the plan, the greedy I design and 3 random starts) and 30 random
candidates (mean of 50).

Time: CPU seconds of one ``plan_poses(robot, 30)`` (one thread, median of ``--rounds``).

Run: ``python benchmarks/bench_calibration_plan.py [--draws 20] [--rounds 3] [--robots ur5,panda,iiwa]``.
Exit status 0.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")  # one thread each: before numpy is imported

import argparse  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import robkin  # noqa: E402
from robkin.calibration import calibrate  # noqa: E402
from robkin.calibration.planning import best_design, design_problem, exchange, expected_error  # noqa: E402
from robkin.calibration.planning_poses import plan_poses  # noqa: E402
from robkin.calibration.simulation import prediction_error, random_configurations, simulate  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_fk import robots_dir  # noqa: E402

ROBOTS = {"ur5": ("ur_description/urdf/ur5_robot.urdf", "tool0"),
          "panda": ("panda_description/urdf/panda.urdf", "panda_link8"),
          "iiwa": (None, None)}
NOISE = 10e-6
POSES = 30
MARKER = np.array([0.02, 0.03, 0.05])


def load(name: str) -> robkin.Robot | None:
    rel, tip = ROBOTS[name]
    if rel is None:
        path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "data", "iiwa14.urdf")
    else:
        path = os.path.join(robots_dir(), rel)
    return robkin.load(path, tip_link=tip) if os.path.isfile(path) else None


def holdout(robot, truth, q, rng, fresh) -> float:
    T = truth.world @ truth.fk(q)
    result = calibrate(robot, q, T[:, :3, 3] + rng.normal(0.0, NOISE, (len(q), 3)))
    return float(np.sqrt(np.mean(prediction_error(result.robot, truth, fresh) ** 2)))


def draws(robot, count: int) -> tuple[np.ndarray, np.ndarray, float]:
    """Hold-out errors (count,) of planned and random poses over noise draws, and the median plan time."""
    planned, random_, times = [], [], []
    for k in range(count):
        sim = simulate(robot, POSES, offset=1e-3, angle=np.radians(0.1), noise=NOISE, seed=100 + k)
        rng = np.random.default_rng(1000 + k)
        fresh = random_configurations(robot, 1000, rng)
        t0 = time.thread_time()
        plan = plan_poses(robot, POSES, marker=sim.marker[:3, 3], noise=NOISE, seed=k)
        times.append(time.thread_time() - t0)
        planned.append(holdout(robot, sim.truth, plan.q, rng, fresh))
        random_.append(holdout(robot, sim.truth, sim.q, rng, fresh))
    return np.array(planned), np.array(random_), float(np.median(times))


def designs(robot) -> tuple[float, float, float]:
    """Expected errors (m) from noise alone: plan, best exchange design, random (mean of 50)."""
    rng = np.random.default_rng(5)
    problem = design_problem(robot, random_configurations(robot, 2000, rng), marker=MARKER)
    J = problem.J / problem.scale
    J_eval = problem.jacobians(random_configurations(robot, 2000, rng))
    plan = exchange(problem, POSES, "D")
    best = best_design(problem, POSES, starts=3)
    rand = np.mean([expected_error(J[rng.choice(len(J), POSES, replace=False)], J_eval, NOISE) for _ in range(50)])
    return expected_error(J[plan], J_eval, NOISE), expected_error(J[best], J_eval, NOISE), float(rand)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--draws", type=int, default=20, help="noise draws per robot (default 20)")
    parser.add_argument("--rounds", type=int, default=3, help="timing rounds of plan_poses (default 3)")
    parser.add_argument("--robots", default=",".join(ROBOTS), help="comma-separated: " + ", ".join(ROBOTS))
    args = parser.parse_args(argv)
    print(f"{'robot':<6} {'joints':>6} {'plan s':>7} {'held-out planned um':>20} {'random um':>10} {'ratio':>6} "
          f"{'planned better':>14} | {'expected plan um':>16} {'best um':>8} {'random um':>10} {'plan/best':>9} "
          f"{'random/best':>11}")
    for name in args.robots.split(","):
        robot = load(name)
        if robot is None:
            print(f"{name}: robot file not installed")
            continue
        times = []
        for _ in range(args.rounds):
            t0 = time.thread_time()
            plan_poses(robot, POSES, marker=MARKER, noise=NOISE)
            times.append(time.thread_time() - t0)
        p, r, _ = draws(robot, args.draws)
        e_plan, e_best, e_rand = designs(robot)
        print(f"{name:<6} {robot.n:>6} {np.median(times):7.2f} {p.mean() * 1e6:20.2f} {r.mean() * 1e6:10.2f} "
              f"{p.mean() / r.mean():6.3f} {f'{int((p < r).sum())}/{len(p)}':>14} | {e_plan * 1e6:16.2f} "
              f"{e_best * 1e6:8.2f} {e_rand * 1e6:10.2f} {e_plan / e_best:9.3f} {e_rand / e_best:11.3f}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
