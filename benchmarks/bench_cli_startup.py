"""Start-up cost of the command line against ``python -c "import numpy"``, as fresh processes.

- ``robkin convert ur5.urdf --to dh``: goal (issue 10) within 1.5x of importing numpy, which is only
  possible if nothing heavy (scipy, matplotlib, rich, pinocchio, the compiled core...) is imported on
  that path;
- ``robkin ik panda.urdf --pose ... --method numeric``: one numeric IK from a fresh process (load
  the URDF, import the compiled core, solve), goal within 3x;
- the first-call cost of the compiled core: importing its modules (``robkin.compiled.fk``,
  ``.jacobian``, ``.lm``, ``.limits``) in a process that has imported robkin, median of fresh processes.

All are measured in the same run, alternating, and the ratios of medians are reported (absolute
times depend on the machine; the ratios much less).

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

GOAL_CONVERT = 1.5
GOAL_IK = 3.0


def _robot_file(*parts: str) -> str:
    found = glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                   "example-robot-data", "robots", *parts))
    if not found:
        sys.exit("example-robot-data is not installed (pip install 'robkin[test]')")
    return found[0]


FIRST_CALL = ("import time, robkin; t0 = time.perf_counter(); "
              "import robkin.compiled.fk, robkin.compiled.jacobian, robkin.compiled.lm, robkin.compiled.limits; "
              "print(time.perf_counter() - t0)")


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
        shutil.copy(_robot_file("ur_description", "urdf", "ur5_robot.urdf"), urdf)
        panda = _robot_file("panda_description", "urdf", "panda.urdf")
        cmds = {
            "python -c 'import numpy'": [sys.executable, "-c", "import numpy"],
            "robkin convert ur5.urdf --to dh": [sys.executable, "-m", "robkin.cli", "convert", urdf,
                                                "--tip-link", "tool0", "--to", "dh"],
            "robkin ik panda.urdf (numeric)": [sys.executable, "-m", "robkin.cli", "ik", panda, "--tip-link",
                                               "panda_hand_tcp", "--pose", "0.4,0.1,0.5,3.1,0.2,0.3",
                                               "--method", "numeric"],
        }
        for cmd in cmds.values():  # warm the file cache
            _time(cmd)
        times: dict[str, list[float]] = {k: [] for k in cmds}
        first_call = []
        for _ in range(args.runs):
            for k, cmd in cmds.items():
                times[k].append(_time(cmd))
            out = subprocess.run([sys.executable, "-c", FIRST_CALL], check=True, capture_output=True, text=True)
            first_call.append(float(out.stdout))
    med = {k: statistics.median(v) for k, v in times.items()}
    base = med["python -c 'import numpy'"]
    for k, v in med.items():
        print(f"{k:36s} median {v * 1000:7.1f} ms over {args.runs} runs  ({v / base:.2f}x numpy)")
    print(f"{'first call: import the compiled core':36s} median {statistics.median(first_call) * 1000:7.2f} ms")
    r_convert = med["robkin convert ur5.urdf --to dh"] / base
    r_ik = med["robkin ik panda.urdf (numeric)"] / base
    print(f"convert ratio {r_convert:.2f} (goal <= {GOAL_CONVERT}): {'goal met' if r_convert <= GOAL_CONVERT else 'GOAL MISSED'}")
    print(f"ik ratio {r_ik:.2f} (goal <= {GOAL_IK}): {'goal met' if r_ik <= GOAL_IK else 'GOAL MISSED'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
