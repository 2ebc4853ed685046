"""Mesh files copied beside an MJCF, made loadable by MuJoCo: its STL reader refuses a file of more
than 200 000 triangles (detailed visual meshes converted from COLLADA often have more), its OBJ
reader has no such limit. Such STL files are rewritten as OBJ (trimesh), or left out with one warning.
"""

from __future__ import annotations

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


def fit_for_mujoco(mesh_files: Mapping[str, str], out_dir: Path, sources: set[Path]) -> dict[str, str]:
    """``mesh_files`` (source name -> file relative to ``out_dir``) with every STL MuJoCo refuses
    rewritten as OBJ beside it (the STL removed unless it is one of the model's own files, ``sources``),
    or left out with one warning line when it cannot be."""
    out = dict(mesh_files)
    done: dict[str, str | None] = {}
    left: list[str] = []
    for name, rel in mesh_files.items():
        if not rel.lower().endswith(".stl"):
            continue
        if rel not in done:
            path = out_dir / rel
            faces = _stl_faces(path)
            done[rel] = rel if faces is None or faces <= MUJOCO_STL_MAX_FACES else _as_obj(path, rel, sources, left)
        if done[rel] is None:
            del out[name]
        else:
            out[name] = done[rel]  # type: ignore[assignment]
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
