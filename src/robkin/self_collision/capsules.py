"""Conservative capsules per link: the least-volume capsule (a sphere is a capsule of no length)
enclosing every vertex of the link's collision geometry, cut into up to ``MAX_PER_LINK`` capsules where
that makes them much tighter.

The link's points (mesh vertices, box corners, round primitives' tessellations grown to enclose them:
``geometry.enclosing_triangles``) are reduced to their convex hull. A capsule of a point set: for each
candidate axis (the hull's three principal axes and the base frame's three axes at q = 0, often the
link's own), the points are projected across the axis, an enclosing circle (``_circle``) gives the
capsule's axis line and least radius, and radii from there up to half the points' length along the
axis are tried, the segment being the shortest that keeps every point within the radius; the least
volume wins. Every point is then measured to the chosen segment and the radius set to the largest of
those distances plus ``MARGIN``: the capsule contains the points' hull whatever the rounding of the
search.

Cuts: the link's surface triangles (``geometry.enclosing_triangles``) are clipped by a plane through
their box centre across one of their principal axes; each side's solid lies in the convex hull of that
side's triangles (its boundary is those triangles and the cut face, whose edge lies on them), so the
two sides' capsules together contain the link, concave links included. A cut is taken (the best of
every part and axis) while it shrinks the volume of the union of the link's capsules (a Monte Carlo
estimate) by at least ``SPLIT_GAIN``: a flat disc (the UR5's base) becomes strips, an elbow two
capsules (conservative: the model never says "free" where the meshes touch).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..lines import frame_with_z
from .geometry import LinkGeometry, enclosing_triangles

__all__ = ["Capsule", "Part", "fit_capsule", "link_capsules", "link_parts", "point_segment_distance", "MARGIN"]

#: Added to each fitted radius, relative to the link's size: 1e-9 is far above float64 rounding of the
#: distances (1e-16 relative) and far below any clearance that matters (a nanometre on a 1 m link).
MARGIN = 1e-9
#: Radii tried per axis between the least (the enclosing circle) and half the link's length.
RADII = 48
#: Most capsules per link, and the least share of the link's capsule volume a cut into two must save
#: (15 %: a long straight link stays one capsule; a flat disc or an L-shaped link is cut).
MAX_PER_LINK = 4
#: Steps of the enclosing-circle iteration (its radius is within ~1/sqrt(steps) of the least; the best
#: centre seen is kept).
CIRCLE_STEPS = 100
SPLIT_GAIN = 0.15
#: Halvings of a link into convex parts for the test between capsules and coal (8 parts: a tube
#: between two housings, the UR5's upper arm, gets thin middle parts).
PART_DEPTH = 3
#: Points of the Monte Carlo estimate of a link's capsule volume (its error, ~1 % of the volume, is well
#: below SPLIT_GAIN).
VOLUME_POINTS = 20000


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


@dataclass(frozen=True)
class Part:
    """A convex part of a link: its hull's vertices (k, 3) and a capsule [a, b], radius around them (base
    frame at q = 0)."""

    link: str
    body: int
    vertices: np.ndarray
    a: np.ndarray
    b: np.ndarray
    radius: float


def point_segment_distance(P: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distances (k,) from the points P (k, 3) to the segment [a, b]."""
    d = b - a
    dd = float(d @ d)
    t = np.zeros(len(P)) if dd == 0.0 else np.clip((P - a) @ d / dd, 0.0, 1.0)
    return np.linalg.norm(P - (a + t[:, None] * d), axis=1)


def _circle(P2: np.ndarray) -> tuple[np.ndarray, float]:
    """A small enclosing circle (centre, radius) of the 2-D points: Badoiu and Clarkson's iteration (the
    centre steps towards the farthest point by 1/(k+1)), from the box centre. Near the least circle; the
    capsule's radius is measured exactly afterwards, so its rounding never matters for containment."""
    c = (P2.min(axis=0) + P2.max(axis=0)) / 2
    best = (float(np.sqrt(((P2 - c) ** 2).sum(axis=1).max())), c)
    for k in range(1, CIRCLE_STEPS + 1):
        d = ((P2 - c) ** 2).sum(axis=1)
        far = int(np.argmax(d))
        if np.sqrt(d[far]) < best[0]:
            best = (float(np.sqrt(d[far])), c)
        c = c + (P2[far] - c) / (k + 1)
    return best[1], best[0]


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
        F = frame_with_z(axis)
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


def _capsule_volume(a: np.ndarray, b: np.ndarray, r: float) -> float:
    return float(np.pi * r * r * np.linalg.norm(b - a) + 4 / 3 * np.pi * r ** 3)


def _clip(T: np.ndarray, s: np.ndarray) -> np.ndarray:
    """The parts of the triangles T (m, 3, 3) where ``s`` (m, 3: the vertices' signed distances to a
    plane) is <= 0, as triangles: a triangle with one vertex there becomes one, with two a quad (two)."""
    inside = s <= 0.0
    count = inside.sum(axis=1)
    out = [T[count == 3]]
    for lone_inside, pick in ((True, count == 1), (False, count == 2)):
        if not pick.any():
            continue
        Tk, sk, ik = T[pick], s[pick], inside[pick]
        first = np.argmax(ik if lone_inside else ~ik, axis=1)       # the vertex on its own side
        order = (first[:, None] + np.arange(3)) % 3
        P = np.take_along_axis(Tk, order[:, :, None], axis=1)
        d = np.take_along_axis(sk, order, axis=1)
        X1 = P[:, 0] + (d[:, 0] / (d[:, 0] - d[:, 1]))[:, None] * (P[:, 1] - P[:, 0])
        X2 = P[:, 0] + (d[:, 0] / (d[:, 0] - d[:, 2]))[:, None] * (P[:, 2] - P[:, 0])
        if lone_inside:
            out.append(np.stack([P[:, 0], X1, X2], axis=1))
        else:
            out.append(np.stack([P[:, 1], P[:, 2], X2], axis=1))
            out.append(np.stack([P[:, 1], X2, X1], axis=1))
    return np.concatenate(out)


def _halves(T: np.ndarray, axis: np.ndarray, c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The triangles T (m, 3, 3) cut by the plane through ``c`` across ``axis``: each side's parts. The
    solid they bound is cut the same way, and each side's part of it lies in the convex hull of that
    side's triangles (its boundary: those triangles and the cut face, whose edge is on them)."""
    s = (T - c) @ axis
    return _clip(T, s), _clip(T, -s)


class _Piece:
    """A part of a link (its surface triangles) and the capsule fitted to them; its cuts on demand."""

    def __init__(self, T: np.ndarray) -> None:
        from ..collision.hull import is_flat

        self.T = T
        self.P = np.unique(T.reshape(-1, 3), axis=0)
        self.flat = is_flat(self.P)
        self.a, self.b, self.r = fit_capsule(self.P)
        self.volume = _capsule_volume(self.a, self.b, self.r)
        self._cuts: list[list[_Piece]] | None = None

    def cuts(self) -> list[list[_Piece]]:
        """This piece cut in two across each of its principal axes through its box centre (none for a flat
        or tiny piece)."""
        if self.flat or len(self.P) < 8:
            return []
        if self._cuts is None:
            from ..collision.hull import principal_frame

            c, R, _ = principal_frame(self.P)
            self._cuts = []
            for k in range(3):
                A, B = _halves(self.T, R[:, k], c)
                if len(A) and len(B):
                    self._cuts.append([_Piece(A), _Piece(B)])
        return self._cuts


def _union_volume(pieces: list[_Piece], X: np.ndarray, box: float) -> float:
    """Monte Carlo volume of the union of the pieces' capsules: the share of the points X (uniform in a
    box of volume ``box``) inside one of them."""
    inside = np.zeros(len(X), dtype=bool)
    for p in pieces:
        inside |= point_segment_distance(X, p.a, p.b) <= p.r
    return box * float(inside.mean())


def link_capsules(links: list[LinkGeometry], max_per_link: int = MAX_PER_LINK) -> list[Capsule]:
    """Capsules of each link (see the module doc), in the order of ``links``: a link's hull is cut in two
    (one of its parts, across one of that part's principal axes) while a cut shrinks the volume of the
    union of the link's capsules by at least ``SPLIT_GAIN``, up to ``max_per_link`` capsules."""
    out = []
    rng = np.random.default_rng(0)   # the volume estimate's points: the same capsules on every run
    for g in links:
        pieces = [_Piece(np.concatenate([enclosing_triangles(s) for s in g.shapes]))]
        p0 = pieces[0]
        lo = np.minimum(p0.a, p0.b) - 1.2 * p0.r
        hi = np.maximum(p0.a, p0.b) + 1.2 * p0.r
        X = lo + (hi - lo) * rng.random((VOLUME_POINTS, 3))
        box = float(np.prod(hi - lo))
        current = _union_volume(pieces, X, box)
        while len(pieces) < max_per_link:
            best = None
            for k, p in enumerate(pieces):
                for parts in p.cuts():
                    if len(pieces) + len(parts) - 1 > max_per_link:
                        continue
                    v = _union_volume(pieces[:k] + parts + pieces[k + 1:], X, box)
                    # the share of the volume saved per capsule added
                    gain = (current - v) / current / (len(parts) - 1)
                    if best is None or gain > best[0]:
                        best = (gain, v, k, parts)
            if best is None or best[0] < SPLIT_GAIN:
                break
            _, current, k, parts = best
            pieces[k:k + 1] = parts
        out += [Capsule(g.name, g.body, p.a, p.b, p.r) for p in pieces]
    return out


def link_parts(links: list[LinkGeometry], depth: int = PART_DEPTH) -> list[Part]:
    """Convex parts of each link: its surface triangles halved across their longest principal axis,
    ``depth`` times (up to 2**depth parts), each part the vertices (k, 3) of its convex hull (base frame
    at q = 0) and a capsule around them; a link's parts consecutive. Together they contain the link (see
    ``_halves``): the finer, tighter test ``SelfCollisionModel.collides(exact=True)`` runs before coal."""
    from ..collision.hull import convex_hull, is_flat, principal_frame

    def split(T: np.ndarray, level: int) -> list[np.ndarray]:
        P = np.unique(T.reshape(-1, 3), axis=0)
        flat = is_flat(P)
        if level == 0 or flat or len(P) < 8:
            return [P if flat else convex_hull(P)[0]]
        c, R, ext = principal_frame(P)
        A, B = _halves(T, R[:, int(np.argmax(ext))], c)
        if not len(A) or not len(B):
            return [convex_hull(P)[0]]
        return split(A, level - 1) + split(B, level - 1)

    out = []
    for g in links:
        T = np.concatenate([enclosing_triangles(s) for s in g.shapes])
        for V in split(T, depth):
            a, b, r = fit_capsule(V)
            out.append(Part(g.name, g.body, V, a, b, r))
    return out
