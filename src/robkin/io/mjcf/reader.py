"""MJCF (MuJoCo's XML) input: the kinematic tree of bodies, joints and sites as a Robot.

What is read, with MuJoCo's own semantics
    ``<compiler angle>`` (degrees are MuJoCo's default) and ``eulerseq``; body, site and ``<frame>``
    poses in every orientation form (``quat``, ``axisangle``, ``xyaxes``, ``zaxis``, ``euler``, and a
    site's ``fromto``); ``hinge`` and ``slide`` joints with ``pos`` (a hinge axis need not pass through
    the body origin), ``axis``, ``ref``, ``range``/``limited`` (and ``autolimits``), several joints in
    one body; ``<default>`` classes with inheritance, ``class`` and ``childclass``; ``<include>``
    (see ``source``); geoms (visual and collision shapes) and ``<inertial>``s as ``Robot.bodies``
    (see ``geoms``), each body's mass as MuJoCo compiles it (from its geoms where MuJoCo takes it from
    them: ``geom_mass``); joint ``damping``, ``frictionloss`` and ``armature`` (the last in the
    dynamics). Actuators, sensors and the rest of the simulation options are ignored.

The tree becomes a ``UrdfModel`` (links = bodies and sites) and the chain is picked by the URDF
reader's ``robot_from_model``, so ``base_link``/``tip_link`` name bodies or sites. A body whose
joints are off its origin, or that has several joints, gets intermediate links named
``BODY/JOINT``; unnamed bodies, joints and sites are called ``bodyI``, ``jointI``, ``siteI`` with
MuJoCo's ids. A site named like a body is the link ``site:NAME``.

What q means
    q is MuJoCo's qpos of the chain's joints, in qpos order: ``Robot.fk(q)`` (with ``Robot.world``
    in front) equals the tip's pose from ``mj_kinematics`` at qpos = q. A joint's ``ref`` is the qpos
    at which the model is drawn as written, so the GJD (q = 0) has each hinge turned by -ref and each
    slide moved by -ref. Limits are ``range`` in qpos units (radians and metres).

Ball and free joints on the chosen chain are refused with one line naming the joint.
"""

from __future__ import annotations

import math
import os
from typing import Any, Callable, Mapping

from ...compiled.conversions import pose_rows
from ...compiled.scanners.attribute_numbers import numbers
from ...errors import InputError, quote
from ...robot import Robot
from ..trees.chain_path import refuse_on_chain
from .poses import Pose, geom_pose, placement, rotation_from_mjcf, unit
from .source import MjcfSource, read_mjcf_source
from ..urdf.chain import robot_from_model
from ..trees.model import UrdfJoint, UrdfModel

__all__ = ["robot_from_mjcf", "model_from_mjcf", "rotation_from_mjcf", "geom_pose"]

JOINT_TYPES = ("hinge", "slide", "ball", "free")
#: The joint kinds that make a serial chain, as messages word them.
CHAIN_JOINTS = "hinge and slide"
IDENTITY = pose_rows.IDENTITY
Z_AXIS = (0.0, 0.0, 1.0)
#: (element, pose of its frame in the body (twelve floats), active class): a body's content
Part = tuple[Any, Pose, str]
#: the elements ``_flatten`` handles (dissolved or refused) in a body's content
_NESTING = frozenset(("frame", "replicate", "attach"))


def _shift(x: float, y: float, z: float) -> Pose:
    """The pure translation (x, y, z)."""
    return (1.0, 0.0, 0.0, x, 0.0, 1.0, 0.0, y, 0.0, 0.0, 1.0, z)


class _TreeBuilder:
    """Walks ``<worldbody>`` in MuJoCo's order (depth first, document order) and collects links and joints."""

    def __init__(self, src: MjcfSource):
        self.src = src
        self.links: list[str] = ["world"]
        self.joints: list[UrdfJoint] = []
        self.kinds: dict[str, str] = {}  # chain joint name -> MuJoCo type, for ball/free refusal
        self.refs: dict[str, float] = {}  # hinge/slide joint name -> ref (qpos units), for the equalities
        self.content: dict[str, list[Part]] = {}  # link -> its geoms and inertial
        self.body_poses: dict[str, Pose] = {}  # body -> its pos/orientation relative to its parent (geom_mass)
        self.counts = {"body": 0, "joint": 0, "site": 0}
        self.names: set[str] = {"world"}
        # every body's name, known before the walk so that a site named like a later body steps aside
        self.body_names = {"world"} | {b.get("name") for b in src.root.iter("body") if b.get("name")}

    def _id(self, kind: str) -> int:
        self.counts[kind] += 1
        return self.counts[kind] - 1

    def _attrs(self, el: Any, cls: str, where: str) -> Mapping[str, str]:
        """The element's attributes with its class's defaults applied (not to be changed: without
        defaults this is the element's own ``attrib``)."""
        name = el.get("class") or cls
        kinds = self.src.defaults.get(name)
        if kinds is None:
            raise InputError(f"{where}: class {quote(name)} is not a <default> class of the file")
        given = kinds.get(el.tag)
        if not given:
            return el.attrib
        out = dict(given)
        out.update(el.attrib)
        return out

    def _link(self, name: str) -> str:
        if name in self.names:
            raise InputError(f"{self.src.source}: two bodies or sites are both called '{name}'")
        self.names.add(name)
        self.links.append(name)
        return name

    def _add(self, name: str, jtype: str, parent: str, child: str, pose: Pose,
             axis: tuple[float, float, float] = Z_AXIS, lower: float | None = None, upper: float | None = None,
             dynamics: tuple[float | None, float | None, float | None] = (None, None, None)) -> None:
        self.joints.append(UrdfJoint(name, jtype, parent, child, None, axis, lower, upper, None,
                                     damping=dynamics[0], friction=dynamics[1], armature=dynamics[2], pose=pose))

    def _flatten(self, el: Any, cls: str) -> list[Part]:
        """(element, pose relative to el, active class) of el's content, ``<frame>``s dissolved."""
        kids = list(el)
        if _NESTING.isdisjoint([child.tag for child in kids]):  # the usual body: no <frame> in it
            return [(child, IDENTITY, cls) for child in kids]
        out: list[Part] = []
        todo = [(child, IDENTITY, cls) for child in reversed(kids)]
        while todo:
            child, T, c = todo.pop()
            tag = child.tag
            if tag == "frame":
                where = f"{self.src.source}: <frame{' ' + child.get('name') if child.get('name') else ''}>"
                F = pose_rows.compose(T, placement(child.attrib, self.src, where))
                inner = child.get("childclass") or c
                todo.extend((g, F, inner) for g in reversed(child))
            elif tag in ("replicate", "attach"):
                raise InputError(f"{self.src.source}: <{tag}> is not supported; expand it in MuJoCo "
                                 f"first (mujoco.mj_saveLastXML writes the expanded model)")
            else:
                out.append((child, T, c))
        return out

    def build(self) -> None:
        todo: list[tuple[Any, str, Pose, str]] = []  # (body element, parent link, pose, class)
        world_parts = [p for wb in self.src.root.iterfind("worldbody") for p in self._flatten(wb, "main")]
        self._id("body")
        self._contents("world", world_parts, todo)
        while todo:
            el, parent, T, cls = todo.pop()
            self._body(el, parent, T, cls, todo)

    def _contents(self, link: str, parts: list[Part], todo: list[tuple[Any, str, Pose, str]]) -> None:
        bodies = []
        for part in parts:
            tag = part[0].tag
            if tag == "body":
                bodies.append(part)
            elif tag in ("geom", "inertial"):
                self.content.setdefault(link, []).append(part)
            elif tag == "site":
                el, T, cls = part
                i = self._id("site")
                name = el.get("name") or f"site{i}"
                where = f"{self.src.source}: site '{name}'"
                attrs = self._attrs(el, cls, where)
                if name in self.body_names:
                    name = f"site:{name}"
                self._add(f"{name}:fixed", "fixed", link, self._link(name),
                          pose_rows.compose(T, placement(attrs, self.src, where)))
        todo.extend((el, link, T, cls) for el, T, cls in reversed(bodies))

    def _body(self, el: Any, parent: str, T: Pose, cls: str,
              todo: list[tuple[Any, str, Pose, str]]) -> None:
        i = self._id("body")
        name = el.get("name") or f"body{i}"
        where = f"{self.src.source}: body '{name}'"
        cls = el.get("childclass") or cls
        own = placement(el.attrib, self.src, where)
        self.body_poses[name] = own
        pending = pose_rows.compose(T, own)
        parts = self._flatten(el, cls)
        joints = [p for p in parts if p[0].tag in ("joint", "freejoint")]  # file order, as MuJoCo
        link = parent
        for k, (j, F, c) in enumerate(joints):
            jname, jtype, axis, origin, after, lo, hi, dynamics = self._joint(j, c, name, F)
            last = k == len(joints) - 1 and not any(after)
            child = self._link(name if last else f"{name}/{jname}")
            self._add(jname, jtype, link, child, pose_rows.compose(pending, origin), axis, lo, hi, dynamics)
            link, pending = child, _shift(*after)
        if not joints or link != name:  # welded body, or its frame is off the last joint's
            self._add(f"{name}:fixed", "fixed", link, self._link(name), pending)
        self.content.setdefault(name, [])  # every body, for <compiler boundmass> (geom_mass)
        self._contents(name, parts, todo)

    def _joint(self, el: Any, cls: str, body: str, frame: Pose
               ) -> tuple[str, str, tuple[float, float, float], Pose, tuple[float, float, float],
                          float | None, float | None, tuple[float | None, float | None, float | None]]:
        """(name, URDF type, unit axis, origin relative to the body frame before the joint, offset to
        apply after it, lower, upper, (damping, frictionloss, armature)) of one MJCF joint; ``frame``
        is the pose of the ``<frame>`` holding it in its body (identity when it sits directly in the body)."""
        i = self._id("joint")
        name = el.get("name") or f"joint{i}"
        where = f"{self.src.source}: joint '{name}' (body '{body}')"
        if el.tag == "freejoint":
            self.kinds[name] = "free"
            return name, "floating", Z_AXIS, IDENTITY, (0.0, 0.0, 0.0), None, None, (None, None, None)
        attrs = self._attrs(el, cls, where)
        kind = attrs.get("type", "hinge")
        if kind not in JOINT_TYPES:
            raise InputError(f"{where}: type {quote(kind)} is not one of {', '.join(JOINT_TYPES)}")
        pos = numbers(attrs.get("pos"), 3, where, "pos", (0.0, 0.0, 0.0))
        if frame is not IDENTITY:
            pos = pose_rows.compose(frame, _shift(*pos))[3::4]
        if kind in ("ball", "free"):
            self.kinds[name] = kind
            at = pos if kind == "ball" else (0.0, 0.0, 0.0)
            return (name, "floating", Z_AXIS, _shift(*at), (-at[0], -at[1], -at[2]), None, None,
                    self._dynamics(attrs, where))
        x, y, z = unit(numbers(attrs.get("axis"), 3, where, "axis", Z_AXIS), f"{where}: axis")
        axis = (x, y, z)
        if frame is not IDENTITY:  # R @ axis
            r = frame
            axis = (r[0] * x + r[1] * y + r[2] * z, r[4] * x + r[5] * y + r[6] * z, r[8] * x + r[9] * y + r[10] * z)
        scale = self.src.angle if kind == "hinge" else float
        ref = scale(numbers(attrs.get("ref"), 1, where, "ref", (0.0,))[0])
        self.refs[name] = ref
        lo, hi = self._limits(attrs, where, scale)
        dynamics = self._dynamics(attrs, where)
        if kind == "slide":
            return (name, "prismatic", axis, _shift(-ref * axis[0], -ref * axis[1], -ref * axis[2]),
                    (0.0, 0.0, 0.0), lo, hi, dynamics)
        origin = pose_rows.from_axis_angle(pos, axis, -ref) if ref else _shift(*pos)
        return (name, "revolute" if lo is not None else "continuous", axis, origin, (-pos[0], -pos[1], -pos[2]),
                lo, hi, dynamics)

    @staticmethod
    def _dynamics(attrs: Mapping[str, str], where: str) -> tuple[float | None, float | None, float | None]:
        """(damping, frictionloss, armature) of a joint, None where neither the joint nor its class gives one."""
        get = attrs.get
        damping, friction, armature = get("damping"), get("frictionloss"), get("armature")
        return (None if damping is None else numbers(damping, 1, where, "damping", ())[0],
                None if friction is None else numbers(friction, 1, where, "frictionloss", ())[0],
                None if armature is None else numbers(armature, 1, where, "armature", ())[0])

    def _limits(self, attrs: Mapping[str, str], where: str,
                scale: Callable[[float], float]) -> tuple[float | None, float | None]:
        limited = attrs.get("limited", "auto")
        if limited not in ("auto", "true", "false"):
            raise InputError(f"{where}: limited {quote(limited)} is not one of auto, true, false")
        lo, hi = numbers(attrs.get("range"), 2, where, "range", (0.0, 0.0))
        if limited == "auto":
            has_range = not (lo == 0 and hi == 0)  # MuJoCo's rule: range "0 0" is no range
            if has_range and not self.src.autolimits:
                raise InputError(f"{where}: has a range but limited is not given and <compiler autolimits> "
                                 f"is false; MuJoCo refuses this (add limited=\"true\" or \"false\")")
            limited = "true" if has_range else "false"
        if limited == "false":
            return None, None
        if not lo < hi:
            raise InputError(f"{where}: range {quote(attrs.get('range', '0 0'))}: the lower end must be below the "
                             f"upper end for a limited joint")
        return scale(float(lo)), scale(float(hi))


def model_from_mjcf(source: str | os.PathLike[str]) -> tuple[UrdfModel, dict[str, str]]:
    """The kinematic tree of an MJCF file (path) or MJCF text, and the ball/free joints by name."""
    from .geoms import MjcfContent

    src = read_mjcf_source(source)
    tree = _TreeBuilder(src)
    tree.build()
    if src.root.find("equality") is not None:
        from .equality import joint_locks, joint_mimics

        mimics = joint_mimics(src, tree.refs)
        locks = joint_locks(src, tree.refs)
        for j in tree.joints:  # joint equalities as mimics (robot_from_mjcf frees those on the chain)
            j.mimic = mimics.get(j.name) if j.type != "fixed" else None
            if j.name in locks and j.type in ("revolute", "continuous", "prismatic"):
                # held at one value: equal limits, the one meaning of robkin.io.trees.joint_limits
                j.lower = j.upper = locks[j.name]
                j.type = "revolute" if j.type == "continuous" else j.type
    content = MjcfContent(src, tree.content, tree._attrs, tree.body_poses)
    return UrdfModel(src.root.get("model"), tuple(tree.links), tuple(tree.joints), src.source, content), tree.kinds


def robot_from_mjcf(source: str | os.PathLike[str], base_link: str | None = None, tip_link: str | None = None,
                    *, name: str | None = None) -> Robot:
    """The serial chain base_link -> tip_link of an MJCF model as a Robot (q = MuJoCo's qpos).

    Parameters
    ----------
    source : path or str
        A .xml/.mjcf file, or MJCF text (a string starting with '<'; it cannot ``<include>``).
    base_link, tip_link : str, optional
        Bodies or sites at the chain's ends. Default base: the body fixed to the world (the world
        when that is not a single body); default tip: the only leaf below the base.
    name : str, optional
        Robot name; default the ``<mujoco model>`` attribute.

    Returns
    -------
    Robot
        GJD frames (n+1, 4, 4) in the base body frame, one joint per hinge/slide of the chain with
        its MJCF name and ``range`` limits (radians, metres); ``world`` = world -> base at qpos = 0.
    """
    model, kinds = model_from_mjcf(source)
    refuse_on_chain(model, kinds, base_link, tip_link, CHAIN_JOINTS)
    if any(j.mimic for j in model.joints):  # an equality-bound joint on the chain stays a joint of its own
        from ..urdf.chain import select_chain

        for j in select_chain(model, base_link, tip_link)[3]:
            j.mimic = None
    return robot_from_model(model, base_link, tip_link, name=name)
