"""Quantities of stacks of GJD frames (..., n+1, 4, 4), for one robot or many at once.

``Robot`` uses them for its own frames (``Robot.scale``, the compiled FK's fixed transforms); the batch
conversions (``representations.placement``) apply them to B robots in one call.
"""

from __future__ import annotations

import numpy as np

from . import se3

__all__ = ["frame_scales", "local_transforms"]


def frame_scales(frames: np.ndarray) -> np.ndarray:
    """``Robot.scale`` of B robots at once from their GJD frames (B, n+1, 4, 4): (B,) lengths."""
    p, z = frames[:, :-1, :3, 3], frames[:, :-1, :3, 2]
    feet = p - np.einsum("bij,bij->bi", p, z)[..., None] * z
    s = np.maximum(np.linalg.norm(frames[:, -1, :3, 3], axis=-1),
                   np.linalg.norm(feet, axis=-1).max(axis=-1))
    # Every axis through the base origin and the tool at it, up to rounding (a robot along one
    # line: coincident axes offset only along them): the axis distances are rounding noise
    # (seen: 1e-28) and say nothing about size, while the frame origins along the axes do.
    # 1e-9: far above the rounding of coordinates (~1e-16 relative), far below any real offset.
    origins = np.linalg.norm(frames[:, :, :3, 3], axis=-1).max(axis=-1)
    s = np.where(s <= 1e-9 * origins, origins, s)
    # Conversions compute with the frame origins, so tolerances must stay above their rounding
    # (eps times their size): the scale is never below 1/1000 of the farthest origin. Only 1/1000,
    # because a frame may sit far along its axis (the common normal of nearly parallel axes)
    # without the robot being any bigger, and tolerances that large would be too loose for it.
    s = np.maximum(s, 1e-3 * origins)
    return np.where(s > 0, s, 1.0)


def local_transforms(frames: np.ndarray) -> np.ndarray:
    """Fixed transforms L (..., n+1, 4, 4) of GJD frames (..., n+1, 4, 4), as ``Robot._local`` (the
    compiled FK's input): L_1 = J_1 and L_i = J_{i-1}^-1 J_i."""
    L = np.empty_like(frames)
    L[..., 0, :, :] = frames[..., 0, :, :]
    L[..., 1:, :, :] = se3.inv(frames[..., :-1, :, :]) @ frames[..., 1:, :, :]
    return L
