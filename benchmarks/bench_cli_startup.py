"""Start-up cost of the command line: ``robkin convert ur5.urdf --to dh`` against ``python -c "import numpy"``.

Goal (issue 3): the whole conversion of a vendor URDF finishes within 2x the time Python needs just to
import numpy, which is only possible if nothing heavy (scipy, matplotlib, rich, pinocchio...) is
imported on that path. Both are measured in the same run, as fresh processes, alternating, and the
ratio of medians is reported (absolute times depend on the machine; the ratio much less).

Run: ``.venv/bin/python benchmarks/bench_cli_startup.py [--runs 15]``. Exit status 0 whatever the
result (a benchmark, not a test); the last line says whether the goal is met.
"""

from __future__ import annotations

import argparse
import glob
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

GOAL = 2.0


def _ur5() -> str:
    found = glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                   "example-robot-data", "robots", "ur_description", "urdf", "ur5_robot.urdf"))
    if not found:
        sys.exit("example-robot-data is not installed (pip install 'robkin[test]')")
    return found[0]


def _time(cmd: list[str]) -> float:
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - t0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=15)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        urdf = os.path.join(tmp, "ur5.urdf")
        shutil.copy(_ur5(), urdf)
        numpy_cmd = [sys.executable, "-c", "import numpy"]
        robkin_cmd = [sys.executable, "-m", "robkin.cli", "convert", urdf, "--tip-link", "tool0", "--to", "dh"]
        for cmd in (numpy_cmd, robkin_cmd):  # warm the file cache
            _time(cmd)
        numpy_t, robkin_t = [], []
        for _ in range(args.runs):
            numpy_t.append(_time(numpy_cmd))
            robkin_t.append(_time(robkin_cmd))
    a, b = statistics.median(numpy_t), statistics.median(robkin_t)
    ratio = b / a
    print(f"python -c 'import numpy'            median {a * 1000:7.1f} ms over {args.runs} runs")
    print(f"robkin convert ur5.urdf --to dh     median {b * 1000:7.1f} ms over {args.runs} runs")
    print(f"ratio {ratio:.2f} (goal <= {GOAL}): {'goal met' if ratio <= GOAL else 'GOAL MISSED'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
