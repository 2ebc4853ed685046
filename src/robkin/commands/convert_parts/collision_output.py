"""``robkin convert --collision MODE --max-faces N``: its options, and the collision stage of a URDF or
MJCF written with meshes (``robkin.collision``)."""

from __future__ import annotations

import argparse
import sys
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Callable, Iterator, Sequence

from ...errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    from ...robot import Robot

__all__ = ["add_collision_options", "check_collision_options", "collision_stage", "COLLISION_HELP"]

#: = robkin.collision.MODES (not imported: the module loads with every command)
_MODES = ("source", "hull", "decompose", "primitives", "none")
#: = robkin.collision.decimate.DEFAULT_MAX_FACES
_DEFAULT_MAX_FACES = 200_000
#: --max-faces bounds: MuJoCo needs 4 vertices (a tetrahedron has 4 faces); 10 M triangles are far beyond
#: any link's collision mesh and bound what a decimation keeps in memory.
_MIN_FACES, _MAX_FACES = 4, 10_000_000
#: --to formats that write collision shapes
_WRITERS = ("urdf", "mjcf", "usd")

COLLISION_HELP = """\
Collision geometry (--to mjcf|urdf, --collision MODE): source (default) keeps the source's collision
shapes, primitives as primitives, a mesh above --max-faces triangles decimated; hull writes one convex
hull per mesh (what MuJoCo collides anyway, as a small file); decompose cuts each mesh into convex parts
with CoACD (pip install 'robkin[collision]'; cached in ~/.cache/robkin/coacd); primitives fits one box,
sphere, cylinder or capsule per link; both print their fit (volume error, one-sided Hausdorff distance);
none writes no collision shapes. New mesh files go into meshes/collision/ beside the output; a flat
mesh (no volume) becomes a thin box. MJCF: body pairs joined by a joint, and pairs whose collision
geoms touch at home (q = 0 clipped into the limits; checked with MuJoCo when it is installed), are
excluded from contact (<contact><exclude>), so the model starts without a penetrating contact.
"""


def _faces(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text[:40]}' is not a whole number of triangles") from None
    if not _MIN_FACES <= value <= _MAX_FACES:
        raise argparse.ArgumentTypeError(f"{value} is not {_MIN_FACES} .. {_MAX_FACES} triangles")
    return value


def add_collision_options(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("collision geometry (--to mjcf, urdf)")
    g.add_argument("--collision", choices=_MODES, default="source",
                   help="collision shapes: source (default: the source's, primitives kept), hull (one convex "
                        "hull per mesh), decompose (convex parts by CoACD, cached), primitives (one fitted "
                        "box/sphere/cylinder/capsule per link, with its fit), none")
    g.add_argument("--max-faces", type=_faces, default=None, metavar="N",
                   help=f"face budget of a collision mesh: one with more triangles is decimated "
                        f"(default {_DEFAULT_MAX_FACES}, MuJoCo's STL limit)")


def check_collision_options(args: argparse.Namespace) -> None:
    """InputError for collision options given with a --to that writes no shapes."""
    mode, faces = getattr(args, "collision", "source"), getattr(args, "max_faces", None)
    if args.to not in _WRITERS:
        if mode != "source":
            raise InputError(f"--collision {mode}: applies to --to mjcf, urdf or usd, not --to {args.to}")
        if faces is not None:
            raise InputError(f"--max-faces: applies to --to mjcf, urdf or usd, not --to {args.to}")


@dataclass
class Stage:
    """What a writer takes from the collision stage: the robot, its premade mesh files, the exclusions."""

    robot: Robot
    premade: dict[str, str] = field(default_factory=dict)
    contact_excludes: Callable[[str], Sequence[tuple[str, str]]] | None = None


def _say(line: str) -> None:
    print(f"robkin: note: {line}", file=sys.stderr)


def _report(result, mode: str) -> None:
    if result.unread and mode != "source":  # in source mode the writer's copy says it for every mesh
        import warnings

        warnings.warn(f"{len(result.unread)} collision mesh(es) could not be read and stay as the source gave them: "
                      f"{', '.join(result.unread[:3])}{', ...' if len(result.unread) > 3 else ''}", UserWarning,
                      stacklevel=3)
    if result.flat:
        _say(f"{len(result.flat)} flat collision mesh(es) (no volume; MuJoCo refuses them) written as thin boxes: "
             f"{', '.join(result.flat[:4])}{', ...' if len(result.flat) > 4 else ''}")
    if result.decimated:
        _say(f"{len(result.decimated)} collision mesh(es) above the face budget decimated: "
             f"{', '.join(result.decimated[:4])}{', ...' if len(result.decimated) > 4 else ''}")
    if mode in ("hull", "decompose"):
        cached = f", {result.cached} from the cache" if mode == "decompose" else ""
        _say(f"--collision {mode}: {result.meshes_in} mesh(es) -> {result.meshes_out} convex mesh file(s), "
             f"{result.faces_out} triangles{cached}, in {result.seconds:.1f} s")
    if mode == "decompose" and result.decompositions:
        print("  per mesh: convex parts, volume error of their union and of the single hull (vs the mesh, or its "
              "hull when the mesh is not closed), one-sided Hausdorff distance (parts -> mesh, robot length unit)",
              file=sys.stderr)
        for d in result.decompositions:
            ref = "" if d.reference == "mesh" else " (vs its hull: the mesh is not closed)"
            print(f"  {d.mesh}: {d.parts} parts, volume {100 * d.volume_error:+.1f} % (hull "
                  f"{100 * d.hull_volume_error:+.1f} %){ref}, Hausdorff {d.hausdorff:.4g}", file=sys.stderr)
    if mode == "primitives":
        _say(f"--collision primitives: {len(result.fits)} link(s) in {result.seconds:.1f} s; per link: kind, "
             f"volume error (vs the link's convex hull), one-sided Hausdorff distance (primitive -> link, in the "
             f"robot's length unit)")
        for f in result.fits:
            err = "n/a (flat link)" if f.volume_error == float("inf") else f"{100 * f.volume_error:+.0f} %"
            print(f"  {f.link}: {f.kind}, volume {err}, Hausdorff {f.hausdorff:.4g}", file=sys.stderr)


@contextmanager
def collision_stage(robot: Robot, args: argparse.Namespace, source: str | None, out_dir: Path | None,
                    mesh_dir: str, fmt: str = "mjcf") -> Iterator[Stage]:
    """The robot with the collision shapes of ``--collision`` (mesh files written under
    ``out_dir/mesh_dir/collision``), and for MJCF the contact exclusions; the files this stage and the
    writer inside the ``with`` add under ``out_dir/mesh_dir`` are removed again when it fails."""
    from ...collision.decimate import MissingExtra

    mode = getattr(args, "collision", "source")
    faces = getattr(args, "max_faces", None) or _DEFAULT_MAX_FACES
    folder = None if out_dir is None else out_dir / mesh_dir
    before = set(_files(folder))
    existed = folder is not None and folder.exists()
    try:
        if mode == "source" and (out_dir is None or not any(s.role == "collision" and s.geometry.kind == "mesh"
                                                             for s in robot.bodies.shapes)):
            stage = Stage(robot)  # without a folder (stdout), the model names the source's files where they are
        else:
            from ...collision import collision_geometry
            from ..support.common import package_paths

            try:
                result = collision_geometry(robot, mode, source=source, out_dir=out_dir, mesh_dir=mesh_dir,
                                            package_paths=package_paths(args), max_faces=faces)
            except (MissingExtra, ValueError) as exc:
                raise InputError(str(exc)) from None
            _report(result, mode)
            stage = Stage(result.robot, result.premade)
        if fmt == "mjcf" and mode != "none":
            stage.contact_excludes = _excludes(stage.robot, out_dir)
        yield stage
    except BaseException:
        for f in set(_files(folder)) - before:
            f.unlink(missing_ok=True)
        if folder is not None and not existed:
            for d in sorted((p for p in folder.rglob("*") if p.is_dir()), reverse=True):
                _rmdir(d)
            _rmdir(folder)
        raise


def _files(folder: Path | None) -> list[Path]:
    if folder is None or not folder.is_dir():
        return []
    return [p for p in folder.rglob("*") if p.is_file() or p.is_symlink()]


def _rmdir(d: Path) -> None:
    try:
        d.rmdir()
    except OSError:
        pass


def _excludes(robot: Robot, out_dir: Path | None) -> Callable[[str], Sequence[tuple[str, str]]]:
    def find(text: str) -> Sequence[tuple[str, str]]:
        from ...collision.exclusions import contact_excludes

        try:
            pairs, note = contact_excludes(text, out_dir, max(float(robot.scale), 1e-9))
        except Exception as exc:  # noqa: BLE001 - MuJoCo refusing the draft: the check after writing says why
            import warnings

            warnings.warn(f"contacts at home not checked: MuJoCo did not compile the draft model "
                          f"({str(exc).splitlines()[0][:120] if str(exc) else type(exc).__name__})", UserWarning,
                          stacklevel=2)
            from ...collision.exclusions import adjacent_pairs

            return adjacent_pairs(text)
        _say(note)
        return pairs

    return find
