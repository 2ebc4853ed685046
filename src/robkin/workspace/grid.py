"""The map's grid: a box of cubic voxels in the robot base frame that holds every tool position, and
the orientation bins (directions of the tool's z axis).

The box is fixed before any sampling, from the robot alone, so that every way of building a map (one
process, any number of threads, a Dask cluster) bins each sample into the same voxel: its corners lie
on multiples of the voxel size in the base frame, and it holds every reachable tool origin (a bound
from the chain's link lengths, ``reach_box``). The finished map is cropped to the voxels reached, which
keeps that alignment.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..errors import InputError, quote
from ..robot import Robot

__all__ = ["reach_box", "sample_ranges", "sphere_directions", "direction_bins", "check_voxel", "check_orientations"]

#: Largest number of voxels of the box before cropping: the map holds K orientation flags, one
#: manipulability and one configuration (n floats) per voxel, ~130 bytes a voxel for a 7-joint arm at
#: K = 50: 64 M voxels would be ~8 GB. Finer maps: a smaller arm region is not offered (yet); use a
#: coarser voxel.
MAX_VOXELS = 16 * 1024 * 1024
#: Most orientation bins (K): the per-sample nearest-direction search is an (N, K) product.
MAX_ORIENTATIONS = 4096


def check_voxel(voxel: float) -> float:
    """The voxel edge (m) as a positive finite float, else InputError naming ``voxel``."""
    try:
        v = float(voxel)
    except (TypeError, ValueError):
        raise InputError(f"voxel: expected a length in metres, got {voxel!r}") from None
    if not math.isfinite(v) or v <= 0:
        raise InputError(f"voxel: expected a positive length in metres, got {voxel!r}")
    return v


def check_orientations(k: int) -> int:
    """The number of orientation bins as an int in 1 .. MAX_ORIENTATIONS, else InputError."""
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or not 1 <= int(k) <= MAX_ORIENTATIONS:
        raise InputError(f"orientations: expected a whole number from 1 to {MAX_ORIENTATIONS}, got {k!r}")
    return int(k)


def sample_ranges(robot: Robot) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper joint values (n,) the map samples between: the joint limits; a revolute joint
    without limits turns through [-pi, pi] (every angle once). A prismatic joint needs limits (its
    workspace would be unbounded): InputError naming it."""
    lim = np.array(robot.limits, dtype=float)
    for i, joint in enumerate(robot.joints):
        if np.isfinite(lim[i]).all():
            continue
        if not joint.revolute:
            raise InputError(f"joint {quote(joint.name)}: a workspace map needs the limits of a prismatic joint "
                             f"(its travel would be unbounded)")
        lim[i] = (-math.pi, math.pi) if not np.isfinite(lim[i]).any() else (
            lim[i, 0] if np.isfinite(lim[i, 0]) else lim[i, 1] - 2 * math.pi,
            lim[i, 1] if np.isfinite(lim[i, 1]) else lim[i, 0] + 2 * math.pi)
    return lim[:, 0].copy(), lim[:, 1].copy()


def reach_box(robot: Robot, voxel: float) -> tuple[np.ndarray, tuple[int, int, int]]:
    """The grid's corner (3,) (m, base frame, a multiple of ``voxel``) and shape (nx, ny, nz).

    Every tool origin lies within R of joint 1's origin o_1 (fixed: a revolute joint turns about an
    axis through it): the distance between frame i's and frame i+1's origins never changes (frame i+1's
    origin is on its own axis, and the link between them is rigid), so the triangle inequality gives
    R = sum |o_{i+1} - o_i| (o_{n+1} the tool) plus each prismatic joint's largest travel.
    """
    v = check_voxel(voxel)
    lo, hi = sample_ranges(robot)
    origins = robot.frames[:, :3, 3]
    reach = float(np.linalg.norm(np.diff(origins, axis=0), axis=1).sum())
    reach += float(sum(max(abs(lo[i]), abs(hi[i])) for i in range(robot.n) if not robot.joints[i].revolute))
    centre = origins[0]
    # one voxel of margin each side: positions on the bound itself, and rounding of the products above
    first = np.floor((centre - reach) / v) - 1
    last = np.ceil((centre + reach) / v) + 1
    shape = tuple(int(s) for s in (last - first))
    voxels = shape[0] * shape[1] * shape[2]
    if voxels > MAX_VOXELS:
        raise InputError(f"voxel: {v:g} m gives a box of {shape[0]} x {shape[1]} x {shape[2]} voxels around this "
                         f"robot's reach ({reach:.3g} m); at most {MAX_VOXELS} voxels: use a larger voxel")
    return first * v, (shape[0], shape[1], shape[2])


def sphere_directions(k: int) -> np.ndarray:
    """K near-uniform unit vectors (K, 3): the Fibonacci (golden-angle) lattice on the sphere.

    Point i has z = 1 - (2i + 1)/K and azimuth i * pi * (3 - sqrt 5), so every point stands for an
    equal area 4 pi / K (a cap of ~sqrt(4/K) rad radius: ~16 degrees at K = 50). K = 1 is the single
    direction +z: one bin for every orientation, a position-only map.
    """
    k = check_orientations(k)
    if k == 1:
        return np.array([[0.0, 0.0, 1.0]])
    i = np.arange(k, dtype=float)
    z = 1.0 - (2.0 * i + 1.0) / k
    r = np.sqrt(np.maximum(0.0, 1.0 - z * z))
    phi = i * math.pi * (3.0 - math.sqrt(5.0))
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)


#: The direction lookup table: bands of equal height in z times sectors of equal azimuth.
_BANDS, _SECTORS = 256, 512
#: Largest K with a table: beyond it, a third of the cells and more are crossed by region boundaries,
#: and the table (built in ~K^2 operations per cell) no longer pays.
_TABLE_UP_TO = 256


def direction_bins(z: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """The bin of each unit direction z (N, 3): the index of the nearest of ``directions`` (K, 3) (largest
    dot product; the first on a tie), (N,) int.

    Exact, and ~10x faster than comparing every direction with every bin: a table over (z, azimuth)
    cells answers for a cell that lies wholly inside one bin's region (``_direction_table``); only
    directions in cells a region boundary crosses are compared with every bin.
    """
    z = np.asarray(z, dtype=float)
    if len(directions) == 1:
        return np.zeros(len(z), dtype=np.intp)
    if len(directions) > _TABLE_UP_TO:
        return np.argmax(z @ directions.T, axis=1)
    table = _direction_table(len(directions), directions.tobytes())
    # both >= 0 (z >= -1 and atan2 >= -pi, to rounding that truncation takes to 0); capped at the top
    band = np.minimum(((z[:, 2] + 1.0) * (_BANDS / 2)).astype(np.intp), _BANDS - 1)
    sector = np.minimum(((np.arctan2(z[:, 1], z[:, 0]) + math.pi) * (_SECTORS / (2 * math.pi))).astype(np.intp),
                        _SECTORS - 1)
    out = table.take(band * _SECTORS + sector).astype(np.intp)
    open_cells = np.flatnonzero(out < 0)
    if len(open_cells):
        out[open_cells] = np.argmax(z[open_cells] @ directions.T, axis=1)
    return out


@functools.lru_cache(maxsize=8)
def _direction_table(k: int, raw: bytes) -> np.ndarray:
    """Per (band, sector) cell: the bin every direction of the cell is nearest to, or -1 where that is
    not certain.

    Every direction u of a cell lies within rho of the cell's centre c (along the meridian to u's
    colatitude, then along that parallel: an upper bound of the great-circle distance). For bins d and
    b, u.b - u.d >= c.(b - d) - rho |b - d|; so when that bound is positive for the best bin b of the
    centre against every other d, b is nearest for the whole cell.
    """
    directions = np.frombuffer(raw, dtype=float).reshape(k, 3)
    edges = np.linspace(-1.0, 1.0, _BANDS + 1)
    colat = np.arccos(edges)                                   # decreasing with z
    zc = 0.5 * (edges[:-1] + edges[1:])
    colat_c = np.arccos(zc)
    along = np.maximum(colat[:-1] - colat_c, colat_c - colat[1:])
    sin_max = np.where((edges[:-1] < 0) & (edges[1:] > 0), 1.0, np.maximum(np.sin(colat[:-1]), np.sin(colat[1:])))
    # 1e-9 rad: a direction computed into a neighbouring cell by rounding (atan2, the products above:
    # ~1e-15) is still within rho of this cell's centre
    rho = np.repeat(along + sin_max * math.pi / _SECTORS + 1e-9, _SECTORS)
    azimuth = (np.arange(_SECTORS) + 0.5) * (2 * math.pi / _SECTORS) - math.pi
    Z, A = np.meshgrid(zc, azimuth, indexing="ij")
    r = np.sqrt(1.0 - Z * Z)
    centres = np.stack([r * np.cos(A), r * np.sin(A), Z], axis=-1).reshape(-1, 3)
    # |b - d| from the Gram matrix; cells in blocks, so that the (cells, K) temporaries stay ~10 MB
    spread_of = np.sqrt(np.maximum(0.0, 2.0 - 2.0 * (directions @ directions.T)))
    table = np.empty(len(centres), dtype=np.int32)
    block = max(1, 400_000 // k)
    for s in range(0, len(centres), block):
        dots = centres[s:s + block] @ directions.T
        best = np.argmax(dots, axis=1)
        gap = dots[np.arange(len(best)), best][:, None] - dots                 # c.(b - d)
        margin = gap - rho[s:s + block, None] * spread_of[best]                # > 0: d cannot beat b
        margin[np.arange(len(best)), best] = 1.0
        table[s:s + block] = np.where(np.all(margin > 0, axis=1), best, -1)
    table.setflags(write=False)
    return table
