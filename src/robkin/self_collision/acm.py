"""The allowed-collision matrix: the link pairs a self-collision check skips, and why.

MoveIt's Setup Assistant rules, in its order, each pair getting the first reason that applies:

* ``Adjacent``: the links are joined by one joint (a parent and its child; links without collision
  geometry are passed through, so the Panda's hand is adjacent to link 7 across the empty link 8);
* ``Default``: they are in collision at the robot's home (``Robot.home()``: q = 0 clipped into the limits;
  joints off the chain, such as a gripper's fingers, held at 0);
* ``Always``: in collision at every sampled configuration;
* ``Never``: in collision at none of them.

The samples are ``samples`` configurations drawn uniformly within the joint limits (``Robot.random_q``,
seed ``rng``). Each pair is first judged by its capsules (``capsules``, compiled, every sample at once):
a pair whose capsules never meet never collides. The pairs whose capsules do meet somewhere are then
collided exactly (``exact``: coal, meshes as triangles), at the samples where their capsules meet,
until the pair is seen both colliding and free. Without coal (``exact=False``) the capsules decide
alone: fewer pairs are "Never" (the capsules are larger than the links), none wrongly.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .model import DisabledPair, SelfCollisionModel

if TYPE_CHECKING:  # pragma: no cover
    from ..robot import Robot
    from .exact import ExactChecker

__all__ = ["adjacent_pairs", "allowed_collisions", "REASONS"]

REASONS = ("Adjacent", "Default", "Always", "Never")
#: Configurations collided per call of the compiled capsule check while sampling (bounds the (chunk, P)
#: distance array at a few MB).
CHUNK = 16384


def adjacent_pairs(robot: Robot, names: list[str]) -> set[frozenset[str]]:
    """Pairs of the links ``names`` (those with collision geometry) joined by one joint, passing through
    links without geometry. A link the robot's link tree does not know (a robot built without one) is
    adjacent to the links of its own body and of the bodies next to it."""
    links = {ln.name: ln for ln in robot.bodies.links}
    has = set(names)
    out: set[frozenset[str]] = set()
    body = {s.link: s.body for s in robot.bodies.shapes}
    for name in names:
        if name not in links:
            out |= {frozenset((name, o)) for o in names if o != name and abs(body[o] - body[name]) <= 1}
            continue
        parent = links[name].parent
        seen = 0
        while parent is not None and parent not in has and parent in links and seen <= len(links):
            parent = links[parent].parent
            seen += 1
        if parent is not None and parent in has:
            out.add(frozenset((name, parent)))
    return out


def allowed_collisions(model: SelfCollisionModel, exact: ExactChecker | None, samples: int = 20000,
                       rng: np.random.Generator | int | None = 0) -> list[DisabledPair]:
    """The allowed-collision matrix of the capsule model ``model`` (its own ``disabled`` ignored), judged
    exactly by ``exact`` where given (see the module doc). Pairs in the order of ``model.links``.

    Parameters
    ----------
    model : SelfCollisionModel
        The capsules (its own ``disabled`` is ignored: every pair is judged).
    exact : ExactChecker or None
        The meshes' check (coal) for pairs whose capsules meet; None: the capsules decide alone.
    samples : int
        Configurations drawn uniformly within the joint limits (``Robot.random_q``).
    rng : Generator, int seed or None
        The samples' source (seed 0: reproducible).

    Returns
    -------
    list of DisabledPair
        The pairs never checked, each with its reason.
    """
    robot = model.robot
    names = model.links
    every = SelfCollisionModel(robot, model.capsules, [])   # all pairs checked
    pairs = [(every._index[a], every._index[b]) for a, b in every.pairs]
    adjacent = adjacent_pairs(robot, names)
    reason: dict[int, str] = {}
    for p, (u, v) in enumerate(pairs):
        if frozenset((names[u], names[v])) in adjacent:
            reason[p] = "Adjacent"
    rest = [p for p in range(len(pairs)) if p not in reason]
    home = robot.home()
    d_home = every.distances(home)
    if exact is not None:
        hit = set(exact.colliding_pairs(home, [pairs[p] for p in rest if d_home[p] <= 0.0]))
        default = [p for p in rest if pairs[p] in hit]
    else:
        default = [p for p in rest if d_home[p] <= 0.0]
    for p in default:
        reason[p] = "Default"
    rest = [p for p in rest if p not in reason]
    Q = robot.random_q(int(samples), rng=rng)
    overlap = np.zeros((len(Q), len(rest)), dtype=bool)
    if rest:
        sub = SelfCollisionModel(robot, model.capsules, [])
        cols = np.array(rest)
        for k in range(0, len(Q), CHUNK):
            overlap[k:k + CHUNK] = sub.distances(Q[k:k + CHUNK])[:, cols] <= 0.0
    met = np.asarray(overlap.any(axis=0), dtype=bool)
    seen_free = np.asarray(~overlap.all(axis=0), dtype=bool)
    seen_hit = met.copy() if exact is None else np.zeros(len(rest), dtype=bool)
    if exact is not None:
        undecided = set(np.flatnonzero(met).tolist())
        for c in np.flatnonzero(overlap[:, sorted(undecided)].any(axis=1)) if undecided else []:
            check = [j for j in undecided if overlap[c, j]]
            if not check:
                continue
            hits = set(exact.colliding_pairs(Q[c], [pairs[rest[j]] for j in check]))
            for j in check:
                if pairs[rest[j]] in hits:
                    seen_hit[j] = True
                else:
                    seen_free[j] = True
                if seen_hit[j] and seen_free[j]:
                    undecided.discard(j)
            if not undecided:
                break
    for j, p in enumerate(rest):
        if not seen_hit[j]:
            reason[p] = "Never"
        elif not seen_free[j]:
            reason[p] = "Always"
    return [DisabledPair(names[pairs[p][0]], names[pairs[p][1]], reason[p]) for p in sorted(reason)]
