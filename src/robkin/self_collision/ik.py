"""Collision-aware inverse kinematics: ``Robot.ik(T, avoid_self_collision=True)``.

``collision_free_ik(ik, robot, T, ...)`` wraps ``robkin.kinematics.ik.ik`` (passed in, so that this
package does not import the kinematics entry point that calls it):

1. IK as asked; its answer (or, with ``all_solutions=True``, each solution) is checked by the
   self-collision model (``build.model_of(robot)``): capsules, then, where they meet, the pair maps and
   the links' convex parts (compiled and conservative: a solution kept is free for the meshes;
   ``level``). Where the preferred closed-form solution collides, every branch of that target (from the
   branches the batch was solved from, ``solve``; else asked of ``ik``) is checked in rounds, the nearest
   to ``q0`` first (IK's order). Colliding solutions are
   **dropped**: ``q`` is the collision-free solution nearest to ``q0``, and with ``all_solutions=True``
   ``solutions`` lists only the collision-free ones.
2. Targets left without a collision-free solution are retried numerically from ``RETRIES`` starts each
   (one batch), drawn from configurations that ``level`` calls free (``POOL`` of them per model, found
   once; the draw seeded by ``rng``), keeping the first collision-free solution (with
   ``all_solutions``, every one). Not where the closed form gives every solution (``COMPLETE``) and
   none of the target's is near a singular configuration (``SINGULAR``): a numeric solve can only find
   those same solutions there (a target with none is out of reach).

The guarantees of ``ik`` hold: a success reaches the target to the tolerances with every joint within
its limits (the solutions are IK's own, checked by its forward kinematics); ``success`` is False, with
the message "every solution found is in self collision", where no collision-free one was found.
"""

from __future__ import annotations

import weakref
from dataclasses import replace
from typing import TYPE_CHECKING, Any, Callable

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:  # pragma: no cover
    from ..robot import Robot
    from .model import SelfCollisionModel

__all__ = ["collision_free_ik", "RETRIES", "POOL", "COMPLETE", "SINGULAR"]

#: Numeric starts (collision-free, one batch) per target whose solutions all collide.
RETRIES = 4
#: Collision-free configurations kept per model and level for the numeric retries' starts (found at the
#: first retry: enough that four starts of a target are almost never alike).
POOL = 256
#: Candidates drawn per pool configuration still needed, in each of up to ``POOL_ROUNDS`` rounds (the
#: UR5's capsules flag ~97 % of random configurations, its 'parts' level ~26 %).
OVERSAMPLE = 8
POOL_ROUNDS = 3
MESSAGE = "every solution found is in self collision"
#: Closed forms (``IKResult.method``) built branch by branch from the class's geometry: every solution of
#: a target, wherever the target is regular (the polynomial ones, 'pieper-6r' and 'general-6r', and the
#: polished 'near-' classes may lose a root: their targets are retried).
COMPLETE = frozenset({"scara", "spherical-wrist-6r", "three-parallel-6r"})
#: A target is still retried where one of its solutions has a Jacobian whose least singular value (rows
#: of length in units of the robot's size; as many values as joints, up to 6) is below this: at a
#: singular configuration, or on a redundant arm (a SCARA with two joints along its axis: always 0), a
#: joint may be free (a continuum of solutions, of which the closed form gives one), and near one its
#: branches are the least certain. A generous bound: 1.5 % of the UR5's random configurations are below it (median
#: 0.09).
SINGULAR = 1e-3
#: Batches of fewer configurations are checked (and follow-up IK batches of fewer targets solved) on
#: one thread (unless ``threads=`` is given): there the OpenMP start and spin-wait of more threads cost
#: more than they save. Larger ones, the IK answers of a batch among them, take the default threads, so
#: that the workers plain IK left spinning work instead (UR5, 1000 targets, default threads on 2 cores,
#: 2026-11-29: with every batch below 4096 on one thread, 5.6x plain IK's CPU time and 3.4x its wall
#: time; below 64 or 256, 2.7-2.9x and 2.5x; always the default threads, 3.2x and 2.5x).
SERIAL_BELOW = 128
#: ``_first_free`` checks the branches left in one batch once they are at most this many.
FEW = 16

#: per model: level -> its pool of collision-free configurations (``_pool``)
_POOLS: weakref.WeakKeyDictionary[SelfCollisionModel, dict[str, np.ndarray]] = weakref.WeakKeyDictionary()


def _collides(model: SelfCollisionModel, q: np.ndarray, level: str, threads: int | None) -> np.ndarray:
    """``model.collides(q, level=level)`` (q (N, n) -> (N,) bool), on one thread for small batches."""
    t = threads if threads is not None else (1 if len(q) < SERIAL_BELOW else None)
    return np.asarray(model.collides(q, level=level, threads=t), dtype=bool)


def _serial(options: dict[str, Any], count: int) -> dict[str, Any]:
    """IK's options for a follow-up batch of ``count`` targets: on one thread when it is small and no
    ``threads`` was given (as ``_collides``: OpenMP's spin-wait costs more CPU than a few targets take)."""
    if options.get("threads") is None and count < SERIAL_BELOW:
        return {**options, "threads": 1}
    return options


def _pool(model: SelfCollisionModel, level: str, threads: int | None) -> np.ndarray:
    """Up to ``POOL`` configurations (P, n) within the limits that ``level`` calls free, found once per
    model and level (fixed seed: the same pool every run); random ones where none is found."""
    pools = _POOLS.setdefault(model, {})
    if level not in pools:
        robot = model.robot
        rng = np.random.default_rng(0)
        found: list[np.ndarray] = []
        for _ in range(POOL_ROUNDS):
            cand = robot.random_q(OVERSAMPLE * (POOL - sum(len(f) for f in found)), rng=rng)
            found.append(cand[~_collides(model, cand, level, threads)])
            if sum(len(f) for f in found) >= POOL:
                break
        pool = np.vstack(found)[:POOL]
        pools[level] = pool if len(pool) else robot.random_q(POOL, rng=rng)
    return pools[level]


def _first_free(model: SelfCollisionModel, G: np.ndarray, counts: np.ndarray, level: str,
                threads: int | None) -> np.ndarray:
    """Per group (``counts[k]`` consecutive rows of G (M, n)), the row of its first collision-free
    configuration, -1 for none: checked in rounds (every group's r-th row in one batch), a group leaving
    at its first free row (most need one or two of their up to 8 closed-form branches checked). Once
    the rows left are few (``FEW``), they are checked in one last batch: a round's fixed cost (~20 us)
    is then more than checking a few rows that a later round might not have needed."""
    first = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.intp)
    out = np.full(len(counts), -1, dtype=np.intp)
    active = np.flatnonzero(counts > 0)
    r = 0
    while len(active):
        if int((counts[active] - r).sum()) <= FEW:     # the rest at once, each group's first free row kept
            rows = np.concatenate([np.arange(first[k] + r, first[k] + counts[k]) for k in active])
            owner = np.repeat(active, counts[active] - r)
            free = ~_collides(model, G[rows], level, threads)
            for k, row in zip(owner[free][::-1].tolist(), rows[free][::-1].tolist()):
                out[k] = row                            # backwards: the first free row of a group stays
            break
        rows = first[active] + r
        hit = _collides(model, G[rows], level, threads)
        out[active[~hit]] = rows[~hit]
        r += 1
        active = active[hit & (counts[active] > r)]
    return out


def _retry(ik: Callable[..., Any], robot: Robot, model: SelfCollisionModel, targets: np.ndarray, level: str,
           all_solutions: bool, gen: np.random.Generator, options: dict[str, Any]
           ) -> tuple[list[np.ndarray], np.ndarray]:
    """Numeric IK of targets (k, 4, 4) from ``RETRIES`` collision-free starts each (``_pool``), one batch:
    per target, its collision-free solutions (S, n) (the first only, without ``all_solutions``), and
    whether any solution was found (k,) bool."""
    n = robot.n
    pool = _pool(model, level, options.get("threads"))
    starts = pool[gen.integers(0, len(pool), size=len(targets) * RETRIES)]
    numeric = {k: v for k, v in options.items() if k != "method"}
    sub = ik(robot, np.repeat(targets, RETRIES, axis=0), q0=starts, method="numeric", all_solutions=all_solutions,
             rng=gen, **_serial(numeric, len(starts)))
    if all_solutions:
        sols = [np.asarray(s, dtype=float).reshape(-1, n) for s in sub.solutions]
    else:
        good = np.asarray(sub.success, dtype=bool)
        qs = np.asarray(sub.q, dtype=float).reshape(-1, n)
        sols = [qs[i:i + 1] if good[i] else qs[:0] for i in range(len(qs))]
    sizes = np.array([len(s) for s in sols])
    G = np.vstack(sols) if sizes.sum() else np.empty((0, n))
    free = ~_collides(model, G, level, options.get("threads")) if len(G) else np.zeros(0, dtype=bool)
    per = sizes.reshape(len(targets), RETRIES).sum(axis=1)
    owner = np.repeat(np.arange(len(targets)), per)
    out = [G[(owner == k) & free] for k in range(len(targets))]
    return (out if all_solutions else [o[:1] for o in out]), per > 0


def collision_free_ik(ik: Callable[..., Any], robot: Robot, T: ArrayLike, *, model: SelfCollisionModel | None = None,
                      level: str | None = None, q0: ArrayLike | None = None, all_solutions: bool = False,
                      rng: np.random.Generator | int | None = 0, solve: Callable[..., Any] | None = None,
                      **options: Any) -> Any:
    """``ik(robot, T, ...)`` keeping only solutions free of self collision (see the module doc).

    Parameters
    ----------
    ik : callable
        ``robkin.kinematics.ik.ik``.
    robot : Robot
        The robot.
    T : array (4, 4) or (N, 4, 4)
        Target pose(s) of the tool in the base frame (length units).
    model : SelfCollisionModel, optional
        Default: ``build.model_of(robot)``.
    level : {'capsules', 'parts', 'exact'}, optional
        How a solution is checked (``SelfCollisionModel.collides``); default 'parts' (compiled and
        conservative: a solution kept is free for the meshes), 'capsules' for a model without parts.
    q0, all_solutions, rng, options
        As for ``ik``.
    solve : callable, optional
        ``robkin.kinematics.ik.solve_with_branches``: the first IK call through it also gives the
        closed-form branches its batch was solved from, so that a target whose answer collides has its
        other branches without a second solve; without it, they are asked of ``ik``.
    """
    from ..compiled.ik.lm import pose_errors
    from ..kinematics.pose_error import check_mask
    from .build import model_of

    model = model or model_of(robot)
    if level is None:
        level = "parts" if model.parts else "capsules"
    if solve is not None:
        res, source = solve(robot, T, q0=q0, all_solutions=all_solutions, rng=rng, **options)
    else:
        res, source = ik(robot, T, q0=q0, all_solutions=all_solutions, rng=rng, **options), None
    threads = options.get("threads")
    single = np.ndim(res.success) == 0
    n = robot.n
    targets = np.asarray(T, dtype=float).reshape(-1, 4, 4)
    ok = np.atleast_1d(res.success).astype(bool)
    q = np.array(res.q, dtype=float).reshape(-1, n)
    # free[i]: target i's collision-free solutions (the chosen one first), for each target not kept as IK
    # answered it; found[i]: some solution was found for it (a failure then says they all collide);
    # known[i]: every solution found for it (without all_solutions: IK's answer and its other branches,
    # the rows of G from ``ends[k] - counts[k]`` to ``ends[k]`` for target ``asked[k]``)
    free: dict[int, np.ndarray] = {}
    known: dict[int, np.ndarray] = {}
    G = q[:0]
    asked = counts = ends = np.zeros(0, dtype=np.intp)
    if all_solutions:
        listed = [res.solutions] if single else list(res.solutions)
        sols = [np.asarray(s, dtype=float).reshape(-1, n) for s in listed]
        sizes = np.array([len(s) for s in sols])
        G = np.vstack(sols) if sizes.sum() else np.empty((0, n))
        hit = _collides(model, G, level, threads) if len(G) else np.zeros(0, dtype=bool)
        ends = np.cumsum(sizes)
        free = {i: s[~hit[e - len(s):e]] for i, (s, e) in enumerate(zip(sols, ends))}
        known = dict(enumerate(sols))
        kept = np.zeros(len(ok), dtype=bool)
        found = sizes > 0
    else:   # the preferred solutions, checked in one batch; the other branches only where one collides
        kept = ok.copy()
        at = np.flatnonzero(ok)
        if len(at):
            kept[at] = ~_collides(model, q[at], level, threads)
        found = ok.copy()
        left = np.flatnonzero(~kept)
        if len(left) and res.method != "numeric":   # closed form: every branch of those targets
            if source is not None:      # the branches the batch was solved from
                listed = source.solutions(left)
            else:
                q0s = None if q0 is None else (np.asarray(q0, dtype=float).reshape(-1, n)[left] if np.ndim(q0) == 2
                                               else q0)
                listed = ik(robot, targets[left], q0=q0s, all_solutions=True, rng=rng,
                            **_serial(options, len(left))).solutions
            counts = np.fromiter(map(len, listed), dtype=np.intp, count=len(left))
            found[left] |= counts > 0
            G = np.concatenate(listed).reshape(-1, n) if counts.sum() else np.empty((0, n))
            owner = np.repeat(np.arange(len(left)), counts)
            # the preferred solution was checked already: the other branches only (NaN: none, equals nothing)
            ref = np.where(ok[left][:, None], q[left], np.nan)
            other = ~np.all(G == ref[owner], axis=1)
            G, counts = G[other], np.bincount(owner[other], minlength=len(left))
            row = _first_free(model, G, counts, level, threads)
            for i, r in zip(left[row >= 0].tolist(), row[row >= 0].tolist()):
                free[i] = G[r:r + 1]
            asked, ends = left, np.cumsum(counts)
    settled = kept.copy()
    settled[[i for i, f in free.items() if len(f)]] = True
    left = np.flatnonzero(~settled)
    if len(left) and res.method in COMPLETE:   # every solution is known: retried only near a singularity
        # (always where the closed form's check failed and IK answered numerically: its list may lack one)
        retried = source.retried[left] if source is not None else np.zeros(len(left), dtype=bool)
        left, kept_left = left[retried], left[~retried]
        for i, k in zip(kept_left.tolist(), np.searchsorted(asked, kept_left).tolist()):
            if k < len(asked) and asked[k] == i:
                g = G[ends[k] - counts[k]:ends[k]]
                known[i] = np.vstack([q[i:i + 1], g]) if ok[i] else g
        left = np.union1d(left, kept_left[_near_singular(robot, [known.get(i, q[:0]) for i in kept_left.tolist()])])
    if len(left):    # RETRIES collision-free starts per target left, all in one numeric batch
        got, any_found = _retry(ik, robot, model, targets[left], level, all_solutions, np.random.default_rng(rng),
                                options)
        found[left] |= any_found
        for i, f in zip(left.tolist(), got):
            free[i] = f
    success = kept.copy()
    messages = [res.message] if single else list(res.message)    # IK's: "" where it succeeded
    changed = []
    for i in np.flatnonzero(~kept).tolist():
        f = free.get(i, q[:0])
        if len(f):
            q[i], success[i], messages[i] = f[0], True, ""
            changed.append(i)
        elif found[i] or ok[i]:
            q[i], messages[i] = np.nan, MESSAGE
            changed.append(i)
    # errors: IK's own where its answer stands (kept, or a failure left as IK gave it), recomputed over
    # the masked components where another answer replaced it (inf where none is left)
    ep = np.array(np.atleast_1d(res.position_error), dtype=float)
    eo = np.array(np.atleast_1d(res.orientation_error), dtype=float)
    if changed:
        ep[changed], eo[changed] = pose_errors(robot._chain, q[changed], targets[changed],
                                               check_mask(options.get("mask")))
    return replace(res, q=q[0] if single else q, success=bool(success[0]) if single else success,
                   position_error=float(ep[0]) if single else ep, orientation_error=float(eo[0]) if single else eo,
                   message=messages[0] if single else messages,
                   solutions=None if not all_solutions else (free.get(0, np.empty((0, n))) if single else
                                                             [free.get(i, np.empty((0, n))) for i in range(len(ok))]))


def _near_singular(robot: Robot, groups: list[np.ndarray]) -> np.ndarray:
    """bool (len(groups),): some configuration of the group (k, n) has a Jacobian whose least singular
    value, with the linear rows in units of the robot's size, is below ``SINGULAR`` (an empty group:
    False)."""
    sizes = np.fromiter(map(len, groups), dtype=np.intp, count=len(groups))
    out = np.zeros(len(groups), dtype=bool)
    if not sizes.sum():
        return out
    J = robot.jacobian(np.ascontiguousarray(np.concatenate(groups)), threads=1)
    J[:, :3] /= robot.scale
    low = np.linalg.svd(J, compute_uv=False)[:, -1] < SINGULAR
    np.logical_or.at(out, np.repeat(np.arange(len(groups)), sizes), low)
    return out
