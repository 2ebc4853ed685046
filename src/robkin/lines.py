"""Line geometry for joint axes: closest points, common normal, and how two axes relate.

A line is a point ``p`` (3,) on it and a unit direction ``u`` (3,). Tolerances are relative: angles
are dimensionless, and distances are compared against ``LENGTH_TOL * scale`` where ``scale`` is the
size of the robot (its largest frame-origin distance from the base), so the same robot in metres or in
millimetres is classified the same way.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

import numpy as np

__all__ = [
    "ANGLE_TOL", "LENGTH_TOL", "AxisRelation", "CommonNormal",
    "closest_points", "common_normal", "classify", "point_line_foot", "perpendicular", "frame_with_z", "cross",
    "norm",
]

#: sin of the angle below which two axes are treated as parallel. Exactly parallel axes computed
#: through a chain of rotations differ by ~1e-15; for nearly parallel axes the common normal's feet
#: are ~(offset / angle) away, and their rounding error grows like eps * offset / angle, while treating
#: the axes as parallel errs by ~angle * offset. The two errors cross at angle ~ sqrt(eps) ~ 1.5e-8,
#: which is the threshold: whichever way an axis pair falls, the error stays below ~1.5e-8 * offset.
#: Treated as parallel, a DH/MDH row also tilts its axis by ~angle (< 1.5e-8 rad): for axes within
#: that band of parallel, DH tables reproduce FK to ~1.5e-8 relative, not to rounding (GJD, PoE and
#: RPY-XYZ are unaffected: they never place a frame from a pair of axes).
ANGLE_TOL = 1.5e-8

#: distance (relative to the robot's scale) below which two axes are treated as meeting. The only
#: effect of meeting is the choice of the sign of x (and, for parallel axes, coincidence), so a
#: tight value near rounding noise of a chain of products (~1e-15 relative) with margin is right.
LENGTH_TOL = 1e-10


class AxisRelation(str, enum.Enum):
    """How joint axis i relates to joint axis i-1 (directions matter: anti- means opposite)."""

    SKEW = "skew"
    PARALLEL = "parallel"
    ANTI_PARALLEL = "anti-parallel"
    COINCIDENT = "coincident"
    ANTI_COINCIDENT = "anti-coincident"
    INTERSECTING = "intersecting"


@dataclass(frozen=True)
class CommonNormal:
    """Closest points of two lines: ``c1`` on line 1, ``c2`` on line 2, parameters t1, t2, distance."""

    c1: np.ndarray
    c2: np.ndarray
    t1: float
    t2: float
    distance: float


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Cross product of two 3-vectors (3,), the same arithmetic as ``np.cross`` without its axis
    handling, which costs ~20x the product itself on 3-vectors (the conversions call it per frame)."""
    a0, a1, a2 = _xyz(a)
    b0, b1, b2 = _xyz(b)
    return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])


def norm(v: np.ndarray) -> float:
    """Euclidean length of a 3-vector, as a Python float."""
    return math.sqrt(float(np.dot(v, v)))


def perpendicular(u: np.ndarray) -> np.ndarray:
    """A unit vector normal to unit u, built from the coordinate axis least aligned with u."""
    k = int(np.argmin(np.abs(u)))
    e = np.zeros(3)
    e[k] = 1.0
    x = e - np.dot(e, u) * u
    return x / norm(x)


def frame_with_z(z: np.ndarray) -> np.ndarray:
    """A rotation (3, 3) whose z column is the direction z (3,) normalised, its x column the base x axis
    made normal to it (the base y axis where z is within ~26 deg of x): the identity for z along +z."""
    z = z / np.linalg.norm(z)
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = helper - (helper @ z) * z
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def point_line_foot(point: np.ndarray, p: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Foot of the perpendicular from ``point`` onto the line (p, u) with unit u."""
    return p + np.dot(point - p, u) * u


def closest_points(p1: np.ndarray, u1: np.ndarray, p2: np.ndarray, u2: np.ndarray) -> CommonNormal:
    """Closest points of two non-parallel lines (unit directions).

    Solves the 2x2 normal equations of min |p1 + t1 u1 - p2 - t2 u2|; the caller guarantees the lines
    are not parallel (sin angle >= ANGLE_TOL), so the determinant 1 - (u1.u2)^2 is >= ANGLE_TOL^2.
    """
    # Re-anchor line 1 at the foot of p2 first. Without this, a p1 far along line 1 (a DH frame placed
    # on the far foot of a previous, nearly parallel pair sits ~offset/sin away) enters the normal
    # equations as dot products of size |p1 - p2|, whose rounding eps |p1 - p2| is divided by sin^2:
    # the feet then slide along the lines by ~eps |p1 - p2| / sin^2, and the x axis through them misses
    # the other line by that times sin. Re-anchored, w is perpendicular to u1 and only as long as the
    # distance of p2 from line 1, so the miss is back to ~eps * offset / sin (see ANGLE_TOL).
    # Scalar arithmetic on Python floats: the inputs are 3-vectors, for which every numpy call costs
    # more than the arithmetic (this runs several times per frame of every conversion).
    (ax, ay, az), (ux, uy, uz) = _xyz(p1), _xyz(u1)
    (bx, by, bz), (vx, vy, vz) = _xyz(p2), _xyz(u2)
    s = (bx - ax) * ux + (by - ay) * uy + (bz - az) * uz
    ax, ay, az = ax + s * ux, ay + s * uy, az + s * uz
    wx, wy, wz = ax - bx, ay - by, az - bz
    b = ux * vx + uy * vy + uz * vz
    d1, d2 = ux * wx + uy * wy + uz * wz, vx * wx + vy * wy + vz * wz
    # |u1 x u2|^2 is computed directly rather than as 1 - b^2 to keep relative accuracy at small angles.
    nx, ny, nz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
    det = nx * nx + ny * ny + nz * nz
    t1 = (b * d2 - d1) / det
    t2 = (d2 - b * d1) / det
    c1 = (ax + t1 * ux, ay + t1 * uy, az + t1 * uz)
    c2 = (bx + t2 * vx, by + t2 * vy, bz + t2 * vz)
    dist = math.sqrt((c2[0] - c1[0]) ** 2 + (c2[1] - c1[1]) ** 2 + (c2[2] - c1[2]) ** 2)
    t1 += s  # back to a parameter along line 1 from the caller's p1
    return CommonNormal(np.array(c1), np.array(c2), t1, t2, dist)


def _xyz(v: np.ndarray) -> list[float]:
    """A 3-vector as three Python floats."""
    return np.asarray(v, dtype=float).tolist()


def common_normal(p1: np.ndarray, u1: np.ndarray, p2: np.ndarray, u2: np.ndarray,
                  *, origin: np.ndarray | None = None) -> CommonNormal:
    """Common normal of two lines. For parallel lines it is the one through ``origin`` (default p1)."""
    if norm(cross(u1, u2)) < ANGLE_TOL:
        start = point_line_foot(p1 if origin is None else origin, p1, u1)
        foot = point_line_foot(start, p2, u2)
        return CommonNormal(start, foot, float(np.dot(start - p1, u1)), float(np.dot(foot - p2, u2)),
                            norm(foot - start))
    return closest_points(p1, u1, p2, u2)


def classify(p1: np.ndarray, u1: np.ndarray, p2: np.ndarray, u2: np.ndarray, scale: float = 1.0
             ) -> AxisRelation:
    """Relation of line 2 to line 1, with the tolerances documented at the top of this module."""
    parallel = norm(cross(u1, u2)) < ANGLE_TOL
    same_sense = np.dot(u1, u2) > 0
    dist = common_normal(p1, u1, p2, u2).distance
    meet = dist <= LENGTH_TOL * max(scale, 1e-300)
    if parallel:
        if meet:
            return AxisRelation.COINCIDENT if same_sense else AxisRelation.ANTI_COINCIDENT
        return AxisRelation.PARALLEL if same_sense else AxisRelation.ANTI_PARALLEL
    return AxisRelation.INTERSECTING if meet else AxisRelation.SKEW
