"""One conservative capsule per link: the least-volume capsule (a sphere is a capsule of no length)
enclosing every vertex of the link's collision geometry.

The link's points (``geometry.enclosing_points``: mesh vertices, box corners, round primitives grown
to enclose their tessellation) are reduced to their convex hull; for each candidate axis (the hull's
three principal axes and the three axes of the base frame at q = 0, often the link's own), the points
are projected across the axis, the smallest enclosing circle gives the capsule's axis line and least
radius, and radii from there up to half the points' length along the axis are tried, the segment being
the shortest that keeps every point within the radius. The least volume wins. Every point is then
measured to the chosen segment and the radius set to the largest of those distances plus ``MARGIN``:
the capsule contains the hull, hence the mesh, whatever the rounding of the search (conservative: the
capsule model never says "free" where the meshes touch).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .geometry import LinkGeometry, enclosing_points

__all__ = ["Capsule", "fit_capsule", "link_capsules", "point_segment_distance", "MARGIN"]

#: Added to each fitted radius, relative to the link's size: 1e-9 is far above float64 rounding of the
#: distances (1e-16 relative) and far below any clearance that matters (a nanometre on a 1 m link).
MARGIN = 1e-9
#: Radii tried per axis between the least (the enclosing circle) and half the link's length.
RADII = 48


@dataclass(frozen=True)
class Capsule:
    """A capsule of a link: the segment [a, b] (3,) each, base frame at q = 0) and its radius."""

    link: str
    body: int
    a: np.ndarray
    b: np.ndarray
    radius: float

    @property
    def volume(self) -> float:
        return float(np.pi * self.radius ** 2 * np.linalg.norm(self.b - self.a) + 4 / 3 * np.pi * self.radius ** 3)


def point_segment_distance(P: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distances (k,) from the points P (k, 3) to the segment [a, b]."""
    d = b - a
    dd = float(d @ d)
    t = np.zeros(len(P)) if dd == 0.0 else np.clip((P - a) @ d / dd, 0.0, 1.0)
    return np.linalg.norm(P - (a + t[:, None] * d), axis=1)


def _circle(P2: np.ndarray) -> tuple[np.ndarray, float]:
    """A small enclosing circle (centre, radius) of the 2-D points (Nelder-Mead from the box centre)."""
    from scipy.optimize import minimize

    def radius(c: np.ndarray) -> float:
        return float(np.sqrt(((P2 - c) ** 2).sum(axis=1).max()))

    start = (P2.min(axis=0) + P2.max(axis=0)) / 2
    scale = max(radius(start), 1e-12)
    res = minimize(radius, start, method="Nelder-Mead", options={"xatol": 1e-7 * scale, "fatol": 1e-9 * scale})
    c = res.x if res.fun <= radius(start) else start
    return c, radius(c)


def _frame(z: np.ndarray) -> np.ndarray:
    z = z / np.linalg.norm(z)
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = helper - (helper @ z) * z
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def fit_capsule(P: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """(a, b, radius): a least-volume capsule enclosing the points P (k, 3) (see the module doc)."""
    P = np.asarray(P, dtype=float)
    from ..collision.hull import convex_hull, is_flat, principal_frame

    if not is_flat(P):
        P, _ = convex_hull(P)
    c, R, ext = principal_frame(P)
    size = max(float(ext.max()), 1e-12)
    best: tuple[float, np.ndarray, np.ndarray, float] | None = None
    for axis in [R[:, k] for k in range(3)] + list(np.eye(3)):
        F = _frame(axis)
        local = P @ F
        c2, rho_max = _circle(local[:, :2])
        rho = np.sqrt(((local[:, :2] - c2) ** 2).sum(axis=1))
        t = local[:, 2]
        for r in np.linspace(rho_max, max(rho_max, float(np.ptp(t)) / 2), RADII):
            cap = np.sqrt(np.maximum(r * r - rho * rho, 0.0))
            top, bottom = float((t - cap).max()), float((t + cap).min())
            lo, hi = (bottom, top) if top > bottom else ((top + bottom) / 2,) * 2
            volume = np.pi * r * r * (hi - lo) + 4 / 3 * np.pi * r ** 3
            if best is None or volume < best[0]:
                best = (volume, F @ np.array([c2[0], c2[1], lo]), F @ np.array([c2[0], c2[1], hi]), float(r))
    assert best is not None
    _, a, b, _ = best
    radius = float(point_segment_distance(P, a, b).max()) + MARGIN * size  # encloses every point, exactly
    return a, b, radius


def link_capsules(links: list[LinkGeometry]) -> list[Capsule]:
    """One capsule per link (see the module doc), in the order of ``links``."""
    out = []
    for g in links:
        P = np.vstack([enclosing_points(s) for s in g.shapes])
        a, b, r = fit_capsule(P)
        out.append(Capsule(g.name, g.body, a, b, r))
    return out
