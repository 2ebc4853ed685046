"""robkin fk: the tool pose at a joint configuration."""

from __future__ import annotations

import argparse
import json

from ._common import add_input, load_input, parse_q

EPILOG = """\
The pose is the tool frame in the robot base frame (a world->base transform is not applied).
Joint values are radians (revolute) and lengths (prismatic); expressions such as pi/2 are accepted.

examples:
  robkin fk rrpr.yaml --q 3*pi/4,-pi/4,0.3,-3*pi/4
  robkin fk rrpr.yaml --q -0.5,0,0.1,0 --json
  robkin fk ur5.urdf --q 0,0,0,0,0,0 --json
"""


def register(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    p = sub.add_parser("fk", help="forward kinematics: tool pose at q",
                       description="Forward kinematics: the tool pose in the robot base frame at q.",
                       epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_input(p)
    p.add_argument("--q", required=True, metavar="Q1,Q2,...", help="joint values, one per joint")
    p.add_argument("--json", action="store_true", help='print {"T": 4x4} as JSON')
    return p


def run(args: argparse.Namespace) -> int:
    from .. import se3
    from ..io.tables import fmt_num, matrix_text

    robot = load_input(args.input, args)
    q = parse_q(args.q, robot.n)
    T = robot.fk(q)
    if args.json:
        print(json.dumps({"T": [[float(v) + 0.0 for v in row] for row in T]}))
        return 0
    rpy = se3.rpy_from_matrix(T[:3, :3])
    print(matrix_text(T, "T (tool in base frame)"))
    print("position: " + ", ".join(fmt_num(v) for v in T[:3, 3]))
    print("rpy:      " + ", ".join(fmt_num(v) for v in rpy) + "  (roll, pitch, yaw; R = Rz Ry Rx)")
    return 0
