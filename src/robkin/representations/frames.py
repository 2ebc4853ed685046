"""Placing DH-style frames on joint axes: the geometric step shared by DH, modified DH and PoE.

Two consecutive axes A (current/previous) and B (next) fix a common normal. Standard DH puts frame i
on axis B with x along the normal from A; modified (Craig) DH puts frame i on axis A with x along the
normal towards B. Both are ``common_normal_frame`` with the frame placed on one line or the other.

Canonical choices where the convention leaves freedom (documented in the README):

- skew or intersecting axes: x = +-(u_A x u_B) / |u_A x u_B|, the sign chosen so that |theta| <= pi/2
  (x . x_prev >= 0; on a tie, theta = +pi/2). The sign of ``a`` and ``alpha`` follow from that, so a
  may be negative (as in most vendor tables) but theta never needs to be pi where a flip avoids it.
- parallel axes: the common normal through the previous frame's origin, so d = 0; x sign as above.
- coincident axes: x of the previous frame is kept (a = d = alpha = theta = 0); anti-coincident: the
  previous frame turned by pi about x (alpha = pi).
- a frame the input already gave that satisfies the convention is kept as it is (``keep``), so a DH
  table read in and written out again comes back unchanged. The callers pass ``keep`` only for frames
  that came from a table of the same kind (``Robot.frames_from``): frames of a URDF, PoE or RPY-XYZ
  input are always placed by the rules above, so every robot gets the same canonical table.
- frame {0} is placed from the robot base z axis by the same rules (the previous frame is the base),
  so it lies where that axis meets joint 1's axis and is the base itself when they coincide.
"""

from __future__ import annotations

import math

import numpy as np

from ..compiled.conversions.tolerances import KEEP_TOL
__all__ = ["common_normal_frame", "frame_from_zx", "satisfies_normal", "dh_params_between",
           "mdh_params_between", "approx_dh_params", "is_identity", "identity_mask", "x_line_on",
           "relative_pose"]

# KEEP_TOL (a given frame is kept only if it satisfies the convention to rounding noise, 1e-12) and
# TIE_TOL (|cos theta| below which theta is taken as +-pi/2, 1e-9) are defined, with why they are what
# they are, beside the compiled kernel that shares them (compiled/conversions/tolerances.py).


def is_identity(T: np.ndarray, scale: float, tol: float = KEEP_TOL) -> bool:
    """Is the pose the identity to rounding noise (rotation to ``tol``, translation to ``tol * scale``)?"""
    return bool(identity_mask(T, np.asarray(scale), tol))


def identity_mask(T: np.ndarray, scale: np.ndarray, tol: float = KEEP_TOL) -> np.ndarray:
    """``is_identity`` for poses (..., 4, 4) with scales (...): a boolean array (...)."""
    return ((np.abs(T[..., :3, :3] - np.eye(3)).max(axis=(-2, -1)) <= tol)
            & (np.abs(T[..., :3, 3]).max(axis=-1) <= tol * scale))


def frame_from_zx(origin: np.ndarray, z: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Pose (4, 4) with the given origin (3,), unit z (3,), and x (3,) made exactly orthogonal to z
    and unit (Gram-Schmidt twice: a given x nearly along z, e.g. a common-normal direction that is
    rounding noise, leaves x . z ~ 1e-10 after one pass; "twice is enough", Parlett)."""
    from ..compiled.conversions.frames import frame_from_zx as compiled

    return compiled(origin, z, x)


def satisfies_normal(frame: np.ndarray, p_other: np.ndarray, u_other: np.ndarray, scale: float,
                     tol: float = KEEP_TOL) -> bool:
    """Does the frame's (4, 4) x axis cross the other line (point, unit direction) at a right angle
    (the DH requirement), to ``tol`` (cosine) and ``tol * scale`` (distance)?"""
    from ..compiled.conversions.frames import satisfies_normal as compiled

    return compiled(frame, p_other, u_other, scale, tol)


def common_normal_frame(p_a: np.ndarray, u_a: np.ndarray, p_b: np.ndarray, u_b: np.ndarray, *,
                        on: str, prev: np.ndarray, scale: float,
                        keep: np.ndarray | None = None) -> np.ndarray:
    """Frame on line A or B (``on`` = 'a' | 'b') whose x axis is the common normal from A to B.

    The rules (module docstring) run compiled (``robkin.compiled.conversions.frames``), the one implementation
    that the whole-chain placements of ``dh_from_robot(s)`` and ``mdh_from_robot(s)`` use as well.
    The axes are classified with the tolerances of ``robkin.lines``; x signs use TIE_TOL.

    Parameters
    ----------
    p_a, u_a, p_b, u_b : (3,) arrays
        Point and unit direction of each line. The frame's z is u_a (on='a') or u_b (on='b').
    prev : (4, 4) array
        The previous frame of the chain. Its x axis is the reference for the sign choice and is kept
        for coincident axes; its origin anchors the normal of parallel axes. For on='b' its z is u_a
        (standard DH); for on='a' its x axis crosses line A (modified DH).
    scale : float
        Robot size for the relative length tolerance.
    keep : (4, 4) array, optional
        A frame the input gave on the same line; returned unchanged if it satisfies the convention.
    """
    if on not in ("a", "b"):
        raise ValueError(f"on must be 'a' or 'b', not {on!r}")
    from ..compiled.conversions.frames import common_normal_frame as compiled

    return compiled(p_a, u_a, p_b, u_b, on == "b", prev, scale, keep)


def x_line_on(prev: np.ndarray, p: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Where the x axis of ``prev`` (4, 4) meets the line (p, u); the foot of prev's origin if they
    miss (x within ANGLE_TOL of parallel to the line). Returns (3,)."""
    from ..compiled.conversions.frames import x_line_on as compiled

    return compiled(prev, p, u)


def tidy_angle(angle: float) -> float:
    """An angle in (-pi, pi]: -pi (and values within rounding noise of it) become +pi, -0.0 becomes 0."""
    # 1e-12: atan2 of entries that are exactly 0 up to rounding returns +-pi for the same geometry;
    # print one of them. The FK effect of the change is below 1e-12 rad.
    if angle <= -math.pi + 1e-12:
        return math.pi
    return angle + 0.0


def relative_pose(prev: np.ndarray, frame: np.ndarray) -> np.ndarray:
    """prev^-1 frame (..., 4, 4) for rigid poses (..., 4, 4), with R^T (cheaper than ``se3.inv``)."""
    Rt = np.swapaxes(prev[..., :3, :3], -1, -2)
    T = np.zeros(np.broadcast_shapes(prev.shape, frame.shape))
    T[..., :3, :3] = Rt @ frame[..., :3, :3]
    T[..., :3, 3] = (Rt @ (frame[..., :3, 3] - prev[..., :3, 3])[..., None])[..., 0]
    T[..., 3, 3] = 1.0
    return T


def dh_params_between(prev: np.ndarray, frame: np.ndarray) -> tuple[float, float, float, float]:
    """(a, d, alpha, theta) with prev^-1 frame = Rz(theta) Tz(d) Tx(a) Rx(alpha) (exact if it is DH);
    angles in (-pi, pi] as ``tidy_angle`` writes them."""
    from ..compiled.conversions.frames import dh_params_between as compiled

    return compiled(prev, frame)


def mdh_params_between(prev: np.ndarray, frame: np.ndarray) -> tuple[float, float, float, float]:
    """(a, d, alpha, theta) with prev^-1 frame = Rx(alpha) Tx(a) Rz(theta) Tz(d) (exact if it is MDH)."""
    from ..compiled.conversions.frames import mdh_params_between as compiled

    return compiled(prev, frame)


def approx_dh_params(prev: np.ndarray, target: np.ndarray) -> tuple[float, float, float, float]:
    """A DH row that moves ``prev`` towards a target frame that no DH row reaches exactly.

    This is the conversion paper's rule for the last row (its eqs. 6-7), restated: theta is the angle
    between the two x axes and alpha the angle between the two z axes (each signed by the side the
    other axis lies on), d the distance between the x-axis lines and a the distance between the
    z-axis lines (signed by the direction from one origin to the other). The residual tool
    T_t = (prev A)^-1 target then carries whatever the row could not express. When the target *is*
    DH-reachable the rule returns that exact row.

    Each sign test is a tie when the tested dot product is 0 (e.g. x1 in the x0-z0 plane); ties go to
    + with a margin of KEEP_TOL (relative to the largest of |o1 - o0|, |o0|, |o1| for lengths: the
    noise of o1 - o0 is eps times the coordinates), so rounding noise of a round trip through the GJD
    cannot flip a sign and a written table reads back as the same table.
    """
    from ..compiled.conversions.frames import approx_dh_params as compiled

    return compiled(prev, target)
