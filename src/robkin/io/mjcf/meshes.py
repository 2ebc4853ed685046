"""Mesh files copied beside an MJCF, made loadable by MuJoCo: its STL reader refuses a file of more
than 200 000 triangles (detailed visual meshes converted from COLLADA often have more), its OBJ
reader has no such limit. Such STL files are rewritten as OBJ (trimesh), or left out with one warning.

A mesh file MuJoCo would refuse, failing the whole model, is left out with one warning line naming it,
as a mesh not found is: an empty file, a binary STL whose header promises more (or fewer) triangles than
the file holds (a header claiming 4e9 triangles is never believed, nor read), an ASCII STL (MuJoCo reads
binary STL only), an STL or OBJ with a vertex coordinate that is NaN or infinite or with fewer than
the 4 vertices MuJoCo needs.
"""

from __future__ import annotations

import re
import struct
import warnings
from pathlib import Path
from typing import Mapping

__all__ = ["MUJOCO_STL_MAX_FACES", "fit_for_mujoco"]

#: MuJoCo's limit on the triangles of one STL file (its stl_decoder refuses more).
MUJOCO_STL_MAX_FACES = 200_000


def _stl_faces(path: Path) -> int | None:
    """Triangle count of a binary STL (from its header), or None for an ASCII STL."""
    with open(path, "rb") as f:
        head = f.read(84)
    if len(head) < 84 or head[:5].lower() == b"solid":
        n = struct.unpack("<I", head[80:84])[0] if len(head) == 84 else 0
        # an ASCII file starts with 'solid'; a binary one may too: its size tells
        if len(head) == 84 and path.stat().st_size == 84 + 50 * n:
            return n
        return None
    return int(struct.unpack("<I", head[80:84])[0])


_OBJ_VERTEX = re.compile(rb"(?m)^[ \t]*v[ \t]")
_OBJ_NOT_FINITE = re.compile(rb"(?im)^[ \t]*v[ \t][^\n]*?(nan|inf)")


def malformed(path: Path) -> str | None:
    """Why MuJoCo would refuse the mesh file ``path`` (a short reason), or None when it may load it.
    Reads at most the file (the copies are at most 64 MB, as ``io.meshes.files`` finds them)."""
    try:
        size = path.stat().st_size
        if size == 0:
            return "empty"
        suffix = path.suffix.lower()
        if suffix == ".stl":
            with open(path, "rb") as f:
                head = f.read(84)
            n = struct.unpack("<I", head[80:84])[0] if len(head) == 84 else -1
            if n < 0 or size != 84 + 50 * n:
                if head[:5].lower() == b"solid":
                    return "ASCII STL (MuJoCo reads binary STL only)"
                return (f"truncated or malformed binary STL (the header says {n} triangles, {84 + 50 * n} bytes; "
                        f"the file has {size})" if n >= 0 else f"truncated STL ({size} bytes)")
            if n == 0:
                return "no triangles"
            import numpy as np

            data = np.fromfile(path, dtype=np.dtype([("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]),
                               count=n, offset=84)
            if not np.isfinite(data["v"]).all():
                return "a vertex coordinate is NaN or infinite"
            if len(np.unique(data["v"].reshape(-1, 3)[:4 * 3], axis=0)) < 4 and \
                    len(np.unique(data["v"].reshape(-1, 3), axis=0)) < 4:
                return "fewer than 4 distinct vertices (MuJoCo needs 4)"
        elif suffix == ".obj":
            data = path.read_bytes()
            if sum(1 for _ in zip(range(4), _OBJ_VERTEX.finditer(data))) < 4:
                return "fewer than 4 vertices (MuJoCo needs 4)"
            if _OBJ_NOT_FINITE.search(data):
                return "a vertex coordinate is NaN or infinite"
    except OSError as exc:
        return f"cannot be read ({exc.strerror or exc})"
    return None


def fit_for_mujoco(mesh_files: Mapping[str, str], out_dir: Path, sources: set[Path]) -> dict[str, str]:
    """``mesh_files`` (source name -> file relative to ``out_dir``) with every STL MuJoCo refuses
    rewritten as OBJ beside it (the STL removed unless it is one of the model's own files, ``sources``),
    or left out with one warning line when it cannot be."""
    out = dict(mesh_files)
    done: dict[str, str | None] = {}
    left: list[str] = []
    bad: list[str] = []
    for name, rel in mesh_files.items():
        if rel not in done and (why := malformed(out_dir / rel)) is not None:
            bad.append(f"{rel} ({why})")
            done[rel] = None
            if (out_dir / rel).resolve() not in sources:
                (out_dir / rel).unlink(missing_ok=True)
        if not rel.lower().endswith(".stl") and done.get(rel, rel) is not None:
            continue
        if rel not in done:
            path = out_dir / rel
            faces = _stl_faces(path)
            done[rel] = rel if faces is None or faces <= MUJOCO_STL_MAX_FACES else _as_obj(path, rel, sources, left)
        if done[rel] is None:
            del out[name]
        else:
            out[name] = done[rel]  # type: ignore[assignment]
    if bad:
        warnings.warn(f"{len(bad)} mesh file(s) MuJoCo would refuse left out of the MJCF: {', '.join(bad[:3])}"
                      f"{', ...' if len(bad) > 3 else ''}", UserWarning, stacklevel=2)
    if left:
        warnings.warn(f"{len(left)} mesh file(s) with more than {MUJOCO_STL_MAX_FACES} triangles (MuJoCo's STL "
                      f"limit) left out: {', '.join(left[:3])}{', ...' if len(left) > 3 else ''}", UserWarning,
                      stacklevel=2)
    return out


def _as_obj(path: Path, rel: str, sources: set[Path], left: list[str]) -> str | None:
    try:
        import trimesh
    except ImportError:
        left.append(f"{path.name} (converting needs trimesh: pip install 'robkin[meshes]')")
        return None
    from ..files.atomic import atomic_file

    target = path.with_suffix(".obj")
    k = 2
    while target.exists():
        target = path.with_name(f"{path.stem}_{k}.obj")
        k += 1
    try:
        mesh = trimesh.load(path, file_type="stl", force="mesh")
        text = trimesh.exchange.obj.export_obj(mesh, include_normals=False, include_color=False,
                                               include_texture=False)
    except Exception as exc:  # noqa: BLE001 - a third-party parser on a file of the source
        left.append(f"{path.name} ({str(exc)[:60] or type(exc).__name__})")
        return None
    with atomic_file(target) as f:
        f.write(text)
    if path.resolve() not in sources:
        path.unlink()
    return str(Path(rel).with_name(target.name).as_posix())
