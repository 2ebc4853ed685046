"""The vertices and triangles of an MJCF mesh asset, as MuJoCo reads them, for its mass (``geom_mass``).

A ``<mesh>`` gives its points in a file (binary or ASCII STL, Wavefront OBJ) or in its own ``vertex``
(and ``face``) attributes. Vertices are float32, as MuJoCo stores them; then, in double precision and
in MuJoCo's order, ``refpos`` is subtracted, ``refquat`` undone and ``scale`` applied; a scale with a
negative product turns every triangle over (MuJoCo keeps the mesh outward). A polygon of an OBJ file
becomes a fan of triangles. MuJoCo's own binary ``.msh`` is not read (``InputError``).

Files are untrusted: found through ``robkin.io.meshes.files`` (mesh suffixes only, at most
``MAX_MESH_BYTES``), and a file that is not a mesh of its kind is refused with one line naming it.
"""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np

from ...errors import InputError

__all__ = ["mesh_points", "read_mesh_file", "transformed"]

#: Most triangles read from one file (Menagerie's and dm_control's largest meshes have ~200 000).
MAX_TRIANGLES = 5_000_000


def _stl(data: bytes, where: str) -> tuple[np.ndarray, np.ndarray]:
    if len(data) >= 84:
        count = struct.unpack_from("<I", data, 80)[0]
        if 84 + 50 * count == len(data):  # binary: the size says so (an ASCII file may also start 'solid')
            if count > MAX_TRIANGLES:
                raise InputError(f"{where}: more than {MAX_TRIANGLES} triangles")
            rec = np.frombuffer(data, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]),
                                count=count, offset=84)
            v = rec["v"].reshape(-1, 3)
            return v, np.arange(len(v), dtype=np.intp).reshape(-1, 3)
    text = data.decode("ascii", errors="replace")
    if not text.lstrip().lower().startswith("solid"):
        raise InputError(f"{where}: not an STL file (neither binary nor ASCII)")
    pts = []
    for line in text.splitlines():
        parts = line.split()
        if parts and parts[0].lower() == "vertex":
            try:
                pts.append([float(x) for x in parts[1:4]])
            except ValueError:
                raise InputError(f"{where}: '{line.strip()[:60]}' is not a vertex") from None
    if len(pts) % 3 or len(pts) > 3 * MAX_TRIANGLES:
        raise InputError(f"{where}: {len(pts)} vertices do not make whole triangles (or are too many)")
    v = np.array(pts, dtype=np.float32).reshape(-1, 3)
    return v, np.arange(len(v), dtype=np.intp).reshape(-1, 3)


def _obj(data: bytes, where: str) -> tuple[np.ndarray, np.ndarray]:
    verts: list[list[float]] = []
    faces: list[tuple[int, int, int]] = []
    for number, raw in enumerate(data.decode("utf-8", errors="replace").splitlines(), 1):
        parts = raw.split()
        if not parts:
            continue
        try:
            if parts[0] == "v":
                verts.append([float(x) for x in parts[1:4]])
            elif parts[0] == "f":
                idx = []
                for p in parts[1:]:
                    i = int(p.split("/")[0])
                    idx.append(i - 1 if i > 0 else len(verts) + i)
                faces.extend((idx[0], idx[k], idx[k + 1]) for k in range(1, len(idx) - 1))
        except ValueError:
            raise InputError(f"{where}: line {number}: '{raw.strip()[:60]}' cannot be read") from None
        if len(faces) > MAX_TRIANGLES:
            raise InputError(f"{where}: more than {MAX_TRIANGLES} triangles")
    v = np.array(verts, dtype=np.float32).reshape(-1, 3)
    f = np.array(faces, dtype=np.intp).reshape(-1, 3)
    if len(f) and (f.min() < 0 or f.max() >= len(v)):
        raise InputError(f"{where}: a face names a vertex the file does not have")
    return v, f


def read_mesh_file(path: Path, where: str) -> tuple[np.ndarray, np.ndarray]:
    """(float32 vertices (nv, 3), triangles (nf, 3)) of an STL or OBJ file."""
    from ..meshes.files import MAX_MESH_BYTES

    suffix = path.suffix.lower()
    if suffix not in (".stl", ".obj"):
        raise InputError(f"{where}: {path.name}: only STL and OBJ meshes are read for their mass (MuJoCo's "
                         f".msh is not)")
    with open(path, "rb") as fh:
        data = fh.read(MAX_MESH_BYTES + 1)
    if len(data) > MAX_MESH_BYTES:
        raise InputError(f"{where}: {path.name} is larger than {MAX_MESH_BYTES // 2 ** 20} MB")
    return _stl(data, where) if suffix == ".stl" else _obj(data, where)


def mesh_points(vertex: str | None, face: str | None, where: str) -> tuple[np.ndarray, np.ndarray]:
    """(float32 vertices, triangles) of a mesh given by its ``vertex`` and ``face`` attributes."""
    try:
        v = np.array([float(x) for x in (vertex or "").split()], dtype=np.float32)
        f = np.array([int(x) for x in (face or "").split()], dtype=np.intp)
    except ValueError:
        raise InputError(f"{where}: vertex or face holds something that is not a number") from None
    if len(v) % 3 or len(f) % 3 or len(v) < 12:
        raise InputError(f"{where}: vertex needs at least 4 points of 3 numbers and face whole triangles")
    v, f = v.reshape(-1, 3), f.reshape(-1, 3)
    if len(f) and (f.min() < 0 or f.max() >= len(v)):
        raise InputError(f"{where}: a face names a vertex the mesh does not have")
    return v, f


def transformed(v32: np.ndarray, f: np.ndarray, scale: tuple[float, ...], refpos: tuple[float, ...],
                refquat: tuple[float, ...]) -> tuple[np.ndarray, np.ndarray]:
    """The vertices in double precision with MuJoCo's ``refpos``, ``refquat`` and ``scale`` applied, and the
    triangles (turned over when the scale mirrors the mesh)."""
    v = v32.astype(float) - np.asarray(refpos, dtype=float)
    if tuple(refquat) != (1.0, 0.0, 0.0, 0.0):
        w, x, y, z = np.asarray(refquat, dtype=float) / np.linalg.norm(refquat)
        R = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                      [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                      [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
        v = v @ R                                          # R^T v for each vertex: refquat undone
    v = v * np.asarray(scale, dtype=float)
    if scale[0] * scale[1] * scale[2] < 0:
        f = f[:, [0, 2, 1]]
    return v, f
