"""Sampling configurations into a map, chunk by chunk, so that the result does not depend on who ran
which chunk.

The samples are ``chunks(samples)`` chunks of ``CHUNK`` configurations; chunk c draws its joint values
uniformly between the limits from its own generator, ``numpy.random.default_rng([seed, c])``. A chunk's
FK positions mark voxels, its tool z axes mark orientation bins, and each voxel keeps the largest
manipulability seen and the configuration that had it. Folding chunks into a ``Partial`` is
associative: marks are an OR, and a voxel's best configuration is the one of largest manipulability,
the earliest chunk (then the earliest sample of that chunk) on a tie. So any split of the chunks
into ranges, folded range by range and the ranges folded in order, gives the same bits: that is how
the Dask path (``distributed``) equals the local one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..robot import Robot
from .grid import direction_bins

__all__ = ["CHUNK", "SWEEP", "Plan", "Partial", "chunks", "split", "sweep_of", "run_chunks", "run_local"]

#: Configurations per chunk: large enough that the kernels' per-call cost (~50 us) is lost in the work
#: and NumPy's per-array overhead too, small enough that a chunk's temporaries (FK poses: 128 bytes a
#: sample) stay ~10 MB.
CHUNK = 65536
#: Configurations per FK evaluation when joint 1 is revolute (``run_chunks``): a power of two (a divisor
#: of CHUNK). The per-configuration NumPy work then dominates; 8 gives ~4x the configurations per second.
SWEEP = 8


@dataclass(frozen=True, eq=False)
class Plan:
    """What every chunk needs: the robot, the grid, the orientation bins, the sampling."""

    robot: Robot
    origin: np.ndarray          # (3,) grid corner, base frame, m
    shape: tuple[int, int, int]
    voxel: float
    directions: np.ndarray      # (K, 3) unit vectors
    lower: np.ndarray           # (n,) sampled joint range
    upper: np.ndarray
    samples: int
    seed: int
    kind: str                   # manipulability kind (Robot.manipulability)
    sweep: int = 1              # configurations per FK evaluation (run_chunks)


def chunks(samples: int) -> int:
    """Number of chunks of ``samples`` configurations (the last one may be shorter)."""
    return -(-int(samples) // CHUNK)


class Partial:
    """A map under construction over the plan's whole box (flat voxel index v = (i * ny + j) * nz + k).

    ``bins`` (V * K,) bool: orientation bin d of voxel v at v * K + d; ``manipulability`` (V,) the
    largest seen, -1 where no sample landed; ``best_q`` (V, n) the configuration that had it.
    """

    def __init__(self, plan: Plan):
        voxels = plan.shape[0] * plan.shape[1] * plan.shape[2]
        self.bins = np.zeros(voxels * len(plan.directions), dtype=bool)
        self.manipulability = np.full(voxels, -1.0)
        self.best_q = np.full((voxels, plan.robot.n), np.nan)

    def fold(self, other: "Partial") -> None:
        """Fold a later range's partial map into this one (earlier wins a tie)."""
        self.bins |= other.bins
        better = other.manipulability > self.manipulability
        self.manipulability[better] = other.manipulability[better]
        self.best_q[better] = other.best_q[better]


def sweep_of(robot: Robot) -> int:
    """Configurations per FK evaluation: ``SWEEP`` when joint 1 is revolute, else 1 (see ``run_chunks``)."""
    return SWEEP if robot.joints[0].revolute else 1


def run_chunks(plan: Plan, start: int, stop: int, threads: int | None = None) -> Partial:
    """The partial map of chunks ``start`` .. ``stop - 1`` of the plan, folded in order.

    A chunk's configurations come in groups of ``plan.sweep`` that differ only in joint 1 (revolute):
    joint values u (uniform in [0, 1)^n, mapped onto the limits) and the same u with u_1 shifted by
    j / sweep (mod 1), j = 1 .. sweep - 1: each configuration is still uniform between the limits, and
    joint 1 is sampled evenly. Turning joint 1 turns the whole arm about joint 1's axis, so one FK and
    one manipulability (which a rigid turn does not change) serve the whole group: the tool poses of the
    others are the first one's turned about that axis. ``threads`` bounds the kernels' threads.
    """
    out = Partial(plan)
    robot, n, sweep = plan.robot, plan.robot.n, plan.sweep
    shape = np.array(plan.shape)
    k = len(plan.directions)
    span = plan.upper - plan.lower
    axis, point = robot.frames[0, :3, 2], robot.frames[0, :3, 3]
    shifts = np.arange(sweep) / sweep
    voxels = int(np.prod(shape))
    best = np.full(voxels, -np.inf)
    first = np.full(voxels, np.iinfo(np.int64).max)
    for c in range(start, stop):
        size = min(CHUNK, plan.samples - c * CHUNK)
        if size <= 0:
            break
        rng = np.random.default_rng([plan.seed, c])
        groups = -(-size // sweep)
        u = rng.random((groups, n))
        q = plan.lower + span * u
        T = robot.fk(q, threads=threads)
        m = np.asarray(robot.manipulability(q, plan.kind, threads=threads))
        if sweep > 1:
            u1 = (u[:, :1] + shifts) % 1.0                                      # (groups, sweep)
            q1 = plan.lower[0] + span[0] * u1
            turn = q1 - q[:, :1]
            p = _turned(T[:, :3, 3] - point, axis, turn) + point
            z = _turned(T[:, :3, 2], axis, turn)
            m = np.repeat(m, sweep)
            qs = np.repeat(q, sweep, axis=0)
            qs[:, 0] = q1.reshape(-1)
            p, z, m, qs = p[:size], z[:size], m[:size], qs[:size]
        else:
            p, z, qs = T[:, :3, 3], T[:, :3, 2], q
        ijk = np.floor((p - plan.origin) / plan.voxel).astype(np.intp)
        # the box holds every reachable position with a voxel to spare (grid.reach_box); the clip only
        # guards against rounding at its edge
        np.clip(ijk, 0, shape - 1, out=ijk)
        flat = (ijk[:, 0] * shape[1] + ijk[:, 1]) * shape[2] + ijk[:, 2]
        out.bins[flat * k + direction_bins(z, plan.directions)] = True
        # per voxel, the configuration of largest manipulability (the earliest on a tie)
        np.maximum.at(best, flat, m)
        top = np.flatnonzero(m == best[flat])
        np.minimum.at(first, flat[top], top)
        pick = top[first[flat[top]] == top]                 # one per voxel: its earliest best
        vox = flat[pick]
        better = m[pick] > out.manipulability[vox]
        out.manipulability[vox[better]] = m[pick[better]]
        out.best_q[vox[better]] = qs[pick[better]]
        best[vox] = -np.inf
        first[vox] = np.iinfo(np.int64).max
    return out


def _turned(v: np.ndarray, axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Vectors v (G, 3) each turned by its angles (G, S) about the unit axis (3,) (Rodrigues' formula):
    (G * S, 3), the S turns of each vector in a row."""
    along = np.outer(v @ axis, axis)                     # the part on the axis, which the turn keeps
    across = v - along
    normal = np.cross(axis, v)
    c, s = np.cos(angle)[:, :, None], np.sin(angle)[:, :, None]
    return (along[:, None, :] + across[:, None, :] * c + normal[:, None, :] * s).reshape(-1, 3)


def split(count: int, parts: int) -> list[tuple[int, int]]:
    """``count`` chunks as at most ``parts`` contiguous ranges (start, stop) of near-equal length, in order."""
    parts = max(1, min(int(parts), count))
    edges = [count * i // parts for i in range(parts + 1)]
    return [(a, b) for a, b in zip(edges[:-1], edges[1:]) if b > a]


def run_local(plan: Plan, threads: int | None = None) -> Partial:
    """Every chunk of the plan in this process: on ``threads`` threads (default: ``robkin.get_threads()``),
    one contiguous range of chunks each (its kernels on one thread), the ranges folded in order.

    A thread per range rather than the kernels' own threads: the sampling, the direction search and
    the per-voxel maximum are NumPy work that would otherwise run on one core between the kernels'
    parallel calls (NumPy releases the GIL in each of them).
    """
    from ..threads import get_threads

    count = chunks(plan.samples)
    workers = get_threads() if threads is None else int(threads)
    ranges = split(count, workers)
    if len(ranges) <= 1:
        return run_chunks(plan, 0, count, 1)
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(max_workers=len(ranges)) as pool:
        parts = list(pool.map(lambda r: run_chunks(plan, r[0], r[1], 1), ranges))
    out = parts[0]
    for part in parts[1:]:
        out.fold(part)
    return out
