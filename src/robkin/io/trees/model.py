"""The robot tree every XML reader builds (URDF, and MJCF and SDF too): links, joints (``tree_joint``) and
what each link holds (``LinkContent``), with the vocabulary they share (joint kinds, "no limit").

The URDF reader (``io.urdf.parser``) fills it from one compiled scan of the text; the MJCF and SDF readers
fill it from their own trees, so one chain reader (``io.urdf.chain``) serves all three.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Iterable, Mapping, Sequence

import numpy as np

from ...compiled.conversions import pose_rows
from ...compiled.scanners.vocabulary import NO_LIMIT, SUPPORTED_TYPES, UNSUPPORTED_TYPES
from .tree_joint import UrdfJoint

if TYPE_CHECKING:  # pragma: no cover
    from ...body_parts import Inertial, Shape

__all__ = ["UrdfModel", "LinkContent", "UrdfJoint", "origin_matrix", "attribute_floats", "NO_LIMIT",
           "SUPPORTED_TYPES", "UNSUPPORTED_TYPES"]


@dataclass(frozen=True)
class LinkContent:
    """What a link holds besides its frame: shapes and mass properties, with poses relative to the
    link frame (``Shape.body`` and ``Inertial.body`` are 0 here; the chain reader assigns bodies)."""

    shapes: tuple[Shape, ...] = ()
    inertial: Inertial | None = None


@dataclass(frozen=True, eq=False)
class UrdfModel:
    """The tree of a URDF: robot name, links in file order, joints, and the links' contents.

    ``content`` maps a link name to its ``LinkContent`` (missing: an empty link). Readers of other
    formats (MJCF, SDF) may fill it with a plain dict. ``extras`` gives the top-level elements robkin
    does not interpret (transmissions, Gazebo and ros2_control tags) as XML text, for the URDF writer.
    """

    name: str | None
    links: tuple[str, ...]
    joints: tuple[UrdfJoint, ...]
    source: str
    content: Mapping[str, LinkContent] = field(default_factory=dict)
    extras: Sequence[str] = ()

    def parent_joint(self) -> dict[str, UrdfJoint]:
        """link name -> the joint whose child it is (made once; callers must not change it)."""
        return self._parent_joint

    def children(self) -> dict[str, list[UrdfJoint]]:
        """link name -> the joints whose parent it is, in file order (made once; not to be changed)."""
        return self._children

    @cached_property
    def _parent_joint(self) -> dict[str, UrdfJoint]:
        return {j.child: j for j in self.joints}

    @cached_property
    def _children(self) -> dict[str, list[UrdfJoint]]:
        out: dict[str, list[UrdfJoint]] = {name: [] for name in self.links}
        for j in self.joints:
            out[j.parent].append(j)
        return out

    def root(self) -> str:
        return self.roots()[0]

    def roots(self) -> list[str]:
        """Links without a parent joint, in file order: one for a URDF; an SDF model may hold several
        unconnected trees (see ``io.sdf.trees``)."""
        parents = self.parent_joint()
        return [name for name in self.links if name not in parents]

    def leaves(self, below: str) -> list[str]:
        """Leaf links of the subtree under ``below`` (itself if it has no children), in file order."""
        kids = self.children()
        out, stack = [], [below]
        while stack:
            link = stack.pop()
            if not kids[link]:
                out.append(link)
            stack.extend(j.child for j in reversed(kids[link]))
        return out


def attribute_floats(text: str | None, count: int, where: str, default: Iterable[float]) -> np.ndarray:
    """``numbers`` as an array (the form the MJCF and SDF readers use)."""
    from ...compiled.scanners.attribute_numbers import numbers  # compiled: loaded by a reader, not by an import

    return np.array(numbers(text, count, where, None, tuple(default)), dtype=float)


def origin_matrix(xyz: tuple[float, ...], rpy: tuple[float, ...]) -> np.ndarray:
    """Pose (4, 4) of a URDF origin: translation xyz, rotation Rz(yaw) Ry(pitch) Rx(roll)."""
    return pose_rows.matrix(pose_rows.from_xyz_rpy(xyz, rpy))
