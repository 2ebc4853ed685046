"""robkin fk: the tool pose at a joint configuration."""

from __future__ import annotations

import argparse

from typing import TYPE_CHECKING, Any

from ..errors import InputError
from .support.common import add_degrees, add_input, add_threads, load_input, parse_q, revolute_degrees
from .support.gravity import EPILOG as GRAVITY_EPILOG
from .support.gravity import add_gravity, gravity_extras, print_gravity

if TYPE_CHECKING:  # pragma: no cover
    import numpy as np

    from ..robot import Robot

EPILOG = """\
The pose is the tool frame in the robot base frame (a world->base transform is not applied).
Joint values are radians (revolute) and lengths (prismatic); expressions such as pi/2 are accepted.

Many configurations: --q-file FILE (CSV with a header naming the joints or q1..qn, .npy, .npz; '-'
for standard input) computes them all in one batch and writes one row per input row - the joint values,
x, y, z, roll, pitch, yaw, qw, qx, qy, qz, success and error (a joint outside its limits) - as CSV on
stdout, as JSON with --json ({"joints": [...], "results": [{"q", "T", "position", "rpy", "quaternion",
"success", "error"}, ...]}), or to -o OUT.csv|.npy|.npz|.json (.npy: the (N, 4, 4) poses). The CSV
reads back as 'robkin ik --poses'. Progress goes to stderr on a terminal for runs of 4096 rows or more.

examples:
  robkin fk rrpr.yaml --q 3*pi/4,-pi/4,0.3,-3*pi/4
  robkin fk rrpr.yaml --q -0.5,0,0.1,0 --json
  robkin fk ur5.urdf --tip-link tool0 --q 0,-pi/2,0,-pi/2,0,0 --json
  robkin fk scara.yaml --q 0,0.3,0.5,0,1 --jacobian --manipulability
  robkin fk ur5.urdf --tip-link tool0 --q 0,-pi/4,pi/2,0,0,0 --gravity
  robkin fk ur5.urdf --tip-link tool0 --q-file q.csv -o poses.csv
  robkin ik ur5.urdf --tip-link tool0 --poses targets.csv | robkin fk ur5.urdf --tip-link tool0 --q-file -
  robkin fk ur5_rows.txt --from dh --q 0,-pi/2,0,-pi/2,0,0
"""


def register(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    p = sub.add_parser("fk", help="forward kinematics: tool pose at q",
                       description="Forward kinematics: the tool pose in the robot base frame at q.",
                       epilog=EPILOG + "\n" + GRAVITY_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_input(p)
    which = p.add_mutually_exclusive_group(required=True)
    which.add_argument("--q", metavar="Q1,Q2,...", help="joint values, one per joint")
    which.add_argument("--q-file", metavar="FILE",
                       help="many joint vectors: CSV with a header (columns named as the joints, or q1..qn), "
                            ".npy (N, n) or .npz; '-' reads standard input. One output row per input row")
    p.add_argument("--json", action="store_true",
                   help='print JSON: "T" (4x4), "position", "rpy", "quaternion" {w, x, y, z}, "joints" '
                        'and "q"')
    add_degrees(p, "revolute joint values in --q, and roll, pitch, yaw and q in the output")
    add_threads(p)
    from .support.batches import add_output

    add_output(p, "--q-file")
    p.add_argument("--jacobian", action="store_true",
                   help='also the geometric Jacobian [v; w] (6 x n, base frame, at the tool origin); '
                        'JSON key "J"')
    p.add_argument("--manipulability", action="store_true",
                   help="also Yoshikawa's manipulability (translational, rotational, full), inverse "
                        'condition number and minimum singular value; JSON key "manipulability"')
    add_gravity(p)
    return p


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from .. import se3
    from ..io.tables.terminal import fmt_num, matrix_text
    from .support.output import joint_names, print_json, warn_outside_limits

    robot = load_input(args.input, args)
    if args.q_file is not None:
        from .support.batches import fk_batch

        if args.jacobian or args.manipulability:
            raise InputError("--jacobian/--manipulability: one --q at a time (for many, use Robot.jacobian "
                             "on an (N, n) array in Python)")
        if args.gravity or args.gravity_vector:
            raise InputError("--gravity: one --q at a time (for many, use Robot.gravity on an (N, n) array "
                             "in Python)")
        return fk_batch(robot, args)
    if args.output:
        raise InputError("-o: writes the results of --q-file; for one --q use --json > FILE")
    q = parse_q(args.q, robot.n)
    if args.degrees:
        q = revolute_degrees(robot, q, to_radians=True)
    warn_outside_limits(robot, q)
    T = robot.fk(q)
    rpy = se3.rpy_from_matrix(T[:3, :3])
    extra = {**_jacobian_extras(robot, q, args), **gravity_extras(robot, q, args)}
    quat = se3.quaternion_from_matrix(T[:3, :3])
    if args.degrees:
        rpy, q = np.degrees(rpy), revolute_degrees(robot, q, to_radians=False)
    if args.json:
        print_json({"T": T, "position": T[:3, 3], "rpy": rpy, "quaternion": dict(zip("wxyz", quat)),
                    "joints": joint_names(robot), "q": q, **extra})
        return 0
    unit = "degrees" if args.degrees else "radians"
    print(matrix_text(T, "T (tool in base frame)"))
    print("position:   " + ", ".join(fmt_num(v) for v in T[:3, 3]) + "  (x, y, z in m)")
    print("rpy:        " + ", ".join(fmt_num(v) for v in rpy) + f"  (roll, pitch, yaw in {unit}; R = Rz Ry Rx)")
    print("quaternion: " + ", ".join(fmt_num(v) for v in quat) + "  (w, x, y, z)")
    if "J" in extra:
        from ..io.tables.terminal import text_table

        rows = [[name] + [fmt_num(v) for v in row] for name, row in zip(("vx", "vy", "vz", "wx", "wy", "wz"),
                                                                          extra["J"])]
        print(text_table([""] + joint_names(robot), rows,
                         title="J (geometric, base frame, at the tool origin; a column per joint, by name)"))
    for key, value in extra.get("manipulability", {}).items():
        print(f"{key}: {fmt_num(value)}")
    print_gravity(robot, extra, args)
    return 0


def _jacobian_extras(robot: "Robot", q: "np.ndarray", args: argparse.Namespace) -> dict[str, Any]:
    """The Jacobian and manipulability measures asked for by --jacobian / --manipulability."""
    out: dict[str, Any] = {}
    if args.jacobian:
        out["J"] = robot.jacobian(q)
    if args.manipulability:
        from ..kinematics.jacobian import measures

        out["manipulability"] = measures(robot, q)
    return out
