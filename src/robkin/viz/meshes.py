"""The visuals (meshes and primitive shapes) the GUI and ``plot -o page.html`` draw for a robot file.

A URDF (or MJCF, SDF) names its meshes by file name; :func:`robkin.io.meshes.files.resolve_meshes`
finds them (``package://``, ``model://``, ``file://``, relative paths, ``--package-path``) and says
why one cannot be used.

The server never opens a path that comes from a request: :class:`MeshRegistry` is built once, when
the GUI starts, from the visuals of the robot file given on the command line; it assigns each mesh
file an id (``m0``, ``m1``, ...), and ``GET /api/mesh/<id>`` serves only those files, only with a
format the page draws (.stl, .dae, .obj), and only up to a size cap. A robot pasted or loaded in the
page is drawn as the stick figure.

The visuals come from ``robot.bodies`` (shapes with their pose at home in the base frame and the
body they move with); a robot without them has no visuals.
"""

from __future__ import annotations

import base64
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

from ..io.meshes.files import MAX_MESH_BYTES, MAX_MESHES, MeshFile, missing_line, resolve_meshes
from ..robot import Robot

__all__ = ["MESH_TYPES", "MAX_MESH_BYTES", "MAX_MESHES", "MAX_PAGE_MESH_BYTES", "MeshRegistry"]

#: Mesh file suffix -> MIME type; the page has a three.js loader for each.
MESH_TYPES = {".stl": "model/stl", ".dae": "model/vnd.collada+xml", ".obj": "model/obj"}
#: Most mesh bytes embedded in one self-contained page (``plot -o page.html``): a browser holds a page
#: of this size comfortably; a robot with more is drawn with the meshes that fit.
MAX_PAGE_MESH_BYTES = 128 * 1024 * 1024


@dataclass
class MeshRegistry:
    """Mesh files the page may fetch (by id) and the visuals to draw, for one robot file.

    ``visuals`` is JSON-ready: one dict per visual shape with ``body`` (0 = base, i = moves with
    joint i), ``link`` (its link's name), ``pose`` (4x4, at home in the base frame), ``kind`` (mesh/box/cylinder/sphere),
    ``size``, ``rgba`` (or None) and, for meshes, ``mesh`` (the id) and ``format`` (stl/dae/obj).
    Meshes that cannot be found are listed in ``missing`` (the page says so) and not drawn.
    """

    files: dict[str, Path] = field(default_factory=dict)
    visuals: list[dict[str, Any]] = field(default_factory=list)
    missing: list[str] = field(default_factory=list)

    #: one line saying which meshes were not found and why (None when all were)
    missing_line: str | None = None

    @classmethod
    def of(cls, robot: Robot, robot_file: Path, package_paths: Mapping[str, Path] | None = None) -> "MeshRegistry":
        """The visuals of ``robot`` (read from ``robot_file``), their mesh files found as
        :func:`robkin.io.meshes.files.resolve_meshes` finds them."""
        reg = cls()
        bodies = getattr(robot, "bodies", None)
        shapes = bodies.visuals() if bodies else ()
        resolved = resolve_meshes(robot, robot_file, package_paths) if shapes else {}
        drawn: dict[str, MeshFile] = {}
        ids: dict[Path, str] = {}
        for s in shapes:
            g = s.geometry
            item: dict[str, Any] = {"body": s.body, "link": s.link, "pose": s.pose.tolist(), "kind": g.kind,
                                    "size": list(g.size), "rgba": list(s.material.rgba) if s.material and
                                    s.material.rgba else None}
            if g.kind == "mesh":
                found = resolved.get(g.filename or "") or MeshFile(g.filename or "", None, "no file name")
                if found.path is not None and found.path.suffix.lower() not in MESH_TYPES:
                    found = MeshFile(found.source, None, f"the viewer draws {', '.join(MESH_TYPES)} files")
                drawn[found.source] = found
                if found.path is None:
                    continue
                ids.setdefault(found.path, f"m{len(ids)}")
                reg.files[ids[found.path]] = found.path
                item.update(mesh=ids[found.path], format=found.path.suffix.lower().lstrip("."))
            reg.visuals.append(item)
        reg.missing = [m.source for m in drawn.values() if m.path is None]
        reg.missing_line = missing_line(drawn, robot_file)
        return reg

    def embedded(self, limit: int = MAX_PAGE_MESH_BYTES) -> tuple[dict[str, str], list[str]]:
        """The mesh files as base64 text by id, for a self-contained page, up to ``limit`` bytes in all;
        and the ids left out (too large together, or gone since)."""
        out: dict[str, str] = {}
        left: list[str] = []
        total = 0
        for mesh_id in self.files:
            found = self.read(mesh_id)
            if found is None or total + len(found[0]) > limit:
                left.append(mesh_id)
                continue
            total += len(found[0])
            out[mesh_id] = base64.b64encode(found[0]).decode("ascii")
        return out, left

    def read(self, mesh_id: str) -> tuple[bytes, str] | None:
        """(bytes, MIME type) of a registered mesh, or None for an unknown id or a file grown too large."""
        path = self.files.get(mesh_id)
        if path is None:
            return None
        try:
            if path.stat().st_size > MAX_MESH_BYTES:
                return None
            return path.read_bytes(), MESH_TYPES[path.suffix.lower()]
        except OSError:
            return None
