"""Maps of the checked link pairs that one or two revolute joints move against each other.

The relative pose of two links on bodies ``a < b`` of the chain depends only on the joints ``a+1 .. b``.
Where those are one or two revolute joints with finite limits, the pair's answer is a function on a
line or a rectangle of joint values, tabulated once: cells of that box proven apart at every joint
value in them (``PairMap.free``). The 'parts' level looks each query's cell up in its compiled first
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

__all__ = ["PairMap", "pair_maps", "cleared", "CELLS", "FIRST", "SHARE"]

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


def _reach(model: SelfCollisionModel, link: int, body: int, joints: tuple[int, ...]) -> np.ndarray:
    """rho (k,): bounds on the distance of the link's points from each joint's axis, any configuration."""
    robot = model.robot
    assert model._parts is not None
    V, S, _, _, LS, LP = model._parts
    pts = np.vstack([V[S[k]:S[k + 1]] for k in LP[LS[link]:LS[link + 1]]])
    own = float(np.linalg.norm(pts, axis=1).max())    # from joint ``body``'s origin, on its axis
    J = robot.frames
    rho = []
    for j in joints:                                  # q index j: joint j+1, its frame J[j]
        if j + 1 == body:
            rho.append(own)
        else:                                         # the joint before: its origin and the next's are fixed in one body
            rho.append(own + float(np.linalg.norm(J[body - 1][:3, 3] - J[j][:3, 3])))
    return np.array(rho)


def _build(model: SelfCollisionModel, pair: int, u: int, v: int, joints: tuple[int, ...], rho: np.ndarray) -> PairMap:
    from ..compiled.collision.parts import parts_apart

    robot = model.robot
    assert model._parts is not None
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
        ok = parts_apart(F, *model._parts, queries, 0, margin).view(np.bool_)
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
    return PairMap(pair, joints, lower, span / CELLS, free)


def pair_maps(model: SelfCollisionModel, rng: int = 0) -> list[PairMap]:
    """The maps of ``model``'s checked pairs that one or two revolute joints with finite limits move
    against each other and whose capsules meet in at least ``SHARE`` of random configurations (none
    without convex parts)."""
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
        if not 1 <= len(joints) <= 2 or share[p] < SHARE:
            continue
        if not robot.revolute[list(joints)].all() or not np.isfinite(robot.limits[list(joints)]).all():
            continue
        far = u if body[names[u]] == hi else v
        out.append(_build(model, p, int(u), int(v), joints, _reach(model, far, hi, joints)))
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
