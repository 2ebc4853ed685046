"""Which body pairs an MJCF model excludes from contact: parent-child pairs, and pairs already touching
at ``home``.

A robot's collision shapes often overlap where links meet (a joint housing inside the next link's
shell) and, in some files, between links two apart or between a gripper's fingers at rest. MuJoCo
already skips a body and its parent, except when the parent is welded to the world (an arm's base and
its first link), and it collides every other pair. So that the model starts at rest without a
penetrating contact, ``contact_excludes`` lists:

* every pair of rigid groups joined by a joint (a body with a joint, and the bodies welded to it, and
  the same for its parent), as MoveIt's "Adjacent";
* every pair of bodies whose collision geoms touch or penetrate at ``home`` (the draft's keyframe
  ``home``: ``Robot.home``, q = 0 clipped into each joint's limits, or ``--home``): closer than
  ``TOUCH`` times the robot's size, as MuJoCo computes their distance (a mesh through its convex
  hull). MoveIt's "Default" makes the same choice. This needs MuJoCo (``pip install mujoco``): the
  model is compiled in memory from the writer's draft and its contacts at home read (``mj_forward``)
  with every collision geom's margin set to the touch distance. Without
  MuJoCo, only the adjacent pairs are excluded, and the note says so.

The pairs are body names, written by the MJCF writer as ``<contact><exclude body1= body2=/>``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Iterable

import numpy as np

__all__ = ["TOUCH", "contact_excludes", "adjacent_pairs", "touching_pairs", "home_qpos", "compile_draft"]

#: Geoms closer than this fraction of the robot's size at home count as touching (1 mm on a 1 m arm:
#: well above MuJoCo's float rounding of mesh hulls, well below any gap a designer leaves on purpose).
TOUCH = 1e-3


def _bodies(text: str) -> dict[str, tuple[str | None, bool, bool]]:
    """Body name -> (parent body name or None for the world, has a joint, has a collision geom)."""
    from lxml import etree

    root = etree.fromstring(text.encode(), etree.XMLParser(resolve_entities=False, no_network=True,
                                                            huge_tree=False))
    out: dict[str, tuple[str | None, bool, bool]] = {}
    for body in root.iter("body"):
        parent = body.getparent()
        pname = parent.get("name") if parent is not None and parent.tag == "body" else None
        joint = any(c.tag in ("joint", "freejoint") for c in body)
        collides = any(c.tag == "geom" and c.get("class") == "collision" for c in body)
        out[body.get("name", "")] = (pname, joint, collides)
    return out


def _group(bodies: dict[str, tuple[str | None, bool, bool]], name: str | None) -> str | None:
    """The root of the rigid group of ``name``: the nearest ancestor-or-self with a joint (None: the world)."""
    while name is not None and not bodies[name][1]:
        name = bodies[name][0]
    return name


def adjacent_pairs(text: str) -> list[tuple[str, str]]:
    """Pairs of colliding bodies in rigid groups joined by one joint (see the module doc)."""
    bodies = _bodies(text)
    members: dict[str | None, list[str]] = {}
    for name, (_, _, collides) in bodies.items():
        if collides:
            members.setdefault(_group(bodies, name), []).append(name)
    out = []
    for name, (parent, joint, _) in bodies.items():
        if not joint:
            continue
        above = _group(bodies, parent)
        out += [(a, b) for a in members.get(above, []) for b in members.get(name, [])]
    return out


def home_qpos(model) -> np.ndarray:
    """MuJoCo's qpos at home: the model's keyframe ``home`` (robkin's MJCF writer holds ``Robot.home`` or
    ``--home`` there), else each hinge and slide joint at 0 clipped into its range (others at qpos0)."""
    for k in range(model.nkey):
        if model.key(k).name == "home":
            return np.array(model.key(k).qpos, dtype=float)
    q = np.array(model.qpos0, dtype=float)
    for j in range(model.njnt):
        if model.jnt_type[j] in (2, 3):  # mjJNT_SLIDE, mjJNT_HINGE
            adr = model.jnt_qposadr[j]
            q[adr] = np.clip(0.0, *model.jnt_range[j]) if model.jnt_limited[j] else 0.0
    return q


def compile_draft(text: str, folder: str | Path | None) -> Any:
    """MuJoCo's model (``mujoco.MjModel``) of the MJCF ``text`` whose mesh files are named relative to
    ``folder``; MuJoCo must be importable, and its refusal is raised as it comes."""
    import mujoco

    spec = mujoco.MjSpec.from_string(text)
    if folder is not None:
        spec.meshdir = str(Path(folder).resolve())
    return spec.compile()


def touching_pairs(text: str, folder: Path | None, size: float) -> list[tuple[str, str]] | None:
    """Body pairs whose collision geoms are closer than ``TOUCH * size`` at home, by MuJoCo; None without
    MuJoCo. ``folder``: where the model's mesh files are named from."""
    try:
        import mujoco
    except ImportError:
        return None
    model = compile_draft(text, folder)
    data = mujoco.MjData(model)
    collision = (model.geom_contype != 0) | (model.geom_conaffinity != 0)
    model.geom_margin[collision] = TOUCH * size
    data.qpos[:] = home_qpos(model)
    mujoco.mj_forward(model, data)
    out = set()
    for c in data.contact[:data.ncon]:
        a, b = (model.body(model.geom_bodyid[g]).name for g in (c.geom1, c.geom2))
        out.add(tuple(sorted((a, b))))
    return sorted(out)  # type: ignore[arg-type]


def _unique(pairs: Iterable[tuple[str, str]]) -> list[tuple[str, str]]:
    seen: dict[tuple[str, str], None] = {}
    for a, b in pairs:
        if a != b:
            seen.setdefault(tuple(sorted((a, b))), None)  # type: ignore[arg-type]
    return list(seen)


def contact_excludes(text: str, folder: Path | None, size: float) -> tuple[list[tuple[str, str]], str]:
    """(body pairs to exclude, a one-line note saying how many of each kind) for the draft MJCF ``text``
    whose meshes are named relative to ``folder`` (see the module doc).

    ``size``: the robot's size (m): geoms closer than ``TOUCH`` times it at home count as touching.
    """
    adjacent = _unique(adjacent_pairs(text))
    touching = touching_pairs(text, folder, size)
    if touching is None:
        return adjacent, (f"{len(adjacent)} parent-child body pair(s) excluded from contact; contacts at home "
                          f"not checked (MuJoCo is not installed)")
    extra = [p for p in _unique(touching) if p not in set(adjacent)]
    shown = ", ".join(f"{a}/{b}" for a, b in extra[:4]) + (", ..." if len(extra) > 4 else "")
    return adjacent + extra, (f"{len(adjacent)} parent-child body pair(s) and {len(extra)} pair(s) touching at "
                              f"home excluded from contact" + (f" ({shown})" if extra else ""))
