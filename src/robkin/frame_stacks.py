"""Quantities of stacks of GJD frames (..., n+1, 4, 4), for one robot or many at once.

``Robot`` uses them for its own frames (``Robot.scale``, the compiled FK's fixed transforms); the batch
conversions (``representations.placement``) apply them to B robots in one call. Both are compiled
(``robkin.compiled.runtime.rigid.frame_stacks``: a few microseconds per robot, where NumPy's small-array calls
cost tens), with NumPy's arithmetic, so the values are those the NumPy expressions below give.
"""

from __future__ import annotations

import numpy as np

__all__ = ["frame_scales", "local_transforms"]


def frame_scales(frames: np.ndarray) -> np.ndarray:
    """``Robot.scale`` of B robots at once from their GJD frames (B, n+1, 4, 4): (B,) lengths.

    With p_i, z_i the origin and z axis of joint frame i and feet_i = p_i - (p_i . z_i) z_i (the foot of
    the base origin on axis i): s = max(|tool origin|, max_i |feet_i|). Every axis through the base
    origin and the tool at it, up to rounding (a robot along one line: coincident axes offset only
    along them), makes the axis distances rounding noise (seen: 1e-28) that says nothing about size,
    while the frame origins along the axes do: where s <= 1e-9 * (the farthest frame origin), s is that
    origin's distance (1e-9: far above the rounding of coordinates, ~1e-16 relative, far below any real
    offset). Conversions compute with the frame origins, so tolerances must stay above their rounding
    (eps times their size): s is never below 1/1000 of the farthest origin. Only 1/1000, because a
    frame may sit far along its axis (the common normal of nearly parallel axes) without the robot
    being any bigger, and tolerances that large would be too loose for it. 1 when everything is at
    the origin.
    """
    from .compiled.runtime.rigid import frame_stacks

    return frame_stacks(frames, True, False)[0]


def local_transforms(frames: np.ndarray) -> np.ndarray:
    """Fixed transforms L (..., n+1, 4, 4) of GJD frames (..., n+1, 4, 4), as ``Robot._local`` (the
    compiled FK's input): L_1 = J_1 and L_i = J_{i-1}^-1 J_i (``se3.inv(J_{i-1}) @ J_i``)."""
    from .compiled.runtime.rigid import frame_stacks

    F = np.asarray(frames, dtype=float)
    return frame_stacks(F.reshape((-1,) + F.shape[-3:]), False, True)[1].reshape(F.shape)
