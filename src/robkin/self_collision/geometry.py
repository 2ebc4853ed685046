"""The collision geometry of each link, as triangle meshes in the robot base frame at q = 0.

``link_geometry(robot, source, package_paths)`` gathers, per link that has collision shapes, its
body (0..n, ``robkin.bodies``) and its shapes: meshes read from their files (``collision.mesh_data``,
untrusted input, bounded) and primitives kept as primitives. The capsule fit (``capsules``) and the
exact check (``exact``) both start from it. A link whose mesh file cannot be found or read is an
``InputError`` naming the link and the file: a self-collision model that silently left a link out
would answer "free" where the arm hits itself.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Mapping

import numpy as np

from ..errors import InputError, quote

if TYPE_CHECKING:  # pragma: no cover
    from ..robot import Robot

__all__ = ["LinkShape", "LinkGeometry", "link_geometry", "enclosing_points", "enclosing_triangles"]


@dataclass(frozen=True, eq=False)
class LinkShape:
    """One collision shape: ``kind`` ('mesh' or a primitive kind), ``size`` (``Geometry.size``; for a
    mesh the scale already applied), ``pose`` (4, 4) in the base frame at q = 0, and for a mesh its
    vertices (k, 3) and faces (m, 3) in the shape's own frame."""

    kind: str
    size: tuple[float, ...]
    pose: np.ndarray
    vertices: np.ndarray | None = None
    faces: np.ndarray | None = None


@dataclass
class LinkGeometry:
    """A link's collision shapes and the body it moves with."""

    name: str
    body: int
    shapes: list[LinkShape] = field(default_factory=list)


def _ring_scale(kind: str) -> float:
    """How much a tessellated round primitive (``collision.tessellate``, inscribed polygons) must grow to
    enclose the true shape: 1 / cos(pi / SEGMENTS) per direction of tessellation (two for a sphere's and
    a capsule's caps)."""
    from ..collision.tessellate import SEGMENTS

    c = 1.0 / np.cos(np.pi / SEGMENTS)
    return c * c if kind in ("sphere", "capsule") else c


def enclosing_points(shape: LinkShape) -> np.ndarray:
    """Points (k, 3) in the base frame at q = 0 whose convex hull contains ``shape``: a mesh's vertices
    (the mesh lies in their hull), a box's corners, a round primitive's tessellation grown to enclose it."""
    from ..collision.tessellate import primitive_mesh

    if shape.kind == "mesh":
        assert shape.vertices is not None
        V = shape.vertices
    else:
        V, _ = primitive_mesh(shape.kind, shape.size)
        if shape.kind != "box":
            V = V * _ring_scale(shape.kind)
    return V @ shape.pose[:3, :3].T + shape.pose[:3, 3]


def enclosing_triangles(shape: LinkShape) -> np.ndarray:
    """Triangles (m, 3, 3) in the base frame at q = 0 bounding a solid that contains ``shape``: a mesh's
    own, a box's, a round primitive's tessellation grown to enclose it (see ``enclosing_points``)."""
    from ..collision.tessellate import primitive_mesh

    if shape.kind == "mesh":
        assert shape.vertices is not None and shape.faces is not None
        V, F = shape.vertices, shape.faces
    else:
        V, F = primitive_mesh(shape.kind, shape.size)
        if shape.kind != "box":
            V = V * _ring_scale(shape.kind)
    return (V @ shape.pose[:3, :3].T + shape.pose[:3, 3])[F]


def link_geometry(robot: Robot, source: str | Path | None = None,
                  package_paths: Mapping[str, Path] | None = None) -> list[LinkGeometry]:
    """Every link with collision shapes, in the order of ``robot.bodies.links`` (see the module doc).

    Parameters
    ----------
    robot : Robot
    source : path, optional
        The robot file its mesh names are relative to (needed when it has collision meshes).
    package_paths : mapping NAME -> folder, optional
        Folders of ``package://NAME`` meshes, tried first.
    """
    from ..collision.mesh_data import MeshError, read_mesh

    shapes = [s for s in robot.bodies.shapes if s.role == "collision"]
    paths: dict[str, Path | None] = {}
    reasons: dict[str, str] = {}
    if any(s.geometry.kind == "mesh" for s in shapes):
        from ..io.meshes.files import resolve_meshes

        only = robot.replace(bodies=replace(robot.bodies, shapes=tuple(shapes)))
        if source is None:
            raise InputError("collision meshes: the robot's collision shapes are mesh files; give the robot "
                             "file they are named from (source=, or load the model from the file)")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # files outside the robot's folder: used, as the writers do
            for name, m in resolve_meshes(only, source, package_paths).items():
                paths[name] = m.path
                reasons[name] = m.reason or ""
    order = [ln.name for ln in robot.bodies.links]
    out: dict[str, LinkGeometry] = {}
    cache: dict[tuple[object, ...], tuple[np.ndarray, np.ndarray]] = {}
    for s in shapes:
        g = s.geometry
        geo = out.setdefault(s.link, LinkGeometry(s.link, s.body))
        if g.kind != "mesh":
            geo.shapes.append(LinkShape(g.kind, tuple(g.size), np.asarray(s.pose)))
            continue
        path = paths.get(g.filename or "")
        if path is None:
            raise InputError(f"link {quote(s.link)}: collision mesh {quote(g.filename or '')} not found "
                             f"({reasons.get(g.filename or '', 'no file name')}; --package-path NAME=DIR)")
        key = (path, tuple(g.size))
        if key not in cache:
            try:
                cache[key] = read_mesh(path, g.size)
            except MeshError as exc:
                raise InputError(f"link {quote(s.link)}: collision mesh {path.name}: {exc}") from None
        V, F = cache[key]
        geo.shapes.append(LinkShape("mesh", tuple(g.size), np.asarray(s.pose), V, F))
    rank = {name: k for k, name in enumerate(order)}
    return sorted(out.values(), key=lambda g: (rank.get(g.name, len(rank)), g.name))
