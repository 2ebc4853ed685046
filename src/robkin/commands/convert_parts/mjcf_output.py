"""``robkin convert --to mjcf``: its options, and the model text with the meshes copied beside it."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

from ...errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    from ...robot import Robot

__all__ = ["add_mjcf_options", "check_mjcf_options", "render_mjcf", "MJCF_HELP"]

#: = io.mjcf.actuators.ACTUATOR_KINDS (not imported: the module loads with every command)
_KINDS = ("motor", "position", "velocity", "none")

MJCF_HELP = """\
MJCF output (--to mjcf): a model MuJoCo simulates. Bodies are named as the source's links (a robot
from a table: base, link1..linkN, tool), joints as its joints with their ranges, damping, friction
(frictionloss) and armature; visual shapes are geoms of class 'visual' (group 2, no contact),
collision shapes of class 'collision' (group 3); inertials are the source's, exactly (no mass is
invented from the shapes); mimic joints follow their joint through an <equality>; a keyframe 'home'
holds q = 0. MuJoCo's qpos[:n] is q (the chain's joints come first) and the site named as the tip
link (or 'tool') is the tool frame. With -o, the meshes are copied into a 'meshes' folder beside the
output, so the folder loads from anywhere. Fixed links stay bodies (a massless, shapeless end frame
is a site); --fuse-fixed merges them into the body they hang from (mass merged exactly, the name kept
as a site). Actuators: --actuators motor (default; ctrl = torque, range +-effort), position (servo,
--kp, --kv; range = the joint range, force +-effort), velocity (servo, --kv; range +-velocity) or
none. robkin reads the written file back and checks its masses, centres, inertias, M(q) and g(q).
"""


def add_mjcf_options(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("MJCF output (--to mjcf)")
    g.add_argument("--actuators", choices=_KINDS, default="motor",
                   help="an actuator on every joint (not the mimic ones): motor (torque, the default), "
                        "position or velocity servos, or none")
    g.add_argument("--kp", type=float, default=None, metavar="GAIN",
                   help="position servo stiffness, N m/rad or N/m (default 100)")
    g.add_argument("--kv", type=float, default=None, metavar="GAIN",
                   help="servo damping (position) or gain (velocity), N m s/rad or N s/m (default 10)")
    g.add_argument("--fuse-fixed", action="store_true",
                   help="merge links fixed to their parent into it (mass merged exactly; names kept as sites)")


def check_mjcf_options(args: argparse.Namespace) -> None:
    """InputError for MJCF options given with another --to, or gains that are no gains."""
    given = [opt for opt, v in (("--kp", args.kp), ("--kv", args.kv), ("--fuse-fixed", args.fuse_fixed),
                                ("--actuators", None if args.actuators == "motor" else args.actuators)) if v]
    if args.to != "mjcf" and given:
        raise InputError(f"{given[0]}: applies to --to mjcf only")
    from ...compiled.scanners.vocabulary import MAX_ABS  # the documents' bound (pure Python, no extension)

    for opt, v in (("--kp", args.kp), ("--kv", args.kv)):
        if v is not None and not (0 <= v <= MAX_ABS):  # also NaN
            raise InputError(f"{opt} {v}: a gain is a number >= 0 and at most {MAX_ABS:g}")
    if args.kp is not None and args.actuators != "position":
        raise InputError(f"--kp: applies to --actuators position (not {args.actuators})")
    if args.kv is not None and args.actuators not in ("position", "velocity"):
        raise InputError(f"--kv: applies to --actuators position or velocity (not {args.actuators})")


def render_mjcf(robot: Robot, args: argparse.Namespace, source: str | None, out_dir: Path | None,
                mesh_dir: str = "meshes") -> str:
    """The MJCF text of ``robot`` read from ``source`` with the command's options; with ``out_dir``, its
    meshes copied into ``out_dir/mesh_dir`` first (see ``robkin.io.mjcf.files``)."""
    from ...io.mjcf.actuators import DEFAULT_KP, DEFAULT_KV
    from ...io.mjcf.files import mjcf_with_meshes
    from .._common import package_paths
    from .collision_output import collision_stage

    with collision_stage(robot, args, source, out_dir, mesh_dir) as stage:  # --collision (collision_output)
        return mjcf_with_meshes(stage.robot, source, out_dir, mesh_dir=mesh_dir, package_paths=package_paths(args),
                                actuators=args.actuators, kp=DEFAULT_KP if args.kp is None else args.kp,
                                kv=DEFAULT_KV if args.kv is None else args.kv, fuse_fixed=args.fuse_fixed,
                                premade=stage.premade, contact_excludes=stage.contact_excludes)
