"""``robkin workspace``: a robot's reachability map, its picture, and where to place its base."""

from __future__ import annotations

import argparse
import sys

from ..errors import InputError
from .support.common import add_input, add_threads, load_input, seed

HELP = "reachability map on a voxel grid (approach directions, manipulability), base placement"
EPILOG = """\
The map samples configurations uniformly between the joint limits and bins their tool poses (FK):
each voxel of the robot base frame counts the approach directions (the tool z axis, in K bins of a
near-uniform sphere lattice) in which the tool origin reaches it, and keeps the largest
manipulability seen and the configuration that had it. The same --seed and --samples give the same
map on any number of threads and on a Dask cluster (--dask). MAP.npz holds reachable (X, Y, Z),
origin (the grid's corner, m), voxel (m), manipulability (X, Y, Z; NaN where unreached), bins
(X, Y, Z, K), directions (K, 3), best_q (X, Y, Z, n) and how it was made; see docs/workspace.md.

--base-for POSES.csv asks where the base may stand on the plane z = --base-height of the poses' frame
so that the task poses are reachable (columns x, y, z with qw, qx, qy, qz or roll, pitch, yaw, as for
'robkin ik --poses'): candidates on a grid of the map's voxel and --yaws headings, scored by how many
poses the map reaches from there; --verify checks the best ones with IK.

On a Dask cluster: --dask tcp://10.0.0.5:8786 (the scheduler's address; pip install 'dask[distributed]').

examples:
  robkin workspace ur5.urdf --tip-link tool0 -o ur5_map.npz --voxel 0.1 --orientations 20 --samples 3e5 --plot ur5_map.png
  robkin workspace ur5.urdf --tip-link tool0 --map ur5_map.npz --base-for targets.csv --yaws 8 --verify
  robkin workspace panda.urdf --tip-link panda_hand_tcp -o panda_map.npz --samples 1e6 --threads 2 --json
"""


def register(subparsers) -> argparse.ArgumentParser:
    p = subparsers.add_parser("workspace", help=HELP, description=HELP.capitalize() + ".", epilog=EPILOG,
                              formatter_class=argparse.RawDescriptionHelpFormatter)
    add_input(p)
    p.add_argument("-o", "--output", metavar="MAP.npz", help="write the map (.npz)")
    p.add_argument("--map", metavar="MAP.npz", help="use this map (from an earlier run) instead of building one")
    p.add_argument("--voxel", metavar="M", type=float, default=0.05, help="voxel edge in metres (default 0.05)")
    p.add_argument("--orientations", metavar="K", type=int, default=50,
                   help="approach-direction bins (default 50; 1: position only)")
    p.add_argument("--samples", metavar="N", type=float,
                   help="configurations sampled (default 4e7 at 5 cm voxels, scaled by (0.05 / voxel)^3)")
    p.add_argument("--seed", type=seed, default=0, help="sampling seed (default 0)")
    p.add_argument("--manipulability", metavar="KIND", default="translational",
                   choices=("translational", "rotational", "full"),
                   help="the measure kept per voxel: translational (default), rotational or full")
    add_threads(p)
    p.add_argument("--dask", metavar="ADDRESS", help="run the sampling on this Dask scheduler (tcp://host:8786)")
    p.add_argument("--plot", metavar="PICTURE", help="draw the map: .png, .svg or .pdf (needs matplotlib)")
    p.add_argument("--base-for", metavar="POSES", help="task poses (CSV/.npy/.npz): score base placements")
    p.add_argument("--base-height", metavar="Z", type=float, default=0.0,
                   help="the plane the base stands on, z in the poses' frame (default 0)")
    p.add_argument("--yaws", metavar="N", type=int, default=16, help="base headings tried (default 16)")
    p.add_argument("--top", metavar="N", type=int, default=10, help="placements listed (default 10)")
    p.add_argument("--verify", action="store_true", help="check the listed placements with IK (robkin ik)")
    p.add_argument("--degrees", action="store_true", help="roll, pitch, yaw of --base-for and yaw printed in degrees")
    p.add_argument("--json", action="store_true", help="print a JSON summary (and the placements)")
    return p


def run(args: argparse.Namespace) -> int:
    from pathlib import Path

    if not (args.output or args.plot or args.base_for):
        raise InputError("-o: give -o MAP.npz, --plot PICTURE or --base-for POSES (nothing to do otherwise)")
    if args.map and (args.dask or args.samples is not None):
        raise InputError("--map: the map is read, not built; --dask and --samples apply to building one")
    if args.output and not args.output.lower().endswith(".npz"):
        raise InputError(f"-o {args.output}: a map is written as .npz")
    from ..io.files.atomic import check_writable_dir

    for path in (args.output, args.plot):
        if path:
            check_writable_dir(path)
    if args.plot:
        if Path(args.plot).suffix.lower() not in (".png", ".svg", ".pdf"):
            raise InputError(f"--plot {args.plot}: one of .png, .svg, .pdf")
        try:
            import matplotlib  # noqa: F401 - only to say clearly what is missing, before any work
        except ImportError:
            raise InputError("--plot: pictures need matplotlib (pip install 'robkin[plot]')") from None
    samples = _samples(args.samples)
    robot = load_input(args.input, args)
    poses = _poses(args) if args.base_for else None
    from ..workspace import load_map, reachability_map, save_map

    if args.map:
        wmap = load_map(args.map)
        if wmap.joints != tuple(j.name for j in robot.joints):
            raise InputError(f"--map {args.map}: made for joints {', '.join(wmap.joints)[:80]}, not this robot's")
    else:
        wmap = reachability_map(robot, args.voxel, args.orientations, samples=samples, seed=args.seed,
                                kind=args.manipulability, threads=args.threads, dask=args.dask)
    summary = _summary(wmap)
    if args.output:
        save_map(wmap, args.output)
    if args.plot:
        from ..viz.plot import save_figure
        from ..viz.workspace_plot import plot_workspace

        save_figure(plot_workspace(wmap), args.plot)
    if poses is not None:
        summary["poses"] = len(poses)
        summary["placements"] = _placements(robot, wmap, poses, args)
    _report(summary, args)
    return 0


def _samples(text: float | None) -> int | None:
    """--samples as a whole number (1e7 is accepted)."""
    if text is None:
        return None
    if not (text >= 1 and float(text).is_integer() and text < 2 ** 53):
        raise InputError(f"--samples: expected a whole number >= 1, got {text:g}")
    return int(text)


def _poses(args: argparse.Namespace):
    from ..io.batch_files import read_rows
    from .support.batches import pose_rows

    return pose_rows(read_rows(args.base_for, key="poses"), degrees=args.degrees)


def _summary(wmap) -> dict:
    reached = int((wmap.reachable > 0).sum())
    return {"voxels": list(wmap.shape), "origin": wmap.origin, "voxel": wmap.voxel,
            "orientations": len(wmap.directions), "samples": wmap.samples, "seed": wmap.seed,
            "reachable_voxels": reached, "volume": reached * wmap.voxel ** 3,
            "max_manipulability": float(max(0.0, float(_nanmax(wmap.manipulability))))}


def _nanmax(a) -> float:
    import numpy as np

    return float(np.nanmax(a)) if np.isfinite(a).any() else 0.0


def _placements(robot, wmap, poses, args: argparse.Namespace) -> list[dict]:
    import math

    from ..workspace import base_placement, verify

    if args.top < 1:
        raise InputError(f"--top: expected a whole number >= 1, got {args.top}")
    result = base_placement(wmap, poses, height=args.base_height, yaws=args.yaws)
    ranked = result.ranked(args.top)
    for row in ranked:
        if args.verify:
            row["verified"] = int(verify(robot, poses, row).sum())
        if args.degrees:
            row["yaw"] = math.degrees(row["yaw"])
    return ranked


def _report(summary: dict, args: argparse.Namespace) -> None:
    from .support.output import print_json, wrote

    for path in (args.output, args.plot):
        if path:
            wrote(path)
    if args.json:
        print_json(summary)
        return
    X, Y, Z = summary["voxels"]
    print(f"map: {X} x {Y} x {Z} voxels of {summary['voxel']:g} m, {summary['orientations']} approach directions, "
          f"{summary['samples']:,} samples (seed {summary['seed']})")
    print(f"reachable: {summary['reachable_voxels']} voxels, {summary['volume']:.4g} m^3; "
          f"largest manipulability {summary['max_manipulability']:.4g}")
    if "placements" in summary:
        from ..io.tables.terminal import fmt_num, text_table

        rows = summary["placements"]
        if not rows:
            print("base placement: no candidate reaches any of the poses", file=sys.stderr)
            return
        unit = "deg" if args.degrees else "rad"
        header = ["x", "y", "z", f"yaw ({unit})", "reached", "dexterity"] + (["verified (IK)"] if args.verify else [])
        table = [[fmt_num(r["x"]), fmt_num(r["y"]), fmt_num(r["z"]), fmt_num(r["yaw"]), str(r["reached"]),
                  fmt_num(r["dexterity"])] + ([str(r["verified"])] if args.verify else []) for r in rows]
        print(text_table(header, table, title=f"base placements in the poses' frame, best first "
                                              f"(reached: of {summary['poses']} poses, by the map)"))
