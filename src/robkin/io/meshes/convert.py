"""Mesh files converted for a target that cannot read their format: binary STL through trimesh.

``copy_meshes`` (``io.meshes.files``) converts COLLADA ``.dae`` and ``.ply`` files for MuJoCo. A mesh
file is untrusted: it is parsed from its bytes, without a resolver, so textures or other files it names
are never read; any failure of the parser leaves the mesh out with a reason.
"""

from __future__ import annotations

import io
import re
from pathlib import Path

__all__ = ["to_stl"]


def _short(text: str, limit: int = 100) -> str:
    """``text`` cut to ``limit`` characters in the middle."""
    if len(text) <= limit:
        return text
    head = (limit - 3) // 2
    return text[:head] + "..." + text[len(text) - (limit - 3 - head):]


def to_stl(path: Path, skipped: list[str]) -> bytes | None:
    """Binary STL of a mesh file (COLLADA's unit applied; nothing but ``path`` is read), or None."""
    try:
        import trimesh
    except ImportError:
        skipped.append(f"{path.name} (converting {path.suffix} needs trimesh: pip install 'robkin[meshes]')")
        return None
    kind = path.suffix.lower().lstrip(".")
    try:
        # from bytes, without a resolver: textures or other files the mesh names are never read
        scene = trimesh.load(io.BytesIO(path.read_bytes()), file_type=kind, force="scene")
        mesh = scene.to_geometry() if hasattr(scene, "to_geometry") else scene.dump(concatenate=True)
        unit = _collada_unit(getattr(scene, "units", None)) if kind == "dae" else 1.0
        if unit != 1.0:
            mesh.apply_scale(unit)
        if len(mesh.faces) == 0:
            raise ValueError("no triangles")
        return bytes(trimesh.exchange.stl.export_stl(mesh))
    except Exception as exc:  # noqa: BLE001 - any failure of a third-party parser on an untrusted file
        skipped.append(f"{path.name} (cannot be converted: {_short(str(exc) or type(exc).__name__, 80)})")
        return None


def _collada_unit(units: object) -> float:
    """Metres per unit of a COLLADA file from trimesh's ``units`` metadata ('meters', '0.001 * meters')."""
    if not isinstance(units, str):
        return 1.0
    m = re.fullmatch(r"\s*([0-9.eE+\-]+)\s*\*\s*meters\s*", units)
    try:
        return float(m.group(1)) if m else 1.0
    except ValueError:
        return 1.0
