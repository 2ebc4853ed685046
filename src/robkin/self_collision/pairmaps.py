"""Maps of the checked link pairs that one or two revolute joints move against each other.

The relative pose of two links on bodies ``a < b`` of the chain depends only on the joints ``a+1 .. b``.
Where those are one or two revolute joints with finite limits, the pair's answer is a function on a
line or a rectangle of joint values, tabulated once: cells of that box proven apart at every joint
value in them (``PairMap.free``). Where they are three, the last one body b's own: the far link turned
about that joint's axis sweeps a solid of revolution, which a polytope contains (``revolved``); tested
in its place, the pair depends on the first two joints only and is mapped over them
(``PairMap.revolved``), when the solid is not much larger than the link (``GROWTH``: a wrist flange
round its own axis, not an arm swung about its elbow). The 'parts' level looks each query's cell up in its compiled first
pass (``compiled.collision.capsules.overlaps``; ``cleared`` is the same lookup in numpy), before the
convex parts' GJK test (``compiled.collision.parts``); the UR5's upper arm over its
flat base (capsules meet in ~90 % of configurations) and its forearm beside the second wrist link are
such pairs.

A cell is proven by the parts' test at its centre with a margin (every plane leaves at least that gap):
moving each joint j by at most half a cell width ``h_j`` moves any point of the farther link, relative
to the nearer one, by at most ``sum_j h_j * rho_j``, ``rho_j`` bounding the points' distance from joint
j's axis (a chord is no longer than its arc); with the margin that large, the links are apart in the
whole cell (never a false "free"). The cells are refined from ``FIRST`` per joint, halving those not
proven, down to ``CELLS`` per joint (``MAX_TESTS`` cell tests at most per pair).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

#: ``model.SelfCollisionModel`` (not imported: the model imports this module)
SelfCollisionModel = Any

__all__ = ["PairMap", "pair_maps", "cleared", "revolved", "CELLS", "FIRST", "SHARE", "GROWTH"]

#: Cells per joint at the finest level (UR5, limits +-pi: 512 cells, half-width 6 mrad, so the upper arm
#: against its base moves at most ~7 mm within a cell: below its ~16 mm clearance over the base).
CELLS = 512
#: Cells per joint at the coarsest level.
FIRST = 16
#: A pair is mapped when its capsules meet in at least this share of random configurations (below it
#: the parts' test is rarely reached for the pair).
SHARE = 0.05
#: Random configurations that estimate the share.
SAMPLES = 2000
#: Cell tests per pair at most (build time, ~1-5 us each).
MAX_TESTS = 400_000
#: A three-joint pair is mapped when the far link's solid of revolution (its ``revolved`` polytope) has at
#: most this times the volume of the link's own hull: larger, the solid meets the near link in most
#: cells, and the map costs its build for little (UR5: the flange 1.0x, the forearm about its elbow ~20x).
GROWTH = 2.0
#: Sides of the polygon that replaces each point's circle about the axis in ``revolved``: the polygon's
#: corners lie 1/cos(pi/SIDES) - 1 = 2 % farther out than the circle (a 4 cm flange: 0.8 mm).
SIDES = 16
#: Relative slack on the margin: a joint value rounded into a neighbouring cell by floating point is
#: still covered (the rounding is ~1e-16 of the span).
SLACK = 1e-9


@dataclass(frozen=True)
class PairMap:
    """The proven-apart cells of one checked link pair (``model.pairs[pair]``) over its joints."""

    pair: int
    #: indices into q of the one or two joints between the pair's bodies
    joints: tuple[int, ...]
    #: each joint's lower limit and cell width (rad), (k,)
    lower: np.ndarray
    width: np.ndarray
    #: True: apart at every joint value in the cell, (CELLS,) or (CELLS, CELLS)
    free: np.ndarray
    #: the far link was tested as its solid of revolution about the next joint's axis (``revolved``): the
    #: cells hold at every value of that joint too
    revolved: bool = False


def _points(parts: tuple[np.ndarray, ...], link: int) -> np.ndarray:
    """The points (k, 3) of a link's parts, in its body's frame (``SelfCollisionModel._parts``)."""
    V, S, _, _, LS, LP = parts
    return np.vstack([V[S[k]:S[k + 1]] for k in LP[LS[link]:LS[link + 1]]])


def _reach(model: SelfCollisionModel, parts: tuple[np.ndarray, ...], link: int, body: int,
           joints: tuple[int, ...]) -> np.ndarray:
    """rho (k,): bounds on the distance of the link's points from each joint's axis, any configuration."""
    own = float(np.linalg.norm(_points(parts, link), axis=1).max())    # from joint ``body``'s origin, on its axis
    J = model.robot.frames                            # q index i: joint i+1, its frame J[i]; the body's J[body-1]
    # |p - o_j| <= |p - o_body| + the steps between consecutive joints' origins from joint j+1 on: each
    # step's two origins are fixed in one body, whatever the joints between (an axis passes its origin)
    return np.array([own + sum(float(np.linalg.norm(J[i + 1][:3, 3] - J[i][:3, 3])) for i in range(j, body - 1))
                     for j in joints])


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


def _revolved_parts(parts: tuple[np.ndarray, ...], link: int) -> tuple[np.ndarray, ...] | None:
    """``parts`` with the link's parts replaced by one: the polytope around their solid of revolution about
    its body's joint axis (``revolved``; the z axis of the body's frame); None when the link is flat or
    that polytope is more than ``GROWTH`` times the volume of the link's own hull."""
    from ..collision.hull import convex_hull, hull_volume, is_flat
    from .capsules import fit_capsule

    P = _points(parts, link)
    if is_flat(P):
        return None
    R = revolved(P)
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


def _build(model: SelfCollisionModel, parts: tuple[np.ndarray, ...], pair: int, u: int, v: int,
           joints: tuple[int, ...], rho: np.ndarray, revolved: bool) -> PairMap:
    from ..compiled.collision.parts import parts_apart

    robot = model.robot
    k = len(joints)
    lim = robot.limits[list(joints)]
    lower, span = lim[:, 0].copy(), lim[:, 1] - lim[:, 0]
    free = np.zeros((CELLS,) * k, dtype=bool)
    n = FIRST
    cand = np.stack(np.meshgrid(*[np.arange(n)] * k, indexing="ij"), axis=-1).reshape(-1, k)
    offsets = np.stack(np.meshgrid(*[np.arange(2)] * k, indexing="ij"), axis=-1).reshape(-1, k)
    home = robot.home()
    tests = 0
    while len(cand) and tests + len(cand) <= MAX_TESTS:
        width = span / n
        margin = float((width / 2 * rho).sum()) * (1 + SLACK) + SLACK * robot.scale
        Q = np.repeat(home[None], len(cand), axis=0)
        Q[:, list(joints)] = lower + (cand + 0.5) * width
        F = robot.frames_at(Q)
        queries = np.column_stack([np.arange(len(cand)), np.full(len(cand), u), np.full(len(cand), v)]).astype(np.intc)
        ok = parts_apart(F, *parts, queries, 0, margin).view(np.bool_)
        tests += len(cand)
        level = np.zeros((n,) * k, dtype=bool)
        level[tuple(cand[ok].T)] = True
        f = CELLS // n
        for axis in range(k):
            level = np.repeat(level, f, axis=axis)
        free |= level
        if n >= CELLS:
            break
        cand = (cand[~ok][:, None, :] * 2 + offsets[None]).reshape(-1, k)
        n *= 2
    return PairMap(pair, joints, lower, span / CELLS, free, revolved)


def pair_maps(model: SelfCollisionModel, rng: int = 0) -> list[PairMap]:
    """The maps of ``model``'s checked pairs that one or two revolute joints with finite limits move
    against each other, or three whose last turns a far link near round about its axis (``GROWTH``), and
    whose capsules meet in at least ``SHARE`` of random configurations (none without convex parts)."""
    if model._parts is None or not len(model._link_pairs):
        return []
    robot = model.robot
    body = {c.link: c.body for c in model.capsules}
    names = model.links
    share = (model.distances(robot.random_q(SAMPLES, rng=rng)) <= 0.0).mean(axis=0)
    out = []
    for p, (u, v) in enumerate(model._link_pairs):
        lo, hi = sorted((body[names[u]], body[names[v]]))
        joints = tuple(range(lo, hi))                 # joints lo+1 .. hi, as q indices
        if not 1 <= len(joints) <= 3 or share[p] < SHARE or not robot.revolute[list(joints)].all():
            continue
        far = int(u if body[names[u]] == hi else v)
        parts: tuple[np.ndarray, ...] | None = model._parts
        if len(joints) == 3:                          # the far link turned about its own joint: two joints left
            parts = _revolved_parts(model._parts, far)
            joints = joints[:2]
        if parts is None or not np.isfinite(robot.limits[list(joints)]).all():
            continue
        out.append(_build(model, parts, p, int(u), int(v), joints, _reach(model, parts, far, hi, joints),
                          parts is not model._parts))
    return out


def cleared(maps: list[PairMap], q: np.ndarray, rows: np.ndarray, pairs: np.ndarray) -> np.ndarray:
    """bool (Q,): query k (configuration ``q[rows[k]]``, checked pair ``pairs[k]``) lies in a cell its
    pair's map proves apart."""
    out = np.zeros(len(rows), dtype=bool)
    for m in maps:
        sel = np.flatnonzero(pairs == m.pair)
        if not len(sel):
            continue
        x = (q[rows[sel]][:, list(m.joints)] - m.lower) / m.width
        inside = ((x >= 0.0) & (x < CELLS)).all(axis=1)
        idx = np.clip(np.floor(x), 0, CELLS - 1).astype(np.intp)
        out[sel] = inside & m.free[tuple(idx.T)]
    return out
