"""URDF load time of robkin against pinocchio, measured in the same run.

For each file (example-robot-data's Talos, 59 joints of which 44 move, the largest; a UR5; a Panda), the time from a
path on disk to a usable model: ``robkin.load(path, base_link, tip_link)`` (parse, chain selection,
GJD, and the kept links; shapes are parsed on first use) against ``pinocchio.buildModelFromUrdf(path)``
(its whole tree, no geometry). The two are interleaved, one call each per round, so that a busy
machine slows both alike, and timed in CPU time of this process (both run in it; wall time on a shared
machine mostly measures the neighbours); the table gives medians; "parse" is the share of the load that
reads the kinematic tree (``robkin.io.urdf.parse_urdf_text`` of the text, read once: the compiled scan
and the checks; timed in the same rounds; "parse/pin" is its ratio to pinocchio's whole load); and (in
brackets) what the construction of the ``Robot`` itself costs (validating every frame as a rigid transform, the names),
as the median of 50 constructions per round.

Goal (a ratio, never an absolute time, since the machine varies): robkin no slower than pinocchio
on each file (ratio <= 1); the last line says for which it is met.

The kinematic tree is read by one pass of the standard library's expat with C callbacks
(``robkin.compiled.scanners.urdf_scan``); no XML tree is built (link shapes, which would need one, are parsed on
first use).

Run: ``python benchmarks/bench_urdf_load.py`` (``--rounds N``, default 60).
"""

from __future__ import annotations

import argparse
import glob
import os
import statistics
import sys
import time
import warnings

import robkin
from robkin.io.urdf import parse_urdf_text

#: (file under example-robot-data/robots, base link, tip link)
FILES = [
    ("talos_data/robots/talos_full_v2.urdf", "torso_2_link", "gripper_left_base_link"),
    ("ur_description/urdf/ur5_robot.urdf", "base", "tool0"),
    ("panda_description/urdf/panda.urdf", None, "panda_hand_tcp"),
]


def _clock() -> float:
    """CPU time of this process (see the module docstring)."""
    return time.process_time()


def robots_dir() -> str:
    found = glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                   "example-robot-data", "robots"))
    if not found:
        raise SystemExit("example-robot-data is not installed (pip install example-robot-data)")
    return found[0]


def main(argv: list[str] | None = None) -> int:
    import pinocchio as pin

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=60)
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")  # talos: torso joints above the chosen base are held at 0
    base_dir = robots_dir()
    ratios: dict[str, float] = {}
    print(f"{'file':<24} {'joints':>6} {'robkin ms':>10} {'parse ms':>9} {'(Robot() us)':>12} {'pinocchio ms':>13} "
          f"{'ratio':>6} {'parse/pin':>9}")
    for rel, base, tip in FILES:
        path = os.path.join(base_dir, rel)
        robkin.load(path, base, tip), pin.buildModelFromUrdf(path)  # warm-up: imports, file cache
        with open(path, encoding="utf-8") as f:
            text = f.read()
        ours, theirs, construct, parse = [], [], [], []
        for _ in range(args.rounds):
            t0 = _clock()
            r = robkin.load(path, base, tip)
            t1 = _clock()
            model = pin.buildModelFromUrdf(path)
            t2 = _clock()
            # what validating the Robot costs (frames checked to be rigid, names), per construction
            for _ in range(50):
                robkin.Robot(r.frames, r.joints, world=r.world, name=r.name, bodies=r.bodies)
            t3 = _clock()
            parse_urdf_text(text, path)
            t4 = _clock()
            ours.append(t1 - t0)
            parse.append(t4 - t3)
            theirs.append(t2 - t1)
            construct.append((t3 - t2) / 50)
        a, b, p = (statistics.median(x) * 1e3 for x in (ours, theirs, parse))
        c = statistics.median(construct) * 1e6
        print(f"{os.path.basename(rel):<24} {model.njoints - 1:>6} {a:>10.2f} {p:>9.2f} {c:>12.1f} {b:>13.2f} "
              f"{a / b:>6.2f} {p / b:>9.2f}")
        ratios[os.path.basename(rel)] = a / b
    met = [name for name, r in ratios.items() if r <= 1.0]
    missed = [f"{name} ({r:.2f})" for name, r in ratios.items() if r > 1.0]
    print(f"goal (ratio <= 1 on every file): {'met' if not missed else 'NOT met'}"
          f"{'; met on ' + ', '.join(met) if met and missed else ''}"
          f"{'; missed on ' + ', '.join(missed) if missed else ''}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
