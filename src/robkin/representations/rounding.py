"""Writing table values that are round up to rounding noise as exactly round, when FK allows it.

A table computed from a URDF or a PoE carries the rounding noise of the frame algebra: a twist that is
0 prints as -4.9e-12, an alpha that is pi/2 as 1.5707963267949, a length that is 0 as 3e-17. Vendor
tables print 0, pi/2 and 0. ``snap_rows`` writes such a value as the exact one (0 or a multiple of pi/2
for an angle, 0 for a length) only when a bound on what the change does to FK, summed over every
value it changes, stays below ``SNAP_BUDGET`` of the robot's size: the table is then FK-identical to
the robot to 1e-12 relative at every configuration, and a value that carries real geometry (a tilt of
1e-9 rad, a 1e-10 m offset) is kept as it is.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from ..compiled.conversions.tolerances import SNAP_BUDGET, SNAP_WINDOW
from ..robot import Joint
__all__ = ["SNAP_WINDOW", "SNAP_BUDGET", "snap_rows", "snap_many", "joint_travel", "travel"]

# SNAP_WINDOW (only values within 1e-9 of a round one are candidates) and SNAP_BUDGET (the FK change
# snapping may cause in total, 1e-12 of the robot's size) are defined, with why, beside the compiled
# table pipeline that shares them (compiled/conversions/tolerances.py).

_QUARTER = math.pi / 2


def joint_travel(joints: Sequence[Joint]) -> np.ndarray:
    """How far each joint moves its successors along its axis (n,): 0 for a revolute joint, the largest
    limit of a prismatic one (infinite if it has none)."""
    limits = np.array([[-math.inf if j.lower is None else j.lower, math.inf if j.upper is None else j.upper]
                       for j in joints])
    return travel(np.array([j.revolute for j in joints], dtype=bool), limits)


def travel(revolute: np.ndarray, limits: np.ndarray) -> np.ndarray:
    """``joint_travel`` from joint types (..., n) and limits (..., n, 2) (-inf / +inf where none)."""
    return np.where(revolute, 0.0, np.abs(limits).max(axis=-1))


def _levers(rows: np.ndarray, travel: np.ndarray, tool: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """For each row i (B robots, (B, n)), a bound on how far any point from row i to the tool lies from
    row i's frames.

    The sum of |a| + |d| over rows i..n, plus the travel of every prismatic joint among them, plus the
    tool's offset. Turning row i's alpha or theta by delta moves the tool by at most delta times this,
    at every configuration.
    """
    tail = np.abs(rows[..., 0]) + np.abs(rows[..., 1]) + travel
    # summed from the tool backwards, the tool's offset first (a running sum, in that order)
    acc = np.concatenate([np.linalg.norm(tool[:, :3, 3], axis=1)[:, None], tail[:, ::-1]], axis=1)
    levers = np.cumsum(acc, axis=1)[:, :0:-1]
    # a rotation's own effect on the tool's orientation, in length units of the robot's size
    return np.maximum(levers, scale[:, None])


def snap_rows(rows: np.ndarray, joints: Sequence[Joint], tool: np.ndarray, scale: float,
              budget: float = SNAP_BUDGET) -> np.ndarray:
    """Rows (n, 4 or 5) of (a, d, alpha, theta[, beta]) with near-round values made exactly round.

    Parameters
    ----------
    rows : (n, k) array
        Columns a, d (lengths) then angles (alpha, theta and, for Hayati, beta), radians.
    joints : sequence of Joint
        For the travel of prismatic joints (their limits).
    tool : (4, 4) array
        The tool transform after the last row (its offset lengthens every lever).
    scale : float
        The robot's size (``Robot.scale``).
    budget : float
        Total FK change allowed, relative to ``scale``.

    Returns
    -------
    (n, k) array
        A copy; candidates are taken cheapest first while the summed bound stays below the budget.
    """
    return snap_many(np.asarray(rows, dtype=float)[None], joint_travel(joints)[None], tool[None],
                     np.array([scale]), budget)[0]


def snap_many(rows: np.ndarray, travel: np.ndarray, tool: np.ndarray, scale: np.ndarray,
              budget: float = SNAP_BUDGET) -> np.ndarray:
    """``snap_rows`` for B robots with n joints each at once.

    Parameters
    ----------
    rows : (B, n, k) array
        Each robot's rows (lengths a, d, then angles in radians).
    travel : (B, n) array
        ``joint_travel`` of each robot's joints.
    tool : (B, 4, 4) array
        The tool transform after each robot's last row.
    scale : (B,) array
        Each robot's size.
    budget : float
        Total FK change allowed per robot, relative to its size.

    Returns
    -------
    (B, n, k) array
        A copy with each robot's candidates taken cheapest first (ties in row-major order) while its
        summed bound stays below its budget.
    """
    out = np.array(rows, dtype=float)
    B, n, k = out.shape
    target = np.zeros_like(out)
    target[..., 2:] = _QUARTER * np.round(out[..., 2:] / _QUARTER) + 0.0
    window = np.empty_like(out)
    window[..., :2] = SNAP_WINDOW * scale[:, None, None]
    window[..., 2:] = SNAP_WINDOW
    lever = np.ones_like(out)  # lengths: a change moves the tool by exactly that much
    lever[..., 2:] = _levers(out, travel, tool, scale)[..., None]
    off = np.abs(out - target)
    cand = (out != target) & (off <= window) & np.isfinite(lever)
    if cand.any():
        cost = np.full_like(out, np.inf)
        cost[cand] = off[cand] * lever[cand]  # (an unbounded lever times 0 elsewhere would be NaN)
        cost = cost.reshape(B, n * k)
        order = np.argsort(cost, axis=1, kind="stable")  # cheapest first; ties in row-major order
        spent = np.cumsum(np.take_along_axis(cost, order, axis=1), axis=1)
        take = np.zeros((B, n * k), dtype=bool)
        np.put_along_axis(take, order, spent < budget * scale[:, None], axis=1)
        take = take.reshape(B, n, k) & cand
        out[take] = target[take]
    # pi/2 multiples that came out as -pi are written as +pi, as tidy_angle does for computed angles
    angles = out[..., 2:]
    angles[angles == -math.pi] = math.pi
    return out
