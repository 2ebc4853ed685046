"""robkin convert: one robot (or a batch) into another representation.

The parser and the run: options checked, inputs loaded, output paths checked, files written all or
nothing. The help text is ``_convert_help``; the output text for one robot, ``_convert_render``.
"""

from __future__ import annotations

import argparse
import sys
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator

from ..errors import InputError
from .support.chains import add_chain_options, chain_ends
from .support.common import add_allow_xacro, add_from, add_package_path
from .convert_parts.help import epilog
from .convert_parts.render import (CHECKED_FORMATS, DOC_EXTENSIONS, EXTENSIONS, TABLE_EXTENSIONS, check_link_geometry,
                                   render_file, render_in, render_usd, section_of, table_representations)
from .support.output import wrote
from .convert_parts.toolbox import CODE_FORMATS, add_toolbox_options, check_toolbox_options


def register(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    from .convert_parts.collision_output import COLLISION_HELP, add_collision_options
    from .convert_parts.mjcf_output import MJCF_HELP, add_mjcf_options

    p = sub.add_parser("convert", help="convert a robot into another representation",
                       description="Convert a robot description into another representation, exactly: "
                                   "forward kinematics of the output equals that of the input at every q.",
                       epilog=epilog().replace("{mjcf}", MJCF_HELP + "\n" + COLLISION_HELP),
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("input", nargs="+", metavar="INPUT",
                   help="robot document (.yaml/.yml/.json) or robot file: URDF (.urdf; .xacro with --allow-xacro), "
                        "MJCF (.xml/.mjcf), SDF (.sdf) or USD (.usda/.usd/.usdc) (one or more)")
    add_chain_options(p)
    add_allow_xacro(p)
    add_from(p)
    formats = section_of()
    p.add_argument("--to", required=True, choices=list(formats), metavar="FORMAT",
                   help="output representation: " + ", ".join(formats))
    p.add_argument("--format", choices=["csv", "markdown", "latex"],
                   help=f"write a table representation (--to {', '.join(table_representations())}) as CSV, "
                        "Markdown or LaTeX, full precision")
    p.add_argument("--pi", action="store_true",
                   help="with --format: angles that are exactly k*pi/m written as such (-pi/2, 3*pi/4)")
    precision = p.add_mutually_exclusive_group()
    precision.add_argument("--digits", type=_digits, metavar="N",
                           help="tables (--format) and YAML documents: N significant digits (default: the "
                                "shortest decimal that keeps FK within 1e-12 of the robot's size)")
    precision.add_argument("--exact", action="store_true",
                           help="tables (--format), YAML documents and --to opw: every digit, reading back to "
                                "the very same floats (JSON documents always do)")
    p.add_argument("-o", "--output", metavar="OUT", help="output file, or folder for several inputs")
    p.add_argument("--json", action="store_true",
                   help="print the robot document with the chosen section as JSON (instead of a table)")
    p.add_argument("--layout", choices=["robkin", "paper"], default="robkin",
                   help="DH table layout on stdout: 'paper' prints the base as row 0 (n+1 rows)")
    p.add_argument("--degrees", action="store_true",
                   help="angles in degrees: in the table on stdout, and in a written robot document "
                        "(which then says 'angles: degrees')")
    add_toolbox_options(p)
    add_package_path(p)
    add_mjcf_options(p)
    add_collision_options(p)
    p.add_argument("--link-geometry", choices=["none", "capsules"], default="none",
                   help="--to urdf|mjcf|usd: give the links shapes a simulator shows: 'capsules' draws a capsule "
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
    from ..io import MJCF_EXTENSIONS, ROBOT_FILE_EXTENSIONS, SDF_EXTENSIONS, USD_EXTENSIONS

    ext = Path(path).suffix.lower()
    if ext not in ROBOT_FILE_EXTENSIONS or fmt in ("urdf", "mjcf", "usd", "json", "yaml"):
        return None
    names = ", ".join(j.name for j in robot.joints[:3]) + (", ..." if robot.n > 3 else "")
    what = ("MuJoCo qpos" if ext in MJCF_EXTENSIONS else "SDF position" if ext in SDF_EXTENSIONS else
            "USD joint position" if ext in USD_EXTENSIONS else "URDF position")
    note = (f"joint variables: q_i in this {fmt} output is the {what} of joint i ({names}), "
            f"with the same sign and the same zero")
    flipped = [j.name for j in robot.joints if j.flip]
    if flipped and _subtracts_flipped(fmt):
        note += (f"; joint(s) {', '.join(flipped)} point against their frame's z (flip: true), so the table "
                 f"subtracts q there")
    return note


def _subtracts_flipped(fmt: str) -> bool:
    """Whether a table of ``fmt`` subtracts q at a flipped joint (its rows are frames whose z a flipped
    joint moves against: the frame-based tables, and RPY-XYZ's joint frames)."""
    from ..representations.registry import representations

    return any(r.name == fmt and (r.frame_based or r.layout == "rpy") for r in representations())


def _load_all(inputs: list[str], args: argparse.Namespace) -> list:
    from ..io import load

    from ..io import TABLE_EXTENSIONS

    # --from applies to the table files among the inputs (the others say what they hold)
    return [load(i, base_link=base, tip_link=tip, allow_xacro=args.allow_xacro,
                 representation=args.representation if i.lower().endswith(TABLE_EXTENSIONS) else None)
            for i, (base, tip) in zip(inputs, chain_ends(args, inputs))]


def _check_table_options(args: argparse.Namespace) -> None:
    tables = table_representations()
    if args.format and args.to not in tables:
        raise InputError(f"--format {args.format}: --to {args.to} is not a table; --format works with --to "
                         f"{', '.join(tables)}")
    if args.pi and not args.format:
        raise InputError("--pi: applies to --format csv|markdown|latex tables")
    if args.format and args.json:
        raise InputError(f"--json prints a robot document; it does not combine with --format {args.format}")


@contextmanager
def _removed_on_error(paths: list[Path]) -> Iterator[None]:
    """Remove the files just written when the check after writing fails (exit 2 leaves no output
    behind: the source held something only the check read, such as a link's inertial)."""
    try:
        yield
    except BaseException:
        for p in paths:
            p.unlink(missing_ok=True)
        raise


def run(args: argparse.Namespace) -> int:
    from ..io.files.atomic import check_writable_dir, write_text_atomic, write_texts_atomic

    inputs: list[str] = args.input
    fmt: str = args.to
    _check_table_options(args)
    check_toolbox_options(args)
    check_link_geometry(args)
    from .convert_parts.mjcf_output import check_mjcf_options

    check_mjcf_options(args)
    from .convert_parts.collision_output import check_collision_options

    check_collision_options(args)
    if args.json and (args.output or fmt in ("urdf", "mjcf", "usd", "yaml")):
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
        robots = _load_all(inputs, args)
        if fmt == "mjcf":  # the meshes are copied while the models are written: the folder is needed first
            out_dir.mkdir(exist_ok=True)
        # the meshes of each model in a folder of their own (meshes/<name>/): two robots' base.stl differ
        texts = [render_in(path, robot, fmt, ext, args, out_dir, f"meshes/{t.stem}")
                 for path, robot, t in zip(inputs, robots, targets)]
        out_dir.mkdir(exist_ok=True)  # only now: a failed conversion leaves no empty folder behind
        write_texts_atomic(list(zip(targets, texts)))  # all or nothing
        for target in targets:
            wrote(target)
        if fmt in CHECKED_FORMATS and not args.format:
            from .convert_parts.output_check import check_written

            with _removed_on_error(targets):
                for robot, target in zip(robots, targets):
                    check_written(robot, target, fmt)
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
        if fmt == "mjcf":  # a model and its meshes: its folder is made (in an existing one) if need be
            parent = out.parent if str(out.parent) else Path(".")
            if not parent.exists() and (parent.parent if str(parent.parent) else Path(".")).is_dir():
                parent.mkdir()
            check_writable_dir(out)
        if fmt == "usd":  # .usd/.usdc are binary
            from ..io.files.atomic import atomic_file

            data = render_usd(robot, out.suffix.lower(), args, inputs[0])
            with atomic_file(out, binary=True) as fh:
                fh.write(data)
            wrote(out)
            written = [out]
        else:
            text = render_file(robot, fmt, out.suffix.lower(), args, inputs[0], out.parent)
            if fmt == "mjcf" and args.scene:  # the model and its scene.xml, all or nothing
                from .convert_parts.mjcf_output import scene_of

                scene = scene_of(robot, out, text)
                write_texts_atomic([(out, text), scene])
                wrote(out)
                wrote(scene[0])
                written = [out, scene[0]]
            else:
                write_text_atomic(out, text)
                wrote(out)
                written = [out]
        if fmt in CHECKED_FORMATS:
            from .convert_parts.output_check import check_written

            with _removed_on_error(written):
                check_written(robot, out, fmt)
        if note:
            print(f"robkin: note: {note}", file=sys.stderr)
        return 0
    if args.format:
        sys.stdout.write(render_file(robot, fmt, ext, args))
        return 0
    if args.json:
        sys.stdout.write(render_file(robot, fmt if section_of()[fmt] or fmt in CODE_FORMATS else "json", ".json",
                                      args))
        return 0
    if section_of()[fmt] is None:
        sys.stdout.write(render_file(robot, fmt, ".json" if fmt == "json" else EXTENSIONS.get(fmt, (".yaml",))[0],
                                      args, inputs[0]))
        return 0
    from ..io.tables.terminal import blocks, show_blocks

    show_blocks(blocks(robot, fmt, layout=args.layout, degrees=args.degrees) + ([f"note: {note}"] if note else []))
    return 0
