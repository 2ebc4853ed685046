"""One fitted primitive per link (``--collision primitives``), and how well it fits.

The link's collision geometry (its meshes' convex hulls, which is what MuJoCo collides, and its
primitives) is enclosed by each of four candidates, and the one of least volume is kept:

* sphere: the smallest enclosing sphere (centre refined by Nelder-Mead from the box centre);
* box: around the hull along its principal axes, or along the link frame's axes when smaller;
* cylinder and capsule: along each of those six axes, the smallest enclosing circle of the points
  projected across the axis; a capsule's radius is searched between that circle's and the point set's
  half length, its segment then the shortest that encloses every point.

Each candidate encloses every vertex of the hulls, so it contains the link's collision geometry
(round primitives to the tessellation's 0.5 %, see ``tessellate``). The fit is reported per link
(``FitReport``): the volume error (primitive volume / volume of the convex hull of the whole link,
minus 1: how much empty space the primitive adds) and the one-sided Hausdorff distance from the
primitive to the link's geometry (the largest distance from a point of the primitive's surface to
the nearest point of a hull: how far the primitive reaches beyond the link), sampled at
``HAUSDORFF_SAMPLES`` points and the primitive's vertices, each measured exactly to the triangles.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..lines import frame_with_z
from .hull import convex_hull, hull_volume, is_flat, principal_frame
from .tessellate import convex_distance, primitive_mesh, surface_samples

__all__ = ["Primitive", "FitReport", "fit_primitive", "fit_report", "primitive_volume"]

#: Points on a primitive's surface where the distance to the link is measured (plus its vertices).
HAUSDORFF_SAMPLES = 2000
#: Smallest size of a fitted primitive relative to the link's (MuJoCo refuses a zero size; a flat link
#: gets a box this thin).
THIN = 1e-3


@dataclass(frozen=True)
class Primitive:
    """kind ('box' | 'sphere' | 'cylinder' | 'capsule'), size as ``Geometry.size``, pose (4, 4)."""

    kind: str
    size: tuple[float, ...]
    pose: np.ndarray


@dataclass(frozen=True)
class FitReport:
    """How a link's primitive fits: its kind, volumes (primitive, link hull), relative volume error,
    one-sided Hausdorff distance (robot length unit)."""

    link: str
    kind: str
    volume: float
    hull_volume: float
    volume_error: float
    hausdorff: float


def primitive_volume(kind: str, size) -> float:
    if kind == "box":
        return float(np.prod(size))
    r = float(size[0])
    if kind == "sphere":
        return 4 / 3 * np.pi * r ** 3
    if kind == "cylinder":
        return np.pi * r * r * float(size[1])
    return np.pi * r * r * float(size[1]) + 4 / 3 * np.pi * r ** 3


def _frame(R: np.ndarray, c: np.ndarray) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, c
    return T


def _enclosing_center(P: np.ndarray, start: np.ndarray) -> tuple[np.ndarray, float]:
    """Centre and radius of a small enclosing ball (circle in 2-D) of ``P``, from ``start``."""
    from scipy.optimize import minimize

    def radius(c: np.ndarray) -> float:
        return float(np.sqrt(((P - c) ** 2).sum(axis=1).max()))

    scale = max(radius(start), 1e-12)
    res = minimize(lambda c: radius(c), start, method="Nelder-Mead",
                   options={"xatol": 1e-7 * scale, "fatol": 1e-9 * scale, "maxiter": 400 * len(start)})
    c = res.x if res.fun <= radius(start) else start
    return c, radius(c)


def _round_candidates(P: np.ndarray, axes: list[np.ndarray]) -> list[Primitive]:
    out = []
    floor = THIN * float(np.ptp(P, axis=0).max())
    for a in axes:
        R = frame_with_z(a)
        local = P @ R
        t = local[:, 2]
        box_c = (local[:, :2].min(axis=0) + local[:, :2].max(axis=0)) / 2
        c2, rho_max = _enclosing_center(local[:, :2], box_c)
        rho = np.sqrt(((local[:, :2] - c2) ** 2).sum(axis=1))
        mid = (t.min() + t.max()) / 2
        centre = R @ np.array([c2[0], c2[1], mid])
        out.append(Primitive("cylinder", (max(rho_max, floor), max(float(t.max() - t.min()), floor)), _frame(R, centre)))
        best = None
        for r in np.linspace(rho_max, max(rho_max, (t.max() - t.min()) / 2) + 1e-12, 48):
            cap = np.sqrt(np.maximum(r * r - rho * rho, 0.0))
            top, bottom = float((t - cap).max()), float((t + cap).min())
            length = max(top - bottom, 0.0)
            v = primitive_volume("capsule", (r, length))
            if best is None or v < best[0]:
                best = (v, r, length, (top + bottom) / 2)
        _, r, length, tc = best
        if length > THIN * max(r, 1e-300):  # a capsule of no length is the sphere candidate's business
            out.append(Primitive("capsule", (float(r), float(length)), _frame(R, R @ np.array([c2[0], c2[1], tc]))))
    return out


def fit_primitive(P: np.ndarray, link_axes: np.ndarray | None = None) -> Primitive:
    """The least-volume primitive enclosing the points ``P`` (k, 3) (see the module doc); ``link_axes``
    (3, 3): the link frame's axes as columns, tried besides the principal ones."""
    P = np.asarray(P, dtype=float)
    if not is_flat(P):
        V, _ = convex_hull(P)
        P = V  # enclosing the hull's vertices encloses everything
    c, R, ext = principal_frame(P)
    floor = THIN * max(float(ext.max()), 1e-300)
    cands = [Primitive("box", tuple(float(x) for x in np.maximum(ext, floor)), _frame(R, c))]
    axes = [R[:, k] for k in range(3)]
    if link_axes is not None:
        L = np.asarray(link_axes, dtype=float)
        local = P @ L
        lo, hi = local.min(axis=0), local.max(axis=0)
        cands.append(Primitive("box", tuple(float(x) for x in np.maximum(hi - lo, floor)), _frame(L, L @ ((lo + hi) / 2))))
        axes += [L[:, k] for k in range(3)]
    centre, radius = _enclosing_center(P, c)
    cands.append(Primitive("sphere", (radius,), _frame(np.eye(3), centre)))
    cands += _round_candidates(P, axes)
    return min(cands, key=lambda p: primitive_volume(p.kind, p.size))


def fit_report(link: str, prim: Primitive, hulls: list[tuple[np.ndarray, np.ndarray]]) -> FitReport:
    """The fit of ``prim`` to the link whose geometry is the union of ``hulls`` [(V, F)] (base frame)."""
    allV = np.vstack([v for v, _ in hulls])
    try:
        hv, hf = convex_hull(allV)
        ref = hull_volume(hv, hf)
    except ValueError:  # a flat link: no volume to compare with
        ref = 0.0
    vol = primitive_volume(prim.kind, prim.size)
    V, F = primitive_mesh(prim.kind, prim.size)
    samples = surface_samples(V, F, HAUSDORFF_SAMPLES) @ prim.pose[:3, :3].T + prim.pose[:3, 3]
    # the primitive encloses every hull, so its surface lies outside each of them (convex_distance)
    h = float(np.min([convex_distance(samples, v, f) for v, f in hulls], axis=0).max())
    return FitReport(link, prim.kind, vol, ref, vol / ref - 1.0 if ref > 0 else float("inf"), h)
