"""Time of the whole ``robkin estimate --optimize COST`` command, every cost: 3 poses, 6 joints, all starts.

The case (fixed, so that runs on different days compare): the 3-pose path that
``robkin.synthesis.sweep.random_task_poses(numpy.random.default_rng(2021), count=3)`` generates (poses
0.3 apart and turned 0.5 rad each, 0.5-1.5 from the base), given on the command line as 16 numbers each,
and

    robkin estimate --pose P1 --pose P2 --pose P3 --joints 6 --type all --optimize COST -o design.yaml

for COST = manipulability and length, which runs the optimiser from the four estimates (A-D) and four random starts. Each round runs the command
in a fresh process (``python -m robkin.cli``, so start-up and imports count) and records its wall time and
its CPU time (user + system of the child, from ``os.wait4``); the table gives the medians.

Goal: under 3 s for every cost (issue 24).

Run: ``python benchmarks/bench_estimate_optimize.py`` (``--rounds N``, default 3).
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

from robkin.synthesis.sweep import random_task_poses


COSTS = ("manipulability", "length")


def command(out_path: str, cost: str = "manipulability") -> list[str]:
    """The measured command line (poses as full-precision 4x4 matrices, row-major)."""
    poses = random_task_poses(np.random.default_rng(2021), count=3)
    args = [sys.executable, "-m", "robkin.cli", "estimate"]
    for T in poses:
        args += ["--pose", ",".join(repr(float(v)) for v in T.ravel())]
    return args + ["--joints", "6", "--type", "all", "--optimize", cost, "-o", out_path]


def run_once(args: list[str]) -> tuple[float, float]:
    """(wall s, CPU s of the child) for one run of ``args``; raises if the command fails."""
    with tempfile.TemporaryFile() as err:  # a file, not a pipe: the child can never block on it
        start = time.perf_counter()
        proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=err)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - start
        proc.returncode = os.waitstatus_to_exitcode(status)
        if proc.returncode != 0:
            err.seek(0)
            raise SystemExit(f"command failed (exit {proc.returncode}): {err.read().decode().strip()}")
    return wall, usage.ru_utime + usage.ru_stime


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    opts = parser.parse_args(argv)
    walls: dict[str, list[float]] = {c: [] for c in COSTS}
    cpus: dict[str, list[float]] = {c: [] for c in COSTS}
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(opts.rounds):           # the costs interleaved round by round
            for cost in COSTS:
                wall, cpu = run_once(command(os.path.join(tmp, "design.yaml"), cost))
                walls[cost].append(wall)
                cpus[cost].append(cpu)
    for cost in COSTS:
        print(f"estimate --optimize {cost}, 3 poses, 6 joints, --type all ({opts.rounds} runs)")
        print(f"  wall s: median {statistics.median(walls[cost]):.2f}  "
              f"(runs: {', '.join(f'{w:.2f}' for w in walls[cost])})")
        print(f"  CPU s:  median {statistics.median(cpus[cost]):.2f}  "
              f"(runs: {', '.join(f'{c:.2f}' for c in cpus[cost])})")
        print(f"  goal < 3 s: {'met' if statistics.median(cpus[cost]) < 3 else 'not met'} (CPU median)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
