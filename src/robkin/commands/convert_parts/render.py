"""``robkin convert``: the output text for one robot in the chosen format (a document, a table file,
a URDF or MJCF with its meshes, a USD file, code for another toolbox), and the formats' sections and
file names."""

from __future__ import annotations

import argparse
from pathlib import Path

from ...errors import InputError
from .toolbox import CODE_EXTENSIONS, CODE_FORMATS, render_code

__all__ = ["section_of", "EXTENSIONS", "DOC_EXTENSIONS", "TABLE_EXTENSIONS", "table_representations",
           "render_file", "render_in", "render_usd", "check_link_geometry"]

#: --to formats that are not a representation: a whole document or another file type
OTHER_FORMATS = ("json", "yaml", "urdf", "mjcf", "usd", *CODE_FORMATS)


def section_of() -> dict[str, str | None]:
    """--to FORMAT -> document section written for it (None: a whole document or another file type):
    every registered representation (``robkin.representations.registry``), then OTHER_FORMATS."""
    from ...representations.registry import representations

    return {**{r.name: r.section for r in representations()}, **dict.fromkeys(OTHER_FORMATS)}


def table_representations() -> tuple[str, ...]:
    """--to values that have a table form for --format."""
    from ...representations.registry import names

    return names("csv")


#: Output file extensions accepted for each format (the first is used for batch output names).
EXTENSIONS = {"urdf": (".urdf",), "mjcf": (".xml", ".mjcf"), "json": (".json",), "yaml": (".yaml", ".yml"),
              "usd": (".usda", ".usd", ".usdc"), **CODE_EXTENSIONS}
#: Formats whose files robkin reads back after writing them, to check them (``output_check``)
CHECKED_FORMATS = ("urdf", "mjcf", "usd")
DOC_EXTENSIONS = (".yaml", ".yml", ".json")
#: --format -> output file extension (kept here, not imported, for the start-up time of every convert)
TABLE_EXTENSIONS = {"csv": ".csv", "markdown": ".md", "latex": ".tex"}


def check_link_geometry(args: argparse.Namespace) -> float | None:
    """The capsule radius (None: the default), after checking the --link-* options fit --to."""
    from ...io.files.numbers import number

    style, radius = getattr(args, "link_geometry", "none"), getattr(args, "link_radius", None)
    if style != "none" and args.to not in ("urdf", "mjcf", "usd"):
        raise InputError(f"--link-geometry {style}: shapes are written by --to urdf, mjcf or usd only, "
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
    from ...link_geometry import with_link_capsules

    return with_link_capsules(robot, check_link_geometry(args))


def render_file(robot, fmt: str, out_ext: str, args: argparse.Namespace | None = None,
                 source: str | None = None, out_dir: Path | None = None, mesh_dir: str = "meshes") -> str:
    """Text of the output file for one robot (``source``: its input file; ``out_dir``: where the
    output goes, for the meshes an MJCF or a URDF takes along)."""
    from ...io.documents.reader import document_from_robot, dump

    degrees = bool(args is not None and args.degrees)

    if args is not None and args.format:
        from ...io.tables.files import render_table

        return render_table(robot, fmt, args.format, pi=args.pi, digits="exact" if args.exact else args.digits)
    if fmt in CODE_FORMATS:
        return render_code(robot, fmt, out_ext, args)
    if fmt == "urdf":
        from .urdf_output import render_urdf

        return render_urdf(_with_link_geometry(robot, args), args or argparse.Namespace(), source, out_dir, mesh_dir)
    if fmt == "mjcf":
        if args is None:
            from ...io.mjcf import mjcf_from_robot

            return mjcf_from_robot(robot)
        from .mjcf_output import render_mjcf

        return render_mjcf(_with_link_geometry(robot, args), args, source, out_dir, mesh_dir)
    if fmt == "usd":
        return render_usd(robot, ".usda", args, source).decode("utf-8")
    section = section_of()[fmt]
    doc = document_from_robot(robot, degrees=degrees) if section is None else \
        document_from_robot(robot, (section,), degrees=degrees)
    doc_fmt = "json" if (fmt == "json" or out_ext == ".json") and fmt != "yaml" else "yaml"
    if doc_fmt == "yaml" and not (args is not None and args.exact):
        from ...io.documents.rounding import round_document

        doc = round_document(doc, robot.scale, None if args is None else args.digits)
    return dump(doc, doc_fmt)


def render_usd(robot, suffix: str, args: argparse.Namespace | None, source: str | None) -> bytes:
    """The bytes of a USD file (``.usda`` text, ``.usd``/``.usdc`` crate) for one robot, the meshes of
    its robot file ``source`` inline (``robkin.io.usd.writer``)."""
    from ...io.usd.writer import usd_bytes
    from ...simulation.servos import servo_plan
    from ..support.common import package_paths

    robot = _with_link_geometry(robot, args)
    # the drives hold the same home with the same gains as the MJCF export's default position servos
    plan = servo_plan(robot)
    drives = {s.name: (s.kp, s.kv, None if s.force is None else s.force[1]) for s in plan.actuated()}
    paths = package_paths(args) if args is not None else None
    if args is None or (getattr(args, "collision", "source") == "source" and getattr(args, "max_faces", None) is None):
        return usd_bytes(robot, suffix, source=source, package_paths=paths, drives=drives, gravity_off=plan.gravcomp)
    import tempfile

    from .collision_output import collision_stage

    # --collision / --max-faces: the collision meshes made in a scratch folder, then inlined like the rest
    with tempfile.TemporaryDirectory(prefix="robkin-usd-collision-") as scratch:
        with collision_stage(robot, args, source, Path(scratch), "meshes", fmt="usd") as stage:
            premade = {name: Path(scratch) / rel for name, rel in stage.premade.items()}
            return usd_bytes(stage.robot, suffix, source=source, package_paths=paths, drives=drives,
                             gravity_off=plan.gravcomp, premade=premade)


def render_in(path: str, robot, fmt: str, out_ext: str, args: argparse.Namespace, out_dir: Path | None = None,
               mesh_dir: str = "meshes") -> str:
    """``render_file`` for one input of a batch: an error names the input it is about."""
    try:
        return render_file(robot, fmt, out_ext, args, path, out_dir, mesh_dir)
    except InputError as exc:
        raise exc.in_source(path) from None
