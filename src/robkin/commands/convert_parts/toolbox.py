"""The code formats of ``robkin convert`` (--to rtb, matlab, eaik, opw): their options and their text."""

from __future__ import annotations

import argparse

from ...errors import InputError

__all__ = ["CODE_FORMATS", "CODE_EXTENSIONS", "add_toolbox_options", "check_toolbox_options", "render_code"]

#: --to FORMAT -> output file extensions (the first is the default: batch names, stdout)
CODE_EXTENSIONS = {"rtb": (".py",), "matlab": (".m",), "eaik": (".json", ".py"), "opw": (".yaml", ".yml", ".json")}
CODE_FORMATS = tuple(CODE_EXTENSIONS)
#: formats that --json prints as JSON
_JSON_FORMS = ("eaik", "opw")


def add_toolbox_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--convention", choices=["dh", "mdh"], default=None,
                   help="--to rtb / matlab: write the standard DH table (dh, the default: RevoluteDH links) or the "
                        "modified (Craig) DH table (mdh: RevoluteMDH links)")


def check_toolbox_options(args: argparse.Namespace) -> None:
    """InputError for options that do not fit the chosen code format (before anything is read)."""
    if args.convention and args.to not in ("rtb", "matlab"):
        raise InputError(f"--convention {args.convention}: applies to --to rtb and --to matlab, not --to {args.to}")
    if args.to in CODE_FORMATS and args.json and (args.to not in _JSON_FORMS or args.output):
        raise InputError(f"--json: --to {args.to} " + ("writes Python or MATLAB code; it has no JSON form"
                                                        if args.to not in _JSON_FORMS else
                                                        "with -o: name a .json file instead"))
    if args.to in CODE_FORMATS and args.layout != "robkin":
        raise InputError(f"--layout {args.layout}: applies to the tables on stdout, not to --to {args.to}")
    if args.to in CODE_FORMATS and args.degrees:
        raise InputError(f"--degrees: --to {args.to} writes angles in radians, as the toolboxes take them")


def render_code(robot, fmt: str, out_ext: str, args: argparse.Namespace | None = None) -> str:
    """Text of the code file of one robot; ``out_ext`` picks JSON or Python (eaik) and YAML or JSON (opw)."""
    convention = (args.convention if args is not None else None) or "dh"
    if fmt == "rtb":
        from ...io.toolboxes.rtb import rtb_from_robot

        return rtb_from_robot(robot, convention)
    if fmt == "matlab":
        from ...io.toolboxes.matlab import matlab_from_robot

        return matlab_from_robot(robot, convention)
    if fmt == "eaik":
        from ...io.toolboxes.eaik import eaik_json, eaik_python

        return eaik_python(robot) if out_ext == ".py" else eaik_json(robot)
    if fmt == "opw":
        from ...io.documents.reader import dump
        from ...io.toolboxes.opw import opw_document

        doc = opw_document(robot)
        if not (args is not None and getattr(args, "exact", False)):
            _shorten_opw(doc, robot)
        return dump(doc, "json" if out_ext == ".json" else "yaml")
    raise ValueError(f"not a code format: {fmt}")  # pragma: no cover  (argparse's choices)


def _shorten_opw(doc: dict, robot) -> None:
    """The seven OPW lengths as their shortest decimals within the FK budget the tables use (0.365, not
    0.36500000000000005: rounding noise of the DH arithmetic), in place; --exact keeps every digit. The
    offsets, sign corrections, base and tool are written as computed (multiples of pi/2 stay exact)."""
    import math

    from ...io.files.float_text import decimal_tolerances, short_text
    from ...representations.rounding import SNAP_BUDGET

    geometry = doc["opw_kinematics_geometric_parameters"]
    tol, _ = decimal_tolerances(robot.scale, robot.scale + math.fsum(abs(v) for v in geometry.values()),
                                len(geometry), SNAP_BUDGET)
    for key, value in geometry.items():
        geometry[key] = float(short_text(value, tol))
