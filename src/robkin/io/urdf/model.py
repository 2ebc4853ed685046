"""URDF in and out: a serial chain of a URDF file as a Robot, and a Robot as a URDF.

This module parses a URDF into a ``UrdfModel`` (the tree of links and joints, read by one compiled pass
of expat, ``compiled.urdf_scan``, that builds no XML tree; the contents of links, visuals, collisions
and inertials, are parsed from the text only when asked for, by ``urdf_content`` on ``urdf_xml``'s tree;
a joint is a ``urdf_joint.UrdfJoint`` whose numbers stay plain floats, composed as ``pose_rows``).
``robot_from_model`` (in ``urdf_chain``) picks a serial chain out of the tree and ``urdf_from_robot``
(in ``urdf_write``) writes a robot back; both are importable from here.

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

import os
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any, Iterable, Mapping, Sequence

import numpy as np

from ...compiled import pose_rows
from ..files.input_files import read_text_file
from ..trees.tree_joint import UrdfJoint
from ..trees.xml_parse import _extras, _parse_urdf_xml, _refuse_dtd
from ...bodies import LazyTuple
from ...errors import InputError

__all__ = ["parse_urdf", "parse_urdf_text", "UrdfModel", "UrdfJoint", "LinkContent", "origin_matrix"]

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
SUPPORTED_TYPES = ("revolute", "continuous", "prismatic", "fixed")
UNSUPPORTED_TYPES = ("floating", "planar")
#: The one-line refusal of a .xacro file read without the opt-in (why, and the two ways out).
XACRO_REFUSED = ("{path}: not expanded: a .xacro file is a program (it can run code, read files and environment "
                 "variables); if you trust it, pass allow_xacro=True or expand it "
                 "yourself: xacro {path} > {stem}.urdf")


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
        return self.roots()[0]

    def roots(self) -> list[str]:
        """Links without a parent joint, in file order: one for a URDF; an SDF model may hold several
        unconnected trees (see ``sdf_trees``)."""
        parents = self.parent_joint()
        return [name for name in self.links if name not in parents]

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


def _floats(text: str | None, count: int, where: str, default: Iterable[float]) -> np.ndarray:
    """``numbers`` as an array (the form the MJCF and SDF readers use)."""
    from ...compiled.attribute_numbers import numbers  # compiled: loaded by a reader, not by an import

    return np.array(numbers(text, count, where, None, tuple(default)), dtype=float)


def origin_matrix(xyz: tuple[float, ...], rpy: tuple[float, ...]) -> np.ndarray:
    """Pose (4, 4) of a URDF origin: translation xyz, rotation Rz(yaw) Ry(pitch) Rx(roll)."""
    return pose_rows.matrix(pose_rows.from_xyz_rpy(xyz, rpy))


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
    from ...compiled.urdf_scan import scan_urdf  # compiled: loaded by a read, not by an import
    from .content import LazyLinkContent

    _refuse_dtd(text, src)
    name, links, joints = scan_urdf(text, src)
    # the tree is built only if link contents or the extras are asked for, once for both
    tree: list[Any] = []

    def root() -> Any:  # a plain memo: functools.cache builds a wrapper per call (~3 us of a small file's load)
        if not tree:
            tree.append(_parse_urdf_xml(text, src))
        return tree[0]

    return UrdfModel(name, links, joints, src, LazyLinkContent(links, root, src), LazyTuple(lambda: _extras(root())))


if TYPE_CHECKING:
    from ...body_parts import Inertial, Shape
