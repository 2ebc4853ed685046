"""``WorkspaceMap`` and ``reachability_map``: where the tool of a robot can go, and with which approach
directions, on a voxel grid in the robot base frame.

Method: sampling. Configurations are drawn uniformly between the joint limits (``sampling``; in
groups of 8 that differ only in a revolute joint 1, whose tool poses are one FK's turned about joint 1's
axis), each one's tool pose is binned: its origin marks a voxel, the direction of its z axis (the approach
axis) marks the nearest of K directions of a near-uniform sphere lattice (``grid.sphere_directions``).
So ``reachable[i, j, k]`` counts the approach directions (within a ~sqrt(4/K) rad cone each) in
which the tool origin reaches voxel (i, j, k); the roll about the approach axis is not binned (a
6- or 7-joint wrist usually turns it freely; a map over full SO(3) bins would need K in the thousands
for cells as fine as these cones). Every mark is made by a configuration inside the limits, so a map
never claims a voxel that cannot be reached; what it can miss is a sliver reached by a small volume
of configurations (see docs/workspace.md for the measured agreement with brute force).

Sampling rather than IK per voxel and direction: a configuration costs ~0.5 us (FK, manipulability and
the binning), so tens of millions fit in a minute on one core, while a numeric IK call per (voxel, direction) cell
(~2 million cells for a 5 cm Panda map with K = 50) costs tens of us each and still has to decide
"unreachable" from a failure to converge.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..robot import Robot
from .grid import check_orientations, check_voxel, direction_bins, reach_box, sample_ranges, sphere_directions
from .sampling import Partial, Plan, run_local, sweep_of

__all__ = ["WorkspaceMap", "reachability_map", "default_samples", "KINDS"]

#: Manipulability measures a map may keep (``Robot.manipulability``'s kinds).
KINDS = ("translational", "rotational", "full")
#: Configurations of a 5 cm map: ~25 s of one core for the Panda (benchmarks/bench_workspace.py), where
#: 1e7 brute-force samples reach 99.7 % of its voxels; finer voxels need proportionally more
#: (``default_samples``).
SAMPLES_AT_5CM = 40_000_000


def default_samples(voxel: float) -> int:
    """Samples for a map of ``voxel`` metres: ``SAMPLES_AT_5CM`` times (0.05 / voxel)^3 (the same
    samples per voxel), at least 10^6."""
    return int(max(1_000_000, round(SAMPLES_AT_5CM * (0.05 / check_voxel(voxel)) ** 3)))


@dataclass(frozen=True, eq=False)
class WorkspaceMap:
    """A reachability map: voxels of the robot base frame, approach-direction bins, manipulability.

    Attributes
    ----------
    origin : (3,) array
        The grid's corner (the low corner of voxel (0, 0, 0)), robot base frame, m.
    voxel : float
        Voxel edge, m. Voxel (i, j, k) spans origin + voxel * [i, i+1) x [j, j+1) x [k, k+1).
    directions : (K, 3) array
        The orientation bins' unit vectors (base frame): bin d holds the tool z axes nearest to it.
    bins : (X, Y, Z, K) bool array
        Whether some sampled configuration puts the tool origin in the voxel with its z axis in bin d.
    manipulability : (X, Y, Z) array
        The largest manipulability (``kind``) over the samples in the voxel; NaN where none landed.
    best_q : (X, Y, Z, n) array
        The configuration that had it (a reaching configuration: a start for IK); NaN where none.
    samples, seed : int
        How the map was sampled (``reachability_map``).
    kind : str
        The manipulability measure (``Robot.manipulability``'s kind).
    joints : tuple of str
        The robot's joint names (the columns of ``best_q``).
    name : str
        The robot's name ('' if none).
    """

    origin: np.ndarray
    voxel: float
    directions: np.ndarray
    bins: np.ndarray
    manipulability: np.ndarray
    best_q: np.ndarray
    samples: int
    seed: int
    kind: str
    joints: tuple[str, ...]
    name: str = ""
    _reachable: list[Any] = field(default_factory=list, repr=False, compare=False)

    @property
    def shape(self) -> tuple[int, int, int]:
        """(X, Y, Z): voxels along each axis."""
        X, Y, Z = self.bins.shape[:3]
        return int(X), int(Y), int(Z)

    @property
    def reachable(self) -> np.ndarray:
        """(X, Y, Z) uint16: how many orientation bins each voxel reaches (0: unreachable)."""
        if not self._reachable:
            self._reachable.append(self.bins.sum(axis=-1, dtype=np.uint16))
        return self._reachable[0]

    def centers(self) -> np.ndarray:
        """Voxel centres (X, Y, Z, 3), base frame, m."""
        axes = [self.origin[a] + self.voxel * (np.arange(self.shape[a]) + 0.5) for a in range(3)]
        return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)

    def voxel_index(self, points: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Voxel indices (N, 3) of base-frame points (N, 3), and a mask (N,) of those inside the grid."""
        p = np.asarray(points, dtype=float).reshape(-1, 3)
        ijk = np.floor((p - self.origin) / self.voxel).astype(np.intp)
        inside = np.all((ijk >= 0) & (ijk < np.array(self.shape)), axis=1)
        return np.where(inside[:, None], ijk, 0), inside

    def reaches(self, T: ArrayLike) -> np.ndarray | bool:
        """Whether each pose ``T`` (4, 4) or (N, 4, 4) (base frame) falls in a marked (voxel, direction) cell.

        A screening, not a proof: the cell was reached by some configuration, with the tool origin
        somewhere in the voxel and its z axis within the bin's cone (roll free). ``Robot.ik`` decides a
        pose exactly (``best_q`` of the voxel is a good start).
        """
        poses = np.asarray(T, dtype=float)
        single = poses.ndim == 2
        poses = poses.reshape(-1, 4, 4)
        ijk, inside = self.voxel_index(poses[:, :3, 3])
        d = direction_bins(poses[:, :3, 2], self.directions)
        hit = self.bins[ijk[:, 0], ijk[:, 1], ijk[:, 2], d] & inside
        return bool(hit[0]) if single else hit

    def global_index(self) -> np.ndarray:
        """The grid's first voxel as whole voxels from the base origin (3,) int (maps of one voxel size are
        aligned: voxel (i, j, k) of this map is voxel global_index + (i, j, k) of any other)."""
        return np.rint(self.origin / self.voxel).astype(np.int64)


def reachability_map(robot: Robot, voxel: float = 0.05, orientations: int = 50, *, samples: int | None = None,
                     seed: int = 0, kind: str = "translational", threads: int | None = None,
                     dask: Any = None, tasks: int | None = None) -> WorkspaceMap:
    """Build a reachability map of ``robot`` by sampling its configurations (see the module).

    Parameters
    ----------
    robot : Robot
        Its joint limits bound the sampling (a revolute joint without limits: a full turn; a prismatic
        one must have limits).
    voxel : float
        Voxel edge, m (default 0.05).
    orientations : int
        K, the number of approach-direction bins (default 50; 1 for a position-only map).
    samples : int, optional
        Configurations sampled (default ``default_samples(voxel)``: 4e7 at 5 cm).
    seed : int
        The sampling's seed: the same seed and samples give the same map, locally or on Dask.
    kind : {'translational', 'rotational', 'full'}
        The manipulability measure kept per voxel (``Robot.manipulability``).
    threads : int, optional
        Threads in this process (default ``robkin.get_threads()``: every core); the map is the same
        bits on any number.
    dask : str or dask.distributed.Client, optional
        A Dask scheduler address ('tcp://host:8786') or a connected client: the chunks run there
        (``robkin.workspace.distributed``), and the map is the same bits as without.
    tasks : int, optional
        With ``dask``: how many tasks the chunks are split into (default: 4 per worker thread).

    Returns
    -------
    WorkspaceMap
        Cropped to the voxels reached.
    """
    if kind not in KINDS:
        raise InputError(f"kind: '{kind}' is not one of {', '.join(KINDS)}")
    v = check_voxel(voxel)
    k = check_orientations(orientations)
    total = default_samples(v) if samples is None else samples
    if isinstance(total, bool) or not isinstance(total, (int, np.integer)) or total < 1:
        raise InputError(f"samples: expected a whole number >= 1, got {samples!r}")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= seed < 2 ** 63:
        raise InputError(f"seed: expected a whole number 0 .. 2**63 - 1, got {seed!r}")
    origin, shape = reach_box(robot, v)
    lower, upper = sample_ranges(robot)
    plan = Plan(robot, origin, shape, v, sphere_directions(k), lower, upper, int(total), int(seed), kind,
                sweep_of(robot))
    if dask is not None:
        from .distributed import run_on_dask

        partial = run_on_dask(plan, dask, tasks)
    else:
        partial = run_local(plan, threads)
    return _cropped(plan, partial)


def _cropped(plan: Plan, partial: Partial) -> WorkspaceMap:
    """The finished map: the partial's arrays on the grid, cut to the box of the voxels reached."""
    X, Y, Z = plan.shape
    k, n = len(plan.directions), plan.robot.n
    bins = partial.bins.reshape(X, Y, Z, k)
    reached = np.argwhere(bins.any(axis=-1))
    lo, hi = reached.min(axis=0), reached.max(axis=0) + 1  # at least one sample lands somewhere
    cut = tuple(slice(a, b) for a, b in zip(lo, hi))
    manip = partial.manipulability.reshape(X, Y, Z)[cut].copy()
    best_q = partial.best_q.reshape(X, Y, Z, n)[cut].copy()
    manip[manip < 0] = np.nan
    return WorkspaceMap(origin=plan.origin + lo * plan.voxel, voxel=plan.voxel, directions=plan.directions,
                        bins=np.ascontiguousarray(bins[cut]), manipulability=manip, best_q=best_q,
                        samples=plan.samples, seed=plan.seed, kind=plan.kind,
                        joints=tuple(j.name for j in plan.robot.joints), name=plan.robot.name or "")
