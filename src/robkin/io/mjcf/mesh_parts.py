"""A COLLADA visual mesh in parts of one colour each, so that MuJoCo draws it in its own colours.

A .dae file carries its materials (a Panda link is white with black joints, a UR arm grey with blue
caps); MuJoCo reads STL and OBJ without colours, and ``mesh_files.copy_meshes`` converts a .dae into one
STL. For a visual shape the source gives no colour of its own, the writer draws instead one geom per
colour of the file: the triangles of each material (after the file's node transforms and unit, as in
the single STL) written as their own STL, with that material's colour as the geom's ``rgba``. A file
of one colour, one that trimesh cannot read, or trimesh missing: no parts (the single grey mesh).
"""

from __future__ import annotations

import io
from pathlib import Path
from typing import Mapping

__all__ = ["visual_mesh_parts"]

#: Most parts one file is split into (a file of many small materials stays one grey mesh).
MAX_PARTS = 12


def _parts(path: Path) -> list[tuple[bytes, tuple[float, ...]]]:
    """[(binary STL, rgba 0..1)] of a COLLADA file, one per colour; [] when it has fewer than two."""
    try:
        import numpy as np
        import trimesh

        from ..meshes.convert import _collada_unit
    except ImportError:
        return []
    try:
        scene = trimesh.load(io.BytesIO(path.read_bytes()), file_type="dae", force="scene")
        unit = _collada_unit(getattr(scene, "units", None))
        groups: dict[tuple[int, ...], list] = {}
        for mesh in scene.dump():
            material = getattr(mesh.visual, "material", None)
            color = getattr(material, "main_color", None)
            key = tuple(int(c) for c in (color if color is not None else (128, 128, 128, 255)))
            groups.setdefault(key, []).append(mesh)
        if not 2 <= len(groups) <= MAX_PARTS:
            return []
        out = []
        for key, meshes in groups.items():
            part = trimesh.util.concatenate(meshes)
            if unit != 1.0:
                part.apply_scale(unit)
            if len(part.faces):
                out.append((bytes(trimesh.exchange.stl.export_stl(part)),
                            tuple(float(c) / 255.0 for c in np.asarray(key, dtype=float))))
        return out
    except Exception:  # noqa: BLE001 - a third-party parser on an untrusted file: the single mesh stays
        return []


def visual_mesh_parts(visual_files: Mapping[str, Path], out_dir: Path, mesh_dir: str
                      ) -> dict[str, list[tuple[str, tuple[float, ...]]]]:
    """Source name -> [(file relative to ``out_dir``, rgba)] for each COLLADA file of ``visual_files``
    (source name -> resolved path) that has several colours; the part files are written into
    ``out_dir/mesh_dir`` as ``STEM_colorK.stl`` (never over an existing file)."""
    from ..files.atomic import atomic_file

    folder = out_dir / mesh_dir
    out: dict[str, list[tuple[str, tuple[float, ...]]]] = {}
    done: dict[Path, list[tuple[str, tuple[float, ...]]]] = {}
    for name, path in visual_files.items():
        if path.suffix.lower() != ".dae":
            continue
        if path not in done:
            written = []
            for k, (data, rgba) in enumerate(_parts(path)):
                target = folder / f"{path.stem}_color{k}.stl"
                n = 2
                while target.exists():
                    target = folder / f"{path.stem}_color{k}_{n}.stl"
                    n += 1
                folder.mkdir(parents=True, exist_ok=True)
                with atomic_file(target, binary=True) as f:
                    f.write(data)
                written.append((f"{mesh_dir}/{target.name}", rgba))
            done[path] = written
        if done[path]:
            out[name] = done[path]
    return out
