"""The robot tree an MJCF or SDF reader builds (``io.trees.model.UrdfModel``), as lint's ``RawUrdf``.

The structure, joint, mass and asset checks are one implementation each, written against ``RawUrdf``;
this module gives them the other formats' trees: each link with its mass properties (MJCF: as MuJoCo
compiles them, from the geoms where the body has no ``<inertial>``: ``io.mjcf.geom_mass``), shapes and
source line (``xml_lines``), each joint with its limits, axis as written and mimic target. Links and
joints robkin makes itself (MJCF's ``BODY/JOINT`` links of a body with several joints, ``NAME:fixed``
welds, SDF's ``CHILD@JOINT``) are marked ``synthetic``: no name checks, no mass of their own expected.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import InputError
from .urdf_source import Geometry, RawJoint, RawLink, RawUrdf
from .xml_lines import XmlLines

__all__ = ["raw_from_model", "half_size"]


def half_size(kind: str, size: tuple[float, ...]) -> tuple[float, float, float] | None:
    """MJCF-style half sizes of a ``body_parts.Geometry``'s full sizes (None for a kind lint does not measure)."""
    try:
        if kind == "box":
            return (size[0] / 2, size[1] / 2, size[2] / 2)
        if kind in ("cylinder", "capsule"):
            return (size[0], size[1] / 2, 0.0)
        if kind == "sphere":
            return (size[0], 0.0, 0.0)
    except (IndexError, TypeError):
        return None
    return None


def _num(x: float | None) -> str | None:
    return None if x is None else repr(float(x))


def _content(model: Any, file: str) -> tuple[dict, list[str]]:
    """link -> LinkContent, and the reader's refusal of the contents (their meshes, geoms), if any."""
    try:
        return {name: model.content.get(name) for name in model.links}, []
    except InputError as exc:
        return {}, [str(exc)]


def raw_from_model(model: Any, file: str, fmt: str, lines: XmlLines) -> tuple[RawUrdf, list[str]]:
    """A ``RawUrdf`` of a reader's tree (``fmt`` "mjcf" or "sdf"), and the reader's refusals of the link
    contents (the tree itself was read: its checks still run, without the mass properties)."""
    content, refused = _content(model, file)
    links = []
    for name in model.links:
        el = lines.links.get(name)
        ln = RawLink(name, XmlLines.line(el) or 0, el)
        ln.synthetic = el is None or el.get("name") != name.split("::")[-1]
        # MJCF BODY/JOINT (a joint's element, or an unnamed body's "bodyI/JOINT"), SDF CHILD@JOINT
        ln.frame_only = (el is not None and el.tag == "joint") or (el is None and ("@" in name if fmt == "sdf"
                                                                                   else "/" in name))
        c = content.get(name)
        if c is not None and c.inertial is not None:
            m = c.inertial
            ln.has_inertial, ln.mass, ln.mass_text = True, float(m.mass), repr(float(m.mass))
            ln.inertial_pose = np.asarray(m.pose, dtype=float)
            ln.com = ln.inertial_pose[:3, 3].copy()
            R = ln.inertial_pose[:3, :3]
            ln.inertia = R @ np.asarray(m.inertia, dtype=float) @ R.T
            inertial = _find(el, "inertial") if el is not None and el.tag in ("body", "link") else None
            ln.inertial_line = XmlLines.line(inertial) or ln.line or None
            # MJCF: a body without <inertial> gets its geoms' mass (inertiafromgeom="auto")
            ln.mass_from = "" if inertial is not None or fmt != "mjcf" else "geoms"
        for s in (c.shapes if c is not None else ()):
            g = s.geometry
            kind = g.kind
            size = half_size(kind, g.size) if kind != "mesh" else None
            scale = tuple(float(x) for x in g.size) if kind == "mesh" and len(g.size) == 3 else (1.0, 1.0, 1.0)
            gel = _shape_element(el, s, fmt, lines)
            ln.geometries.append(Geometry(s.role, kind, size, g.filename, scale,  # type: ignore[arg-type]
                                          np.asarray(s.pose, dtype=float), XmlLines.line(gel) or ln.line))
        links.append(ln)
    joints = []
    for j in model.joints:
        el = lines.joints.get(j.name)
        line = XmlLines.line(el)
        synthetic = el is None and (j.name.endswith((":fixed", ":child", ":frame")))
        if line is None:  # a weld or site of a body: the body's line
            parent_el = lines.links.get(j.child)
            line = XmlLines.line(parent_el)
        axis_text, axis_line = " ".join(repr(float(x)) for x in j.axis_xyz()), line
        limit_line = line
        if el is not None and fmt == "mjcf" and el.get("axis") is not None:
            axis_text = el.get("axis")  # as written: MuJoCo normalises it silently
        elif el is not None and fmt == "sdf":
            xyz = el.find("axis/xyz")
            if xyz is not None and xyz.text:
                axis_text, axis_line = xyz.text, XmlLines.line(xyz)
            limit_line = XmlLines.line(el.find("axis/limit")) or line
        limit = None
        if j.type in ("revolute", "prismatic") or any(v is not None for v in (j.effort, j.velocity)):
            limit = {k: v for k, v in (("lower", _num(j.lower)), ("upper", _num(j.upper)),
                                       ("effort", _num(j.effort)), ("velocity", _num(j.velocity))) if v is not None}
        rj = RawJoint(j.name, line or 0, el, j.type, j.parent, j.child, np.asarray(j.origin, dtype=float),
                      axis_text, None, None, limit, limit_line, axis_line,
                      j.mimic.joint if j.mimic is not None else None, line if j.mimic is not None else None)
        rj.synthetic = synthetic
        joints.append(rj)
    name = model.name
    return RawUrdf(file, lines.root, name if name else ("" if fmt == "urdf" else "model"), links, joints,
                   fmt=fmt), refused


def _find(el: Any, tag: str) -> Any:
    """The first ``tag`` child of a body or link (through MJCF ``<frame>``s)."""
    from .xml_lines import _in_bodies

    for c in _in_bodies(el):
        if c.tag == tag:
            return c
    return None


def _shape_element(el: Any, shape: Any, fmt: str, lines: XmlLines) -> Any:
    """The element that wrote a shape: a mesh's ``<asset><mesh>`` (MJCF: where its file is named), else
    the geom (SDF: the visual or collision) of that name, else the first of its kind in the body."""
    if el is None or el.tag not in ("body", "link"):
        return el
    from .xml_lines import _in_bodies

    kids = _in_bodies(el)
    if fmt == "sdf":
        for c in kids:
            if c.tag == shape.role and (shape.name is None or c.get("name") == shape.name):
                return c
        return el
    geoms = [c for c in kids if c.tag == "geom"]
    named = [c for c in geoms if shape.name and c.get("name") == shape.name]
    kind = shape.geometry.kind
    g = named[0] if named else next((c for c in geoms if c.get("type", "sphere") == kind or
                                     (kind == "mesh" and c.get("mesh"))), None)
    if kind == "mesh" and g is not None and g.get("mesh") in lines.meshes:
        return lines.meshes[g.get("mesh")]
    return g if g is not None else el
