"""The collision geometry a simulator gets (``robkin convert --collision MODE``): the robot's collision
shapes turned into new ones, mesh files written beside the output.

Modes
    source      the source's shapes (primitives stay primitives); a mesh above the face budget is
                decimated (``decimate``), a flat one becomes a thin box (``hull.flat_box``)
    hull        one convex hull per mesh, written as an STL file
    decompose   convex parts per mesh by CoACD (``decompose``, cached)
    primitives  one fitted box, sphere, cylinder or capsule per link (``primitives``, with its fit)
    none        no collision shapes

``collision_geometry`` returns a ``Collision``: the robot with its collision shapes replaced (the other
shapes untouched), and the files it wrote (their names in the new shapes, absolute, -> paths relative to
the output folder), which a writer names instead of finding them in the source (``premade``). New mesh
files go into ``OUT/<mesh_dir>/collision/`` (never over a mesh of the source; never through a symbolic
link leading out of the output folder), their coordinates in the shape's own frame with the source's
scale applied. A mesh that cannot be read is left as the source gave it, for the writer to copy or
leave out (it says so).
"""

from __future__ import annotations

import re
import time
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Mapping

import numpy as np

from .decimate import DEFAULT_MAX_FACES, decimate
from .hull import convex_hull, flat_box, is_flat
from .mesh_data import MeshError, read_mesh, stl_bytes

if TYPE_CHECKING:  # pragma: no cover
    from ..body_parts import Shape
    from ..robot import Robot
    from .decompose_fit import DecompositionReport
    from .primitives import FitReport

__all__ = ["MODES", "Collision", "collision_geometry"]

MODES = ("source", "hull", "decompose", "primitives", "none")


@dataclass
class Collision:
    """What ``collision_geometry`` made (see the module doc)."""

    robot: Robot
    premade: dict[str, str] = field(default_factory=dict)
    fits: list[FitReport] = field(default_factory=list)
    decompositions: list[DecompositionReport] = field(default_factory=list)
    meshes_in: int = 0          # distinct source meshes used for collision
    meshes_out: int = 0         # mesh files written
    faces_out: int = 0          # their triangles
    primitives_out: int = 0     # primitive collision shapes in the result
    cached: int = 0             # decompositions taken from the cache
    flat: list[str] = field(default_factory=list)       # flat meshes written as thin boxes
    decimated: list[str] = field(default_factory=list)  # meshes above the face budget
    unread: list[str] = field(default_factory=list)     # meshes that could not be read ("name (why)")
    seconds: float = 0.0


class _Writer:
    """Mesh files into OUT/<mesh_dir>/collision, names unique in this run, never over a source mesh."""

    def __init__(self, out_dir: Path, mesh_dir: str, sources: set[Path]) -> None:
        from ..io.files.atomic import check_inside

        self.out_dir = out_dir
        self.rel = f"{mesh_dir}/collision"
        self.folder = check_inside(out_dir, out_dir / self.rel)
        self.sources = sources
        self.taken: set[str] = set()
        self.written: dict[str, str] = {}

    def write(self, stem: str, V: np.ndarray, F: np.ndarray) -> str:
        from ..io.files.atomic import atomic_file

        stem = re.sub(r"[^A-Za-z0-9_.\-]", "_", stem)[:80] or "mesh"
        k = 1
        while True:
            name = f"{stem}{'' if k == 1 else f'_{k}'}.stl"
            k += 1
            target = self.folder / name
            if name.lower() in self.taken or (target.exists() and target.resolve() in self.sources):
                continue
            break
        self.taken.add(name.lower())
        self.folder.mkdir(parents=True, exist_ok=True)
        with atomic_file(target, binary=True) as f:
            f.write(stl_bytes(V, F))
        key = str(target.resolve())
        self.written[key] = f"{self.rel}/{name}"
        return key


def _with(shape: Shape, kind: str, size, filename: str | None, pose: np.ndarray | None = None,
          name: str | None = None) -> Shape:
    from ..body_parts import Geometry

    return replace(shape, geometry=Geometry(kind, tuple(float(x) for x in size), filename),
                   pose=shape.pose if pose is None else pose, origin=None if pose is not None else shape.origin,
                   name=name if name is not None else shape.name)


def _transform(T: np.ndarray, V: np.ndarray) -> np.ndarray:
    return V @ T[:3, :3].T + T[:3, 3]


def collision_geometry(robot: Robot, mode: str, *, source: str | None, out_dir: Path | None,
                       mesh_dir: str = "meshes", package_paths: Mapping[str, Path] | None = None,
                       max_faces: int = DEFAULT_MAX_FACES) -> Collision:
    """The robot with its collision shapes made for ``mode`` (see the module doc).

    Parameters
    ----------
    robot : Robot
        Read from ``source`` (its mesh names are found from there).
    mode : one of ``MODES``
    source : path or None
        The robot file (None: a robot without mesh files).
    out_dir : Path or None
        The output's folder; new mesh files go under ``out_dir/mesh_dir/collision``. None: modes that
        write meshes (hull, decompose, a decimated or flat source mesh) need it (ValueError).
    mesh_dir : str
        The meshes' folder under ``out_dir`` (as the MJCF writer names it).
    package_paths : mapping of package name to folder, optional
        Where ``package://NAME/...`` meshes are (``--package-path NAME=DIR``).
    max_faces : int
        The face budget of a written mesh.
    """
    if mode not in MODES:
        raise ValueError(f"collision mode {mode!r}: one of {', '.join(MODES)}")
    start = time.perf_counter()
    bodies = robot.bodies
    others = [s for s in bodies.shapes if s.role != "collision"]
    shapes = [s for s in bodies.shapes if s.role == "collision"]
    result = Collision(robot)
    if mode == "source" and not any(s.geometry.kind == "mesh" for s in shapes):
        return result
    paths: dict[str, Path] = {}
    if source is not None and any(s.geometry.kind == "mesh" for s in shapes):
        from ..io.meshes.files import resolve_meshes

        only = robot.replace(bodies=replace(bodies, shapes=tuple(shapes)))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the writer says which meshes it cannot find, once
            paths = {k: m.path for k, m in resolve_meshes(only, source, package_paths).items() if m.path is not None}
    result.meshes_in = len({(paths.get(s.geometry.filename or ""), s.geometry.size) for s in shapes
                            if s.geometry.kind == "mesh" and s.geometry.filename in paths})
    writer = _Writer(out_dir, mesh_dir, set(paths.values())) if out_dir is not None and mode != "none" else None
    meshes: dict[tuple[Path, tuple[float, ...]], tuple[np.ndarray, np.ndarray] | None] = {}
    made: dict[tuple, list[tuple[str, tuple, str | None, np.ndarray | None]]] = {}  # per mesh: new geometries

    def mesh_of(s: Shape) -> tuple[np.ndarray, np.ndarray] | None:
        path = paths.get(s.geometry.filename or "")
        if path is None:
            return None
        key = (path, tuple(s.geometry.size))
        if key not in meshes:
            try:
                meshes[key] = read_mesh(path, s.geometry.size)
            except MeshError as exc:
                meshes[key] = None
                result.unread.append(f"{path.name} ({exc})")
        return meshes[key]

    def need_writer() -> _Writer:
        if writer is None:
            raise ValueError(f"--collision {mode}: writes mesh files, which needs an output folder (-o)")
        return writer

    new: list[Shape] = []
    if mode == "primitives":
        new = _primitives(robot, shapes, mesh_of, result)
    elif mode != "none":
        for s in shapes:
            data = mesh_of(s) if s.geometry.kind == "mesh" else None
            if data is None:  # a primitive, or a mesh not found or unreadable: as the source gave it
                new.append(s)
                continue
            V, F = data
            key = (paths[s.geometry.filename or ""], tuple(s.geometry.size))
            stem = paths[s.geometry.filename or ""].stem
            if key not in made:
                made[key] = _convert(mode, V, F, stem, need_writer, max_faces, result)
            for kind, size, file, local in made[key]:
                pose = None if local is None else s.pose @ local
                new.append(s if kind == "keep" else _with(s, kind, size, file, pose))
    result.robot = robot.replace(bodies=replace(bodies, shapes=tuple(others) + tuple(new)))
    result.premade = dict(writer.written) if writer is not None else {}
    result.meshes_out = len(result.premade)
    result.primitives_out = sum(1 for s in new if s.geometry.kind != "mesh")
    result.seconds = time.perf_counter() - start
    return result


def _convert(mode: str, V: np.ndarray, F: np.ndarray, stem: str, need_writer, max_faces: int,
             result: Collision) -> list[tuple[str, tuple, str | None, np.ndarray | None]]:
    """The new geometries of one mesh: [(kind or 'keep', size, written file, pose in the shape's frame)]."""
    if is_flat(V[np.unique(F)]):
        T, size = flat_box(V[np.unique(F)])
        result.flat.append(stem)
        return [("box", tuple(size), None, T)]
    one = (1.0, 1.0, 1.0)
    if mode == "source":
        if len(F) <= max_faces:
            return [("keep", (), None, None)]
        result.decimated.append(stem)
        Vd, Fd = decimate(V, F, max_faces)
        result.faces_out += len(Fd)
        return [("mesh", one, need_writer().write(f"{stem}_{len(Fd)}", Vd, Fd), np.eye(4))]
    if mode == "hull":
        hv, hf = convex_hull(V)
        if len(hf) > max_faces:
            hv, hf = decimate(hv, hf, max_faces)
            hv, hf = convex_hull(hv)
        result.faces_out += len(hf)
        return [("mesh", one, need_writer().write(f"{stem}_hull", hv, hf), np.eye(4))]
    from .decompose import decompose

    from .decompose import cached_fit, remember_fit
    from .decompose_fit import DecompositionReport, decomposition_report

    parts, cached = decompose(V, F)
    result.cached += int(cached)
    hulls = [convex_hull(pv) for pv, _ in parts if not is_flat(pv)]  # a part's hull drops stray inner vertices
    if not hulls:
        return [("keep", (), None, None)]
    known = cached_fit(V, F, len(hulls)) if cached else None
    if known is not None:
        result.decompositions.append(DecompositionReport(stem, len(hulls), float(known[1]), float(known[2]),
                                                         "mesh" if known[3] else "hull", float(known[4])))
    else:
        report = decomposition_report(stem, V, F, hulls)
        result.decompositions.append(report)
        remember_fit(V, F, (report.parts, report.volume_error, report.hull_volume_error,
                            float(report.reference == "mesh"), report.hausdorff))
    out = []
    for k, (hv, hf) in enumerate(hulls):
        result.faces_out += len(hf)
        out.append(("mesh", one, need_writer().write(f"{stem}_part{k}", hv, hf), np.eye(4)))
    return out


def _primitives(robot: Robot, shapes: list[Shape], mesh_of, result: Collision) -> list[Shape]:
    """One fitted primitive per link that has collision shapes (see ``primitives``)."""
    from ..body_parts import Geometry, Shape
    from .primitives import fit_primitive, fit_report
    from .tessellate import primitive_mesh

    links = {ln.name: ln for ln in robot.bodies.links}
    by_link: dict[tuple[str, int], list[tuple[np.ndarray, np.ndarray]]] = {}
    for s in shapes:
        g = s.geometry
        if g.kind == "mesh":
            data = mesh_of(s)
            if data is None:
                continue
            V, F = data
            used = V[np.unique(F)]
            if is_flat(used):
                T, size = flat_box(used)
                hv, hf = primitive_mesh("box", size)
                hv = _transform(T, hv)
            else:
                hv, hf = convex_hull(used)
        else:
            hv, hf = primitive_mesh(g.kind, g.size)
        by_link.setdefault((s.link, s.body), []).append((_transform(s.pose, hv), hf))
    out = []
    for (link, body), hulls in by_link.items():
        axes = links[link].pose[:3, :3] if link in links else None
        prim = fit_primitive(np.vstack([v for v, _ in hulls]), axes)
        result.fits.append(fit_report(link, prim, hulls))
        out.append(Shape(link=link, body=body, role="collision", pose=prim.pose,
                         geometry=Geometry(prim.kind, prim.size), name=f"{link}_collision"))  # type: ignore[arg-type]
    return out
