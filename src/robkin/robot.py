"""The hub: a robot as its Global Joint Description (GJD) plus joint specifications.

For n joints at the home configuration (q = 0) the GJD is n + 1 poses in the robot base frame:
J_1..J_n, whose z axis is joint i's axis pointing in the joint's positive direction, and J_{n+1}, the
tool. Every representation converts to and from this hub, and forward kinematics of any of them at the
same q gives the same tool pose.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property
from types import MethodType
from typing import TYPE_CHECKING, Any, Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike

from .checks import EXACT_TOL, PROJECTION_TOL, check_out, check_pose, check_poses, check_q, check_threads
from .errors import InputError, quote
from .names import check_name, duplicates
from .bodies import EMPTY_BODIES, Bodies
from .capabilities import ik_function, self_collision_distances_function, self_collision_function
from .capabilities import compliance as _compliance, jacobian as _jacobian_module, rigid_body as _rigid_body
from .joints import JOINT_TYPES, Joint, JointType, default_joints, home_configuration
from .frame_stacks import frame_scales, local_transforms

if TYPE_CHECKING:  # pragma: no cover
    from .compiled.chain.fk import Chain

__all__ = ["Joint", "JointType", "Robot", "JOINT_TYPES", "default_joints", "home_configuration", "EXACT_TOL", "PROJECTION_TOL", "check_pose", "check_poses", "check_q",
           "identity_pose"]



def identity_pose() -> np.ndarray:
    """A new (4, 4) identity: the default of every pose field (``Robot.world``, a table's base and tool)."""
    return np.eye(4)

class CapabilityMethod:
    """A method of ``Robot`` that *is* a function of a higher layer, imported on first use.

    ``Robot.ik`` is ``robkin.kinematics.ik.ik`` with the robot as its first argument; the hub reaches it
    only through its facade (``capabilities.ik_function``). The first access, through the class or an
    instance, puts that function itself in the class in place of this placeholder: Robot's own
    attribute, set by Robot's own module. So ``help(Robot.ik)`` and ``inspect.signature`` show the
    function's full signature before and after the first call alike, and every later call is a plain
    method call: a descriptor answering each access would cost ~0.16 us per call (~6 % of a
    closed-form single IK call, the margin to EAIK's per-target call in ``bench_closed_form.py``), and
    a bound method kept on each robot would refer back to it (a dropped robot would then wait for the
    cyclic garbage collector).

    Parameters
    ----------
    load : callable
        Returns the function (imported on first use, then kept); its first parameter is the robot.
    """

    def __init__(self, load: Callable[[], Callable[..., Any]]) -> None:
        self.load = load
        self.owner: type | None = None
        self.name = ""

    def __set_name__(self, owner: type, name: str) -> None:
        self.owner, self.name = owner, name

    def __get__(self, instance: object | None, owner: type | None = None) -> Any:
        function = self.load()
        if self.owner is not None:
            setattr(self.owner, self.name, function)  # this class's own attribute, once
        return function if instance is None else MethodType(function, instance)


@dataclass(frozen=True, eq=False)
class Robot:
    """A serial robot: GJD frames (n+1, 4, 4) in the base frame at q = 0, and its joints.

    Parameters
    ----------
    frames : (n+1, 4, 4) array
        J_1..J_n (z = joint axis, positive direction) and the tool J_{n+1}, in the robot base frame.
    joints : sequence of Joint
        One per joint, base to tip.
    world : (4, 4) array, optional
        World -> robot base transform. Kept and written out (RPY row 0, URDF world joint), but not
        part of forward kinematics, which is always in the robot base frame.
    name : str, optional
    frames_from : str, optional
        The frame-based table these frames are the frames of ('dh', 'mdh' or 'hayati'), or None (URDF,
        PoE, RPY-XYZ, GJD input, or frames computed otherwise). A conversion back to that same table
        keeps the given frames (so a table read in and written out comes back as it was); every other
        conversion places its frames by the canonical rules. Cleared by ``replace(frames=...)``.
    bodies : Bodies, optional
        What the source file said beyond kinematics (link names, shapes, inertials, attached links;
        see ``robkin.bodies``), kept so that writers lose nothing. Empty by default.
    """

    frames: np.ndarray
    joints: tuple[Joint, ...]
    world: np.ndarray = field(default_factory=identity_pose)
    name: str | None = None
    frames_from: str | None = None
    bodies: Bodies = EMPTY_BODIES

    def __post_init__(self) -> None:
        frames = np.asarray(self.frames, dtype=float)  # copied below (concatenate, check_poses)
        joints = tuple(self.joints)
        if frames.ndim != 3 or frames.shape[1:] != (4, 4):
            raise InputError(f"gjd.frames: expected n+1 4x4 matrices, got shape {frames.shape}")
        n = len(joints)
        if n < 1:
            raise InputError("joints: a robot needs at least one joint")
        if frames.shape[0] != n + 1:
            raise InputError(f"gjd.frames: expected {n + 1} frames for {n} joints, got {frames.shape[0]}")
        for i, j in enumerate(joints):
            check_name(j.name, f"joints[{i}].name")
        if self.name is not None:
            check_name(self.name, "name")
        dup = duplicates(j.name for j in joints) if len({j.name for j in joints}) < n else None
        if dup:
            raise InputError(f"joints: duplicate joint name(s) {', '.join(quote(d) for d in dup[:8])}")
        if np.shape(self.world) == (4, 4):   # frames and world checked in one vectorised pass
            both = check_poses(np.concatenate([frames, np.asarray(self.world, dtype=float)[None]]),
                               lambda i: f"gjd.frames[{i}]" if i <= n else "world")
            checked, world = both[:-1], both[-1]
        else:
            checked, world = check_poses(frames, lambda i: f"gjd.frames[{i}]"), check_pose(self.world, "world")
        checked.setflags(write=False)
        world.setflags(write=False)
        object.__setattr__(self, "frames", checked)
        object.__setattr__(self, "joints", joints)
        object.__setattr__(self, "world", world)

    # ------------------------------------------------------------------ structure
    @property
    def n(self) -> int:
        """Number of joints."""
        return len(self.joints)

    @property
    def tool(self) -> np.ndarray:
        """Tool pose J_{n+1} at q = 0, (4, 4)."""
        return self.frames[-1]

    @property
    def types(self) -> tuple[str, ...]:
        return tuple(j.type for j in self.joints)

    @cached_property
    def revolute(self) -> np.ndarray:
        """Boolean mask (n,) of revolute joints."""
        m = np.array([j.revolute for j in self.joints])
        m.setflags(write=False)
        return m

    @property
    def axes(self) -> np.ndarray:
        """Joint axis directions (n, 3), positive direction, in the base frame at q = 0."""
        return self.frames[:-1, :3, 2]

    @property
    def points(self) -> np.ndarray:
        """A point on each joint axis (the GJD frame origins), (n, 3)."""
        return self.frames[:-1, :3, 3]

    @cached_property
    def scale(self) -> float:
        """Characteristic length for relative tolerances (1 if everything passes through the origin).

        The largest of the tool's distance from the base and each joint axis's distance from the base
        origin. Axis distances, not frame-origin distances: a frame may sit far along its axis (the
        common normal of nearly parallel axes) without the robot being any bigger.
        """
        return float(frame_scales(self.frames[None])[0])

    @cached_property
    def limits(self) -> np.ndarray:
        """Joint limits (n, 2), -inf/+inf where none are given (read-only)."""
        lim = np.array([[-np.inf if j.lower is None else j.lower, np.inf if j.upper is None else j.upper]
                        for j in self.joints])
        lim.setflags(write=False)
        return lim

    def home(self, q: ArrayLike | None = None) -> np.ndarray:
        """The robot's home (n,): q = 0 clipped into the joint limits, or ``q`` checked against them
        (``robkin.joints.home_configuration``: the MJCF keyframe ``home``, the GUI's "home")."""
        return home_configuration(self.joints, q)

    def screws(self) -> np.ndarray:
        """Space-frame unit screws (n, 6) ordered (w, v): revolute (z, -z x p), prismatic (0, z)."""
        z, p = self.axes, self.points
        S = np.zeros((self.n, 6))
        S[self.revolute, :3] = z[self.revolute]
        S[self.revolute, 3:] = -np.cross(z[self.revolute], p[self.revolute])
        S[~self.revolute, 3:] = z[~self.revolute]
        return S

    def replace(self, **changes: Any) -> "Robot":
        """A copy with some fields changed (frames, joints, world, name, frames_from).

        New frames are no longer those of the table the robot came from, so unless ``frames_from`` is
        given with them it is cleared.

        ``changes``: the fields to change, as keyword arguments (``frames=``, ``joints=``, ``world=``, ``name=``,
        ``frames_from=``, ``bodies=``); TypeError for a field Robot does not have.
        """
        if "frames" in changes:
            changes.setdefault("frames_from", None)
        return replace(self, **changes)

    # ------------------------------------------------------------------ kinematics
    @cached_property
    def _local(self) -> np.ndarray:
        """Fixed transforms L (n+1, 4, 4): T(q) = L_1 Z_1(q_1) L_2 ... L_n Z_n(q_n) L_{n+1}.

        L_1 = J_1 and L_i = J_{i-1}^-1 J_i, because exp([S_i] q) = J_i Z(q) J_i^-1 with Z a rotation
        about (or translation along) z.
        """
        L = local_transforms(self.frames)
        L.setflags(write=False)
        return L

    @cached_property
    def _chain(self) -> "Chain":
        """The compiled chain (``robkin.compiled.chain.fk.Chain``), built on the first kinematics call."""
        from .compiled.chain.fk import Chain

        return Chain(self._local, self.revolute)

    def fk(self, q: ArrayLike, *, threads: int | None = None, out: np.ndarray | None = None) -> np.ndarray:
        """Tool pose in the base frame: q (n,) -> (4, 4), or a batch (N, n) -> (N, 4, 4).

        Compiled (``robkin.compiled.chain.fk``); a float64 array is used as it is, anything else is
        validated and converted first. Joint values in radians (revolute) or length units (prismatic).
        ``threads``: at most that many threads for a large batch (default: ``robkin.set_threads``,
        ROBKIN_NUM_THREADS, OMP_NUM_THREADS or the cores; see ``robkin.threads``); the results are the same bits.
        ``out``: a float64 array of the result's shape to write into and return (a large batch in
        chunks then needs no new memory per chunk); when q holds a NaN or an infinity the call raises
        and ``out`` may hold part of the batch (each block's values are checked by its thread).
        """
        t = 0 if threads is None else check_threads(threads)
        T = self._chain.fk(q, t, out)
        if T is None:   # not a float64 array of finite values as it is: validate, convert, explain
            qa = np.ascontiguousarray(check_q(q, self.n))
            T = self._chain.fk(qa, t, None if out is None else check_out(out, qa.shape[:-1] + (4, 4)))
        assert T is not None  # a checked, contiguous float64 array is always usable
        return T

    def frames_at(self, q: ArrayLike, *, threads: int | None = None, out: np.ndarray | None = None) -> np.ndarray:
        """All GJD frames moved to configuration q: (n,) -> (n+1, 4, 4), (N, n) -> (N, n+1, 4, 4).

        Frame i is joint i's frame *after* its own motion, so frame n+1 is the tool pose fk(q).
        Joint i's axis at q is the z axis of frame i before its motion, which has the same z axis.
        ``threads`` and ``out`` as for ``fk``.
        """
        t = 0 if threads is None else check_threads(threads)
        F = self._chain.frames(q, t, out)
        if F is None:
            qa = np.ascontiguousarray(check_q(q, self.n))
            F = self._chain.frames(qa, t, None if out is None else check_out(out, qa.shape[:-1] + (self.n + 1, 4, 4)))
        assert F is not None  # a checked, contiguous float64 array is always usable
        return F

    #: Inverse kinematics: joint values that put the tool at T. This method is ``robkin.kinematics.ik.ik``
    #: with the robot as its first argument (``CapabilityMethod``: imported on first use, then the function
    #: itself), so ``help(Robot.ik)`` shows that function's parameters: T (4, 4) or (N, 4, 4), q0, mask,
    #: method, all_solutions, tol_position, tol_orientation, max_iterations, restarts, rng, threads, lock,
    #: arm_angle; it returns an ``IKResult`` with ``.q`` and ``.success``.
    #: (not annotated: a dataclass would take an annotated class attribute for a field)
    ik = CapabilityMethod(ik_function)

    #: Self collision at q (n,) -> bool, (N, n) -> (N,) bool: ``robkin.self_collision.build.self_collision``
    #: (conservative capsules per link, compiled, every core; ``exact=True`` confirms with the meshes), with the
    #: model ``robkin.self_collision.self_collision_model(robot, source)`` last built for this robot.
    self_collision = CapabilityMethod(self_collision_function)
    #: Capsule distances of the checked link pairs at q: (n,) -> (P,), (N, n) -> (N, P) (negative: overlap):
    #: ``robkin.self_collision.build.self_collision_distances``; ``model.pairs`` names them.
    self_collision_distances = CapabilityMethod(self_collision_distances_function)

    def jacobian(self, q: ArrayLike, frame: str = "base", *, threads: int | None = None,
                 out: np.ndarray | None = None) -> np.ndarray:
        """Jacobian at q (n,) -> (6, n), or at q (N, n) -> (N, 6, n).

        Parameters
        ----------
        q : (n,) or (N, n) array
            Joint values (radians for revolute joints, length units for prismatic ones).
        frame : {'base', 'tool', 'space', 'body'}
            - ``'base'`` (default): rows [v; w], the linear velocity of the tool origin and the angular
              velocity, both in base-frame axes (Robotics Toolbox ``jacob0``, pinocchio
              ``LOCAL_WORLD_ALIGNED``).
            - ``'tool'``: the same [v; w] in tool-frame axes (``jacobe``, pinocchio ``LOCAL``).
            - ``'space'``: the space Jacobian of Modern Robotics, rows (w, v), the twist in the base frame.
            - ``'body'``: the body Jacobian of Modern Robotics, rows (w, v), the twist in the tool frame.

        threads : int, optional
            At most that many threads for a large batch (see ``fk``).
        out : (6, n) or (N, 6, n) float64 array, optional
            Written into and returned ('base', 'space', 'body'; see ``fk``).

        Returns
        -------
        (6, n) or (N, 6, n) array
            Columns per joint; v rows in length units per joint unit, w rows in radians per joint unit.
        """
        jac = _jacobian_module()
        if frame == "base":
            return jac.jacobian_geometric(self, q, threads, out)
        if frame == "space":
            return jac.jacobian_space(self, q, threads, out)
        if frame == "tool" and out is not None:
            raise InputError("out: not available for frame='tool' (its rows are the body Jacobian's, reordered)")
        if frame in ("body", "tool"):
            J = jac.jacobian_body(self, q, threads, out)
            # the body twist's v is the velocity of the tool origin in tool axes: [v; w] is (w, v) swapped
            return J if frame == "body" else J[..., _V_THEN_W, :]
        raise InputError(f"frame: '{frame}' is not one of base, tool, space, body")

    def manipulability(self, q: ArrayLike, kind: str = "translational", *,
                       threads: int | None = None) -> np.ndarray | float:
        """Yoshikawa's manipulability at q (n,) -> float, or at q (N, n) -> (N,) array.

        Parameters
        ----------
        q : (n,) or (N, n) array
            Joint values.
        kind : {'translational', 'rotational', 'full'}
            Rows of the base-frame Jacobian [v; w] used: v (length^3), w (dimensionless) or both.
        threads : int, optional
            At most that many threads for a batch (default automatic, see ``robkin.threads``).

        Returns
        -------
        float or (N,) array
            The product of the singular values of the selected rows (0 at a singularity); see
            ``robkin.kinematics.jacobian.manipulability``.
        """
        return _jacobian_module().manipulability(self, q, kind, threads)

    # ------------------------------------------------------------------ dynamics (robkin.dynamics)
    def inverse_dynamics(self, q: ArrayLike, qd: ArrayLike | None = None, qdd: ArrayLike | None = None, *,
                         gravity: ArrayLike | None = None, threads: int | None = None) -> np.ndarray:
        """Joint torques/forces (n,) or (N, n) producing qdd at (q, qd): recursive Newton-Euler, compiled.

        q, qd, qdd of one shape (n,) or (N, n), SI units; qd, qdd default to zero. ``gravity`` (3,) in
        the world frame (``world`` maps it to the base), default (0, 0, -9.81) m/s^2. Needs the links'
        mass properties (``bodies.inertials``); see ``robkin.dynamics.rigid_body``. ``threads`` as ``fk``.
        Each joint's ``armature`` (MJCF) adds armature * qdd, as in MuJoCo.
        """
        return _rigid_body().inverse_dynamics(self, q, qd, qdd, gravity, threads)

    def gravity(self, q: ArrayLike, *, gravity: ArrayLike | None = None, threads: int | None = None) -> np.ndarray:
        """Torques/forces (n,) or (N, n) that hold the robot still at q (``inverse_dynamics`` at rest).

        ``q`` (n,) or (N, n); ``gravity``: (3,) m/s^2 in the world frame, default (0, 0, -9.81); ``threads``:
        at most that many threads for a batch (default automatic, see ``robkin.threads``).
        """
        return _rigid_body().gravity_torques(self, q, gravity, threads)

    def mass_matrix(self, q: ArrayLike, *, threads: int | None = None) -> np.ndarray:
        """Joint-space mass matrix at q: (n,) -> (n, n), (N, n) -> (N, n, n); composite rigid bodies, each
        joint's ``armature`` (MJCF) on the diagonal, as in MuJoCo.

        ``q`` (n,) or (N, n); ``threads``: at most that many threads for a batch (default automatic, see
        ``robkin.threads``).
        """
        return _rigid_body().mass_matrix(self, q, threads)

    def fk_compliant(self, q: ArrayLike, payload: ArrayLike = 0.0, payload_com: ArrayLike | None = None, *,
                     gravity: ArrayLike | None = None) -> np.ndarray:
        """Tool pose (base frame) with each joint deflected by its gravity torque over its ``stiffness``.

        q (n,) -> (4, 4), (N, n) -> (N, 4, 4) (rad, m: the commanded, encoder values); ``payload`` (kg, a
        scalar or one per configuration) at the tool origin or at ``payload_com`` (3,) in the tool frame (m);
        ``gravity`` (3,) in the robot base frame, default (0, 0, -9.81) m/s^2. The links' own weight counts
        where the robot has masses. Joints without a stiffness are rigid; with none, this is ``fk``.
        See ``robkin.calibration.compliance`` (the model, first order in the deflection).
        """
        return _compliance().fk_compliant(self, q, payload, payload_com, gravity)

    # ------------------------------------------------------------------ conveniences
    def random_q(self, size: int | None = None, rng: np.random.Generator | int | None = None,
                 default_range: float = math.pi) -> np.ndarray:
        """Random joint values within limits (uniform); unlimited joints use +-default_range.

        ``size``: None for one configuration (n,), else N for (N, n); ``rng``: a numpy Generator, an int seed
        or None (fresh entropy); ``default_range``: the half range of unlimited joints (radians, or length
        units for prismatic joints).
        """
        rng = np.random.default_rng(rng)
        lim = self.limits
        lo = np.where(np.isfinite(lim[:, 0]), lim[:, 0], -default_range)
        hi = np.where(np.isfinite(lim[:, 1]), lim[:, 1], default_range)
        shape = (self.n,) if size is None else (size, self.n)
        return rng.uniform(lo, hi, size=shape)

    def __repr__(self) -> str:
        kinds = "".join("R" if j.revolute else "P" for j in self.joints)
        return f"Robot(name={self.name!r}, n={self.n}, joints={kinds})"


#: row order that turns a (w, v) twist into [v; w]
_V_THEN_W = [3, 4, 5, 0, 1, 2]


def robot_from_frames(frames: Sequence[ArrayLike], types: Sequence[str] | None = None,
                      joints: Sequence[Joint] | None = None, **kw: Any) -> Robot:
    """Robot from GJD frames and either joint types or Joint objects."""
    if joints is None:
        if types is None:
            raise InputError("joints: give joint types or Joint objects")
        joints = default_joints(types)
    return Robot(np.asarray(frames, dtype=float), tuple(joints), **kw)
