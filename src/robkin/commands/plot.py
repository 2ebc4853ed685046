"""``robkin plot``: pictures of a robot's structure, or of estimation metrics."""

from __future__ import annotations

import argparse

from ..errors import InputError
from .support.common import add_input, add_package_path, load_input, package_paths, parse_q
from .support.output import warn_outside_limits, wrote

HELP = "draw a robot (joint axes blue, tool pink), representations overlaid, or estimation metrics"
EPILOG = """\
examples:
  robkin plot rrpr.yaml -o rrpr.png
  robkin plot rrpr.yaml --q 3*pi/4,-pi/4,0.3,-3*pi/4 --overlay dh,poe -o rrpr_q.svg
  robkin plot ur5.urdf --tip-link tool0 --frames -o ur5.png
  robkin plot ur5.urdf --tip-link tool0 -o ur5.html      # 3D page with the URDF's meshes
  robkin plot original.yaml converted.yaml -o both.png     # several robots in one picture
  robkin plot vendor_dh.yaml robot.urdf --exaggerate 100 -o diff.png   # 4-decimal table vs the robot
  robkin plot --metrics pose1_A.yaml pose1_B.yaml pose1_C.yaml pose1_D.yaml -o metrics.png

--overlay draws the robot rebuilt from each listed representation (gjd, dh, mdh, poe, poe-body,
rpy-xyz): link lines go through each one's frame origins, so they differ, while joint axes and the
tool frame coincide; the title states by how much they disagree (rounding only, for one robot).
-o takes .png, .svg, .pdf or .html; without -o the picture is written to INPUT's name with .png in
the current folder. .html is an interactive 3D page (the GUI's viewer: drag to turn, right-drag to
pan, wheel to zoom, front/side/top views), one self-contained file that works offline; it needs the
three.js modules of `make assets`, not matplotlib; it draws the first robot file's meshes as the GUI
does (found as the GUI finds them, --package-path NAME=DIR for packages found nowhere else) and names
the ones that were not found, with why, on stderr and in the page.
With several INPUTs, --exaggerate K draws every robot after the first with its differences from the
first multiplied by K (where an axis lies and points, the tool origin), and red arrows from the
first robot's joint axes to the others', labelled with the true distance: a 6 mm difference on a 1 m
arm is invisible as it is and plain at K = 100.
With --metrics, each INPUT is an estimation result document; its metrics object (or, if absent,
metrics computed at q = 0) is drawn as the estimation paper's bar and log plots. Results named
<group>_<type> (pose1_A.yaml, or name: pose1-A) are grouped per pose, one bar per type.
"""


def register(subparsers) -> argparse.ArgumentParser:
    p = subparsers.add_parser("plot", help=HELP, description=HELP.capitalize() + ".", epilog=EPILOG,
                              formatter_class=argparse.RawDescriptionHelpFormatter)
    add_input(p, many=True)
    add_package_path(p)
    p.add_argument("--q", metavar="Q1,Q2,...",
                   help="joint values (rad / length units; expressions like 3*pi/4 allowed); default home")
    from ..representations.registry import overlays

    p.add_argument("--overlay", metavar="REPS", default="",
                   help="comma-separated representations to overlay: " + ", ".join(r.name for r in overlays()))
    p.add_argument("--frames", action="store_true", help="also draw every joint frame (RGB triads)")
    p.add_argument("--exaggerate", metavar="K",
                   help="several INPUTs: multiply their differences from the first by K (1 to 1e6) and draw "
                        "difference arrows labelled with the true distance")
    p.add_argument("--view", metavar="ELEV,AZIM", default="25,-60", help="camera angles in degrees (default 25,-60)")
    p.add_argument("--title", help="picture title (default: robot name and q)")
    p.add_argument("--metrics", action="store_true",
                   help="INPUTs are estimation results: plot length and manipulability (bar and log plots)")
    p.add_argument("-o", "--output", metavar="OUT", help="output picture: .png, .svg, .pdf or .html")
    return p


def run(args: argparse.Namespace) -> int:
    from pathlib import Path

    from ..io.files.numbers import number_list

    out = Path(args.output) if args.output else Path(Path(args.input[0]).stem + ".png")
    from ..viz.plot import PICTURE_FORMATS

    if out.suffix.lower() not in PICTURE_FORMATS:  # before any work: nothing is written on bad input
        raise InputError(f"-o {out}: unknown picture format '{out.suffix or '(none)'}'; "
                         f"one of {', '.join(PICTURE_FORMATS)}")
    if out.suffix.lower() == ".html" and not args.metrics:
        return _viewer_page(args, out, number_list(args.view, "--view", 2))
    try:
        import matplotlib  # noqa: F401 - only to say clearly what is missing
    except ImportError:
        raise InputError("plot: pictures need matplotlib (pip install 'robkin[plot]')") from None
    if args.metrics:
        if args.q or args.overlay or args.frames:
            raise InputError("--metrics: --q, --overlay and --frames apply to robot pictures, not metrics")
        from ..viz.metrics import plot_metrics, read_metrics

        fig = plot_metrics([read_metrics(path) for path in args.input], title=args.title)
        caption = ""
    else:
        fig, caption = _robot_figure(args, number_list(args.view, "--view", 2))
    from ..viz.plot import save_figure

    save_figure(fig, out, caption=caption)
    wrote(out)
    return 0


def _robots(args: argparse.Namespace):
    """(overlay names, robots, q) of a robot picture, checked: robots drawn together share q."""
    from ..viz.scene import REPRESENTATIONS

    overlay = [r.strip() for r in args.overlay.split(",") if r.strip()]
    for r in overlay:
        if r not in REPRESENTATIONS:
            raise InputError(f"--overlay: unknown representation '{r}'; one of {', '.join(REPRESENTATIONS)}")
    robots = [load_input(path, args) for path in args.input]
    q = parse_q(args.q, robots[0].n) if args.q else None
    import numpy as np

    for r in robots:
        warn_outside_limits(r, np.zeros(r.n) if q is None else q, "--q" if args.q else "home (q = 0)")
    if len(robots) > 1:
        if overlay:
            raise InputError("--overlay: give one INPUT to overlay its representations, or several INPUTs "
                             "without --overlay")
        for path, r in zip(args.input[1:], robots[1:]):
            if r.n != robots[0].n:
                raise InputError(f"{path}: has {r.n} joints, {args.input[0]} has {robots[0].n}; "
                                 f"robots drawn together must share q")
    elif args.exaggerate is not None:
        raise InputError("--exaggerate: give two or more INPUTs (the first is the reference)")
    return overlay, robots, q


def _exaggeration(args: argparse.Namespace) -> float | None:
    """--exaggerate K as a number (None when not given)."""
    if args.exaggerate is None:
        return None
    from ..io.files.numbers import number

    k = number(args.exaggerate, "--exaggerate")
    if not 1 <= k <= 1e6:
        raise InputError(f"--exaggerate: expected a factor from 1 to 1e6, got {args.exaggerate}")
    return k


def _caption(robot, q) -> str:
    import numpy as np

    T = robot.fk(np.zeros(robot.n) if q is None else q)
    return "tool pose T (robot base frame):\n" + "\n".join(" ".join(f"{v: .6f}" for v in row) for row in T)


def _viewer_page(args: argparse.Namespace, out, view: list[float]) -> int:
    from pathlib import Path

    import numpy as np

    from ..io.files.atomic import write_text_atomic
    from ..viz.assets import require_assets
    from ..viz.viewer_page import viewer_data, viewer_page

    require_assets()
    overlay, robots, q = _robots(args)
    labels = [Path(p).name for p in args.input] if len(robots) > 1 else [robots[0].name or "robot"]
    where = "home (q = 0)" if q is None else f"q = {np.round(q, 4).tolist()}"
    title = args.title or (f"{robots[0].name or Path(args.input[0]).stem} at {where}" if len(robots) == 1
                           else f"{len(robots)} robots at {where}")
    data = viewer_data(robots, q, overlay, labels, frames=args.frames, view=view, exaggerate=_exaggeration(args),
                       source=args.input[0], package_paths=package_paths(args))
    write_text_atomic(out, viewer_page(data, title, _caption(robots[0], q)))
    wrote(out)
    return 0


def _robot_figure(args: argparse.Namespace, view: list[float]):
    from pathlib import Path

    import numpy as np

    from ..viz.plot import plot_robot, plot_scenes
    from ..viz.scene import build_scene

    overlay, robots, q = _robots(args)
    if len(robots) == 1:
        fig = plot_robot(robots[0], q, overlay or ("gjd",), frames=args.frames, view=tuple(view), title=args.title)
        robot = robots[0]
    else:
        k = _exaggeration(args)
        scenes = [build_scene(r, q, label=Path(path).name) for path, r in zip(args.input, robots)]
        robot = robots[0]
        where = "home (q = 0)" if q is None else f"q = {np.round(q, 4).tolist()}"
        title = args.title or f"{len(robots)} robots at {where}" + ("" if k is None else f", differences x{k:g}")
        fig = plot_scenes(scenes, frames=args.frames, view=tuple(view), title=title, exaggerate=k)
    return fig, _caption(robot, q)
