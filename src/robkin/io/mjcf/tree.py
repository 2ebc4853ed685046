"""The body tree an MJCF file is written from: which link becomes which body, joint, site.

``body_tree(robot)`` plans the ``<worldbody>`` of ``robkin.io.mjcf.writer``; every pose here is in the
robot base frame at q = 0 (the writer re-expresses them relative to the parent body).

From a robot file (``Robot.bodies`` holds its links)
    Every link of the source under its own name. The chain's base link is a body fixed to the world at
    ``Robot.world``; below it the chain's links, each with its joint, the chain child listed first in
    every body so that MuJoCo numbers the chain's joints first (qpos[:n] = q). Links hanging from the
    chain keep their own joints (a gripper's fingers, the rest of a humanoid) and come after. Links
    above the base (the root of a humanoid when the chain starts at its torso) are bodies fixed to
    the world at their pose, joints between them and the base held at 0. A link that is fixed to its
    parent, massless, without shapes and without child links is a ``<site>`` (UR's ``tool0``); a link
    called ``world`` with nothing on it is MuJoCo's world itself (a site there). The tip link is a
    body holding a site of the same name (MuJoCo rounds a site's own sub-micro-radian rotation away; a
    site at the origin of its body is exact).

From a table or a document (no links)
    Bodies ``base``, ``link1`` .. ``linkN`` (one per joint, at the joint frame) and ``tool`` (with a
    site ``tool``); shapes and inertials the robot carries go on the body of their index.

``fuse_fixed=True`` merges every body fixed to its parent (not the base, not the tip) into that
parent: its shapes move there, its inertial is merged exactly (``robkin.dynamics.merge_masses``), its
name stays as a site at its frame.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from ...body_parts import Inertial, Link, Mimic, Shape
    from ...robot import Robot

__all__ = ["JointPlan", "BodyPlan", "body_tree"]

#: URDF joint types that become MJCF joints (others off the chain, floating and planar, are welded).
MOVING = ("revolute", "continuous", "prismatic")


@dataclass
class JointPlan:
    """A joint of the output: the chain's (``chain`` = its index) or one off the chain (None).

    axis : (3,) unit axis (positive direction) in the base frame at q = 0; point : (3,) a point on it
    """

    name: str
    slide: bool
    axis: np.ndarray
    point: np.ndarray
    lower: float | None
    upper: float | None
    chain: int | None = None
    effort: float | None = None
    velocity: float | None = None
    damping: float | None = None
    friction: float | None = None
    armature: float | None = None
    mimic: Mimic | None = None


@dataclass
class BodyPlan:
    """A ``<body>`` of the output: name, parent body (None: the world), pose (4, 4) at q = 0."""

    name: str
    parent: int | None
    frame: np.ndarray
    joint: JointPlan | None = None
    shapes: list[Shape] = field(default_factory=list)
    inertials: list[Inertial] = field(default_factory=list)
    #: (site name, pose (4, 4) in the base frame)
    sites: list[tuple[str, np.ndarray]] = field(default_factory=list)
    children: list[int] = field(default_factory=list)
    #: the source's origin numbers (xyz, rpy) of the joint that attaches the link to its parent
    origin: tuple[float, ...] | None = None


def _chain_joint(robot: Robot, i: int) -> JointPlan:
    j = robot.joints[i]
    F = robot.frames[i]
    return JointPlan(j.name, not j.revolute, F[:3, 2].copy(), F[:3, 3].copy(), j.lower, j.upper, i, j.effort,
                     j.velocity, j.damping, j.friction, getattr(j, "armature", None))


def _plain(robot: Robot) -> list[BodyPlan]:
    from ...representations.dh import flip_frame

    D = [np.eye(4)] + [flip_frame(robot.frames[i], j.flip) for i, j in enumerate(robot.joints)]
    names = ["base"] + [f"link{i + 1}" for i in range(robot.n)]
    out = [BodyPlan(names[0], None, np.eye(4))]  # frames in the base frame; the writer puts it at world
    for i in range(robot.n):
        out.append(BodyPlan(names[i + 1], i, D[i + 1], _chain_joint(robot, i)))
        out[i].children.append(i + 1)
    tool = BodyPlan("tool", robot.n, np.asarray(robot.tool, dtype=float), sites=[("tool", robot.tool)])
    out[robot.n].children.append(len(out))
    out.append(tool)
    for s in robot.bodies.shapes:
        out[min(max(s.body, 0), robot.n)].shapes.append(s)
    for m in robot.bodies.inertials:
        out[min(max(m.body, 0), robot.n)].inertials.append(m)
    return out


def _is_frame_only(link: Link, kids: dict[str, list[Link]], shapes: dict[str, list[Shape]],
                   inertials: dict[str, list[Inertial]], tip: str | None, chain: set[str]) -> bool:
    """A link written as a site: fixed, nothing on it, nothing below it, not the tip or the chain's."""
    return (link.name not in chain and link.name != tip and not kids.get(link.name)
            and not shapes.get(link.name) and not any(m.mass > 0 for m in inertials.get(link.name, ())))


def _faithful(robot: Robot, frames: dict[str, np.ndarray]) -> list[BodyPlan]:
    b = robot.bodies
    by_name = {link.name: link for link in b.links}
    chain = list(b.chain)
    chain_index = {name: i for i, name in enumerate(chain[1:])}
    kids: dict[str, list[Link]] = {}
    for link in b.links:
        if link.parent is not None:
            kids.setdefault(link.parent, []).append(link)
    shapes: dict[str, list[Shape]] = {}
    for s in b.shapes:
        shapes.setdefault(s.link if s.link in by_name else chain[s.body], []).append(s)
    inertials: dict[str, list[Inertial]] = {}
    for m in b.inertials:
        inertials.setdefault(m.link if m.link in by_name else chain[m.body], []).append(m)
    # links above the base: the path from the base up to the source's root (fixed to the world)
    above: list[str] = []
    link = by_name[chain[0]]
    while link.parent is not None:
        above.append(link.parent)
        link = by_name[link.parent]
    above_set = set(above)
    out: list[BodyPlan] = []
    world: int | None = None  # the plan entry of MuJoCo's world body, when the source has a 'world' link
    welded: list[str] = []
    chain_set = set(chain)
    on_path = set(chain)  # the links from the base to the tip, fixed ones between chain links included
    if b.tip in by_name:
        lk = by_name[b.tip]
        while lk.name != chain[0] and lk.parent is not None:
            on_path.add(lk.name)
            lk = by_name[lk.parent]

    def world_site(name: str) -> None:
        # a root link with nothing on it (URDF's virtual 'world'): MuJoCo's world body itself, whose name
        # is 'world' already
        out.append(BodyPlan("world", None, frames[name]))

    def add(link: Link, parent: int | None) -> None:
        """Body (or site) of ``link`` under plan index ``parent``, then its subtree, chain child first."""
        stack: list[tuple[Link, int | None]] = [(link, parent)]
        while stack:
            lk, par = stack.pop()
            lj = lk.joint
            moving = lk.name in chain_index or (lj is not None and lj.type in MOVING and lk.name not in above_set
                                                 and lk.name != chain[0])
            if not moving and _is_frame_only(lk, kids, shapes, inertials, b.tip, chain_set) and (
                    par is not None or world is not None):
                out[world if par is None else par].sites.append((lk.name, frames[lk.name]))  # type: ignore[index]
                continue
            joint = None
            if lk.name in chain_index:
                joint = _chain_joint(robot, chain_index[lk.name])
            elif moving and lj is not None:
                P = frames[lk.name]
                axis = P[:3, :3] @ np.asarray(lj.axis, dtype=float)
                joint = JointPlan(lj.name, lj.type == "prismatic", axis / np.linalg.norm(axis), P[:3, 3].copy(),
                                  None if lj.type == "continuous" else lj.lower,
                                  None if lj.type == "continuous" else lj.upper, None, lj.effort, lj.velocity,
                                  lj.damping, lj.friction, lj.armature, lj.mimic)
            elif lj is not None and lj.type not in ("fixed",) + MOVING:
                welded.append(f"{lj.name} ({lj.type})")
            idx = len(out)
            out.append(BodyPlan(lk.name, par, frames[lk.name], joint, shapes.get(lk.name, []),
                                inertials.get(lk.name, []),
                                origin=lj.xyz_rpy if lj is not None and par is not None else None))
            if par is not None:
                out[par].children.append(idx)
            if lk.name == b.tip:
                out[idx].sites.append((lk.name, frames[lk.name]))
            below = [k for k in kids.get(lk.name, []) if k.name not in above_set]
            below.sort(key=lambda k: k.name not in on_path)  # the chain child first: its joints first
            stack.extend((k, idx) for k in reversed(below))

    add(by_name[chain[0]], None)
    for name in above:  # fixed to the world, each with the subtrees hanging from it (not the base's)
        lk = by_name[name]
        if (lk.parent is None and name == "world" and not shapes.get(name) and not inertials.get(name)):
            world = len(out)
            world_site(name)
            for k in kids.get(name, []):
                if k.name not in above_set and k.name != chain[0]:
                    add(k, None)
            continue
        idx = len(out)
        out.append(BodyPlan(name, None, frames[name], None, shapes.get(name, []), inertials.get(name, [])))
        for k in kids.get(name, []):
            if k.name not in above_set and k.name != chain[0]:
                add(k, idx)
    # joints above the base are welded: the reader warned that they are held at 0
    if welded:
        warnings.warn(f"joint(s) {', '.join(welded[:6])}{', ...' if len(welded) > 6 else ''} are welded at 0 "
                      f"(not a hinge or slide)", UserWarning, stacklevel=3)
    return out


def fuse_fixed(plan: list[BodyPlan], keep: set[str]) -> list[BodyPlan]:
    """``plan`` with every body fixed to a parent body (no joint, names not in ``keep``) merged into it."""
    alive = list(range(len(plan)))
    target = list(range(len(plan)))  # body -> the body it merges into
    for i, bp in enumerate(plan):
        if bp.parent is not None and bp.joint is None and bp.name not in keep:
            t = target[bp.parent]
            target[i] = t
            into = plan[t]
            into.shapes += bp.shapes
            into.inertials += bp.inertials
            into.sites += [(bp.name, bp.frame)] + bp.sites
            alive.remove(i)
    index = {old: new for new, old in enumerate(alive)}
    out = []
    for old in alive:
        bp = plan[old]
        bp.parent = None if bp.parent is None else index[target[bp.parent]]
        out.append(bp)
    for bp in out:
        bp.children = []
    for k, bp in enumerate(out):
        if bp.parent is not None:
            out[bp.parent].children.append(k)
    return out


def body_tree(robot: Robot, *, fuse: bool = False) -> tuple[list[BodyPlan], bool]:
    """(bodies in MuJoCo's order, whether the source's link names are used): see the module doc.

    Bodies are listed parents first; ``BodyPlan.children`` keeps the order they are written in. A
    plan entry with an empty name is the world itself (it holds sites only).
    """
    from ..urdf.writer import _faithful_frames

    frames = _faithful_frames(robot) if robot.bodies.links else None
    plan = _plain(robot) if frames is None else _faithful(robot, frames)
    if fuse:
        keep = {robot.bodies.tip or "tool"} if frames is not None else {"tool"}
        plan = fuse_fixed(plan, keep)
    return plan, frames is not None
