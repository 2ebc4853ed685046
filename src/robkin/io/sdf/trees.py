"""An SDF model whose links form several unconnected trees: picking the one a chain lies in.

SDFormat lets a model hold links that no joint connects (a robot and a table beside it, two arms as
nested models, free objects): each unconnected tree moves on its own. A serial chain lies in one of
them. The tree is the one holding ``tip_link`` or ``base_link``; without either, the only tree with a
moving joint; otherwise one line lists the trees and what to pass. The links of the other trees are
left out of the robot (a URDF has one root), said in one warning line.

A model whose joints close a loop (Cassie's leg linkages: a link that is the child of two joints) is no
tree: ``check_tree`` refuses it with one line naming the link and both joints (walking it as a tree
would never end).
"""

from __future__ import annotations

import warnings
from dataclasses import replace

from ...errors import InputError
from ..trees.model import UrdfModel

__all__ = ["trees", "pick_tree", "check_tree"]

#: Trees listed in a message at most (one line stays readable).
MAX_LISTED = 6


def check_tree(model: UrdfModel) -> None:
    """InputError (one line) when a link is the child of two joints, or the joints form a cycle."""
    parent: dict[str, str] = {}
    for j in model.joints:
        if j.child == j.parent:
            raise InputError(f"{model.source}: joint '{j.name}': parent and child are the same link '{j.child}'")
        if j.child in parent:
            raise InputError(f"{model.source}: link '{j.child}' is the child of two joints, '{parent[j.child]}' and "
                             f"'{j.name.removesuffix(':child')}': the joints close a kinematic loop; robkin reads trees (remove one of "
                             f"the joints to read a chain)")
        parent[j.child] = j.name.removesuffix(":child")  # the SDF joint, not the reader's link behind it
    reached = {link for tree in trees(model) for link in tree}
    cycle = [link for link in model.links if link not in reached]
    if cycle:
        raise InputError(f"{model.source}: the joints form a cycle through link(s) {', '.join(cycle[:6])}; "
                         f"robkin reads trees")


def trees(model: UrdfModel) -> list[list[str]]:
    """The links of each unconnected tree, root first, in file order of the roots."""
    parents = model.parent_joint()
    kids = model.children()
    out = []
    for root in (name for name in model.links if name not in parents):
        links, stack = [], [root]
        while stack:
            link = stack.pop()
            links.append(link)
            stack.extend(j.child for j in reversed(kids[link]))
        out.append(links)
    return out


def _moving(model: UrdfModel, links: list[str]) -> int:
    parents = model.parent_joint()
    return sum(1 for link in links if link in parents and parents[link].type != "fixed")


def _name(links: list[str]) -> str:
    """A tree as messages name it: its root, or below a ``world`` link, the link fixed to it."""
    return links[1] if links[0] == "world" and len(links) > 1 else links[0]


def pick_tree(model: UrdfModel, base_link: str | None = None, tip_link: str | None = None) -> UrdfModel:
    """``model`` restricted to the tree the chain lies in (unchanged when it has one tree).

    InputError (one line) when ``base_link`` and ``tip_link`` lie in different trees, or when neither
    is given and several trees have moving joints (the message lists them and a ``tip_link`` for each).
    Links not known to the model are left for the chain selection to report.
    """
    parents = model.parent_joint()
    if sum(1 for link in model.links if link not in parents) < 2:  # trees() has one tree per root link
        return model
    found = trees(model)
    src = model.source
    tree_of = {link: k for k, links in enumerate(found) for link in links}
    picks = {opt: tree_of[link] for opt, link in (("base_link", base_link), ("tip_link", tip_link))
             if link is not None and link in tree_of}
    if len(picks) < sum(x is not None for x in (base_link, tip_link)):
        return model  # an unknown link: robot_from_model names it with the links there are
    if len(set(picks.values())) > 1:
        raise InputError(f"{src}: base_link='{base_link}' and tip_link='{tip_link}' are in different unconnected "
                         f"trees of the model (rooted at '{_name(found[picks['base_link']])}' and "
                         f"'{_name(found[picks['tip_link']])}'); no joint joins them")
    if picks:
        chosen = next(iter(picks.values()))
    else:
        moving = [k for k, links in enumerate(found) if _moving(model, links)]
        if len(moving) != 1:
            listed = "; ".join(f"'{_name(found[k])}' ({_moving(model, found[k])} moving joint(s), tip_link="
                               f"'{model.leaves(found[k][0])[-1]}')" for k in (moving or range(len(found)))[:MAX_LISTED])
            more = f"; and {len(moving) - MAX_LISTED} more" if len(moving) > MAX_LISTED else ""
            raise InputError(f"{src}: the model's links form {len(found)} unconnected trees, {len(moving)} of them "
                             f"with moving joints: {listed}{more}; pick the chain with tip_link= (or base_link=)")
        chosen = moving[0]
    keep = set(found[chosen])
    left = [link for link in model.links if link not in keep]
    shown = ", ".join(f"'{x}'" for x in left[:8]) + (f" and {len(left) - 8} more" if len(left) > 8 else "")
    warnings.warn(f"{src}: {len(left)} link(s) not connected to the chain's tree (rooted at '{_name(found[chosen])}') "
                  f"are left out: {shown}", UserWarning, stacklevel=3)
    return replace(model, links=tuple(link for link in model.links if link in keep),
                   joints=tuple(j for j in model.joints if j.child in keep))
