"""Structure checks of a URDF: dangling or duplicate links and joints, cycles, roots, unreachable links, names."""

from __future__ import annotations

import re

import numpy as np

from .findings import ERROR, INFO, WARNING, Finding
from .urdf_source import RawUrdf

__all__ = ["structure_findings", "moving_links", "rigid_groups", "poses_in_group"]

#: names every tool takes (ROS, SDF, MuJoCo, USD prims after escaping): letters, digits, _ - . /
_PLAIN_NAME = re.compile(r"[A-Za-z0-9_\-./]+")


def structure_findings(u: RawUrdf) -> list[Finding]:
    f: list[Finding] = []
    F = u.file

    def add(sev, code, line, element, message, fix):
        f.append(Finding(sev, code, F, line, element, message, fix))

    if not u.links:
        add(ERROR, "no-links", u.root.sourceline, "", "the robot has no <link>", "add the robot's links")
        return f
    seen: dict[str, int] = {}
    for kind, items in (("link", u.links), ("joint", u.joints)):
        seen = {}
        for it in items:
            if not it.name:
                add(ERROR, "name-missing", it.line, kind, f"a <{kind}> without a name (every parser refuses it)",
                    f"give the {kind} a unique name")
                continue
            if it.name in seen:
                add(ERROR, f"{kind}-duplicate", it.line, f"{kind} '{it.name}'",
                    f"{kind} '{it.name}' is defined twice (first at line {seen[it.name]}); urdfdom, pinocchio and "
                    f"MuJoCo refuse the file", f"rename or remove one of the two {kind}s")
            else:
                seen[it.name] = it.line
            own = it.name.rsplit("::", 1)[-1] if u.fmt == "sdf" else it.name   # SDF scopes nested names
            if not it.synthetic and not _PLAIN_NAME.fullmatch(own):
                add(INFO, "name-characters", it.line, f"{kind} '{it.name}'",
                    f"{kind} name has characters other than letters, digits and _ - . / (ROS names, SDF and USD "
                    f"prim names reject some of them)", "rename it with letters, digits and underscores")
    if not u.name and u.fmt == "urdf":
        add(ERROR, "robot-name", u.root.sourceline, "robot", "<robot> has no name attribute (urdfdom, so pinocchio, "
            "refuses it)",
            'add name="..." to <robot>')
    names = {ln.name for ln in u.links}
    parent_of: dict[str, str] = {}
    for j in u.joints:
        el = f"joint '{j.name}'"
        for end, link in (("parent", j.parent), ("child", j.child)):
            if not link:
                add(ERROR, "joint-dangling", j.line, el, f"joint has no <{end} link=...>",
                    f"add <{end} link=\"...\"/> naming a link of the file")
            elif link not in names:
                add(ERROR, "joint-dangling", j.line, el, f"{end} link '{link}' is not defined in the file",
                    f"define <link name=\"{link}\"> or name an existing link")
        if j.child and j.child in parent_of:
            add(ERROR, "link-two-parents", j.line, el,
                f"link '{j.child}' is already the child of joint '{parent_of[j.child]}': a link has one parent",
                "remove one of the two joints or give it another child")
        elif j.child:
            parent_of[j.child] = j.name
        if j.parent and j.parent == j.child:
            add(ERROR, "joint-cycle", j.line, el, f"joint connects link '{j.child}' to itself", "name two links")
    by_joint = {j.name: j for j in u.joints}
    roots = [ln for ln in u.links if ln.name and ln.name not in parent_of]
    if len(roots) > 1:
        # an SDF model may hold several trees (each a free body in Gazebo and drake): a warning there
        sev, why = (WARNING, "each is a free body in Gazebo and drake") if u.fmt == "sdf" else (ERROR, "a URDF is one tree")
        for r in roots[1:]:
            add(sev, "several-roots", r.line, f"{u.link_word} '{r.name}'",
                f"link '{r.name}' has no parent joint, nor has '{roots[0].name}': the file has {len(roots)} roots "
                f"({why})", f"connect '{r.name}' to the tree with a joint, or remove it")
    # cycles: following parents from a link comes back to it
    reported: set[str] = set()
    for start in parent_of:
        path, link = [], start
        while link in parent_of and link not in path:
            path.append(link)
            link = by_joint[parent_of[link]].parent if parent_of[link] in by_joint else None  # type: ignore[assignment]
        if link in path and not reported & set(path[path.index(link):]):
            cyc = path[path.index(link):]
            reported |= set(cyc)
            j = by_joint[parent_of[cyc[0]]]
            add(ERROR, "joint-cycle", j.line, f"joint '{j.name}'",
                f"links {' -> '.join(reversed(cyc))} form a cycle (a URDF is a tree); unreachable from the root",
                "remove one joint of the cycle (a closed chain is a constraint, e.g. MJCF <equality>)")
    return f


def moving_links(u: RawUrdf) -> set[str]:
    """Names of the links that a non-fixed joint moves relative to the root (they and everything below)."""
    children: dict[str, list] = {}
    for j in u.joints:
        if j.parent:
            children.setdefault(j.parent, []).append(j)
    parents = {j.child for j in u.joints}
    out: set[str] = set()
    stack = [(ln.name, False) for ln in u.links if ln.name not in parents]
    seen: set[str] = set()
    while stack:
        name, moving = stack.pop()
        if name in seen:
            continue
        seen.add(name)
        if moving:
            out.add(name)
        for j in children.get(name, ()):
            stack.append((j.child, moving or j.type != "fixed"))
    return out


def rigid_groups(u: RawUrdf) -> dict[str, str]:
    """Link -> the link its group hangs from by a non-fixed joint (links joined by fixed joints form a body,
    as MuJoCo, pinocchio and drake fuse them)."""
    parent = {j.child: j for j in u.joints if j.child}
    out = {}
    for ln in u.links:
        name, hops = ln.name, 0
        while name in parent and parent[name].type == "fixed" and hops <= len(u.joints):
            name, hops = parent[name].parent, hops + 1
        out[ln.name] = name
    return out


def poses_in_group(u: RawUrdf) -> dict[str, np.ndarray]:
    """Link -> its frame in the frame of its rigid group's head (``rigid_groups``), through the fixed joints."""
    parent = {j.child: j for j in u.joints if j.child}
    out: dict[str, np.ndarray] = {}
    for ln in u.links:
        T, name, hops = np.eye(4), ln.name, 0
        while name in parent and parent[name].type == "fixed" and hops <= len(u.joints):
            T = parent[name].origin @ T
            name, hops = parent[name].parent, hops + 1
        out[ln.name] = T
    return out
