"""robkin calibrate MODEL --plan N -o POSES.csv: which configurations to measure (a pose plan).

The command-line side of ``robkin.calibration.planning_poses``: its options (``add_plan_options``),
and ``dispatch``, which runs a plan when ``--plan`` is given and otherwise checks that no plan-only
option was.
"""

from __future__ import annotations

import argparse
import sys

from ..support.common import positive_int

PLAN_HELP = """\
--plan N writes N joint configurations to measure (POSES.csv: a header line with one column per joint,
named as the model's joints, radians or metres, then one configuration per line) instead of
calibrating; no MEASUREMENTS. They are chosen from candidates (random inside the joint limits, or
--candidates FILE) to make the identification well conditioned for the error model (--model) and the
marker (--marker: where it will sit in the tool frame; default the tool origin): D-optimal design,
det(J^T J) of the identifiable parameters maximised by Fedorov's exchange. The report states the
condition number, each parameter's expected standard deviation and the calibrated robot's expected
position error from noise alone, for --noise, and the same for as many random candidates.
"""

#: Options that mean something only with --plan (dest, flag).
PLAN_ONLY = (("candidates", "--candidates"), ("box", "--box"), ("cone", "--cone"), ("noise", "--noise"),
             ("random_candidates", "--random-candidates"))


def add_plan_options(p: argparse.ArgumentParser) -> None:
    """The pose-planning options of ``robkin calibrate``."""
    g = p.add_argument_group("pose planning (--plan N, no MEASUREMENTS)", PLAN_HELP)
    g.add_argument("--plan", type=positive_int, metavar="N",
                   help="write N configurations to measure to -o POSES.csv instead of calibrating")
    g.add_argument("--candidates", metavar="CANDIDATES.csv",
                   help="choose among these configurations (a column per joint; x, y, z, qw..qz ignored) "
                        "instead of random ones inside the limits")
    g.add_argument("--box", metavar="XMIN,XMAX,YMIN,YMAX,ZMIN,ZMAX",
                   help="keep candidates whose marker lies in this box (model's world frame, metres): where the "
                        "measuring device sees it")
    g.add_argument("--cone", metavar="X,Y,Z,AX,AY,AZ,DEG[,RANGE]",
                   help="keep candidates whose marker the device at X,Y,Z looking along AX,AY,AZ sees within DEG "
                        "degrees (and RANGE metres)")
    g.add_argument("--noise", type=float, metavar="METRES",
                   help="measurement noise per coordinate for the expected figures (default 1e-05)")
    g.add_argument("--random-candidates", type=positive_int, metavar="K",
                   help="random candidates to draw (default 2000; --seed seeds them)")


def dispatch(args: argparse.Namespace) -> int | None:
    """Run the plan if ``--plan`` was given (its exit status); None for a calibration, after checking
    that it has MEASUREMENTS and no plan-only option."""
    from ...errors import InputError

    if args.plan is None:
        given = [flag for dest, flag in PLAN_ONLY if getattr(args, dest) is not None]
        if given:
            raise InputError(f"{given[0]} applies to a pose plan: add --plan N (and no MEASUREMENTS)")
        if args.measurements is None:
            raise InputError("MEASUREMENTS is missing: give the measured poses (or --plan N to plan them)")
        return None
    return run_plan(args)


def run_plan(args: argparse.Namespace) -> int:
    from pathlib import Path

    from ...calibration.planning_candidates import parse_region, read_candidates
    from ...calibration.planning_poses import DEFAULT_CANDIDATES, DEFAULT_NOISE, plan_poses
    from ...errors import InputError
    from ..support.common import load_input, parse_q
    from ..support.output import print_json, wrote

    if args.measurements is not None:
        raise InputError(f"--plan: no MEASUREMENTS ({args.measurements}): the plan says which poses to measure")
    out = Path(args.output)
    if out.suffix.lower() != ".csv":
        raise InputError(f"{out}: a pose plan is written as .csv")
    if out.is_dir():
        raise InputError(f"{out}: is a folder; -o names the output file")
    if args.box is not None and args.cone is not None:
        raise InputError("--box and --cone: give one region")
    region = None
    if args.box is not None:
        region = parse_region("box", args.box)
    elif args.cone is not None:
        region = parse_region("cone", args.cone)
    robot = load_input(args.input, args)
    marker = None if args.marker is None else parse_q(args.marker, 3, "--marker")
    candidates = None if args.candidates is None else read_candidates(args.candidates, robot)
    plan = plan_poses(robot, args.plan, model=args.model, candidates=candidates, region=region,
                      noise=DEFAULT_NOISE if args.noise is None else args.noise, marker=marker,
                      base_known=args.base_known, random_count=args.random_candidates or DEFAULT_CANDIDATES,
                      seed=args.seed, source=args.candidates)
    write_poses_csv(out, plan.joints, plan.q)
    wrote(out)
    if args.json:
        d = plan.to_dict()
        d.update(model_file=args.input, output=str(out), candidates_file=args.candidates)
        print_json(d)
    else:
        sys.stdout.write(plan.text() + "\n")
    return 0


def write_poses_csv(path, joints: list[str], q) -> None:
    """The configurations (N, n) as CSV: a header of joint names, full-precision numbers, atomically."""
    import csv
    import io

    from ...io.files.atomic import write_text_atomic
    from ...io.tables.cells import csv_text_cell

    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow([csv_text_cell(h) for h in joints])   # a joint name starting a formula gets its quote
    for row in q:
        w.writerow([repr(float(v)) for v in row])
    write_text_atomic(path, buf.getvalue())
