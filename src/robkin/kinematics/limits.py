"""Joint limits for IK solutions: choosing the 2*pi turn of a revolute joint, and limit checks."""

from __future__ import annotations

import numpy as np

from ..compiled.ik.limits import wrap

__all__ = ["wrap_into_limits", "within_limits", "default_preference", "LIMIT_TOL"]

#: Slack on limit checks: a solution computed on a limit (clipped there, or a closed-form angle equal
#: to it) may differ from it by rounding of a few ulps of 2*pi; 1e-12 covers that and nothing more.
LIMIT_TOL = 1e-12


def wrap_into_limits(Q: np.ndarray, limits: np.ndarray, revolute: np.ndarray,
                     q_ref: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Revolute values shifted by multiples of 2*pi into their limits, nearest to q_ref.

    Parameters
    ----------
    Q : (..., n) array
        Joint values (radians for revolute joints, lengths for prismatic ones).
    limits : (n, 2) array
        Lower and upper limits, -inf/+inf where none.
    revolute : (n,) bool array
    q_ref : (..., n) array, optional
        Preferred values (default 0): among the turns within the limits, the one nearest to q_ref.

    Returns
    -------
    Q_wrapped : (..., n) array
        The same poses; revolute joints moved by whole turns. Unlimited revolute joints end up within
        pi of q_ref.
    ok : (...) bool array
        Whether every joint is within its limits (prismatic joints are only checked).
    """
    Q = np.asarray(Q, dtype=float)
    if Q.ndim == 2 and q_ref is not None and np.shape(q_ref) == Q.shape:   # the IK case: no reshaping
        return wrap(Q, limits[:, 0], limits[:, 1], revolute, q_ref, LIMIT_TOL)
    n = Q.shape[-1]
    ref = np.zeros_like(Q) if q_ref is None else np.broadcast_to(q_ref, Q.shape)
    out, ok = wrap(Q.reshape(-1, n), limits[:, 0], limits[:, 1], revolute, ref.reshape(-1, n), LIMIT_TOL)
    return out.reshape(Q.shape), ok.reshape(Q.shape[:-1])


def within_limits(Q: np.ndarray, limits: np.ndarray) -> np.ndarray:
    """(...) bool: every joint of Q (..., n) within [lower, upper] up to LIMIT_TOL."""
    return np.all((Q >= limits[:, 0] - LIMIT_TOL) & (Q <= limits[:, 1] + LIMIT_TOL), axis=-1)


def default_preference(limits: np.ndarray) -> np.ndarray:
    """(n,) the default start of IK when the caller gives no ``q0``: inside every joint's limits.

    Each joint starts at zero where zero lies within its limits (the robot's own home: nothing changes for
    an arm whose ranges all contain it), else at the midpoint of its range, the value farthest from both
    limits. (Zero clipped into the range would sit on a limit: the Panda's joint 4, range [-3.07, -0.07],
    would start at -0.07, an elbow stretched straight against its stop, a singular start from which the
    numeric solver wanders to a contorted answer.) A range with one infinite end takes the finite limit
    nearest zero when zero lies outside it (no midpoint exists).

    Parameters
    ----------
    limits : (n, 2) array
        Lower and upper limits (radians or length units), -inf / +inf where none.

    Returns
    -------
    (n,) array
        The default start; within ``limits`` on every joint.
    """
    lower, upper = limits[:, 0], limits[:, 1]
    inside = (lower <= 0.0) & (upper >= 0.0)
    finite = np.isfinite(lower) & np.isfinite(upper)
    with np.errstate(invalid="ignore"):     # inf + -inf where a range is unbounded: not used there
        middle = 0.5 * (lower + upper)
    return np.where(inside, 0.0, np.where(finite, middle, np.minimum(np.maximum(0.0, lower), upper)))
