"""Batch IK on one thread against all the cores, in the same run: speed-up, the machine's ceiling, bits.

Numeric IK on the Franka Panda (example-robot-data, tool ``panda_hand_tcp``) and the KUKA LBR iiwa 14
(``bench_ik.iiwa_urdf``), closed-form IK on the UR5 (example-robot-data, ``tool0``; the three-parallel
6R). Targets: the FK of random joint values within the limits. The same ``Robot.ik`` batch call with
``threads=1`` and ``threads=k`` (k = 2 .. the cores available), and the machine's ceiling: the
targets in k parts, solved by k independent one-thread calls at the same time (``thread_timing``; why:
see ``bench_threads``, the vCPUs of this shared machine do not run at equal speeds). Interleaved
rounds, **wall** time, rounds from a time budget, medians over the rounds of the ratios within a
round; the k-thread call is timed after the round's pause and again right after it (see
``thread_timing``). Every multi-thread result (q, success, iterations, attempts, errors) is checked
bit for bit against the one-thread result, and a sample of rows against single calls (rows the first
attempt solved: a restart's random stream depends on the row, see ``compiled.ik.lm``). The ceiling's parts are
checked on the rows that must agree: all of the first part, and elsewhere the rows solved by their
first attempt (a later part's restarted rows draw other random streams, and may also cost a different
number of iterations: the ceiling's work is the same only up to those rows).

Goal (issue 24): at N >= 1e4, >= 1.8x the one-core speed on this 2-core machine, identical bits; and
>= 95 % of the ceiling measured in the same rounds. The whole of a batch IK call but its array checks
and the result's assembly runs in the compiled loop without the GIL, so the speed-up on N cores is
bounded by the cores, not by Python.

Run: ``python benchmarks/bench_ik_threads.py [--targets 10000] [--seconds 6] [--rounds 5]`` (about
30 s). Exit status 0 whatever the speed-up, 1 if the bits differ.
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
from thread_timing import (Budget, Concurrent, goal_lines, ik_parts_agree, ik_same_bits,  # noqa: E402
                           header_cells, legend, measure, row_cells)

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
    parser.add_argument("--seconds", type=float, default=6.0,
                        help="time budget of an arm's interleaved rounds (default 6)")
    parser.add_argument("--rounds", type=int, default=5, help="at least that many rounds (default 5)")
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
    if cores < 2:
        print("one core available to this process: nothing to compare")
        return 0
    counts = list(range(2, cores + 1))
    best = counts[-1]
    rng = np.random.default_rng(0)
    N = args.targets
    budget = Budget(args.seconds, args.rounds, 200)
    bits_ok = True
    rows = []
    with Concurrent(best) as pool:
        for name, robot, method in arms:
            T = robot.fk(robot.random_q(N, rng))
            call = lambda t, s, robot=robot, T=T, method=method: robot.ik(T[s], method=method, threads=t)  # noqa: E731
            one = call(1, slice(0, N))
            single = rows_are_single_calls(robot, T, one, method)
            r = measure(call, N, counts, pool, budget, ik_same_bits, ik_parts_agree)
            bits_ok &= single and r.bits and r.ceiling_bits
            rows.append((name, one.method, r, float(np.mean(one.success)), single and r.bits, r.ceiling_bits))
    print(f"batch IK of {N:,} targets, robkin {robkin.__version__}, {cores} cores available; wall time, medians "
          f"over interleaved rounds (~{args.seconds:g} s an arm) of the ratios within a round")
    print(f"{'arm':<9}{'method':<20}{'1 thread us/target':>20}{header_cells(counts)}"
          f"{'success':>10}  bits (threads, parts)")
    for name, method, r, success, ok, parts_ok in rows:
        print(f"{name:<9}{method:<20}{r.t1 / N * 1e6:>20.2f}{row_cells(r)}{success:>10.4f}  "
              f"{'same' if ok else 'DIFFER'}, {'same' if parts_ok else 'DIFFER'}")
    print(legend(best, "the targets"))
    print(f"bits identical with every thread count and as single calls: {'yes' if bits_ok else 'NO'} (the "
          "ceiling's parts: the rows whose random restart streams do not depend on the part)")
    lines = goal_lines([(name, r) for name, _, r, _, _, _ in rows], best)
    print(lines[0] if N >= 10_000 else lines[0].split(":")[0] + ": not measured (N < 1e4)")
    print(lines[1])
    return 0 if bits_ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
