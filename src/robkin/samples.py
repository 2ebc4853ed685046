"""Fixed, well-spread sample points for the FK cross-checks (no random generator needed).

The conversions, ``robkin check`` and the document reader compare two robots' FK at a handful of fixed
configurations. A seeded ``numpy.random`` generator would do, but importing ``numpy.random`` costs
~8-10 ms, a tenth of a whole ``robkin convert`` start-up, and these checks need spread, not randomness.
So the points come from an additive (Kronecker) recurrence: u_k = frac(1/2 + k alpha) with the
components of alpha the powers 1/phi_d, 1/phi_d^2, ..., 1/phi_d^d of the generalised golden ratio phi_d
(the positive root of x^(d+1) = x + 1), a sequence whose points spread evenly in any dimension d
(Roberts' "R_d" sequence). Written here because it is ten lines and no dependency offers it without
that import cost.
"""

from __future__ import annotations

import numpy as np

__all__ = ["unit_sample", "golden"]

_CACHE: dict[tuple[int, int], np.ndarray] = {}


def golden(d: int) -> float:
    """phi_d, the positive root of x^(d+1) = x + 1 (phi_1 is the golden ratio)."""
    x = 2.0
    # x <- (1 + x)^(1/(d+1)) contracts towards the root from above; 60 steps reach it to rounding for
    # every d (the contraction factor is at most 1/(d+1) * (1+x)^(-d/(d+1)) < 0.5).
    for _ in range(60):
        x = (1.0 + x) ** (1.0 / (d + 1))
    return x


def unit_sample(count: int, d: int) -> np.ndarray:
    """``count`` fixed points spread over the unit cube [0, 1)^d, the same on every call.

    Parameters
    ----------
    count : int
        Number of points (rows).
    d : int
        Dimension (columns), e.g. the number of joints.

    Returns
    -------
    (count, d) float array, read-only (cached per shape).
    """
    key = (count, d)
    U = _CACHE.get(key)
    if U is None:
        alpha = (1.0 / golden(d)) ** np.arange(1, d + 1)
        U = np.mod(0.5 + np.arange(1, count + 1)[:, None] * alpha[None, :], 1.0)
        U.setflags(write=False)
        _CACHE[key] = U
    return U
