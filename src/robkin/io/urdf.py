"""URDF in and out: a serial chain of a URDF file as a Robot, and a Robot as a URDF.

Import (``robot_from_urdf``)
    revolute, continuous (revolute without limits), prismatic and fixed joints; any joint axis (a
    non-unit axis is normalised with a ``ProjectionWarning``) and any ``rpy`` origin. Fixed joints are
    folded into the neighbouring transforms. Meshes, inertias, transmissions and plugins are ignored:
    only kinematics is read, so ``package://`` references never need to resolve. A serial chain is
    picked from a tree with ``base_link``/``tip_link``. The XML is parsed with defusedxml (no entity
    expansion, no external entities, no DTD tricks).

    The GJD: joint i's frame is the product of the origins from the base link up to joint i, turned
    so that its z axis is the (normalised) joint axis; the URDF joint position then *is* robkin's q_i
    (same sign, same zero). When the axis points against its link frame's z (negative z component),
    the joint gets ``flip`` and the frame turned minimally onto -axis is used for frame-based tables,
    so an axis ``0 0 -1`` gives RPY-XYZ rows equal to the URDF origins. The tool is the tip link
    frame; the links above the base link (typically a fixed ``world`` link) become ``Robot.world``.

Export (``urdf_from_robot``)
    links ``world``, ``base``, one per joint and ``tool``; each joint's origin relative to the
    previous joint frame, axis ``0 0 1`` (``0 0 -1`` for a flipped joint), limits, and the
    world->base transform as a fixed joint. Numbers are written with ``repr`` (full precision).
"""

from __future__ import annotations

import math
import os
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Iterable

import numpy as np

from .. import se3
from .files import read_text_file
from .xmltext import quoteattr
from ..errors import InputError, ProjectionWarning, quote
from ..names import duplicates
from ..robot import Joint, Robot

__all__ = ["robot_from_urdf", "robot_from_model", "urdf_from_robot", "parse_urdf", "parse_urdf_text",
           "UrdfModel", "UrdfJoint", "axis_frame"]

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
                 "variables); if you trust it, pass --allow-xacro (Python: allow_xacro=True) or expand it "
                 "yourself: xacro {path} > {stem}.urdf")
SUPPORTED_TYPES = ("revolute", "continuous", "prismatic", "fixed")
UNSUPPORTED_TYPES = ("floating", "planar")


@dataclass(frozen=True)
class UrdfJoint:
    """One <joint> element, parsed: origin (4, 4), unit axis (3,), limits (None where absent)."""

    name: str
    type: str
    parent: str
    child: str
    origin: np.ndarray
    axis: np.ndarray
    lower: float | None
    upper: float | None
    mimic: bool


@dataclass(frozen=True)
class UrdfModel:
    """The kinematic tree of a URDF: robot name, links in file order, joints by child link."""

    name: str | None
    links: tuple[str, ...]
    joints: tuple[UrdfJoint, ...]
    source: str

    def parent_joint(self) -> dict[str, UrdfJoint]:
        return {j.child: j for j in self.joints}

    def children(self) -> dict[str, list[UrdfJoint]]:
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
def _read_source(source: str | os.PathLike, allow_xacro: bool = False) -> tuple[str, str]:
    """(XML text, name of the source for messages) from a path or an XML string."""
    if isinstance(source, str) and source.lstrip().startswith("<"):
        return source, "<urdf string>"
    p = Path(source)
    if p.suffix.lower() == ".xacro":
        if not allow_xacro:
            raise InputError(XACRO_REFUSED.format(path=p, stem=p.stem))
        return _expand_xacro(p), str(p)
    text = read_text_file(p, MAX_BYTES, "a URDF")
    if not text.strip():
        raise InputError(f"{p}: file is empty; expected a URDF <robot> element")
    return text, str(p)


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


def _parse_xml(text: str, source: str):
    """Root element of hardened-parsed XML; InputError for malformed or dangerous XML."""
    from defusedxml import DefusedXmlException
    from defusedxml.ElementTree import ParseError, fromstring

    try:
        # forbid_dtd: a URDF never needs a DTD, and refusing it outright also stops entity tricks.
        return fromstring(text, forbid_dtd=True, forbid_entities=True, forbid_external=True)
    except DefusedXmlException as exc:
        kind = type(exc).__name__
        raise InputError(f"{source}: refused XML construct ({kind}); a URDF needs no DTD, entities or "
                         f"external references") from None
    except ParseError as exc:
        line, col = getattr(exc, "position", (None, None))
        where = f" (line {line}, column {col + 1})" if line else ""
        raise InputError(f"{source}: not well-formed XML{where}") from None
    except (ValueError, RecursionError) as exc:
        raise InputError(f"{source}: not valid XML ({exc})") from None


def _floats(text: str | None, count: int, where: str, default: Iterable[float]) -> np.ndarray:
    if text is None:
        return np.array(list(default), dtype=float)
    parts = text.split()
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise InputError(f"{where}: '{text}' is not {count} numbers") from None
    if len(values) != count:
        raise InputError(f"{where}: '{text}' has {len(values)} numbers; expected {count}")
    if not all(math.isfinite(v) for v in values):
        raise InputError(f"{where}: '{text}' contains NaN or infinity; expected {count} finite numbers")
    if any(abs(v) > MAX_ABS for v in values):
        raise InputError(f"{where}: '{text}' has a number beyond +-{MAX_ABS:g}; no robot is that large")
    return np.array(values)


def _limit(text: str | None, where: str) -> float | None:
    if text is None:
        return None
    try:
        v = float(text)
    except ValueError:
        raise InputError(f"{where}: '{text}' is not a number") from None
    if math.isnan(v):
        raise InputError(f"{where}: is NaN; expected a number")
    return v if abs(v) < NO_LIMIT else None  # no limit on that side (as urdf_from_robot writes it)


def _joint(el, source: str, index: int) -> UrdfJoint:
    name = el.get("name")
    if not name:
        raise InputError(f"{source}: joint #{index + 1} has no name attribute")
    where = f"{source}: joint '{name}'"
    jtype = el.get("type")
    if jtype is None:
        raise InputError(f"{where}: no type attribute; one of {', '.join(SUPPORTED_TYPES)}")
    if jtype not in SUPPORTED_TYPES + UNSUPPORTED_TYPES:
        raise InputError(f"{where}: unknown type '{jtype}'; one of {', '.join(SUPPORTED_TYPES + UNSUPPORTED_TYPES)}")
    links = []
    for tag in ("parent", "child"):
        sub = el.find(tag)
        if sub is None or not sub.get("link"):
            raise InputError(f"{where}: missing <{tag} link=\"...\"/>")
        links.append(sub.get("link"))
    origin_el = el.find("origin")
    xyz = _floats(None if origin_el is None else origin_el.get("xyz"), 3, f"{where}: origin xyz", (0, 0, 0))
    rpy = _floats(None if origin_el is None else origin_el.get("rpy"), 3, f"{where}: origin rpy", (0, 0, 0))
    origin = se3.homogeneous(se3.matrix_from_rpy(rpy), xyz)
    axis_el = el.find("axis")
    axis = _floats(None if axis_el is None else axis_el.get("xyz"), 3, f"{where}: axis xyz", (1, 0, 0))
    lower = upper = None
    lim = el.find("limit")
    if lim is not None and jtype in ("revolute", "prismatic"):
        # URDF: lower/upper default to 0 when <limit> is present but an attribute is not
        lower = _limit(lim.get("lower", "0"), f"{where}: limit lower")
        upper = _limit(lim.get("upper", "0"), f"{where}: limit upper")
        if lower is not None and upper is not None and lower > upper:
            raise InputError(f"{where}: limit lower {lower} > upper {upper}")
    return UrdfJoint(name, jtype, links[0], links[1], origin, axis, lower, upper, el.find("mimic") is not None)


def parse_urdf(source: str | os.PathLike, *, allow_xacro: bool = False) -> UrdfModel:
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
    root = _parse_xml(text, src)
    if any(isinstance(el.tag, str) and el.tag.startswith("{http://www.ros.org/wiki/xacro}") for el in root.iter()):
        raise InputError(f"{src}: contains xacro macros; give the file a .xacro extension and, if you trust it, "
                         f"pass --allow-xacro, or expand it first: xacro {Path(src).name} > robot.urdf")
    if root.tag != "robot":
        raise InputError(f"{src}: root element is <{root.tag}>; a URDF has <robot>")
    links = []
    for i, el in enumerate(root.findall("link")):
        name = el.get("name")
        if not name:
            raise InputError(f"{src}: link #{i + 1} has no name attribute")
        links.append(name)
    if not links:
        raise InputError(f"{src}: no <link> elements; a URDF robot needs links joined by joints")
    dup = duplicates(links)
    if dup:
        raise InputError(f"{src}: duplicate link name(s) {', '.join(quote(d) for d in dup[:8])}")
    joints = [_joint(el, src, i) for i, el in enumerate(root.findall("joint"))]
    names = [j.name for j in joints]
    dup = duplicates(names)
    if dup:
        raise InputError(f"{src}: duplicate joint name(s) {', '.join(quote(d) for d in dup[:8])}")
    known = set(links)
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
    model = UrdfModel(root.get("name"), tuple(links), tuple(joints), src)
    if not roots:
        raise InputError(f"{src}: the joints form a cycle (every link has a parent); a URDF is a tree")
    reach = {roots[0]}
    kids = model.children()
    stack = [roots[0]]
    while stack:
        for j in kids[stack.pop()]:
            reach.add(j.child)
            stack.append(j.child)
    lost = [name for name in links if name not in reach]
    if lost:
        cyc = [name for name in lost if name in parent_of]
        if len(roots) == 1 and cyc:
            raise InputError(f"{src}: the joints form a cycle through link(s) {', '.join(cyc[:6])}; a URDF is a tree")
        raise InputError(f"{src}: the links are not connected: several root links "
                         f"({', '.join(roots[:8])}); join them with joints or remove the extra ones")
    return model


def _chain(model: UrdfModel, base_link: str | None, tip_link: str | None
           ) -> tuple[str, list[UrdfJoint], np.ndarray]:
    """(base link, joints base->tip, world->base transform) for the chosen serial chain."""
    src = model.source
    known = set(model.links)
    for opt, link in (("base_link", base_link), ("tip_link", tip_link)):
        if link is not None and link not in known:
            close = ", ".join(sorted(known, key=lambda s: (not s.startswith(link[:3]), s))[:8])
            raise InputError(f"{src}: {opt}='{link}' is not a link of the file (links include: {close})")
    parents = model.parent_joint()
    kids = model.children()
    root = model.root()
    if base_link is None:
        base_link = root
        # a virtual 'world' root fixed to the robot: it is the world->base transform, not the robot
        if root == "world" and len(kids[root]) == 1 and kids[root][0].type == "fixed":
            base_link = kids[root][0].child
    if tip_link is None:
        leaves = model.leaves(base_link)
        if len(leaves) != 1:
            shown = ", ".join(leaves[:24]) + (f", ... ({len(leaves) - 24} more)" if len(leaves) > 24 else "")
            raise InputError(f"{src}: the links below '{base_link}' form a tree with {len(leaves)} leaf links; "
                             f"pick the chain's end with tip_link=, one of: {shown}")
        tip_link = leaves[0]
    path: list[UrdfJoint] = []
    link = tip_link
    while link != base_link:
        if link not in parents:
            raise InputError(f"{src}: tip_link='{tip_link}' is not below base_link='{base_link}' "
                             f"(links below it end in: {', '.join(model.leaves(base_link))})")
        j = parents[link]
        path.append(j)
        link = j.parent
    path.reverse()
    # world -> base: the origins from the root down to the base link, with joints there held at 0
    above: list[UrdfJoint] = []
    link = base_link
    while link in parents:
        above.append(parents[link])
        link = parents[link].parent
    moving = [j.name for j in above if j.type != "fixed"]
    if moving:
        warnings.warn(f"{src}: joint(s) {', '.join(reversed(moving))} above base link '{base_link}' are held "
                      f"at 0 in the world->base transform", UserWarning, stacklevel=3)
    world = np.eye(4)
    for j in reversed(above):
        world = world @ j.origin
    return base_link, path, world


def axis_frame(axis: np.ndarray) -> tuple[np.ndarray, bool]:
    """Rotation (3, 3) whose z column is the unit ``axis``, and whether the joint is flipped.

    Axes with a non-negative z component get the minimal rotation taking z onto the axis (identity for
    ``0 0 1``). Axes pointing against z get flip = True and the minimal rotation onto -axis, turned
    by pi about x: its z is the axis, and the flipped frame used by DH/RPY tables is the minimal one.
    """
    flip = bool(axis[2] < 0)
    b = -axis if flip else axis
    # minimal rotation e_z -> b (b_z >= 0): R = I + K + K^2 / (1 + c), K = [e_z x b], c = b_z;
    # 1 + c >= 1, so this is well conditioned for every b in the upper half sphere.
    K = se3.skew(np.array([-b[1], b[0], 0.0]))
    R = np.eye(3) + K + K @ K / (1.0 + b[2])
    if flip:
        R = R @ np.diag([1.0, -1.0, -1.0])  # Rx(pi)
    return R, flip


def _unit_axis(j: UrdfJoint, src: str) -> np.ndarray:
    k = float(np.linalg.norm(j.axis))
    if k < AXIS_ZERO_TOL:
        raise InputError(f"{src}: joint '{j.name}': axis xyz is zero; a {j.type} joint needs a direction "
                         f"such as '0 0 1'")
    if abs(k - 1.0) > AXIS_UNIT_TOL:
        warnings.warn(f"{src}: joint '{j.name}': axis has length {k:.6g}; normalised to a unit vector",
                      ProjectionWarning, stacklevel=4)
    return j.axis / k


def robot_from_urdf(source: str | os.PathLike, base_link: str | None = None, tip_link: str | None = None,
                    *, name: str | None = None, allow_xacro: bool = False) -> Robot:
    """The serial chain base_link -> tip_link of a URDF (path, .xacro path, or XML string) as a Robot.

    Parameters
    ----------
    source : path or str
        A .urdf or .xacro file, or URDF XML text (a string starting with '<').
    base_link, tip_link : str, optional
        Ends of the chain. Default base: the root link (its child when the root is a ``world`` link
        fixed to it). Default tip: the only leaf below the base; with several an InputError lists them.
    name : str, optional
        Robot name; default the URDF's ``<robot name>``.
    allow_xacro : bool
        Expand a .xacro file (default False: refused). xacro runs code and reads files and
        environment variables named in the file; pass True only for files you trust.

    Returns
    -------
    Robot
        GJD frames (n+1, 4, 4) in the base link frame (lengths in the file's unit, normally metres),
        joints with the URDF names and limits, ``world`` = root link -> base link at q = 0.
    """
    return robot_from_model(parse_urdf(source, allow_xacro=allow_xacro), base_link, tip_link, name=name)


def robot_from_model(model: UrdfModel, base_link: str | None = None, tip_link: str | None = None,
                     *, name: str | None = None) -> Robot:
    """``robot_from_urdf`` of an already parsed URDF (see ``parse_urdf_text`` for text input)."""
    src = model.source
    base, path, world = _chain(model, base_link, tip_link)
    frames: list[np.ndarray] = []
    joints: list[Joint] = []
    T = np.eye(4)
    for j in path:
        if j.type in UNSUPPORTED_TYPES:
            raise InputError(f"{src}: joint '{j.name}' is {j.type}; only revolute, continuous, prismatic and "
                             f"fixed joints make a serial chain (pick another chain with base_link=/tip_link=)")
        if j.mimic:
            raise InputError(f"{src}: joint '{j.name}' mimics another joint; robkin needs independent joints "
                             f"(end the chain before it with tip_link=)")
        T = T @ j.origin
        if j.type == "fixed":
            continue
        R, flip = axis_frame(_unit_axis(j, src))
        F = T.copy()
        F[:3, :3] = T[:3, :3] @ R
        frames.append(F)
        jtype = "prismatic" if j.type == "prismatic" else "revolute"
        joints.append(Joint(j.name, jtype, j.lower, j.upper, flip))  # type: ignore[arg-type]
    if not joints:
        raise InputError(f"{src}: no revolute, continuous or prismatic joint between '{base}' and "
                         f"'{path[-1].child if path else base}'; a robot needs at least one")
    frames.append(T)
    return Robot(np.stack(frames), tuple(joints), world=world, name=name or model.name)


# ------------------------------------------------------------------------------------------ writing
def _num(x: float) -> str:
    """Full-precision text of a float (repr round-trips exactly); exact zeros without a sign."""
    x = float(x)
    return "0" if x == 0 else repr(x)


def _origin(T: np.ndarray) -> str:
    rpy = se3.rpy_from_matrix(T[:3, :3])
    return (f'<origin xyz="{" ".join(_num(v) for v in T[:3, 3])}" '
            f'rpy="{" ".join(_num(v) for v in rpy)}"/>')


def _unique_names(robot: Robot) -> tuple[str, str, list[str], str, str, str]:
    """Names of the links world, base, link1..n, tool and of the two fixed joints, suffixed where a
    robot joint already uses one (pinocchio turns links and joints into frames of one namespace)."""
    taken = {j.name for j in robot.joints}

    def free(s: str) -> str:
        out = s
        while out in taken:
            out += "_"
        taken.add(out)
        return out

    # the root link keeps the name 'world' whatever the joints are called: readers (robkin's
    # included) recognise a fixed 'world' root as the world->base transform
    world, base = "world", free("base")
    links = [free(f"link{i + 1}") for i in range(robot.n)]
    tool = free("tool")
    return world, base, links, tool, free(base + "_fixed"), free(tool + "_fixed")


def urdf_from_robot(robot: Robot) -> str:
    """A URDF (text) of the robot: world, base, one link per joint, tool; FK-identical at every q.

    Joint origins are relative transforms between consecutive joint frames (flip-adjusted, so a
    flipped joint has axis ``0 0 -1``). Revolute joints without limits are ``continuous``; a missing
    limit on one side (or on a prismatic joint, which URDF requires limits for) is written as
    +-``NO_LIMIT`` (1e10), which the reader takes as no limit. Effort and velocity limits, which URDF requires, are written as 0 (robkin carries
    kinematics only).
    """
    from .. import __version__
    from ..representations.dh import flip_frame

    world, base, links, tool, base_joint, tool_joint = _unique_names(robot)
    D = [flip_frame(robot.frames[i], j.flip) for i, j in enumerate(robot.joints)]
    out = ['<?xml version="1.0"?>',
           f"<!-- written by robkin {__version__}: kinematics only (no meshes, no inertias) -->",
           f"<robot name={quoteattr(robot.name or 'robot')}>",
           "  <!-- for MuJoCo's URDF reader: keep fixed links (the tool frame) as bodies, and give the",
           "       massless links a tiny placeholder mass so that the model compiles -->",
           '  <mujoco><compiler fusestatic="false" boundmass="1e-06" boundinertia="1e-12"/></mujoco>',
           f"  <link name={quoteattr(world)}/>",
           f"  <link name={quoteattr(base)}/>",
           f"  <joint name={quoteattr(base_joint)} type=\"fixed\">",
           f"    <parent link={quoteattr(world)}/>",
           f"    <child link={quoteattr(base)}/>",
           f"    {_origin(robot.world)}",
           "  </joint>"]
    prev_name, prev = base, np.eye(4)
    for i, j in enumerate(robot.joints):
        rel = se3.inv(prev) @ D[i]
        unlimited = j.revolute and j.lower is None and j.upper is None
        jtype = "continuous" if unlimited else j.type
        out += [f"  <link name={quoteattr(links[i])}/>",
                f"  <joint name={quoteattr(j.name)} type=\"{jtype}\">",
                f"    <parent link={quoteattr(prev_name)}/>",
                f"    <child link={quoteattr(links[i])}/>",
                f"    {_origin(rel)}",
                f"    <axis xyz=\"0 0 {'-1' if j.flip else '1'}\"/>"]
        if not unlimited:
            lo = _num(-NO_LIMIT if j.lower is None else j.lower)
            hi = _num(NO_LIMIT if j.upper is None else j.upper)
            out.append(f'    <limit lower="{lo}" upper="{hi}" effort="0" velocity="0"/>')
        out.append("  </joint>")
        prev_name, prev = links[i], D[i]
    out += [f"  <link name={quoteattr(tool)}/>",
            f"  <joint name={quoteattr(tool_joint)} type=\"fixed\">",
            f"    <parent link={quoteattr(prev_name)}/>",
            f"    <child link={quoteattr(tool)}/>",
            f"    {_origin(se3.inv(prev) @ robot.tool)}",
            "  </joint>",
            "</robot>", ""]
    return "\n".join(out)
