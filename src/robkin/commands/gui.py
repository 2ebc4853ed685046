"""``robkin gui``: open a robot in a local browser app (3D view, joint sliders, all representations)."""

from __future__ import annotations

import argparse
import sys

from ..errors import InputError
from .support.common import add_package_path, package_paths

HELP = "browser app: see a robot in 3D, drag its tool by IK, convert it, compare two descriptions"
EPILOG = """\
examples:
  robkin gui                          # starts with the bundled RRPR example
  robkin gui rrpr.yaml --open         # also opens the page in your web browser
  robkin gui ur5.urdf --tip-link tool0 --port 9000
  robkin gui ur5.urdf --tip-link tool0 --package-path ur_description=.   # package://ur_description/ is here
  robkin gui rrpr.yaml rrpr_dh.yaml   # check: B drawn over A, robkin check's verdict (joints and masses)
  robkin gui vendor_dh.yaml robot.urdf --exaggerate 100   # B's differences from A drawn 100x larger

The app runs on this machine only: it listens on a loopback address (127.0.0.1 by default; --host
takes another 127.x.y.z, ::1 or localhost, nothing else) and answers only requests from its own page
(loopback Host header, same origin), so other web sites open in the browser cannot use it. It needs
no internet. Open the printed address in a browser; stop with Ctrl-C. In the page, paste or load a robot document (YAML/JSON) or a URDF; every
representation is shown as a table and can be downloaded. Bad input is shown as a message in the page.
Drag the pink tool frame's handles and the robot follows by inverse kinematics. A URDF, MJCF or SDF
given here is drawn with the meshes it references (package:// found with --package-path, above the
file or on ROS_PACKAGE_PATH / AMENT_PREFIX_PATH, MJCF meshes in its meshdir, SDF model:// above the
file or on GZ_SIM_RESOURCE_PATH); meshes that cannot be found are named, with why, on stderr and in
the page. The
3D view needs three.js, installed by `make assets` (or `make demo` / `make test`) from npm.
The GUI never expands .xacro files (they are programs); expand one yourself with xacro first.
"""


def register(subparsers) -> argparse.ArgumentParser:
    p = subparsers.add_parser("gui", help=HELP, description=HELP[0].upper() + HELP[1:] + ".", epilog=EPILOG,
                              formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("input", nargs="?", metavar="INPUT",
                   help="robot document (.yaml/.yml/.json), URDF (.urdf), MJCF (.xml/.mjcf) or SDF (.sdf) to show first")
    p.add_argument("other", nargs="?", metavar="B",
                   help="a second description to compare INPUT with, as 'robkin check' does (kinematics and "
                        "mass properties, the first difference in red; --base-link/--tip-link apply to both "
                        "when both are the same XML format)")
    p.add_argument("--base-link", metavar="LINK", help="URDF/SDF link or MJCF body/site: first of the serial chain")
    p.add_argument("--tip-link", metavar="LINK", help="URDF/SDF link or MJCF body/site: last of the chain (the tool)")
    add_package_path(p)
    p.add_argument("--host", default="127.0.0.1",
                   help="loopback address to listen on: 127.0.0.1 (default), another 127.x.y.z, ::1 or localhost")
    p.add_argument("--port", type=int, default=8765, help="port (default 8765; 0 picks a free one)")
    p.add_argument("--open", action="store_true", help="open the page in the default web browser")
    p.add_argument("--verbose", action="store_true", help="log every request to stderr")
    p.add_argument("--exaggerate", type=int, choices=[1, 10, 100, 1000], default=1, metavar="K",
                   help="with B: draw B's differences from A K times larger (1, 10, 100 or 1000; the page's "
                        "'differences x' field); arrows give the true distances")
    return p


_FORMATS = {".yaml": "yaml", ".yml": "yaml", ".json": "json", ".urdf": "urdf", ".xml": "mjcf", ".mjcf": "mjcf",
            ".sdf": "sdf"}
_CHAIN_FORMATS = ("urdf", "mjcf", "sdf")


def _format_of(path: str) -> str:
    from pathlib import Path

    return _FORMATS.get(Path(path).suffix.lower(), "")


def _read(path: str, base_link: str | None, tip_link: str | None) -> tuple[str, str]:
    """(text, format) of a robot file for the page, checked here so that bad input fails before serving."""
    from pathlib import Path

    from ..io.files.input_files import read_text_file
    from ..viz.gui_api import MAX_TEXT, parse_robot

    p = Path(path)
    fmt = _format_of(path)
    if p.suffix.lower() == ".xacro":
        raise InputError(f"{p}: the GUI never expands xacro (a .xacro file is a program that can run code); "
                         f"if you trust it, expand it yourself: xacro {p} > {p.stem}.urdf")
    if not fmt:
        raise InputError(f"{p}: unknown extension '{p.suffix.lower()}'; expected .yaml, .yml, .json, .urdf, .xml, "
                         f".mjcf or .sdf")
    text = read_text_file(p, MAX_TEXT, "a robot file for the GUI")
    if not text.strip():
        raise InputError(f"{p}: file is empty; expected a robot document (YAML/JSON) or a robot file")
    parse_robot(text, fmt, base_link, tip_link, source=str(p))
    return text, fmt


def run(args: argparse.Namespace) -> int:
    from ..viz.gui import make_server

    if not 0 <= args.port <= 65535:
        raise InputError(f"--port: {args.port} is not a port number (0..65535)")
    text, fmt, source, other = "", "auto", "", None
    if args.input:
        text, fmt = _read(args.input, args.base_link, args.tip_link)
        source = args.input
    if args.other:
        # the same chain in B when A and B are the same XML format (two descriptions of one robot)
        chain = fmt in _CHAIN_FORMATS and _format_of(args.other) == fmt
        b_text, b_fmt = _read(args.other, *((args.base_link, args.tip_link) if chain else (None, None)))
        other = {"text": b_text, "fmt": b_fmt, "source": args.other, "exaggerate": args.exaggerate,
                 "base_link": (args.base_link or "") if chain else "", "tip_link": (args.tip_link or "") if chain else ""}
    elif args.exaggerate != 1:
        raise InputError("--exaggerate: give a second robot B to compare with")
    server = make_server(args.host, args.port, text, fmt, args.base_link, args.tip_link, source,
                         quiet=not args.verbose, other=other, package_paths=package_paths(args))
    if server.meshes.missing_line:
        import warnings

        warnings.warn(server.meshes.missing_line, UserWarning, stacklevel=1)
    print(f"robkin gui: serving on {server.url}  (Ctrl-C to stop)", file=sys.stderr, flush=True)
    if args.open:
        import webbrowser

        webbrowser.open(server.url)
    try:
        server.serve_forever()
    except KeyboardInterrupt:
        print("robkin gui: stopped", file=sys.stderr)
    finally:
        server.server_close()
    return 0
