"""Collision-aware inverse kinematics: ``Robot.ik(T, avoid_self_collision=True)``.

``collision_free_ik(ik, robot, T, ...)`` wraps ``robkin.kinematics.ik.ik`` (passed in, so that this
package does not import the kinematics entry point that calls it):

1. IK as asked; its answer (or, with ``all_solutions=True``, each solution) is checked by the
   self-collision model (``build.model_of(robot)``): capsules, then, where they meet, the links' convex
   parts (both compiled and conservative: a solution kept is free for the meshes; ``level``). Where the preferred closed-form solution collides, every branch of that target is asked
   for. Colliding solutions are **dropped**: ``q`` is the collision-free solution nearest to ``q0``
   (IK's order), and with ``all_solutions=True`` ``solutions`` lists only the collision-free ones.
2. Targets left without a collision-free solution are retried numerically from ``RETRIES`` other
   starts each (one batch), configurations drawn within the limits that ``level`` calls free (seeded
   by ``rng``), keeping the first collision-free solution (with ``all_solutions``, every one).

The guarantees of ``ik`` hold: a success reaches the target to the tolerances with every joint within
its limits (the solutions are IK's own, checked by its forward kinematics); ``success`` is False, with
the message "every solution found is in self collision", where no collision-free one was found.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING, Any, Callable

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:  # pragma: no cover
    from ..robot import Robot
    from .model import SelfCollisionModel

__all__ = ["collision_free_ik", "RETRIES"]

#: Numeric starts (collision-free, one batch) per target whose solutions all collide.
RETRIES = 4
MESSAGE = "every solution found is in self collision"
#: Batches of fewer configurations are checked (and follow-up IK batches of fewer targets solved) on
#: one thread (unless ``threads=`` is given): the
#: OpenMP start and spin-wait of more threads cost more CPU than they save there (UR5, 1000 targets
#: on a loaded 2-core machine: 14 us of CPU a target with two threads, 10 with one).
SERIAL_BELOW = 4096
#: Candidates drawn per start needed (``_free_starts``).
OVERSAMPLE = 8


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


def _free_starts(robot: Robot, model: SelfCollisionModel, count: int, rng: np.random.Generator,
                 level: str = "capsules", threads: int | None = None) -> np.ndarray:
    """``count`` configurations within the limits that ``level`` calls free: candidates drawn in a few
    rounds of one batch each (``OVERSAMPLE`` a start still needed), any left over plain random ones
    (the UR5's capsules flag ~97 % of random configurations, its 'parts' level ~26 %)."""
    out = robot.random_q(count, rng=rng)
    need = np.ones(count, dtype=bool)
    for _ in range(3):
        cand = robot.random_q(OVERSAMPLE * int(need.sum()), rng=rng)
        free = cand[~_collides(model, cand, level, threads)]
        idx = np.flatnonzero(need)[:len(free)]
        out[idx] = free[:len(idx)]
        need[idx] = False
        if not need.any():
            break
    return out


def _collision_free(model: SelfCollisionModel, sols: list[np.ndarray], level: str,
                    threads: int | None = None) -> list[np.ndarray]:
    """Each target's solutions without the colliding ones (one batch check of all of them)."""
    sizes = [len(s) for s in sols]
    if not sum(sizes):
        return sols
    hit = _collides(model, np.vstack([s for s in sols if len(s)]), level, threads)
    out, k = [], 0
    for s, m in zip(sols, sizes):
        out.append(s[~hit[k:k + m]])
        k += m
    return out


def _first_free(model: SelfCollisionModel, sols: list[np.ndarray], level: str,
                threads: int | None = None) -> list[np.ndarray]:
    """Each target's first collision-free solution (1, n), or none (0, n): the solutions checked in
    rounds, IK's preferred one first, a target leaving the rounds at its first free one (most targets
    need one or two of their up to 8 closed-form branches checked, not all)."""
    n = sols[0].shape[1] if sols else 0
    out = [np.empty((0, n)) for _ in sols]
    left = [i for i, s in enumerate(sols) if len(s)]
    r = 0
    while left:
        hit = _collides(model, np.vstack([sols[i][r] for i in left]), level, threads)
        for i, h in zip(left, hit):
            if not h:
                out[i] = sols[i][r:r + 1]
        r += 1
        left = [i for i, h in zip(left, hit) if h and len(sols[i]) > r]
    return out


def collision_free_ik(ik: Callable[..., Any], robot: Robot, T: ArrayLike, *, model: SelfCollisionModel | None = None,
                      level: str | None = None, q0: ArrayLike | None = None, all_solutions: bool = False,
                      rng: np.random.Generator | int | None = 0, **options: Any) -> Any:
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
    """
    from .build import model_of

    model = model or model_of(robot)
    if level is None:
        level = "parts" if model.parts else "capsules"
    res = ik(robot, T, q0=q0, all_solutions=all_solutions, rng=rng, **options)
    threads = options.get("threads")
    single = np.ndim(res.success) == 0
    n = robot.n
    ok = np.atleast_1d(res.success).astype(bool)
    # sols, free: per target left to settle, every solution found and the collision-free ones
    if all_solutions:
        listed = [res.solutions] if single else list(res.solutions)
        sols = dict(enumerate(np.asarray(s, dtype=float).reshape(-1, n) for s in listed))
        free = dict(enumerate(_collision_free(model, list(sols.values()), level, threads)))
        kept = np.zeros(len(ok), dtype=bool)
        sols_0: dict[int, np.ndarray] = {}
    else:   # the preferred solutions, checked in one batch; the other branches only where one collides
        qs = np.array(res.q, dtype=float).reshape(-1, n)
        kept = ok.copy()
        if ok.any():
            kept[ok] = ~_collides(model, qs[ok], level, threads)
        sols = {int(i): qs[i:i + 1] if ok[i] else np.empty((0, n)) for i in np.flatnonzero(~kept)}
        sols_0 = {i: s[0] for i, s in sols.items() if len(s)}
        free = {i: np.empty((0, n)) for i in sols}
    targets = np.asarray(T, dtype=float).reshape(-1, 4, 4)
    left = [i for i, f in free.items() if not len(f)]
    if left and not all_solutions and res.method != "numeric":   # closed form: every branch of those targets
        sub = ik(robot, targets[left] if not single else targets[0], q0=None if q0 is None else
                 (np.asarray(q0, dtype=float).reshape(-1, n)[left] if np.ndim(q0) == 2 else q0),
                 all_solutions=True, rng=rng, **_serial(options, len(left)))
        got = [sub.solutions] if single else list(sub.solutions)
        got = [np.asarray(g, dtype=float).reshape(-1, n) for g in got]
        for i, g in zip(left, got):
            sols[i] = g
        # the preferred solution was checked already: the other branches only
        G = np.vstack(got) if got else np.empty((0, n))
        owner = np.repeat(np.arange(len(left)), [len(g) for g in got])
        ref = np.full((len(left), n), np.nan)       # NaN (no preferred solution) equals nothing
        for k, i in enumerate(left):
            if i in sols_0:
                ref[k] = sols_0[i]
        keep = ~np.all(G == ref[owner], axis=1)
        ends = np.cumsum(np.bincount(owner[keep], minlength=len(left)))
        G = G[keep]
        others = [G[e - c:e] for e, c in zip(ends, np.diff(np.r_[0, ends]))]
        for i, g in zip(left, _first_free(model, others, level, threads)):
            free[i] = g
    left = [i for i, f in free.items() if not len(f)]
    if left:    # RETRIES collision-free starts per target left, all in one numeric batch
        gen = np.random.default_rng(rng)
        numeric = {k: v for k, v in options.items() if k not in ("method",)}
        idx = np.repeat(left, RETRIES)
        starts = _free_starts(robot, model, len(idx), gen, level, threads)
        sub = ik(robot, targets[idx], q0=starts, method="numeric", all_solutions=all_solutions, rng=gen,
                 **_serial(numeric, len(idx)))
        if all_solutions:
            got = list(sub.solutions)
        else:
            good = np.atleast_1d(sub.success)
            got = [q[None] if g else np.empty((0, n)) for q, g in zip(np.array(sub.q, dtype=float).reshape(-1, n), good)]
        got = [np.asarray(g, dtype=float).reshape(-1, n) for g in got]
        ok_got = _collision_free(model, got, level, threads)
        for k, i in enumerate(left):
            mine = got[k * RETRIES:(k + 1) * RETRIES]
            found = np.vstack(mine)
            sols[i] = found if len(found) else sols[i]
            kept_free = np.vstack(ok_got[k * RETRIES:(k + 1) * RETRIES])
            free[i] = kept_free if all_solutions else kept_free[:1]
    q = np.array(res.q, dtype=float).reshape(-1, robot.n)
    success = kept.copy()
    messages = [res.message] if single else list(res.message)
    for j in np.flatnonzero(kept).tolist():
        messages[j] = ""
    for i, f in free.items():
        if len(f):
            q[i], success[i] = f[0], True
            messages[i] = ""
        elif len(sols[i]) or bool(np.atleast_1d(res.success)[i]):
            q[i] = np.nan
            messages[i] = MESSAGE
    # errors: IK's own where its answer was kept (the same q), recomputed where another one replaced it
    ep = np.where(kept, np.atleast_1d(res.position_error), np.inf).astype(float)
    eo = np.where(kept, np.atleast_1d(res.orientation_error), np.inf).astype(float)
    changed = np.flatnonzero(~kept)
    if len(changed):
        ep[changed], eo[changed] = _errors(robot, targets[changed] if len(targets) > 1 else targets, q[changed])
    if options.get("mask") not in (None, "pose"):   # errors over the masked components: IK's own, per target
        ep = np.where(np.isfinite(q).all(axis=1), np.atleast_1d(res.position_error), np.inf)
        eo = np.where(np.isfinite(q).all(axis=1), np.atleast_1d(res.orientation_error), np.inf)
    return replace(res, q=q[0] if single else q, success=bool(success[0]) if single else success,
                   position_error=float(ep[0]) if single else ep, orientation_error=float(eo[0]) if single else eo,
                   message=messages[0] if single else messages,
                   solutions=None if not all_solutions else (free[0] if single else [free[i] for i in range(len(free))]))


def _errors(robot: Robot, targets: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Position and orientation errors (full pose; inf where q is NaN) of the chosen solutions."""
    ep = np.full(len(q), np.inf)
    eo = np.full(len(q), np.inf)
    ok = np.isfinite(q).all(axis=1)
    if ok.any():
        P = robot.fk(np.ascontiguousarray(q[ok]))
        Td = targets[ok] if len(targets) > 1 else np.repeat(targets, int(ok.sum()), axis=0)
        ep[ok] = np.linalg.norm(Td[:, :3, 3] - P[:, :3, 3], axis=1)
        E = Td[:, :3, :3] @ np.swapaxes(P[:, :3, :3], 1, 2)   # R_d R^T; its angle by atan2 (accurate near 0)
        c = (np.trace(E, axis1=1, axis2=2) - 1.0) / 2.0
        w = np.stack([E[:, 2, 1] - E[:, 1, 2], E[:, 0, 2] - E[:, 2, 0], E[:, 1, 0] - E[:, 0, 1]], axis=1)
        eo[ok] = np.arctan2(np.linalg.norm(w, axis=1) / 2.0, c)
    return ep, eo
