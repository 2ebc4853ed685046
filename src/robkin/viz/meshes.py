"""The visuals (meshes and primitive shapes) the GUI draws for a robot given on the command line.

A URDF (or MJCF, SDF) names its meshes by file name: ``package://pkg/path/link.stl``, a path relative
to the file (an MJCF's already joined with its ``meshdir``), SDF's ``model://name/path``, or
``file:///abs/path``. :func:`resolve_mesh` finds such a file the way ROS does:
``package://pkg/...`` in a folder named ``pkg`` above the robot file or on ``ROS_PACKAGE_PATH``.

The server never opens a path that comes from a request: :class:`MeshRegistry` is built once, when
the GUI starts, from the visuals of the robot file given on the command line; it assigns each mesh
file an id (``m0``, ``m1``, ...), and ``GET /api/mesh/<id>`` serves only those files, only with a
mesh extension (.stl, .dae, .obj), and only up to a size cap. A robot pasted or loaded in the page
is drawn as the stick figure.

The visuals come from ``robot.bodies`` (shapes with their pose at home in the base frame and the
body they move with); a robot without them has no visuals.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any
from urllib.parse import unquote, urlparse

from ..robot import Robot

__all__ = ["MESH_TYPES", "MAX_MESH_BYTES", "MAX_MESHES", "resolve_mesh", "MeshRegistry"]

#: Mesh file suffix -> MIME type; the page has a three.js loader for each.
MESH_TYPES = {".stl": "model/stl", ".dae": "model/vnd.collada+xml", ".obj": "model/obj"}
#: Largest mesh file served (a detailed arm link is a few MB; this bounds memory per request).
MAX_MESH_BYTES = 64 * 1024 * 1024
#: Most mesh files one robot may reference (a humanoid has about a hundred visuals).
MAX_MESHES = 1000


#: Where each URI scheme's first component is looked up besides the folders above the robot file: ROS
#: packages, and Gazebo's models (SDF ``model://NAME/...``).
SEARCH_PATHS = {"package": ("ROS_PACKAGE_PATH",), "model": ("GZ_SIM_RESOURCE_PATH", "GAZEBO_MODEL_PATH")}


def _package_roots(package: str, robot_file: Path, variables: tuple[str, ...]) -> list[Path]:
    """Folders that may be package (or model) ``package``: named so, above the robot file or on the
    search path environment ``variables``."""
    roots = [d for d in robot_file.resolve().parents if d.name == package]
    for entry in (e for var in variables for e in os.environ.get(var, "").split(os.pathsep)):
        if entry:
            base = Path(entry)
            roots += [base] if base.name == package else [base / package]
    return roots


def resolve_mesh(filename: str, robot_file: Path) -> Path | None:
    """The mesh file a robot file names, or None if it is not found or not a served mesh type.

    Parameters
    ----------
    filename : str
        As written in the robot file: ``package://pkg/rel``, ``model://name/rel`` (SDF; in a folder
        ``name`` above the file or on GZ_SIM_RESOURCE_PATH / GAZEBO_MODEL_PATH), ``file:///abs``, or
        a relative path.
    robot_file : Path
        The robot file (relative names are relative to its folder).
    """
    url = urlparse(filename)
    if url.scheme in SEARCH_PATHS:
        rel = unquote(url.path).lstrip("/")
        candidates = [root / rel for root in _package_roots(url.netloc, robot_file, SEARCH_PATHS[url.scheme])]
    elif url.scheme == "file":
        candidates = [Path(unquote(url.path))]
    elif url.scheme == "" or len(url.scheme) == 1:  # a plain path (a Windows drive letter parses as a scheme)
        p = Path(filename)
        candidates = [p if p.is_absolute() else robot_file.resolve().parent / p]
    else:
        return None  # http:// and friends: nothing is fetched
    for c in candidates:
        if c.suffix.lower() in MESH_TYPES and c.is_file():
            return c.resolve()
    return None


@dataclass
class MeshRegistry:
    """Mesh files the page may fetch (by id) and the visuals to draw, for one robot file.

    ``visuals`` is JSON-ready: one dict per visual shape with ``body`` (0 = base, i = moves with
    joint i), ``pose`` (4x4, at home in the base frame), ``kind`` (mesh/box/cylinder/sphere),
    ``size``, ``rgba`` (or None) and, for meshes, ``mesh`` (the id) and ``format`` (stl/dae/obj).
    Meshes that cannot be found are listed in ``missing`` (the page says so) and not drawn.
    """

    files: dict[str, Path] = field(default_factory=dict)
    visuals: list[dict[str, Any]] = field(default_factory=list)
    missing: list[str] = field(default_factory=list)

    @classmethod
    def of(cls, robot: Robot, robot_file: Path) -> "MeshRegistry":
        reg = cls()
        bodies = getattr(robot, "bodies", None)
        shapes = bodies.visuals() if bodies else ()
        ids: dict[Path, str] = {}
        for s in shapes:
            g = s.geometry
            item: dict[str, Any] = {"body": s.body, "pose": s.pose.tolist(), "kind": g.kind,
                                    "size": list(g.size), "rgba": list(s.material.rgba) if s.material and
                                    s.material.rgba else None}
            if g.kind == "mesh":
                path = resolve_mesh(g.filename or "", robot_file)
                if path is None or path.stat().st_size > MAX_MESH_BYTES:
                    reg.missing.append(g.filename or "")
                    continue
                if path not in ids:
                    if len(ids) >= MAX_MESHES:
                        reg.missing.append(g.filename or "")
                        continue
                    ids[path] = f"m{len(ids)}"
                    reg.files[ids[path]] = path
                item.update(mesh=ids[path], format=path.suffix.lower().lstrip("."))
            reg.visuals.append(item)
        return reg

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
