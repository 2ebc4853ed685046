"""robkin lint: is a robot file physically right, and will a simulator take it as it is? (and --fix)."""

from __future__ import annotations

import argparse
import sys

from .support.common import add_allow_xacro, add_package_path, package_paths

EPILOG = """\
Each finding is one line: FILE:LINE: SEVERITY: ELEMENT: what is wrong; fix: what to do. Severities:
error (a simulator refuses the file, or the physics is wrong), warning (a tool silently changes it, or it
looks wrong), info (style). What MuJoCo, pinocchio and drake refuse or silently change is said per tool.

URDF files get every check with its line: structure (dangling, duplicate or cyclic links and joints,
several roots, names), joints (reversed or empty limits, missing or zero effort and velocity, mimic
targets, axes), mass properties (moving links without mass, inertias not positive definite or breaking
the triangle inequality, more inertia than the geometry can hold, density over the collision volume
outside 20-25000 kg/m^3, centre of mass outside the geometry, placeholders) and meshes (missing,
unreadable, flat, open, more than --max-faces triangles, millimetres). MJCF and SDF get the same checks
on the tree their reader builds, each at its element's line (MJCF: masses as MuJoCo compiles them, from
the geoms where a body has no <inertial>; MuJoCo's own verdict; compiler settings with which MuJoCo
silently changes masses); robot documents and tables the same on the robot they hold (the line naming
the joint); USD its reader's checks. A reader's refusal is an error finding at the element it names.

--fix -o OUT writes the file with what lint can correct changed and nothing else (URDF, MJCF, SDF;
documents and tables: convert to URDF and fix that; an MJCF's or SDF's OUT belongs beside it, where its
meshes are): limits
swapped, axes normalised, dangling or cyclic <mimic> removed, invalid inertias replaced (--inertia
nearest: the nearest valid tensor; geometry: the collision geometry's at the link's mass), a moving
link without mass given its collision geometry's at --density. One line per change (on stderr with
--format json or sarif). The exit status is then the lint of OUT.

exit status: 0 no errors (warnings allowed), 1 errors found, 2 a file cannot be read.

examples:
  robkin lint panda.urdf
  robkin lint ur5.urdf panda.urdf --format json
  robkin lint ur5.urdf --format sarif
  robkin lint ur5.urdf --fix --inertia geometry -o ur5_fixed.urdf
"""


#: the inputs --fix writes a corrected copy of
FIXES = (".urdf", ".xacro", ".xml", ".mjcf", ".sdf")


def register(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    p = sub.add_parser("lint", help="find what is wrong in a robot file (physics, simulator readiness); --fix",
                       description="Check robot files for defects a simulator refuses or silently changes: structure, "
                                   "joints, mass properties, meshes. Each finding names its file:line, the link or "
                                   "joint, what is wrong and the fix.",
                       epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("input", nargs="+", metavar="FILE",
                   help="URDF (.urdf; .xacro with --allow-xacro), MJCF (.xml/.mjcf), SDF, USD, robot document or table")
    p.add_argument("--format", choices=("text", "json", "sarif"), default="text",
                   help="text (one line per finding; default), json (a list of objects) or sarif (SARIF 2.1.0, for CI)")
    p.add_argument("--fix", action="store_true", help="write a corrected copy of the (one, URDF, MJCF or SDF) input to -o")
    p.add_argument("-o", "--output", metavar="OUT", help="with --fix: the corrected file")
    p.add_argument("--inertia", choices=("nearest", "geometry"), default="nearest",
                   help="with --fix: an invalid inertia becomes the nearest valid tensor (default) or the collision "
                        "geometry's at the link's mass (geometry also replaces placeholder inertias)")
    p.add_argument("--density", type=float, default=1000.0, metavar="KG_M3",
                   help="with --fix: density giving a moving link without mass its mass (default 1000 kg/m^3)")
    p.add_argument("--max-faces", type=int, default=None, metavar="N",
                   help="warn about meshes with more triangles than N (default 200000)")
    add_package_path(p)
    add_allow_xacro(p)
    return p


def _emit(findings, fmt: str) -> None:
    from ..lint.report import as_json, as_sarif, as_text
    from ..version import __version__

    text = {"text": as_text, "json": as_json}.get(fmt)
    sys.stdout.write(text(findings) if text else as_sarif(findings, __version__))


def run(args: argparse.Namespace) -> int:
    from pathlib import Path

    from ..errors import InputError
    from ..lint import lint_file

    if args.fix and (len(args.input) != 1 or not args.output):
        raise InputError("--fix takes one input file and -o OUT (the corrected file)")
    if not args.fix and args.output:
        raise InputError("-o is the file --fix writes: give --fix too")
    if args.fix and Path(args.input[0]).suffix.lower() not in FIXES:
        raise InputError(f"{args.input[0]}: --fix supports URDF (.urdf, .xacro), MJCF (.xml, .mjcf) and SDF (.sdf) "
                         "only; for documents and tables lint names each defect and its fix, or convert to URDF "
                         "(robkin convert --to urdf) and fix that")
    if args.density <= 0:
        raise InputError(f"--density {args.density:g}: a density in kg/m^3 is positive")
    packages = package_paths(args)
    findings, unreadable = [], []
    for path in args.input:
        try:
            findings += lint_file(path, package_paths=packages, allow_xacro=args.allow_xacro, max_faces=args.max_faces)
        except InputError as exc:
            if args.fix:
                raise
            unreadable.append(str(exc))
    if args.fix:
        return _fix(args, findings, packages)
    _emit(findings, args.format)
    for line in unreadable:
        print(f"robkin lint: {line}", file=sys.stderr)
    if unreadable:
        return 2
    return 1 if any(f.severity == "error" for f in findings) else 0


def _fix(args: argparse.Namespace, findings, packages) -> int:
    from pathlib import Path

    from ..io.files.atomic import write_text_atomic
    from ..lint import lint_urdf
    from ..lint.fix_urdf import fix_urdf
    from ..lint.geometry import MeshCache
    from ..lint.urdf_source import read_urdf

    path = args.input[0]
    say = sys.stdout if args.format == "text" else sys.stderr
    _emit(findings, args.format)
    if Path(path).suffix.lower() in (".xml", ".mjcf", ".sdf"):
        from ..lint import lint_file
        from ..lint.fix_mjcf import fix_mjcf
        from ..lint.fix_sdf import fix_sdf
        from ..lint.other_formats import read_tree

        fix = fix_sdf if Path(path).suffix.lower() == ".sdf" else fix_mjcf
        text, changes = fix(path, findings, inertia=args.inertia, density=args.density, raw=read_tree(path),
                            meshes=MeshCache(path, packages))
        write_text_atomic(args.output, text)
        # MuJoCo (and an SDF's relative mesh URIs) find files beside the model: the output is checked where it is
        after = lint_file(args.output, package_paths=packages, max_faces=args.max_faces)
        if Path(args.output).resolve().parent != Path(path).resolve().parent:
            after = [f for f in after if not (f.code == "mesh-missing" or f.code.endswith("-refuses") and
                                              any(w in f.message.lower() for w in ("mesh", "resource", "include")))]
    else:
        raw = read_urdf(path, allow_xacro=args.allow_xacro)
        text, changes = fix_urdf(raw, findings, inertia=args.inertia, density=args.density,
                                 meshes=MeshCache(path, packages))
        write_text_atomic(args.output, text)
        # the output is checked with its meshes found from the input's place (its file names are the input's)
        after = lint_urdf(read_urdf(args.output), packages, args.max_faces, mesh_base=path)
    for line in changes:
        print(line, file=say)
    errors = sum(f.severity == "error" for f in after)
    print(f"robkin lint: wrote {args.output} ({len([c for c in changes if 'not fixed' not in c])} changes; "
          f"{errors} errors remain)", file=say)
    return 1 if errors else 0
