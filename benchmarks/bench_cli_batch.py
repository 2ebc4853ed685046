"""Many IK targets from the command line: one ``robkin ik --poses FILE`` against a loop of ``--pose`` calls.

The issue this answers: 1000 targets as a shell loop of ``robkin ik --pose`` cost minutes (one
process start-up, URDF load and compiled-core import per target) against milliseconds in Python.
Measured here, as fresh processes with one BLAS thread, alternating:

- ``ik --poses targets.csv -o out.csv`` with 1000 UR5 targets (closed form) and with 200 Panda targets
  (numeric, 7 joints);
- one ``ik --pose`` call of each kind (a loop of N calls costs N times its median);
- the Python batch call ``Robot.ik(T)`` on the same targets, in this process (the floor).

Medians over the runs; CPU time (user + system, ``wait4``) beside wall time, since the machine is
shared. Run: ``.venv/bin/python benchmarks/bench_cli_batch.py [--runs 7]``. Exit status 0 whatever
the result (a benchmark, not a test).
"""

from __future__ import annotations

import argparse
import glob
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import robkin

ONE_THREAD = {**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}


def _robot_file(*parts: str) -> str:
    found = glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                   "example-robot-data", "robots", *parts))
    if not found:
        sys.exit("example-robot-data is not installed (pip install 'robkin[test]')")
    return found[0]


def _time(cmd: list[str]) -> tuple[float, float]:
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=ONE_THREAD)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    if os.waitstatus_to_exitcode(status) != 0:
        raise subprocess.CalledProcessError(os.waitstatus_to_exitcode(status), cmd)
    return wall, usage.ru_utime + usage.ru_stime


def _targets_csv(robot: robkin.Robot, count: int, path: str, seed: int) -> np.ndarray:
    from robkin import se3

    T = robot.fk(robot.random_q(count, rng=seed))
    rpy = se3.rpy_from_matrix(T[:, :3, :3])
    rows = np.hstack([T[:, :3, 3], rpy])
    with open(path, "w") as f:
        f.write("x,y,z,roll,pitch,yaw\n")
        f.writelines(",".join(repr(float(v)) for v in r) + "\n" for r in rows)
    return T


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=7)
    args = ap.parse_args()
    cli = [sys.executable, "-c", "import sys; from robkin.cli import main; sys.exit(main())"]
    with tempfile.TemporaryDirectory() as tmp:
        cases = []
        for name, rel, tip, count in (("UR5 (closed form)", ("ur_description", "urdf", "ur5_robot.urdf"), "tool0", 1000),
                                      ("Panda (numeric)", ("panda_description", "urdf", "panda.urdf"),
                                       "panda_hand_tcp", 200)):
            urdf = _robot_file(*rel)
            robot = robkin.load(urdf, tip_link=tip)
            csv = os.path.join(tmp, f"{tip}.csv")
            T = _targets_csv(robot, count, csv, seed=1)
            x, y, z = T[0, :3, 3]
            roll, pitch, yaw = robkin.se3.rpy_from_matrix(T[0, :3, :3])
            one = ",".join(repr(float(v)) for v in (x, y, z, roll, pitch, yaw))
            batch = cli + ["ik", urdf, "--tip-link", tip, "--poses", csv, "-o", os.path.join(tmp, "out.csv")]
            single = cli + ["ik", urdf, "--tip-link", tip, f"--pose={one}"]
            cases.append((name, count, robot, T, batch, single))
        results = {c[0]: {"batch": [], "single": [], "python": []} for c in cases}
        for _ in range(args.runs):
            for name, count, robot, T, batch, single in cases:
                results[name]["batch"].append(_time(batch))
                results[name]["single"].append(_time(single))
                t0 = time.perf_counter()
                robot.ik(T)
                results[name]["python"].append((time.perf_counter() - t0, 0.0))
        print(f"medians of {args.runs} runs (wall s / CPU s)")
        for name, count, *_ in cases:
            r = results[name]
            bw, bc = (statistics.median(v[i] for v in r["batch"]) for i in (0, 1))
            sw, sc = (statistics.median(v[i] for v in r["single"]) for i in (0, 1))
            py = statistics.median(v[0] for v in r["python"])
            print(f"{name}, {count} targets: ik --poses {bw:.3f} / {bc:.3f}; one ik --pose {sw:.3f} / {sc:.3f} "
                  f"(a loop of {count}: ~{count * sw:.0f} s wall); Robot.ik in Python {py:.4f}; "
                  f"batch/loop {bw / (count * sw):.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
