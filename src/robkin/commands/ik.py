"""robkin ik: joint values that put the tool at a pose (closed form where possible, else numeric)."""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING

from .support.common import (add_degrees, add_input, add_package_path, add_threads, load_input, package_paths,
                             parse_pose, parse_q, revolute_degrees, seed)

if TYPE_CHECKING:  # pragma: no cover
    import numpy as np

    from ..robot import Robot

EPILOG = """\
The pose is the tool frame in the robot base frame: x,y,z,roll,pitch,yaw (URDF rpy, radians) or
16 numbers (a row-major 4x4). Expressions such as pi/2 are accepted.

The solver is closed-form where the geometry allows - SCARA-type arms (all axes parallel: both elbow
solutions; redundant vertical joints split nearest to --q0), 6R arms with axes 2 || 3 and a spherical
wrist (KUKA, ABB, Fanuc type) and 6R arms with axes 2 || 3 || 4 (Universal Robots type), up to 8
solutions, arms within calibration error of those, and every other revolute 6R arm (up to 16 solutions)
- and Levenberg-Marquardt with joint limits and random restarts otherwise. A 7-joint arm is solved in
closed form with one joint held: --lock NAME=VALUE (repeatable; any method, any number of joints; the
solutions printed are full length). An SRS arm (KUKA iiwa: 7R, axes 1-3 and 5-7 meeting) takes the
elbow's swivel instead: --arm-angle PSI gives every solution (up to 8) at that arm angle, the printed
one on --q0's branch. Every solution printed is checked by forward kinematics to the
tolerances.

The start: --q0, or by default a configuration inside every joint's limits (zero for each joint whose
range holds zero, else the middle of its range: the Panda's joint 4, range [-3.07, -0.07], starts at
-1.57). One solution is the one nearest the start among those found (closed form: of every branch;
numeric: the first success, from the start itself when that attempt succeeds). --all lists one row per
closed-form branch; a numeric set on a redundant arm (a 7-joint arm at a full pose, any arm with
--position-only) is a continuum, of which the rows kept differ pairwise by more than 0.5 rad in some
revolute joint (0.1 x the robot's size in some prismatic one).

A pose with no solution is not an error: the output has no solutions, the reason and the closest
configuration's distance from the target (as the GUI shows it; JSON key "closest": q, position_error
in length units, orientation_error in radians) go to stderr (one line), and the exit status is 0.
Exit status 2 means bad input (file, pose, options).

Many targets: --poses FILE (CSV with a header: x, y, z and qw, qx, qy, qz or roll, pitch, yaw, as
'robkin fk -o' writes them, or m11..m34; .npy (N, 4, 4), (N, 6), (N, 7) or .npz; '-' for standard
input) solves them in one batch (Robot.ik on (N, 4, 4)) and writes one row per target - success, the
joint values (the closest configuration where there is no solution), position_error, orientation_error
and the reason - as CSV on stdout, as JSON with --json ({"joints", "method", "results": [{"q", "success",
"position_error", "orientation_error", "reason"}, ...]}), or to -o OUT.csv|.npy|.npz|.json (.npy: the
(N, n) joint values). With --all every solution of every target: one CSV row each (column 'solution'
numbers them; 0 marks a target without one), "solutions" per target in JSON, and in .npz an array
'solutions' (M, 1 + n) of the target's row index (from 0) and q. Progress goes to stderr on a terminal
for runs of 4096 targets or more.

examples:
  robkin ik scara.yaml --pose 7.87,0,-3.94,0,0,0
  robkin ik scara.yaml --pose 10,5,-2,0,0,0.5 --all --json
  robkin ik ur5.urdf --tip-link tool0 --pose 0.4,0.1,0.3,pi,0,0 --all
  robkin ik panda.urdf --tip-link panda_hand_tcp --pose 0.5,0,0.4,pi,0,0 --q0=0,0,0,-1.5,0,1.5,0
  robkin ik panda.urdf --tip-link panda_hand_tcp --pose 0.5,0,0.4,0,0,0 --position-only
  robkin ik panda.urdf --tip-link panda_hand_tcp --pose 0.5,0,0.4,pi,0,0 --lock panda_joint7=0.8 --all
  robkin ik ur5.urdf --tip-link tool0 --poses targets.csv -o solutions.csv
  robkin ik iiwa14.yaml --pose 0.5,0,0.5,0,180,0 --degrees --arm-angle 30 --all
"""


def register(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    p = sub.add_parser("ik", help="inverse kinematics: joint values for a tool pose",
                       description="Inverse kinematics: joint values that put the tool at a pose in the "
                                   "robot base frame.",
                       epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_input(p)
    which = p.add_mutually_exclusive_group(required=True)
    which.add_argument("--pose", metavar="POSE", help="x,y,z,roll,pitch,yaw or 16 numbers (row-major 4x4)")
    which.add_argument("--poses", metavar="FILE",
                       help="many target poses: CSV with a header (x, y, z with qw, qx, qy, qz or roll, pitch, "
                            "yaw; or m11..m34), .npy (N, 4, 4) / (N, 6) / (N, 7) or .npz; '-' reads standard "
                            "input. One output row per target, with success and error columns")
    p.add_argument("--all", action="store_true",
                   help="every distinct solution, nearest to --q0 first (closed form: one per branch; "
                        "numeric: those found from 1 + RESTARTS starts, and on a redundant arm (more joints "
                        "than matched components) only those more than 0.5 rad apart in some joint)")
    p.add_argument("--json", action="store_true",
                   help='print {"solutions": [{"q": [...], "position_error": ..., "orientation_error": ...}], '
                        '"joints": [...], "method": ..., "success": ..., "reason": ...}')
    add_degrees(p, "roll, pitch, yaw in --pose, revolute joint values in --q0 and in the solutions")
    p.add_argument("--q0", metavar="Q1,Q2,...",
                   help="preferred configuration: numeric start and tie-break, clipped into the limits (default: "
                        "zero for each joint whose range holds it, else the middle of its range)")
    mask = p.add_mutually_exclusive_group()
    mask.add_argument("--position-only", action="store_true", help="match the position only (numeric)")
    mask.add_argument("--mask", metavar="X,Y,Z,RX,RY,RZ",
                      help="components to match, six 0/1 values (numeric unless all 1)")
    p.add_argument("--lock", action="append", default=[], metavar="NAME=VALUE",
                   help="hold joint NAME at VALUE (radians, or degrees with --degrees; within its limits) and "
                        "solve the others: a 7-joint arm with one joint locked gets a 6R closed form; "
                        "repeatable")
    p.add_argument("--arm-angle", metavar="PSI",
                   help="SRS arms (iiwa): the elbow's swivel about the shoulder-wrist line (radians, or degrees "
                        "with --degrees; 0 = elbow in the plane of that line and joint 1's axis, on the side "
                        "joint 1's axis points to); every solution at that angle, up to 8")
    p.add_argument("--method", choices=("auto", "analytic", "numeric"), default="auto",
                   help="solver (default: auto = closed form when one fits)")
    p.add_argument("--tol-position", type=float, default=1e-9, metavar="LENGTH",
                   help="position tolerance in length units (default 1e-9)")
    p.add_argument("--tol-orientation", type=float, default=1e-9, metavar="RAD",
                   help="orientation tolerance in radians (default 1e-9)")
    p.add_argument("--restarts", type=int, default=200, metavar="N",
                   help="numeric: restarts after the first attempt, spread over the joint limits (default "
                        "200, as Robot.ik; a target stops at its first success)")
    p.add_argument("--seed", type=seed, default=0, help="numeric: random seed (default 0)")
    p.add_argument("--collision-free", action="store_true",
                   help="only solutions free of self collision (the robot's collision geometry: capsules, then "
                        "the links' convex parts, conservative: a solution kept is free for the meshes; the "
                        "allowed-collision matrix sampled as 'robkin collision' does, or read from --srdf); see "
                        "docs/collision.md")
    p.add_argument("--srdf", metavar="FILE", help="with --collision-free: the link pairs never checked (SRDF "
                                                  "<disable_collisions>, as 'robkin collision' writes)")
    add_package_path(p)
    add_threads(p)
    from .support.batches import add_output

    add_output(p, "--poses")
    return p


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from ..io.files.numbers import number_list
    from ..errors import InputError

    robot = load_input(args.input, args)
    if args.output and not args.poses:
        raise InputError("-o: writes the results of --poses; for one --pose use --json > FILE")
    T = None if args.poses else parse_pose(args.pose, degrees=args.degrees)
    q0 = parse_q(args.q0, robot.n, "--q0") if args.q0 else None
    if q0 is not None and args.degrees:
        q0 = revolute_degrees(robot, q0, to_radians=True)
    mask = "position" if args.position_only else None
    if args.mask:
        mask = number_list(args.mask, "--mask")
        if len(mask) != 6:
            raise InputError(f"--mask: expected 6 values 0/1 for x,y,z,rx,ry,rz, got {len(mask)}")
    solve = dict(q0=q0, mask=mask, method=args.method, tol_position=args.tol_position,
                 tol_orientation=args.tol_orientation, restarts=args.restarts,
                 lock=_parse_lock(robot, args.lock, args.degrees))
    if args.arm_angle is not None:
        import math

        from ..io.files.numbers import number

        psi = number(args.arm_angle, "--arm-angle")
        solve["arm_angle"] = math.radians(psi) if args.degrees else psi
    if args.collision_free:
        _collision_model(robot, args)
        solve["avoid_self_collision"] = True
    elif args.srdf:
        raise InputError("--srdf: goes with --collision-free")
    if args.poses:
        from .support.batches import ik_batch

        return ik_batch(robot, args, solve)
    result = robot.ik(T, all_solutions=args.all, rng=args.seed, **solve)
    closest = None
    if result.success:
        solutions = result.solutions if args.all else result.q[None]
    else:
        from .support.batches import closest_of

        solutions = np.empty((0, robot.n))
        closest = closest_of(robot, T, result, args.seed)
        print(f"robkin: ik: no solution ({result.method}): {result.message}; closest: "
              f"{closest['position_error']:.4g} m from the target position, "
              f"{closest['orientation_error']:.4g} rad from its orientation", file=sys.stderr)
    errors = [_residuals(robot, q, T) for q in solutions]
    if args.degrees:
        solutions = revolute_degrees(robot, solutions, to_radians=False)
    if args.json:
        from .support.output import joint_names, print_json

        print_json({"solutions": [{"q": q, "position_error": e[0], "orientation_error": e[1]}
                                  for q, e in zip(solutions, errors)],
                    "joints": joint_names(robot), "method": result.method, "success": bool(result.success),
                    "reason": None if result.success else result.message,
                    **({} if closest is None else {"closest": {**closest, "q": revolute_degrees(
                        robot, closest["q"], to_radians=False) if args.degrees else closest["q"]}})})
        return 0
    if len(solutions):
        from ..kinematics.ik_text import solutions_block
        from ..io.tables.terminal import show_blocks

        show_blocks([solutions_block(solutions, result.method, [j.name for j in robot.joints])])
    return 0


def _parse_lock(robot: "Robot", items: list[str], degrees: bool) -> dict[str, float] | None:
    """--lock NAME=VALUE options as {name: value} (radians / length units), or None; each name once."""
    import math

    from ..errors import InputError, quote
    from ..io.files.numbers import number

    lock: dict[str, float] = {}
    for item in items:
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise InputError(f"--lock: expected NAME=VALUE, got {quote(item)}")
        if name in lock:
            raise InputError(f"--lock: joint {quote(name)} is given twice")
        value = number(text, f"--lock {name}")
        revolute = {j.name: j.revolute for j in robot.joints}.get(name, True)
        lock[name] = math.radians(value) if degrees and revolute else value
    return lock or None


def _residuals(robot: "Robot", q: "np.ndarray", T: "np.ndarray") -> tuple[float, float]:
    """Position error |p_T - p(q)| (length units) and orientation error |log(R_T R(q)^T)| (radians)."""
    import numpy as np

    from .. import se3

    F = robot.fk(q)
    angle = np.linalg.norm(se3.log_rotation(T[:3, :3] @ F[:3, :3].T))
    return float(np.linalg.norm(T[:3, 3] - F[:3, 3])), float(angle)


def _collision_model(robot, args: argparse.Namespace) -> None:
    """The self-collision model ``Robot.ik(avoid_self_collision=True)`` then uses for this robot."""
    from ..io.srdf import read_srdf
    from ..self_collision.build import self_collision_model
    from ..self_collision.model import DisabledPair

    disabled = [DisabledPair(*p) for p in read_srdf(args.srdf)[1]] if args.srdf else None
    self_collision_model(robot, args.input, package_paths=package_paths(args), disabled=disabled)
