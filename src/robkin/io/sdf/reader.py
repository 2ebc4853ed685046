"""SDF (SDFormat 1.4+, Gazebo's XML) input: the links and joints of a model as a Robot.

What is read
    ``<link>``, ``<joint>`` (revolute, continuous, prismatic, fixed), explicit ``<frame>``s and
    nested ``<model>``s (their names scoped as ``inner::link``), each ``<pose>`` with ``relative_to``
    (SDFormat 1.8; also ``degrees`` and ``rotation_format="quat_xyzw"`` of 1.9), joint axes
    ``<axis><xyz expressed_in>`` with ``<limit><lower><upper>``; visuals, collisions and inertials as
    ``Robot.bodies`` (see ``sdf_shapes``). Sensors and plugins are ignored; ``<include>`` (a model from
    a URI) is refused.

Default frames (every version)
    a link's or nested model's pose is in its model frame; a joint's pose is in its child link's
    frame; an explicit frame's pose is in the frame it is attached to. A joint axis is in the joint
    frame from 1.5 on (unless ``use_parent_model_frame`` is true or ``expressed_in`` names another
    frame) and in the model frame in 1.4.

The tree becomes a ``UrdfModel`` whose links are the SDF links and frames (a joint whose frame is not
its child link's frame gets an intermediate link ``CHILD@JOINT``) and the chain is picked by the URDF
reader's ``robot_from_model``. q is the SDF joint position (same sign and zero); a joint whose parent
is ``world`` fixes the model in the world (``Robot.world``). Other joint kinds (ball, universal,
screw...) on the chosen chain are refused with one line naming the joint.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ...compiled import pose_rows
from ...compiled.attribute_numbers import numbers
from ...errors import InputError, quote
from ...robot import Robot
from ..trees.chain_path import refuse_on_chain
from ..files.input_files import read_text_file
from .axes import Z_AXIS, axis_dynamics, joint_axis
from ..urdf.chain import robot_from_model
from ..urdf.model import UrdfJoint, UrdfModel

if TYPE_CHECKING:  # pragma: no cover
    from ...compiled.pose_rows import Pose  # twelve floats: the top three rows of a (4, 4) pose
else:
    Pose = tuple

__all__ = ["robot_from_sdf", "model_from_sdf"]

#: Largest SDF read (world files with many models are a few MB; this stops huge inputs).
MAX_BYTES = 64 * 1024 * 1024
#: Nested models deeper than this are refused (real files nest one or two levels).
MAX_NESTING = 16
JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed")
OTHER_JOINTS = ("ball", "universal", "revolute2", "screw", "gearbox")
#: The joint kinds that make a serial chain, as messages word them.
CHAIN_JOINTS = "revolute, continuous, prismatic and fixed"
#: The pose of one frame in another is composed through their nearest common frame of the relative_to
#: graph when that is at most this many steps away (a joint next to its links: 1-3), from the file's own
#: numbers; farther, through the model frame (poses of frames deep in a chain of relative_to carry the
#: rounding of every pose above them, ~1e-16 per step: a 1000-link chain's frames were then no longer
#: rigid to 1e-12). A bound keeps each lookup O(1).
NEAR_STEPS = 8
IDENTITY = pose_rows.IDENTITY
INVERSE_IDENTITY = pose_rows.inverse(IDENTITY)  # the same floats inverse() gives each time, made once
ZEROS6 = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


def the_models(root: Any) -> list[Any]:
    """The ``<model>`` elements of an SDF root: its own, else those of its ``<world>``s."""
    return root.findall("model") or [m for w in root.findall("world") for m in w.findall("model")]


def _version(root: Any, source: str) -> tuple[int, int]:
    text = root.get("version")
    if text is None:
        raise InputError(f"{source}: <sdf> has no version attribute; expected e.g. version=\"1.9\"")
    try:
        major, minor = (int(x) for x in text.split("."))
    except ValueError:
        raise InputError(f"{source}: <sdf version=\"{text}\"> is not a version such as 1.9") from None
    if (major, minor) < (1, 4):
        raise InputError(f"{source}: SDFormat {text} is not read; robkin reads SDFormat 1.4 and later")
    return major, minor


def _pose(el: Any, where: str) -> tuple[Pose, str | None]:
    """(pose (twelve floats, see ``pose_rows``), relative_to or None) of an element's ``<pose>`` child
    (identity when absent)."""
    pose = el.find("pose")
    if pose is None:
        return IDENTITY, None
    text = pose.text
    text = (text.strip() or None) if text else None
    form = pose.get("rotation_format", "euler_rpy")
    if form == "euler_rpy":
        if text is None:  # from_xyz_rpy of six zeros: exactly these floats (its exact branch)
            return IDENTITY, pose.get("relative_to") or None
        v = numbers(text, 6, where, "<pose>", ZEROS6)
        rpy = tuple(math.radians(a) for a in v[3:]) if pose.get("degrees") == "true" else v[3:]
        return pose_rows.from_xyz_rpy(v[:3], rpy), pose.get("relative_to") or None
    at = f"{where}: <pose>"
    if form == "quat_xyzw":
        v = numbers(text, 7, at, None, (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0))
        if math.hypot(*v[3:]) < 1e-10:  # a quaternion this short is a typo; unit quaternions have length 1
            raise InputError(f"{at}: quaternion is zero")
        return pose_rows.from_quat(v[:3], (v[6], v[3], v[4], v[5])), pose.get("relative_to") or None
    raise InputError(f"{at}: rotation_format {quote(pose.get('rotation_format'))} is not euler_rpy or quat_xyzw")


class _Model:
    """The frames of one model file, flattened over nested models, resolved to the outer model frame."""

    def __init__(self, source: str, version: tuple[int, int]):
        self.source = source
        self.version = version
        self.raw: dict[str, tuple[Pose, str]] = {}  # frame -> (pose, frame it is relative to)
        self.kind: dict[str, str] = {}                       # frame -> link | joint | frame | model
        self.attached: dict[str, str] = {}                   # explicit frame -> frame it is attached to
        self.links: list[str] = []
        self.joints: list[tuple[str, Any, str]] = []         # (scoped name, element, scope prefix)
        self.resolved: dict[str, Pose] = {}
        self.up: dict[str, str] = {}     # frame -> the frame its pose is relative to (nested models: X::__model__)
        self.depth: dict[str, int] = {}  # frame -> steps of relative_to from it to the model frame
        self.joint_child: dict[str, str] = {}                # joint -> its child link
        self.child_of: dict[Any, str] = {}                   # <joint> element read above -> its child link
        self.link_elements: list[tuple[str, Any, str]] = []  # (scoped link name, <link>, scope prefix)

    def _frame(self, name: str, kind: str, pose: Pose, rel: str) -> None:
        if name in self.kind:
            raise InputError(f"{self.source}: two {self.kind[name]}/{kind} elements are called '{name}'")
        self.kind[name] = kind
        self.raw[name] = (pose, rel)

    def read(self, model: Any, prefix: str, depth: int) -> None:
        if depth > MAX_NESTING:
            raise InputError(f"{self.source}: models nest more than {MAX_NESTING} levels deep")
        scope = prefix + "__model__"
        if model.find("include") is not None:
            raise InputError(f"{self.source}: model '{prefix}{model.get('name')}': <include> (a model from a URI) is "
                             f"not read; merge the included model into the file")
        for tag in ("link", "frame", "model", "joint"):
            for i, el in enumerate(model.findall(tag)):
                local = el.get("name")
                if not local:
                    raise InputError(f"{self.source}: <{tag}> #{i + 1} of model '{prefix or model.get('name')}' "
                                     f"has no name attribute")
                name = prefix + local
                if tag == "joint":
                    self.joints.append((name, el, prefix))
                    continue  # its frame (by default its child link's) is registered below, after the links
                pose, rel = _pose(el, f"{self.source}: {tag} '{name}'")
                if tag == "frame":
                    attached = self.scoped(el.get("attached_to") or "__model__", prefix)
                    self.attached[name] = attached
                    self._frame(name, "frame", pose, self.scoped(rel, prefix) if rel else attached)
                elif tag == "link":
                    self.links.append(name)
                    self.link_elements.append((name, el, prefix))
                    self._frame(name, "link", pose, self.scoped(rel, prefix) if rel else scope)
                else:
                    self._frame(name + "::__model__", "model", pose, self.scoped(rel, prefix) if rel else scope)
                    self.read(el, name + "::", depth + 1)
        for name, el, p in self.joints:
            if p == prefix and name not in self.kind:
                child = self.scoped(self._text(el, "child", name), prefix)
                self.joint_child[name] = self.child_of[el] = child
                pose, rel = _pose(el, f"{self.source}: joint '{name}'")
                self._frame(name, "joint", pose, self.scoped(rel, prefix) if rel else child)

    def _text(self, el: Any, tag: str, name: str) -> str:
        sub = el.find(tag)
        text = (sub.text or "").strip() if sub is not None else ""
        if not text:
            raise InputError(f"{self.source}: joint '{name}': missing <{tag}>LINK</{tag}>")
        return text

    @staticmethod
    def scoped(name: str, prefix: str) -> str:
        return name if name == "world" else prefix + name

    def _depth(self, name: str, where: str) -> int:
        """Steps of relative_to from frame ``name`` to the model frame, filling ``up`` and ``depth`` along
        the way (InputError for a frame the file does not have, or a loop)."""
        raw = self.raw.get(name) if name != "__model__" else None
        if raw is not None:  # relative_to a frame already resolved (keys of depth are names of raw)
            rel = raw[1]
            d = 0 if rel == "__model__" else self.depth.get(rel)
            if d is not None and rel != name:
                self.depth[name], self.up[name] = d + 1, rel
                return d + 1
        chain, seen = [], set()
        while name != "__model__" and name not in self.depth:
            if name not in self.raw and name + "::__model__" in self.raw:
                name += "::__model__"  # a nested model's name stands for its model frame
            if name not in self.raw:
                raise InputError(f"{where}: frame {quote(name)} is not a link, joint, frame or model of the file")
            if name in seen:
                raise InputError(f"{where}: the poses' relative_to form a loop through '{name}'")
            seen.add(name)
            chain.append(name)
            name = self.raw[name][1]
        depth = 0 if name == "__model__" else self.depth[name]
        for n in reversed(chain):
            depth += 1
            self.depth[n], self.up[n], name = depth, name, n
        return depth

    def pose(self, name: str, where: str) -> Pose:
        """Pose of frame ``name`` in the outermost model frame (q = 0), as twelve floats: the poses
        along its relative_to path composed from the model frame down, each made once."""
        T = self.resolved.get(name)
        if T is not None:
            return T
        self._depth(name, where)
        chain = []
        while name != "__model__" and name not in self.resolved:
            name = name if name in self.raw else name + "::__model__"  # _depth has checked the names
            chain.append(name)
            name = self.up[name]
        T = IDENTITY if name == "__model__" else self.resolved[name]
        for n in reversed(chain):
            T = self.resolved[n] = pose_rows.compose(T, self.raw[n][0])
        return T

    def relative(self, a: str, b: str, where: str) -> Pose:
        """Pose of frame ``b`` in frame ``a`` (q = 0): through their nearest common frame when that is
        at most ``NEAR_STEPS`` away (see there), else through the model frame."""
        depth, up, raw = self.depth, self.up, self.raw
        da = depth.get(a)
        if da is None:
            da = self._depth(a, where)
        db = depth.get(b)
        if db is None:
            db = self._depth(b, where)
        # one frame relative_to the other (a joint and its links): the walk below in one step
        if up.get(b) == a:
            return pose_rows.compose(INVERSE_IDENTITY, pose_rows.compose(raw[b][0], IDENTITY))
        if up.get(a) == b:
            return pose_rows.compose(pose_rows.inverse(pose_rows.compose(raw[a][0], IDENTITY)), IDENTITY)
        a0, b0 = a, b
        a = a if a == "__model__" or a in raw else a + "::__model__"  # _depth has checked the names
        b = b if b == "__model__" or b in raw else b + "::__model__"
        A = B = IDENTITY  # poses of the given a and b in the frames a and b have walked up to
        for _ in range(NEAR_STEPS):
            if a == b:
                return pose_rows.compose(INVERSE_IDENTITY if A is IDENTITY else pose_rows.inverse(A), B)
            if da >= db:
                A, a, da = pose_rows.compose(raw[a][0], A), up[a], da - 1
            else:
                B, b, db = pose_rows.compose(raw[b][0], B), up[b], db - 1
        return pose_rows.compose(pose_rows.inverse(self.pose(a0, where)), self.pose(b0, where))


def model_from_sdf(source: str | os.PathLike[str]) -> tuple[UrdfModel, dict[str, str]]:
    """The kinematic tree of an SDF file (path) or SDF text, and the joints robkin cannot model."""
    from ...compiled.sdf_scan import kinematic_tree
    from .shapes import sdf_content
    from .trees import check_tree
    from ..trees.xml_parse import _refuse_dtd

    folder = None
    if isinstance(source, str) and source.lstrip().startswith("<"):
        text, src = source, "<sdf string>"
    else:
        text, src, folder = read_text_file(Path(source), MAX_BYTES, "an SDF model"), str(source), Path(source).parent
        if not text.strip():
            raise InputError(f"{src}: file is empty; expected an SDF <sdf> element")
    _refuse_dtd(text, src)
    root = kinematic_tree(text, src)  # only the elements read here; sdf_content parses the rest when asked
    if root.tag != "sdf":
        raise InputError(f"{src}: root element is <{root.tag}>; an SDF file has <sdf>")
    version = _version(root, src)
    models = the_models(root)
    if len(models) != 1:
        raise InputError(f"{src}: holds {len(models)} <model> elements; robkin reads a file with one model")
    j = _Model(src, version)
    j.read(models[0], "", 0)
    # the model's pose in the world; used when a joint fixes the model to the world
    world = _pose(models[0], f"{src}: model")[0]
    links = list(j.links) + [name for name in j.attached]
    joints: list[UrdfJoint] = []
    kinds: dict[str, str] = {}
    uses_world = False
    for name, el, prefix in j.joints:
        where = f"{src}: joint '{name}'"
        jtype = el.get("type")
        if jtype not in JOINT_TYPES and jtype not in OTHER_JOINTS:
            raise InputError(f"{where}: type {quote(jtype)} is not one of {', '.join(JOINT_TYPES + OTHER_JOINTS)}")
        parent = j.scoped(j._text(el, "parent", name), prefix)
        child = j.child_of.get(el) or j.scoped(j._text(el, "child", name), prefix)
        if parent != "world" and j.kind.get(parent) != "link":
            raise InputError(f"{where}: parent {quote(parent)} is not a link of the model")
        if child != "world" and j.kind.get(child) != "link":
            raise InputError(f"{where}: child {quote(child)} is not a link of the model")
        # the joint frame in the parent link's (the world's: the model's pose in it)
        origin = pose_rows.compose(world, j.pose(name, where)) if parent == "world" else \
            j.relative(parent, name, where)
        uses_world |= parent == "world"
        # joint frame -> child link frame; exactly the identity when the joint's pose is the default
        rest = j.relative(name, child, where)
        moving = jtype if jtype in JOINT_TYPES else "floating"
        axis_el = el.find("axis")
        axis, lower, upper = (Z_AXIS, None, None) if jtype == "fixed" or moving == "floating" \
            else joint_axis(j, axis_el, name, where)
        if moving == "floating":
            kinds[name] = jtype
        if moving == "revolute" and lower is None and upper is None:
            moving = "continuous"
        # the joint moves the joint frame; the child link hangs off it (directly when the frames coincide)
        exact = rest == IDENTITY
        mid = child if exact else f"{child}@{name}"
        if not exact:
            links.append(mid)
        effort, velocity, damping, friction = (axis_dynamics(axis_el, where)
                                               if moving != "floating" else (None, None, None, None))
        joints.append(UrdfJoint(name, moving, parent, mid, None, axis, lower, upper, None, effort=effort,
                                velocity=velocity, damping=damping, friction=friction, pose=origin))
        if not exact:
            joints.append(UrdfJoint(f"{name}:child", "fixed", mid, child, None, Z_AXIS, None, None, None, pose=rest))
    for name, attached in j.attached.items():
        base = attached
        while j.kind.get(base) == "frame":
            base = j.attached[base]
        if base == "__model__":  # the model frame is fixed to the canonical link
            base = models[0].get("canonical_link") or (j.links[0] if j.links else "")
        base = j.joint_child.get(base, base)  # a joint frame moves with its child link
        if j.kind.get(base) != "link":
            raise InputError(f"{src}: frame '{name}' is attached to '{attached}', which is not a link, joint or "
                             f"frame of the model's top level; attach it to a link (attached_to=\"LINK\")")
        joints.append(UrdfJoint(f"{name}:frame", "fixed", base, name, None, Z_AXIS, None, None, None,
                                pose=j.relative(base, name, src)))
    if uses_world:
        links.insert(0, "world")
    model = UrdfModel(models[0].get("name"), tuple(links), tuple(joints), src, sdf_content(j, folder, text))
    check_tree(model)
    return model, kinds


def robot_from_sdf(source: str | os.PathLike[str], base_link: str | None = None, tip_link: str | None = None,
                   *, name: str | None = None) -> Robot:
    """The serial chain base_link -> tip_link of an SDF model as a Robot (q = the SDF joint positions).

    Parameters
    ----------
    source : path or str
        A .sdf file, or SDF text (a string starting with '<').
    base_link, tip_link : str, optional
        Links or explicit frames at the chain's ends (nested models' as ``inner::link``). Default base:
        the root link (the link fixed to ``world`` when a joint does that); default tip: the only leaf.
        A model whose links form several unconnected trees: the tree holding these links, or the
        only one with moving joints (see ``sdf_trees``).
    name : str, optional
        Robot name; default the model's name.

    Returns
    -------
    Robot
        GJD frames (n+1, 4, 4) in the base link frame, joints with the SDF names and limits
        (radians, metres); ``world`` = world -> base at q = 0 when the model is fixed to the world.
    """
    from .trees import pick_tree

    model, kinds = model_from_sdf(source)
    model = pick_tree(model, base_link, tip_link)  # a model may hold several unconnected trees
    refuse_on_chain(model, kinds, base_link, tip_link, CHAIN_JOINTS)
    return robot_from_model(model, base_link, tip_link, name=name)
