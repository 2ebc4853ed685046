"""Temporary stand-in for ``robkin.io.mesh_files`` (same API), until that module is merged.

Resolves ``package://NAME/...`` (a folder NAME above the source file), ``file://`` and relative paths;
copies STL and OBJ files into the output folder; skips the rest with one warning.
"""

from __future__ import annotations

import shutil
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Mapping

if TYPE_CHECKING:  # pragma: no cover
    from ..robot import Robot

__all__ = ["MeshFile", "resolve_meshes", "copy_meshes"]

READABLE = (".stl", ".obj")


@dataclass(frozen=True)
class MeshFile:
    source: str
    path: Path | None
    reason: str | None = None


def _find(name: str, folder: Path, package_paths: Mapping[str, str]) -> Path | None:
    if name.startswith("package://"):
        pkg, _, rest = name[len("package://"):].partition("/")
        if pkg in package_paths:
            p = Path(package_paths[pkg]) / rest
            return p if p.is_file() else None
        for up in [folder, *folder.parents]:
            if up.name == pkg and (up / rest).is_file():
                return up / rest
        return None
    if name.startswith("file://"):
        name = name[len("file://"):]
    p = Path(name)
    p = p if p.is_absolute() else folder / p
    return p if p.is_file() else None


def resolve_meshes(robot: Robot, source_file: str | None, package_paths: Mapping[str, str] | None = None
                   ) -> dict[str, MeshFile]:
    folder = Path(source_file).resolve().parent if source_file else Path(".")
    out: dict[str, MeshFile] = {}
    for s in robot.bodies.shapes:
        name = s.geometry.filename
        if s.geometry.kind != "mesh" or not name or name in out:
            continue
        p = _find(name, folder, package_paths or {})
        out[name] = MeshFile(name, p, None if p is not None else "not found")
    return out


def copy_meshes(resolved: Mapping[str, MeshFile], out_dir: str | Path, subdir: str = "meshes") -> dict[str, str]:
    out_dir = Path(out_dir)
    mapping: dict[str, str] = {}
    skipped: list[str] = []
    used: set[str] = set()
    for name, mf in resolved.items():
        if mf.path is None or mf.path.suffix.lower() not in READABLE:
            skipped.append(name)
            continue
        target = mf.path.name
        k = 1
        while target in used:
            k += 1
            target = f"{mf.path.stem}_{k}{mf.path.suffix}"
        used.add(target)
        (out_dir / subdir).mkdir(parents=True, exist_ok=True)
        shutil.copyfile(mf.path, out_dir / subdir / target)
        mapping[name] = f"{subdir}/{target}"
    if skipped:
        warnings.warn(f"{len(skipped)} mesh file(s) not found or not in a format MuJoCo reads (STL, OBJ): "
                      f"{', '.join(skipped[:3])}{', ...' if len(skipped) > 3 else ''}", UserWarning, stacklevel=2)
    return mapping
