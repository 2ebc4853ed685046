"""Convex hulls of point sets (SciPy's Qhull), and the test for a flat one.

MuJoCo collides every mesh geom through its convex hull; ``--collision hull`` writes that hull as a
mesh file of its own (a few hundred triangles instead of the source's thousands). A hull whose
thinnest extent is below ``FLAT`` times its largest (a decal, a plane of a visual mesh used for
collision) has no volume: MuJoCo refuses such a mesh ("coplanar vertices, cannot compute convex hull"),
so it is replaced by a thin box (``flat_box``) instead, as MuJoCo itself suggests.
"""

from __future__ import annotations

import numpy as np

__all__ = ["convex_hull", "hull_volume", "principal_frame", "is_flat", "flat_box", "FLAT"]

#: Thinnest / largest extent (along the principal axes) below which a point set is flat. 1e-6 is far
#: above the rounding of float32 STL coordinates (1e-7 relative) and far below any real part's thickness.
FLAT = 1e-6
#: The thickness given to the box that stands for a flat mesh, relative to its largest extent
#: (a sheet 1 mm thick on a 1 m part).
FLAT_THICKNESS = 1e-3


def principal_frame(P: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(centre, axes (3, 3) as columns, extents (3,)) of the box around ``P`` (k, 3) along its principal
    axes (right-handed; the centre is the box's, not the mean)."""
    mean = P.mean(axis=0)
    _, _, vt = np.linalg.svd(P - mean, full_matrices=False) if len(P) >= 3 else (None, None, np.eye(3))
    R = vt.T if vt.shape == (3, 3) else np.eye(3)
    if np.linalg.det(R) < 0:
        R[:, 2] = -R[:, 2]
    local = (P - mean) @ R
    lo, hi = local.min(axis=0), local.max(axis=0)
    return mean + R @ ((lo + hi) / 2), R, hi - lo


def is_flat(P: np.ndarray) -> bool:
    """Whether the points span no volume (see ``FLAT``)."""
    if len(P) < 4:
        return True
    _, _, ext = principal_frame(P)
    return bool(ext.min() <= FLAT * max(ext.max(), 1e-300))


def flat_box(P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(pose (4, 4), full sizes (3,)) of a thin box covering the flat point set ``P``."""
    c, R, ext = principal_frame(P)
    ext = np.maximum(ext, FLAT_THICKNESS * max(ext.max(), 1e-9))
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, c
    return T, ext


def convex_hull(P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(V, F) of the convex hull of ``P`` (k, 3): only the hull's vertices, triangles facing outwards.
    ValueError for a flat point set (``is_flat``)."""
    from scipy.spatial import ConvexHull, QhullError

    P = np.asarray(P, dtype=np.float64)
    if is_flat(P):
        raise ValueError("flat: the points span no volume")
    try:
        h = ConvexHull(P)
    except QhullError as exc:  # pragma: no cover - is_flat catches what Qhull refuses
        raise ValueError(f"no convex hull ({str(exc).splitlines()[0][:60]})") from None
    used = np.unique(h.simplices)
    index = np.full(len(P), -1)
    index[used] = np.arange(len(used))
    V, F = P[used], index[h.simplices]
    # Qhull's simplices are not consistently oriented: each made to face away from the hull's inside
    inside = V.mean(axis=0)
    tri = V[F]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    flip = np.einsum("ij,ij->i", normal, tri[:, 0] - inside) < 0
    F[flip] = F[flip][:, ::-1]
    return V, F


def hull_volume(V: np.ndarray, F: np.ndarray) -> float:
    """Volume enclosed by the closed, outward-facing triangles (V, F) (divergence theorem)."""
    tri = V[F]
    return float(np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum() / 6.0)
