"""Conversion benchmark: how long one table costs, per robot, single and batch, and where the time goes.

For random 6-joint robots (random RPY-XYZ rows: skew axes, the common case of synthesis candidates)
and for example-robot-data's UR5, it times ``dh_from_robot``, ``mdh_from_robot`` and
``hayati_from_robot`` one robot per call, and ``dh_from_robots`` / ``mdh_from_robots`` on the whole
list (median of interleaved rounds, one thread); then ``--batch`` (default 10^4) fresh robots, never
converted before (so their cached ``Robot`` properties are not yet computed, as for the candidates
of a synthesis run), through the batch API once. Finally it splits the single call into its stages:
frame placement (compiled), rounding of near-round values, residual tool, pose validation and the
FK check that measures the table's error.

The goal (issue 10) is 0.2 ms per 6-joint robot, or 10^4 robots per second through a batch API.

usage:
  python benchmarks/bench_convert.py              # 200 random robots, 5 rounds, a batch of 10^4
  python benchmarks/bench_convert.py --robots 50 --rounds 3 --batch 1000
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
from robkin import se3
from robkin.representations.frames import relative_pose
from robkin.representations.link_table import pose_difference, residual_tool, sample_configurations
from robkin.representations.placement import place_frames
from robkin.representations.rounding import joint_travel, snap_many
from robkin.robot import check_poses, local_transforms
from robkin.representations.rpy_xyz import RPYTable


def random_robots(count: int, n: int = 6, seed: int = 0) -> list[robkin.Robot]:
    rng = np.random.default_rng(seed)
    joints = [robkin.Joint(f"j{i + 1}") for i in range(n)]
    out = []
    for _ in range(count):
        rows = np.column_stack([rng.uniform(-3, 3, (n + 2, 3)), rng.uniform(-0.5, 0.5, (n + 2, 3))])
        out.append(RPYTable(rows, joints).to_robot())
    return out


def per_robot_ms(fn, robots, rounds: int) -> float:
    """Median over rounds of the mean time per robot (ms)."""
    times = []
    for _ in range(rounds):
        t = time.perf_counter()
        for r in robots:
            fn(r)
        times.append((time.perf_counter() - t) / len(robots) * 1e3)
    return statistics.median(times)


def fk_check(robot: robkin.Robot, rows: np.ndarray, base: np.ndarray, tool: np.ndarray) -> np.ndarray:
    """The FK self-check of the conversions (as ``placement._convert_group`` runs it) for one robot."""
    from robkin.compiled.frames import robots_fk, tables_fk

    revolute, limits, scale = robot.revolute[None], robot.limits[None], np.array([robot.scale])
    Q = sample_configurations(revolute, limits, scale)
    sign = np.array([[-1.0 if j.flip else 1.0 for j in robot.joints]])
    return pose_difference(tables_fk(False, base, rows, tool, revolute, sign, Q),
                           robots_fk(local_transforms(robot.frames[None]), revolute, Q), scale)


def stages(robot: robkin.Robot) -> dict:
    """Callables for each stage of dh_from_robot on one robot (inputs precomputed)."""
    F, rows = place_frames("dh", [robot])
    base, last = F[:, 0], F[:, -1]
    travel = joint_travel(robot.joints)[None]
    tool_pose = robot.tool[None]
    scale = np.array([robot.scale])
    tool = residual_tool(base, rows, se3.dh_matrix, tool_pose, scale)
    return {
        "frame placement": lambda: place_frames("dh", [robot]),
        "round values": lambda: snap_many(rows, travel, relative_pose(last, tool_pose), scale),
        "residual tool": lambda: residual_tool(base, rows, se3.dh_matrix, tool_pose, scale),
        "pose validation": lambda: check_poses(np.concatenate([base, tool]), str),
        "FK check": lambda: fk_check(robot, rows, base, tool),
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robots", type=int, default=200)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--batch", type=int, default=10_000, help="fresh robots converted in one batch call")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")  # random robots may have nearly parallel axes: warnings are not timed
    robots = random_robots(args.robots)
    print(f"robkin {robkin.__version__}, numpy {np.__version__}, Python {platform.python_version()}, "
          f"{os.cpu_count()} cpu(s)")
    print(f"\n{args.robots} random 6-joint robots, ms per robot (median of {args.rounds} rounds):")
    for fn in (robkin.dh_from_robot, robkin.mdh_from_robot, robkin.hayati_from_robot):
        ms = per_robot_ms(fn, robots, args.rounds)
        print(f"  {fn.__name__:20s} {ms:7.3f} ms   ({1e3 / ms:7.0f} robots/s)")
    for fn in (robkin.dh_from_robots, robkin.mdh_from_robots):
        ms = per_robot_ms(lambda rs: fn(rs), [robots], args.rounds) / len(robots)
        print(f"  {fn.__name__:20s} {ms:7.3f} ms   ({1e3 / ms:7.0f} robots/s)  ({args.robots} robots per call)")
    if args.batch:
        print(f"\n{args.batch} fresh random 6-joint robots, one batch call each:")
        for fn in (robkin.dh_from_robots, robkin.mdh_from_robots):
            fresh = random_robots(args.batch, seed=1 + (fn is robkin.mdh_from_robots))
            t, c = time.perf_counter(), time.process_time()
            fn(fresh)
            s, cpu = time.perf_counter() - t, time.process_time() - c
            # CPU time as well: on a shared machine the wall time includes waiting for a core
            print(f"  {fn.__name__:20s} {s:7.3f} s    ({args.batch / s:7.0f} robots/s)   CPU {cpu:.3f} s "
                  f"({args.batch / cpu:7.0f} robots/s)")
    print("\ndh_from_robot by stage, ms per robot:")
    parts = [stages(r) for r in robots[: max(1, args.robots // 4)]]
    for name in parts[0]:
        times = []
        for _ in range(args.rounds):
            t = time.perf_counter()
            for p in parts:
                p[name]()
            times.append((time.perf_counter() - t) / len(parts) * 1e3)
        print(f"  {name:20s} {statistics.median(times):7.3f}")
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
