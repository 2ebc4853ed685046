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
file is not in it is left out; the writer warns once with how many and which. So is a primitive of
size zero or less (a sphere of radius 0, as pybullet's Laikago has), which MuJoCo refuses ("size 0 must
be positive in geom"), failing the whole model.

Mesh inertia: no geom adds mass, but MuJoCo computes every mesh's volume when it compiles and refuses a
mesh whose volume is (nearly) zero, such as a flat decal of a visual mesh. A mesh only visual geoms use
is written with ``inertia="shell"`` (its surface, which a flat mesh has), a mesh a collision geom uses
with ``inertia="convex"`` (its convex hull, which is what MuJoCo collides; a flat collision mesh is made
a thin box before it gets here, ``robkin.collision``). Tested with MuJoCo 4.0; a release without the
mesh ``inertia`` attribute refuses it.
"""

from __future__ import annotations

import re
from pathlib import PurePosixPath
from typing import TYPE_CHECKING, Mapping, Sequence

import numpy as np

from ... import se3
from ..files.float_text import float_text as _num
from .format import place_attrs
from ..files.xmltext import quoteattr

if TYPE_CHECKING:  # pragma: no cover
    from ...body_parts import Material, Shape

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

    def __init__(self, mesh_files: Mapping[str, str] | None,
                 mesh_parts: Mapping[str, Sequence[tuple[str, tuple[float, ...]]]] | None = None) -> None:
        self.mesh_files = dict(mesh_files or {})
        #: source name -> [(written file, rgba)]: a visual mesh in parts of one colour each (COLLADA's
        #: materials), drawn in its own colours when the source gives the shape none
        self.mesh_parts = dict(mesh_parts or {})
        self.meshes: dict[tuple[str, tuple[float, ...]], str] = {}  # (written file, scale) -> asset name
        self.colliding: set[str] = set()  # mesh assets a collision geom uses
        self.materials: dict[str, Material] = {}
        self.missing: list[str] = []
        #: "link: kind" of the primitives left out because a size is zero or less (or not finite)
        self.degenerate: list[str] = []
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

    def _asset(self, written: str, size: Sequence[float]) -> str:
        key = (written, tuple(float(x) for x in size))
        if key not in self.meshes:
            self.meshes[key] = self._unique(PurePosixPath(written.replace("\\", "/")).stem)
        return self.meshes[key]

    def _mesh(self, s: Shape) -> str | None:
        file = s.geometry.filename or ""
        if file not in self.mesh_files:
            if file not in self.missing:
                self.missing.append(file)
            return None
        return self._asset(self.mesh_files[file], s.geometry.size)

    def _color(self, m: Material | None) -> str:
        if m is None or m.rgba is None:
            return ""
        if m.name:
            known = self.materials.setdefault(m.name, m)
            if known.rgba == m.rgba:
                return f" material={quoteattr(m.name)}"
        return f' rgba="{_nums(m.rgba)}"'

    def geoms(self, s: Shape, body_frame: np.ndarray, scale: float = 1.0) -> list[str]:
        """The ``<geom/>``s of a shape on a body at ``body_frame`` (4, 4): one, one per colour of a
        visual mesh in parts, or none when its file is not available."""
        parts = self.mesh_parts.get(s.geometry.filename or "") if s.geometry.kind == "mesh" else None
        if parts and s.role == "visual" and (s.material is None or s.material.rgba is None):
            place = place_attrs(se3.inv(body_frame) @ s.pose, scale, s.origin)
            out = []
            for k, (written, rgba) in enumerate(parts):
                name = self._geom_name(f"{s.name}_{k}") if s.name else ""
                out.append(f'<geom class="visual"{name} type="mesh" mesh={quoteattr(self._asset(written, s.geometry.size))}'
                           f'{place} rgba="{_nums(rgba)}"/>')
            return out
        one = self._one(s, body_frame, scale)
        return [] if one is None else [one]

    def _geom_name(self, wanted: str) -> str:
        """`` name="..."``, unique among the geoms (a URDF's visual and collision often share a name)."""
        label, k = wanted, 1
        while label in self._geom_names:
            k += 1
            label = f"{wanted}_{k}"
        self._geom_names.add(label)
        return f" name={quoteattr(label)}"

    def _one(self, s: Shape, body_frame: np.ndarray, scale: float) -> str | None:
        g = s.geometry
        if g.kind == "mesh":
            mesh = self._mesh(s)
            if mesh is None:
                return None
            what = f'type="mesh" mesh={quoteattr(mesh)}'
            if s.role == "collision":
                self.colliding.add(mesh)
        elif not all(np.isfinite(v) and v > 0 for v in g.size):
            self.degenerate.append(f"{s.link}: {s.role} {g.kind} of size {' '.join(_num(v) for v in g.size)}")
            return None
        elif g.kind == "box":
            what = f'type="box" size="{_nums(np.asarray(g.size) / 2)}"'
        elif g.kind == "sphere":
            what = f'type="sphere" size="{_num(g.size[0])}"'
        elif g.kind in ("cylinder", "capsule"):
            what = f'type="{g.kind}" size="{_num(g.size[0])} {_num(g.size[1] / 2)}"'
        else:  # pragma: no cover - Geometry.kind is one of the above
            return None
        name = self._geom_name(s.name) if s.name else ""
        color = self._color(s.material) if s.role == "visual" else ""
        rel = se3.inv(body_frame) @ s.pose
        return f'<geom class="{s.role}"{name} {what}{place_attrs(rel, scale, s.origin)}{color}/>'

    def asset_lines(self) -> list[str]:
        out = []
        for (written, scale), name in self.meshes.items():
            sc = "" if scale == (1.0, 1.0, 1.0) else f' scale="{_nums(scale)}"'
            inertia = "convex" if name in self.colliding else "shell"
            out.append(f"    <mesh name={quoteattr(name)} file={quoteattr(written)}{sc} inertia=\"{inertia}\"/>")
        for name, m in self.materials.items():
            out.append(f"    <material name={quoteattr(name)} rgba=\"{_nums(m.rgba or (1, 1, 1, 1))}\"/>")
        return out
