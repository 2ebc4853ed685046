"""Mesh files read into points and triangles, to be written inline in a USD file.

A USD file robkin writes stands alone: its meshes are ``UsdGeom.Mesh`` prims holding the points and
triangles of the source's mesh files, not references to them (which a reader would have to resolve,
and robkin's own reader does not follow). The files are found as for the MJCF and URDF exports
(``io.meshes.files``: ``package://``, ``model://``, relative paths) and parsed by trimesh
(``pip install 'robkin[meshes]'``) from their bytes, without a resolver (a COLLADA file's textures or
other files it names are never read), COLLADA's unit applied. Any failure leaves that mesh out, said in
one warning line for all of them.
"""

from __future__ import annotations

import io
from pathlib import Path
from typing import Mapping

import numpy as np

__all__ = ["MeshData", "read_meshes", "MAX_TRIANGLES"]

#: Triangles read from one mesh file: a visual mesh of 2 million triangles is already ~50 MB of USD text.
MAX_TRIANGLES = 2_000_000


class MeshData:
    """Points (N, 3) float and triangles (M, 3) int of one mesh file, in metres."""

    __slots__ = ("points", "triangles")

    def __init__(self, points: np.ndarray, triangles: np.ndarray) -> None:
        self.points, self.triangles = points, triangles


def _read(path: Path) -> MeshData:
    import trimesh

    from ..meshes.convert import _collada_unit

    kind = path.suffix.lower().lstrip(".")
    scene = trimesh.load(io.BytesIO(path.read_bytes()), file_type=kind, force="scene")
    mesh = scene.to_geometry() if hasattr(scene, "to_geometry") else scene.dump(concatenate=True)
    unit = _collada_unit(getattr(scene, "units", None)) if kind == "dae" else 1.0
    points = np.asarray(mesh.vertices, dtype=float) * unit
    triangles = np.asarray(mesh.faces, dtype=np.int64)
    if len(triangles) == 0:
        raise ValueError("no triangles")
    if len(triangles) > MAX_TRIANGLES:
        raise ValueError(f"{len(triangles)} triangles, more than {MAX_TRIANGLES}")
    return MeshData(points, triangles)


def read_meshes(files: Mapping[str, Path]) -> tuple[dict[str, MeshData], list[str]]:
    """(mesh file name as the source wrote it -> its data, the files left out with why)."""
    out: dict[str, MeshData] = {}
    left: list[str] = []
    if not files:
        return out, left
    try:
        import trimesh  # noqa: F401
    except ImportError:
        return out, [f"{len(files)} mesh file(s) (reading meshes needs trimesh: pip install 'robkin[meshes]')"]
    for name, path in files.items():
        try:
            out[name] = _read(path)
        except Exception as exc:  # noqa: BLE001 - any failure of a third-party parser on an untrusted file
            text = (str(exc) or type(exc).__name__).splitlines()[0][:80]
            left.append(f"{path.name} ({text})")
    return out, left
