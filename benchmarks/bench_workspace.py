"""The Panda's workspace map: time on one core, and agreement with brute-force sampling of 1e7
configurations (issue 35's goals: 5 cm voxels x 50 orientations in <= 60 s on one core, >= 99 % voxel
agreement).

1. The map: ``reachability_map(panda, 0.05, 50)`` at its default configurations (4e7), ``threads=1``: wall
   and CPU time of this process (``time.process_time``; the machine's other load shows up less there).
2. Brute force: 1e7 configurations drawn uniformly between the limits with another seed, FK
   (``Robot.fk``), positions binned with plain NumPy (``floor(p / 0.05)``), no code of the map's.
3. Agreement, a voxel being reachable when any orientation bin is: ``recall`` (of the voxels brute force
   reaches, the fraction the map reaches: the goal's measure, as the map cannot mark an unreached voxel,
   each mark being a configuration within the limits, so disagreement is only voxels one of the two
   samplings missed; the map's voxels that brute force missed are each checked through the map's own
   witness, ``best_q``), ``jaccard`` and ``box_agreement`` (``robkin.workspace.agreement``). And, as the
   yardstick of what sampling can give, a second brute force of 1e7 with a third seed against the first:
   two 1e7 samplings miss different voxels at the boundary.

Run: ``python benchmarks/bench_workspace.py [--samples N] [--reference N] [--threads T]``. Needs
example-robot-data. Prints one line per measure.
"""

from __future__ import annotations

import argparse
import glob
import os
import sys
import time

import numpy as np

import robkin
from robkin.workspace import reachability_map

ROBOTS = (glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                 "example-robot-data", "robots")) or [""])[0]
VOXEL = 0.05


def brute_force(robot: robkin.Robot, count: int, seed: int) -> set[tuple[int, int, int]]:
    """Voxels (whole voxels from the base origin) reached by ``count`` uniform samples."""
    rng = np.random.default_rng(seed)
    lo, hi = robot.limits[:, 0], robot.limits[:, 1]
    seen: set[tuple[int, int, int]] = set()
    block = 500_000
    for start in range(0, count, block):
        p = robot.fk(rng.uniform(lo, hi, size=(min(block, count - start), robot.n)), threads=1)[:, :3, 3]
        seen |= {tuple(int(x) for x in r) for r in np.unique(np.floor(p / VOXEL).astype(np.int64), axis=0)}
    return seen


def compare(a: set, b: set) -> str:
    both = len(a & b)
    return f"recall {both / len(b):.4f}, precision {both / len(a):.4f}, jaccard {both / len(a | b):.4f}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=float, default=None, help="map samples (default: the map's default, 4e7)")
    ap.add_argument("--reference", type=float, default=1e7, help="brute-force samples (default 1e7)")
    ap.add_argument("--threads", type=int, default=1)
    args = ap.parse_args()
    panda = robkin.load(os.path.join(ROBOTS, "panda_description/urdf/panda.urdf"), tip_link="panda_hand_tcp")
    samples = None if args.samples is None else int(args.samples)
    wall, cpu = time.perf_counter(), time.process_time()
    wmap = reachability_map(panda, VOXEL, 50, samples=samples, seed=0, threads=args.threads)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    print(f"map: {wmap.samples:.3g} samples, {args.threads} thread(s): {wall:.1f} s wall, {cpu:.1f} s CPU "
          f"(goal <= 60 s on one core); {int((wmap.reachable > 0).sum())} voxels, "
          f"{int(wmap.bins.sum())} (voxel, direction) cells", flush=True)
    from robkin.workspace.compare import reachable_voxels

    mine = reachable_voxels(wmap)
    t = time.perf_counter()
    ref = brute_force(panda, int(args.reference), 1)
    print(f"brute force: {args.reference:.3g} samples, {len(ref)} voxels, {time.perf_counter() - t:.1f} s", flush=True)
    grid_box = _box_agreement(mine, ref)
    print(f"map vs brute force: {compare(mine, ref)}, box agreement {grid_box:.4f} (goal >= 0.99)", flush=True)
    extra = np.array(sorted(mine - ref), dtype=np.int64).reshape(-1, 3)
    q = wmap.best_q[tuple((extra - wmap.global_index()).T)]
    inside = (q >= panda.limits[:, 0]).all(axis=1) & (q <= panda.limits[:, 1]).all(axis=1)
    landed = np.floor(panda.fk(q)[:, :3, 3] / VOXEL).astype(np.int64)
    shown = int((inside & (landed == extra).all(axis=1)).sum())
    print(f"the map's {len(extra)} voxels brute force missed: {shown} shown reachable by their best_q (within "
          f"the limits, FK in the voxel)", flush=True)
    other = brute_force(panda, int(args.reference), 2)
    print(f"brute force vs brute force (another seed): {compare(other, ref)}", flush=True)


def _box_agreement(a: set, b: set) -> float:
    """Fraction of the voxels of the box around both on which they agree."""
    pts = np.array(sorted(a | b))
    lo, hi = pts.min(axis=0), pts.max(axis=0) + 1
    return 1.0 - len(a ^ b) / float(np.prod(hi - lo))


if __name__ == "__main__":
    main()
