"""Batch IK on one thread against all the cores, in the same run: speed-up and identical bits.

Numeric IK on the Franka Panda (example-robot-data, tool ``panda_hand_tcp``) and the KUKA LBR iiwa 14
(``bench_ik.iiwa_urdf``), closed-form IK on the UR5 (example-robot-data, ``tool0``; the three-parallel
6R). Targets: the FK of random joint values within the limits. The same ``Robot.ik`` batch call with
``threads=1`` and ``threads=k`` (k = 2 .. the cores available), interleaved rounds, medians of **wall**
time (threads are about wall time; other load on the machine shows up in both). Every multi-thread
result (q, success, iterations, attempts, errors) is checked bit for bit against the one-thread result,
and a sample of rows against single calls (rows the first attempt solved: a restart's random stream
depends on the row, see ``compiled.lm``).

Goal (issue 24): at N >= 1e4, >= 1.8x the one-core speed on this 2-core machine, identical bits. The
whole of a batch IK call but its array checks and the result's assembly runs in the compiled loop
without the GIL, so the speed-up on N cores is bounded by the cores, not by Python.

Run: ``python benchmarks/bench_ik_threads.py [--targets 10000] [--rounds 5]``. Exit status 0 whatever
the speed-up, 1 if the bits differ.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")  # BLAS on one thread: only robkin's own threads are measured

import argparse  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402

import robkin  # noqa: E402
from robkin.threads import available_cores, parallel_build  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_fk import robots_dir  # noqa: E402
from bench_ik import iiwa_urdf  # noqa: E402
from bench_threads import interleaved  # noqa: E402

FIELDS = ("q", "success", "iterations", "attempts", "position_error", "orientation_error")


def same_bits(a: robkin.IKResult, b: robkin.IKResult) -> bool:
    """Every per-target field of two batch results bit for bit (NaN where NaN)."""
    return all(np.array_equal(getattr(a, f), getattr(b, f), equal_nan=True) for f in FIELDS)


def rows_are_single_calls(robot: robkin.Robot, T: np.ndarray, batch: robkin.IKResult, method: str) -> bool:
    """Up to 50 rows solved by their first attempt (closed form: every row) against single calls."""
    rows = np.flatnonzero(batch.attempts == 1)[:50]
    for k in rows:
        one = robot.ik(T[k], method=method)
        if not (np.array_equal(one.q, batch.q[k], equal_nan=True) and one.position_error == batch.position_error[k]
                and one.orientation_error == batch.orientation_error[k]):
            return False
    return True


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--targets", type=int, default=10_000, help="targets per batch (default 1e4)")
    parser.add_argument("--rounds", type=int, default=5, help="interleaved rounds (default 5)")
    args = parser.parse_args(argv)
    path = os.path.join(robots_dir(), "panda_description/urdf/panda.urdf")
    if not os.path.isfile(path):
        print("example-robot-data is not installed: nothing to measure")
        return 0
    if not parallel_build():
        print("robkin was built without OpenMP: every batch runs on one thread")
        return 0
    with warnings.catch_warnings(), tempfile.TemporaryDirectory() as tmp:
        warnings.simplefilter("ignore")
        arms = [("Panda", robkin.load(path, tip_link="panda_hand_tcp"), "numeric"),
                ("iiwa 14", robkin.load(iiwa_urdf(tmp), tip_link="tool"), "numeric"),
                ("UR5", robkin.load(os.path.join(robots_dir(), "ur_description/urdf/ur5_robot.urdf"),
                                    tip_link="tool0"), "auto")]
    cores = available_cores()
    counts = list(range(2, cores + 1))
    rng = np.random.default_rng(0)
    N = args.targets
    bits_ok = True
    rows = []
    for name, robot, method in arms:
        T = robot.fk(robot.random_q(N, rng))
        call = lambda t, robot=robot, T=T, method=method: robot.ik(T, method=method, threads=t)  # noqa: E731
        one = call(1)
        ok = rows_are_single_calls(robot, T, one, method)
        for k in counts:
            ok &= same_bits(call(k), one)
        bits_ok &= ok
        t = interleaved({k: (lambda k=k: call(k)) for k in [1, *counts]}, args.rounds)
        rows.append((name, one.method, t[1], {k: t[1] / t[k] for k in counts}, float(np.mean(one.success)), ok))
    print(f"batch IK of {N:,} targets, robkin {robkin.__version__}, {cores} cores available; medians of "
          f"{args.rounds} interleaved rounds, wall time")
    header = "".join(f"{f'{k} threads':>12}" for k in counts)
    print(f"{'arm':<9}{'method':<20}{'1 thread us/target':>20}{header}{'success':>10}  bits")
    for name, method, t1, speed, success, ok in rows:
        print(f"{name:<9}{method:<20}{t1 / N * 1e6:>20.2f}" + "".join(f"{speed[k]:>11.2f}x" for k in counts)
              + f"{success:>10.4f}  {'same' if ok else 'DIFFER'}")
    print(f"bits identical with every thread count and as single calls: {'yes' if bits_ok else 'NO'}")
    if counts:
        best = counts[-1]
        met = N >= 10_000 and all(speed[best] >= 0.9 * best for _, _, _, speed, _, _ in rows)
        print(f"goal >= {0.9 * best:.1f}x on {best} cores at N >= 1e4: {'met' if met else 'MISSED'}")
    return 0 if bits_ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
