"""A body's mass properties as an MJCF ``<inertial>``: exact where MuJoCo can load them, repaired
(and said so) where it cannot.

The inertia is written as principal moments (``diaginertia``) in a frame (``pos`` + ``quat``) relative
to the body: the source's own inertial frame when the tensor is diagonal in it (then the numbers are
the source's), else its eigenvectors (``numpy.linalg.eigh``: the tensor comes back to ~1e-16 of its
largest moment). Several inertials on one body (fused fixed links, a table's bodies) are merged
exactly first (``robkin.dynamics.merge_masses``: parallel-axis theorem).

MuJoCo refuses principal moments that are negative or break the triangle inequality (A + B >= C),
and a moving body whose mass or inertia, with everything welded to it, is below 1e-15. Such values
are repaired here, and the writer warns once naming the bodies:
* a negative moment becomes 0; a largest moment above the sum of the others becomes that sum;
* a moving body with nothing massive welded to it gets ``PLACEHOLDER_MASS`` and ``PLACEHOLDER_INERTIA``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Sequence

import numpy as np

from ... import se3
from ..files.float_text import float_text as _num

if TYPE_CHECKING:  # pragma: no cover
    from ...body_parts import Inertial

__all__ = ["BodyMass", "body_mass", "inertial_xml", "PLACEHOLDER_MASS", "PLACEHOLDER_INERTIA"]

#: Mass (kg) and principal moments (kg m^2) given to a moving body that has none, so that MuJoCo
#: (which needs > 1e-15 of each) loads the model: small enough that M(q) and g(q) of a robot of
#: ~0.1 kg and up change by < 1e-8 of their largest entry.
PLACEHOLDER_MASS = 1e-9
PLACEHOLDER_INERTIA = 1e-12
#: Principal moments within this of valid (relative to the largest) are rounding of the eigen
#: decomposition or of the source's printed digits: made valid silently.
ROUNDING = 1e-12


class BodyMass:
    """Mass properties of one body: mass (kg), centre (3,) and inertia (3, 3) about it, base frame."""

    def __init__(self, mass: float, com: np.ndarray, inertia: np.ndarray, frame: np.ndarray | None = None,
                 diag: np.ndarray | None = None, origin: tuple[float, ...] | None = None):
        self.mass, self.com, self.inertia = mass, com, inertia
        #: the source's six origin numbers (xyz, rpy) of the inertial frame in its link, if one inertial
        self.origin = origin
        #: a frame (4, 4, base frame) in which the inertia is diagonal with moments ``diag``, if known exactly
        self.frame, self.diag = frame, diag


def body_mass(inertials: Sequence[Inertial]) -> BodyMass | None:
    """The merged mass properties of a body's inertials (None when it has none)."""
    inertials = [m for m in inertials if m.mass != 0 or np.any(m.inertia)]  # mass 0, inertia 0: nothing
    if not inertials:
        return None
    if len(inertials) == 1:
        m = inertials[0]
        R = m.pose[:3, :3]
        I = np.asarray(m.inertia, dtype=float)
        diag = np.diag(I).copy() if not np.any(I - np.diag(np.diag(I))) else None
        return BodyMass(float(m.mass), m.pose[:3, 3].copy(), R @ I @ R.T, m.pose if diag is not None else None, diag,
                        m.origin)
    from ...mass_properties import merge_masses

    mass = np.array([m.mass for m in inertials], dtype=float)
    com = np.stack([m.pose[:3, 3] for m in inertials])
    inertia = np.stack([m.pose[:3, :3] @ m.inertia @ m.pose[:3, :3].T for m in inertials])
    total, c, I = merge_masses(mass, com, inertia)
    return BodyMass(float(total), np.asarray(c, dtype=float), np.asarray(I, dtype=float))


def _principal(bm: BodyMass) -> tuple[np.ndarray, np.ndarray]:
    """(rotation (3, 3) of the principal axes in the base frame, moments (3,))."""
    if bm.frame is not None and bm.diag is not None:
        return bm.frame[:3, :3], bm.diag
    w, V = np.linalg.eigh((bm.inertia + bm.inertia.T) / 2)
    if np.linalg.det(V) < 0:
        V[:, 0] = -V[:, 0]
    return V, w


def valid_moments(w: np.ndarray) -> tuple[np.ndarray, bool]:
    """(moments MuJoCo accepts, whether they were changed beyond rounding)."""
    w = np.array(w, dtype=float)
    big = float(np.abs(w).max()) if w.size else 0.0
    changed = bool((w < -ROUNDING * big).any())
    w = np.maximum(w, 0.0)
    k = int(np.argmax(w))
    a, b = (w[i] for i in range(3) if i != k)
    if w[k] > a + b:  # a + b exactly as MuJoCo adds them, so that its check A + B >= C passes
        changed = changed or w[k] - (a + b) > ROUNDING * big
        w[k] = a + b
    return w, changed


def inertial_xml(bm: BodyMass, body_frame: np.ndarray, scale: float = 1.0) -> tuple[str, bool]:
    """(the ``<inertial .../>`` element relative to a body at ``body_frame`` (4, 4), whether the
    moments had to be repaired)."""
    from .format import NOISE, SAME_ORIGIN_TOL, quat_from_matrix

    R, w = _principal(bm)
    w, changed = valid_moments(w)
    inv = se3.inv(body_frame)
    pos = inv[:3, :3] @ bm.com + inv[:3, 3]
    if bm.origin is not None and np.abs(np.asarray(bm.origin[:3]) - pos).max() <= SAME_ORIGIN_TOL * scale:
        pos = np.array(bm.origin[:3], dtype=float)  # the source's numbers, where they still hold
    pos[np.abs(pos) < NOISE * scale] = 0.0
    Rl = body_frame[:3, :3].T @ R
    q = quat_from_matrix(Rl)
    q[np.abs(q) < NOISE] = 0.0
    quat = "" if (q[1:] == 0).all() else f' quat="{" ".join(_num(v) for v in q)}"'
    return (f'<inertial pos="{" ".join(_num(v) for v in pos)}"{quat} mass="{_num(bm.mass)}" '
            f'diaginertia="{" ".join(_num(v) for v in w)}"/>', changed)
