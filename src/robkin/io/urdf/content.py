"""The contents of URDF links (visuals, collisions, inertials), parsed when first asked for.

Most uses of a URDF need only its joints; a whole humanoid has hundreds of shapes. ``LazyLinkContent``
builds the XML tree of the file the first time a link is looked up (a load for kinematics builds none)
and parses one link's ``<visual>``, ``<collision>`` and ``<inertial>`` children when that link is.
Poses are relative to the link frame; mesh file names are kept as written and never opened.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Callable, Iterator, Mapping, Sequence

import numpy as np

# the records are imported where they are made: a load for kinematics imports this module, makes none
if TYPE_CHECKING:
    from ...body_parts import Geometry, Inertial, Material, Shape
from ...errors import InputError
from ...compiled.scanners.attribute_numbers import number as _number
from ...compiled.scanners.attribute_numbers import numbers
from ..trees.model import LinkContent, origin_matrix

__all__ = ["LazyLinkContent", "ContentOnce", "GEOMETRY_TAGS"]

GEOMETRY_TAGS = ("box", "cylinder", "sphere", "mesh")
_EMPTY = LinkContent()
_ZERO3 = (0.0, 0.0, 0.0)


def parse_origin(el: Any, where: str) -> tuple[np.ndarray, tuple[float, ...]]:
    """(pose (4, 4), the six numbers xyz + rpy) of an element's <origin> child (identity if none)."""
    origin = el.find("origin")
    get = (lambda key: None) if origin is None else origin.get
    xyz_rpy = (numbers(get("xyz"), 3, where, "origin xyz", _ZERO3)
               + numbers(get("rpy"), 3, where, "origin rpy", _ZERO3))
    return origin_matrix(xyz_rpy[:3], xyz_rpy[3:]), xyz_rpy


def _material(el: Any, where: str, named: Mapping[str, Material]) -> Material | None:
    """A visual's <material>: inline colour/texture, or a reference by name to a top-level one."""
    from ...body_parts import Material
    if el is None:
        return None
    name = el.get("name")
    color, texture = el.find("color"), el.find("texture")
    if color is None and texture is None:
        return named.get(name or "", Material(name))
    rgba = None if color is None else numbers(color.get("rgba"), 4, where, "material color rgba", (0, 0, 0, 1))
    return Material(name, rgba, None if texture is None else texture.get("filename"))  # type: ignore[arg-type]


def _geometry(el: Any, where: str) -> Geometry:
    from ...body_parts import Geometry
    g = el.find("geometry")
    shape = None if g is None else next((c for c in g if c.tag in GEOMETRY_TAGS), None)
    if shape is None:
        raise InputError(f"{where}: no <geometry> with one of {', '.join(GEOMETRY_TAGS)}")
    tag = shape.tag
    if tag == "box":
        return Geometry("box", numbers(shape.get("size"), 3, where, "box size", (0.0, 0.0, 0.0)))
    if tag == "sphere":
        return Geometry("sphere", numbers(shape.get("radius"), 1, where, "sphere radius", (0.0,)))
    if tag == "cylinder":
        r = numbers(shape.get("radius"), 1, where, "cylinder radius", (0.0,))
        h = numbers(shape.get("length"), 1, where, "cylinder length", (0.0,))
        return Geometry("cylinder", r + h)
    filename = shape.get("filename")
    if not filename:
        raise InputError(f"{where}: <mesh> has no filename")
    return Geometry("mesh", numbers(shape.get("scale"), 3, where, "mesh scale", (1.0, 1.0, 1.0)), filename)


def parse_link_content(el: Any, src: str, named: Mapping[str, Material]) -> LinkContent:
    """Shapes and inertial of one <link> element (poses relative to the link frame)."""
    from ...body_parts import Shape
    link = el.get("name")
    shapes: list[Shape] = []
    for role in ("visual", "collision"):
        for k, sub in enumerate(el.iterfind(role)):
            where = f"{src}: link '{link}' {role} #{k + 1}"
            pose, xyz_rpy = parse_origin(sub, where)
            material = _material(sub.find("material"), where, named) if role == "visual" else None
            shapes.append(Shape(link, 0, role, pose, _geometry(sub, where), material,
                                sub.get("name"), xyz_rpy))
    inertial = parse_inertial(el, src)
    if not shapes and inertial is None:
        return _EMPTY
    return LinkContent(tuple(shapes), inertial)


def parse_inertial(el: Any, src: str) -> Inertial | None:
    """The <inertial> of one <link> element (pose relative to the link frame), or None; parsed on its
    own, so that mass properties (dynamics, tables with masses) never depend on the shapes."""
    from ...body_parts import Inertial

    link = el.get("name")
    inertial = None
    iel = el.find("inertial")
    if iel is not None:
        where = f"{src}: link '{link}' inertial"
        pose, xyz_rpy = parse_origin(iel, where)
        mass_el = iel.find("mass")
        mass = _number(None if mass_el is None else mass_el.get("value"), where, "mass value") or 0.0
        i_el = iel.find("inertia")
        get = (lambda key: None) if i_el is None else i_el.get
        ixx, ixy, ixz, iyy, iyz, izz = (_number(get(k), where, f"inertia {k}") or 0.0
                                        for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"))
        inertial = Inertial(link, 0, pose, mass, np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]]),
                            xyz_rpy)
    return inertial


class LazyLinkContent(Mapping[str, LinkContent]):
    """link name -> LinkContent, parsed on first lookup from the <link> elements of ``root()``.

    ``links`` are the file's link names (unique, as the reader checked); ``root`` gives the parsed
    <robot> element, and is called only on the first lookup of a link's content.
    """

    def __init__(self, links: Sequence[str], root: Callable[[], Any], src: str) -> None:
        self._links = links
        self._root = root
        self._elements: dict[str, Any] | None = None
        self._material_elements: list[Any] = []
        self._named: dict[str, Material] | None = None
        self._src = src
        self._cache: dict[str, LinkContent] = {}

    def _element(self, link: str) -> Any:
        if self._elements is None:
            elements: dict[str, Any] = {}
            for el in self._root():
                if el.tag == "link":
                    elements.setdefault(el.get("name"), el)
                elif el.tag == "material":
                    self._material_elements.append(el)
            self._elements = elements
        return self._elements.get(link)

    def _materials(self) -> dict[str, Material]:
        if self._named is None:
            named: dict[str, Material] = {}
            for el in self._material_elements:
                m = _material(el, f"{self._src}: material '{el.get('name')}'", {})
                if m is not None and m.name:
                    named[m.name] = m
            self._named = named
        return self._named

    def __getitem__(self, link: str) -> LinkContent:
        if link not in self._cache:
            el = self._element(link)
            self._cache[link] = _EMPTY if el is None else parse_link_content(el, self._src, self._materials())
        return self._cache[link]

    def inertial(self, link: str) -> Inertial | None:
        """The link's inertial alone (its shapes not parsed: a broken shape does not stop dynamics)."""
        if link in self._cache:
            return self._cache[link].inertial
        el = self._element(link)
        return None if el is None else parse_inertial(el, self._src)

    def __iter__(self) -> Iterator[str]:
        return iter(self._links)

    def __len__(self) -> int:
        return len(self._links)


class ContentOnce(Mapping[str, LinkContent]):
    """link name -> LinkContent, all made by ``make()`` on the first lookup (the MJCF and SDF readers')."""

    def __init__(self, make: Callable[[], dict[str, LinkContent]]) -> None:
        self._make: Callable[[], dict[str, LinkContent]] | None = make
        self._made: dict[str, LinkContent] = {}

    def _all(self) -> dict[str, LinkContent]:
        if self._make is not None:
            self._made, self._make = self._make(), None
        return self._made

    def __getitem__(self, link: str) -> LinkContent:
        return self._all()[link]

    def __iter__(self) -> Iterator[str]:
        return iter(self._all())

    def __len__(self) -> int:
        return len(self._all())
