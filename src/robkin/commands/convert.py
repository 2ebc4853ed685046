"""robkin convert: one robot (or a batch) into another representation."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..errors import InputError
from ._chains import add_chain_options, chain_ends
from ._common import add_allow_xacro, add_from
from ._output import wrote
from ._toolbox import CODE_EXTENSIONS, CODE_FORMATS, add_toolbox_options, check_toolbox_options, render_code

#: --to FORMAT -> document section written for it (None: a whole document or another file type)
SECTION_OF = {"dh": "dh", "mdh": "mdh", "hayati": "hayati", "poe": "poe", "poe-body": "poe_body", "rpy-xyz": "rpy_xyz",
              "gjd": "gjd", "json": None, "yaml": None, "urdf": None, "mjcf": None,
              **{code: None for code in CODE_FORMATS}}
#: Output file extensions accepted for each format (the first is used for batch output names).
EXTENSIONS = {"urdf": (".urdf",), "mjcf": (".xml", ".mjcf"), "json": (".json",), "yaml": (".yaml", ".yml"),
              **CODE_EXTENSIONS}
DOC_EXTENSIONS = (".yaml", ".yml", ".json")
#: --format -> output file extension (kept here, not imported, for the start-up time of every convert)
TABLE_EXTENSIONS = {"csv": ".csv", "markdown": ".md", "latex": ".tex"}
#: --to values that have a table form for --format
TABLE_REPRESENTATIONS = ("dh", "mdh", "hayati", "poe", "poe-body", "rpy-xyz", "gjd")

EPILOG = """\
formats:
  dh        standard DH table (+ base, + residual tool)     mdh       modified (Craig) DH table
  hayati    Hayati's parameters: DH with a tilt beta about y instead of d between nearly parallel
            axes (exact and short there, the calibration standard)
  poe       Product of Exponentials, space frame            poe-body  PoE, body frame
  rpy-xyz   RPY-XYZ table, n+2 rows (URDF convention)       gjd       Global Joint Description frames
  json/yaml a robot document with every section             urdf      a URDF file (a URDF input's whole file)
  mjcf      a MuJoCo model (MJCF), tool as site 'tool'
code for other toolboxes (need no robkin; names and numbers from the input are data in them, never code):
  rtb       a Python file defining `robot`, a Robotics Toolbox DHRobot (--convention mdh: modified DH)
            with base, tool, offsets, limits and each link's mass, centre of mass and inertia in its
            DH frame: robot.fkine, robot.rne and robot.gravload equal robkin's
  matlab    a MATLAB/Octave script (.m) defining the struct `robot` (DH or --convention mdh table,
            base, tool, limits, mass properties) and `robot_fk`: T = robot_fk(q)
  eaik      the joint axes H and offsets P that EAIK's IK takes: JSON, or a Python file (-o x.py)
  opw       the seven OPW parameters (a1 a2 b c1 c2 c3 c4) with joint offsets and sign corrections
            of an industrial 6R arm (ortho-parallel base, spherical wrist), as moveit_opw_kinematics
            reads them (YAML, or JSON); other arms are refused with the condition they fail

Without -o a readable table (or the document/URDF/MJCF text) goes to stdout; --json prints the
robot document with the chosen section as JSON instead of a table. With -o FILE a robot document
(.yaml/.yml/.json) holding the joints and the chosen section is written (or the whole document for
json/yaml, or the URDF/MJCF). Several inputs need -o DIR; every input is read and converted first,
and files are written only if all of them succeed. Output goes to a temporary file renamed into
place, so a failed run never leaves a partial or clobbered file.

Angles are in radians unless --degrees is given: then the table on stdout shows degrees, and a
written robot document holds its angles in degrees and says 'angles: degrees'. Tables note where an
offset had to go into the base or tool transform, and warn (with the FK error measured) where a DH
or modified DH table cannot be exact (nearly parallel axes: use --to hayati). The table on stdout shows
values closer to 0 than 1e-9 (lengths: times the robot's size) as 0 and says so in a note; -o, --format
and --json keep every digit.

Tables as input: a CSV table written with --format csv reads back as INPUT (its header says which
table it is, except a PoE's frame: --from poe or poe-body), and so do bare rows as pasted from a paper
('a d alpha theta [R|P]' per line, .txt/.csv/.tsv) with --from dh or mdh (poe: screw rows then 'M ...';
rpy-xyz: n + 2 rows).

Tables for papers and spreadsheets: --format csv|markdown|latex with a table --to (dh, mdh, hayati, poe,
poe-body, rpy-xyz, gjd) writes the table as CSV (reads back: the fixed transforms follow the rows
after an empty line), Markdown or LaTeX (a table environment; matrices use amsmath); -o names a .csv,
.md or .tex file.

Numbers in files: tables and YAML documents write each value as the shortest decimal that keeps the
table's FK within 1e-12 of the robot's size (0.3839999999999999 is written 0.384, -4.16e-18 is 0);
--digits N writes N significant digits, and --exact every digit, so that the file reads back to the
very same floats (JSON documents always keep every digit). --pi writes angles that are exactly k*pi/m as
such (-pi/2, 3*pi/4).

Chains: --base-link / --tip-link given once apply to every robot file among the inputs; given once
per input, in input order, the k-th belongs to the k-th input ('-' = that file's default, and what a
robot document takes). A base or tip may be any link rigidly attached to the chain's end (UR's
'base', 'tool0'). A folder given with -o (several inputs, or a name ending in '/') that does not exist
is created in an existing one, once every input has been converted.

Joint variables are the same in every output: q_i means the same configuration in the DH table, the
PoE and the URDF it came from (same sign, same zero); a note on stderr says so for URDF input.

examples:
  robkin convert rrpr.yaml --to poe
  robkin convert rrpr.yaml --to dh --layout paper
  robkin convert ur5.urdf --tip-link tool0 --to dh -o ur5_dh.yaml
  robkin convert panda.urdf --tip-link panda_hand_tcp --to mdh --json
  robkin convert ur5.urdf --tip-link tool0 --to dh --degrees
  robkin convert ur5.urdf --tip-link tool0 --to hayati -o ur5_hayati.yaml
  robkin convert robot.yaml --to urdf -o robot.urdf
  robkin convert robot.yaml --to mjcf -o robot.xml
  robkin convert panda.urdf --tip-link panda_hand_tcp --to rtb -o panda_rtb.py
  robkin convert ur5.urdf --tip-link tool0 --to rtb --convention mdh -o ur5_mdh.py
  robkin convert ur5.urdf --tip-link tool0 --to matlab -o ur5.m
  robkin convert ur5.urdf --tip-link tool0 --to eaik -o ur5_eaik.py
  robkin convert kr6_r700.yaml --to opw -o kr6_opw.yaml
  robkin convert a.yaml b.yaml c.urdf --to yaml -o converted/
  robkin convert ur5.urdf --base-link base --tip-link tool0 --to dh --format latex --pi
  robkin convert ur5.urdf --base-link base --tip-link tool0 --to dh --format csv -o ur5_dh.csv
  robkin convert ur5_dh.csv --to mdh
  robkin convert ur5_rows.txt --from dh --to urdf -o ur5_from_rows.urdf
  robkin convert ur5.urdf panda.urdf a.yaml --tip-link tool0 --tip-link panda_hand_tcp --tip-link - --to mdh -o out/
"""


def register(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    p = sub.add_parser("convert", help="convert a robot into another representation",
                       description="Convert a robot description into another representation, exactly: "
                                   "forward kinematics of the output equals that of the input at every q.",
                       epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("input", nargs="+", metavar="INPUT",
                   help="robot document (.yaml/.yml/.json) or robot file: URDF (.urdf; .xacro with --allow-xacro), "
                        "MJCF (.xml/.mjcf) or SDF (.sdf) (one or more)")
    add_chain_options(p)
    add_allow_xacro(p)
    add_from(p)
    p.add_argument("--to", required=True, choices=list(SECTION_OF), metavar="FORMAT",
                   help="output representation: " + ", ".join(SECTION_OF))
    p.add_argument("--format", choices=["csv", "markdown", "latex"],
                   help="write a table representation (--to dh, mdh, hayati, poe, poe-body, rpy-xyz, gjd) as CSV, "
                        "Markdown or LaTeX, full precision")
    p.add_argument("--pi", action="store_true",
                   help="with --format: angles that are exactly k*pi/m written as such (-pi/2, 3*pi/4)")
    precision = p.add_mutually_exclusive_group()
    precision.add_argument("--digits", type=_digits, metavar="N",
                           help="tables (--format) and YAML documents: N significant digits (default: the "
                                "shortest decimal that keeps FK within 1e-12 of the robot's size)")
    precision.add_argument("--exact", action="store_true",
                           help="tables (--format) and YAML documents: every digit, reading back to the very "
                                "same floats (JSON documents always do)")
    p.add_argument("-o", "--output", metavar="OUT", help="output file, or folder for several inputs")
    p.add_argument("--json", action="store_true",
                   help="print the robot document with the chosen section as JSON (instead of a table)")
    p.add_argument("--layout", choices=["robkin", "paper"], default="robkin",
                   help="DH table layout on stdout: 'paper' prints the base as row 0 (n+1 rows)")
    p.add_argument("--degrees", action="store_true",
                   help="angles in degrees: in the table on stdout, and in a written robot document "
                        "(which then says 'angles: degrees')")
    add_toolbox_options(p)
    p.add_argument("--link-geometry", choices=["none", "capsules"], default="none",
                   help="--to urdf|mjcf: give the links shapes a simulator shows: 'capsules' draws a capsule "
                        "from each joint frame origin to the next and a cylinder along each joint axis "
                        "(visual and collision; URDF writes a capsule as a cylinder and two spheres), as the "
                        "Robotics Toolbox draws a DH robot; added to the shapes the input has (default: none)")
    p.add_argument("--link-radius", metavar="R",
                   help="with --link-geometry capsules: the capsule radius in the robot's length unit "
                        "(default: 3%% of the robot's size)")
    return p


def _digits(text: str) -> int:
    """argparse type of --digits: 1 .. 17 significant digits (17 always reproduces a float)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text[:40]}' is not a whole number") from None
    if not 1 <= value <= 17:
        raise argparse.ArgumentTypeError(f"{value} is not 1 .. 17")
    return value


def _check_link_geometry(args: argparse.Namespace) -> float | None:
    """The capsule radius (None: the default), after checking the --link-* options fit --to."""
    from ..io.numbers import number

    style, radius = getattr(args, "link_geometry", "none"), getattr(args, "link_radius", None)
    if style != "none" and args.to not in ("urdf", "mjcf"):
        raise InputError(f"--link-geometry {style}: shapes are written by --to urdf or --to mjcf only, "
                         f"not --to {args.to}")
    if radius is None:
        return None
    if style == "none":
        raise InputError("--link-radius: applies with --link-geometry capsules")
    r = number(radius, "--link-radius")
    if not r > 0:
        raise InputError(f"--link-radius: must be a positive length, got {radius}")
    return r


def _with_link_geometry(robot, args: argparse.Namespace | None):
    """The robot with stand-in link shapes when --link-geometry asks for them (robkin.link_geometry)."""
    if args is None or getattr(args, "link_geometry", "none") == "none":
        return robot
    from ..link_geometry import with_link_capsules

    return with_link_capsules(robot, _check_link_geometry(args))


def _render_file(robot, fmt: str, out_ext: str, args: argparse.Namespace | None = None) -> str:
    """Text of the output file for one robot."""
    from ..io.document import document_from_robot, dump

    degrees = bool(args is not None and args.degrees)

    if args is not None and args.format:
        from ..io.table_files import render_table

        return render_table(robot, fmt, args.format, pi=args.pi, digits="exact" if args.exact else args.digits)
    if fmt in CODE_FORMATS:
        return render_code(robot, fmt, out_ext, args)
    if fmt == "urdf":
        from ..io.urdf import urdf_from_robot

        return urdf_from_robot(_with_link_geometry(robot, args))
    if fmt == "mjcf":
        from ..io.mjcf import mjcf_from_robot

        return mjcf_from_robot(_with_link_geometry(robot, args))
    section = SECTION_OF[fmt]
    doc = document_from_robot(robot, degrees=degrees) if section is None else \
        document_from_robot(robot, (section,), degrees=degrees)
    doc_fmt = "json" if (fmt == "json" or out_ext == ".json") and fmt != "yaml" else "yaml"
    if doc_fmt == "yaml" and not (args is not None and args.exact):
        from ..io.document_round import round_document

        doc = round_document(doc, robot.scale, None if args is None else args.digits)
    return dump(doc, doc_fmt)


def _render_in(path: str, robot, fmt: str, out_ext: str, args: argparse.Namespace) -> str:
    """``_render_file`` for one input of a batch: an error names the input it is about."""
    try:
        return _render_file(robot, fmt, out_ext, args)
    except InputError as exc:
        raise exc.in_source(path) from None


def _out_ext(fmt: str, table_format: str | None = None) -> str:
    if table_format:
        return TABLE_EXTENSIONS[table_format]
    return EXTENSIONS.get(fmt, (".yaml",))[0]


def _check_ext(out: Path, fmt: str, table_format: str | None = None) -> None:
    """The output file's extension must fit the format (a URDF in 'x.yaml' would mislead every reader)."""
    ok = (TABLE_EXTENSIONS[table_format],) if table_format else EXTENSIONS.get(fmt, DOC_EXTENSIONS)
    if out.suffix.lower() not in ok:
        raise InputError(f"{out}: --to {fmt} writes a {' or '.join(ok)} file; name the output accordingly")


def _check_path(path: Path) -> None:
    """InputError for an output path the system refuses outright (e.g. a name too long): pathlib's
    is_dir() and the writer would otherwise raise a bare OSError."""
    for p in (path, path.parent):
        try:
            p.stat()
        except FileNotFoundError:
            pass
        except OSError as exc:
            raise InputError(f"{path}: cannot write ({exc.strerror or exc})") from None


def _mapping_note(path: str, robot, fmt: str) -> str | None:
    """For robot-file input: the joint variables of the output are the file's joint positions."""
    from ..io import MJCF_EXTENSIONS, ROBOT_FILE_EXTENSIONS, SDF_EXTENSIONS

    ext = Path(path).suffix.lower()
    if ext not in ROBOT_FILE_EXTENSIONS or fmt in ("urdf", "mjcf", "json", "yaml"):
        return None
    names = ", ".join(j.name for j in robot.joints[:3]) + (", ..." if robot.n > 3 else "")
    what = "MuJoCo qpos" if ext in MJCF_EXTENSIONS else "SDF position" if ext in SDF_EXTENSIONS else "URDF position"
    note = (f"joint variables: q_i in this {fmt} output is the {what} of joint i ({names}), "
            f"with the same sign and the same zero")
    flipped = [j.name for j in robot.joints if j.flip]
    if flipped and fmt in ("dh", "mdh", "hayati", "rpy-xyz"):
        note += (f"; joint(s) {', '.join(flipped)} point against their frame's z (flip: true), so the table "
                 f"subtracts q there")
    return note


def _load_all(inputs: list[str], args: argparse.Namespace) -> list:
    from ..io import load

    from ..io import TABLE_EXTENSIONS

    # --from applies to the table files among the inputs (the others say what they hold)
    return [load(i, base_link=base, tip_link=tip, allow_xacro=args.allow_xacro,
                 representation=args.representation if i.lower().endswith(TABLE_EXTENSIONS) else None)
            for i, (base, tip) in zip(inputs, chain_ends(args, inputs))]


def _check_table_options(args: argparse.Namespace) -> None:
    if args.format and args.to not in TABLE_REPRESENTATIONS:
        raise InputError(f"--format {args.format}: --to {args.to} is not a table; --format works with --to "
                         f"{', '.join(t for t in TABLE_REPRESENTATIONS if t in SECTION_OF)}")
    if args.pi and not args.format:
        raise InputError("--pi: applies to --format csv|markdown|latex tables")
    if args.format and args.json:
        raise InputError(f"--json prints a robot document; it does not combine with --format {args.format}")


def run(args: argparse.Namespace) -> int:
    from ..io.atomic import check_writable_dir, write_text_atomic, write_texts_atomic

    inputs: list[str] = args.input
    fmt: str = args.to
    _check_table_options(args)
    check_toolbox_options(args)
    _check_link_geometry(args)
    if args.json and (args.output or fmt in ("urdf", "mjcf", "yaml")):
        raise InputError(f"--json prints a table format as JSON to stdout; it does not combine with "
                         f"{'-o' if args.output else '--to ' + fmt}")
    ext = _out_ext(fmt, args.format)
    folder = args.output and (len(inputs) > 1 or args.output.endswith(("/", "\\")))
    if folder:
        out_dir = Path(args.output)
        _check_path(out_dir)
        if out_dir.exists() and not out_dir.is_dir():
            raise InputError(f"{out_dir}: not a folder; with several inputs -o names a folder")
        if not out_dir.exists() and not (out_dir.parent if str(out_dir.parent) else Path(".")).is_dir():
            raise InputError(f"{out_dir}: folder {out_dir.parent} does not exist")
        targets = [out_dir / (Path(i).stem + ext) for i in inputs]
        for t in targets:
            _check_path(t)
        seen: set[Path] = set()
        dup = {str(t) for t in targets if t in seen or seen.add(t)}  # linear: a batch may hold 10^4 inputs
        if dup:
            raise InputError(f"several inputs would write the same file(s): {', '.join(sorted(dup))}")
        check_writable_dir(targets[0] if out_dir.is_dir() else out_dir)  # the folder, or where it will be made
        texts = [_render_in(path, robot, fmt, ext, args) for path, robot in zip(inputs, _load_all(inputs, args))]
        out_dir.mkdir(exist_ok=True)  # only now: a failed conversion leaves no empty folder behind
        write_texts_atomic(list(zip(targets, texts)))  # all or nothing
        for target in targets:
            wrote(target)
        return 0
    if len(inputs) > 1:
        raise InputError("several inputs need -o DIR (a folder for the converted files)")
    robot = _load_all(inputs, args)[0]
    note = _mapping_note(inputs[0], robot, fmt)
    if args.output:
        out = Path(args.output)
        _check_path(out)
        if out.is_dir():
            out = out / (Path(inputs[0]).stem + ext)
            _check_path(out)
        _check_ext(out, fmt, args.format)
        text = _render_file(robot, fmt, out.suffix.lower(), args)
        write_text_atomic(out, text)
        wrote(out)
        if note:
            print(f"robkin: note: {note}", file=sys.stderr)
        return 0
    if args.format:
        sys.stdout.write(_render_file(robot, fmt, ext, args))
        return 0
    if args.json:
        sys.stdout.write(_render_file(robot, fmt if SECTION_OF[fmt] or fmt in CODE_FORMATS else "json", ".json",
                                      args))
        return 0
    if SECTION_OF[fmt] is None:
        sys.stdout.write(_render_file(robot, fmt, ".json" if fmt == "json" else EXTENSIONS.get(fmt, (".yaml",))[0],
                                      args))
        return 0
    from ..io.tables import blocks, show_blocks

    show_blocks(blocks(robot, fmt, layout=args.layout, degrees=args.degrees) + ([f"note: {note}"] if note else []))
    return 0
