"""robkin ik: joint values that put the tool at a pose (closed form where possible, else numeric)."""

from __future__ import annotations

import argparse
import json
import sys

from ._common import add_degrees, add_input, load_input, parse_pose, parse_q, revolute_degrees

EPILOG = """\
The pose is the tool frame in the robot base frame: x,y,z,roll,pitch,yaw (URDF rpy, radians) or
16 numbers (a row-major 4x4). Expressions such as pi/2 are accepted.

The solver is closed-form where the geometry allows - SCARA-type arms (all axes parallel: both elbow
solutions; redundant vertical joints split nearest to --q0), 6R arms with axes 2 || 3 and a spherical
wrist (KUKA, ABB, Fanuc type) and 6R arms with axes 2 || 3 || 4 (Universal Robots type), up to 8
solutions - and Levenberg-Marquardt with joint limits and random restarts otherwise. Every solution
printed is checked by forward kinematics to the tolerances.

A pose with no solution is not an error: the output has no solutions, the reason goes to stderr
(one line), and the exit status is 0. Exit status 2 means bad input (file, pose, options).

examples:
  robkin ik scara.yaml --pose 7.87,0,-3.94,0,0,0
  robkin ik scara.yaml --pose 10,5,-2,0,0,0.5 --all --json
  robkin ik ur5.urdf --tip-link tool0 --pose 0.4,0.1,0.3,pi,0,0 --all
  robkin ik panda.urdf --tip-link panda_hand_tcp --pose 0.5,0,0.4,pi,0,0 --q0=0,0,0,-1.5,0,1.5,0
  robkin ik panda.urdf --tip-link panda_hand_tcp --pose 0.5,0,0.4,0,0,0 --position-only
"""


def register(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    p = sub.add_parser("ik", help="inverse kinematics: joint values for a tool pose",
                       description="Inverse kinematics: joint values that put the tool at a pose in the "
                                   "robot base frame.",
                       epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_input(p)
    p.add_argument("--pose", required=True, metavar="POSE",
                   help="x,y,z,roll,pitch,yaw or 16 numbers (row-major 4x4)")
    p.add_argument("--all", action="store_true",
                   help="every distinct solution (closed form: all branches; numeric: those found from "
                        "1 + RESTARTS starts)")
    p.add_argument("--json", action="store_true", help='print {"solutions": [{"q": [...]}, ...]}')
    add_degrees(p, "roll, pitch, yaw in --pose, revolute joint values in --q0 and in the solutions")
    p.add_argument("--q0", metavar="Q1,Q2,...",
                   help="preferred configuration: numeric start and tie-break (default: zeros)")
    mask = p.add_mutually_exclusive_group()
    mask.add_argument("--position-only", action="store_true", help="match the position only (numeric)")
    mask.add_argument("--mask", metavar="X,Y,Z,RX,RY,RZ",
                      help="components to match, six 0/1 values (numeric unless all 1)")
    p.add_argument("--method", choices=("auto", "analytic", "numeric"), default="auto",
                   help="solver (default: auto = closed form when one fits)")
    p.add_argument("--tol-position", type=float, default=1e-9, metavar="LENGTH",
                   help="position tolerance in length units (default 1e-9)")
    p.add_argument("--tol-orientation", type=float, default=1e-9, metavar="RAD",
                   help="orientation tolerance in radians (default 1e-9)")
    p.add_argument("--restarts", type=int, default=50, metavar="N",
                   help="numeric: random restarts after the first attempt (default 50)")
    p.add_argument("--seed", type=int, default=0, help="numeric: random seed (default 0)")
    return p


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from ..io.numbers import number_list
    from ..io.tables import fmt_num, text_table
    from ..errors import InputError

    robot = load_input(args.input, args)
    T = parse_pose(args.pose, degrees=args.degrees)
    q0 = parse_q(args.q0, robot.n, "--q0") if args.q0 else None
    if q0 is not None and args.degrees:
        q0 = revolute_degrees(robot, q0, to_radians=True)
    mask = "position" if args.position_only else None
    if args.mask:
        mask = number_list(args.mask, "--mask")
        if len(mask) != 6:
            raise InputError(f"--mask: expected 6 values 0/1 for x,y,z,rx,ry,rz, got {len(mask)}")
    result = robot.ik(T, q0=q0, mask=mask, method=args.method, all_solutions=args.all,
                      tol_position=args.tol_position, tol_orientation=args.tol_orientation,
                      restarts=args.restarts, rng=args.seed)
    if result.success:
        solutions = result.solutions if args.all else result.q[None]
    else:
        solutions = np.empty((0, robot.n))
        print(f"robkin: ik: no solution ({result.method}): {result.message}", file=sys.stderr)
    if args.degrees:
        solutions = revolute_degrees(robot, solutions, to_radians=False)
    if args.json:
        print(json.dumps({"solutions": [{"q": [float(v) + 0.0 for v in q]} for q in solutions]}))
        return 0
    names = [j.name for j in robot.joints]
    rows = [[str(i + 1)] + [fmt_num(v) for v in q] for i, q in enumerate(solutions)]
    if rows:
        print(text_table(["#"] + names, rows, title=f"IK solutions ({result.method}, nearest to q0 first)"))
    return 0
