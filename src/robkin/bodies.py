"""What a robot file says beyond kinematics: link names, shapes, inertials, attached links.

A ``Robot`` is its GJD frames and joints; ``Robot.bodies`` (a ``Bodies``, empty by default) carries the
rest of what a URDF (or MJCF, SDF) gave, so that writing the robot back loses nothing.

Bodies
    Body 0 is fixed to the robot base; body i (1..n) moves with joint i (and every joint before it).

Poses
    Every pose here (shapes, inertials, links) is the pose **in the robot base frame at
    q = 0** (the home configuration). At configuration q the pose of anything on body i is

        body_motion_i(q) @ pose,   body_motion_i(q) = J_i(q) @ J_i(0)^-1

    where J_i(q) is GJD frame i moved to q (``Robot.frames_at``). The motion is the product of the
    joint screws' exponentials, the same for every choice of GJD frames of the same robot, so a
    conversion that moves the frames (DH, canonical tables) never makes these poses stale.
    ``body_motions`` and ``shape_poses`` compute them; writers re-express them in their own link
    frames.

Links
    Every link of the source, each on the body it moves with: the chain's own links, links hanging
    from them through fixed joints (UR's ``base``, ``flange``, ``tool0``), and links attached through
    joints that are not part of the chain (a gripper finger, the other arm of a humanoid), which are
    held at 0. The joint that attaches each link is kept (name, type, axis, limits, mimic), so that
    the whole file can be written back.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable, Iterable, Iterator, Protocol, Sequence, TypeVar, overload

import numpy as np
from numpy.typing import ArrayLike

from .lazy_exports import lazy_exports

if TYPE_CHECKING:  # pragma: no cover
    from .body_parts import Geometry, GeometryKind, Inertial, Link, LinkJoint, Material, Mimic, Shape

__all__ = ["Geometry", "Material", "Shape", "Inertial", "Mimic", "LinkJoint", "Link", "Bodies",
           "EMPTY_BODIES", "LazyTuple", "body_motions", "shape_poses"]

T = TypeVar("T")

# the parts (shapes, inertials, links, ...) are defined in ``body_parts`` and imported on first use: a
# load for kinematics makes none, and each frozen dataclass costs ~1 ms of start-up to define
__getattr__, __dir__ = lazy_exports(__name__, globals(), dict.fromkeys(
    ("Geometry", "GeometryKind", "Material", "Shape", "Inertial", "Mimic", "LinkJoint", "Link"), ".body_parts"))


class LazyTuple(Sequence[T]):
    """A read-only sequence made by ``make()`` on first use (readers defer parsing shapes with it:
    most uses of a robot file never look at them)."""

    def __init__(self, make: Callable[[], Iterable[T]]) -> None:
        self._make: Callable[[], Iterable[T]] | None = make
        self._items: tuple[T, ...] = ()

    def _get(self) -> tuple[T, ...]:
        if self._make is not None:
            self._items = tuple(self._make())
            self._make = None
        return self._items

    @overload
    def __getitem__(self, i: int) -> T: ...
    @overload
    def __getitem__(self, i: slice) -> tuple[T, ...]: ...

    def __getitem__(self, i: int | slice) -> T | tuple[T, ...]:
        return self._get()[i]

    def __len__(self) -> int:
        return len(self._get())

    def __iter__(self) -> Iterator[T]:
        return iter(self._get())

    def __repr__(self) -> str:
        return repr(self._get()) if self._make is None else "LazyTuple(<not made yet>)"

    def __reduce__(self) -> tuple[type[tuple[T, ...]], tuple[tuple[T, ...]]]:
        # pickled (for another process) and copied as the plain tuple: the maker is a closure
        return (tuple, (self._get(),))


@dataclass(frozen=True, eq=False)
class Bodies:
    """Everything a robot file says beyond kinematics; all fields empty when nothing was given.

    links : every link of the source, in its order: the chain's bodies, links rigidly attached to
        them (UR's ``base``, ``flange``, ``tool0``), links off the chain (held at 0), links above the base
    chain : the chain's link names, n + 1 of them: the base link, then the child link of each joint
    tip : the link whose frame is the tool (J_{n+1}); None if unknown
    shapes, inertials : visual/collision shapes and mass properties, on bodies 0..n
    extras : elements of the source that robkin does not interpret (URDF: ``<transmission>``,
        ``<gazebo>``, ``<ros2_control>``...), as XML text; the writer of the same format repeats them

    links, shapes, inertials and extras are tuples, or ``LazyTuple``s that a reader fills on first use.
    """

    links: Sequence[Link] = ()
    chain: tuple[str, ...] = ()
    tip: str | None = None
    shapes: Sequence[Shape] = ()
    inertials: Sequence[Inertial] = ()
    extras: Sequence[str] = ()

    def __bool__(self) -> bool:
        return bool(self.chain or self.links or self.shapes or self.inertials)

    def visuals(self) -> tuple[Shape, ...]:
        return tuple(s for s in self.shapes if s.role == "visual")

    def collisions(self) -> tuple[Shape, ...]:
        return tuple(s for s in self.shapes if s.role == "collision")


#: The empty default of ``Robot.bodies``.
EMPTY_BODIES = Bodies()


class MovingChain(Protocol):
    """What ``body_motions`` and ``shape_poses`` use of a robot (a ``robkin.Robot``; this module lies below
    ``robkin.robot``, which imports it, so it names the robot by what it offers)."""

    @property
    def n(self) -> int: ...

    @property
    def frames(self) -> np.ndarray: ...

    @property
    def bodies(self) -> "Bodies": ...

    def frames_at(self, q: ArrayLike) -> np.ndarray: ...


def body_motions(robot: MovingChain, q: ArrayLike) -> np.ndarray:
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


def shape_poses(robot: MovingChain, q: ArrayLike, shapes: Sequence[Shape] | None = None) -> np.ndarray:
    """Poses of shapes at q in the robot base frame: (n,) -> (S, 4, 4), (N, n) -> (N, S, 4, 4).

    ``shapes`` defaults to all of ``robot.bodies.shapes`` (in their order). Prefix ``robot.world``
    for world poses.
    """
    shapes = robot.bodies.shapes if shapes is None else shapes
    M = body_motions(robot, q)
    if not shapes:
        return np.empty(M.shape[:-3] + (0, 4, 4))
    idx = np.array([s.body for s in shapes])
    bad = [s.name or s.link for s in shapes if not 0 <= s.body <= robot.n]
    if bad:
        raise ValueError(f"shape(s) {', '.join(map(str, bad[:5]))} on a body outside 0..{robot.n}: the bodies "
                         f"belong to another robot")
    P = np.stack([s.pose for s in shapes])
    return M[..., idx, :, :] @ P

