"""Links turned about a joint's axis: a polytope around the solid they sweep (for ``pairmaps``).

A link turned about an axis, whatever the angle, stays inside the solid of revolution of its points.
Where a pair map's test takes that solid in the link's place, the joint that turns it drops out of the
pair's relative pose: the far link of a pair turned about its own joint's axis, or the near link about
the axis of the first joint after it (a round base under an arm's shoulder joint), leave the map one
joint fewer (``pairmaps``).
"""

from __future__ import annotations

import numpy as np

__all__ = ["revolved", "revolved_parts", "axis_frame", "PartArrays", "GROWTH", "SIDES"]

#: A model's convex parts as ``parts_apart`` takes them (``SelfCollisionModel._parts``): the points, each
#: part's first row, frame and bounding capsule, each link's first part and the parts of the links in turn.
PartArrays = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]

#: A link is turned in a map's test only when its ``revolved`` polytope has at most this times the
#: volume of the link's own hull: larger, the solid meets the other link in most cells, and the map
#: costs its build for little (UR5: the flange 1.2x, base and wrists 1.6-1.8x, the forearm about its
#: elbow ~16x).
GROWTH = 2.0
#: Sides of the polygon that replaces each point's circle about the axis in ``revolved``: the polygon's
#: corners lie 1/cos(pi/SIDES) - 1 = 2 % farther out than the circle (a 4 cm flange: 0.8 mm).
SIDES = 16


def revolved(P: np.ndarray, sides: int = SIDES) -> np.ndarray:
    """The vertices (m, 3) of a polytope containing the solid that the points P (k, 3) sweep turning about
    the z axis: each point's circle (radius r about the axis, at its height) replaced by the regular
    polygon around it (corners at r / cos(pi / sides): the polygon's sides touch the circle), and the
    convex hull of them all (it contains the hull of the circles, which contains every turned copy of
    the points' hull)."""
    from ..collision.hull import convex_hull

    r = np.hypot(P[:, 0], P[:, 1]) / np.cos(np.pi / sides)
    t = 2 * np.pi * np.arange(sides) / sides
    ring = np.column_stack([(r[:, None] * np.cos(t)).ravel(), (r[:, None] * np.sin(t)).ravel(),
                            np.repeat(P[:, 2], sides)])
    return convex_hull(ring)[0]


def axis_frame(frames: list[np.ndarray], body: int, joint: int) -> np.ndarray:
    """(4, 4): joint ``joint``'s frame (its z axis the joint's axis, its origin on it) in the coordinates of
    body ``body``'s frame (body 0: the base), both at q = 0; ``frames`` is ``Robot.frames`` (frame i of
    joint i+1). The joint is the body's own (``joint == body``: the identity) or the next one."""
    own = np.eye(4) if body == 0 else frames[body - 1]
    return np.linalg.solve(own, frames[joint - 1])


def _points(parts: PartArrays, link: int) -> np.ndarray:
    """The points (k, 3) of a link's parts, in its body's frame (``SelfCollisionModel._parts``)."""
    V, S, _, _, LS, LP = parts
    return np.vstack([V[S[k]:S[k + 1]] for k in LP[LS[link]:LS[link + 1]]])


def revolved_parts(parts: PartArrays, link: int, axis: np.ndarray) -> PartArrays | None:
    """``parts`` (``SelfCollisionModel._parts``) with the link's parts replaced by one: the polytope
    around their solid of revolution about the z axis of ``axis`` (4, 4; in the link's body frame,
    ``axis_frame``); None when the link is flat or that polytope has more than ``GROWTH`` times the
    volume of the link's own hull."""
    from ..collision.hull import convex_hull, hull_volume, is_flat
    from .capsules import fit_capsule

    P = _points(parts, link)
    if is_flat(P):
        return None
    R0, p0 = axis[:3, :3], axis[:3, 3]
    R = revolved((P - p0) @ R0) @ R0.T + p0
    if hull_volume(*convex_hull(R)) > GROWTH * hull_volume(*convex_hull(P)):
        return None
    V, S, K, B, LS, LP = parts
    a, b, radius = fit_capsule(R)
    lists = [list(LP[LS[m]:LS[m + 1]]) for m in range(len(LS) - 1)]
    lists[link] = [len(K)]                            # the new part, after the others
    return (np.vstack([V, R]), np.append(S, S[-1] + len(R)).astype(np.intp),
            np.append(K, K[LP[LS[link]]]).astype(np.intc), np.vstack([B, [*a, *b, radius]]),
            np.concatenate([[0], np.cumsum([len(x) for x in lists])]).astype(np.intp),
            np.array([k for x in lists for k in x], dtype=np.intc))
