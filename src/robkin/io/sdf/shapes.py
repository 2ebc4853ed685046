"""SDF ``<visual>``, ``<collision>`` and ``<inertial>`` elements as the shapes and mass properties of a link.

Poses follow SDFormat: a visual's, collision's or inertial's ``<pose>`` is in its link's frame unless
``relative_to`` names another frame of the model (a link, joint, explicit frame or nested model; at
q = 0). Geometry: ``box`` (size, full side lengths), ``cylinder`` (radius, length), ``sphere`` (radius),
``capsule`` (radius, length between the caps' centres; SDFormat 1.9) and ``mesh`` (``uri``, ``scale``);
``plane``, ``ellipsoid``, ``heightmap``, ``polyline`` and the rest are skipped. Colour: the material's
``diffuse`` (else ``ambient``).

Mesh URIs are kept exactly as written (``model://NAME/...``, ``package://...``, ``file://``, a path
relative to the SDF file); :mod:`robkin.io.meshes.files` finds them when they are needed, refuses
names that cannot be used and says once which files lie outside the model's folder. Parsed on first
use; robkin never opens a mesh file here.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ...bodies import Geometry, Inertial, Material, Shape
from ...compiled.conversions import pose_rows
from ...errors import InputError
from ..trees.model import LinkContent, attribute_floats as _floats
from ..urdf.content import ContentOnce

if TYPE_CHECKING:  # pragma: no cover
    from .frame_graph import FrameGraph

__all__ = ["sdf_content"]

SKIPPED = ("plane", "ellipsoid", "heightmap", "polyline", "image", "empty")


def _number(el: Any, tag: str, where: str, default: float | None = None) -> float:
    text = el.findtext(tag)
    if text is None and default is not None:
        return default
    return float(_floats((text or "").strip() or None, 1, f"{where}: <{tag}>", ())[0])


def _geometry(el: Any, where: str) -> Geometry | None:
    g = el.find("geometry")
    shape = None if g is None else next(iter(g), None)
    if shape is None:
        raise InputError(f"{where}: no <geometry> with a shape (box, cylinder, sphere, capsule, mesh)")
    kind = shape.tag
    if kind == "box":
        size = _floats((shape.findtext("size") or "").strip() or None, 3, f"{where}: box <size>", (1, 1, 1))
        return Geometry("box", tuple(float(x) for x in size))
    if kind == "sphere":
        return Geometry("sphere", (_number(shape, "radius", where, 1.0),))
    if kind in ("cylinder", "capsule"):
        return Geometry(kind, (_number(shape, "radius", where, 1.0), _number(shape, "length", where, 1.0)))
    if kind == "mesh":
        uri = (shape.findtext("uri") or "").strip()
        if not uri:
            raise InputError(f"{where}: <mesh> has no <uri>")
        scale = _floats((shape.findtext("scale") or "").strip() or None, 3, f"{where}: mesh <scale>", (1, 1, 1))
        return Geometry("mesh", tuple(float(x) for x in scale), uri)
    if kind in SKIPPED:
        return None
    raise InputError(f"{where}: <{kind}> is not an SDF geometry (box, cylinder, sphere, capsule, mesh, "
                     f"{', '.join(SKIPPED)})")


def _material(el: Any, where: str) -> Material | None:
    m = el.find("material")
    if m is None:
        return None
    text = (m.findtext("diffuse") or m.findtext("ambient") or "").strip()
    if not text:
        return None
    v = _floats(text, 4, f"{where}: material colour", ()) if len(text.split()) == 4 else \
        np.append(_floats(text, 3, f"{where}: material colour", ()), 1.0)
    return Material(None, tuple(float(x) for x in v))  # type: ignore[arg-type]


def _inertial(el: Any, link: str, X: np.ndarray, where: str) -> Inertial:
    i = el.find("inertia")
    # SDFormat's defaults: mass 1, inertia the identity (also when <inertia> is absent)
    def get(key: str) -> float:
        default = 1.0 if key[1] == key[2] else 0.0
        return default if i is None else _number(i, key, where, default)

    xx, xy, xz, yy, yz, zz = (get(k) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"))
    return Inertial(link, 0, X, _number(el, "mass", where, 1.0),
                    np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]))


def _links(model: Any) -> list[Any]:
    """The ``<link>`` elements of a ``<model>`` and of the models nested in it, in the order the reader
    lists them (``frame_graph.FrameGraph.read``: a model's own links, then those of each nested model)."""
    out = model.findall("link")
    for inner in model.findall("model"):
        out += _links(inner)
    return out


def sdf_content(model: "FrameGraph", folder: Path | None, text: str) -> ContentOnce:
    """link -> LinkContent of the model's links (poses relative to each link's frame), made on first use.

    ``model`` is the reader's resolved frame graph (``frame_graph.FrameGraph``, its ``link_elements`` filled);
    ``folder`` the SDF file's folder (None for text input; mesh names are kept as written either way);
    ``text`` the file's text, parsed whole here (the reader's tree holds only the kinematic elements).
    """
    from .frame_graph import element_pose, the_models
    from ..trees.xml_parse import _parse_xml

    def make() -> dict[str, LinkContent]:
        out = {}
        elements = _links(the_models(_parse_xml(text, model.source))[0])
        for (link, _, prefix), el in zip(model.link_elements, elements):
            def placed(sub: Any, where: str) -> np.ndarray:
                pose, rel = element_pose(sub, where)
                if rel is None or model.scoped(rel, prefix) == link:
                    return pose_rows.matrix(pose)
                return pose_rows.matrix(pose_rows.compose(model.relative(link, model.scoped(rel, prefix), where), pose))

            shapes = []
            for role in ("visual", "collision"):
                for k, sub in enumerate(el.findall(role)):
                    where = f"{model.source}: link '{link}' {role} '{sub.get('name') or f'#{k + 1}'}'"
                    geometry = _geometry(sub, where)
                    if geometry is not None:
                        material = _material(sub, where) if role == "visual" else None
                        shapes.append(Shape(link, 0, role, placed(sub, where), geometry, material, sub.get("name")))
            iel = el.find("inertial")
            inertial = None if iel is None else \
                _inertial(iel, link, placed(iel, f"{model.source}: link '{link}' inertial"),
                          f"{model.source}: link '{link}' inertial")
            if shapes or inertial is not None:
                out[link] = LinkContent(tuple(shapes), inertial)
        return out

    return ContentOnce(make)
