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
        inertia = np.einsum("kji,kjl,klm->kim", R, self.inertia, R)  # R^T I R
        return self.mass.copy(), com, 0.5 * (inertia + inertia.transpose(0, 2, 1))


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
    mass, com, inertia = merge_masses_by_group(np.array([part.mass for part in inertials]), pose[:, :3, 3],
                                               rotated, body, n + 1)
    return LinkMasses(mass, com, inertia)


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
