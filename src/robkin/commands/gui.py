"""``robkin gui``: open a robot in a local browser app (3D view, joint sliders, all representations)."""

from __future__ import annotations

import argparse
import sys

from ..errors import InputError

HELP = "browser app: load or paste a robot, see it in 3D with joint sliders, convert and download"
EPILOG = """\
examples:
  robkin gui                          # starts with the bundled RRPR example
  robkin gui rrpr.yaml --open         # also opens the page in your web browser
  robkin gui ur5.urdf --tip-link tool0 --port 9000

The app runs on this machine only: it listens on a loopback address (127.0.0.1 by default; --host
takes another 127.x.y.z, ::1 or localhost, nothing else) and answers only requests from its own page
(loopback Host header, same origin), so other web sites open in the browser cannot use it. It needs
no internet. Open the printed address in a browser; stop with Ctrl-C. In the page, paste or load a robot document (YAML/JSON) or a URDF; every
representation is shown as a table and can be downloaded. Bad input is shown as a message in the page.
The GUI never expands .xacro files (they are programs); expand one yourself with xacro first.
"""


def register(subparsers) -> argparse.ArgumentParser:
    p = subparsers.add_parser("gui", help=HELP, description=HELP.capitalize() + ".", epilog=EPILOG,
                              formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("input", nargs="?", metavar="INPUT",
                   help="robot document (.yaml/.yml/.json), URDF (.urdf), MJCF (.xml/.mjcf) or SDF (.sdf) to show first")
    p.add_argument("--base-link", metavar="LINK", help="URDF/SDF link or MJCF body/site: first of the serial chain")
    p.add_argument("--tip-link", metavar="LINK", help="URDF/SDF link or MJCF body/site: last of the chain (the tool)")
    p.add_argument("--host", default="127.0.0.1",
                   help="loopback address to listen on: 127.0.0.1 (default), another 127.x.y.z, ::1 or localhost")
    p.add_argument("--port", type=int, default=8765, help="port (default 8765; 0 picks a free one)")
    p.add_argument("--open", action="store_true", help="open the page in the default web browser")
    p.add_argument("--verbose", action="store_true", help="log every request to stderr")
    return p


def run(args: argparse.Namespace) -> int:
    from pathlib import Path

    from ..io.files import read_text_file
    from ..viz.gui import make_server
    from ..viz.gui_api import MAX_TEXT, parse_robot

    if not 0 <= args.port <= 65535:
        raise InputError(f"--port: {args.port} is not a port number (0..65535)")
    text, fmt, source = "", "auto", ""
    if args.input:
        p = Path(args.input)
        ext = p.suffix.lower()
        fmt = {".yaml": "yaml", ".yml": "yaml", ".json": "json", ".urdf": "urdf", ".xml": "mjcf", ".mjcf": "mjcf",
               ".sdf": "sdf"}.get(ext, "")
        if ext == ".xacro":
            raise InputError(f"{p}: the GUI never expands xacro (a .xacro file is a program that can run code); "
                             f"if you trust it, expand it yourself: xacro {p} > {p.stem}.urdf")
        if not fmt:
            raise InputError(f"{p}: unknown extension '{ext}'; expected .yaml, .yml, .json, .urdf, .xml, .mjcf "
                             f"or .sdf")
        text = read_text_file(p, MAX_TEXT, "a robot file for the GUI")
        if not text.strip():
            raise InputError(f"{p}: file is empty; expected a robot document (YAML/JSON) or a robot file")
        parse_robot(text, fmt, args.base_link, args.tip_link, source=str(p))  # bad input fails here, not in the page
        source = str(p)
    server = make_server(args.host, args.port, text, fmt, args.base_link, args.tip_link, source,
                         quiet=not args.verbose)
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
