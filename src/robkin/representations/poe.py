"""Product of Exponentials (space and body frame), to and from the GJD hub.

Screws are (w, v) as in Modern Robotics: revolute (w, -w x p) with |w| = 1, prismatic (0, v) with
|v| = 1. Space frame: T(q) = exp([S_1] q_1) ... exp([S_n] q_n) M. Body frame:
T(q) = M exp([B_1] q_1) ... exp([B_n] q_n) with B_i = Ad_{M^-1} S_i.

PoE -> GJD places frames on the screw axes by the DH rules (``frames.common_normal_frame``).
A prismatic screw has no position: its axis is placed through the point of the previous axis
(the paper's q_i = q_{i-1}; the robot base origin for joint 1). FK does not depend on that choice,
but a DH table derived from the PoE may differ from the one the PoE came from (the paper's Table III).

Mass properties (optional ``masses``, ``mass_rows.MassRows``): a PoE has no link frames, so each link's
are given at q = 0 in the PoE's own reference frame: the robot base for space screws (so ``r`` is the
centre of mass's home position, as Modern Robotics' space-frame quantities are), the home tool pose M
for body screws.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import ArrayLike

from .. import se3
from ..errors import InputError, ProjectionWarning
from ..robot import EXACT_TOL, PROJECTION_TOL, Joint, Robot, check_pose, check_q
from .frames import common_normal_frame
from .link_table import check_masses
from .mass_rows import masses_of_robot, table_bodies

if TYPE_CHECKING:  # pragma: no cover
    from .mass_rows import MassRows

__all__ = ["PoE", "poe_from_robot", "robot_from_poe", "check_screws"]

Frame = Literal["space", "body"]


def check_screws(screws: ArrayLike, joints: tuple[Joint, ...], field_name: str = "poe.screws",
                 *, warn: bool = True, size: float = 0.0) -> np.ndarray:
    """Validate unit screws (n, 6) against joint types; project near-valid ones with a warning.

    Revolute: |w| = 1 and w . v = 0 (no pitch). Prismatic: w = 0 and |v| = 1. Within PROJECTION_TOL
    (relative: |w . v| is compared with the robot's size, the largest of ``size`` and the revolute
    |v|) the screw is projected onto the nearest valid one.

    ``size`` is a length of the robot the screws do not show, in the screws' length unit: the
    distance from the PoE's reference frame to the tool (|translation of M|). In the body frame every
    axis may pass through the tool origin (all |v| ~ 0) while the tool is 1000 units from the base.

    ``joints``: the joints the screws belong to (their types decide what is valid); ``field_name``: how
    messages name the screws (``poe.screws[i]``); ``warn``: False projects silently.
    """
    try:
        S = np.array(screws, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{field_name}: expected rows of 6 numbers (wx, wy, wz, vx, vy, vz)") from None
    n = len(joints)
    if S.ndim != 2 or S.shape[1] != 6:
        raise InputError(f"{field_name}: expected rows of 6 numbers (wx, wy, wz, vx, vy, vz), got shape {S.shape}")
    if S.shape[0] != n:
        raise InputError(f"{field_name}: expected {n} screws (one per joint), got {S.shape[0]}")
    out = S.copy()
    # The pitch tolerance is relative to the robot's size (the farthest revolute axis from the
    # origin, |v| = distance, or the tool: ``size``): relative to each screw's own |v| it refused an
    # axis passing 10 um from the origin typed to the um, where rounding is 5 % of that |v| but 1e-3
    # of the robot.
    finite = np.all(np.isfinite(S), axis=1) & np.array([j.revolute for j in joints])
    size = max(float(np.linalg.norm(S[finite, 3:], axis=1).max()) if finite.any() else 0.0, size)
    for i, (s, joint) in enumerate(zip(S, joints)):
        where = f"{field_name}[{i}] (joint '{joint.name}', {joint.type})"
        if not np.all(np.isfinite(s)):
            raise InputError(f"{where}: contains NaN or infinity")
        w, v = s[:3], s[3:]
        fixes = []
        if joint.revolute:
            k = np.linalg.norm(w)
            if abs(k - 1.0) > PROJECTION_TOL:
                raise InputError(f"{where}: w must be a unit vector (|w| = {k:.4g}); a revolute screw is "
                                 f"(w, -w x p) with |w| = 1")
            if abs(k - 1.0) > EXACT_TOL:
                fixes.append(f"|w| = {k:.6g} normalised")
            w, v = w / k, v / k
            pitch = float(np.dot(w, v))
            if abs(pitch) > PROJECTION_TOL * max(float(np.linalg.norm(v)), size, 1e-300) and abs(pitch) > EXACT_TOL:
                raise InputError(f"{where}: w . v = {pitch:.4g} is not 0; a revolute joint has no pitch "
                                 f"(v = -w x p)")
            if abs(pitch) > EXACT_TOL:
                fixes.append(f"pitch w.v = {pitch:.3g} removed")
            v = v - pitch * w
        else:
            kw = np.linalg.norm(w)
            if kw > PROJECTION_TOL:
                raise InputError(f"{where}: w must be 0 for a prismatic joint (|w| = {kw:.4g})")
            if kw > EXACT_TOL:
                fixes.append(f"|w| = {kw:.3g} set to 0")
            w = np.zeros(3)
            k = np.linalg.norm(v)
            if abs(k - 1.0) > PROJECTION_TOL:
                raise InputError(f"{where}: v must be a unit vector (|v| = {k:.4g}) for a prismatic joint")
            if abs(k - 1.0) > EXACT_TOL:
                fixes.append(f"|v| = {k:.6g} normalised")
            v = v / k
        if fixes and warn:
            warnings.warn(f"{where}: {'; '.join(fixes)}", ProjectionWarning, stacklevel=3)
        out[i] = np.concatenate([w, v])
    return out


@dataclass(frozen=True, eq=False)
class PoE:
    """Product of Exponentials: home tool pose M (4, 4) and unit screws (n, 6) in ``frame``; ``masses``
    of links 1..n at q = 0 in the same frame (the base, or M), or None when unknown."""

    M: np.ndarray
    screws: np.ndarray
    joints: tuple[Joint, ...]
    frame: Frame = "space"
    masses: "MassRows | None" = None

    def __post_init__(self) -> None:
        if self.frame not in ("space", "body"):
            raise InputError(f"poe.frame: '{self.frame}' is not one of space, body")
        section = "poe" if self.frame == "space" else "poe_body"
        object.__setattr__(self, "joints", tuple(self.joints))
        object.__setattr__(self, "M", check_pose(self.M, f"{section}.M"))
        object.__setattr__(self, "screws", check_screws(self.screws, self.joints, f"{section}.screws",
                                                        size=float(np.linalg.norm(self.M[:3, 3]))))
        if self.masses is not None:
            check_masses(self.masses, len(self.joints), section)

    @property
    def n(self) -> int:
        return len(self.joints)

    def __str__(self) -> str:
        """The table as the CLI prints it (``robkin convert --to poe / poe-body``)."""
        from .presentation import table_text

        return table_text(self)

    def to_dict(self) -> dict[str, Any]:
        """A robot document (dict): ``joints`` and this table's section, as ``robkin.load`` reads it."""
        from .presentation import table_document

        return table_document(self)

    def space_screws(self) -> np.ndarray:
        """Screws in the space frame (n, 6)."""
        if self.frame == "space":
            return self.screws
        return self.screws @ se3.adjoint(self.M).T

    def body_screws(self) -> np.ndarray:
        """Screws in the body (tool) frame (n, 6)."""
        if self.frame == "body":
            return self.screws
        return self.screws @ se3.adjoint(se3.inv(self.M)).T

    def link_frames(self) -> np.ndarray:
        """(n + 1, 4, 4): the frame the ``masses`` are in, once per body: the identity (space screws)
        or M (body screws)."""
        return np.broadcast_to(np.eye(4) if self.frame == "space" else self.M, (self.n + 1, 4, 4)).copy()

    def to_frame(self, frame: Frame) -> "PoE":
        """The same PoE with screws (and masses) expressed in the other frame (via the adjoint of M)."""
        S = self.space_screws() if frame == "space" else self.body_screws()
        out = PoE(self.M, S, self.joints, frame)
        if self.masses is None or frame == self.frame:
            return replace(out, masses=self.masses)
        return replace(out, masses=masses_of_robot(self.to_robot(), out.link_frames()))

    def fk(self, q: ArrayLike) -> np.ndarray:
        """Tool pose from the exponentials: q (n,) -> (4, 4), (N, n) -> (N, 4, 4)."""
        Q = check_q(q, self.n)
        E = se3.exp_twist(self.screws, Q)  # (..., n, 4, 4)
        T = np.broadcast_to(np.eye(4), Q.shape[:-1] + (4, 4))
        for i in range(self.n):
            T = T @ E[..., i, :, :]
        return T @ self.M if self.frame == "space" else self.M @ T

    def to_robot(self, name: str | None = None) -> Robot:
        """The robot these screws describe (``robot_from_poe``); ``name``: the robot's name (default: none)."""
        return robot_from_poe(self, name=name)


#: a GJD frame farther than this many robot sizes along its axis from the previous origin is slid back
#: (``robot_from_poe``): real links are within a few sizes; the far ones come of nearly parallel axes
FAR = 10.0


def robot_from_poe(poe: "PoE | ArrayLike", name: str | None = None, *, M: ArrayLike | None = None,
                   joints: Any = None, frame: Frame = "space") -> Robot:
    """GJD from a PoE: DH-style frames on the screw axes (prismatic axes through the previous axis point).

    ``poe`` may also be the screws alone, an (n, 6) array of (wx, wy, wz, vx, vy, vz), with ``M`` (the
    home tool pose (4, 4); identity when absent), ``frame`` ('space' or 'body') and ``joints`` (None:
    prismatic where w = 0, revolute elsewhere; a type string such as "RRPR"; or n ``Joint``); anything
    else raises one InputError.

    ``name``: the robot's name (default: none).
    """
    if not isinstance(poe, PoE):
        poe = _poe_of(poe, M, joints, frame)
    elif M is not None or joints is not None:
        raise InputError("robot_from_poe: M= and joints= go with an array of screws; the PoE has its own")
    S = poe.space_screws()
    # Scale for tolerances: the robot's size from M and the axis points closest to the origin.
    pts = np.cross(S[:, :3], S[:, 3:])
    scale = float(max(np.linalg.norm(poe.M[:3, 3]), np.linalg.norm(pts, axis=1).max(), 0.0)) or 1.0
    frames = np.empty((poe.n + 1, 4, 4))
    prev = np.eye(4)
    p = np.zeros(3)  # the point of the previous axis (the base origin before joint 1)
    for i, joint in enumerate(poe.joints):
        w, v = S[i, :3], S[i, 3:]
        if joint.revolute:
            u, p = w, np.cross(w, v)  # w x v = foot of the axis from the origin
        else:
            # the paper's q_i = q_{i-1}: through the previous axis's point, which lies near the robot.
            # Not through the previous DH frame's origin: after nearly parallel axes that frame may sit
            # ~offset / sin away, and a next axis nearly parallel to this one would put the following
            # frame ~offset / sin^2 away, where FK loses eps times that (seen: 1e-4 of the robot size).
            u = v
        joint_frame = common_normal_frame(prev[:3, 3], prev[:3, 2], p, u, on="b", prev=prev, scale=scale)
        # Nearly parallel axes (not parallel within robkin.lines' tolerance) meet their common normal
        # ~offset / sin away: SO-100's base z and joint-1 axis are 6.3e-6 rad apart and put J_1 7.1 km out,
        # where FK through the frames loses eps x 7 km = 6e-12 of the robot's size. Such a frame slides back
        # along its axis to the point nearest the previous origin (z, x kept: still a frame on the axis whose x
        # is the common normal's direction); FAR x the robot's size is far beyond any real link offset.
        o, z = joint_frame[:3, 3], joint_frame[:3, 2]
        foot = o + float(np.dot(prev[:3, 3] - o, z)) * z
        if np.linalg.norm(foot - o) > FAR * scale:
            joint_frame[:3, 3] = foot
        prev = joint_frame
        frames[i] = prev
    frames[-1] = poe.M
    return Robot(frames, poe.joints, name=name, bodies=table_bodies(poe.masses, poe.link_frames()))


def poe_from_robot(robot: Robot, frame: Frame = "space") -> PoE:
    """PoE of a robot: M = J_{n+1}, screws from the GJD axes (space frame, or body via the adjoint);
    the robot's mass properties (if any) at q = 0 in that frame."""
    poe = PoE(robot.tool, robot.screws(), robot.joints, "space")
    poe = poe if frame == "space" else poe.to_frame("body")
    if robot.bodies.inertials:
        poe = replace(poe, masses=masses_of_robot(robot, poe.link_frames()))
    return poe


def _poe_of(screws: Any, M: ArrayLike | None, joints: Any, frame: Frame) -> PoE:
    """A PoE from an (n, 6) array of screws (``robot_from_poe``)."""
    from .table_input import joints_for, rows_array

    where = "robot_from_poe"
    if hasattr(screws, "SECTION"):
        raise InputError(f"{where}: got a {type(screws).__name__}; use robot_from_{screws.SECTION} or its .to_robot()")
    S = rows_array(screws, ("wx", "wy", "wz", "vx", "vy", "vz"), where,
                   expected="a PoE or an (n, 6) array of screws (wx, wy, wz, vx, vy, vz)")
    if joints is None:  # a screw without rotation is a prismatic joint's
        joints = "".join("P" if not np.any(s[:3]) else "R" for s in S)
    return PoE(np.eye(4) if M is None else np.asarray(M, dtype=float), S, joints_for(joints, len(S), where), frame)
