"""The joints a serial chain of a robot tree passes through, and refusing those robkin cannot model."""

from __future__ import annotations

from typing import TYPE_CHECKING

from ...errors import InputError

if TYPE_CHECKING:  # the tree types only: a robot document's info does not load the URDF reader
    from .model import UrdfJoint, UrdfModel

__all__ = ["joints_between", "refuse_on_chain"]


def joints_between(model: UrdfModel, a: str, b: str) -> list[UrdfJoint]:
    """The joints on the tree path between links ``a`` and ``b`` (either may be above the other)."""
    parents = model.parent_joint()

    def up(link: str) -> list[UrdfJoint]:
        out = []
        while link in parents:
            out.append(parents[link])
            link = parents[link].parent
        return out

    up_a, up_b = up(a), up(b)
    shared = {j.name for j in up_a} & {j.name for j in up_b}
    return [j for j in up_a if j.name not in shared] + [j for j in up_b if j.name not in shared]


def refuse_on_chain(model: UrdfModel, kinds: dict[str, str], base: str | None, tip: str | None,
                    supported: str) -> None:
    """InputError naming the first joint of ``kinds`` (name -> its kind in the file) on the chain.

    ``base``/``tip`` as given by the user; a missing base is the tree's root, a missing tip the only
    leaf below the base. When the ends are unknown or ambiguous nothing is raised here: the chain
    selection (``robot_from_model``) then explains what to choose. ``supported`` words the joint kinds
    that do make a chain, e.g. "hinge and slide".
    """
    if not kinds:
        return
    base = base or model.root()
    if base not in model.links:
        return
    if tip is None:
        leaves = model.leaves(base)
        if len(leaves) != 1:
            return
        tip = leaves[0]
    if tip not in model.links:
        return
    for j in joints_between(model, base, tip):
        if j.name in kinds:
            raise InputError(f"{model.source}: joint '{j.name}' is a {kinds[j.name]} joint; only {supported} "
                             f"joints make a serial chain (pick a chain without it with base_link=/tip_link=)")
