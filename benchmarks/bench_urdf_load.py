"""URDF load time of robkin against pinocchio, measured in the same run.

For each file (example-robot-data's Talos, 59 joints of which 44 move, the largest; a UR5; a Panda), the time from a
path on disk to a usable model: ``robkin.load(path, base_link, tip_link)`` (parse, chain selection,
GJD, and the kept links; shapes are parsed on first use) against ``pinocchio.buildModelFromUrdf(path)``
(its whole tree, no geometry). The two are interleaved, one call each per round, so that a busy
machine slows both alike, and timed in CPU time of this process (both run in it; wall time on a shared
machine mostly measures the neighbours); the table gives medians, and (in brackets) what the
construction of the ``Robot`` itself costs (validating every frame as a rigid transform, the names),
as the median of 50 constructions per round.

Goal (a ratio, never an absolute time, since the machine varies): robkin no slower than pinocchio
on each file (ratio <= 1); the last line says for which it is met.

The Talos file (110 kB) is parsed with lxml, which that first load imports; the two small files are then
parsed with lxml too, as in any process that has loaded a big URDF before (in a fresh process a small
file is parsed with the standard library's expat instead: see ``robkin.io.urdf_xml.LXML_FROM``).

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
    print(f"{'file':<24} {'joints':>6} {'robkin ms':>10} {'(Robot() us)':>12} {'pinocchio ms':>13} {'ratio':>6}")
    for rel, base, tip in FILES:
        path = os.path.join(base_dir, rel)
        robkin.load(path, base, tip), pin.buildModelFromUrdf(path)  # warm-up: imports, file cache
        ours, theirs, construct = [], [], []
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
            ours.append(t1 - t0)
            theirs.append(t2 - t1)
            construct.append((t3 - t2) / 50)
        a, b = (statistics.median(x) * 1e3 for x in (ours, theirs))
        c = statistics.median(construct) * 1e6
        print(f"{os.path.basename(rel):<24} {model.njoints - 1:>6} {a:>10.2f} {c:>12.1f} {b:>13.2f} {a / b:>6.2f}")
        ratios[os.path.basename(rel)] = a / b
    met = [name for name, r in ratios.items() if r <= 1.0]
    missed = [f"{name} ({r:.2f})" for name, r in ratios.items() if r > 1.0]
    print(f"goal (ratio <= 1 on every file): {'met' if not missed else 'NOT met'}"
          f"{'; met on ' + ', '.join(met) if met and missed else ''}"
          f"{'; missed on ' + ', '.join(missed) if missed else ''}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
