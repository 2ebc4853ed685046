"""The solid mass properties of a link's collision geometry (its visual one when it has none), per unit density.

Meshes are found and read once per file (``MeshCache``: ``io.meshes.files.resolve_mesh_file``, then
``collision.mesh_data.read_mesh``, the same rules as ``convert``: nothing else is read). A closed mesh
counts with its own volume; an open one with its convex hull's (said by ``asset_checks``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping

import numpy as np

from .urdf_source import Geometry, RawLink

__all__ = ["MeshCache", "Solid", "link_solid"]


@dataclass
class MeshRead:
    path: Path | None
    reason: str | None
    V: np.ndarray | None = None
    F: np.ndarray | None = None
    closed: bool = False
    solids: dict = field(default_factory=dict)   # scale -> (volume, centre, inertia, lo, hi) or None


def is_closed(F: np.ndarray, nv: int) -> bool:
    """Every undirected edge shared by exactly two triangles (one int64 key per edge: a sort of 3m numbers)."""
    e = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    e.sort(axis=1)
    _, counts = np.unique(e[:, 0].astype(np.int64) * (nv + 1) + e[:, 1], return_counts=True)
    return bool(len(counts)) and bool(np.all(counts == 2))


class MeshCache:
    """Mesh file name (as written) -> where it is and its triangles (unscaled), read at most once."""

    def __init__(self, source_file: str, package_paths: Mapping[str, Path] | None = None):
        self.source_file, self.package_paths = source_file, dict(package_paths or {})
        self._cache: dict[str, MeshRead] = {}
        self._summaries: dict[str, tuple] = {}

    def found(self, filename: str) -> MeshRead:
        """Where the mesh is (or why not), without reading it (a read one's triangles are kept)."""
        if filename in self._cache:
            return self._cache[filename]
        from ..io.meshes.files import resolve_mesh_file

        found = resolve_mesh_file(filename, self.source_file, self.package_paths)
        return MeshRead(found.path, found.reason)

    def summary(self, filename: str):
        """(where the mesh is or why not, its ``mesh_summary.MeshSummary`` or None): a COLLADA file summed up
        from its XML, any other read whole (``get``)."""
        if filename in self._summaries:
            return self._summaries[filename]
        from .mesh_summary import MeshSummary, dae_summary

        r = self._cache.get(filename) or self.found(filename)
        got = None
        if r.path is not None and r.V is None and r.path.suffix.lower() == ".dae" and filename not in self._cache:
            try:
                got = dae_summary(r.path)
            except (ValueError, OSError) as exc:
                r = MeshRead(r.path, f"unreadable ({exc})")
        elif r.path is not None:
            r = self.get(filename)
            if r.V is not None and r.F is not None:
                got = MeshSummary(len(r.F), r.V.min(axis=0), r.V.max(axis=0))
        self._summaries[filename] = (r, got)
        return r, got

    def get(self, filename: str) -> MeshRead:
        if filename not in self._cache:
            from ..collision.mesh_data import MeshError, read_mesh
            from ..io.meshes.files import resolve_mesh_file

            found = resolve_mesh_file(filename, self.source_file, self.package_paths)
            r = MeshRead(found.path, found.reason)
            if found.path is not None:
                try:
                    r.V, r.F = read_mesh(found.path)
                    r.closed = is_closed(r.F, len(r.V))
                except (MeshError, OSError) as exc:
                    r.reason = f"unreadable ({exc})"
            self._cache[filename] = r
        return self._cache[filename]


@dataclass
class Solid:
    """Volume (m^3), centre (3,) in the link frame, inertia (3, 3) per unit density about the centre, link
    axes; ``extent`` the bounding box (lo, hi) of the geometry in the link frame."""

    volume: float
    centre: np.ndarray
    inertia: np.ndarray
    lo: np.ndarray
    hi: np.ndarray


def _primitive(g: Geometry) -> tuple[float, np.ndarray, np.ndarray, np.ndarray] | None:
    """(volume, unit-density inertia about the centre in the shape's axes, box lo, hi) of a primitive."""
    from ..io.mjcf.geom_inertia import primitive_measure, primitive_moments

    if g.size is None or min(g.size[:1]) < 0:
        return None
    vol = primitive_measure(g.kind, g.size, False)
    moments = primitive_moments(g.kind, g.size, vol, False)
    s = g.size
    half = {"box": np.array(s), "cylinder": np.array([s[0], s[0], s[1]]), "sphere": np.full(3, s[0]),
            "capsule": np.array([s[0], s[0], s[1] + s[0]])}[g.kind]
    return vol, np.diag(moments), -half, half


def _mesh(g: Geometry, meshes: MeshCache) -> tuple[float, np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None:
    """(volume, centre, unit-density inertia about it, lo, hi) of a mesh in its own frame, scale applied."""
    from ..io.mjcf.geom_inertia import mesh_mass

    if not g.filename:
        return None
    r = meshes.get(g.filename)
    if r.V is None or r.F is None:
        return None
    if g.scale not in r.solids:
        V = r.V * np.asarray(g.scale)
        try:
            mm = mesh_mass(V, r.F if r.closed else np.zeros((0, 3), dtype=np.int64), "exact")
            r.solids[g.scale] = (mm.measure, mm.centre, mm.inertia, V.min(axis=0), V.max(axis=0))
        except Exception:  # MuJoCo's refusals (ValueError), qhull's on flat point sets (QhullError)
            r.solids[g.scale] = None
    return r.solids[g.scale]


def _box(g: Geometry, meshes: MeshCache) -> tuple[np.ndarray, np.ndarray] | None:
    """Bounding box (lo, hi) of a shape in the link frame (its box's corners moved by the shape's pose)."""
    if g.kind == "mesh":
        got = _mesh(g, meshes)
        if got is None:
            return None
        a, b = got[3], got[4]
    else:
        p = _primitive(g)
        if p is None:
            return None
        a, b = p[2], p[3]
    R, t = g.pose[:3, :3], g.pose[:3, 3]
    corners = np.array([[x, y, z] for x in (a[0], b[0]) for y in (a[1], b[1]) for z in (a[2], b[2])]) @ R.T + t
    return corners.min(axis=0), corners.max(axis=0)


def link_solid(link: RawLink, meshes: MeshCache) -> Solid | None:
    """The solid of ``link``'s collision shapes (visual ones when it has none); None without usable shapes.
    Its box (``lo``, ``hi``) holds the same shapes."""
    shapes = [g for g in link.geometries if g.role == "collision"] or [g for g in link.geometries if g.role == "visual"]
    parts = []
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    for g in shapes:
        box = _box(g, meshes)
        if box is not None:
            lo, hi = np.minimum(lo, box[0]), np.maximum(hi, box[1])
    for g in shapes:
        if g.kind == "mesh":
            got = _mesh(g, meshes)
            if got is None:
                return None
            vol, c, I = got[0], got[1], got[2]
        else:
            p = _primitive(g)
            if p is None:
                return None
            vol, I, c = p[0], p[1], np.zeros(3)
        R, t = g.pose[:3, :3], g.pose[:3, 3]
        parts.append((vol, R @ c + t, R @ I @ R.T))
    if not parts:
        return None
    total = sum(p[0] for p in parts)
    if total <= 0:
        return Solid(0.0, (lo + hi) / 2, np.zeros((3, 3)), lo, hi)
    centre = sum(p[0] * p[1] for p in parts) / total
    inertia = np.zeros((3, 3))
    for vol, c, I in parts:
        d = c - centre
        inertia += I + vol * (d @ d * np.eye(3) - np.outer(d, d))
    return Solid(total, centre, inertia, lo, hi)
