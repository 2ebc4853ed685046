"""MJCF geoms and inertials as the shapes and mass properties of a link (``robkin.bodies``).

Each body's ``<geom>`` elements become ``Shape``s on the link of that body, posed relative to the
body frame exactly as MuJoCo places them (``pos`` and every orientation form, ``fromto``, and the
``<frame>``s around them); its ``<inertial>`` becomes an ``Inertial``. Parsed on first use: loading a
robot for its kinematics costs none of it.

Visual or collision (MuJoCo has no such split; its own flags decide)
    A geom is a **visual** when MuJoCo's viewer draws it by default (``group`` 0, 1 or 2) and a
    **collision** shape when it takes part in contacts (``contype`` or ``conaffinity`` not 0). A geom
    that is both (MuJoCo's defaults: group 0, contype 1, conaffinity 1) gives one shape of each role,
    as a URDF link with the same ``<visual>`` and ``<collision>``; one that is neither is skipped.
    Menagerie's ``visual`` classes (group 2, contype 0, conaffinity 0) are visuals only and its
    ``collision`` classes (group 3) collision shapes only.

Geometry
    ``sphere``, ``box`` (MJCF half sizes become full side lengths), ``cylinder`` and ``capsule``
    (MJCF radius and half-length become radius and length; ``fromto`` gives the length), ``mesh``
    (the ``<asset><mesh file scale>`` named by the geom). ``plane``, ``hfield``, ``ellipsoid`` and
    ``sdf`` geoms, meshes given by their vertices (no ``file``) and primitives fitted to a mesh (a
    ``mesh`` attribute with a primitive ``type``) are skipped. Colour: the geom's ``rgba`` when it differs from MuJoCo's default, else its
    ``material``'s, else MuJoCo's default grey.

Mesh files
    A mesh is named by ``<compiler meshdir>`` (or ``assetdir``) joined with its ``file``, relative to
    the main model file's folder (an absolute ``file`` or ``meshdir`` stays absolute), as MuJoCo
    looks it up; :mod:`robkin.io.meshes.files` finds it when it is needed and says once which files
    lie outside the model's folder. robkin never opens a mesh file here.

The frame of a mesh shape is the frame of the mesh file's coordinates. (MuJoCo moves a compiled mesh
geom's frame to the mesh's centre of mass, ``mesh_pos``/``mesh_quat``; the shape is where MuJoCo
draws the file.)
"""

from __future__ import annotations

from pathlib import PurePosixPath
from typing import Any, Callable, Mapping

import numpy as np

from ...bodies import Geometry, Inertial, Material, Shape
from ...compiled.conversions import pose_rows
from ...errors import InputError, quote
from .poses import Pose, geom_placement
from .source import MjcfSource
from ..trees.model import LinkContent, attribute_floats as _floats
from ..urdf.content import ContentOnce

__all__ = ["MjcfContent", "VISIBLE_GROUPS", "DEFAULT_RGBA"]

#: Geom groups MuJoCo's viewer shows by default (``mjVisOption.geomgroup``: groups 0, 1 and 2 on).
VISIBLE_GROUPS = (0, 1, 2)
#: MuJoCo's internal default geom colour; a geom ``rgba`` equal to it does not override a material.
DEFAULT_RGBA = (0.5, 0.5, 0.5, 1.0)
PRIMITIVES = ("sphere", "box", "cylinder", "capsule")
SKIPPED = ("plane", "hfield", "ellipsoid", "sdf")

#: (element, class, where) -> the element's attributes, its class's defaults applied
Attrs = Callable[[Any, str, str], Mapping[str, str]]


def _int(text: str | None, default: int, where: str) -> int:
    if text is None:
        return default
    try:
        return int(text.strip())
    except ValueError:
        raise InputError(f"{where}: '{text[:40]}' is not a whole number") from None


def _sizes(text: str | None, where: str) -> list[float]:
    """A geom's ``size``: one to three numbers (MuJoCo reads those the type needs), padded with 0."""
    parts = (text or "0").split()
    if not 1 <= len(parts) <= 3:
        raise InputError(f"{where}: '{(text or '')[:60]}' has {len(parts)} numbers; expected 1 to 3")
    return [float(_floats(p, 1, where, ())[0]) for p in parts] + [0.0] * (3 - len(parts))


class MjcfContent(ContentOnce):
    """link (body) name -> LinkContent of its geoms and inertial, all made on the first lookup.

    Parameters
    ----------
    src : MjcfSource
        The resolved model (assets, compiler settings, classes).
    parts : dict
        Body name -> [(element, pose (twelve floats, ``pose_rows``) of its frame relative to the body,
        class)] of its
        ``<geom>`` and ``<inertial>`` children (``<frame>``s dissolved).
    attrs : callable
        (element, class, where) -> the element's attributes with its class's defaults applied.
    body_poses : dict, optional
        Body name -> its own pose attributes (relative to its parent), for ``geom_mass``.
    """

    def __init__(self, src: MjcfSource, parts: dict[str, list[tuple[Any, Pose, str]]], attrs: Attrs,
                 body_poses: Mapping[str, Pose] | None = None):
        self._src, self._parts, self._attrs, self._body_poses = src, parts, attrs, body_poses or {}
        super().__init__(self._build)

    def _build(self) -> dict[str, LinkContent]:
        from .geom_mass import BodyMasses

        meshes, materials = self._assets()
        shapes: dict[str, list[Shape]] = {}
        explicit: dict[str, Inertial] = {}
        for link, parts in self._parts.items():
            shapes[link] = []
            for k, (el, T, cls) in enumerate(parts):
                if el.tag == "inertial":
                    explicit[link] = self._inertial(el, T, link)
                else:
                    shapes[link] += self._geom(el, T, cls, link, k, meshes, materials)
        inertials = BodyMasses(self._src, self._attrs, self._body_poses).inertials(self._parts, explicit)
        out = {}
        for link in self._parts:
            if shapes[link] or inertials.get(link) is not None:
                out[link] = LinkContent(tuple(shapes[link]), inertials.get(link))
        return out

    def _assets(self) -> tuple[dict[str, tuple[str, tuple[float, ...]]], dict[str, Material]]:
        """Mesh name -> (file name relative to the model folder, "" for a mesh without a file (given
        by its vertices); scale); material name -> Material."""
        meshes: dict[str, tuple[str, tuple[float, ...]]] = {}
        materials: dict[str, Material] = {}
        for asset in self._src.root.findall("asset"):
            for el in asset.findall("mesh"):
                file = el.get("file")
                a = self._attrs(el, "main", f"{self._src.source}: mesh '{el.get('name') or file}'")
                name = el.get("name") or (PurePosixPath(file.replace("\\", "/")).stem if file else None)
                if name:
                    where = f"{self._src.source}: mesh '{name}'"
                    scale = tuple(float(x) for x in _floats(a.get("scale"), 3, f"{where}: scale", (1, 1, 1)))
                    meshes[name] = (self._mesh_file(file) if file else "", scale)
            for el in asset.findall("material"):
                name = el.get("name")
                if name:
                    a = self._attrs(el, "main", f"{self._src.source}: material '{name}'")
                    rgba = _floats(a.get("rgba"), 4, f"{self._src.source}: material '{name}': rgba", (1, 1, 1, 1))
                    materials[name] = Material(name, tuple(float(x) for x in rgba))  # type: ignore[arg-type]
        return meshes, materials

    def _mesh_file(self, file: str) -> str:
        """meshdir/file, relative to the model's folder unless either is absolute (MuJoCo's rule)."""
        return str(PurePosixPath(self._src.meshdir.replace("\\", "/")) / file.replace("\\", "/"))

    def _geom(self, el: Any, T: Pose, cls: str, link: str, k: int,
              meshes: dict[str, tuple[str, tuple[float, ...]]], materials: dict[str, Material]) -> list[Shape]:
        name = el.get("name")
        where = f"{self._src.source}: geom '{name or f'#{k + 1}'}' (body '{link}')"
        a = self._attrs(el, cls, where)
        kind = a.get("type", "sphere")
        roles = []
        if _int(a.get("group"), 0, f"{where}: group") in VISIBLE_GROUPS:
            roles.append("visual")
        if _int(a.get("contype"), 1, f"{where}: contype") or _int(a.get("conaffinity"), 1, f"{where}: conaffinity"):
            roles.append("collision")
        if not roles or kind in SKIPPED or (kind in PRIMITIVES and a.get("mesh")):
            return []
        pose, length = geom_placement(a, self._src, where)
        size = _sizes(a.get("size"), f"{where}: size")
        if kind == "sphere":
            geometry = Geometry("sphere", (size[0],))
        elif kind == "box":
            # a box given by fromto is square in cross-section: MuJoCo uses the first size for x and y
            half = list(size) if length is None else [size[0], size[0], length / 2]
            geometry = Geometry("box", tuple(2 * x for x in half))
        elif kind in ("cylinder", "capsule"):
            geometry = Geometry(kind, (size[0], 2 * size[1] if length is None else length))  # type: ignore[arg-type]
        elif kind == "mesh":
            mesh = a.get("mesh")
            if mesh not in meshes:
                raise InputError(f"{where}: mesh {quote(mesh)} is not a <mesh> of the <asset>s")
            file, scale = meshes[mesh]
            if file == "":  # a mesh given by its vertices in the file: no file to draw
                return []
            geometry = Geometry("mesh", scale, file)
        else:
            raise InputError(f"{where}: type {quote(kind)} is not one of {', '.join(PRIMITIVES + ('mesh',) + SKIPPED)}")
        rgba = tuple(float(x) for x in _floats(a.get("rgba"), 4, f"{where}: rgba", DEFAULT_RGBA))
        material = materials.get(a.get("material") or "") if rgba == DEFAULT_RGBA else None
        material = material or Material(a.get("material"), rgba)  # type: ignore[arg-type]
        P = pose_rows.matrix(pose_rows.compose(T, pose))
        return [Shape(link, 0, role, P, geometry, material if role == "visual" else None, name)  # type: ignore[arg-type]
                for role in roles]

    def _inertial(self, el: Any, T: Pose, link: str) -> Inertial:
        where = f"{self._src.source}: body '{link}' inertial"
        a = dict(el.attrib)
        if a.get("fullinertia") is not None and a.get("diaginertia") is not None:
            raise InputError(f"{where}: has both diaginertia and fullinertia; give one")
        if a.get("fullinertia") is not None:
            xx, yy, zz, xy, xz, yz = _floats(a["fullinertia"], 6, f"{where}: fullinertia", ())
            inertia = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
        else:
            inertia = np.diag(_floats(a.get("diaginertia"), 3, f"{where}: diaginertia", (0, 0, 0)))
        mass = float(_floats(a.get("mass"), 1, f"{where}: mass", ())[0])
        pose, _ = geom_placement(a, self._src, where)
        return Inertial(link, 0, pose_rows.matrix(pose_rows.compose(T, pose)), mass, inertia)
