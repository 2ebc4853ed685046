"""Cubic Bezier curves between a base frame and a target pose (the estimation paper's eqs. 11-15).

The curve leaves the base origin along the base z axis and arrives at the target origin along the
target z axis; its inner control points sit at half the base-target distance along those axes.
Joints of the type B and D estimates are placed on this curve at equal parameter steps.
"""

from __future__ import annotations

from math import comb

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["control_points", "bezier_points", "curve_points"]


def control_points(base: ArrayLike, target: ArrayLike) -> np.ndarray:
    """The four control points (4, 3) of the curve from ``base`` (4, 4) to ``target`` (4, 4).

    P1 = t_b, P2 = t_b + p z_b, P3 = t_p - p z_p, P4 = t_p with p = |t_p - t_b| / 2.
    """
    B = np.asarray(base, dtype=float)
    T = np.asarray(target, dtype=float)
    tb, tp = B[:3, 3], T[:3, 3]
    p = 0.5 * float(np.linalg.norm(tp - tb))
    return np.stack([tb, tb + p * B[:3, 2], tp - p * T[:3, 2], tp])


def bezier_points(control: ArrayLike, t: ArrayLike) -> np.ndarray:
    """Points (m, 3) of the Bezier curve with control points (k, 3) at parameters t (m,) in [0, 1].

    Bernstein form: B(t) = sum_j C(k-1, j) t^j (1 - t)^(k-1-j) P_j. At t = 0 and t = 1 it returns the
    end control points exactly (the other weights are exactly zero).
    """
    P = np.asarray(control, dtype=float)
    t = np.atleast_1d(np.asarray(t, dtype=float))
    deg = P.shape[0] - 1
    j = np.arange(deg + 1)
    weights = np.array([comb(deg, int(k)) for k in j], dtype=float) * t[:, None] ** j * (1 - t[:, None]) ** (deg - j)
    return weights @ P


def curve_points(base: ArrayLike, target: ArrayLike, count: int) -> np.ndarray:
    """``count`` points (count, 3) at equal parameter steps from the base origin to the target origin."""
    return bezier_points(control_points(base, target), np.linspace(0.0, 1.0, count))
