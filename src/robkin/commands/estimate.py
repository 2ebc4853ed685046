"""robkin estimate: an initial kinematic structure (types A-D) that reaches a pose, optionally optimised."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from ..errors import InputError
from .support.common import parse_pose, seed

EPILOG = """\
Types (Huczala et al. 2021): A nearest distance and B joints on a Bezier curve reach the position;
C common perpendicular and D Bezier + common perpendicular reach the full pose. The DH table carries
the theta offsets with which q = 0 reaches the target. Metrics at q = 0: length sum sqrt(a^2 + d^2)
and Yoshikawa manipulability (translational, rotational).

--pose/--base: x,y,z,roll,pitch,yaw (URDF rpy, radians) or 16 numbers (row-major 4x4).
--optimize then optimises the DH parameters so that every --pose is reached at the least cost,
starting from the estimate (with --type all: from A-D and 4 random starts, the best is kept).

examples:
  # the estimation paper's Pose(1), (3) and all four types side by side
  robkin estimate --pose -1,0.9,0.8,-3.08232,-1.04169,-3.01168 --joints 4 --type all
  robkin estimate --pose 0.4,0.6,0.7,pi,0,pi/2 --joints 4 --type D -o pose3_D.yaml
  robkin estimate --pose -1,0.9,0.8,-3.08232,-1.04169,-3.01168 --joints 5 --type all -o results/ --plot cmp.png
  # synthesis for three poses from estimate D (--type all: from A-D and 4 random starts, the best
  # kept; a minute or more, with a progress bar on a terminal)
  robkin estimate --pose 0.8,0.2,0.5,0,1.57,0 --pose 0.8,0.4,0.5,0,1.57,0.3 --pose 0.7,0.5,0.6,0,1.4,0.5 \\
      --joints 6 --type D --optimize length -o design.yaml
"""

TYPES = ("A", "B", "C", "D", "ALL")


def register(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    p = sub.add_parser("estimate", help="initial structure (types A-D) reaching a pose; optional synthesis",
                       description="Estimate a serial structure of N revolute joints whose home "
                                   "configuration reaches a target pose (estimation types A-D), and "
                                   "optionally optimise it for several poses.",
                       epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--pose", required=True, action="append", metavar="POSE",
                   help="target TCP pose in the world frame; repeat for several poses (with --optimize)")
    p.add_argument("--joints", required=True, type=int, metavar="N", help="number of joints (>= 3)")
    p.add_argument("--type", default="D", type=str.upper, choices=TYPES, metavar="A|B|C|D|all",
                   help="estimation type, or all four side by side (default D)")
    p.add_argument("--base", metavar="POSE", help="robot base frame in the world frame (default identity)")
    p.add_argument("-o", "--output", metavar="OUT",
                   help="output robot document (.yaml/.yml/.json); with --type all a folder for A-D")
    p.add_argument("--format", choices=("yaml", "json"),
                   help="document format for a folder output (default yaml; files use their suffix)")
    p.add_argument("--optimize", choices=("length", "manipulability"), metavar="COST",
                   help="optimise the DH parameters for all --pose at least COST (length|manipulability)")
    p.add_argument("--reach", choices=("pose", "position"), default="pose",
                   help="what --optimize must reach (default pose)")
    p.add_argument("--seed", type=seed, default=0, help="random-start seed for --optimize with --type all")
    p.add_argument("--plot", metavar="FILE", help="with --type all: bar plots of the metrics (.png/.svg/.pdf)")
    p.add_argument("--json", action="store_true", help="print the metrics (and optimisation) as JSON")
    return p


def run(args: argparse.Namespace) -> int:
    from ..synthesis.estimate import estimate_all

    poses = [parse_pose(text, "--pose") for text in args.pose]
    base = parse_pose(args.base, "--base") if args.base else None
    if args.joints < 3:
        raise InputError(f"--joints: need at least 3 joints, got {args.joints}")
    if len(poses) > 1 and not args.optimize:
        raise InputError("--pose: several poses need --optimize (an estimate targets one pose)")
    kinds = ("A", "B", "C", "D") if args.type == "ALL" else (args.type,)
    outputs = _output_paths(args, kinds)
    if args.plot and args.type != "ALL":
        raise InputError("--plot: only with --type all (it compares the four estimates)")
    if args.plot:
        _check_plot_path(args.plot)

    estimates = estimate_all(poses[0], args.joints, base, kinds)
    for k, e in estimates.items():
        for note in e.notes:
            print(f"robkin: note: type {k}: {note}", file=sys.stderr)
    results = {k: (e.robot, e.metrics, e.rows) for k, e in estimates.items()}
    opt_summary = None
    if args.optimize:
        results, opt_summary = _optimise(args, poses, base, estimates)

    if args.json:
        from .support.output import print_json

        out: dict[str, Any] = {k: dict(m.as_dict(), type=k, dh=_dh_json(rows))
                               for k, (_, m, rows) in results.items()}
        if opt_summary is not None:
            out["optimization"] = opt_summary
        print_json(out)
    else:
        _print_text(results, estimates, opt_summary)
    from .support.output import wrote

    _write_all({path: results[k][:2] for k, path in outputs.items()})
    for path in outputs.values():
        wrote(path)
    if args.plot:
        _plot(estimates, args.plot)
        wrote(args.plot)
    return 0


def _dh_json(rows: Any) -> dict[str, Any]:
    """The DH table of an estimate, rows as named columns (theta at q = 0 reaches the target)."""
    return {"rows": [dict(zip(("a", "d", "alpha", "theta"), map(float, r))) for r in rows]}


def _output_paths(args: argparse.Namespace, kinds: tuple[str, ...]) -> dict[str, Path]:
    """Where each result goes; checked before any work so that bad paths fail fast (nothing written)."""
    from ..io.files.atomic import check_writable_dir

    if not args.output:
        return {}
    out = Path(args.output)
    if args.optimize and len(kinds) > 1:
        kinds = ("best",)
    if len(kinds) == 1:
        if out.suffix.lower() not in (".yaml", ".yml", ".json"):
            raise InputError(f"{out}: output must end in .yaml, .yml or .json")
        check_writable_dir(out)
        return {kinds[0] if kinds[0] != "best" else "best": out}
    if out.exists() and not out.is_dir():
        raise InputError(f"{out}: with --type all, -o names a folder (A-D are written into it)")
    suffix = ".json" if args.format == "json" else ".yaml"
    paths = {k: out / f"estimate_{k}{suffix}" for k in kinds}
    if not out.exists():
        check_writable_dir(out)  # the folder is made when the results are written, not before
        return paths
    for p in paths.values():
        check_writable_dir(p)
    return paths


def _check_plot_path(path: str) -> None:
    """--plot's file and matplotlib, checked before any work: without matplotlib nothing is written."""
    from ..io.files.atomic import check_writable_dir

    if Path(path).suffix.lower() not in (".png", ".svg", ".pdf"):
        raise InputError(f"--plot {path}: picture must end in .png, .svg or .pdf")
    check_writable_dir(path)
    try:
        # matplotlib itself: the drawing modules import it lazily, inside their functions, so importing
        # them proves nothing (an ImportError would surface only when drawing, as a traceback)
        import matplotlib  # noqa: F401
    except ImportError:
        raise InputError("--plot: pictures need matplotlib (pip install 'robkin[plot]')") from None


def _optimise(args, poses, base, estimates):
    """Synthesis for all poses from the chosen estimate (or A-D + 4 random, keeping the best)."""
    import numpy as np

    from ..synthesis.metrics import structure_metrics
    from ..synthesis.optimize import make_task, synthesize

    task = make_task(np.stack(poses), base, reach=args.reach)
    starts = list(estimates) + (["random"] * 4 if len(estimates) > 1 else [])
    rng = np.random.default_rng(args.seed)
    from ..synthesis.sweep import progress_bar

    bar = progress_bar(len(starts), desc="optimising", enabled=sys.stderr.isatty())
    runs = []
    try:
        for s in starts:
            runs.append(synthesize(task, args.joints, s, args.optimize, rng=rng))
            bar.update(1)
    finally:
        bar.close()
    ok = [r for r in runs if r.converged] or [r for r in runs if r.reaches]
    if not ok:
        raise InputError("--optimize: no start reached every --pose with "
                         f"{args.joints} joints; try more joints or poses closer together")
    best = min(ok, key=lambda r: r.cost)
    key = "best" if len(estimates) > 1 else next(iter(estimates))
    metrics = structure_metrics(best.robot, best.table.rows)
    summary = {"cost": args.optimize, "chosen_start": best.start,
               "runs": [r.summary() for r in runs]}
    return {key: (best.robot, metrics, best.table.rows)}, summary


def _print_text(results, estimates, opt_summary) -> None:
    from ..io.tables.terminal import fmt_num, text_table

    headers = ["type", "reaches", "length", "manip. transl.", "manip. rot."]
    rows = []
    for k, (_, m, _) in results.items():
        reach = estimates[k].reaches if opt_summary is None else "all poses"
        rows.append([k, reach, m.length, m.manipulability_translational, m.manipulability_rotational])
    if len(results) > 1:
        print(text_table(headers, rows, title="estimates (metrics at q = 0)"))
        print()
    for k, (_, m, dh_rows) in results.items():
        title = f"type {k}: DH rows (theta at q = 0 reaches the target)" if opt_summary is None else \
            f"optimised for {opt_summary['cost']} (start {opt_summary['chosen_start']}): DH rows, q = 0 " \
            "reaches the first pose"
        print(text_table(["joint", "a", "d", "alpha", "theta"],
                         [[str(i + 1), *r] for i, r in enumerate(dh_rows)], title=title))
        if len(results) == 1:
            print(f"length {fmt_num(m.length)}, manipulability translational "
                  f"{fmt_num(m.manipulability_translational)}, rotational {fmt_num(m.manipulability_rotational)}")
        print()
    if opt_summary:
        print(text_table(["start", "converged", "cost", "length", "evaluations"],
                         [[r["start"], "yes" if r["converged"] else "no", r["cost"], r["length"], r["evaluations"]]
                          for r in opt_summary["runs"]], title="optimisation runs"))


def _write_all(outputs: dict[Path, tuple]) -> None:
    """Write each (robot, metrics) as a document, all or nothing; a folder made for them goes on failure."""
    from ..io.files.atomic import write_texts_atomic
    from ..io.documents.reader import document_from_robot, dump

    items = []
    for path, (robot, metrics) in outputs.items():
        doc = document_from_robot(robot)
        doc["metrics"] = metrics.as_dict()
        items.append((path, dump(doc, "json" if path.suffix.lower() == ".json" else "yaml")))
    folders = {p.parent for p in outputs if not p.parent.exists()}
    try:
        for folder in folders:
            folder.mkdir()
        write_texts_atomic(items)
    except OSError as exc:
        _remove_folders(folders)
        raise InputError(f"{next(iter(folders))}: cannot make the folder ({exc.strerror or exc})") from None
    except BaseException:
        _remove_folders(folders)
        raise


def _remove_folders(folders: set[Path]) -> None:
    for folder in folders:
        try:
            folder.rmdir()
        except OSError:
            pass


def _plot(estimates, path: str) -> None:
    from ..viz.metrics import MetricEntry, plot_metrics
    from ..viz.plot import save_figure

    entries = [MetricEntry(f"type {k}", "target", k, e.metrics.length, e.metrics.manipulability_translational,
                           e.metrics.manipulability_rotational) for k, e in estimates.items()]
    save_figure(plot_metrics(entries, title="estimates A-D"), path)
