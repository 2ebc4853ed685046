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

__all__ = ["CHUNK", "Plan", "Partial", "chunks", "split", "run_chunks", "run_local"]

#: Configurations per chunk: large enough that the kernels' per-call cost (~50 us) is lost in the work
#: and NumPy's per-array overhead too, small enough that a chunk's temporaries (FK poses: 128 bytes a
#: sample) stay ~10 MB.
CHUNK = 65536


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


def run_chunks(plan: Plan, start: int, stop: int, threads: int | None = None) -> Partial:
    """The partial map of chunks ``start`` .. ``stop - 1`` of the plan, folded in order.

    ``threads`` bounds the FK and manipulability kernels' threads (see ``robkin.threads``).
    """
    out = Partial(plan)
    robot, n = plan.robot, plan.robot.n
    shape = np.array(plan.shape)
    k = len(plan.directions)
    span = plan.upper - plan.lower
    for c in range(start, stop):
        size = min(CHUNK, plan.samples - c * CHUNK)
        if size <= 0:
            break
        rng = np.random.default_rng([plan.seed, c])
        q = plan.lower + span * rng.random((size, n))
        T = robot.fk(q, threads=threads)
        ijk = np.floor((T[:, :3, 3] - plan.origin) / plan.voxel).astype(np.intp)
        # the box holds every reachable position with a voxel to spare (grid.reach_box); the clip only
        # guards against rounding at its edge
        np.clip(ijk, 0, shape - 1, out=ijk)
        flat = (ijk[:, 0] * shape[1] + ijk[:, 1]) * shape[2] + ijk[:, 2]
        out.bins[flat * k + direction_bins(T[:, :3, 2], plan.directions)] = True
        m = np.asarray(robot.manipulability(q, plan.kind, threads=threads))
        # per voxel, the sample of largest manipulability (the earliest on a tie: lexsort is stable)
        order = np.lexsort((-m, flat))
        sorted_flat = flat[order]
        first = np.ones(size, dtype=bool)
        first[1:] = sorted_flat[1:] != sorted_flat[:-1]
        pick = order[first]
        vox = flat[pick]
        better = m[pick] > out.manipulability[vox]
        out.manipulability[vox[better]] = m[pick[better]]
        out.best_q[vox[better]] = q[pick[better]]
    return out


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
