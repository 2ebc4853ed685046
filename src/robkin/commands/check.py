"""robkin check: are two descriptions (e.g. a vendor DH table and a URDF) the same robot?"""

from __future__ import annotations

import argparse
import math

from .support.chains import add_chain_options

EPILOG = """\
Two descriptions are the same robot when the tool pose is the same at every joint vector q. If they
are not, the joints are compared in order and the first one that differs is named, with how: joint
type, axis direction (angle), axis position (distance), positive direction (sign) or zero offset.
Descriptions that differ only in signs and zero offsets are the same mechanism with another joint
convention; the table gives the mapping q_A = sign * q_B + offset. Where a zero offset would carry one
axis into place but leave more axes (and the tool) out of place than the axes as they are, the joint
named is the first whose axis line differs: a tilted joint k is joint k, not an offset of joint k-1.
Values that differ are printed with as many digits as show the difference (mass 14.5893 kg vs
14.58932 kg).

Past a difference the comparison goes on: both robots are written as the same kind of table (standard
DH, or modified DH / Hayati when either came from one) by the same frame rules, and every row that
differs says which parameters and by how much ("a2 -0.6127 vs -0.612 m"); a joint whose row matches is
'aligned'. Lengths are in the robots' unit (metres), angles in radians unless marked deg. A half turn
at joint 1 is nearly always the base frame (a UR URDF's base_link against the base of UR's DH tables):
a note says so, with the option that picks the other base. Robots with different joint counts get
the verdict first.

Where both give mass properties (URDF/MJCF/SDF inertials, or m, r, I in a table's rows) and the
mechanism is the same, they are compared too: body by body (mass, centre of mass, inertia; body i is
everything that moves with joint i) and through the mass matrix M(q) and gravity torques g(q) at 16
fixed configurations (gravity along -z of each base); the first body that differs is named. Bodies
that differ make the exit status 1; a side without inertials is reported as not compared.

exit status: 0 same robot (and the same mass properties, where both have them); 1 not the same robot
(including a different joint convention, or different mass properties); 2 bad input.

With measurements as B (.csv, .npz or .npy, the format 'robkin calibrate' reads), the model is
compared with measured samples: given its best base and marker, how far it is from them (RMS and
max), and which joint's parameters, then which parameter, explain most of the difference. Then --tol
is the RMS position residual in metres the model may leave (default 0.0005); exit status 0 if the
model explains them within it. A model whose joints carry a stiffness (calibrate --compliance) is
deflected by the gravity torques of the links and of the measurements' payload column first.

--report iso9283 prints instead ISO 9283 pose accuracy AP and repeatability RP per commanded pose (the
rows with equal joint values; the command being the model with its best base and marker); --report html
-o REPORT.html writes a standalone page with the diagnosis, that table and residual plots per pose and
per joint (matplotlib). The exit status is the same.

examples:
  robkin check ur5.urdf ur5_dh.yaml --tip-link tool0
  robkin check vendor_dh.yaml robot.urdf --tol 1e-4       # a table typed with 4 decimals
  robkin check a.yaml b.yaml --json
  robkin check ur5.urdf ur5_dh.yaml --tip-link tool0 --tip-link -     # a chain per input, in order
  robkin check ur5_rows.txt ur5.urdf --from dh --base-link - --base-link base --tip-link - --tip-link tool0
  robkin check ur5.urdf measurements.csv --tip-link tool0            # a model against measurements
  robkin check ur5.urdf measurements.csv --tip-link tool0 --report iso9283
  robkin check ur5.urdf measurements.csv --tip-link tool0 --report html -o report.html
"""


def register(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    from .support.common import add_allow_xacro, add_from

    p = sub.add_parser("check", help="are two descriptions (or a model and measurements) the same robot? (exit 0 if yes)",
                       description="Compare two robot descriptions joint by joint: are they the same robot, "
                                   "and if not, which joint differs first and how.",
                       epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("a", metavar="A", help="first robot (document .yaml/.yml/.json, .urdf/.xacro, .xml/.mjcf, .sdf or "
                                            ".usda/.usd/.usdc)")
    p.add_argument("b", metavar="B", help="second robot, or measurements (.csv, .npz, .npy) to compare A with")
    add_chain_options(p)
    add_allow_xacro(p)
    add_from(p)
    p.add_argument("--tol", type=float, default=None,  # 1e-6 = equivalence.DEFAULT_TOL (not imported: startup time)
                   help="relative tolerance on angles (rad) and lengths / robot size (default 1e-06); against "
                        "measurements: RMS position residual in metres (default 0.0005)")
    p.add_argument("--payload-com", metavar="X,Y,Z",
                   help="against measurements with a payload column: the payload's centre of mass in the model's "
                        "tool frame (m; default the tool origin)")
    p.add_argument("--json", action="store_true", help="print the comparison as JSON")
    from .support.measurement_reports import add_report_options

    add_report_options(p)
    return p


def run(args: argparse.Namespace) -> int:
    from ..equivalence.comparison import compare
    from ..errors import InputError

    from .support.measurement_reports import check_report_options

    measured = args.b.lower().endswith((".csv", ".npz", ".npy"))
    check_report_options(args, measured)
    if measured:   # a model against measured samples
        from .support.check_measurements import run_measurements

        return run_measurements(args)
    args.tol = 1e-6 if args.tol is None else args.tol
    if not (math.isfinite(args.tol) and args.tol > 0):
        raise InputError(f"--tol: {args.tol} is not a positive number")
    from .support.chains import chain_ends
    from ..io import load

    (base_a, tip_a), (base_b, tip_b) = chain_ends(args, [args.a, args.b])
    rep = args.representation
    a = load(args.a, base_link=base_a, tip_link=tip_a, allow_xacro=args.allow_xacro,
             representation=rep if args.a.lower().endswith((".csv", ".tsv", ".txt")) else None)
    b = load(args.b, base_link=base_b, tip_link=tip_b, allow_xacro=args.allow_xacro,
             representation=rep if args.b.lower().endswith((".csv", ".tsv", ".txt")) else None)
    from ..messages import render_options

    result = compare(a, b, tol=args.tol)
    from ..dynamics.compare import compare_masses, same_robot

    masses = compare_masses(a, b, result)
    if args.json:
        d = result.to_dict()
        d["a"], d["b"] = args.a, args.b
        d["notes"] = [render_options(note, args._flags) for note in d["notes"]]
        d["mass"] = masses.to_dict()
        from .support.output import print_json

        print_json(d)
    else:
        from ..equivalence.report import comparison_blocks
        from ..io.tables.text import show_blocks

        kinds = lambda r: "".join("R" if j.revolute else "P" for j in r.joints)  # noqa: E731
        title = f"A: {args.a} ({a.n} joints {kinds(a)})   B: {args.b} ({b.n} joints {kinds(b)})"
        # notes name options as the library does (base_link=): here as this command's flags
        show_blocks([render_options(blk, args._flags) if isinstance(blk, str) else blk
                     for blk in comparison_blocks(result, title)])
        print(masses.summary())
    return 0 if same_robot(result, masses) else 1


