"""Inverse reachability: where may the robot's base stand so that given task poses are reachable?

Candidate base frames B stand on a horizontal plane of the task's (world) frame: B = Trans(x, y, h)
Rz(yaw), on a grid of (x, y) and ``yaws`` headings. A task pose T (world) is, seen from a base at B,
B^-1 T; the map tells whether that pose's cell (voxel of its origin, bin of its z axis) was reached.
Each candidate scores the number of task poses reached, the tie broken by the sum of the map's
manipulability at their voxels. This is the map read backwards (inverting the transforms), a screening:
``verify`` runs ``Robot.ik`` on the best candidates to prove the poses reachable.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..checks import check_poses
from ..errors import InputError
from ..robot import Robot
from .grid import direction_bins
from .maps import WorkspaceMap

__all__ = ["Placement", "base_placement", "verify"]

#: Candidates x poses looked up per block: bounds the temporaries to ~100 MB whatever the grid.
_BLOCK = 2_000_000


@dataclass(frozen=True)
class Placement:
    """Scores of candidate base placements.

    Attributes
    ----------
    xs, ys : (nx,), (ny,) arrays
        Candidate base positions on the plane z = ``height`` (task frame, m).
    yaws : (m,) array
        Candidate headings (rad, about the plane's normal).
    height : float
    counts : (m, nx, ny) int array
        Task poses the map reaches from each candidate.
    dexterity : (m, nx, ny) array
        The sum of the map's manipulability at the voxels of the poses reached (the tie-break).
    poses : int
        How many task poses were asked.
    """

    xs: np.ndarray
    ys: np.ndarray
    yaws: np.ndarray
    height: float
    counts: np.ndarray
    dexterity: np.ndarray
    poses: int

    @property
    def best_count(self) -> np.ndarray:
        """(nx, ny): the most poses reached at each position, over the headings."""
        return self.counts.max(axis=0)

    def ranked(self, top: int = 10) -> list[dict[str, float]]:
        """The ``top`` best candidates: dicts x, y, z, yaw (rad), reached, dexterity; most poses first,
        then the largest dexterity. Candidates reaching no pose are left out."""
        flat_c, flat_d = self.counts.ravel(), self.dexterity.ravel()
        order = np.lexsort((-flat_d, -flat_c))
        out = []
        for idx in order[:max(0, int(top))]:
            if flat_c[idx] == 0:
                break
            w, i, j = np.unravel_index(idx, self.counts.shape)
            out.append({"x": float(self.xs[i]), "y": float(self.ys[j]), "z": self.height,
                        "yaw": float(self.yaws[w]), "reached": int(flat_c[idx]), "dexterity": float(flat_d[idx])})
        return out


def base_frame(x: float, y: float, z: float, yaw: float) -> np.ndarray:
    """Trans(x, y, z) Rz(yaw): a candidate base frame (4, 4) in the task frame."""
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s, 0, x], [s, c, 0, y], [0, 0, 1, z], [0, 0, 0, 1.0]])


def base_placement(wmap: WorkspaceMap, poses: ArrayLike, *, height: float = 0.0, yaws: int = 16,
                   step: float | None = None, margin: float | None = None) -> Placement:
    """Score base positions on the plane z = ``height`` by how many task poses the map reaches.

    Parameters
    ----------
    wmap : WorkspaceMap
    poses : (4, 4) or (P, 4, 4) array
        Task poses (the tool frame wanted), in the task (world) frame, m.
    height : float
        The plane the base stands on (task frame z, m).
    yaws : int
        Headings tried, evenly over a full turn (1: the base's x axis along the task's).
    step : float, optional
        Grid spacing of the candidate positions (default: the map's voxel).
    margin : float, optional
        How far beyond the poses' x-y extent candidates go (default: the map's horizontal reach, the
        farthest reached voxel centre from the base's z axis, plus a voxel).

    Returns
    -------
    Placement
    """
    T = np.asarray(poses, dtype=float)
    T = T[None] if T.ndim == 2 else T
    if T.ndim != 3 or T.shape[1:] != (4, 4) or len(T) == 0:
        raise InputError(f"poses: expected (4, 4) or (P, 4, 4) task poses, got shape {np.shape(poses)}")
    T = check_poses(T, lambda i: f"poses[{i}]")
    if isinstance(yaws, bool) or not isinstance(yaws, (int, np.integer)) or not 1 <= yaws <= 3600:
        raise InputError(f"yaws: expected a whole number of headings from 1 to 3600, got {yaws!r}")
    if not math.isfinite(height):
        raise InputError(f"height: expected a finite length, got {height!r}")
    step = wmap.voxel if step is None else float(step)
    if not math.isfinite(step) or step <= 0:
        raise InputError(f"step: expected a positive length, got {step!r}")
    if margin is None:
        c = wmap.centers()[wmap.reachable > 0]
        margin = float(np.hypot(c[:, 0], c[:, 1]).max()) + wmap.voxel
    elif not math.isfinite(margin) or margin < 0:
        raise InputError(f"margin: expected a length >= 0, got {margin!r}")
    p = T[:, :3, 3]
    xs = _axis(p[:, 0].min() - margin, p[:, 0].max() + margin, step)
    ys = _axis(p[:, 1].min() - margin, p[:, 1].max() + margin, step)
    if len(xs) * len(ys) * yaws > 50_000_000:
        raise InputError(f"step: {len(xs)} x {len(ys)} positions x {yaws} headings are too many candidates; "
                         f"use a larger step or fewer yaws")
    yaw = 2 * math.pi * np.arange(yaws) / yaws
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    offsets = np.stack([X.ravel(), Y.ravel(), np.full(X.size, float(height))], axis=1)  # (C, 3)
    manip = np.nan_to_num(wmap.manipulability, nan=0.0)
    counts = np.zeros((yaws, X.size), dtype=np.int64)
    dexterity = np.zeros((yaws, X.size))
    block = max(1, _BLOCK // len(T))
    for w, a in enumerate(yaw):
        Rt = base_frame(0, 0, 0, a)[:3, :3].T             # base axes <- task axes
        d = direction_bins(T[:, :3, 2] @ Rt.T, wmap.directions)  # (P,): a heading's bins, any position
        local = p @ Rt.T                                   # R^T p
        for s in range(0, X.size, block):
            o = offsets[s:s + block] @ Rt.T                # R^T t: the base origin seen in base axes
            pts = local[None, :, :] - o[:, None, :]        # (C, P, 3) R^T (p - t)
            ijk, inside = wmap.voxel_index(pts.reshape(-1, 3))
            hit = wmap.bins[ijk[:, 0], ijk[:, 1], ijk[:, 2], np.tile(d, len(o))] & inside
            m = np.where(hit, manip[ijk[:, 0], ijk[:, 1], ijk[:, 2]], 0.0)
            counts[w, s:s + block] = hit.reshape(len(o), -1).sum(axis=1)
            dexterity[w, s:s + block] = m.reshape(len(o), -1).sum(axis=1)
    shape = (yaws, len(xs), len(ys))
    return Placement(xs, ys, yaw, float(height), counts.reshape(shape), dexterity.reshape(shape), len(T))


def _axis(lo: float, hi: float, step: float) -> np.ndarray:
    """Grid values on multiples of ``step`` covering [lo, hi]."""
    return step * np.arange(math.floor(lo / step), math.ceil(hi / step) + 1)


def verify(robot: Robot, poses: ArrayLike, candidate: dict[str, float], **ik_options: object) -> np.ndarray:
    """Which task ``poses`` (P, 4, 4) ``robot``'s ``Robot.ik`` reaches from a ``candidate`` base (a dict of ``Placement.ranked``).

    Returns (P,) bool: the IK's success for B^-1 T of each pose (within the joint limits, at the IK's
    default tolerances); ``ik_options`` go to ``Robot.ik``.
    """
    T = np.asarray(poses, dtype=float).reshape(-1, 4, 4)
    B = base_frame(candidate["x"], candidate["y"], candidate["z"], candidate["yaw"])
    local = np.linalg.inv(B) @ T
    result = robot.ik(local, **ik_options)
    return np.asarray(result.success, dtype=bool).reshape(-1)
