"""Visual and collision shapes as MJCF ``<geom>``s, with the ``<asset>``s (meshes, materials) they use.

MuJoCo's usual split (as in MuJoCo Menagerie): visual shapes are geoms of class ``visual`` (group 2,
``contype`` = ``conaffinity`` = 0: drawn, never in contact), collision shapes geoms of class
``collision`` (group 3: in contact, hidden by the viewer's default groups). Neither adds mass: the
writer sets ``inertiafromgeom="false"``, the bodies' inertials are the source's.

Geometry: box (half sizes), sphere, cylinder and capsule (radius, half length), mesh (an ``<asset>``
mesh with the shape's scale, one per file and scale). Colours: a named material of the source becomes
an ``<asset><material>`` of that name, an unnamed colour the geom's ``rgba``; textures are not written
(MuJoCo's textures are PNG files with their own mapping).

Mesh files: ``mesh_files`` maps a shape's file name as the source wrote it to the ``file`` to write
(relative to the output file's folder, where ``robkin convert`` copies the meshes). A mesh shape whose
file is not in it is left out; the writer warns once with how many and which.
"""

from __future__ import annotations

import re
from pathlib import PurePosixPath
from typing import TYPE_CHECKING, Mapping

import numpy as np

from .. import se3
from .float_text import float_text as _num
from .mjcf import place_attrs
from .xmltext import quoteattr

if TYPE_CHECKING:  # pragma: no cover
    from ..body_parts import Material, Shape

__all__ = ["GeomAssets", "DEFAULT_CLASSES"]

#: The default classes every written model carries (see the module doc).
DEFAULT_CLASSES = ['    <default class="visual">',
                   '      <geom group="2" contype="0" conaffinity="0"/>',
                   "    </default>",
                   '    <default class="collision">',
                   '      <geom group="3"/>',
                   "    </default>"]


def _nums(v) -> str:
    return " ".join(_num(x) for x in v)


class GeomAssets:
    """Collects the mesh and material assets while the geoms are written."""

    def __init__(self, mesh_files: Mapping[str, str] | None) -> None:
        self.mesh_files = dict(mesh_files or {})
        self.meshes: dict[tuple[str, tuple[float, ...]], str] = {}  # (file, scale) -> asset name
        self.materials: dict[str, Material] = {}
        self.missing: list[str] = []
        self._names: set[str] = set()
        self._geom_names: set[str] = set()

    def _unique(self, stem: str) -> str:
        base = re.sub(r"[^A-Za-z0-9_.-]", "_", stem) or "mesh"
        name, k = base, 1
        while name in self._names:
            k += 1
            name = f"{base}_{k}"
        self._names.add(name)
        return name

    def _mesh(self, s: Shape) -> str | None:
        g = s.geometry
        file = g.filename or ""
        if file not in self.mesh_files:
            if file not in self.missing:
                self.missing.append(file)
            return None
        key = (file, tuple(float(x) for x in g.size))
        if key not in self.meshes:
            self.meshes[key] = self._unique(PurePosixPath(file.replace("\\", "/")).stem)
        return self.meshes[key]

    def _color(self, m: Material | None) -> str:
        if m is None or m.rgba is None:
            return ""
        if m.name:
            known = self.materials.setdefault(m.name, m)
            if known.rgba == m.rgba:
                return f" material={quoteattr(m.name)}"
        return f' rgba="{_nums(m.rgba)}"'

    def geom(self, s: Shape, body_frame: np.ndarray, scale: float = 1.0) -> str | None:
        """The ``<geom/>`` of a shape on a body at ``body_frame`` (4, 4); None if left out."""
        g = s.geometry
        if g.kind == "mesh":
            mesh = self._mesh(s)
            if mesh is None:
                return None
            what = f'type="mesh" mesh={quoteattr(mesh)}'
        elif g.kind == "box":
            what = f'type="box" size="{_nums(np.asarray(g.size) / 2)}"'
        elif g.kind == "sphere":
            what = f'type="sphere" size="{_num(g.size[0])}"'
        elif g.kind in ("cylinder", "capsule"):
            what = f'type="{g.kind}" size="{_num(g.size[0])} {_num(g.size[1] / 2)}"'
        else:  # pragma: no cover - Geometry.kind is one of the above
            return None
        name = ""
        if s.name:  # MuJoCo needs unique geom names; a URDF's visual and collision often share one
            label, k = s.name, 1
            while label in self._geom_names:
                k += 1
                label = f"{s.name}_{k}"
            self._geom_names.add(label)
            name = f" name={quoteattr(label)}"
        color = self._color(s.material) if s.role == "visual" else ""
        rel = se3.inv(body_frame) @ s.pose
        return f'<geom class="{s.role}"{name} {what}{place_attrs(rel, scale, s.origin)}{color}/>'

    def asset_lines(self) -> list[str]:
        out = []
        for (file, scale), name in self.meshes.items():
            sc = "" if scale == (1.0, 1.0, 1.0) else f' scale="{_nums(scale)}"'
            out.append(f"    <mesh name={quoteattr(name)} file={quoteattr(self.mesh_files[file])}{sc}/>")
        for name, m in self.materials.items():
            out.append(f"    <material name={quoteattr(name)} rgba=\"{_nums(m.rgba or (1, 1, 1, 1))}\"/>")
        return out
