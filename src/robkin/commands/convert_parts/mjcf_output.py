"""``robkin convert --to mjcf``: its options, and the model text with the meshes copied beside it."""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import TYPE_CHECKING

from ...errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    from ...robot import Robot
    from ...simulation.servos import ServoPlan

__all__ = ["add_mjcf_options", "check_mjcf_options", "render_mjcf", "servos_of", "scene_of", "MJCF_HELP"]

#: = io.mjcf.actuators.ACTUATOR_KINDS (not imported: the module loads with every command)
_KINDS = ("position", "velocity", "motor", "none")

MJCF_HELP = """\
MJCF output (--to mjcf): a model MuJoCo simulates: open it (or the --scene) in MuJoCo's viewer and
press play, it holds its pose and moves to the controls. Bodies are named as the source's links (a
robot from a table: base, link1..linkN, tool), joints as its joints with their ranges, damping,
friction (frictionloss) and armature; visual shapes are geoms of class 'visual' (group 2, no contact),
collision shapes of class 'collision' (group 3); inertials are the source's, exactly (no mass is
invented from the shapes); mimic joints follow their joint through an <equality>. MuJoCo's qpos[:n]
is q (the chain's joints come first) and the site named as the tip link (or 'tool') is the tool
frame. With -o, the meshes are copied into a 'meshes' folder beside the output, so the folder loads
from anywhere. Fixed links stay bodies (a massless, shapeless end frame is a site); --fuse-fixed
merges them into the body they hang from (mass merged exactly, the name kept as a site).
Simulation: integrator implicitfast, time step 2 ms; a keyframe 'home' with every joint inside its
limits (q = 0 clipped into them, or --home q1,q2,...) and ctrl holding it. Actuators: --actuators
position (default: a servo per joint, kp and kv from the joint's reflected inertia at home, critically
damped at 5 Hz, stiff enough that the source's friction stalls it within 1 mrad; range = the joint
range, force +-effort), velocity (servo, range +-velocity), motor (ctrl = torque, range +-effort) or
none; --kp/--kv replace the gains on every joint. Gravity is compensated (MuJoCo's gravcomp, through
the actuators, within the effort) for position and velocity servos; --no-gravcomp turns it off,
--gravcomp on for motors. --scene also writes scene.xml beside the model: a floor, a light and the
robot. robkin reads the written file back and checks its masses, centres, inertias, M(q) and g(q),
and, with MuJoCo installed, that it loads without warnings, home is inside the limits, and home holds
for 5 s (one line with the numbers).
"""


def add_mjcf_options(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("MJCF output (--to mjcf)")
    g.add_argument("--actuators", choices=_KINDS, default=None,
                   help="an actuator on every joint (not the mimic ones): position servos (the default), "
                        "velocity servos, motor (torque) or none")
    g.add_argument("--kp", type=str, default=None, metavar="GAIN",
                   help="position servo stiffness on every joint, N m/rad or N/m (default: per joint, from "
                        "its reflected inertia and friction)")
    g.add_argument("--kv", type=str, default=None, metavar="GAIN",
                   help="servo damping (position) or gain (velocity) on every joint, N m s/rad or N s/m "
                        "(default: per joint, critically damped)")
    g.add_argument("--home", default=None, metavar="Q1,Q2,...",
                   help="the keyframe 'home' (one value per chain joint, inside its limits; default q = 0 "
                        "clipped into the limits)")
    g.add_argument("--gravcomp", action=argparse.BooleanOptionalAction, default=None,
                   help="gravity compensation (default: on for position and velocity servos, off for motor "
                        "and none)")
    g.add_argument("--scene", action="store_true",
                   help="also write scene.xml beside the model: a floor, a light and the robot, ready to "
                        "simulate")
    g.add_argument("--fuse-fixed", action="store_true",
                   help="merge links fixed to their parent into it (mass merged exactly; names kept as sites)")


def _gain(opt: str, text: str | None) -> float | None:
    """A gain option's value: a finite number >= 0 (the documents' bound), else InputError."""
    if text is None:
        return None
    from ...compiled.scanners.vocabulary import MAX_ABS  # the documents' bound (pure Python, no extension)
    from ...io.files.numbers import number

    try:
        v = number(text, opt)
    except InputError:
        v = math.nan
    if not (0 <= v <= MAX_ABS):  # also NaN
        raise InputError(f"{opt} {text}: a gain is a number >= 0 and at most {MAX_ABS:g}")
    return v


def check_mjcf_options(args: argparse.Namespace) -> None:
    """InputError for MJCF options given with another --to, or gains that are no gains; the gains are
    then numbers (``args.kp``, ``args.kv``) and ``args.actuators`` a kind."""
    given = [opt for opt, v in (("--kp", args.kp), ("--kv", args.kv), ("--fuse-fixed", args.fuse_fixed),
                                ("--actuators", args.actuators), ("--home", args.home),
                                ("--gravcomp" if args.gravcomp else "--no-gravcomp",
                                 args.gravcomp is not None), ("--scene", args.scene)) if v]
    if args.to != "mjcf" and given:
        raise InputError(f"{given[0]}: applies to --to mjcf only")
    args.kp, args.kv = _gain("--kp", args.kp), _gain("--kv", args.kv)
    kind = args.actuators = args.actuators or "position"
    if args.kp is not None and kind != "position":
        raise InputError(f"--kp: applies to --actuators position (not {kind})")
    if args.kv is not None and kind not in ("position", "velocity"):
        raise InputError(f"--kv: applies to --actuators position or velocity (not {kind})")
    if args.scene and not args.output:
        raise InputError("--scene: writes scene.xml beside the model, so it needs -o FOLDER/robot.xml")
    if args.scene and (len(args.input) > 1 or str(args.output).endswith(("/", "\\"))):
        raise InputError("--scene: one model per folder (scene.xml includes it): convert one input with "
                         "-o FOLDER/robot.xml")


def servos_of(robot: Robot, args: argparse.Namespace) -> ServoPlan:
    """The servo plan of the command's options (``--home`` checked against the robot's limits)."""
    from ...simulation.servos import servo_plan
    from ..support.common import parse_q

    home = None
    if args.home is not None:
        home = parse_q(args.home, robot.n, "--home")
        try:
            robot.home(home)
        except InputError as exc:
            raise InputError(f"--home: {str(exc).removeprefix('home: ')}") from None
    return servo_plan(robot, kind=args.actuators, home=home, kp=args.kp, kv=args.kv, gravcomp=args.gravcomp)


def render_mjcf(robot: Robot, args: argparse.Namespace, source: str | None, out_dir: Path | None,
                mesh_dir: str = "meshes") -> str:
    """The MJCF text of ``robot`` read from ``source`` with the command's options; with ``out_dir``, its
    meshes copied into ``out_dir/mesh_dir`` first (see ``robkin.io.mjcf.files``)."""
    from ...io.mjcf.files import mjcf_with_meshes
    from ..support.common import package_paths
    from .collision_output import collision_stage

    servos = servos_of(robot, args)  # before the meshes are copied: a bad --home writes nothing
    with collision_stage(robot, args, source, out_dir, mesh_dir) as stage:  # --collision (collision_output)
        return mjcf_with_meshes(stage.robot, source, out_dir, mesh_dir=mesh_dir, package_paths=package_paths(args),
                                servos=servos, fuse_fixed=args.fuse_fixed, premade=stage.premade,
                                contact_excludes=stage.contact_excludes)


def scene_of(robot: Robot, out: Path, text: str | None = None) -> tuple[Path, str]:
    """(``scene.xml`` beside ``out``, its text: ``robkin.io.mjcf.scene``); ``text``: the model's MJCF,
    whose geoms at home the floor goes under (``robkin.simulation.ground``, when MuJoCo is installed)."""
    from ...io.mjcf.scene import scene_text
    from ...simulation.ground import lowest_point

    scene = out.with_name("scene.xml")
    if scene == out:
        raise InputError(f"--scene: {out} is itself named scene.xml; name the model otherwise")
    lowest = None if text is None else lowest_point(text, out.parent)
    return scene, scene_text(robot, out.name, lowest)
