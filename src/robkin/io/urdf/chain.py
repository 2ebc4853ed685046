"""A serial chain out of a URDF tree (``UrdfModel``), as a Robot that keeps the rest of the file.

The chain runs from ``base_link`` to ``tip_link``. Either end may be any link rigidly attached to the
chain: the path between them may first climb from the base through fixed joints (UR's ``base`` is a
fixed child of ``base_link``, turned by pi) and then descends to the tip, through the chain's joints
and any fixed ones (a ``flange``, a ``tool0``). Every other link of the file is kept, on the body it
moves with, in ``Robot.bodies`` (see ``robkin.bodies``); joints off the chain are held at 0.
"""

from __future__ import annotations

import math
import os
import warnings
from typing import TYPE_CHECKING, Callable, Iterator

import numpy as np

from ...bodies import Bodies, LazyTuple
from ...errors import InputError, ProjectionWarning
from ...robot import Joint, Robot
from ...compiled.conversions import pose_rows
from ...compiled.scanners.vocabulary import MAX_JOINTS
if TYPE_CHECKING:
    from ...body_parts import Inertial, Link, LinkJoint, Shape
from ..trees.model import UNSUPPORTED_TYPES, UrdfJoint, UrdfModel
from .parser import AXIS_UNIT_TOL, AXIS_ZERO_TOL, parse_urdf
from ..trees.joint_limits import warn_locked

Rows3 = tuple[tuple[float, float, float], tuple[float, float, float], tuple[float, float, float]]

__all__ = ["robot_from_urdf", "robot_from_model", "axis_frame", "axis_rotation", "select_chain", "chains_of"]


def _tree_leaves(kids: dict[str, list[UrdfJoint]], top: str, rigid_too: bool) -> list[str]:
    """Leaf links below ``top`` in file order; without ``rigid_too``, not those joined to ``top`` by
    fixed joints only (they are part of the base, not the end of a chain)."""
    out: list[str] = []
    stack: list[tuple[str, bool]] = [(top, True)]
    while stack:
        link, rigid = stack.pop()
        if not kids[link] and (rigid_too or not rigid):
            out.append(link)
        stack.extend((j.child, rigid and j.type == "fixed") for j in reversed(kids[link]))
    return out


def _default_base(model: UrdfModel, root: str | None = None) -> str:
    """The root link (or ``root``), or its child when the root is a ``world`` link fixed to it (a
    virtual world link is the world->base transform, not the robot)."""
    root = model.root() if root is None else root
    kids = model.children()[root]
    if root == "world" and len(kids) == 1 and kids[0].type == "fixed":
        return kids[0].child
    return root


def _tip_candidates(model: UrdfModel, base_link: str) -> list[str]:
    """Leaves below the base that end a chain: not those rigidly part of the base itself."""
    parents = model.parent_joint()
    top = base_link  # the highest link rigidly joined to the base: chains start below it
    while top in parents and parents[top].type == "fixed":
        top = parents[top].parent
    return _tree_leaves(model.children(), top, rigid_too=False)


def chains_of(model: UrdfModel, base_link: str | None = None) -> list[tuple[str, str, list[UrdfJoint]]]:
    """Every serial chain the tree offers from the base: (base, tip leaf, its moving joints), in file
    order. Chains that climb through a moving joint (a base in the middle of the tree) are left out.
    Without ``base_link``, the chains of every unconnected tree (an SDF model may hold several)."""
    bases = [_default_base(model, root) for root in model.roots()] if base_link is None else [base_link]
    out = []
    for base in bases:
        for tip in _tip_candidates(model, base):
            _, _, _, down = select_chain(model, base, tip)
            out.append((base, tip, [j for j in down if j.type != "fixed"]))
    return out


def select_chain(model: UrdfModel, base_link: str | None, tip_link: str | None
                 ) -> tuple[str, str, list[UrdfJoint], list[UrdfJoint]]:
    """(base link, tip link, joints climbed from the base (all fixed), joints descended to the tip).

    Defaults: the base is the root link (its child when the root is a ``world`` link fixed to it); the
    tip is the only leaf below the base that is not rigidly part of the base. InputError otherwise,
    listing the choices.
    """
    src = model.source
    known = set(model.links)
    for opt, link in (("base_link=", base_link), ("tip_link=", tip_link)):
        if link is not None and link not in known:
            stem = link[:3]
            close = ", ".join(sorted(known, key=lambda s: (not s.startswith(stem), s))[:8])
            raise InputError(f"{src}: {opt}'{link}' is not a link of the file (links include: {close})")
    parents = model.parent_joint()
    kids = model.children()
    if base_link is None:
        base_link = _default_base(model)
    if tip_link is None:
        leaves = _tip_candidates(model, base_link)
        if len(leaves) > 1:
            shown = ", ".join(leaves[:24]) + (f", ... ({len(leaves) - 24} more)" if len(leaves) > 24 else "")
            raise InputError(f"{src}: the links below '{base_link}' form a tree with {len(leaves)} leaf links; "
                             f"pick the chain's end with tip_link=, one of: {shown} (robkin info lists the "
                             f"chains)")
        tip_link = leaves[0] if leaves else base_link
    above_tip = {tip_link}  # the path from the tip up to the root
    link = tip_link
    while True:
        above_tip.add(link)
        if link not in parents:
            break
        link = parents[link].parent
    up: list[UrdfJoint] = []
    link = base_link
    while link not in above_tip:
        up.append(parents[link])
        link = parents[link].parent
    meet = link
    down: list[UrdfJoint] = []
    link = tip_link
    while link != meet:
        down.append(parents[link])
        link = parents[link].parent
    down.reverse()
    moving = [j.name for j in up if j.type != "fixed"]
    if moving:
        raise InputError(f"{src}: tip_link='{tip_link}' is not below base_link='{base_link}': the path "
                         f"between them climbs through joint '{moving[0]}', which moves; a base may hang from "
                         f"the chain through fixed joints only (links below '{base_link}' end in: "
                         f"{', '.join(_tree_leaves(kids, base_link, rigid_too=True)[:12])})")
    return base_link, tip_link, up, down


#: ``axis_rotation`` of the axis 0 0 1: the identity (the joint frame is its link's frame)
_Z_UP: Rows3 = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


def axis_rotation(x: float, y: float, z: float) -> Rows3:
    """``axis_frame``'s rotation for the unit axis (x, y, z), as three rows of plain floats.

    Scalar arithmetic: it runs for every joint of a chain, where numpy's per-call overhead on 3x3
    arrays was most of the load time of a small URDF.
    """
    flip = z < 0
    bx, by, bz = (-x, -y, -z) if flip else (x, y, z)
    if bx == 0 and by == 0:  # the axis is +-z: the rotation is exact (no rounding)
        return ((1.0, 0.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, -1.0)) if flip else _Z_UP
    # minimal rotation e_z -> b (b_z >= 0): R = I + K + K^2 / (1 + c), K = [e_z x b], c = b_z;
    # 1 + c >= 1, so this is well conditioned for every b in the upper half sphere.
    c = 1.0 + bz
    xy = -bx * by / c
    R = ((1.0 - bx * bx / c, xy, bx), (xy, 1.0 - by * by / c, by), (-bx, -by, 1.0 - (bx * bx + by * by) / c))
    if flip:  # turned by pi about x: columns 2 and 3 change sign
        (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = R
        R = ((r00, -r01, -r02), (r10, -r11, -r12), (r20, -r21, -r22))
    return R


def axis_frame(axis: np.ndarray) -> tuple[np.ndarray, bool]:
    """Rotation (3, 3) whose z column is the unit ``axis``, and whether the joint is flipped.

    Axes with a non-negative z component get the minimal rotation taking z onto the axis (identity for
    ``0 0 1``). Axes pointing against z get flip = True and the minimal rotation onto -axis, turned
    by pi about x: its z is the axis, and the flipped frame used by DH/RPY tables is the minimal one.
    """
    x, y, z = (float(v) for v in axis)
    return np.array(axis_rotation(x, y, z)), z < 0


def _unit_axis(j: UrdfJoint, src: str) -> tuple[float, float, float]:
    """The joint's axis as a unit vector of plain floats (InputError if zero, warned if not unit)."""
    x, y, z = j.axis_xyz()
    k = math.sqrt(x * x + y * y + z * z)
    if k < AXIS_ZERO_TOL:
        raise InputError(f"{src}: joint '{j.name}': axis xyz is zero; a {j.type} joint needs a direction "
                         f"such as '0 0 1'")
    if abs(k - 1.0) > AXIS_UNIT_TOL:
        warnings.warn(f"{src}: joint '{j.name}': axis has length {k:.6g}; normalised to a unit vector",
                      ProjectionWarning, stacklevel=5)
    return x / k, y / k, z / k


def robot_from_urdf(source: str | os.PathLike[str], base_link: str | None = None, tip_link: str | None = None,
                    *, name: str | None = None, allow_xacro: bool = False) -> Robot:
    """The serial chain base_link -> tip_link of a URDF (path, .xacro path, or XML string) as a Robot.

    Parameters
    ----------
    source : path or str
        A .urdf or .xacro file, or URDF XML text (a string starting with '<').
    base_link, tip_link : str, optional
        Ends of the chain; each may be any link rigidly attached to the chain's ends (through fixed
        joints in either direction). Default base: the root link (its child when the root is a
        ``world`` link fixed to it). Default tip: the only leaf below the base that is not rigidly
        part of it; with several an InputError lists them.
    name : str, optional
        Robot name; default the URDF's ``<robot name>``.
    allow_xacro : bool
        Expand a .xacro file (default False: refused). xacro runs code and reads files and
        environment variables named in the file; pass True only for files you trust.

    Returns
    -------
    Robot
        GJD frames (n+1, 4, 4) in the base link frame (lengths in the file's unit, normally metres),
        joints with the URDF names, limits, effort, velocity and dynamics, ``world`` = root link ->
        base link at q = 0, and ``bodies``: every link, shape and inertial of the file.
    """
    return robot_from_model(parse_urdf(source, allow_xacro=allow_xacro), base_link, tip_link, name=name)


def _link_joint(j: UrdfJoint) -> LinkJoint:
    from ...body_parts import LinkJoint

    x, y, z = j.axis_xyz()
    k = math.sqrt(x * x + y * y + z * z)
    axis = (x / k, y / k, z / k) if k >= AXIS_ZERO_TOL else (x, y, z)
    # ``or None``: readers of other formats may give mimic=False (the field was a flag once)
    return LinkJoint(j.name, j.type, axis, j.lower, j.upper, j.effort, j.velocity, j.damping, j.friction,
                     j.mimic or None, j.xyz_rpy, j.armature)


def robot_from_model(model: UrdfModel, base_link: str | None = None, tip_link: str | None = None,
                     *, name: str | None = None) -> Robot:
    """``robot_from_urdf`` of an already parsed URDF (see ``parse_urdf_text`` for text input)."""
    src = model.source
    base, tip, up, down = select_chain(model, base_link, tip_link)
    chain = [j for j in down if j.type != "fixed"]
    for j in chain:
        if j.type in UNSUPPORTED_TYPES:
            raise InputError(f"{src}: joint '{j.name}' is {j.type}; only revolute, continuous, prismatic and "
                             f"fixed joints make a serial chain (pick another chain with base_link=/tip_link=)")
        if j.mimic:
            raise InputError(f"{src}: joint '{j.name}' mimics another joint; robkin needs independent joints "
                             f"(end the chain before it with tip_link=)")
    if len(chain) > MAX_JOINTS:
        raise InputError(f"{src}: {len(chain)} joints between '{base}' and '{tip}'; at most {MAX_JOINTS} are read "
                         f"(pick a shorter chain with base_link=/tip_link=)")
    if not chain:
        raise InputError(f"{src}: no revolute, continuous or prismatic joint between '{base}' and "
                         f"'{tip}'; a robot needs at least one")
    # poses along the path base -> tip (climbing, then descending): all the kinematics needs
    T = pose_rows.IDENTITY
    poses = {base: T}
    for j in up:
        T = pose_rows.compose(T, pose_rows.inverse(j.pose()))
        poses[j.parent] = T
    for j in down:
        T = pose_rows.compose(T, j.pose())
        poses[j.child] = T
    # each joint's frame: its child link's frame turned so that z is the axis
    frames, joints = [], []
    for j in chain:
        x, y, z = _unit_axis(j, src)
        R = axis_rotation(x, y, z)
        if R is _Z_UP:
            frames.append(poses[j.child])
        else:
            (a, b, c), (d, e, f), (g, h, i) = R
            frames.append(pose_rows.compose(poses[j.child], (a, b, c, 0.0, d, e, f, 0.0, g, h, i, 0.0)))
        jtype = "prismatic" if j.type == "prismatic" else "revolute"
        joints.append(Joint(j.name, jtype, j.lower, j.upper, z < 0, j.effort, j.velocity,  # type: ignore[arg-type]
                            j.damping, j.friction, j.armature))
    frames.append(poses[tip])
    warn_locked(src, joints)  # equal limits: locked, as urdfdom, pinocchio and yourdfpy read them
    world = _world(model, base)
    links, shapes, inertials = _rest_of_the_file(model, base, {j.name: i + 1 for i, j in enumerate(chain)})
    bodies = Bodies(LazyTuple(links), (base,) + tuple(j.child for j in chain), tip, LazyTuple(shapes),
                    LazyTuple(inertials), model.extras)
    return Robot(pose_rows.matrices(frames), tuple(joints), world=world, name=name or model.name, bodies=bodies)


def _rest_of_the_file(model: UrdfModel, base: str, chain_index: dict[str, int]) -> tuple[
        Callable[[], Iterator[Link]], Callable[[], Iterator[Shape]], Callable[[], Iterator[Inertial]]]:
    """Three functions giving the links, the shapes and the inertials of the whole file, each on its
    body, made on first use (see ``LazyTuple``): loading a robot for its kinematics costs none of it."""
    memo: list[tuple[dict[str, np.ndarray], dict[str, int]]] = []

    def tree() -> tuple[dict[str, np.ndarray], dict[str, int]]:
        if not memo:
            memo.append(_home_poses(model, base, chain_index))
        return memo[0]

    def links() -> Iterator[Link]:
        from ...body_parts import Link

        poses, body = tree()
        parents = model.parent_joint()
        for link in model.links:
            pj = parents.get(link)
            yield Link(link, body[link], poses[link], None if pj is None else pj.parent,
                       None if pj is None else _link_joint(pj))

    def shapes() -> Iterator[Shape]:
        from ...body_parts import Shape

        poses, body = tree()
        for link in model.links:
            content = model.content.get(link)
            if content is not None:
                P, b = poses[link], body[link]
                for s in content.shapes:
                    yield Shape(s.link, b, s.role, np.dot(P, s.pose), s.geometry, s.material, s.name, s.origin)

    def inertials() -> Iterator[Inertial]:
        from ...body_parts import Inertial

        poses, body = tree()
        content = model.content
        # the inertial alone where the reader can parse it so (URDF): the shapes need not be valid
        inertial_of = getattr(content, "inertial", None) or (lambda link: getattr(content.get(link), "inertial", None))
        for link in model.links:
            m = inertial_of(link)
            if m is not None:
                yield Inertial(m.link, body[link], np.dot(poses[link], m.pose), m.mass, m.inertia, m.origin)

    return links, shapes, inertials


def _home_poses(model: UrdfModel, base: str, chain_index: dict[str, int]
                ) -> tuple[dict[str, np.ndarray], dict[str, int]]:
    """Pose (4, 4) of every link in the base link frame with every joint at 0, and the body each moves
    with (0 = the base; i = after chain joint i). A walk over the tree from the base, climbing
    (inverse origins) as well as descending; joints off the chain count as held at 0."""
    parents = model.parent_joint()
    kids = model.children()
    poses = {base: pose_rows.IDENTITY}
    body = {base: 0}
    stack = [base]
    while stack:
        link = stack.pop()
        P, b = poses[link], body[link]
        for j in kids[link]:
            if j.child not in poses:
                poses[j.child] = pose_rows.compose(P, j.pose())
                body[j.child] = chain_index.get(j.name, b)
                stack.append(j.child)
        pj = parents.get(link)
        if pj is not None and pj.parent not in poses:
            # climbing: the chain's joints all lie below the base, so a climbed joint is never one
            poses[pj.parent] = pose_rows.compose(P, pose_rows.inverse(pj.pose()))
            body[pj.parent] = b
            stack.append(pj.parent)
    arrays = pose_rows.matrices(list(poses.values()))
    return dict(zip(poses, arrays)), body


def _world(model: UrdfModel, base: str) -> np.ndarray:
    """World (root link) -> base link with the joints between them held at 0 (warned if any moves)."""
    parents = model.parent_joint()
    above: list[UrdfJoint] = []
    link = base
    while link in parents:
        above.append(parents[link])
        link = parents[link].parent
    moving = [j.name for j in above if j.type != "fixed"]
    if moving:
        warnings.warn(f"{model.source}: joint(s) {', '.join(reversed(moving))} above base link '{base}' are "
                      f"held at 0 in the world->base transform", UserWarning, stacklevel=4)
    world = pose_rows.IDENTITY
    for j in reversed(above):
        world = pose_rows.compose(world, j.pose())
    return pose_rows.matrix(world)
