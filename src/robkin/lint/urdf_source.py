"""A URDF read tolerantly for lint: every link and joint as written, with its line, nothing refused.

The strict reader (``io.urdf``) refuses a file at its first defect; lint wants them all, with lines. So
the text is read with the same rules as ``convert`` (``io.files.input_files``' byte cap, no DTD or
entities: ``io.trees.xml_parse``) and parsed with lxml, whose elements know their ``sourceline``.
Only "cannot be read" (no file, too big, not XML, no ``<robot>``) raises ``InputError``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import InputError

__all__ = ["Geometry", "RawLink", "RawJoint", "RawUrdf", "read_urdf", "parse_urdf_text", "numbers"]

MOVING_TYPES = ("revolute", "continuous", "prismatic", "floating", "planar")
JOINT_TYPES = MOVING_TYPES + ("fixed",)


def numbers(text: str | None, count: int) -> tuple[float, ...] | None:
    """``count`` floats of an attribute, or None when absent or malformed (malformed is reported elsewhere)."""
    if text is None:
        return None
    try:
        values = tuple(float(x) for x in text.split())
    except ValueError:
        return None
    return values if len(values) == count and all(math.isfinite(v) for v in values) else None


def _pose(el: Any) -> np.ndarray:
    """4x4 of an ``<origin xyz rpy>`` child (identity when absent or malformed)."""
    from ..se3 import matrix_from_rpy

    T = np.eye(4)
    o = el.find("origin") if el is not None else None
    if o is None:
        return T
    T[:3, 3] = numbers(o.get("xyz"), 3) or (0.0, 0.0, 0.0)
    T[:3, :3] = matrix_from_rpy(np.array(numbers(o.get("rpy"), 3) or (0.0, 0.0, 0.0)))
    return T


@dataclass
class Geometry:
    """A visual or collision shape: ``kind`` box/cylinder/sphere/mesh, MJCF-style half sizes for primitives."""

    role: str
    kind: str
    size: tuple[float, float, float] | None
    filename: str | None
    scale: tuple[float, float, float]
    pose: np.ndarray
    line: int


@dataclass
class RawLink:
    name: str
    line: int
    el: Any
    mass: float | None = None
    mass_text: str | None = None
    com: np.ndarray = field(default_factory=lambda: np.zeros(3))
    inertia: np.ndarray | None = None    # 3x3 about the COM, in the inertial frame's axes
    inertial_pose: np.ndarray = field(default_factory=lambda: np.eye(4))
    inertial_line: int | None = None
    has_inertial: bool = False
    geometries: list[Geometry] = field(default_factory=list)
    #: a name robkin's reader made (MJCF's bodyI, BODY/JOINT, site:NAME; SDF's CHILD@JOINT): no name checks
    synthetic: bool = False
    #: a frame between a body's joints (MJCF BODY/JOINT, SDF CHILD@JOINT), not a body: no mass expected
    frame_only: bool = False
    #: where the mass comes from when not an <inertial> ("geoms": MJCF's inertiafromgeom)
    mass_from: str = ""


@dataclass
class RawJoint:
    name: str
    line: int
    el: Any
    type: str
    parent: str | None
    child: str | None
    origin: np.ndarray
    axis_text: str | None
    limit: Any
    mimic: Any
    # the same, format-neutral (every format's reader fills these; the checks read only them):
    #: <limit> attributes as written (lower, upper, effort, velocity; absent keys missing), None: no limit
    limit_text: dict[str, str] | None = None
    limit_line: int | None = None
    axis_line: int | None = None
    #: the joint a mimic (MJCF: a joint equality) follows ("" when the element names none); None: no mimic
    mimic_target: str | None = None
    mimic_line: int | None = None
    synthetic: bool = False    # a weld or frame joint robkin's reader made (MJCF NAME:fixed, SDF NAME:child)


@dataclass
class RawUrdf:
    file: str
    root: Any
    name: str | None
    links: list[RawLink]
    joints: list[RawJoint]
    declaration: str = ""    # the file's own <?xml ...?> line, written back by --fix
    #: the format read ("urdf", "mjcf", "sdf", "document"): checks of one format's own rules (urdfdom's
    #: required <limit effort velocity>) and the words of what each simulator does depend on it
    fmt: str = "urdf"

    @property
    def link_word(self) -> str:
        """What the format calls a link, for the findings' ``element``."""
        return "body" if self.fmt == "mjcf" else "link"


def _geometry(role: str, el: Any) -> Geometry | None:
    g = el.find("geometry")
    shapes = [c for c in g if isinstance(c.tag, str)] if g is not None else []
    if not shapes:
        return None
    shape = shapes[0]
    kind, size, filename, scale = shape.tag, None, None, (1.0, 1.0, 1.0)
    if kind == "box":
        s = numbers(shape.get("size"), 3)
        size = (s[0] / 2, s[1] / 2, s[2] / 2) if s else None
    elif kind == "cylinder":
        r, h = numbers(shape.get("radius"), 1), numbers(shape.get("length"), 1)
        size = (r[0], h[0] / 2, 0.0) if r and h else None
    elif kind == "sphere":
        r = numbers(shape.get("radius"), 1)
        size = (r[0], 0.0, 0.0) if r else None
    elif kind == "mesh":
        filename = shape.get("filename")
        scale = numbers(shape.get("scale"), 3) or (1.0, 1.0, 1.0)
    else:
        return None
    return Geometry(role, kind, size, filename, scale, _pose(el), shape.sourceline or el.sourceline)


def _link(el: Any) -> RawLink:
    link = RawLink(el.get("name") or "", el.sourceline or 0, el)
    inertial = el.find("inertial")
    if inertial is not None:
        link.has_inertial, link.inertial_line = True, inertial.sourceline
        link.inertial_pose = _pose(inertial)
        link.com = link.inertial_pose[:3, 3].copy()
        m = inertial.find("mass")
        if m is not None:
            link.mass_text = m.get("value")
            v = numbers(link.mass_text, 1)
            link.mass = v[0] if v else None
        i = inertial.find("inertia")
        if i is not None:
            vals = [numbers(i.get(k), 1) for k in ("ixx", "iyy", "izz", "ixy", "iyz", "ixz")]
            if all(vals):
                xx, yy, zz, xy, yz, xz = (v[0] for v in vals)  # type: ignore[index]
                R = link.inertial_pose[:3, :3]
                link.inertia = R @ np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]) @ R.T
    for role in ("visual", "collision"):
        for g in el.findall(role):
            geo = _geometry(role, g)
            if geo is not None:
                link.geometries.append(geo)
    return link


def _joint(el: Any) -> RawJoint:
    p, c = el.find("parent"), el.find("child")
    axis, limit, mimic = el.find("axis"), el.find("limit"), el.find("mimic")
    line = el.sourceline or 0
    return RawJoint(el.get("name") or "", line, el, el.get("type") or "",
                    p.get("link") if p is not None else None, c.get("link") if c is not None else None,
                    _pose(el), axis.get("xyz") if axis is not None else None, limit, mimic,
                    dict(limit.attrib) if limit is not None else None, limit.sourceline if limit is not None else None,
                    axis.sourceline if axis is not None else line,
                    (mimic.get("joint") or "") if mimic is not None else None,
                    mimic.sourceline if mimic is not None else None)


def parse_urdf_text(text: str, source: str) -> RawUrdf:
    """The tolerant tree of URDF text; InputError only when it is not XML or not a ``<robot>``."""
    from lxml import etree  # type: ignore[import-untyped, unused-ignore]

    from ..io.trees.xml_parse import _refuse_dtd

    _refuse_dtd(text, source)
    # comments kept: --fix writes the tree back, and the reader's find/findall skip them
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False, huge_tree=False,
                             remove_comments=False, remove_pis=True, encoding="utf-8")
    try:
        root = etree.fromstring(text.encode("utf-8", "surrogatepass"), parser)
    except etree.XMLSyntaxError as exc:
        line, col = getattr(exc, "position", (None, None))
        raise InputError(f"{source}: not well-formed XML" + (f" (line {line}, column {col})" if line else "")) from None
    except (ValueError, RecursionError, UnicodeError) as exc:
        raise InputError(f"{source}: not valid XML ({exc})") from None
    if root.tag != "robot":
        raise InputError(f"{source}: root element is <{root.tag}>, not a URDF <robot>")
    links = [_link(el) for el in root.findall("link")]
    joints = [_joint(el) for el in root.findall("joint")]
    head = text.lstrip("\ufeff")
    declaration = head[:head.index("?>") + 2] if head.startswith("<?xml") and "?>" in head[:200] else ""
    return RawUrdf(source, root, root.get("name"), links, joints, declaration)


def read_urdf(path: str, allow_xacro: bool = False) -> RawUrdf:
    """The tolerant tree of a .urdf file (a .xacro expanded with ``allow_xacro``; its lines are the expansion's)."""
    from ..io.urdf.parser import _read_source

    text, source = _read_source(path, allow_xacro=allow_xacro)
    return parse_urdf_text(text, source)
