"""What a robot file says beyond kinematics: link names, shapes, inertials, attached links.

A ``Robot`` is its GJD frames and joints; ``Robot.bodies`` (a ``Bodies``, empty by default) carries the
rest of what a URDF (or MJCF, SDF) gave, so that writing the robot back loses nothing.

Bodies
    Body 0 is fixed to the robot base; body i (1..n) moves with joint i (and every joint before it).

Poses
    Every pose here (shapes, inertials, attached links) is the pose **in the robot base frame at
    q = 0** (the home configuration). At configuration q the pose of anything on body i is

        body_motion_i(q) @ pose,   body_motion_i(q) = J_i(q) @ J_i(0)^-1

    where J_i(q) is GJD frame i moved to q (``Robot.frames_at``). The motion is the product of the
    joint screws' exponentials, the same for every choice of GJD frames of the same robot, so a
    conversion that moves the frames (DH, canonical tables) never makes these poses stale.
    ``body_motions`` and ``shape_poses`` compute them; writers re-express them in their own link
    frames.

Attached links
    Links that are not a chain body but hang from one: through a fixed joint (UR's ``base``,
    ``flange``, ``tool0``) or through a joint that is not part of the chain (a gripper finger, held at
    0 for the kinematics), with the joint that attaches them kept (name, type, axis, limits, mimic) so
    that they can be written back.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:  # pragma: no cover
    from .robot import Robot

__all__ = ["Geometry", "Material", "Shape", "Inertial", "Mimic", "AttachedJoint", "AttachedLink", "Bodies",
           "EMPTY_BODIES", "body_motions", "shape_poses"]

GeometryKind = Literal["mesh", "box", "cylinder", "sphere"]


def _pose(T: ArrayLike) -> np.ndarray:
    A = np.array(T, dtype=float)
    if A.shape != (4, 4):
        raise ValueError(f"pose: expected a (4, 4) matrix, got shape {A.shape}")
    A.setflags(write=False)
    return A


@dataclass(frozen=True)
class Geometry:
    """A shape's geometry, in the units of the file (normally metres).

    kind : 'mesh' | 'box' | 'cylinder' | 'sphere'
    size : box (x, y, z) full side lengths; cylinder (radius, length) along its z axis; sphere
        (radius,); mesh (sx, sy, sz), the scale applied to the mesh file's coordinates.
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
class AttachedJoint:
    """The joint that attaches an ``AttachedLink`` to its parent link, as the source gave it.

    type : 'fixed', 'revolute', 'continuous' or 'prismatic' (a non-fixed one is held at 0)
    axis : (3,) unit axis in the attached link's frame
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


@dataclass(frozen=True, eq=False)
class AttachedLink:
    """A link that is not a chain body but moves rigidly with body ``body`` (see the module doc).

    pose : (4, 4) pose of the link frame in the robot base frame at q = 0
    parent : the link it hangs from in the source (a chain body's link or another attached link)
    joint : the joint from ``parent`` to this link
    """

    name: str
    body: int
    pose: np.ndarray
    parent: str
    joint: AttachedJoint

    def __post_init__(self) -> None:
        object.__setattr__(self, "pose", _pose(self.pose))


@dataclass(frozen=True, eq=False)
class Bodies:
    """Everything a robot file says beyond kinematics; all fields empty when nothing was given.

    links : names of the chain's bodies' links, n + 1 of them (body 0 = the base link), or () if unknown
    tip : the link whose frame is the tool (J_{n+1}); an attached link or links[n]; None if unknown
    joint_parents : for each chain joint, the link it hangs from in the source (links[i - 1] or an
        attached link on body i - 1); () if unknown
    attached : links hanging from the bodies (fixed links, held off-chain joints), parents first
    shapes, inertials : visual/collision shapes and mass properties, on bodies 0..n
    world_link, world_joint : names of the root link above the base and of the joint joining them
    """

    links: tuple[str, ...] = ()
    tip: str | None = None
    joint_parents: tuple[str, ...] = ()
    attached: tuple[AttachedLink, ...] = ()
    shapes: tuple[Shape, ...] = ()
    inertials: tuple[Inertial, ...] = ()
    world_link: str | None = None
    world_joint: str | None = None

    def __bool__(self) -> bool:
        return bool(self.links or self.attached or self.shapes or self.inertials)

    def visuals(self) -> tuple[Shape, ...]:
        return tuple(s for s in self.shapes if s.role == "visual")

    def collisions(self) -> tuple[Shape, ...]:
        return tuple(s for s in self.shapes if s.role == "collision")


#: The empty default of ``Robot.bodies``.
EMPTY_BODIES = Bodies()


def body_motions(robot: "Robot", q: ArrayLike) -> np.ndarray:
    """Rigid motion of every body from q = 0 to q: (n,) -> (n+1, 4, 4), (N, n) -> (N, n+1, 4, 4).

    Motion 0 (the base) is the identity; motion i is J_i(q) @ J_i(0)^-1, so a pose P given in the
    base frame at q = 0 on body i is ``motion_i @ P`` at q. In the robot base frame (prefix
    ``robot.world`` for the world frame).
    """
    from . import se3

    F = robot.frames_at(q)  # (..., n+1, 4, 4); the first n are the joint frames after their motion
    out = np.empty(F.shape)
    out[..., 0, :, :] = np.eye(4)
    out[..., 1:, :, :] = F[..., :-1, :, :] @ se3.inv(robot.frames[:-1])
    return out


def shape_poses(robot: "Robot", q: ArrayLike, shapes: tuple[Shape, ...] | None = None) -> np.ndarray:
    """Poses of shapes at q in the robot base frame: (n,) -> (S, 4, 4), (N, n) -> (N, S, 4, 4).

    ``shapes`` defaults to all of ``robot.bodies.shapes`` (visuals and collisions, in that order).
    """
    shapes = robot.bodies.shapes if shapes is None else shapes
    M = body_motions(robot, q)
    if not shapes:
        return np.empty(M.shape[:-3] + (0, 4, 4))
    idx = np.array([s.body for s in shapes])
    P = np.stack([s.pose for s in shapes])
    return M[..., idx, :, :] @ P

