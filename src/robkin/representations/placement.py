"""DH and modified DH tables of many robots at once: the one pipeline behind ``dh_from_robot(s)`` and
``mdh_from_robot(s)``.

Robots are grouped by joint count; each group goes through every stage as whole arrays:

1. frame placement and the rows between the frames (the canonical rules of
   ``frames.common_normal_frame`` along the whole chain), values within rounding of 0 or a multiple
   of pi/2 written exactly (``rounding.snap_many``, for robots whose frames are not already those of
   a table of the same kind) and the residual tool: compiled, one robot after another in C
   (``robkin.compiled.conversions.frames.convert_tables``, on several threads for a large batch);
3. validation of every base and tool pose (``robot.check_poses``);
4. the mass properties of robots that have them (``Robot.bodies.inertials``), merged per link and
   expressed in the table's own link frames (``mass_rows.masses_of_robot``);
5. the FK self-check, compiled as well (``check_tables``): each table's FK (from its rows) against
   the robot's compiled FK at q = 0 and the fixed sample of ``link_table.check_configurations``; a
   table off by more than WARN_TOL gets a ConditioningWarning stating its measured error.

A single robot is a batch of one, so ``dh_from_robot(robot)`` and ``dh_from_robots([robot])[0]`` are
the same table, bit for bit.
"""

from __future__ import annotations

from typing import Sequence, TypeVar

import numpy as np

from ..errors import InputError
from ..frame_stacks import frame_scales, local_transforms
from ..robot import Robot, check_poses
from .link_table import _CHECK_SAMPLES as CHECK_SAMPLES
from .link_table import FLIP_X, WARN_TOL, LinkTable, report_fk_error
from .mass_rows import masses_of_robot

__all__ = ["tables_from_robots", "place_frames"]

Table = TypeVar("Table", bound=LinkTable)


def joint_frames(frames: np.ndarray, flip: np.ndarray) -> np.ndarray:
    """Joint frames (B, n, 4, 4) from GJD frames (B, n + 1, 4, 4), each turned by pi about x where its
    joint is flipped (``flip`` (B, n); ``link_table.flip_frame``)."""
    cand = frames[:, :-1].copy()
    if flip.any():
        cand[flip] = cand[flip] @ FLIP_X
    return cand


def place_frames(section: str, robots: Sequence[Robot]) -> tuple[np.ndarray, np.ndarray]:
    """Frames {0}..{n} (B, n + 1, 4, 4) and unrounded rows (B, n, 4) of ``section`` ('dh' or 'mdh')
    for robots with n joints each; a robot's own frames are kept (where they satisfy the convention)
    only if they are a table of that section's frames (``Robot.frames_from``)."""
    frames = np.stack([r.frames for r in robots])
    flip = np.array([[j.flip for j in r.joints] for r in robots], dtype=bool)
    return _place(section, robots, frames, flip, frame_scales(frames))


def _place(section: str, robots: Sequence[Robot], frames: np.ndarray, flip: np.ndarray,
           scale: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    from ..compiled.conversions.frames import placement

    cand = joint_frames(frames, flip)
    keep = np.array([r.frames_from == section for r in robots])
    return placement(section == "mdh", cand, frames[:, -1], scale, keep)


def tables_from_robots(cls: type[Table], robots: Sequence[Robot], *, label: bool = True,
                       stacklevel: int = 3, threads: int | None = None) -> list[Table]:
    """Tables of class ``cls`` (DHTable or MDHTable) of the robots, in their order.

    Parameters
    ----------
    cls : type
        The table class; its ``SECTION`` ('dh' or 'mdh') selects the frame rules.
    robots : sequence of Robot
        Any joint counts (>= 1); robots with the same count are converted together.
    label : bool
        Prefix each warning with the robot's position (``robots[i]: ``), for batches.
    stacklevel : int
        Of the warnings, counted from this function (so that they point at the caller's caller).
    threads : int >= 1, optional
        At most this many threads for the compiled stages (default: automatic, ``robkin.threads``);
        the tables are the same bits with any number.
    """
    from ..checks import check_threads

    t = 0 if threads is None else check_threads(threads)
    robots = list(robots)
    for i, r in enumerate(robots):
        if not isinstance(r, Robot):
            raise InputError(f"robots[{i}]: expected a robkin.Robot, got {type(r).__name__}")
    out: list[Table | None] = [None] * len(robots)
    groups: dict[int, list[int]] = {}
    for i, r in enumerate(robots):
        groups.setdefault(r.n, []).append(i)
    for idx in groups.values():
        for i, table in zip(idx, _convert_group(cls, [robots[i] for i in idx], idx, label, stacklevel + 1, t)):
            out[i] = table
    tables: list[Table] = out  # type: ignore[assignment]  # every slot filled above
    for i, r in enumerate(robots):
        if r.bodies.inertials:  # the mass properties, in the table's own link frames
            tables[i] = tables[i].with_masses(masses_of_robot(r, tables[i].link_frames()))
    return tables


def _convert_group(cls: type[Table], robots: list[Robot], idx: list[int], label: bool,
                   stacklevel: int, threads: int) -> list[Table]:
    """``tables_from_robots`` for robots that all have the same joint count."""
    from ..compiled.conversions.frames import check_tables, convert_tables
    from ..samples import unit_sample

    section = cls.SECTION
    modified = section == "mdh"
    B = len(robots)
    if B == 1:  # one robot: its own cached size and fixed transforms (the same functions' values)
        robot = robots[0]
        frames = robot.frames[None]
        scale = np.array([robot.scale])
        local = robot._local[None]
    else:
        frames = np.stack([r.frames for r in robots])  # (B, n + 1, 4, 4)
        scale = frame_scales(frames)  # Robot.scale, for all at once
        local = local_transforms(frames)
    # every joint's (revolute, flip, lower, upper) in one pass: (B, n, 4)
    J = np.array([[(j.revolute, j.flip, -np.inf if j.lower is None else j.lower,
                    np.inf if j.upper is None else j.upper) for j in r.joints] for r in robots], dtype=float)
    # placement, rounding of near-round values (robots whose frames are not already this kind's
    # table) and the residual tool, compiled
    rows, base, tool = convert_tables(modified, frames, J, [r.frames_from == section for r in robots],
                                      [r.frames_from != section for r in robots], scale, FLIP_X, threads)
    if not np.isfinite(rows).all():  # cannot happen for a valid robot: let the table explain
        bad = int(np.flatnonzero(~np.isfinite(rows).all(axis=(1, 2)))[0])
        cls(rows[bad], robots[bad].joints, base=base[bad], tool=tool[bad])
    poses = check_poses(np.concatenate([base, tool]),
                        lambda k: f"{section}.{'base' if k < B else 'tool'}")
    base, tool = poses[:B], poses[B:]
    tables = [cls._from_checked(rows[k], r.joints, base[k], tool[k]) for k, r in enumerate(robots)]
    # the FK self-check: each table's FK from its rows against the robot's compiled FK, at the same
    # configurations (``link_table.sample_configurations``), and each table's longest length
    err, lengths = check_tables(modified, base, rows, tool, local, J, scale,
                                unit_sample(CHECK_SAMPLES, rows.shape[1]), threads)
    off = err > WARN_TOL * scale
    if off.any():  # (the test first: flatnonzero costs more than the check of a single table)
        for k in np.flatnonzero(off):
            report_fk_error(float(err[k]), robots[k], section, where=f"robots[{idx[k]}]: " if label else "",
                            stacklevel=stacklevel + 1)
    from .long_lengths import LONG_FACTOR, warn_long_lengths

    long = lengths > LONG_FACTOR * scale
    if long.any():
        for k in np.flatnonzero(long):
            warn_long_lengths(section, rows[k], base[k], tool[k], robots[k].axes, float(scale[k]),
                              where=f"robots[{idx[k]}]: " if label else "", stacklevel=stacklevel + 1)
    return tables
