"""Maps of the checked link pairs that one or two revolute joints move against each other.

The relative pose of two links on bodies ``a < b`` of the chain depends only on the joints ``a+1 .. b``.
Where those are one or two revolute joints with finite limits, the pair's answer is a function on a
line or a rectangle of joint values, tabulated once: cells of that box proven apart at every joint
value in them (``PairMap.bits``, one bit a cell). A joint can also be taken out (``revolve``): the far link turned about
its own joint's axis, or the near link about the first joint's after it, sweeps a solid of revolution
that a polytope contains; with that polytope in the link's place the pair no longer depends on the
joint. Such a map covers three joints with two (the UR5's flange beside its forearm, turned about wrist
3; its base beside the forearm, turned about the shoulder pan) or four (its base and wrist 1, both
turned), or a two-joint pair with one, at a far finer cell. Of the ways to map a pair, the one proving
most of its joint box apart is kept (the UR5's upper arm over its base keeps its two-joint map: 95 %
proven, the base turned only 66 %, its cable outlet sweeping a ring). The 'parts' level looks
each query's cell up in its compiled first pass (``compiled.collision.capsules.overlaps``; ``cleared``
is the same lookup in numpy), before the convex parts' GJK test (``compiled.collision.parts``).

A cell is proven by the parts' test at its centre with a margin (every plane leaves at least that gap):
moving each joint j by at most half a cell width ``h_j`` moves any point of the farther link, relative
to the nearer one, by at most ``sum_j h_j * rho_j``, ``rho_j`` bounding the points' distance from joint
j's axis (a chord is no longer than its arc); with the margin that large, the links are apart in the
whole cell (never a false "free"). The cells are refined from ``FIRST`` per joint, halving those not
proven, down to ``CELLS[k]`` per joint for a map over k joints (``MAX_TESTS`` cell tests at most per map).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .revolve import PartArrays

#: ``model.SelfCollisionModel`` (not imported: the model imports this module)
SelfCollisionModel = Any

__all__ = ["PairMap", "pair_maps", "cleared", "CELLS", "FIRST", "SHARE"]

#: Cells per joint at the finest level, for maps over one and over two joints (UR5, limits +-pi: 1024
#: cells, half-width 3 mrad, so its upper arm against the base moves at most ~3.5 mm within a cell, below
#: its ~16 mm clearance; over one joint 65536, half-width 48 urad).
CELLS = {1: 65536, 2: 1024}
#: Cells per joint at the coarsest level.
FIRST = 16
#: From this many cells per joint on, only the unproven cells next to a proven one are refined (the
#: boundary of the proven region, where finer cells prove more; its far side is in collision).
FULL = 128
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
    #: the cells, one bit each (``np.packbits``, little bit order; cell (i0, i1) is bit i0 * cells + i1):
    #: 1, apart at every joint value in the cell
    bits: np.ndarray
    #: cells per joint
    cells: int
    #: the links (model indices) tested as their solids of revolution (``revolve``): the cells hold at
    #: every value of the joint that turns them
    revolved: tuple[int, ...] = ()

    @property
    def free(self) -> np.ndarray:
        """bool (cells,) or (cells, cells): True where the cell is proven apart (unpacked from ``bits``)."""
        k = len(self.joints)
        return np.unpackbits(self.bits, count=self.cells ** k, bitorder="little").view(bool).reshape((self.cells,) * k)

    @property
    def proven(self) -> float:
        """The share of the joint box proven apart."""
        return float(np.unpackbits(self.bits, bitorder="little").sum()) / self.cells ** len(self.joints)


def _reach(model: SelfCollisionModel, parts: PartArrays, link: int, body: int,
           joints: tuple[int, ...]) -> np.ndarray:
    """rho (k,): bounds on the distance of the link's points from each joint's axis, any configuration."""
    from .revolve import _points

    own = float(np.linalg.norm(_points(parts, link), axis=1).max())    # from joint ``body``'s origin, on its axis
    J = model.robot.frames                            # q index i: joint i+1, its frame J[i]; the body's J[body-1]
    # |p - o_j| <= |p - o_body| + the steps between consecutive joints' origins from joint j+1 on: each
    # step's two origins are fixed in one body, whatever the joints between (an axis passes its origin)
    return np.array([own + sum(float(np.linalg.norm(J[i + 1][:3, 3] - J[i][:3, 3])) for i in range(j, body - 1))
                     for j in joints])


def _build(model: SelfCollisionModel, parts: PartArrays, pair: int, u: int, v: int,
           joints: tuple[int, ...], rho: np.ndarray, revolved: tuple[int, ...]) -> PairMap:
    from ..compiled.collision.parts import parts_apart

    robot = model.robot
    k = len(joints)
    lim = robot.limits[list(joints)]
    lower, span = lim[:, 0].copy(), lim[:, 1] - lim[:, 0]
    cells = CELLS[k]
    free = np.zeros((cells,) * k, dtype=bool)
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
        f = cells // n
        for axis in range(k):
            level = np.repeat(level, f, axis=axis)
        free |= level
        if n >= cells:
            break
        left = cand[~ok]
        if n >= FULL and len(left):
            # refined: cells whose centre is free (apart with no margin), and cells next to a proven one;
            # a cell in collision at its centre with no proven neighbour is deep in the colliding region
            grid = free[(slice(None, None, cells // n),) * k]
            near = grid.copy()
            for shift in np.stack(np.meshgrid(*[[-1, 0, 1]] * k, indexing="ij"), axis=-1).reshape(-1, k):
                near |= np.roll(grid, tuple(shift), axis=tuple(range(k)))
            centre = parts_apart(F, *parts, queries[~ok], 0, 0.0).view(np.bool_)
            tests += len(left)
            left = left[centre | near[tuple(left.T)]]
        cand = (left[:, None, :] * 2 + offsets[None]).reshape(-1, k)
        n *= 2
    return PairMap(pair, joints, lower, span / cells, np.packbits(free.reshape(-1), bitorder="little"), cells, revolved)


def _ways(model: SelfCollisionModel, near: int, far: int, lo: int, hi: int
          ) -> list[tuple[PartArrays, tuple[int, ...], tuple[int, ...]]]:
    """The ways to map the pair of links ``near`` (on body lo) and ``far`` (on body hi > lo): (parts, the
    joints mapped (q indices), the links turned), the joints lo+1 .. hi less those a turned link takes out
    (``revolve``), one or two left, all revolute with finite limits."""
    from .revolve import axis_frame, revolved_parts

    robot = model.robot
    joints = tuple(range(lo, hi))                     # joints lo+1 .. hi, as q indices
    if not robot.revolute[list(joints)].all():
        return []
    out = []
    for turn_near in (False, True):
        for turn_far in (False, True):
            left = joints[int(turn_near):len(joints) - int(turn_far)]
            if not 1 <= len(left) <= 2 or not np.isfinite(robot.limits[list(left)]).all():
                continue
            parts: PartArrays | None = model._parts
            if turn_far and parts is not None:
                parts = revolved_parts(parts, far, np.eye(4))
            if turn_near and parts is not None:
                parts = revolved_parts(parts, near, axis_frame(robot.frames, lo, lo + 1))
            if parts is not None:
                out.append((parts, left, (near,) * turn_near + (far,) * turn_far))
    return out


def pair_maps(model: SelfCollisionModel, rng: int = 0) -> list[PairMap]:
    """The maps of ``model``'s checked pairs whose capsules meet in at least ``SHARE`` of random
    configurations and that one or two revolute joints with finite limits move against each other, once
    links near round about a joint's axis are turned (``_ways``; of several ways, the one proving the
    most): none without convex parts."""
    if model._parts is None or not len(model._link_pairs):
        return []
    robot = model.robot
    body = {c.link: c.body for c in model.capsules}
    names = model.links
    share = (model.distances(robot.random_q(SAMPLES, rng=rng)) <= 0.0).mean(axis=0)
    out = []
    for p, (u, v) in enumerate(model._link_pairs):
        if share[p] < SHARE:
            continue
        lo, hi = sorted((body[names[u]], body[names[v]]))
        far = int(u if body[names[u]] == hi else v)
        near = int(v if far == u else u)
        built = [_build(model, parts, p, int(u), int(v), joints, _reach(model, parts, far, hi, joints), turned)
                 for parts, joints, turned in _ways(model, near, far, lo, hi)]
        if built:
            out.append(max(built, key=lambda m: m.proven))
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
        inside = ((x >= 0.0) & (x < m.cells)).all(axis=1)
        idx = np.clip(np.floor(x), 0, m.cells - 1).astype(np.intp)
        cell = idx[:, 0] * m.cells + idx[:, 1] if idx.shape[1] == 2 else idx[:, 0]
        out[sel] = inside & ((m.bits[cell >> 3] >> (cell & 7)) & 1).astype(bool)
    return out
