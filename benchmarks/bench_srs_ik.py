"""SRS arms by arm angle (``Robot.ik(T, arm_angle=psi, all_solutions=True)``) against the numeric solver and
the locked-joint closed form on the same targets.

Arms: KUKA iiwa 14 (the test data URDF) and a Kinova Gen3 from its published DH table with the 11.8 mm /
12.8 mm offsets removed (the SRS arm it is built around; ``tests/test_ik_srs.py``). Targets: FK of random
joint values within the limits; the arm angle asked for is the generating configuration's.

Rows, time per target (CPU time of this process, one thread, medians of interleaved rounds):

- ``srs arm angle``: every solution at that arm angle (up to 8), one target per call and on the batch;
- ``lock q3``: ``ik(T, lock={joint 3: its generating value}, all_solutions=True)``, the general closed
  form of the locked 6R arm (another way to fix the redundancy; up to 16 solutions);
- ``numeric``: ``ik(T, method='numeric')``, one solution per target (default restarts).

Also counted: how often the generating configuration is among the arm-angle solutions.

Run: ``.venv/bin/python benchmarks/bench_srs_ik.py [--targets 300] [--rounds 3]``. Exit status 0.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")  # one thread each: before numpy is imported

import argparse
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))

import ik_arms as arms  # noqa: E402
from test_ik_srs import gen3_ideal  # noqa: E402
from robkin.kinematics.srs_geometry import arm_angle_of  # noqa: E402


def _clock() -> float:
    """CPU time of this process: the machine is shared."""
    return time.process_time()


def run_arm(name: str, robot, n: int, rounds: int, numeric: int) -> None:
    q = robot.random_q(n, rng=1)
    T = robot.fk(q)
    psi = arm_angle_of(robot, q)
    j3 = robot.joints[2].name
    found = 0
    res = robot.ik(T, arm_angle=psi, all_solutions=True)
    for k, s in enumerate(res.solutions):
        found += bool(len(s)) and float(np.abs((s - q[k] + np.pi) % (2 * np.pi) - np.pi).max(axis=1).min()) < 1e-9
    per = {"srs arm angle (1 per call)": [], "srs arm angle (batch)": [], "lock q3 (1 per call)": [],
           "numeric (1 per call)": []}
    for _ in range(rounds):        # interleaved rounds
        t = _clock()
        for k in range(n):
            robot.ik(T[k], arm_angle=psi[k], all_solutions=True)
        per["srs arm angle (1 per call)"].append((_clock() - t) / n)
        t = _clock()
        robot.ik(T, arm_angle=psi, all_solutions=True)
        per["srs arm angle (batch)"].append((_clock() - t) / n)
        t = _clock()
        for k in range(n):
            robot.ik(T[k], lock={j3: q[k, 2]}, all_solutions=True)
        per["lock q3 (1 per call)"].append((_clock() - t) / n)
        t = _clock()
        for k in range(numeric):
            robot.ik(T[k], method="numeric")
        per["numeric (1 per call)"].append((_clock() - t) / numeric)
    num_ok = int(np.sum(robot.ik(T[:numeric], method="numeric").success))
    print(f"{name}: generating configuration found on {found}/{n} targets; "
          f"{np.mean([len(s) for s in res.solutions]):.2f} solutions per target; numeric success "
          f"{num_ok}/{numeric} (one solution each, no arm-angle control)")
    for row, times in per.items():
        print(f"  {row:30s} {1e6 * np.median(times):9.1f} us/target")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--targets", type=int, default=300)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--numeric", type=int, default=50, help="targets timed for the numeric solver")
    args = ap.parse_args()
    for name, make in (("iiwa", arms.iiwa), ("gen3-ideal", gen3_ideal)):
        run_arm(name, make(), args.targets, args.rounds, min(args.numeric, args.targets))
    return 0


if __name__ == "__main__":
    sys.exit(main())
