"""robkin convert: one robot (or a batch) into another representation."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..errors import InputError
from ._common import add_input, load_input

#: --to FORMAT -> document section written for it (None: a whole document or another file type)
SECTION_OF = {"dh": "dh", "mdh": "mdh", "poe": "poe", "poe-body": "poe_body", "rpy-xyz": "rpy_xyz",
              "gjd": "gjd", "json": None, "yaml": None, "urdf": None}

EPILOG = """\
formats:
  dh        standard DH table (+ base, + residual tool)     mdh       modified (Craig) DH table
  poe       Product of Exponentials, space frame            poe-body  PoE, body frame
  rpy-xyz   RPY-XYZ table, n+2 rows (URDF convention)       gjd       Global Joint Description frames
  json/yaml a robot document with every section             urdf      a URDF file

Without -o a readable table (or the document/URDF text) goes to stdout. With -o FILE a robot document
(.yaml/.yml/.json) holding the joints and the chosen section is written (or the whole document for
json/yaml, or the URDF). Several inputs need -o DIR; every input is read and converted first, and
files are written only if all of them succeed.

examples:
  robkin convert rrpr.yaml --to poe
  robkin convert rrpr.yaml --to dh --layout paper
  robkin convert ur5.urdf --to dh -o ur5_dh.yaml
  robkin convert robot.yaml --to json -o robot.json
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
    p.add_argument("--layout", choices=["robkin", "paper"], default="robkin",
                   help="DH table layout on stdout: 'paper' prints the base as row 0 (n+1 rows)")
    return p


def _render_file(robot, fmt: str, out_ext: str) -> str:
    """Text of the output file for one robot."""
    from ..io.document import document_from_robot, dump

    if fmt == "urdf":
        from ..io.urdf import urdf_from_robot

        return urdf_from_robot(robot)
    section = SECTION_OF[fmt]
    doc = document_from_robot(robot) if section is None else document_from_robot(robot, (section,))
    doc_fmt = "json" if (fmt == "json" or out_ext == ".json") and fmt != "yaml" else "yaml"
    return dump(doc, doc_fmt)


def _out_ext(fmt: str) -> str:
    return {"urdf": ".urdf", "json": ".json"}.get(fmt, ".yaml")


def run(args: argparse.Namespace) -> int:
    from ..io.atomic import check_writable_dir, write_text_atomic

    inputs: list[str] = args.input
    fmt: str = args.to
    if len(inputs) > 1:
        if not args.output:
            raise InputError("several inputs need -o DIR (a folder for the converted files)")
        out_dir = Path(args.output)
        if not out_dir.is_dir():
            raise InputError(f"{out_dir}: not a folder; with several inputs -o names an existing folder")
        targets = [out_dir / (Path(i).stem + _out_ext(fmt)) for i in inputs]
        dup = {str(t) for t in targets if targets.count(t) > 1}
        if dup:
            raise InputError(f"several inputs would write the same file(s): {', '.join(sorted(dup))}")
        texts = [_render_file(load_input(i, args), fmt, _out_ext(fmt)) for i in inputs]
        check_writable_dir(targets[0])
        for target, text in zip(targets, texts):
            write_text_atomic(target, text)
        print(f"wrote {len(targets)} files to {out_dir}", file=sys.stderr)
        return 0
    robot = load_input(inputs[0], args)
    if args.output:
        out = Path(args.output)
        if out.is_dir():
            out = out / (Path(inputs[0]).stem + _out_ext(fmt))
        text = _render_file(robot, fmt, out.suffix.lower())
        write_text_atomic(out, text)
        print(f"wrote {out}", file=sys.stderr)
        return 0
    if SECTION_OF[fmt] is None:
        sys.stdout.write(_render_file(robot, fmt, ".json" if fmt == "json" else ".yaml"))
        return 0
    from ..io.tables import render

    print(render(robot, fmt, layout=args.layout))
    return 0
