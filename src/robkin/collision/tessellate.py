"""Primitive shapes as triangle meshes, in their own frame (box, sphere, cylinder, capsule), and the
exact distance from points to triangles: what the primitive fit measures its error with."""

from __future__ import annotations

import numpy as np

__all__ = ["primitive_mesh", "point_triangle_distance", "convex_distance", "surface_samples"]

#: Segments around a round primitive's axis (and latitude bands of a sphere): 32 keeps the chord
#: error below 0.5 % of the radius (1 - cos(pi/32)).
SEGMENTS = 32


def _ring_mesh(profile: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A solid of revolution about z from a profile [(r, z)] from bottom to top, r = 0 at both ends."""
    a = np.linspace(0, 2 * np.pi, SEGMENTS, endpoint=False)
    rings = [(np.zeros((1, 2)) if r == 0 else np.c_[r * np.cos(a), r * np.sin(a)], z) for r, z in profile]
    V, starts = [], []
    for xy, z in rings:
        starts.append(len(V))
        V.extend(np.c_[xy, np.full(len(xy), z)])
    F = []
    for k in range(len(rings) - 1):
        s0, s1 = starts[k], starts[k + 1]
        n0, n1 = len(rings[k][0]), len(rings[k + 1][0])
        for i in range(SEGMENTS):
            j = (i + 1) % SEGMENTS
            if n0 == 1:
                F.append((s0, s1 + i, s1 + j))
            elif n1 == 1:
                F.append((s0 + i, s1, s0 + j))
            else:
                F.append((s0 + i, s1 + i, s1 + j))
                F.append((s0 + i, s1 + j, s0 + j))
    return np.asarray(V, dtype=float), np.asarray(F, dtype=np.int64)[:, ::-1].copy()  # facing outwards


def primitive_mesh(kind: str, size) -> tuple[np.ndarray, np.ndarray]:
    """(V, F) of a primitive in its own frame; sizes as ``robkin.body_parts.Geometry`` gives them (box full
    sides; sphere (r,); cylinder and capsule (r, length) along z, a capsule's length between its caps' centres)."""
    if kind == "box":
        h = np.asarray(size, dtype=float) / 2
        V = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float) * h
        F = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                      [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
        return V, F
    r = float(size[0])
    if kind == "sphere":
        t = np.linspace(np.pi, 0, SEGMENTS // 2 + 1)
        return _ring_mesh([(r * np.sin(x) if 0 < k < len(t) - 1 else 0.0, r * np.cos(x)) for k, x in enumerate(t)])
    half = float(size[1]) / 2
    if kind == "cylinder":
        return _ring_mesh([(0.0, -half), (r, -half), (r, half), (0.0, half)])
    if kind == "capsule":
        t = np.linspace(np.pi, np.pi / 2, SEGMENTS // 4 + 1)
        lower = [(r * np.sin(x) if k else 0.0, -half + r * np.cos(x)) for k, x in enumerate(t)]
        upper = [(rr, -zz) for rr, zz in reversed(lower)]  # the lower cap mirrored
        return _ring_mesh(lower + upper)
    raise ValueError(f"not a primitive: {kind}")


def surface_samples(V: np.ndarray, F: np.ndarray, count: int, seed: int = 0) -> np.ndarray:
    """The vertices and ``count`` points spread over the triangles by area (fixed seed)."""
    tri = V[F]
    area = np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    rng = np.random.default_rng(seed)
    pick = rng.choice(len(F), size=count, p=area / area.sum()) if area.sum() > 0 else rng.integers(0, len(F), count)
    u, v = rng.random((2, count))
    over = u + v > 1
    u[over], v[over] = 1 - u[over], 1 - v[over]
    t = tri[pick]
    return np.vstack([V, t[:, 0] + u[:, None] * (t[:, 1] - t[:, 0]) + v[:, None] * (t[:, 2] - t[:, 0])])


def _pair_distance(p: np.ndarray, A: np.ndarray, B: np.ndarray, C: np.ndarray) -> np.ndarray:
    """Distance from each point p[k] to the triangle (A[k], B[k], C[k]) (Ericson's closest-point regions)."""
    AB, AC = B - A, C - A
    AP, BP, CP = p - A, p - B, p - C
    d1, d2 = (AB * AP).sum(-1), (AC * AP).sum(-1)
    d3, d4 = (AB * BP).sum(-1), (AC * BP).sum(-1)
    d5, d6 = (AB * CP).sum(-1), (AC * CP).sum(-1)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    denom = va + vb + vc
    with np.errstate(divide="ignore", invalid="ignore"):
        v = np.where(denom != 0, vb / denom, 0.0)
        w = np.where(denom != 0, vc / denom, 0.0)
        # edges, then corners: applied in reverse order of precedence, so that the first region wins
        e_bc = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        reg = (va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0)
        v, w = np.where(reg, 1 - e_bc, v), np.where(reg, e_bc, w)
        e_ac = d2 / (d2 - d6)
        reg = (vb <= 0) & (d2 >= 0) & (d6 <= 0)
        v, w = np.where(reg, 0.0, v), np.where(reg, e_ac, w)
        e_ab = d1 / (d1 - d3)
        reg = (vc <= 0) & (d1 >= 0) & (d3 <= 0)
        v, w = np.where(reg, e_ab, v), np.where(reg, 0.0, w)
        reg = (d6 >= 0) & (d5 <= d6)
        v, w = np.where(reg, 0.0, v), np.where(reg, 1.0, w)
        reg = (d3 >= 0) & (d4 <= d3)
        v, w = np.where(reg, 1.0, v), np.where(reg, 0.0, w)
        reg = (d1 <= 0) & (d2 <= 0)
        v, w = np.where(reg, 0.0, v), np.where(reg, 0.0, w)
    closest = A + v[..., None] * AB + w[..., None] * AC
    return np.sqrt(((p - closest) ** 2).sum(-1))


def convex_distance(P: np.ndarray, V: np.ndarray, F: np.ndarray, chunk: int = 512) -> np.ndarray:
    """Distance from each point of ``P`` (k, 3) to the convex polytope (V, F) (closed, outward triangles):
    0 inside, else exactly the distance to its nearest triangle.

    Only triangles that can be nearest are measured: a point outside a convex polytope is nearest to a
    triangle it sees (on the outer side of its plane), and no farther than its nearest vertex, which
    bounds the answer from above; a triangle whose bounding ball lies beyond that bound is skipped."""
    P, V, F = np.asarray(P, dtype=float), np.asarray(V, dtype=float), np.asarray(F)
    tri = V[F]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    length = np.linalg.norm(normal, axis=1)
    ok = length > 0
    tri, normal = tri[ok], normal[ok] / length[ok, None]
    offset = (normal * tri[:, 0]).sum(-1)
    centre = tri.mean(axis=1)
    reach = np.sqrt(((tri - centre[:, None]) ** 2).sum(-1)).max(axis=1)
    out = np.zeros(len(P))
    size = float(np.ptp(V, axis=0).max())
    for s in range(0, len(P), chunk):
        p = P[s:s + chunk]
        plane = p @ normal.T - offset                        # (k, T): > 0 where the triangle is seen
        upper = np.sqrt(((p[:, None, :] - V[None]) ** 2).sum(-1).min(axis=1))
        near = np.sqrt(np.maximum((p * p).sum(-1)[:, None] + (centre * centre).sum(-1)[None]
                                  - 2 * p @ centre.T, 0.0)) <= (upper[:, None] + reach[None] + 1e-9 * size)
        k, t = np.nonzero((plane > 1e-12 * size) & near)
        if len(k) == 0:
            continue                                          # inside or on the surface
        d = _pair_distance(p[k], tri[t, 0], tri[t, 1], tri[t, 2])
        best = upper.copy()
        np.minimum.at(best, k, np.nan_to_num(d, nan=np.inf))
        seen = np.zeros(len(p), dtype=bool)
        seen[k] = True
        out[s:s + chunk] = np.where(seen, best, 0.0)
    return out


def point_triangle_distance(P: np.ndarray, V: np.ndarray, F: np.ndarray, chunk: int = 64) -> np.ndarray:
    """Distance from each point of ``P`` (k, 3) to the nearest triangle of (V, F): every pair measured
    (chunks of ``chunk`` points); ``convex_distance`` is the fast way for a convex polytope."""
    P, V, F = np.asarray(P, dtype=float), np.asarray(V, dtype=float), np.asarray(F)
    A, B, C = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    out = np.empty(len(P))
    for s in range(0, len(P), chunk):
        d = _pair_distance(P[s:s + chunk, None, :], A[None], B[None], C[None])
        out[s:s + chunk] = np.nan_to_num(d, nan=np.inf).min(axis=1)
    return out
