"""A Robot as an MJCF model MuJoCo simulates: bodies, joints, geoms, inertials, actuators.

What is written (``mjcf_text``)
    ``<compiler angle="radian" autolimits="true" inertiafromgeom="false">``: radians, and no mass
    invented from the shapes; the default classes ``visual`` and ``collision`` (``geoms_write``);
    mesh and material assets; the body tree of ``tree`` (body names = the source's link names);
    each joint with its axis, ``range`` (``limited="false"`` when unlimited, or when lower = upper:
    MuJoCo refuses an empty range), ``damping``, ``frictionloss`` and ``armature`` where the source
    gave them; inertials exact (``inertial``); mimic joints as ``<equality><joint>`` with
    ``polycoef="offset multiplier 0 0 0"``; actuators (``actuators``).

Simulation (a servo plan, ``robkin.simulation.servos``: the gain rule is that module's doc)
    ``<option integrator="implicitfast" timestep="0.002">`` (the servos' damping integrated implicitly;
    the step the gains are made for); position servos by default; gravity compensation (on by default
    for position and velocity servos) as ``gravcomp="1"`` on every moving body: MuJoCo's passive force,
    an ideal counterbalance outside the actuators' effort (see ``robkin.simulation.servos``); a keyframe ``home`` with
    every joint inside its limits (``Robot.home``: q = 0 clipped into them, or the caller's) and
    ``ctrl`` holding it. The bodies are drawn at home and each joint's ``ref`` is its home, so MuJoCo's
    qpos0 (its reset, the viewer's start) is home too, while qpos stays q; the joint equalities, which
    MuJoCo writes relative to qpos0, are offset to match.

What q means
    MuJoCo's qpos[:n] is q: the chain's joints come first in the tree (each chain child is its
    parent's first child), joints off the chain after them (at 0 clipped into their limits in
    ``home``). The site named as the tip link (``tool`` for a robot from a table) is at
    world @ robot.fk(q).

Numbers are written in full precision (``repr``); poses relative to the parent body as ``pos`` and a
unit quaternion ``quat`` (w, x, y, z), axis components below 1e-15 as 0 (rounding noise).
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING, Any, Mapping, Sequence

import numpy as np

from ... import se3
from ..files.float_text import float_text as _num
from .format import place_attrs
from .actuators import ServoPlan, actuated, actuator_lines
from .contacts import contact_lines
from .geoms_write import DEFAULT_CLASSES, GeomAssets
from .inertial import PLACEHOLDER_INERTIA, PLACEHOLDER_MASS, BodyMass, body_mass, inertial_xml
from .tree import BodyPlan, JointPlan, body_tree
from ..files.xmltext import quoteattr

if TYPE_CHECKING:  # pragma: no cover
    from ...robot import Robot

__all__ = ["mjcf_from_robot", "mjcf_text", "CHANGED_MARK"]

#: Axis components and joint offsets below this (relative to 1 and to the robot size) are rounding
#: noise of unit-size products: written as 0.
UNIT_NOISE = 1e-15
#: Start of the comment that lists the masses the writer changed so that MuJoCo loads the model
#: (``robkin convert``'s check after writing looks for it).
CHANGED_MARK = "masses changed so that MuJoCo loads the model"
#: MuJoCo's mjMINVAL: a moving body needs more mass and principal inertia than this (with what is welded to it).
MJ_MINVAL = 1e-15


def _nums(v) -> str:
    return " ".join(_num(x) for x in v)


def _clean(v: np.ndarray, scale: float = 1.0) -> np.ndarray:
    out = np.array(v, dtype=float)
    out[np.abs(out) < UNIT_NOISE * scale] = 0.0
    return out


def _joint_xml(j: JointPlan, frame: np.ndarray, scale: float, ref: float = 0.0) -> str:
    from ..trees.model import NO_LIMIT

    axis = _clean(frame[:3, :3].T @ j.axis)
    pos = _clean(se3.inv(frame)[:3, :3] @ j.point + se3.inv(frame)[:3, 3], scale)
    out = f"<joint name={quoteattr(j.name)} type=\"{'slide' if j.slide else 'hinge'}\""
    if pos.any():
        out += f' pos="{_nums(pos)}"'
    out += f' axis="{_nums(axis)}"'
    if ref != 0.0:  # drawn at home: qpos0 = home, so MuJoCo's reset and viewer start there
        out += f' ref="{_num(ref)}"'
    if (j.lower is None and j.upper is None) or j.lower == j.upper:
        out += ' limited="false"'
    else:
        lo = -NO_LIMIT if j.lower is None else j.lower
        hi = NO_LIMIT if j.upper is None else j.upper
        out += f' limited="true" range="{_num(lo)} {_num(hi)}"'
    for attr, v in (("damping", j.damping), ("frictionloss", j.friction), ("armature", j.armature)):
        if v is not None:
            out += f' {attr}="{_num(v)}"'
    return out + "/>"


def _masses(plan: list[BodyPlan]) -> tuple[list[BodyMass | None], list[str]]:
    """Each body's mass properties, with placeholders where MuJoCo needs them: (masses, the bodies given
    placeholders)."""
    from ...mass_properties import merge_masses
    from .inertial import valid_moments

    masses = [body_mass(bp.inertials) for bp in plan]
    placeholders: list[str] = []
    for i, bp in enumerate(plan):
        if bp.joint is None:
            continue
        group = [i]
        k = 0
        while k < len(group):  # this body and the bodies welded to it
            group += [c for c in plan[group[k]].children if plan[c].joint is None]
            k += 1
        parts = [masses[g] for g in group if masses[g] is not None and masses[g].mass > 0]  # type: ignore[union-attr]
        total = sum(p.mass for p in parts)  # type: ignore[union-attr]
        moments = np.zeros(3)
        if total > MJ_MINVAL:
            _, _, I = merge_masses(np.array([p.mass for p in parts]), np.stack([p.com for p in parts]),  # type: ignore[union-attr]
                                   np.stack([p.inertia for p in parts]))  # type: ignore[union-attr]
            moments = valid_moments(np.linalg.eigvalsh(I))[0]
        if total > MJ_MINVAL and moments.min() > MJ_MINVAL:
            continue
        placeholders.append(bp.name)
        own = masses[i]
        if own is None or own.mass <= 0:
            masses[i] = BodyMass(PLACEHOLDER_MASS, bp.frame[:3, 3].copy(), PLACEHOLDER_INERTIA * np.eye(3),
                                 bp.frame, np.full(3, PLACEHOLDER_INERTIA))
        else:
            masses[i] = BodyMass(own.mass, own.com, own.inertia + PLACEHOLDER_INERTIA * np.eye(3), own.frame,
                                 None if own.diag is None else own.diag + PLACEHOLDER_INERTIA)
    return masses, placeholders


def _is_world(bp: BodyPlan) -> bool:
    """A plan entry that is MuJoCo's world body (a source link called 'world' fixed at the top)."""
    return bp.parent is None and bp.name in ("", "world")


def _screw_motion(j: JointPlan, v: float) -> np.ndarray:
    """The rigid motion (4, 4, base frame) of joint ``j`` moved from 0 to ``v``."""
    T = np.eye(4)
    a = np.asarray(j.axis, dtype=float)
    if j.slide:
        T[:3, 3] = v * a
        return T
    K = np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
    R = np.eye(3) + np.sin(v) * K + (1.0 - np.cos(v)) * (K @ K)
    T[:3, :3] = R
    T[:3, 3] = j.point - R @ j.point
    return T


def _home_motions(plan: list[BodyPlan], homes: Mapping[str, float]) -> list[np.ndarray]:
    """Each body's rigid motion (base frame) from q = 0 to home: the product of its joints' motions from
    the root down (``plan`` lists parents first)."""
    out: list[np.ndarray] = []
    for bp in plan:
        M = np.eye(4) if bp.parent is None else out[bp.parent]
        v = homes.get(bp.joint.name, 0.0) if bp.joint is not None else 0.0
        out.append(M @ _screw_motion(bp.joint, v) if bp.joint is not None and v != 0.0 else M)
    return out


def _body_lines(plan: list[BodyPlan], masses: list[BodyMass | None], world: np.ndarray, geoms: GeomAssets,
                scale: float, repaired: list[str], gravcomp: bool = False,
                homes: Mapping[str, float] | None = None) -> list[str]:
    """The bodies' lines; ``gravcomp``: gravity compensated on every moving body; ``homes``: joint name ->
    home, each body placed at home and each joint's ``ref`` its home (qpos = q still; MuJoCo's qpos0 =
    home). Whatever a body carries (geoms, inertial, sites, its joint's axis) keeps its pose relative
    to the body."""
    homes = homes or {}
    motion = _home_motions(plan, homes)
    out: list[str] = []
    moving = [False] * len(plan)
    top = [i for i, bp in enumerate(plan) if bp.parent is None]
    todo: list[tuple[int, int, bool]] = [(i, 2, False) for i in reversed(top)]  # (body, depth, closing)
    while todo:
        i, depth, closing = todo.pop()
        ind = "  " * depth
        if closing:
            out.append(f"{ind}</body>")
            continue
        bp = plan[i]
        par = bp.parent
        parent_frame = np.eye(4) if par is None or _is_world(plan[par]) else world @ motion[par] @ plan[par].frame
        abs_frame = world @ motion[i] @ bp.frame
        if _is_world(bp):  # MuJoCo's world body itself: its geoms and sites, then its children, in <worldbody>
            for s in bp.shapes:
                out += [f"{ind}{g}" for g in geoms.geoms(s, se3.inv(world), scale)]
            out += [f"{ind}<site name={quoteattr(n)}{place_attrs(world @ P, scale)}/>" for n, P in bp.sites]
            todo.extend((c, depth, False) for c in reversed(bp.children))
            continue
        moving[i] = bp.joint is not None or (par is not None and moving[par])
        comp = ' gravcomp="1"' if gravcomp and moving[i] else ""
        out.append(f"{ind}<body name={quoteattr(bp.name)}{place_attrs(se3.inv(parent_frame) @ abs_frame, scale, bp.origin)}{comp}>")
        if bp.joint is not None:
            out.append(f"{ind}  {_joint_xml(bp.joint, bp.frame, scale, homes.get(bp.joint.name, 0.0))}")
        if masses[i] is not None:
            text, changed = inertial_xml(masses[i], bp.frame, scale)  # type: ignore[arg-type]
            if changed:
                repaired.append(bp.name)
            out.append(f"{ind}  {text}")
        for s in bp.shapes:
            out += [f"{ind}  {g}" for g in geoms.geoms(s, bp.frame, scale)]
        for name, P in bp.sites:
            out.append(f"{ind}  <site name={quoteattr(name)}{place_attrs(se3.inv(bp.frame) @ P, scale)}/>")
        todo.append((i, depth, True))
        todo.extend((c, depth + 1, False) for c in reversed(bp.children))
    return out


def _equalities(joints: list[JointPlan], refs: Mapping[str, float] | None = None) -> list[str]:
    """The ``<equality>`` lines. MuJoCo's joint equality relates qpos - qpos0 (``ref``): with ``refs``
    (joint name -> ref), y - y0 = (offset + multiplier x0 - y0) + multiplier (x - x0) is y = offset +
    multiplier x, and a lock at v is y - y0 = v - y0."""
    from ..trees.joint_limits import locked_joints

    refs = refs or {}
    names = {j.name for j in joints}
    # equal limits: locked at that value (MuJoCo refuses an empty range; see robkin.io.trees.joint_limits)
    out = [f"    <joint joint1={quoteattr(name)} polycoef=\"{_num(v - refs.get(name, 0.0))} 0 0 0 0\"/>"
           for name, v in locked_joints([j for j in joints if j.mimic is None])]
    lost = []
    for j in joints:
        if j.mimic is None:
            continue
        if j.mimic.joint not in names:
            lost.append(j.name)
            continue
        offset = j.mimic.offset + j.mimic.multiplier * refs.get(j.mimic.joint, 0.0) - refs.get(j.name, 0.0)
        out.append(f"    <joint joint1={quoteattr(j.name)} joint2={quoteattr(j.mimic.joint)} "
                   f"polycoef=\"{_num(offset)} {_num(j.mimic.multiplier)} 0 0 0\"/>")
    if lost:
        warnings.warn(f"joint(s) {', '.join(lost[:6])} mimic a joint that is not in the model: written as free "
                      f"joints", UserWarning, stacklevel=4)
    return ["  <equality>"] + out + ["  </equality>"] if out else []


def mjcf_text(robot: Robot, *, mesh_files: Mapping[str, str] | None = None, actuators: str = "position",
              kp: float | None = None, kv: float | None = None, home: Sequence[float] | None = None,
              gravcomp: bool | None = None, servos: ServoPlan | None = None, fuse_fixed: bool = False,
              mesh_parts: Mapping[str, Sequence[tuple[str, tuple[float, ...]]]] | None = None,
              contact_excludes: Sequence[tuple[str, str]] | None = None) -> str:
    """The MJCF text of a robot (see the module doc).

    Parameters
    ----------
    robot : Robot
    mesh_files : mapping, optional
        Mesh file name as the source wrote it -> ``file`` to write (relative to the output's folder);
        mesh shapes whose file is not in it are left out (one warning when no mapping is given: the
        maker of a mapping says what it could not find).
    actuators : 'position' | 'velocity' | 'motor' | 'none'
    kp, kv : float, optional
        Servo gains of position (kp, kv) and velocity (kv) actuators (N m/rad, N m s/rad or N/m, N s/m)
        on every joint; default: each joint's from the rule of ``robkin.simulation.servos``.
    home : (n,) sequence of float, optional
        The chain's keyframe ``home`` (checked against the limits); default q = 0 clipped into them.
    gravcomp : bool, optional
        Gravity compensation; default on for position and velocity servos.
    servos : ServoPlan, optional
        A plan made by the caller (``robkin.simulation.servo_plan``); then ``actuators``, ``kp``, ``kv``,
        ``home`` and ``gravcomp`` are the plan's (the arguments of those names are not used).
    fuse_fixed : bool
        Merge bodies fixed to their parent into it (mass merged exactly; their names become sites).
    mesh_parts : mapping, optional
        Mesh file name as the source wrote it -> [(file to write, rgba)]: a visual mesh split by colour
        (``mesh_parts``), drawn as one geom per part where the source gives the shape no colour.
    contact_excludes : sequence of (body, body), optional
        Body pairs written as ``<contact><exclude>`` (``robkin.io.mjcf.contacts``).
    """
    from ...version import __version__

    if servos is None:
        from ...capabilities import servo_plan

        servos = servo_plan()(robot, kind=actuators, home=home, kp=kp, kv=kv, gravcomp=gravcomp)
    plan, named = body_tree(robot, fuse=fuse_fixed)
    scale = max(robot.scale, 1.0)
    geoms = GeomAssets(mesh_files, mesh_parts)
    masses, placeholders = _masses(plan)
    repaired: list[str] = []
    # MuJoCo's joint (and qpos) order is the tree's, which lists the chain first
    joints = [bp.joint for bp in plan if bp.joint is not None]
    driven = actuated(servos, joints)
    homes = {j.name: s.home for j in joints if (s := servos.get(j.name)) is not None}
    bodies = _body_lines(plan, masses, np.asarray(robot.world, dtype=float), geoms, scale, repaired,
                         servos.gravcomp, homes)
    if placeholders:
        warnings.warn(f"body(ies) {', '.join(placeholders[:6])}{', ...' if len(placeholders) > 6 else ''} move "
                      f"without mass or inertia (with what is welded to them): given {PLACEHOLDER_MASS:g} kg "
                      f"/ {PLACEHOLDER_INERTIA:g} kg m^2 so that MuJoCo loads the model", UserWarning, stacklevel=3)
    if repaired:
        warnings.warn(f"body(ies) {', '.join(repaired[:6])}{', ...' if len(repaired) > 6 else ''}: inertia not "
                      f"physical (a negative principal moment, or one above the sum of the other two): clipped to "
                      f"the nearest valid moments", UserWarning, stacklevel=3)
    if geoms.degenerate:
        shown = "; ".join(geoms.degenerate[:3]) + (f"; ... ({len(geoms.degenerate) - 3} more)"
                                                    if len(geoms.degenerate) > 3 else "")
        warnings.warn(f"{len(geoms.degenerate)} shape(s) of size zero left out of the MJCF (MuJoCo refuses them): "
                      f"{shown}", UserWarning, stacklevel=3)
    if geoms.missing and mesh_files is None:  # with a mapping, its maker said what it could not find
        shown = ", ".join(geoms.missing[:4]) + (f", ... ({len(geoms.missing) - 4} more)" if len(geoms.missing) > 4 else "")
        warnings.warn(f"{len(geoms.missing)} mesh file(s) not available to the MJCF ({shown}): their shapes are "
                      f"left out", UserWarning, stacklevel=3)
    changed = [f"<!-- {CHANGED_MARK}: {kind} of {', '.join(names).replace('--', '- -')} -->"
               for kind, names in (("placeholder mass", placeholders), ("repaired inertia", repaired)) if names]
    head = ['<?xml version="1.0"?>',
            f"<!-- written by robkin {__version__}"
            + ("" if named else ": bodies base, link1..linkN, tool (the robot has no link names)") + " -->",
            *changed,
            f"<mujoco model={quoteattr(robot.name or 'robot')}>",
            '  <compiler angle="radian" autolimits="true" inertiafromgeom="false"/>',
            # the servos' damping integrated implicitly, at the step their gains are made for
            f'  <option integrator="{servos.integrator}" timestep="{_num(servos.timestep)}"/>',
            # a brighter viewer headlight than MuJoCo's default (0.1 ambient, 0.4 diffuse): the model is
            # seen as it is without a scene around it
            '  <visual><headlight ambient="0.3 0.3 0.3" diffuse="0.6 0.6 0.6" specular="0.1 0.1 0.1"/></visual>',
            "  <default>"] + DEFAULT_CLASSES + ["  </default>"]
    assets = geoms.asset_lines()
    out = head + (["  <asset>"] + assets + ["  </asset>"] if assets else [])
    light = ['    <light name="robkin_light" pos="0 0 4" dir="0 0 -1" directional="true" castshadow="false"/>']
    out += ["  <worldbody>"] + light + bodies + ["  </worldbody>"]
    out += contact_lines(contact_excludes)
    out += _equalities(joints, homes)
    out += actuator_lines(servos, joints)
    qpos = [(s.home if (s := servos.get(j.name)) is not None else 0.0) for j in joints]
    key = f'    <key name="home" qpos="{_nums(qpos)}"'
    if driven:
        key += f' ctrl="{_nums([s.home if servos.kind == "position" else 0.0 for s in driven])}"'
    out += ["  <keyframe>", key + "/>", "  </keyframe>", "</mujoco>", ""]
    return "\n".join(out)


def mjcf_from_robot(robot: Robot, **options: Any) -> str:
    """MJCF text of the robot: a model MuJoCo simulates (``robkin.io.mjcf.writer.mjcf_text``, whose
    keyword options ``mesh_files``, ``actuators``, ``kp``, ``kv``, ``home``, ``gravcomp``, ``servos``,
    ``fuse_fixed`` it takes).

    MuJoCo's qpos[:n] is q, and the site named as the tip link (``tool`` for a robot without link
    names) is at ``world @ robot.fk(q)``.
    """
    return mjcf_text(robot, **options)
