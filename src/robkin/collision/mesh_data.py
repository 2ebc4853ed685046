"""Triangle meshes as arrays: read from a mesh file (untrusted), written as binary STL.

``read_mesh(path, scale)`` gives (V, F): vertices (k, 3) float64 in the shape's own frame with the
source's scale applied, faces (m, 3) int64. A binary STL is read with NumPy (its header's triangle count
checked against the file size before anything is allocated); other formats (OBJ, COLLADA, PLY, ASCII
STL) through trimesh from the file's bytes, without a resolver (no other file is read; COLLADA's unit
applied), which needs ``pip install 'robkin[meshes]'``. The files are at most
``io.meshes.files.MAX_MESH_BYTES``, as the resolver finds them; a mesh with more than
``MAX_READ_FACES`` triangles, a NaN or infinite coordinate or no triangle is refused with a
``MeshError`` whose message is one short reason.
"""

from __future__ import annotations

import io
import struct
from pathlib import Path
from typing import Sequence

import numpy as np

__all__ = ["MeshError", "read_mesh", "stl_bytes", "MAX_READ_FACES"]

#: Most triangles read from one file (a 64 MB binary STL holds 1.3 M; 4 M bounds what trimesh builds
#: from a text format of the same size). Above it the mesh is refused, not decimated: reading it is the cost.
MAX_READ_FACES = 4_000_000


class MeshError(ValueError):
    """A mesh file that cannot be used here; the message is a short reason (no file name)."""


def _binary_stl(data: bytes) -> tuple[np.ndarray, np.ndarray] | None:
    """(V, F) of a binary STL, or None when ``data`` is not one (an ASCII STL)."""
    if len(data) < 84:
        return None
    n = struct.unpack("<I", data[80:84])[0]
    if len(data) != 84 + 50 * n:
        return None
    if n > MAX_READ_FACES:
        raise MeshError(f"{n} triangles (more than {MAX_READ_FACES} are not read)")
    rec = np.frombuffer(data, dtype=np.dtype([("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]),
                        count=n, offset=84)
    tri = rec["v"].astype(np.float64).reshape(-1, 3)
    # shared corners merged (exact float equality, as STL writers repeat them bit for bit)
    V, F = np.unique(tri, axis=0, return_inverse=True)
    return V, F.reshape(-1, 3).astype(np.int64)


def _with_trimesh(data: bytes, kind: str) -> tuple[np.ndarray, np.ndarray]:
    try:
        import trimesh
    except ImportError:
        raise MeshError(f"reading .{kind} needs trimesh: pip install 'robkin[meshes]'") from None
    from ..io.meshes.convert import _collada_unit

    try:
        scene = trimesh.load(io.BytesIO(data), file_type=kind, force="scene")
        mesh = scene.to_geometry() if hasattr(scene, "to_geometry") else scene.dump(concatenate=True)
        unit = _collada_unit(getattr(scene, "units", None)) if kind == "dae" else 1.0
        V = np.asarray(mesh.vertices, dtype=np.float64) * unit
        F = np.asarray(mesh.faces, dtype=np.int64)
    except MeshError:
        raise
    except Exception as exc:  # noqa: BLE001 - a third-party parser on an untrusted file
        raise MeshError(f"cannot be read ({(str(exc) or type(exc).__name__)[:80]})") from None
    return V, F


def read_mesh(path: str | Path, scale: Sequence[float] = (1.0, 1.0, 1.0)) -> tuple[np.ndarray, np.ndarray]:
    """(V, F) of the mesh file ``path`` with ``scale`` applied (see the module doc); MeshError if unusable."""
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise MeshError(f"cannot be read ({exc.strerror or exc})") from None
    kind = path.suffix.lower().lstrip(".")
    got = _binary_stl(data) if kind == "stl" else None
    V, F = got if got is not None else _with_trimesh(data, kind)
    if len(F) == 0:
        raise MeshError("no triangles")
    if len(F) > MAX_READ_FACES:
        raise MeshError(f"{len(F)} triangles (more than {MAX_READ_FACES} are not read)")
    if not np.isfinite(V).all():
        raise MeshError("a vertex coordinate is NaN or infinite")
    if F.min() < 0 or F.max() >= len(V):
        raise MeshError("a face names a vertex that does not exist")
    return V * np.asarray(scale, dtype=np.float64), F


def stl_bytes(V: np.ndarray, F: np.ndarray) -> bytes:
    """Binary STL of the triangles (V[F]), with their normals (zero for a degenerate triangle)."""
    tri = np.asarray(V, dtype=np.float64)[np.asarray(F)]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    length = np.linalg.norm(normal, axis=1, keepdims=True)
    normal = np.divide(normal, length, out=np.zeros_like(normal), where=length > 0)
    rec = np.zeros(len(tri), dtype=np.dtype([("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]))
    rec["normal"] = normal
    rec["v"] = tri
    return b"robkin".ljust(80, b" ") + struct.pack("<I", len(tri)) + rec.tobytes()
