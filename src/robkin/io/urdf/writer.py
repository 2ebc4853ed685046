"""A Robot as URDF text: the source file again when the robot came from one, else a plain chain.

From a robot file (``Robot.bodies`` holds its links)
    every link and joint of the source under its own name, in its order: the chain's joints with
    the robot's limits, effort, velocity and dynamics; the joints off the chain (gripper fingers,
    the rest of a humanoid) as the source gave them, mimic included; fixed links (``base``,
    ``flange``, ``tool0``) where they were; visuals, collisions and inertials; and the elements robkin
    does not interpret (transmissions, Gazebo and ros2_control tags) as the source wrote them. A link keeps its
    source frame wherever that frame still fits the robot (its origin on the joint axis), so a
    round trip repeats the source's numbers; where a conversion moved a joint frame, the link gets
    the new frame and everything on it (origins of shapes, inertials, child joints) is re-expressed
    so that it sits at the same pose at every q.

Otherwise (a robot from a table or a document)
    links ``world``, ``base``, one per joint and ``tool``: each joint's origin relative to the
    previous joint frame, axis ``0 0 1`` (``0 0 -1`` for a flipped joint), and the world->base
    transform as a fixed joint. Shapes and inertials the robot carries without link names go on the
    link of their body.

Limit-free joints: a revolute joint without limits is written as ``revolute`` with limits
+-``NO_LIMIT`` (1e10), so pinocchio gives it one coordinate (nq = n; a ``continuous`` joint takes two,
cos and sin) and MuJoCo a hinge whose range never binds; robkin reads such limits back as none. A
joint the source called ``continuous`` stays ``continuous``. Effort and velocity, which URDF requires
in ``<limit>``, are written from the joint; where they are unknown (robots not read from a URDF)
they are written as 0, which a file comment marks as unknown.

Shapes: URDF has no capsule, so a capsule (MJCF, SDF, ``robkin.link_geometry``) is written as its
cylinder and a sphere on each end.

Numbers are written in full precision (``repr``). Origins that still hold are written with the
source's own numbers; re-expressed ones carry the rounding of the products that made them, except
that rpy angles and axis components below 1e-15 are written as 0 (rounding noise of unit-size
products, not information).
"""

from __future__ import annotations

from collections import defaultdict
from typing import Iterable

import numpy as np

from ... import se3
from ...bodies import Inertial, Link, Mimic, Shape
from ...robot import Robot
from ..trees.model import NO_LIMIT, origin_matrix
from ...mass_properties import EXACT_ZERO
from ..files.float_text import float_text as _num
from ..files.xmltext import quoteattr

__all__ = ["urdf_from_robot"]

#: A source link frame is kept for a chain joint when its origin lies this close to the joint axis,
#: relative to the robot size: conversions of the same robot move axes only by rounding (~1e-15).
ON_AXIS_TOL = 1e-12
#: The source's own origin numbers are repeated when they give the re-expressed origin to this,
#: relative to the robot size (rounding of the products that re-expressed it, ~1e-16).
SAME_ORIGIN_TOL = 1e-12
#: Rotation entries and axis components below this are rounding noise of unit-size products.
UNIT_NOISE = 1e-15

_HEADER = ["  <!-- for MuJoCo's URDF reader: keep fixed links (the tool frame) as bodies, and give the",
           "       massless links a tiny placeholder mass so that the model compiles -->",
           '  <mujoco><compiler fusestatic="false" boundmass="1e-06" boundinertia="1e-12"/></mujoco>']


def _unit(v: Iterable[float]) -> str:
    return " ".join("0" if abs(float(c)) < UNIT_NOISE else _num(c) for c in v)


def _origin(T: np.ndarray, xyz_rpy: tuple[float, ...] | None = None, scale: float = 1.0) -> str:
    """<origin> of a pose; the source's numbers ``xyz_rpy`` when they still give it."""
    if xyz_rpy is not None and np.abs(origin_matrix(xyz_rpy[:3], xyz_rpy[3:]) - T).max() <= SAME_ORIGIN_TOL * scale:
        xyz, rpy = " ".join(_num(v) for v in xyz_rpy[:3]), " ".join(_num(v) for v in xyz_rpy[3:])
    else:
        xyz, rpy = " ".join(_num(v) for v in T[:3, 3]), _unit(se3.rpy_from_matrix(T[:3, :3]))
    if xyz == "0 0 0" and rpy == "0 0 0":
        return ""
    return f'<origin xyz="{xyz}" rpy="{rpy}"/>'


def _limit(jtype: str, lower: float | None, upper: float | None, effort: float | None,
           velocity: float | None) -> str | None:
    """<limit> for a joint of a URDF type: bounds for revolute and prismatic joints (+-NO_LIMIT where
    absent), effort and velocity for every type that was given them (None: no element)."""
    ev = f'effort="{_num(effort or 0.0)}" velocity="{_num(velocity or 0.0)}"'
    if jtype not in ("revolute", "prismatic"):
        return None if effort is None and velocity is None else f"<limit {ev}/>"
    lo = _num(-NO_LIMIT if lower is None else lower)
    hi = _num(NO_LIMIT if upper is None else upper)
    return f'<limit lower="{lo}" upper="{hi}" {ev}/>'


def _joint_xml(name: str, jtype: str, parent: str, child: str, origin: str, axis: str | None,
               limit: str | None, damping: float | None = None, friction: float | None = None,
               mimic: Mimic | None = None) -> list[str]:
    out = [f"  <joint name={quoteattr(name)} type=\"{jtype}\">",
           f"    <parent link={quoteattr(parent)}/>", f"    <child link={quoteattr(child)}/>"]
    if origin:
        out.append(f"    {origin}")
    if axis is not None and jtype != "fixed":
        out.append(f'    <axis xyz="{axis}"/>')
    if limit:
        out.append(f"    {limit}")
    if damping is not None or friction is not None:
        out.append("    <dynamics" + (f' damping="{_num(damping)}"' if damping is not None else "")
                   + (f' friction="{_num(friction)}"' if friction is not None else "") + "/>")
    if mimic is not None:
        out.append(f"    <mimic joint={quoteattr(mimic.joint)} multiplier=\"{_num(mimic.multiplier)}\" "
                   f"offset=\"{_num(mimic.offset)}\"/>")
    out.append("  </joint>")
    return out


def _geometry(s: Shape) -> str:
    g = s.geometry
    if g.kind == "box":
        return f'<box size="{" ".join(_num(v) for v in g.size)}"/>'
    if g.kind == "sphere":
        return f'<sphere radius="{_num(g.size[0])}"/>'
    if g.kind == "cylinder":
        return f'<cylinder radius="{_num(g.size[0])}" length="{_num(g.size[1])}"/>'
    if g.kind == "capsule":  # split by _urdf_shapes before it gets here; a lone one: its cylinder
        return f'<cylinder radius="{_num(g.size[0])}" length="{_num(g.size[1])}"/>'
    scale = "" if tuple(g.size) == (1.0, 1.0, 1.0) else f' scale="{" ".join(_num(v) for v in g.size)}"'
    return f"<mesh filename={quoteattr(g.filename or '')}{scale}/>"


def _urdf_shapes(shapes: list[Shape]) -> list[Shape]:
    """The shapes as URDF can say them: URDF has no capsule, so each capsule becomes its cylinder
    (same radius, the length between the cap centres) and a sphere on each end, which urdfdom,
    pinocchio and MuJoCo all read. Names of the caps: the capsule's name + ``_cap1`` / ``_cap2``."""
    from dataclasses import replace

    from ...bodies import Geometry

    out: list[Shape] = []
    for s in shapes:
        if s.geometry.kind != "capsule":
            out.append(s)
            continue
        r, length = s.geometry.size[0], s.geometry.size[1]
        out.append(replace(s, geometry=Geometry("cylinder", (r, length))))  # same pose, same origin
        for k, sign in ((1, -1.0), (2, 1.0)):
            end = np.eye(4)
            end[2, 3] = sign * length / 2
            out.append(replace(s, pose=s.pose @ end, geometry=Geometry("sphere", (r,)), origin=None,
                               name=None if s.name is None else f"{s.name}_cap{k}"))
    return out


def _link_xml(name: str, frame: np.ndarray, shapes: list[Shape], inertial: Inertial | None,
              scale: float) -> list[str]:
    if not shapes and inertial is None:
        return [f"  <link name={quoteattr(name)}/>"]
    out = [f"  <link name={quoteattr(name)}>"]
    inv = se3.inv(frame)
    if inertial is not None:
        I = inertial.inertia
        at = inv @ inertial.pose
        # a centre of mass on a link frame's axis stays on it: a coordinate within the rounding of the
        # two positions it is the difference of is 0 (mass_properties.EXACT_ZERO)
        reach = float(np.abs(frame[:3, 3]).max() + np.abs(inertial.pose[:3, 3]).max())
        at[:3, 3][np.abs(at[:3, 3]) <= EXACT_ZERO * reach] = 0.0
        out += ["    <inertial>", f"      {_origin(at, inertial.origin, scale)}".rstrip(),
                f'      <mass value="{_num(inertial.mass)}"/>',
                f'      <inertia ixx="{_num(I[0, 0])}" ixy="{_num(I[0, 1])}" ixz="{_num(I[0, 2])}" '
                f'iyy="{_num(I[1, 1])}" iyz="{_num(I[1, 2])}" izz="{_num(I[2, 2])}"/>', "    </inertial>"]
    for s in _urdf_shapes(shapes):
        head = f"    <{s.role}" + (f" name={quoteattr(s.name)}" if s.name else "") + ">"
        out += [head, f"      {_origin(inv @ s.pose, s.origin, scale)}".rstrip(),
                f"      <geometry>{_geometry(s)}</geometry>"]
        m = s.material
        if m is not None:
            inner = ("" if m.rgba is None else f'<color rgba="{" ".join(_num(v) for v in m.rgba)}"/>') + \
                ("" if m.texture is None else f"<texture filename={quoteattr(m.texture)}/>")
            # URDF needs a name on every material; a colour without one (MJCF, SDF) is named by its numbers
            label = m.name or ("rgba " + " ".join(_num(v) for v in m.rgba) if m.rgba is not None else None)
            name = f" name={quoteattr(label)}" if label else ""
            out.append(f"      <material{name}>{inner}</material>" if inner else f"      <material{name}/>")
        out.append(f"    </{s.role}>")
    out = [line for line in out if line.strip()]
    out.append("  </link>")
    return out


def _faithful_frames(robot: Robot) -> dict[str, np.ndarray] | None:
    """Frame of every source link in the output (base frame at q = 0), or None when the bodies do not
    describe this robot (another joint count or names), so that the plain writer is used."""
    from ...representations.dh import flip_frame

    b = robot.bodies
    by_name = {link.name: link for link in b.links}
    if (len(b.chain) != robot.n + 1 or len(by_name) != len(b.links) or b.tip not in by_name
            or any(name not in by_name for name in b.chain)):
        return None
    for i, j in enumerate(robot.joints):
        lj = by_name[b.chain[i + 1]].joint
        if lj is None or lj.name != j.name:
            return None
    frames = {link.name: link.pose for link in b.links}
    frames[b.chain[0]] = np.eye(4)
    tol = ON_AXIS_TOL * robot.scale
    for i, j in enumerate(robot.joints):
        P, J = frames[b.chain[i + 1]], robot.frames[i]
        d = P[:3, 3] - J[:3, 3]
        off_axis = np.linalg.norm(d - np.dot(d, J[:3, 2]) * J[:3, 2])
        if j.revolute and off_axis > tol:
            frames[b.chain[i + 1]] = flip_frame(J, j.flip)
    if b.tip == b.chain[-1] and np.abs(frames[b.tip] - robot.tool).max() > tol:
        # the last link is the tool link: it can take the tool's frame where that frame's origin is on
        # the last joint's axis (a calibrated flange; any frame for a prismatic joint)
        J, d = robot.frames[-2], robot.tool[:3, 3] - robot.frames[-2][:3, 3]
        if not robot.joints[-1].revolute or np.linalg.norm(d - np.dot(d, J[:3, 2]) * J[:3, 2]) <= tol:
            frames[b.tip] = robot.tool
    if b.tip == b.chain[-1]:
        if np.abs(frames[b.tip] - robot.tool).max() > tol:
            return None  # the tool left the last link's frame: no source link can carry it
    frames[b.tip] = robot.tool
    # the world -> base transform (Robot.world): a root link above the base is placed so that the path
    # down to the base gives it (readers compose that path into Robot.world); a root at the base gets a
    # 'world' link in ``_faithful``
    root = next((link.name for link in b.links if link.parent is None), b.chain[0])
    if root != b.chain[0]:
        frames[root] = se3.inv(robot.world)
    return frames


def _faithful(robot: Robot, frames: dict[str, np.ndarray]) -> list[str]:
    b = robot.bodies
    scale = max(robot.scale, 1.0)
    chain_joint = {name: i for i, name in enumerate(b.chain[1:])}
    shapes: dict[str, list[Shape]] = defaultdict(list)
    for s in b.shapes:
        shapes[s.link if s.link in frames else b.chain[s.body]].append(s)
    inertials: dict[str, Inertial] = {}
    for m in b.inertials:  # URDF has one inertial per link: the first one found for a link is kept
        inertials.setdefault(m.link if m.link in frames else b.chain[m.body], m)
    out: list[str] = []
    root = next((link.name for link in b.links if link.parent is None), b.chain[0])
    if root == b.chain[0] and "world" not in frames and np.abs(robot.world - np.eye(4)).max() > UNIT_NOISE:
        out.append('  <link name="world"/>')
        taken = {lk.joint.name for lk in b.links if lk.joint is not None}
        out += _joint_xml(_free_name("world_joint", taken), "fixed", "world", root,
                          _origin(robot.world, None, scale), None, None)
    for link in b.links:
        out += _link_xml(link.name, frames[link.name], shapes.get(link.name, []), inertials.get(link.name), scale)
    for link in b.links:
        if link.parent is None or link.joint is None:
            continue
        out += _link_joint_xml(robot, link, frames, chain_joint.get(link.name), scale)
    out += ["  " + x for x in b.extras]  # transmissions, Gazebo tags...: as the source wrote them
    return out


def _free_name(name: str, taken: set[str]) -> str:
    while name in taken:
        name += "_"
    return name


def _link_joint_xml(robot: Robot, link: Link, frames: dict[str, np.ndarray], index: int | None,
                    scale: float) -> list[str]:
    """The joint from ``link.parent`` to ``link``: the robot's joint ``index`` or the source's as it was."""
    lj, parent = link.joint, link.parent
    if lj is None or parent is None:  # pragma: no cover - callers skip the root
        raise ValueError(f"link '{link.name}' has no parent joint")
    child = frames[link.name]
    rel = se3.inv(frames[parent]) @ child
    origin = _origin(rel, lj.xyz_rpy, scale)
    if index is None:
        return _joint_xml(lj.name, lj.type, parent, link.name, origin, _unit(lj.axis),
                          _limit(lj.type, lj.lower, lj.upper, lj.effort, lj.velocity), lj.damping, lj.friction,
                          lj.mimic)
    j = robot.joints[index]
    axis = child[:3, :3].T @ robot.frames[index][:3, 2]
    if np.abs(axis - np.asarray(lj.axis)).max() <= UNIT_NOISE * 10:
        axis = np.asarray(lj.axis)  # the source's unit axis, where the link frame is the source's
    if not j.revolute:
        jtype = "prismatic"
    elif j.lower is None and j.upper is None and lj.type == "continuous":
        jtype = "continuous"
    else:
        jtype = "revolute"
    return _joint_xml(j.name, jtype, parent, link.name, origin, _unit(axis),
                      _limit(jtype, j.lower, j.upper, j.effort, j.velocity), j.damping, j.friction)


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


def _plain(robot: Robot) -> list[str]:
    """world, base, link1..linkN, tool; shapes and inertials (if any) on the link of their body."""
    from ...representations.dh import flip_frame

    world, base, links, tool, base_joint, tool_joint = _unique_names(robot)
    scale = max(robot.scale, 1.0)
    D = [np.eye(4)] + [flip_frame(robot.frames[i], j.flip) for i, j in enumerate(robot.joints)]
    shapes: dict[int, list[Shape]] = defaultdict(list)
    for s in robot.bodies.shapes:
        shapes[s.body].append(s)
    inertials: dict[int, Inertial] = {}
    for m in robot.bodies.inertials:  # URDF has one inertial per link: the first one of a body is kept
        inertials.setdefault(m.body, m)
    out = [f"  <link name={quoteattr(world)}/>"]
    for b, name in enumerate([base] + links):
        out += _link_xml(name, D[b], shapes.get(b, []), inertials.get(b), scale)
    out.append(f"  <link name={quoteattr(tool)}/>")
    out += _joint_xml(base_joint, "fixed", world, base, _origin(robot.world, None, scale), None, None)
    prev_name = base
    for i, j in enumerate(robot.joints):
        jtype = j.type
        out += _joint_xml(j.name, jtype, prev_name, links[i], _origin(se3.inv(D[i]) @ D[i + 1], None, scale),
                          f"0 0 {'-1' if j.flip else '1'}", _limit(jtype, j.lower, j.upper, j.effort, j.velocity),
                          j.damping, j.friction)
        prev_name = links[i]
    out += _joint_xml(tool_joint, "fixed", prev_name, tool, _origin(se3.inv(D[-1]) @ robot.tool, None, scale),
                      None, None)
    return out


def _warn_armature(robot: Robot) -> None:
    """One warning line naming the joints whose armature (rotor inertia, MJCF) URDF has no place for."""
    named = [j.name for j in robot.joints if j.armature]
    named += [lk.joint.name for lk in robot.bodies.links
              if lk.joint is not None and lk.joint.armature and lk.joint.name not in named]
    if named:
        import warnings

        listed = ", ".join(named[:8]) + (f" and {len(named) - 8} more" if len(named) > 8 else "")
        warnings.warn(f"URDF cannot carry joint armature (rotor inertia, in the mass matrix of MJCF models): "
                      f"left out for {listed}", UserWarning, stacklevel=3)


def urdf_from_robot(robot: Robot) -> str:
    """A URDF (text) of the robot, FK-identical at every q; see the module doc for what it holds.

    Joint armature (MJCF) has no URDF element: it is left out, said in one warning line naming the joints.

    Parameters
    ----------
    robot : Robot
        Any robot. With ``robot.bodies`` from a robot file, the file's links, joints, shapes and
        inertials are written under their own names; otherwise a plain chain world, base,
        link1..linkN, tool.
    """
    from ...version import __version__

    frames = _faithful_frames(robot) if robot.bodies.links else None
    body = _plain(robot) if frames is None else _faithful(robot, frames)
    _warn_armature(robot)
    unknown = [j.name for j in robot.joints if j.effort is None or j.velocity is None]
    head = ['<?xml version="1.0"?>', f"<!-- written by robkin {__version__} -->"]
    if unknown:
        names = ", ".join(unknown[:8]).replace("--", "- -")  # '--' may not appear inside a comment
        head.append(f"<!-- effort and velocity of joint(s) {names}"
                    f"{', ...' if len(unknown) > 8 else ''} are not known: written as 0 -->")
    return "\n".join(head + [f"<robot name={quoteattr(robot.name or 'robot')}>"] + _HEADER + body
                     + ["</robot>", ""])
