"""Which joint to name when two robots differ: the walk's mapping or the axes as they are.

The walk (``equivalence.walk``) explains B by A under a joint mapping q_A = s q_B + delta, matching
axes in order and solving each joint's zero offset as soon as a later axis depends on it. When the
robots differ, that greed can name the wrong joint: tilt joint k's axis about axis k-1 (where axis
k-1 passes through joint k's axis, as UR5's shoulder), and a zero offset of joint k-1 does carry
axis k onto its tilted place, but it turns every later axis (and the tool) with it, so the walk
reports "offset at joint k-1" and a difference at joint k+1, while joint k's axis is the only line
that moved.

``attribute`` weighs the two explanations by what each leaves unexplained: the number of joint axes
(lines in the base frame at the configuration each mapping puts A in) and tool poses that differ,
plus the zero offsets the mapping needs. The axes as they are (no offsets, the walk's signs) win when
they need fewer; then the first joint whose axis line differs is the one named.
"""

from __future__ import annotations

import numpy as np

from .walk import _Result, _describe, _screw_error, pose_difference
from ..robot import Robot

__all__ = ["attribute"]


def _differing(a: Robot, b: Robot, signs: np.ndarray, q: np.ndarray, scale: float, tol: float) -> list[int]:
    """Joints (0-based; n for the tool) whose axis line in A at configuration q is not B's at 0
    (directions taken with ``signs``), by the walk's own measure (``_screw_error``)."""
    n = min(a.n, b.n)
    moved = a.frames_at(q)
    SA = a.replace(frames=moved, frames_from=None).screws() * signs[:, None]
    SB = b.screws()
    out = [i for i in range(n)
           if a.joints[i].type != b.joints[i].type or _screw_error(SA[i], SB[i], scale) > tol]
    d, angle = pose_difference(moved[-1], b.tool)
    if d > tol * scale or angle > tol:
        out.append(n)
    return out


def attribute(a: Robot, b: Robot, result: _Result, scale: float, tol: float) -> _Result:
    """``result`` (the walk's), or the joint whose axis line differs first when naming it explains the
    difference with less (see the module). Only for robots of the same joint count the walk could not
    map (a failing joint, or a tool that differs after every joint matched)."""
    n = a.n
    if a.n != b.n or n == 0 or (result.failure is None and result.tool in ("same", "not compared")):
        return result
    signs = np.asarray(result.signs, dtype=float)
    offsets = np.asarray(result.offsets, dtype=float)
    tol_off = np.array([tol if j.revolute else tol * scale for j in a.joints])
    shifted = np.abs(offsets[:result.matched]) > tol_off[:result.matched]
    if not shifted.any():  # the walk named the first difference without moving any joint
        return result
    walked = _differing(a, b, signs, offsets, scale, tol)
    plain = _differing(a, b, signs, np.zeros(n), scale, tol)
    # the axes as they are must leave less unexplained, and name a joint no later than the walk's
    if not plain or len(plain) >= len(walked) + int(shifted.sum()) or plain[0] >= n or plain[0] > result.matched:
        return result
    k = plain[0]
    ja, jb = a.joints[k], b.joints[k]
    if ja.type != jb.type:
        why = f"type {ja.type} in A, {jb.type} in B"
    else:
        why = _describe(a.screws()[k] * signs[k], b.screws()[k], ja.revolute)
    return _Result(k, signs.copy(), np.zeros(n), why, "not compared")

