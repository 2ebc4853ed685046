"""Conversion benchmark: how long one table costs, per robot, single and batch, and where the time goes.

For random 6-joint robots (random RPY-XYZ rows: skew axes, the common case of synthesis candidates)
and for example-robot-data's UR5, it times ``dh_from_robot``, ``mdh_from_robot`` and
``hayati_from_robot`` one robot per call: "warm" robots (converted or used before, so their cached
``Robot`` size and fixed transforms exist, as for any robot that ran FK) and "fresh" ones (never used:
those are computed in the call). Then ``dh_from_robots`` / ``mdh_from_robots`` / ``hayati_from_robots``
on ``--batch`` (default 10^4) fresh robots, once per thread count of ``--threads`` (wall and CPU
time; results checked bit-identical across thread counts). Finally it splits a batch of DH
conversions into its compiled and Python parts (what threads can and cannot speed up).

The goal (issue 24) is 0.2 ms per 6-joint robot for a single ``dh_from_robot`` / ``mdh_from_robot``.

usage:
  python benchmarks/bench_convert.py              # 200 random robots, 5 rounds, batches of 10^4, threads 1 2
  python benchmarks/bench_convert.py --quick      # 50 robots, 3 rounds, batches of 2000
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import sys
import time
import warnings

import numpy as np

import robkin
from robkin.threads import parallel_build
from robkin.frame_stacks import frame_scales, local_transforms
from robkin.representations.link_table import _CHECK_SAMPLES, FLIP_X
from robkin.representations.rpy_xyz import RPYTable
from robkin.robot import check_poses
from robkin.samples import unit_sample


def random_robots(count: int, n: int = 6, seed: int = 0) -> list[robkin.Robot]:
    rng = np.random.default_rng(seed)
    joints = [robkin.Joint(f"j{i + 1}") for i in range(n)]
    out = []
    for _ in range(count):
        rows = np.column_stack([rng.uniform(-3, 3, (n + 2, 3)), rng.uniform(-0.5, 0.5, (n + 2, 3))])
        out.append(RPYTable(rows, joints).to_robot())
    return out


def per_robot_ms(fn, robots, rounds: int) -> float:
    """Median over rounds of the mean CPU time per robot (ms): on a machine shared with other work the
    wall time of a single call includes waiting for a core; one call runs on one thread."""
    times = []
    for _ in range(rounds):
        t = time.process_time()
        for r in robots:
            fn(r)
        times.append((time.process_time() - t) / len(robots) * 1e3)
    return statistics.median(times)


def batch_parts(robots: list[robkin.Robot], threads: int) -> dict:
    """Seconds of each part of ``dh_from_robots`` on fresh-robot inputs (as ``placement._convert_group``
    runs them): the compiled stages, which threads split, and the Python around them, which they do not."""
    from robkin.compiled.conversions.frames import check_tables, convert_tables

    out = {}
    t = time.perf_counter()
    frames = np.stack([r.frames for r in robots])
    scale, local = frame_scales(frames), local_transforms(frames)
    J = np.array([[(j.revolute, j.flip, -np.inf if j.lower is None else j.lower,
                    np.inf if j.upper is None else j.upper) for j in r.joints] for r in robots], dtype=float)
    keep = [r.frames_from == "dh" for r in robots]
    out["Python: inputs (stack, size, fixed transforms, joints)"] = time.perf_counter() - t
    t = time.perf_counter()
    rows, base, tool = convert_tables(False, frames, J, keep, [not k for k in keep], scale, FLIP_X, threads)
    out["compiled: placement, rounding, residual tool"] = time.perf_counter() - t
    t = time.perf_counter()
    poses = check_poses(np.concatenate([base, tool]), str)
    tables = [robkin.DHTable._from_checked(rows[k], r.joints, poses[k], poses[len(robots) + k])
              for k, r in enumerate(robots)]
    out["Python: pose validation, table objects"] = time.perf_counter() - t
    t = time.perf_counter()
    check_tables(False, base, rows, tool, local, J, scale, unit_sample(_CHECK_SAMPLES, rows.shape[1]), threads)
    out["compiled: FK self-check"] = time.perf_counter() - t
    assert len(tables) == len(robots)
    return out


def same_tables(a: list, b: list) -> bool:
    return all(np.array_equal(x.rows, y.rows) and np.array_equal(x.base, y.base) and np.array_equal(x.tool, y.tool)
               for x, y in zip(a, b))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robots", type=int, default=200)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--batch", type=int, default=10_000, help="fresh robots converted in one batch call")
    ap.add_argument("--threads", type=int, nargs="+", default=[1, 2], help="thread counts for the batches")
    ap.add_argument("--quick", action="store_true", help="50 robots, 3 rounds, batches of 2000")
    args = ap.parse_args(argv)
    if args.quick:
        args.robots, args.rounds, args.batch = 50, 3, 2000
    warnings.simplefilter("ignore")  # random robots may have nearly parallel axes: warnings are not timed
    robots = random_robots(args.robots)
    print(f"robkin {robkin.__version__}, numpy {np.__version__}, Python {platform.python_version()}, "
          f"{os.cpu_count()} cpu(s), OpenMP {parallel_build()}")
    singles = (robkin.dh_from_robot, robkin.mdh_from_robot, robkin.hayati_from_robot)
    print(f"\n{args.robots} random 6-joint robots, one call per robot, CPU ms per robot (median of {args.rounds} "
          "interleaved rounds):")
    warm = {fn.__name__: [] for fn in singles}
    fresh = {fn.__name__: [] for fn in singles}
    for k in range(args.rounds):
        for fn in singles:
            warm[fn.__name__].append(per_robot_ms(fn, robots, 1))
            new = random_robots(args.robots, seed=100 + k)
            fresh[fn.__name__].append(per_robot_ms(fn, new, 1))
    for fn in singles:
        w, f = statistics.median(warm[fn.__name__]), statistics.median(fresh[fn.__name__])
        print(f"  {fn.__name__:20s} warm {w:7.3f} ms ({1e3 / w:6.0f}/s)   fresh {f:7.3f} ms ({1e3 / f:6.0f}/s)")
    if args.batch:
        print(f"\n{args.batch} fresh random 6-joint robots, one batch call (wall and CPU time):")
        for fn in (robkin.dh_from_robots, robkin.mdh_from_robots, robkin.hayati_from_robots):
            first = None
            for threads in args.threads:
                fresh_robots = random_robots(args.batch, seed=1)
                t, c = time.perf_counter(), time.process_time()
                tables = fn(fresh_robots, threads=threads)
                s, cpu = time.perf_counter() - t, time.process_time() - c
                first = first or tables
                # CPU time as well: on a shared machine the wall time includes waiting for a core
                print(f"  {fn.__name__:20s} threads={threads}  {s:7.3f} s ({args.batch / s:7.0f} robots/s)   "
                      f"CPU {cpu:.3f} s   same bits as threads={args.threads[0]}: {same_tables(first, tables)}")
        print(f"\ndh_from_robots on {args.batch} fresh robots by part, s (median of {args.rounds}):")
        for threads in args.threads:
            runs = [batch_parts(random_robots(args.batch, seed=2), threads) for _ in range(args.rounds)]
            for name in runs[0]:
                print(f"  threads={threads}  {name:55s} {statistics.median(r[name] for r in runs):7.4f}")
    ur5 = os.path.join(sys.prefix, "lib", f"python{sys.version_info.major}.{sys.version_info.minor}",
                       "site-packages", "cmeel.prefix", "share", "example-robot-data", "robots",
                       "ur_description", "urdf", "ur5_robot.urdf")
    if os.path.isfile(ur5):
        robot = robkin.load(ur5, tip_link="tool0")
        ms = per_robot_ms(robkin.dh_from_robot, [robot] * 50, args.rounds)
        print(f"\nUR5 (example-robot-data) dh_from_robot: {ms:.3f} ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
