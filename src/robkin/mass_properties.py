"""Mass properties of a robot's bodies, merged and re-expressed exactly.

A robot file gives inertials per *link*; ``robkin.bodies`` puts each on the *body* it moves with (body 0
is fixed to the base, body i moves with joint i), with its pose in the robot base frame at q = 0. For
dynamics, and for tables that carry one mass per link frame, everything on one body is one rigid body:
``link_masses`` merges them (the parallel-axis theorem) into a mass, a centre of mass and an inertia
about that centre per body, still in the base frame at q = 0; ``LinkMasses.in_frames`` re-expresses
them in any frames that move with the bodies (DH frame {i}, modified-DH frame {i}, GJD frame J_i), and
``inertials_from_frames`` is the way back, from a table's per-link values to ``Inertial`` records.

Units: kg, metres, kg m^2 (or the file's consistent units).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Sequence

import numpy as np
from numpy.typing import ArrayLike

from .errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    from .body_parts import Inertial
    from .robot import Robot

__all__ = ["LinkMasses", "link_masses", "merge_masses", "merge_masses_by_group", "inertials_from_frames",
           "check_inertia"]


def merge_masses(mass: ArrayLike, com: ArrayLike, inertia: ArrayLike) -> tuple[float, np.ndarray, np.ndarray]:
    """Combine k rigid bodies given in one frame into one, exactly.

    Parameters
    ----------
    mass : (k,) array
        Masses (kg), each >= 0.
    com : (k, 3) array
        Centres of mass in the common frame (m).
    inertia : (k, 3, 3) array
        Inertias about each body's own centre of mass, in the common frame's axes (kg m^2).

    Returns
    -------
    mass : float
        Total mass.
    com : (3,) array
        Centre of mass of the whole (the origin when the total mass is 0).
    inertia : (3, 3) array
        Inertia of the whole about its centre of mass (parallel-axis theorem), symmetric.
    """
    m = np.asarray(mass, dtype=float).reshape(-1)
    total, centre, merged = merge_masses_by_group(m, com, inertia, np.zeros(len(m), dtype=np.intp), 1)
    return float(total[0]), centre[0], merged[0]


def merge_masses_by_group(mass: ArrayLike, com: ArrayLike, inertia: ArrayLike, groups: ArrayLike,
                          count: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``merge_masses`` for several wholes at once: the k bodies of each group 0..count-1 merged.

    Parameters
    ----------
    mass, com, inertia : (k,), (k, 3), (k, 3, 3) arrays
        As ``merge_masses``.
    groups : (k,) int array
        The group of each body, in 0..count-1.
    count : int
        Number of groups.

    Returns
    -------
    mass : (count,) array
    com : (count, 3) array
        The origin for a group without mass (or without bodies).
    inertia : (count, 3, 3) array
        Zero for a group without mass.
    """
    m = np.asarray(mass, dtype=float).reshape(-1)
    c = np.asarray(com, dtype=float).reshape(-1, 3)
    inertia_c = np.asarray(inertia, dtype=float).reshape(-1, 3, 3)
    g = np.asarray(groups, dtype=np.intp).reshape(-1)
    total = np.bincount(g, weights=m, minlength=count)
    moment = np.zeros((count, 3))
    np.add.at(moment, g, m[:, None] * c)
    massive = total > 0.0
    centre = np.zeros((count, 3))
    centre[massive] = moment[massive] / total[massive, None]
    # a whole of one massive part is that part: its centre exactly (m c / m can be off by an ulp, and
    # the parallel-axis term of that ulp would be 1e-32 noise where the part has a 0 product of inertia)
    alone = massive & (np.bincount(g, weights=(m > 0.0), minlength=count) == 1)
    which = np.zeros(count, dtype=np.intp)
    which[g[m > 0.0]] = np.flatnonzero(m > 0.0)
    centre[alone] = c[which[alone]]
    d = c - centre[g]                                # offsets of each body's centre from its whole's
    # parallel axis: I_about_centre = I_c + m (|d|^2 E - d d^T), summed per group
    shift = m[:, None, None] * ((d * d).sum(axis=1)[:, None, None] * np.eye(3) - d[:, :, None] * d[:, None, :])
    merged = np.zeros((count, 3, 3))
    np.add.at(merged, g, inertia_c + shift)
    merged[~massive] = 0.0
    return total, centre, 0.5 * (merged + merged.transpose(0, 2, 1))


@dataclass(frozen=True, eq=False)
class LinkMasses:
    """Mass properties of the chain's bodies 0..n at q = 0, each body's parts merged exactly.

    Attributes
    ----------
    mass : (n+1,) array
        kg; body 0 is everything fixed to the robot base (it never moves, so dynamics ignore it).
    com : (n+1, 3) array
        Centre of mass in the robot base frame at q = 0 (m); the origin where the mass is 0.
    inertia : (n+1, 3, 3) array
        Inertia about the centre of mass in base-frame axes (kg m^2).
    """

    mass: np.ndarray
    com: np.ndarray
    inertia: np.ndarray
    #: the parts merged (``link_masses``), for which entries of ``in_frames`` are exactly 0; None: unknown
    parts: "_Parts | None" = None

    def __post_init__(self) -> None:
        for name in ("mass", "com", "inertia"):
            a = np.array(getattr(self, name), dtype=float)
            a.setflags(write=False)
            object.__setattr__(self, name, a)

    @property
    def n(self) -> int:
        """Number of joints (bodies 1..n move)."""
        return len(self.mass) - 1

    @property
    def total_mass(self) -> float:
        """Mass of the whole robot, base included (kg)."""
        return float(self.mass.sum())

    def in_frames(self, frames: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The same mass properties expressed in one frame per body.

        Parameters
        ----------
        frames : (n+1, 4, 4) array
            Pose of body i's frame in the robot base frame at q = 0 (it must move with body i: DH
            frame {i}, modified-DH frame {i}, GJD frame J_i; index 0 a frame fixed to the base).

        Returns
        -------
        mass : (n+1,) array
        com : (n+1, 3) array
            Centre of mass in frame i (m); 0 where the mass is 0.
        inertia : (n+1, 3, 3) array
            Inertia about the centre of mass, in frame i's axes (kg m^2).
        """
        F = np.asarray(frames, dtype=float)
        if F.shape != (self.n + 1, 4, 4):
            raise InputError(f"frames: expected ({self.n + 1}, 4, 4) for {self.n + 1} bodies, got {F.shape}")
        R, p = F[:, :3, :3], F[:, :3, 3]
        com = np.einsum("kji,kj->ki", R, self.com - p)          # R^T (c - p)
        com[self.mass == 0] = 0.0
        # a centre closer to 0 than the rounding of c - p (a few ulps of the larger) is 0: the
        # frame sits on it exactly, and what is left is the noise of the frame algebra
        reach = np.abs(self.com).max(axis=1) + np.abs(p).max(axis=1)
        com[np.abs(com) <= EXACT_ZERO * reach[:, None]] = 0.0
        inertia = np.einsum("kji,kjl,klm->kim", R, self.inertia, R)  # R^T I R
        inertia = 0.5 * (inertia + inertia.transpose(0, 2, 1))
        if self.parts is not None:  # the entries that are 0 in the source stay exactly 0
            inertia[~self.parts.nonzero_in(R, self.com)] = 0.0
        return self.mass.copy(), com, inertia


#: A rotation entry (or a centre's coordinate, relative to the lengths it was computed from) this close
#: to 0 is the rounding of an exact 0: cos(pi/2) is 6.1e-17 in floats, and products of rotations leave
#: a few ulps of 1 where the exact product has 0. 4 ulps of 1 (8.9e-16): far below any tilt a robot
#: file describes (UR5's 1.57079632679 for pi/2 is a 4.9e-12 rad tilt, which stays).
EXACT_ZERO = 4 * float(np.finfo(float).eps)


@dataclass(frozen=True, eq=False)
class _Parts:
    """The inertials merged into bodies: which body each is on, its axes in the base frame at q = 0,
    which entries of its inertia are nonzero, its mass and centre (base frame)."""

    body: np.ndarray        # (k,) int
    rotation: np.ndarray    # (k, 3, 3)
    nonzero: np.ndarray     # (k, 3, 3) bool
    mass: np.ndarray        # (k,)
    centre: np.ndarray      # (k, 3)

    def nonzero_in(self, R: np.ndarray, centres: np.ndarray) -> np.ndarray:
        """(n+1, 3, 3) bool: the entries of each body's inertia in axes R (n+1, 3, 3) that are not 0 by
        structure: a part's nonzero entries carried by the rotation from its axes to R's (entries
        within EXACT_ZERO of 0 counted as 0), and the parallel-axis terms of parts off the body's
        centre ``centres`` (n+1, 3) (offsets within the rounding of the centres counted as 0)."""
        net = np.abs(np.einsum("kji,kjl->kil", R[self.body], self.rotation)) > EXACT_ZERO  # part axes -> R's
        S = net.astype(float)
        carried = np.einsum("kij,kjl,kml->kim", S, self.nonzero.astype(float), S) > 0
        d = np.einsum("kji,kj->ki", R[self.body], self.centre - centres[self.body])
        reach = np.abs(self.centre).max(axis=1) + np.abs(centres[self.body]).max(axis=1)
        off = (np.abs(d) > EXACT_ZERO * reach[:, None]) & (self.mass > 0)[:, None]
        # m (|d|^2 E - d d^T): entry (a, a) has d_b^2 + d_c^2, entry (a, b) has d_a d_b
        shift = off[:, :, None] & off[:, None, :]
        others = off.sum(axis=1)[:, None] - off                    # nonzero d's other than d_a
        shift[:, np.arange(3), np.arange(3)] = others > 0
        out = np.zeros((len(R), 3, 3), dtype=bool)
        np.logical_or.at(out, self.body, carried | shift)
        return out


def link_masses(robot: "Robot") -> LinkMasses | None:
    """Merged mass properties of bodies 0..n, or None when the robot has no inertials at all.

    Every inertial of ``robot.bodies`` counts on the body it moves with: fixed links, the tool, and
    links off the chain (whose joints are held at 0) merge into the chain body they hang from. None
    means "unknown" (a kinematics-only source), never zero mass.
    """
    inertials = robot.bodies.inertials
    if not inertials:
        return None
    n = robot.n
    body = np.array([part.body for part in inertials], dtype=np.intp)
    outside = (body < 0) | (body > n)
    if outside.any():
        part = inertials[int(np.argmax(outside))]
        raise InputError(f"inertial of link '{part.link}': on body {part.body}, outside 0..{n}")
    pose = np.stack([part.pose for part in inertials])
    R = pose[:, :3, :3]
    rotated = R @ np.stack([part.inertia for part in inertials]) @ R.transpose(0, 2, 1)   # into base axes
    masses = np.array([part.mass for part in inertials])
    mass, com, inertia = merge_masses_by_group(masses, pose[:, :3, 3], rotated, body, n + 1)
    parts = _Parts(body, R, np.stack([np.asarray(part.inertia) != 0 for part in inertials]), masses,
                   pose[:, :3, 3])
    return LinkMasses(mass, com, inertia, parts)


def check_inertia(mass: float, inertia: ArrayLike, where: str) -> np.ndarray:
    """A (3, 3) inertia about the centre of mass, checked: symmetric, finite, mass >= 0.

    Returns the symmetrised matrix. Raises InputError naming ``where`` otherwise. Physical validity
    (positive definite, triangle inequality) is not required here: sources hold massless frames and
    rounded inertias, and the writers decide what their target format accepts.
    """
    I = np.asarray(inertia, dtype=float)
    if I.shape == (6,):      # Ixx, Iyy, Izz, Ixy, Iyz, Ixz (the robot document's order)
        xx, yy, zz, xy, yz, xz = I
        I = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
    if I.shape != (3, 3):
        raise InputError(f"{where}: inertia must be 6 values (Ixx, Iyy, Izz, Ixy, Iyz, Ixz) or 3x3, got shape {I.shape}")
    if not (np.all(np.isfinite(I)) and np.isfinite(mass)):
        raise InputError(f"{where}: mass and inertia must be finite numbers")
    if mass < 0:
        raise InputError(f"{where}: mass {mass} is negative")
    # 1e-9 relative: inertias written with ~10 significant digits are symmetric to that, not exactly
    if np.max(np.abs(I - I.T)) > 1e-9 * max(1.0, float(np.max(np.abs(I)))):
        raise InputError(f"{where}: inertia matrix is not symmetric")
    return 0.5 * (I + I.T)


def inertials_from_frames(frames: ArrayLike, mass: ArrayLike, com: ArrayLike, inertia: ArrayLike,
                          links: Sequence[str]) -> tuple["Inertial", ...]:
    """Inertial records for bodies 0..n from mass properties given in per-body frames (a table's rows).

    The inverse of ``LinkMasses.in_frames``.

    Parameters
    ----------
    frames : (n+1, 4, 4) array
        Pose of each body's frame in the robot base frame at q = 0.
    mass : (n+1,) array
        kg; NaN for a body whose mass is unknown (no record is made for it, nor for mass 0).
    com : (n+1, 3) array
        Centre of mass in frame i (m).
    inertia : (n+1, 3, 3) or (n+1, 6) array
        About the centre of mass, in frame i's axes (kg m^2); 6 values are Ixx, Iyy, Izz, Ixy, Iyz, Ixz.
    links : sequence of n+1 str
        Link names for the records.

    Returns
    -------
    tuple of Inertial
        One per body with a positive mass, its pose the centre-of-mass frame (axes of frame i).
    """
    from .body_parts import Inertial

    F = np.asarray(frames, dtype=float)
    m = np.asarray(mass, dtype=float).reshape(-1)
    c = np.asarray(com, dtype=float).reshape(-1, 3)
    inertia_arr = np.asarray(inertia, dtype=float)
    k = len(m)
    if F.shape != (k, 4, 4) or len(c) != k or len(inertia_arr) != k or len(links) != k:
        raise InputError(f"mass properties: expected {len(F)} bodies in frames, mass, com, inertia and links")
    out = []
    for i in range(k):
        if np.isnan(m[i]) or m[i] == 0.0:
            continue
        I = check_inertia(float(m[i]), inertia_arr[i], f"link '{links[i]}'")
        pose = F[i].copy()
        pose[:3, 3] = F[i, :3, :3] @ c[i] + F[i, :3, 3]
        out.append(Inertial(link=links[i], body=i, pose=pose, mass=float(m[i]), inertia=I))
    return tuple(out)
