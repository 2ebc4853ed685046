"""robkin calibrate: identify the real robot from measured tool points (and orientations)."""

from __future__ import annotations

import argparse
import sys

from .support.common import add_input, seed

EPILOG = """\
MEASUREMENTS is a CSV file with a header line: one column per joint, named as the model's joints
(q in radians, or metres for a prismatic joint), then x, y, z (the measured point in the measuring
device's frame, metres), optionally qw, qx, qy, qz (a unit quaternion of the measured orientation) and
payload (kg carried at that pose). .npz and .npy files with the same columns are read too (see the
calibration guide).

Identified: every joint's zero offset and the link parameters of the chosen model (hayati: Hayati rows
between nearly parallel axes, DH elsewhere, the default; mdh; poe: every joint frame moved freely), the
robot base in the measuring frame (unless --base-known) and the marker on the tool (unless --marker).
Parameters the measurements cannot determine are found (QR with column pivoting of the scaled
identification Jacobian), held at their nominal values and named in the report. The fit is robust:
poses far off (beyond 4.6 robust standard deviations) are rejected and listed.

--compliance also identifies each joint's stiffness (N m/rad; N/m prismatic): the joint deflects by the
gravity torque of the links (where the model has masses) and of the payload (at the measured point, or
at --payload-com in the model's tool frame) over its stiffness, gravity along -z of the robot base. A
joint whose gravity torque is ~0 at every pose (a vertical first axis) is reported as not observable.
The calibrated robot document carries 'stiffness' on each joint (URDF and MJCF have no place for it: a
warning says so; write .yaml or .json to keep it).

OUT is the calibrated robot, written by its extension: .urdf (keeps the source's link and joint names,
limits, shapes and inertials), .xml/.mjcf (MuJoCo), .yaml/.yml/.json (a robot document with every
section, except DH tables whose common normals run off between nearly parallel axes (a note says so);
--to picks one section: hayati, dh, mdh, poe, rpy-xyz, gjd). Its world transform (the URDF's world joint, the
RPY-XYZ table's row 0) is the robot base in the measuring frame and its tool origin is the measured
point, so world @ fk(q) predicts a measurement (the default: the file is the measured robot). Every source
link keeps its name; where the tool link is the last moving link, a fixed link 'marker' carries the
measured point. --keep-frames writes a drop-in replacement for MODEL instead: its world transform and
flange as MODEL's (moved with the calibrated chain), the marker as a fixed link 'marker' under the tool
link, the robot base in the measuring frame in the report only; 'robkin check MODEL OUT' then compares
flange with flange. The report goes to stdout (--json: as JSON).

For the controller: --offsets FILE.csv writes the joint zero offsets (joint, offset, unit, identified:
the real joint at encoder value q is where the nominal model puts q + offset); --table FILE writes the
calibrated table, flange kept, in the source's convention (a DH, modified DH or Hayati model; else
--to's) as .csv, .md, .tex, .yaml or .json; --filter TARGETS.csv --filtered OUT.csv reads flange poses
(x, y, z, qw, qx, qy, qz [, payload], robot base frame; 'robkin fk -o' writes such a file) and writes per target the joint values that
bring the calibrated robot there (IK started from the nominal model's own solution), the filtered pose
(the nominal model's FK of them: send it to a controller that runs the nominal kinematics), reached and
the error left (m).

exit status: 0 calibrated; 2 bad input (nothing written).

examples:
  robkin calibrate ur5.urdf measurements.csv -o ur5_calibrated.urdf --tip-link tool0
  robkin calibrate ur5.urdf measurements.csv -o ur5_calibrated.yaml --tip-link tool0 --to hayati
  robkin calibrate panda.urdf panda_poses.csv -o panda_cal.urdf --tip-link panda_link8 --holdout 0.2 --json
  robkin calibrate robot.yaml probe.csv -o robot_cal.yaml --base-known --marker 0,0,0.05
  robkin calibrate ur5.urdf loaded.csv -o ur5_cal.yaml --tip-link tool0 --compliance
  robkin calibrate ur5.urdf measurements.csv -o ur5_cal.urdf --tip-link tool0 --keep-frames
  robkin calibrate robot.yaml probe.csv -o cal.yaml --base-known --offsets offsets.csv --table cal_dh.csv
  robkin calibrate ur5.urdf measurements.csv -o c.yaml --tip-link tool0 --filter targets.csv --filtered cmd.csv
  robkin calibrate ur5.urdf --plan 30 -o poses.csv --tip-link tool0 --marker 0,0.03,0.05
"""

OUT_EXTENSIONS = (".urdf", ".xml", ".mjcf", ".yaml", ".yml", ".json")


def register(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    p = sub.add_parser("calibrate", help="identify the real robot from measurements (kinematic calibration)",
                       description="Kinematic calibration: fit a robot model to measured tool points (and "
                                   "orientations), and write the calibrated robot.",
                       epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_input(p)
    p.add_argument("measurements", metavar="MEASUREMENTS", nargs="?",
                   help="measured poses: .csv, .npz or .npy (none with --plan)")
    p.add_argument("-o", "--output", metavar="OUT", required=True,
                   help="the calibrated robot: .urdf, .xml/.mjcf, .yaml/.yml/.json")
    from ..representations.registry import names

    p.add_argument("--to", choices=sorted(names()),
                   help="write only this table section in a robot document (and --table's convention)")
    p.add_argument("--model", choices=["hayati", "mdh", "poe"], default="hayati",
                   help="error model (default hayati: Hayati rows between nearly parallel axes, DH elsewhere)")
    p.add_argument("--holdout", type=float, metavar="F", default=0.0,
                   help="fraction of the poses kept out of the fit to test the result on (default 0)")
    p.add_argument("--seed", type=seed, default=0, help="random seed of the hold-out choice (default 0)")
    p.add_argument("--base-known", action="store_true",
                   help="the model's world transform already is the robot base in the measuring frame: keep it")
    p.add_argument("--marker", metavar="X,Y,Z",
                   help="the measured point in the model's tool frame, if known (metres); identified otherwise")
    p.add_argument("--orientation-weight", type=float, metavar="M_PER_RAD",
                   help="metres per radian an orientation residual counts (default: from the residuals)")
    p.add_argument("--loss", choices=["huber", "linear"], default="huber",
                   help="huber (default: robust, outliers rejected and listed) or linear (plain least squares)")
    p.add_argument("--compliance", action="store_true",
                   help="also identify each joint's stiffness from the gravity deflections (payload column)")
    p.add_argument("--payload-com", metavar="X,Y,Z",
                   help="the payload's centre of mass in the model's tool frame (m; default the measured point)")
    p.add_argument("--keep-frames", action="store_true",
                   help="keep MODEL's world and flange frames (a drop-in replacement), the marker as a link")
    p.add_argument("--offsets", metavar="FILE.csv", help="also write the joint zero offsets (CSV)")
    p.add_argument("--table", metavar="FILE",
                   help="also write the calibrated table (flange kept) in the source's convention")
    p.add_argument("--filter", metavar="TARGETS.csv", help="flange poses to reach with the calibrated robot")
    p.add_argument("--filtered", metavar="OUT.csv", help="where --filter writes joint values and filtered poses")
    p.add_argument("--json", action="store_true", help="print the report as JSON")
    from .calibrate_parts.plan import add_plan_options

    add_plan_options(p)
    return p


def run(args: argparse.Namespace) -> int:
    from pathlib import Path

    from ..calibration.measurements import read_measurements
    from ..calibration.solve import calibrate
    from ..errors import InputError
    from ..io.files.atomic import write_texts_atomic
    from .support.common import load_input
    from .support.output import print_json, wrote
    from .calibrate_parts.plan import dispatch

    planned = dispatch(args)   # --plan N: the poses to measure, not a calibration
    if planned is not None:
        return planned
    out = Path(args.output)
    if out.suffix.lower() not in OUT_EXTENSIONS:
        raise InputError(f"{out}: the calibrated robot is written as {', '.join(OUT_EXTENSIONS)}")
    if args.to and out.suffix.lower() not in (".yaml", ".yml", ".json") and not args.table:
        raise InputError(f"--to {args.to}: a table section is written in a robot document (.yaml, .yml, .json)")
    if out.is_dir():
        raise InputError(f"{out}: is a folder; -o names the output file")
    if (args.filter is None) != (args.filtered is None):
        raise InputError("--filter TARGETS.csv and --filtered OUT.csv go together")
    robot = load_input(args.input, args)
    m = read_measurements(args.measurements, robot)
    from .support.common import parse_q

    marker = None if args.marker is None else parse_q(args.marker, 3, "--marker")
    com = None if args.payload_com is None else parse_q(args.payload_com, 3, "--payload-com")
    targets = None
    if args.filter is not None:
        from .calibrate_parts.controller import read_targets

        targets = read_targets(args.filter, robot)
    result = calibrate(robot, m.q, m.positions, m.quaternions, model=args.model,
                       world=robot.world if args.base_known else None, marker=marker,
                       orientation_weight=args.orientation_weight, loss=args.loss,
                       holdout=args.holdout or None, seed=args.seed, rows=m.rows, compliance=args.compliance,
                       payload=m.payloads, payload_com=com)
    from .calibrate_parts.frames import written_robot

    ext = out.suffix.lower()
    if ext not in (".yaml", ".yml", ".json") and any(j.stiffness for j in result.robot.joints):
        print(f"robkin: warning: {out}: {ext} has no place for joint stiffness: written without it (a .yaml or "
              f".json robot document keeps it)", file=sys.stderr)
    if args.keep_frames and ext in (".yaml", ".yml", ".json"):
        print(f"robkin: note: {out}: a robot document has no links: its tool is the calibrated flange, the "
              f"marker is in the report", file=sys.stderr)
    files = [(out, render_robot(written_robot(result, robot, args.keep_frames), ext, args.to))]
    files += _controller_files(args, result, robot, targets)
    write_texts_atomic(files)
    for path, _ in files:
        wrote(path)
    if args.json:
        d = result.to_dict()
        d.update(model_file=args.input, measurements=args.measurements, output=str(out))
        print_json(d)
    else:
        sys.stdout.write(result.text() + "\n")
    return 0


def _controller_files(args: argparse.Namespace, result, robot, targets) -> list:
    """(path, text) of --offsets, --table and --filtered."""
    from .calibrate_parts import controller
    from .calibrate_parts.frames import written_robot

    out = []
    if args.offsets:
        out.append((args.offsets, controller.offsets_csv(result, robot)))
    kept = written_robot(result, robot, keep_frames=True)
    if args.table:
        out.append((args.table, controller.table_text(kept, robot, args.table, args.to)))
    if targets is not None:
        q, poses, ok, err = controller.filter_targets(kept, robot, *targets)
        out.append((args.filtered, controller.filtered_csv(robot, q, poses, ok, err)))
    return out


def render_robot(robot, ext: str, section: str | None = None) -> str:
    """The robot as the text of a file with extension ``ext`` (and only ``section`` in a document)."""
    if ext == ".urdf":
        from ..io.urdf import urdf_from_robot

        return urdf_from_robot(robot)
    if ext in (".xml", ".mjcf"):
        from ..io.mjcf import mjcf_from_robot

        return mjcf_from_robot(robot)
    from ..io.documents.reader import document_from_robot, dump

    from ..representations.registry import by_name

    sections = short_sections(robot) if section is None else (by_name(section).section,)
    return dump(document_from_robot(robot, sections), "json" if ext == ".json" else "yaml")


#: A table whose lengths exceed this many robot sizes has a runaway common normal (nearly parallel axes)
RUNAWAY = 10.0


def short_sections(robot) -> tuple[str, ...]:
    """Every document section except a link table (DH, modified DH) whose common normals run off.

    A calibrated robot's nearly parallel axes (a UR's shoulder, elbow and wrist 1) are no longer exactly
    parallel: their DH rows are exact but put the common normal hundreds of metres away, useless to
    anyone reading the file; the Hayati section holds the same robot in short rows. ``--to dh`` still
    writes it.
    """
    import warnings

    import numpy as np

    from ..representations.registry import by_section, sections

    keep = []
    for key in sections():
        rep = by_section(key)
        if rep.layout == "link-table":
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")   # the conditioning warning is what this check reports
                table = rep.table_of(robot)
            lengths = [k for k, c in enumerate(rep.columns) if c.kind == "length"]
            longest = float(np.abs(table.rows[:, lengths]).max())
            if longest > RUNAWAY * robot.scale:
                print(f"robkin: note: section {key} left out: between nearly parallel axes its common normal "
                      f"runs {longest:.3g} m away (--to {rep.name} writes it anyway; the hayati section is exact "
                      f"and short)", file=sys.stderr)
                continue
        keep.append(key)
    return tuple(keep)
