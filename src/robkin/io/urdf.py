"""URDF in and out: a serial chain of a URDF file as a Robot, and a Robot as a URDF.

This module parses a URDF into a ``UrdfModel`` (the tree of links and joints; the contents of links,
visuals, collisions and inertials, are parsed only when asked for, by ``urdf_content``; the XML
itself by ``urdf_xml``; a joint is a ``urdf_joint.UrdfJoint`` whose numbers stay plain floats, composed
as ``pose_rows``). ``robot_from_model`` (in ``urdf_chain``) picks a serial chain out of the tree
and ``urdf_from_robot`` (in ``urdf_write``) writes a robot back; both are importable from here.

Import (``robot_from_urdf``)
    revolute, continuous (revolute without limits), prismatic and fixed joints; any joint axis (a
    non-unit axis is normalised with a ``ProjectionWarning``) and any ``rpy`` origin. Fixed joints are
    folded into the neighbouring transforms. A serial chain is picked from a tree with
    ``base_link``/``tip_link``; either may be any link rigidly attached (through fixed joints, in
    either direction) to the chain's ends. Everything else the file says (link names, visuals,
    collisions, inertials, the links off the chain, joint effort/velocity/dynamics/mimic) is kept in
    ``Robot.bodies`` and ``Joint``; mesh files are never opened, so ``package://`` references need not
    resolve. The XML must have no DTD (so no entities of any kind); transmissions, ``<gazebo>`` and
    other extensions are ignored.

    The GJD: joint i's frame is its child link's frame at q = 0, turned so that its z axis is the
    (normalised) joint axis; the URDF joint position then *is* robkin's q_i (same sign, same zero).
    When the axis points against its link frame's z (negative z component), the joint gets ``flip``
    and the frame turned minimally onto -axis is used for frame-based tables, so an axis ``0 0 -1``
    gives RPY-XYZ rows equal to the URDF origins. The tool is the tip link frame; the links above the
    base link (typically a fixed ``world`` link) become ``Robot.world``.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any, Iterable, Mapping, Sequence

import numpy as np

from ..compiled import pose_rows
from .files import read_text_file
from .urdf_joint import UrdfJoint
from .urdf_xml import _extras, _may_hold_xacro, _parse_urdf_xml
from .urdf_xml import _parse_xml as _parse_xml  # re-exported: the MJCF and SDF readers import it from here
from ..bodies import Inertial, LazyTuple, Mimic, Shape
from ..errors import InputError
from ..lazy_exports import lazy_exports

__all__ = ["robot_from_urdf", "robot_from_model", "urdf_from_robot", "parse_urdf", "parse_urdf_text",
           "UrdfModel", "UrdfJoint", "LinkContent", "axis_frame", "origin_matrix"]

#: Largest URDF read. Vendor URDFs of whole humanoids are ~1 MB; this stops accidental huge inputs.
MAX_BYTES = 64 * 1024 * 1024
#: A joint axis whose norm differs from 1 by more than this is normalised with a warning; below it
#: the difference is decimal rounding of a typed unit vector (e.g. 0.707107) and is fixed silently.
AXIS_UNIT_TOL = 1e-6
#: A joint axis shorter than this is no direction at all (URDF axes are unit vectors, typed with a
#: few decimals; anything this short is a zero or a typo).
AXIS_ZERO_TOL = 1e-9
#: URDF has no way to say "no limit" on a prismatic joint (urdfdom, and so pinocchio, refuse ``inf``),
#: so a missing limit is written as +-NO_LIMIT and a limit at least this large is read as none. No real
#: joint travels 1e10 m or rad; the value is finite in float32 too (MuJoCo's limits).
NO_LIMIT = 1e10
#: Largest magnitude accepted for an origin or axis number. Norms square their inputs, so numbers
#: near 1e154 would overflow float64 in robot size and tolerance computations; 1e100 leaves margin
#: and is still absurd for any length unit.
MAX_ABS = 1e100
#: The one-line refusal of a .xacro file read without the opt-in (why, and the two ways out).
XACRO_REFUSED = ("{path}: not expanded: a .xacro file is a program (it can run code, read files and environment "
                 "variables); if you trust it, pass allow_xacro=True or expand it "
                 "yourself: xacro {path} > {stem}.urdf")
SUPPORTED_TYPES = ("revolute", "continuous", "prismatic", "fixed")
UNSUPPORTED_TYPES = ("floating", "planar")


@dataclass(frozen=True)
class LinkContent:
    """What a link holds besides its frame: shapes and mass properties, with poses relative to the
    link frame (``Shape.body`` and ``Inertial.body`` are 0 here; the chain reader assigns bodies)."""

    shapes: tuple[Shape, ...] = ()
    inertial: Inertial | None = None


@dataclass(frozen=True, eq=False)
class UrdfModel:
    """The tree of a URDF: robot name, links in file order, joints, and the links' contents.

    ``content`` maps a link name to its ``LinkContent`` (missing: an empty link). Readers of other
    formats (MJCF, SDF) may fill it with a plain dict. ``extras`` gives the top-level elements robkin
    does not interpret (transmissions, Gazebo and ros2_control tags) as XML text, for the URDF writer.
    """

    name: str | None
    links: tuple[str, ...]
    joints: tuple[UrdfJoint, ...]
    source: str
    content: Mapping[str, LinkContent] = field(default_factory=dict)
    extras: Sequence[str] = ()

    def parent_joint(self) -> dict[str, UrdfJoint]:
        """link name -> the joint whose child it is (made once; callers must not change it)."""
        return self._parent_joint

    def children(self) -> dict[str, list[UrdfJoint]]:
        """link name -> the joints whose parent it is, in file order (made once; not to be changed)."""
        return self._children

    @cached_property
    def _parent_joint(self) -> dict[str, UrdfJoint]:
        return {j.child: j for j in self.joints}

    @cached_property
    def _children(self) -> dict[str, list[UrdfJoint]]:
        out: dict[str, list[UrdfJoint]] = {name: [] for name in self.links}
        for j in self.joints:
            out[j.parent].append(j)
        return out

    def root(self) -> str:
        parents = self.parent_joint()
        roots = [name for name in self.links if name not in parents]
        return roots[0]

    def leaves(self, below: str) -> list[str]:
        """Leaf links of the subtree under ``below`` (itself if it has no children), in file order."""
        kids = self.children()
        out, stack = [], [below]
        while stack:
            link = stack.pop()
            if not kids[link]:
                out.append(link)
            stack.extend(j.child for j in reversed(kids[link]))
        return out


# ------------------------------------------------------------------------------------------ reading
def _read_source(source: str | os.PathLike[str], allow_xacro: bool = False) -> tuple[str, str]:
    """(XML text, name of the source for messages) from a path or an XML string."""
    if isinstance(source, str) and source.lstrip().startswith("<"):
        return source, "<urdf string>"
    name = os.fspath(source)  # no Path for a plain file: making one costs ~10 us of a small URDF's load
    if os.path.splitext(name)[1].lower() == ".xacro":
        p = Path(name)
        if not allow_xacro:
            raise InputError(XACRO_REFUSED.format(path=p, stem=p.stem))
        return _expand_xacro(p), str(p)
    text = read_text_file(name, MAX_BYTES, "a URDF")
    if not text or text.isspace():
        raise InputError(f"{name}: file is empty; expected a URDF <robot> element")
    return text, name


def _expand_xacro(path: Path) -> str:
    """A .xacro file expanded to URDF text with the optional ``xacro`` package."""
    if not path.is_file():
        raise InputError(f"{path}: no such file")
    try:
        import xacro  # lazy, optional: pip install 'robkin[xacro]'
    except ImportError:
        raise InputError(f"{path}: .xacro input needs the 'xacro' package (pip install 'robkin[xacro]'); "
                         f"or expand it first: xacro {path.name} > robot.urdf") from None
    try:
        doc = xacro.process_file(str(path))
        return doc.toxml()
    except Exception as exc:  # xacro raises many types (XacroException, XML errors, NameError...)
        msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise InputError(f"{path}: xacro expansion failed: {msg}") from None


def numbers(text: str | None, count: int, where: str, what: str | None,
            default: tuple[float, ...]) -> tuple[float, ...]:
    """``count`` finite numbers of bounded size from an attribute's text (``default`` if absent);
    messages name ``where`` (file and element) and ``what`` (the attribute, if not in ``where``)."""
    if text is None:
        return default
    try:
        values = tuple(map(float, text.split()))
    except ValueError:
        values = None
    if values is not None and len(values) == count:
        for v in values:
            if not -MAX_ABS <= v <= MAX_ABS:  # also false for NaN
                break
        else:
            return values
    # the messages, made only for a bad attribute
    at = where if what is None else f"{where}: {what}"
    wanted = "a number" if count == 1 else f"{count} numbers"
    if values is None:
        raise InputError(f"{at}: '{text}' is not {wanted}")
    if len(values) != count:
        raise InputError(f"{at}: '{text}' has {len(values)} numbers; expected {wanted}")
    v = next(v for v in values if not -MAX_ABS <= v <= MAX_ABS)
    bad = "contains NaN or infinity" if not math.isfinite(v) else f"has a number beyond +-{MAX_ABS:g}"
    raise InputError(f"{at}: '{text}' {bad}; expected {count} finite numbers of a robot's size")


def _floats(text: str | None, count: int, where: str, default: Iterable[float]) -> np.ndarray:
    """``numbers`` as an array (the form the MJCF and SDF readers use)."""
    return np.array(numbers(text, count, where, None, tuple(default)), dtype=float)


def _number(text: str | None, where: str, what: str, infinite_ok: bool = False) -> float | None:
    """One number from an attribute's text (finite unless ``infinite_ok``), None if absent."""
    if text is None:
        return None
    try:
        v = float(text)
    except ValueError:
        raise InputError(f"{where}: {what}: '{text}' is not a number") from None
    if math.isnan(v) or not (infinite_ok or math.isfinite(v)):
        raise InputError(f"{where}: {what}: '{text}' is NaN or infinite; expected a finite number")
    return v


def _limit(text: str, where: str, what: str) -> float | None:
    """A joint limit; None (no limit on that side) at +-inf or beyond +-NO_LIMIT, as written out."""
    v = _number(text, where, what, infinite_ok=True)
    return v if v is not None and abs(v) < NO_LIMIT else None


ZERO3 = (0.0, 0.0, 0.0)
ZERO6 = ZERO3 + ZERO3
X_AXIS = (1.0, 0.0, 0.0)  # URDF's default joint axis


def origin_matrix(xyz: tuple[float, ...], rpy: tuple[float, ...]) -> np.ndarray:
    """Pose (4, 4) of a URDF origin: translation xyz, rotation Rz(yaw) Ry(pitch) Rx(roll)."""
    return pose_rows.matrix(pose_rows.from_xyz_rpy(xyz, rpy))


def first_children(el: Any) -> dict[str, Any]:
    """The first child element of each tag (one pass over the children, backwards so that the first
    of a tag is the one kept; lxml makes an object for every element it hands out, so one pass beats
    a ``find`` per tag)."""
    return {c.tag: c for c in reversed(el)}


def origin_numbers(origin_el: Any, where: str) -> tuple[float, ...]:
    """The six numbers xyz + rpy of an <origin> element (zeros for None or a missing attribute)."""
    if origin_el is None:
        return ZERO6
    return (numbers(origin_el.get("xyz"), 3, where, "origin xyz", ZERO3)
            + numbers(origin_el.get("rpy"), 3, where, "origin rpy", ZERO3))


def parse_origin(el: Any, where: str) -> tuple[np.ndarray, tuple[float, ...]]:
    """(pose (4, 4), the six numbers xyz + rpy) of an element's <origin> child (identity if none)."""
    xyz_rpy = origin_numbers(el.find("origin"), where)
    return origin_matrix(xyz_rpy[:3], xyz_rpy[3:]), xyz_rpy


def _joint(el: Any, source: str, index: int) -> UrdfJoint:
    """One <joint> element, every attribute checked (the numbers stay plain floats: see UrdfJoint)."""
    get = el.get
    name = get("name")
    if not name:
        raise InputError(f"{source}: joint #{index + 1} has no name attribute")
    where = f"{source}: joint '{name}'"
    jtype = get("type")
    if jtype not in SUPPORTED_TYPES:
        if jtype is None:
            raise InputError(f"{where}: no type attribute; one of {', '.join(SUPPORTED_TYPES)}")
        if jtype not in UNSUPPORTED_TYPES:
            raise InputError(f"{where}: unknown type '{jtype}'; one of "
                             f"{', '.join(SUPPORTED_TYPES + UNSUPPORTED_TYPES)}")
    kids = first_children(el)
    sub = kids.get("parent")
    parent = None if sub is None else sub.get("link")
    if not parent:
        raise InputError(f"{where}: missing <parent link=\"...\"/>")
    sub = kids.get("child")
    child = None if sub is None else sub.get("link")
    if not child:
        raise InputError(f"{where}: missing <child link=\"...\"/>")
    xyz_rpy = origin_numbers(kids.get("origin"), where)
    axis_el = kids.get("axis")
    axis = numbers(None if axis_el is None else axis_el.get("xyz"), 3, where, "axis xyz", X_AXIS)
    lower = upper = effort = velocity = damping = friction = mimic = None
    lim = kids.get("limit")
    if lim is not None:
        effort = _number(lim.get("effort"), where, "limit effort")
        velocity = _number(lim.get("velocity"), where, "limit velocity")
        if jtype in ("revolute", "prismatic"):
            # URDF: lower/upper default to 0 when <limit> is present but an attribute is not
            lower = _limit(lim.get("lower", "0"), where, "limit lower")
            upper = _limit(lim.get("upper", "0"), where, "limit upper")
            if lower is not None and upper is not None and lower > upper:
                raise InputError(f"{where}: limit lower {lower} > upper {upper}")
    dyn = kids.get("dynamics")
    if dyn is not None:
        damping = _number(dyn.get("damping"), where, "dynamics damping")
        friction = _number(dyn.get("friction"), where, "dynamics friction")
    mim = kids.get("mimic")
    if mim is not None:
        if not mim.get("joint"):
            raise InputError(f"{where}: <mimic> has no joint attribute")
        mult = _number(mim.get("multiplier"), where, "mimic multiplier")
        off = _number(mim.get("offset"), where, "mimic offset")
        mimic = Mimic(mim.get("joint"), 1.0 if mult is None else mult, 0.0 if off is None else off)
    return UrdfJoint(name, jtype, parent, child, None, axis, lower, upper, mimic,  # type: ignore[arg-type]
                     effort, velocity, damping, friction, xyz_rpy)


def parse_urdf(source: str | os.PathLike[str], *, allow_xacro: bool = False) -> UrdfModel:
    """Parse and validate the kinematic tree of a URDF (path, .xacro path, or XML string).

    A .xacro path is expanded only with ``allow_xacro=True``: xacro evaluates Python expressions and
    reads files and environment variables named in the file, so only trusted files may be expanded.

    Checks: a <robot> root; unique link and joint names; every joint's parent and child link exist;
    each link has at most one parent joint; one root link; no cycles. Messages name file, joint, link.
    """
    text, src = _read_source(source, allow_xacro)
    return parse_urdf_text(text, src)


def parse_urdf_text(text: str, src: str = "<urdf string>") -> UrdfModel:
    """``parse_urdf`` of URDF text; ``src`` names it in messages."""
    from .urdf_content import LazyLinkContent

    root = _parse_urdf_xml(text, src)
    if _may_hold_xacro(text) and next(root.iterfind(".//{http://www.ros.org/wiki/xacro}*"), None) is not None:
        raise InputError(f"{src}: contains xacro macros; give the file a .xacro extension and, if you trust it, "
                         f"pass allow_xacro=True, or expand it first: xacro {Path(src).name} > robot.urdf")
    if root.tag != "robot":
        raise InputError(f"{src}: root element is <{root.tag}>; a URDF has <robot>")
    link_els: list[Any] = []
    joint_els: list[Any] = []
    material_els: list[Any] = []
    kinds = {"link": link_els, "joint": joint_els, "material": material_els}
    for el in root:  # one pass over the top level (lxml makes an object for each element visited)
        kind = kinds.get(el.tag)
        if kind is not None:
            kind.append(el)
    links: list[str] = []
    known: set[str] = set()
    link_elements = {}
    for i, el in enumerate(link_els):
        name = el.get("name")
        if not name:
            raise InputError(f"{src}: link #{i + 1} has no name attribute")
        if name in known:
            raise InputError(f"{src}: duplicate link name(s) '{name}'")
        known.add(name)
        links.append(name)
        link_elements[name] = el
    if not links:
        raise InputError(f"{src}: no <link> elements; a URDF robot needs links joined by joints")
    joints = [_joint(el, src, i) for i, el in enumerate(joint_els)]
    names: set[str] = set()
    for j in joints:
        if j.name in names:
            raise InputError(f"{src}: duplicate joint name(s) '{j.name}'")
        names.add(j.name)
    parent_of: dict[str, str] = {}
    for j in joints:
        for role, link in (("parent", j.parent), ("child", j.child)):
            if link not in known:
                raise InputError(f"{src}: joint '{j.name}': {role} link '{link}' is not a <link> of the file")
        if j.parent == j.child:
            raise InputError(f"{src}: joint '{j.name}': parent and child are the same link '{j.child}'")
        if j.child in parent_of:
            raise InputError(f"{src}: link '{j.child}' has two parent joints, '{parent_of[j.child]}' and "
                             f"'{j.name}'; a URDF is a tree")
        parent_of[j.child] = j.name
    roots = [name for name in links if name not in parent_of]
    content = LazyLinkContent(link_elements, material_els, src)
    model = UrdfModel(root.get("name"), tuple(links), tuple(joints), src, content, LazyTuple(lambda: _extras(root)))
    if not roots:
        raise InputError(f"{src}: the joints form a cycle (every link has a parent); a URDF is a tree")
    reach = {roots[0]}
    kids = model.children()
    stack = [roots[0]]
    while stack:
        for j in kids[stack.pop()]:
            reach.add(j.child)
            stack.append(j.child)
    if len(reach) < len(links):
        lost = [name for name in links if name not in reach]
        cyc = [name for name in lost if name in parent_of]
        if len(roots) == 1 and cyc:
            raise InputError(f"{src}: the joints form a cycle through link(s) {', '.join(cyc[:6])}; a URDF is a tree")
        raise InputError(f"{src}: the links are not connected: several root links "
                         f"({', '.join(roots[:8])}); join them with joints or remove the extra ones")
    return model


# the chain reader and the writer, importable from here, imported on first use: they import this
# module's parser (so either can be imported first), and loading a URDF for its kinematics does not
# pay for the writer (see robkin.lazy_exports)
__getattr__, __dir__ = lazy_exports(__name__, globals(), {
    **dict.fromkeys(("axis_frame", "robot_from_model", "robot_from_urdf"), ".urdf_chain"),
    "urdf_from_robot": ".urdf_write"})

if TYPE_CHECKING:
    from .urdf_chain import axis_frame, robot_from_model, robot_from_urdf
    from .urdf_write import urdf_from_robot
