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

from ..robot import Joint

__all__ = ["SNAP_WINDOW", "SNAP_BUDGET", "snap_rows"]

#: Only values this close (radians, or relative to the robot's size for lengths) to a round one are
#: candidates: far above the rounding noise of the frame algebra (~1e-15 relative) and of inputs
#: written with 11 decimals (URDF files commonly write pi/2 as 1.57079632679, 4.9e-12 off), far below
#: any parameter a designer means (the budget below decides in the end).
SNAP_WINDOW = 1e-9
#: The FK change that snapping may cause in total, relative to the robot's size: 1e-12 is the
#: agreement promised for exact conversions, three orders above float64 rounding of a chain.
SNAP_BUDGET = 1e-12

_QUARTER = math.pi / 2


def _levers(rows: np.ndarray, joints: Sequence[Joint], tool: np.ndarray, scale: float) -> np.ndarray:
    """For each row i, a bound on how far any point from row i to the tool lies from row i's frames.

    The sum of |a| + |d| over rows i..n, plus the travel of every prismatic joint among them (its
    largest limit; unbounded if it has none), plus the tool's offset. Turning row i's alpha or theta by
    delta moves the tool by at most delta times this, at every configuration.
    """
    n = len(joints)
    own = np.abs(rows[:, 0]) + np.abs(rows[:, 1])
    travel = np.array([0.0 if j.revolute else max(abs(j.lower if j.lower is not None else math.inf),
                                                    abs(j.upper if j.upper is not None else math.inf))
                       for j in joints])
    tail = own + travel
    levers = np.empty(n)
    acc = float(np.linalg.norm(tool[:3, 3]))
    for i in range(n - 1, -1, -1):
        acc += float(tail[i])
        levers[i] = acc
    # a rotation's own effect on the tool's orientation, in length units of the robot's size
    return np.maximum(levers, scale)


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
    out = np.array(rows, dtype=float)
    levers = _levers(out, joints, tool, scale)
    cands: list[tuple[float, int, int, float]] = []
    for i, row in enumerate(out):
        for j, v in enumerate(row):
            if j < 2:  # lengths: a change moves the tool by exactly that much
                target, window, lever = 0.0, SNAP_WINDOW * scale, 1.0
            else:
                target, window, lever = _QUARTER * round(v / _QUARTER) + 0.0, SNAP_WINDOW, levers[i]
            if v != target and abs(v - target) <= window and math.isfinite(lever):
                cands.append((abs(v - target) * lever, i, j, target))
    spent, allowed = 0.0, budget * scale
    for cost, i, j, target in sorted(cands):
        if spent + cost >= allowed:
            break
        spent += cost
        out[i, j] = target
    # pi/2 multiples that came out as -pi are written as +pi, as tidy_angle does for computed angles
    angles = out[:, 2:]
    angles[angles == -math.pi] = math.pi
    return out
