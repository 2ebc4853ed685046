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
from typing import Iterable, Literal, Sequence

import numpy as np
from numpy.typing import ArrayLike

from .errors import InputError, ProjectionWarning
from . import se3
from .bodies import EMPTY_BODIES, Bodies, Mimic

__all__ = ["Joint", "Robot", "JOINT_TYPES", "check_pose", "check_q"]

JointType = Literal["revolute", "prismatic"]
JOINT_TYPES: tuple[str, ...] = ("revolute", "prismatic")

#: An input rotation farther than this (Frobenius norm) from SO(3), or a unit vector whose norm is
#: farther than this from 1, is an error; closer than this it is projected with a warning. 1e-2 admits
#: matrices typed with 3 decimals (error up to ~sqrt(9) * 5e-4 ~ 1.5e-3, plus cross-terms) with margin,
#: while anything visibly wrong (a typo in one entry of 0.1) is still refused.
PROJECTION_TOL = 1e-2
#: Below this the input is taken as valid as it is (rounding noise of float64 products); between this
#: and PROJECTION_TOL it is projected and a warning names the field.
EXACT_TOL = 1e-9


@dataclass(frozen=True)
class Joint:
    """One joint: name, type, optional limits (rad or length units) and Corke's ``flip`` flag.

    ``flip`` means the joint moves opposite to the z axis of its frame in frame-based representations
    (DH, modified DH, RPY-XYZ). The GJD and PoE always use the positive direction, so for them flip
    only decides how frame-based tables are written.

    ``effort`` (N or N m), ``velocity`` (m/s or rad/s), ``damping``, ``friction`` and ``mimic`` are
    kept from robot files and written back; kinematics never uses them.
    """

    name: str
    type: JointType = "revolute"
    lower: float | None = None
    upper: float | None = None
    flip: bool = False
    effort: float | None = None
    velocity: float | None = None
    damping: float | None = None
    friction: float | None = None
    mimic: Mimic | None = None

    def __post_init__(self) -> None:
        if self.type not in JOINT_TYPES:
            raise InputError(f"joint '{self.name}': type '{self.type}' is not one of {', '.join(JOINT_TYPES)}")
        for bound in ("lower", "upper"):
            v = getattr(self, bound)
            if v is not None and math.isnan(v):
                raise InputError(f"joint '{self.name}': limits.{bound} is NaN")
        if self.lower is not None and self.upper is not None and self.lower > self.upper:
            raise InputError(f"joint '{self.name}': limits.lower {self.lower} > limits.upper {self.upper}")

    @property
    def revolute(self) -> bool:
        return self.type == "revolute"


def default_joints(types: Iterable[str]) -> tuple[Joint, ...]:
    """Joints named joint1..jointN with the given types."""
    return tuple(Joint(f"joint{i + 1}", t) for i, t in enumerate(types))  # type: ignore[arg-type]


def check_pose(T: ArrayLike, field_name: str, *, warn: bool = True) -> np.ndarray:
    """Validate and normalise one 4x4 rigid transform.

    Returns a float array whose rotation block is exactly orthonormal (projected if the input was
    within PROJECTION_TOL, with a ProjectionWarning naming ``field_name``). Raises InputError otherwise.
    """
    import warnings

    try:
        A = np.array(T, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{field_name}: expected a 4x4 matrix of numbers") from None
    if A.shape == (3, 4):
        A = np.vstack([A, [0.0, 0.0, 0.0, 1.0]])
    if A.shape != (4, 4):
        raise InputError(f"{field_name}: expected a 4x4 matrix, got shape {A.shape}")
    if not np.all(np.isfinite(A)):
        raise InputError(f"{field_name}: contains NaN or infinity")
    if np.max(np.abs(A[3] - [0, 0, 0, 1])) > EXACT_TOL:
        raise InputError(f"{field_name}: last row must be [0, 0, 0, 1], got {A[3].tolist()}")
    A[3] = [0.0, 0.0, 0.0, 1.0]
    err = float(se3.rotation_error(A[:3, :3]))
    if err > PROJECTION_TOL:
        what = "has det <= 0 (a reflection)" if not np.isfinite(err) else f"is {err:.3g} from a rotation"
        raise InputError(f"{field_name}: rotation block {what}; a rotation matrix is needed "
                         f"(tolerance {PROJECTION_TOL})")
    if err > EXACT_TOL:
        if warn:
            warnings.warn(f"{field_name}: rotation block is {err:.2g} from orthonormal; projected onto "
                          f"the nearest rotation", ProjectionWarning, stacklevel=3)
        A[:3, :3] = se3.nearest_rotation(A[:3, :3])
    return A


def check_q(q: ArrayLike, n: int) -> np.ndarray:
    """Joint values as float array (n,) or (N, n); InputError for wrong shapes or non-finite values."""
    try:
        Q = np.asarray(q, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"q: expected {n} numbers") from None
    if Q.ndim == 0 or Q.shape[-1] != n or Q.ndim > 2:
        raise InputError(f"q: expected shape ({n},) or (N, {n}), got {Q.shape}")
    if not np.all(np.isfinite(Q)):
        raise InputError("q: contains NaN or infinity")
    return Q


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
    bodies : Bodies, optional
        What the source file said beyond kinematics (link names, shapes, inertials, attached links;
        see ``robkin.bodies``), kept so that writers lose nothing. Empty by default.
    """

    frames: np.ndarray
    joints: tuple[Joint, ...]
    world: np.ndarray = field(default_factory=lambda: np.eye(4))
    name: str | None = None
    bodies: Bodies = EMPTY_BODIES

    def __post_init__(self) -> None:
        frames = np.array(self.frames, dtype=float)
        joints = tuple(self.joints)
        if frames.ndim != 3 or frames.shape[1:] != (4, 4):
            raise InputError(f"gjd.frames: expected n+1 4x4 matrices, got shape {frames.shape}")
        n = len(joints)
        if n < 1:
            raise InputError("joints: a robot needs at least one joint")
        if frames.shape[0] != n + 1:
            raise InputError(f"gjd.frames: expected {n + 1} frames for {n} joints, got {frames.shape[0]}")
        names = [j.name for j in joints]
        dup = {x for x in names if names.count(x) > 1}
        if dup:
            raise InputError(f"joints: duplicate joint name(s) {', '.join(sorted(dup))}")
        checked = np.stack([check_pose(F, f"gjd.frames[{i}]") for i, F in enumerate(frames)])
        world = check_pose(self.world, "world")
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
        p, z = self.points, self.axes
        feet = p - np.einsum("ij,ij->i", p, z)[:, None] * z
        s = float(max(np.linalg.norm(self.tool[:3, 3]), np.linalg.norm(feet, axis=1).max()))
        # Every axis through the base origin and the tool at it, up to rounding (a robot along one
        # line: coincident axes offset only along them): the axis distances are rounding noise
        # (seen: 1e-28) and say nothing about size, while the frame origins along the axes do.
        # 1e-9: far above the rounding of coordinates (~1e-16 relative), far below any real offset.
        origins = float(np.linalg.norm(self.frames[:, :3, 3], axis=1).max())
        if s <= 1e-9 * origins:
            s = origins
        # Conversions compute with the frame origins, so tolerances must stay above their rounding
        # (eps times their size): the scale is never below 1/1000 of the farthest origin. Only 1/1000,
        # because a frame may sit far along its axis (the common normal of nearly parallel axes)
        # without the robot being any bigger, and tolerances that large would be too loose for it.
        s = max(s, 1e-3 * origins)
        return s if s > 0 else 1.0

    @property
    def limits(self) -> np.ndarray:
        """Joint limits (n, 2), -inf/+inf where none are given."""
        return np.array([[-np.inf if j.lower is None else j.lower, np.inf if j.upper is None else j.upper]
                         for j in self.joints])

    def screws(self) -> np.ndarray:
        """Space-frame unit screws (n, 6) ordered (w, v): revolute (z, -z x p), prismatic (0, z)."""
        z, p = self.axes, self.points
        S = np.zeros((self.n, 6))
        S[self.revolute, :3] = z[self.revolute]
        S[self.revolute, 3:] = -np.cross(z[self.revolute], p[self.revolute])
        S[~self.revolute, 3:] = z[~self.revolute]
        return S

    def replace(self, **changes) -> "Robot":
        """A copy with some fields changed (frames, joints, world, name)."""
        return replace(self, **changes)

    # ------------------------------------------------------------------ kinematics
    @cached_property
    def _local(self) -> np.ndarray:
        """Fixed transforms L (n+1, 4, 4): T(q) = L_1 Z_1(q_1) L_2 ... L_n Z_n(q_n) L_{n+1}.

        L_1 = J_1 and L_i = J_{i-1}^-1 J_i, because exp([S_i] q) = J_i Z(q) J_i^-1 with Z a rotation
        about (or translation along) z.
        """
        F = self.frames
        L = np.empty_like(F)
        L[0] = F[0]
        L[1:] = se3.inv(F[:-1]) @ F[1:]
        L.setflags(write=False)
        return L

    def fk(self, q: ArrayLike) -> np.ndarray:
        """Tool pose in the base frame: q (n,) -> (4, 4), or a batch (N, n) -> (N, 4, 4)."""
        Q = check_q(q, self.n)
        if Q.ndim == 1:
            return self._fk_one(Q)
        return self._fk_batch(Q)

    def _joint_motions(self, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """cos, sin and slide of every joint for q (..., n): revolute (cos q, sin q, 0), prismatic (1, 0, q)."""
        rev = self.revolute
        c = np.where(rev, np.cos(Q), 1.0)
        s = np.where(rev, np.sin(Q), 0.0)
        t = np.where(rev, 0.0, Q)
        return c, s, t

    @cached_property
    def _fk_parts(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, bool]:
        """B, C, S, P (n, 4, 4) with L_i Z_i(q) = B_i + cos(q) C_i + sin(q) S_i + q P_i, and whether
        any joint is prismatic (P is then not all zero).

        A revolute Z mixes columns 0 and 1 of L_i (x -> c x + s y, y -> c y - s x); a prismatic Z
        adds q z to column 3. Precomputed once, so FK needs no per-joint branching or masking (the
        cos/sin of a prismatic q multiply zero matrices).
        """
        L = self._local[:-1]
        rev, pri = self.revolute, ~self.revolute
        B, C, S, P = L.copy(), np.zeros_like(L), np.zeros_like(L), np.zeros_like(L)
        B[rev, :, :2] = 0.0
        C[rev, :, 0], C[rev, :, 1] = L[rev, :, 0], L[rev, :, 1]
        S[rev, :, 0], S[rev, :, 1] = L[rev, :, 1], -L[rev, :, 0]
        P[pri, :, 3] = L[pri, :, 2]
        for part in (B, C, S, P):
            part.setflags(write=False)
        return B, C, S, P, bool(pri.any())

    def _fk_one(self, q: np.ndarray) -> np.ndarray:
        # All link transforms at once, A_i = L_i Z_i(q_i), in a few whole-array operations, then
        # their product. At this size the cost is Python-call overhead, not arithmetic: np.dot on
        # 4x4 costs about half of the @ operator (measured), and no per-joint branching remains.
        B, C, S, P, prismatic = self._fk_parts
        A = B + np.cos(q)[:, None, None] * C + np.sin(q)[:, None, None] * S
        if prismatic:
            A += q[:, None, None] * P
        T = A[0]
        for i in range(1, self.n):
            T = np.dot(T, A[i])
        return np.dot(T, self._local[-1])

    #: configurations per block of batch FK: the block's pose columns (4 x 3 x 1024 doubles, 96 kB)
    #: stay in cache through all joints. Measured on a 7-joint arm (a shared, noisy machine): whole
    #: batches of 1e5 ran ~3x slower per configuration than 1e3; blocks of 2048 ~1.4x slower than
    #: 1024; 512 no faster.
    _FK_BLOCK = 1024

    def _fk_batch(self, Q: np.ndarray) -> np.ndarray:
        # The poses are kept column-major, F[k] = column k of [R | p] for every configuration, shape
        # (4, m, 3), so that every operation runs on contiguous memory: right-multiplying by a fixed
        # 4x4 is one GEMM L^T (4, 4) @ F (4, 3m), and a joint motion mixes two columns (revolute) or
        # adds to the last one (prismatic). Joint values are taken per block and transposed, so the
        # per-joint factors are contiguous too.
        N = Q.shape[0]
        L = self._local
        out = np.empty((N, 4, 4))
        out[:, 3] = (0.0, 0.0, 0.0, 1.0)
        first = np.ascontiguousarray(L[0, :3].T)[:, None, :]  # (4, 1, 3)
        for start in range(0, N, self._FK_BLOCK):
            stop = min(N, start + self._FK_BLOCK)
            m = stop - start
            Qb = np.ascontiguousarray(Q[start:stop].T)[:, :, None]  # (n, m, 1)
            c, s = np.cos(Qb), np.sin(Qb)
            F = np.repeat(first, m, axis=1)  # (4, m, 3)
            for i in range(self.n):
                if self.revolute[i]:
                    x = F[0] * c[i]
                    x += F[1] * s[i]
                    F[1] *= c[i]
                    F[1] -= F[0] * s[i]
                    F[0] = x
                else:
                    F[3] += Qb[i] * F[2]
                F = (L[i + 1].T @ F.reshape(4, -1)).reshape(4, m, 3)
            out[start:stop, :3] = F.transpose(1, 2, 0)
        return out

    def frames_at(self, q: ArrayLike) -> np.ndarray:
        """All GJD frames moved to configuration q: (n,) -> (n+1, 4, 4), (N, n) -> (N, n+1, 4, 4).

        Frame i is joint i's frame *after* its own motion, so frame n+1 is the tool pose fk(q).
        Joint i's axis at q is the z axis of frame i before its motion, which has the same z axis.
        """
        Q = check_q(q, self.n)
        single = Q.ndim == 1
        Q2 = np.atleast_2d(Q)
        N = Q2.shape[0]
        L = self._local
        c, s, t = self._joint_motions(Q2)
        out = np.empty((N, self.n + 1, 4, 4))
        T = np.broadcast_to(L[0], (N, 4, 4)).copy()
        for i in range(self.n):
            Z = np.broadcast_to(np.eye(4), (N, 4, 4)).copy()
            Z[:, 0, 0] = Z[:, 1, 1] = c[:, i]
            Z[:, 0, 1], Z[:, 1, 0] = -s[:, i], s[:, i]
            Z[:, 2, 3] = t[:, i]
            out[:, i] = T @ Z
            T = out[:, i] @ L[i + 1]
        out[:, self.n] = T
        return out[0] if single else out

    def ik(self, T: ArrayLike, **options):
        """Inverse kinematics for a target (4, 4) or targets (N, 4, 4): see ``robkin.kinematics.ik.ik``.

        Returns an ``IKResult`` with ``.q``, ``.success`` and the errors reached.
        """
        from .kinematics.ik import ik

        return ik(self, T, **options)

    # ------------------------------------------------------------------ conveniences
    def random_q(self, size: int | None = None, rng: np.random.Generator | int | None = None,
                 default_range: float = math.pi) -> np.ndarray:
        """Random joint values within limits (uniform); unlimited joints use +-default_range."""
        rng = np.random.default_rng(rng)
        lim = self.limits
        lo = np.where(np.isfinite(lim[:, 0]), lim[:, 0], -default_range)
        hi = np.where(np.isfinite(lim[:, 1]), lim[:, 1], default_range)
        shape = (self.n,) if size is None else (size, self.n)
        return rng.uniform(lo, hi, size=shape)

    def __repr__(self) -> str:
        kinds = "".join("R" if j.revolute else "P" for j in self.joints)
        return f"Robot(name={self.name!r}, n={self.n}, joints={kinds})"


def robot_from_frames(frames: Sequence[ArrayLike], types: Sequence[str] | None = None,
                      joints: Sequence[Joint] | None = None, **kw) -> Robot:
    """Robot from GJD frames and either joint types or Joint objects."""
    if joints is None:
        if types is None:
            raise InputError("joints: give joint types or Joint objects")
        joints = default_joints(types)
    return Robot(np.asarray(frames, dtype=float), tuple(joints), **kw)
