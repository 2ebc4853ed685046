"""``robkin lint`` speed: every URDF of example-robot-data in one process on one core, and a single arm.

Goals (issue 33): all of example-robot-data's URDFs (69 files in its 4.x releases, meshes included:
the collision meshes are read, their volumes and inertias computed) within 60 s of CPU time on one core;
a single arm (UR5, Panda) well under a second, measured two ways: ``lint_file`` in a warm process (the
library's cost) and ``robkin lint FILE`` as a fresh process (what a CI step pays, Python's start-up and
imports included).

Each lint builds its own mesh cache: nothing is shared between files (as ``robkin lint A B`` does).
BLAS and OpenMP run one thread (the goal is per core). CPU time is ``time.process_time`` in process and
``wait4``'s user + system for the fresh processes.

Run: ``.venv/bin/python benchmarks/bench_lint.py``. Exit status 0 whatever the result (a benchmark, not
a test); the last lines say whether the goals are met.
"""

from __future__ import annotations

import glob
import os
import subprocess
import sys
import time

ONE_THREAD = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
os.environ.update(ONE_THREAD)

GOAL_ALL = 60.0
GOAL_ONE = 1.0
ROBOTS = (glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                 "example-robot-data", "robots")) or [""])[0]
ARMS = {"ur5": "ur_description/urdf/ur5_robot.urdf", "panda": "panda_description/urdf/panda.urdf"}


def _fresh(path: str) -> tuple[float, float]:
    """(wall, CPU) seconds of ``robkin lint path`` as a new process."""
    code = "import sys; from robkin.cli import main; sys.exit(main(sys.argv[1:]))"
    t = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-c", code, "lint", path], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, env={**os.environ})
    _, _, usage = os.wait4(proc.pid, 0)
    return time.perf_counter() - t, usage.ru_utime + usage.ru_stime


def main() -> int:
    if not ROBOTS:
        print("example-robot-data is not installed (pip install example-robot-data): nothing to measure")
        return 0
    from robkin.lint import lint_file

    try:
        os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})  # one core
    except (AttributeError, OSError):
        pass
    files = sorted(glob.glob(os.path.join(ROBOTS, "**", "*.urdf"), recursive=True))
    counts = {"error": 0, "warning": 0, "info": 0}
    cpu0, wall0 = time.process_time(), time.perf_counter()
    slowest = []
    for f in files:
        c = time.process_time()
        for finding in lint_file(f):
            counts[finding.severity] += 1
        slowest.append((time.process_time() - c, os.path.relpath(f, ROBOTS)))
    cpu, wall = time.process_time() - cpu0, time.perf_counter() - wall0
    print(f"all example-robot-data URDFs: {len(files)} files, {cpu:.1f} s CPU ({wall:.1f} s wall) on one core; "
          f"{counts['error']} errors, {counts['warning']} warnings, {counts['info']} infos")
    for t, name in sorted(slowest, reverse=True)[:3]:
        print(f"  slowest: {name} {t:.2f} s")
    one = {}
    for name, rel in ARMS.items():
        path = os.path.join(ROBOTS, rel)
        warm = []
        for _ in range(5):
            c = time.process_time()
            lint_file(path)
            warm.append(time.process_time() - c)
        fresh = sorted(_fresh(path) for _ in range(3))[1]
        one[name] = (min(warm), fresh[1])
        print(f"{name}: lint_file {min(warm) * 1e3:.0f} ms CPU (warm, best of 5); robkin lint as a fresh process "
              f"{fresh[1]:.2f} s CPU ({fresh[0]:.2f} s wall, median of 3)")
    print(f"goal all <= {GOAL_ALL:g} s: {'met' if cpu <= GOAL_ALL else 'NOT met'} ({cpu:.1f} s)")
    worst = max(v[0] for v in one.values())
    print(f"goal one arm < {GOAL_ONE:g} s: {'met' if worst < GOAL_ONE else 'NOT met'} (library {worst:.2f} s; "
          f"fresh process {max(v[1] for v in one.values()):.2f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
