"""robkin convert: one robot (or a batch) into another representation."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..errors import InputError
from ._common import add_input, load_input
from ._output import wrote

#: --to FORMAT -> document section written for it (None: a whole document or another file type)
SECTION_OF = {"dh": "dh", "mdh": "mdh", "hayati": "hayati", "poe": "poe", "poe-body": "poe_body", "rpy-xyz": "rpy_xyz",
              "gjd": "gjd", "json": None, "yaml": None, "urdf": None, "mjcf": None}
#: Output file extensions accepted for each format (the first is used for batch output names).
EXTENSIONS = {"urdf": (".urdf",), "mjcf": (".xml", ".mjcf"), "json": (".json",), "yaml": (".yaml", ".yml")}
DOC_EXTENSIONS = (".yaml", ".yml", ".json")

EPILOG = """\
formats:
  dh        standard DH table (+ base, + residual tool)     mdh       modified (Craig) DH table
  hayati    Hayati's parameters: DH with a tilt beta about y instead of d between nearly parallel
            axes (exact and short there, the calibration standard)
  poe       Product of Exponentials, space frame            poe-body  PoE, body frame
  rpy-xyz   RPY-XYZ table, n+2 rows (URDF convention)       gjd       Global Joint Description frames
  json/yaml a robot document with every section             urdf      a URDF file
  mjcf      a MuJoCo model (MJCF), tool as site 'tool'

Without -o a readable table (or the document/URDF/MJCF text) goes to stdout; --json prints the
robot document with the chosen section as JSON instead of a table. With -o FILE a robot document
(.yaml/.yml/.json) holding the joints and the chosen section is written (or the whole document for
json/yaml, or the URDF/MJCF). Several inputs need -o DIR; every input is read and converted first,
and files are written only if all of them succeed. Output goes to a temporary file renamed into
place, so a failed run never leaves a partial or clobbered file.

Angles are in radians unless --degrees is given: then the table on stdout shows degrees, and a
written robot document holds its angles in degrees and says 'angles: degrees'. Tables note where an
offset had to go into the base or tool transform, and warn (with the FK error measured) where a DH
or modified DH table cannot be exact (nearly parallel axes: use --to hayati).

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
  robkin convert a.yaml b.yaml c.urdf --to yaml -o converted/
"""


def register(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    p = sub.add_parser("convert", help="convert a robot into another representation",
                       description="Convert a robot description into another representation, exactly: "
                                   "forward kinematics of the output equals that of the input at every q.",
                       epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_input(p, many=True)
    p.add_argument("--to", required=True, choices=list(SECTION_OF), metavar="FORMAT",
                   help="output representation: " + ", ".join(SECTION_OF))
    p.add_argument("-o", "--output", metavar="OUT", help="output file, or folder for several inputs")
    p.add_argument("--json", action="store_true",
                   help="print the robot document with the chosen section as JSON (instead of a table)")
    p.add_argument("--layout", choices=["robkin", "paper"], default="robkin",
                   help="DH table layout on stdout: 'paper' prints the base as row 0 (n+1 rows)")
    p.add_argument("--degrees", action="store_true",
                   help="angles in degrees: in the table on stdout, and in a written robot document "
                        "(which then says 'angles: degrees')")
    return p


def _render_file(robot, fmt: str, out_ext: str, degrees: bool = False) -> str:
    """Text of the output file for one robot."""
    from ..io.document import document_from_robot, dump

    if fmt == "urdf":
        from ..io.urdf import urdf_from_robot

        return urdf_from_robot(robot)
    if fmt == "mjcf":
        from ..io.mjcf import mjcf_from_robot

        return mjcf_from_robot(robot)
    section = SECTION_OF[fmt]
    doc = document_from_robot(robot, degrees=degrees) if section is None else \
        document_from_robot(robot, (section,), degrees=degrees)
    doc_fmt = "json" if (fmt == "json" or out_ext == ".json") and fmt != "yaml" else "yaml"
    return dump(doc, doc_fmt)


def _out_ext(fmt: str) -> str:
    return EXTENSIONS.get(fmt, (".yaml",))[0]


def _check_ext(out: Path, fmt: str) -> None:
    """The output file's extension must fit the format (a URDF in 'x.yaml' would mislead every reader)."""
    ok = EXTENSIONS.get(fmt, DOC_EXTENSIONS)
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


def run(args: argparse.Namespace) -> int:
    from ..io.atomic import check_writable_dir, write_text_atomic, write_texts_atomic

    inputs: list[str] = args.input
    fmt: str = args.to
    if args.json and (args.output or fmt in ("urdf", "mjcf", "yaml")):
        raise InputError(f"--json prints a table format as JSON to stdout; it does not combine with "
                         f"{'-o' if args.output else '--to ' + fmt}")
    if len(inputs) > 1:
        if not args.output:
            raise InputError("several inputs need -o DIR (a folder for the converted files)")
        out_dir = Path(args.output)
        _check_path(out_dir)
        if out_dir.exists() and not out_dir.is_dir():
            raise InputError(f"{out_dir}: not a folder; with several inputs -o names a folder")
        if not out_dir.exists() and not (out_dir.parent if str(out_dir.parent) else Path(".")).is_dir():
            raise InputError(f"{out_dir}: folder {out_dir.parent} does not exist")
        targets = [out_dir / (Path(i).stem + _out_ext(fmt)) for i in inputs]
        for t in targets:
            _check_path(t)
        dup = {str(t) for t in targets if targets.count(t) > 1}
        if dup:
            raise InputError(f"several inputs would write the same file(s): {', '.join(sorted(dup))}")
        check_writable_dir(targets[0] if out_dir.is_dir() else out_dir)  # the folder, or where it will be made
        texts = [_render_file(load_input(i, args), fmt, _out_ext(fmt), args.degrees) for i in inputs]
        out_dir.mkdir(exist_ok=True)  # only now: a failed conversion leaves no empty folder behind
        write_texts_atomic(list(zip(targets, texts)))  # all or nothing
        for target in targets:
            wrote(target)
        return 0
    robot = load_input(inputs[0], args)
    note = _mapping_note(inputs[0], robot, fmt)
    if args.output:
        out = Path(args.output)
        _check_path(out)
        if out.is_dir():
            out = out / (Path(inputs[0]).stem + _out_ext(fmt))
            _check_path(out)
        _check_ext(out, fmt)
        text = _render_file(robot, fmt, out.suffix.lower(), args.degrees)
        write_text_atomic(out, text)
        wrote(out)
        if note:
            print(f"robkin: note: {note}", file=sys.stderr)
        return 0
    if args.json:
        sys.stdout.write(_render_file(robot, fmt if SECTION_OF[fmt] else "json", ".json", args.degrees))
        return 0
    if SECTION_OF[fmt] is None:
        sys.stdout.write(_render_file(robot, fmt, ".json" if fmt == "json" else ".yaml", args.degrees))
        return 0
    from ..io.tables import blocks, show_blocks

    show_blocks(blocks(robot, fmt, layout=args.layout, degrees=args.degrees) + ([f"note: {note}"] if note else []))
    return 0
