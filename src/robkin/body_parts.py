"""The parts of what a robot file says beyond kinematics (see ``robkin.bodies``, which exports them).

Geometry, Material, Shape, Inertial, Mimic, LinkJoint and Link: frozen records, poses (4, 4) in the
robot base frame at q = 0 (see ``robkin.bodies`` for bodies and poses). Kept apart from ``bodies``
so that a load for kinematics, which makes none of them, does not pay for defining them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["Geometry", "GeometryKind", "Material", "Shape", "Inertial", "Mimic", "LinkJoint", "Link"]

GeometryKind = Literal["mesh", "box", "cylinder", "sphere", "capsule"]


def _pose(T: ArrayLike) -> np.ndarray:
    A = np.array(T, dtype=float)
    if A.shape != (4, 4):
        raise ValueError(f"pose: expected a (4, 4) matrix, got shape {A.shape}")
    A.setflags(write=False)
    return A


@dataclass(frozen=True)
class Geometry:
    """A shape's geometry, in the units of the file (normally metres).

    kind : 'mesh' | 'box' | 'cylinder' | 'sphere' | 'capsule'
    size : box (x, y, z) full side lengths; cylinder (radius, length) along its z axis; sphere
        (radius,); capsule (radius, length) along its z axis, the length between the centres of its
        two half-sphere caps (MJCF, SDF); mesh (sx, sy, sz), the scale applied to the mesh file's
        coordinates.
    filename : for a mesh, the file name exactly as the source wrote it (``package://...``); robkin
        never opens it.
    """

    kind: GeometryKind
    size: tuple[float, ...]
    filename: str | None = None


@dataclass(frozen=True)
class Material:
    """A visual material: its name in the source, colour (r, g, b, a in 0..1), texture file name."""

    name: str | None = None
    rgba: tuple[float, float, float, float] | None = None
    texture: str | None = None


@dataclass(frozen=True, eq=False)
class Shape:
    """A visual or collision shape.

    link : name of the link (or body) the source attached it to
    body : 0..n, the robot body it moves with
    role : 'visual' | 'collision'
    pose : (4, 4) pose of the geometry's own frame in the robot base frame at q = 0
    """

    link: str
    body: int
    role: Literal["visual", "collision"]
    pose: np.ndarray
    geometry: Geometry
    material: Material | None = None
    name: str | None = None
    #: the six numbers (xyz, rpy) of the source's origin relative to its link, for writing them back
    origin: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "pose", _pose(self.pose))


@dataclass(frozen=True, eq=False)
class Inertial:
    """Mass properties of a link: mass (kg), inertia (3, 3) about the centre of mass in the axes of
    ``pose`` (kg m^2), pose (4, 4) of that centre-of-mass frame in the robot base frame at q = 0."""

    link: str
    body: int
    pose: np.ndarray
    mass: float
    inertia: np.ndarray
    #: the six numbers (xyz, rpy) of the source's origin relative to its link, for writing them back
    origin: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "pose", _pose(self.pose))
        inertia = np.array(self.inertia, dtype=float).reshape(3, 3)
        inertia.setflags(write=False)
        object.__setattr__(self, "inertia", inertia)


@dataclass(frozen=True)
class Mimic:
    """A joint that follows another: q = multiplier * q_joint + offset (URDF ``<mimic>``)."""

    joint: str
    multiplier: float = 1.0
    offset: float = 0.0


@dataclass(frozen=True, eq=False)
class LinkJoint:
    """The joint from a link's parent to the link, as the source gave it (kept to write it back).

    type : the source's type ('fixed', 'revolute', 'continuous', 'prismatic', ...); a joint that is
        not one of the chain's is held at 0
    axis : (3,) unit axis in the link's own frame
    xyz_rpy : the six numbers of the source's origin (xyz, then rpy), or None
    """

    name: str
    type: str = "fixed"
    axis: tuple[float, float, float] = (0.0, 0.0, 1.0)
    lower: float | None = None
    upper: float | None = None
    effort: float | None = None
    velocity: float | None = None
    damping: float | None = None
    friction: float | None = None
    mimic: Mimic | None = None
    xyz_rpy: tuple[float, ...] | None = None
    #: rotor inertia added to the joint (MJCF ``armature``), None where the source gave none
    armature: float | None = None


@dataclass(frozen=True, eq=False)
class Link:
    """A link of the source file and the body it moves with (see the module doc).

    pose : (4, 4) pose of the link frame in the robot base frame at q = 0
    parent : the link it hangs from in the source (None for the source's root)
    joint : the joint from ``parent`` to this link (None for the root)
    """

    name: str
    body: int
    pose: np.ndarray
    parent: str | None = None
    joint: LinkJoint | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "pose", _pose(self.pose))
