"""MJCF (MuJoCo's XML) input: the kinematic tree of bodies, joints and sites as a Robot.

What is read, with MuJoCo's own semantics
    ``<compiler angle>`` (degrees are MuJoCo's default) and ``eulerseq``; body, site and ``<frame>``
    poses in every orientation form (``quat``, ``axisangle``, ``xyaxes``, ``zaxis``, ``euler``, and a
    site's ``fromto``); ``hinge`` and ``slide`` joints with ``pos`` (a hinge axis need not pass through
    the body origin), ``axis``, ``ref``, ``range``/``limited`` (and ``autolimits``), several joints in
    one body; ``<default>`` classes with inheritance, ``class`` and ``childclass``; ``<include>``
    (see ``mjcf_source``); geoms (visual and collision shapes) and ``<inertial>``s as ``Robot.bodies``
    (see ``mjcf_geoms``). Actuators and everything dynamic are ignored.

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

import numpy as np

from .. import se3
from ..errors import InputError, quote
from ..robot import Robot
from .chain_path import refuse_on_chain
from .mjcf import matrix_from_quat
from .mjcf_source import MjcfSource, read_mjcf_source
from .urdf import UrdfJoint, UrdfModel, _floats, robot_from_model

__all__ = ["robot_from_mjcf", "model_from_mjcf", "rotation_from_mjcf"]

ORIENTATIONS = ("quat", "axisangle", "xyaxes", "zaxis", "euler")
JOINT_TYPES = ("hinge", "slide", "ball", "free")
#: The joint kinds that make a serial chain, as messages word them.
CHAIN_JOINTS = "hinge and slide"
#: A direction (quaternion, axis, xyaxes, zaxis, fromto) shorter than this is no direction: MuJoCo
#: refuses such vectors too; typed directions have lengths ~1 (at least ~1e-6 with few decimals).
ZERO_VECTOR = 1e-10


def _rodrigues(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rotation (3, 3) by ``angle`` (rad) about the unit ``axis`` (3,)."""
    K = se3.skew(axis)
    return np.eye(3) + math.sin(angle) * K + (1.0 - math.cos(angle)) * (K @ K)


def _unit(v: np.ndarray, where: str) -> np.ndarray:
    n = float(np.linalg.norm(v))
    if n < ZERO_VECTOR:
        raise InputError(f"{where}: is a zero vector; a direction is needed")
    return v / n


def _z_to(v: np.ndarray) -> np.ndarray:
    """Minimal rotation taking +z onto the unit v (MuJoCo's rule; +z -> -z turns by pi about x)."""
    s = math.hypot(v[0], v[1])
    if s < ZERO_VECTOR:
        return np.eye(3) if v[2] > 0 else np.diag([1.0, -1.0, -1.0])
    return _rodrigues(np.array([-v[1] / s, v[0] / s, 0.0]), math.atan2(s, v[2]))


def rotation_from_mjcf(attrs: Mapping[str, str], src: MjcfSource, where: str) -> np.ndarray:
    """Rotation (3, 3) of an element's orientation attributes (identity when it has none)."""
    given = [k for k in ORIENTATIONS if attrs.get(k) is not None]
    if len(given) > 1:
        raise InputError(f"{where}: has both {given[0]} and {given[1]}; give one orientation")
    if not given:
        return np.eye(3)
    kind = given[0]
    text, at = attrs[kind], f"{where}: {kind}"
    if kind == "quat":
        return matrix_from_quat(_unit(_floats(text, 4, at, ()), at))
    if kind == "axisangle":
        v = _floats(text, 4, at, ())
        return _rodrigues(_unit(v[:3], at), src.angle(v[3]))
    if kind == "zaxis":
        return _z_to(_unit(_floats(text, 3, at, ()), at))
    if kind == "xyaxes":
        v = _floats(text, 6, at, ())
        x = _unit(v[:3], at)
        y = _unit(v[3:] - x * float(x @ v[3:]), f"{at} (y is parallel to x)")
        return np.column_stack([x, y, np.cross(x, y)])
    v = _floats(text, 3, at, ())
    R = np.eye(3)
    for letter, angle in zip(src.eulerseq, v):
        step = _rodrigues(np.eye(3)["xyz".index(letter.lower())], src.angle(angle))
        R = R @ step if letter.islower() else step @ R  # lower case: rotating axes; upper: fixed axes
    return R


def _pose(attrs: Mapping[str, str], src: MjcfSource, where: str) -> np.ndarray:
    """Pose (4, 4) of a body, site, geom or frame relative to its parent."""
    return geom_pose(attrs, src, where)[0]


def geom_pose(attrs: Mapping[str, str], src: MjcfSource, where: str) -> tuple[np.ndarray, float | None]:
    """(pose (4, 4) relative to the parent, length of the ``fromto`` segment or None) of an element."""
    if attrs.get("fromto") is not None:  # centre of the segment, z from 'to' towards 'from' (MuJoCo's)
        v = _floats(attrs["fromto"], 6, f"{where}: fromto", ())
        d = v[:3] - v[3:]
        return se3.homogeneous(_z_to(_unit(d, f"{where}: fromto")), (v[:3] + v[3:]) / 2), float(np.linalg.norm(d))
    pos = _floats(attrs.get("pos"), 3, f"{where}: pos", (0, 0, 0))
    return se3.homogeneous(rotation_from_mjcf(attrs, src, where), pos), None


class _TreeBuilder:
    """Walks ``<worldbody>`` in MuJoCo's order (depth first, document order) and collects links and joints."""

    def __init__(self, src: MjcfSource):
        self.src = src
        self.links: list[str] = ["world"]
        self.joints: list[UrdfJoint] = []
        self.kinds: dict[str, str] = {}  # chain joint name -> MuJoCo type, for ball/free refusal
        self.content: dict[str, list[tuple[Any, np.ndarray, str]]] = {}  # link -> its geoms and inertial
        self.counts = {"body": 0, "joint": 0, "site": 0}
        self.names: set[str] = {"world"}
        # every body's name, known before the walk so that a site named like a later body steps aside
        self.body_names = {"world"} | {b.get("name") for b in src.root.iter("body") if b.get("name")}

    def _id(self, kind: str) -> int:
        self.counts[kind] += 1
        return self.counts[kind] - 1

    def _attrs(self, el: Any, cls: str, where: str) -> dict[str, str]:
        name = el.get("class") or cls
        if name not in self.src.defaults:
            raise InputError(f"{where}: class {quote(name)} is not a <default> class of the file")
        out = dict(self.src.defaults[name].get(el.tag, {}))
        out.update(el.attrib)
        return out

    def _link(self, name: str) -> str:
        if name in self.names:
            raise InputError(f"{self.src.source}: two bodies or sites are both called '{name}'")
        self.names.add(name)
        self.links.append(name)
        return name

    def _add(self, name: str, jtype: str, parent: str, child: str, origin: np.ndarray,
             axis: np.ndarray = np.array([0.0, 0.0, 1.0]), lower: float | None = None,
             upper: float | None = None) -> None:
        self.joints.append(UrdfJoint(name, jtype, parent, child, origin, axis, lower, upper, None))

    def _flatten(self, el: Any, cls: str) -> list[tuple[Any, np.ndarray, str]]:
        """(element, pose relative to el, active class) of el's content, ``<frame>``s dissolved."""
        out: list[tuple[Any, np.ndarray, str]] = []
        todo = [(child, np.eye(4), cls) for child in reversed(list(el))]
        while todo:
            child, T, c = todo.pop()
            if child.tag == "frame":
                where = f"{self.src.source}: <frame{' ' + child.get('name') if child.get('name') else ''}>"
                F = T @ _pose(child.attrib, self.src, where)
                inner = child.get("childclass") or c
                todo.extend((g, F, inner) for g in reversed(list(child)))
            elif child.tag in ("replicate", "attach"):
                raise InputError(f"{self.src.source}: <{child.tag}> is not supported; expand it in MuJoCo "
                                 f"first (mujoco.mj_saveLastXML writes the expanded model)")
            else:
                out.append((child, T, c))
        return out

    def build(self) -> None:
        todo: list[tuple[Any, str, np.ndarray, str]] = []  # (body element, parent link, pose, class)
        world_parts = [p for wb in self.src.root.findall("worldbody") for p in self._flatten(wb, "main")]
        self._id("body")
        self._contents("world", world_parts, todo)
        while todo:
            el, parent, T, cls = todo.pop()
            self._body(el, parent, T, cls, todo)

    def _contents(self, link: str, parts: list[tuple[Any, np.ndarray, str]],
                  todo: list[tuple[Any, str, np.ndarray, str]]) -> None:
        for el, T, cls in parts:
            if el.tag in ("geom", "inertial"):
                self.content.setdefault(link, []).append((el, T, cls))
            elif el.tag == "site":
                i = self._id("site")
                name = el.get("name") or f"site{i}"
                where = f"{self.src.source}: site '{name}'"
                attrs = self._attrs(el, cls, where)
                if name in self.body_names:
                    name = f"site:{name}"
                self._add(f"{name}:fixed", "fixed", link, self._link(name), T @ _pose(attrs, self.src, where))
        todo.extend((el, link, T, cls) for el, T, cls in reversed(parts) if el.tag == "body")

    def _body(self, el: Any, parent: str, T: np.ndarray, cls: str,
              todo: list[tuple[Any, str, np.ndarray, str]]) -> None:
        i = self._id("body")
        name = el.get("name") or f"body{i}"
        where = f"{self.src.source}: body '{name}'"
        cls = el.get("childclass") or cls
        pending = T @ _pose(el.attrib, self.src, where)
        parts = self._flatten(el, cls)
        joints = [(j, F, c) for j, F, c in parts if j.tag in ("joint", "freejoint")]  # file order, as MuJoCo
        link = parent
        for k, (j, F, c) in enumerate(joints):
            jname, jtype, axis, origin, after, lo, hi = self._joint(j, c, name, F)
            last = k == len(joints) - 1 and not after.any()
            child = self._link(name if last else f"{name}/{jname}")
            self._add(jname, jtype, link, child, pending @ origin, axis, lo, hi)
            link, pending = child, se3.trans(*after)
        if not joints or link != name:  # welded body, or its frame is off the last joint's
            self._add(f"{name}:fixed", "fixed", link, self._link(name), pending)
        self._contents(name, parts, todo)

    def _joint(self, el: Any, cls: str, body: str, frame: np.ndarray
               ) -> tuple[str, str, np.ndarray, np.ndarray, np.ndarray, float | None, float | None]:
        """(name, URDF type, unit axis, origin relative to the body frame before the joint,
        offset to apply after it, lower, upper) of one MJCF joint; ``frame`` (4, 4) is the pose of
        the ``<frame>`` holding it in its body (identity when it sits directly in the body)."""
        i = self._id("joint")
        name = el.get("name") or f"joint{i}"
        where = f"{self.src.source}: joint '{name}' (body '{body}')"
        if el.tag == "freejoint":
            self.kinds[name] = "free"
            return name, "floating", np.array([0.0, 0.0, 1.0]), np.eye(4), np.zeros(3), None, None
        attrs = self._attrs(el, cls, where)
        kind = attrs.get("type", "hinge")
        if kind not in JOINT_TYPES:
            raise InputError(f"{where}: type {quote(kind)} is not one of {', '.join(JOINT_TYPES)}")
        pos = frame[:3, :3] @ _floats(attrs.get("pos"), 3, f"{where}: pos", (0, 0, 0)) + frame[:3, 3]
        if kind in ("ball", "free"):
            self.kinds[name] = kind
            at = pos if kind == "ball" else np.zeros(3)
            return name, "floating", np.array([0.0, 0.0, 1.0]), se3.trans(*at), -at, None, None
        axis = frame[:3, :3] @ _unit(_floats(attrs.get("axis"), 3, f"{where}: axis", (0, 0, 1)), f"{where}: axis")
        scale = self.src.angle if kind == "hinge" else float
        ref = scale(float(_floats(attrs.get("ref"), 1, f"{where}: ref", (0,))[0]))
        lo, hi = self._limits(attrs, where, scale)
        if kind == "slide":
            return name, "prismatic", axis, se3.trans(*(-ref * axis)), np.zeros(3), lo, hi
        origin = se3.homogeneous(_rodrigues(axis, -ref), pos)
        return name, "revolute" if lo is not None else "continuous", axis, origin, -pos, lo, hi

    def _limits(self, attrs: Mapping[str, str], where: str,
                scale: Callable[[float], float]) -> tuple[float | None, float | None]:
        limited = attrs.get("limited", "auto")
        if limited not in ("auto", "true", "false"):
            raise InputError(f"{where}: limited {quote(limited)} is not one of auto, true, false")
        lo, hi = _floats(attrs.get("range"), 2, f"{where}: range", (0, 0))
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
    from .mjcf_geoms import MjcfContent

    src = read_mjcf_source(source)
    tree = _TreeBuilder(src)
    tree.build()
    content = MjcfContent(src, tree.content, tree._attrs)
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
    return robot_from_model(model, base_link, tip_link, name=name)
