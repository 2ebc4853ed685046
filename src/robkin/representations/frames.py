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

from ..lines import (ANGLE_TOL, LENGTH_TOL, AxisRelation, classify, closest_points, cross, norm,
                     perpendicular, point_line_foot)
from .. import se3

__all__ = ["common_normal_frame", "frame_from_zx", "satisfies_normal", "dh_params_between",
           "mdh_params_between", "approx_dh_params", "is_identity", "x_line_on", "relative_pose"]

#: A given frame is kept only if it satisfies the convention to rounding noise: the DH parameters read
#: back from it then reproduce it to ~1e-12 relative, well inside the 1e-9 FK agreement we promise.
KEEP_TOL = 1e-12
#: |cos theta| below which theta is taken as +-pi/2 and the tie-break (theta = +pi/2) applies; wider
#: than rounding noise (~1e-16) so exact right angles computed through products resolve consistently.
TIE_TOL = 1e-9


def is_identity(T: np.ndarray, scale: float, tol: float = KEEP_TOL) -> bool:
    """Is the pose the identity to rounding noise (rotation to ``tol``, translation to ``tol * scale``)?"""
    return bool(np.abs(T[:3, :3] - np.eye(3)).max() <= tol and np.abs(T[:3, 3]).max() <= tol * scale)


def frame_from_zx(origin: np.ndarray, z: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Pose (4, 4) with the given origin, unit z, and x (made exactly orthogonal to z and unit)."""
    # Python floats: for 3-vectors every numpy call costs more than the arithmetic
    zx, zy, zz = np.asarray(z, dtype=float).tolist()
    k = math.sqrt(zx * zx + zy * zy + zz * zz)
    zx, zy, zz = zx / k, zy / k, zz / k
    xx, xy, xz = np.asarray(x, dtype=float).tolist()
    # Gram-Schmidt twice: when the given x is nearly along z (e.g. a common-normal direction that is
    # rounding noise, between coincident axes classified as parallel far from the base), one pass
    # leaves x . z ~ eps |x| / |x_perp| (seen: 5.6e-10) and the frame is not a rotation; the second
    # pass brings it back to rounding noise ("twice is enough", Parlett).
    for _ in range(2):
        c = xx * zx + xy * zy + xz * zz
        xx, xy, xz = xx - c * zx, xy - c * zy, xz - c * zz
        k = math.sqrt(xx * xx + xy * xy + xz * xz)
        xx, xy, xz = xx / k, xy / k, xz / k
    yx, yy, yz = zy * xz - zz * xy, zz * xx - zx * xz, zx * xy - zy * xx
    ox, oy, oz = np.asarray(origin, dtype=float).tolist()
    return np.array([[xx, yx, zx, ox], [xy, yy, zy, oy], [xz, yz, zz, oz], [0.0, 0.0, 0.0, 1.0]])


def satisfies_normal(frame: np.ndarray, p_other: np.ndarray, u_other: np.ndarray, scale: float,
                     tol: float = KEEP_TOL) -> bool:
    """Does the frame's x axis cross the other line at a right angle (the DH requirement)?"""
    o, x = frame[:3, 3], frame[:3, 0]
    if abs(np.dot(x, u_other)) > tol:
        return False
    if norm(cross(x, u_other)) < ANGLE_TOL:  # x along the other line: cannot cross it
        return False
    return closest_points(o, x, p_other, u_other).distance <= tol * scale


def _choose_sign(x: np.ndarray, x_pref: np.ndarray, y_pref: np.ndarray) -> np.ndarray:
    """+-x, whichever keeps |theta| <= pi/2 from x_pref (on a tie, theta = +pi/2 towards y_pref)."""
    c = float(np.dot(x, x_pref))
    if abs(c) > TIE_TOL:
        return x if c > 0 else -x
    return x if np.dot(x, y_pref) >= 0 else -x


def common_normal_frame(p_a: np.ndarray, u_a: np.ndarray, p_b: np.ndarray, u_b: np.ndarray, *,
                        on: str, prev: np.ndarray, scale: float,
                        keep: np.ndarray | None = None) -> np.ndarray:
    """Frame on line A or B (``on`` = 'a' | 'b') whose x axis is the common normal from A to B.

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
    u_self, p_self = (u_a, p_a) if on == "a" else (u_b, p_b)
    u_other, p_other = (u_b, p_b) if on == "a" else (u_a, p_a)
    if keep is not None and satisfies_normal(keep, p_other, u_other, scale):
        return keep
    x_prev = prev[:3, 0]
    # the point where the previous frame meets line A: its origin (DH), or where its x crosses A (MDH)
    anchor = point_line_foot(prev[:3, 3], p_a, u_a) if on == "b" else x_line_on(prev, p_a, u_a)
    y_ref = cross(u_a, x_prev)
    rel = classify(p_a, u_a, p_b, u_b, scale)
    if rel in (AxisRelation.PARALLEL, AxisRelation.ANTI_PARALLEL):
        foot_b = point_line_foot(anchor, p_b, u_b)
        normal = foot_b - anchor
        dist = float(norm(normal))
        # Measured from the anchor rather than from p_a, the lines may still meet to rounding (seen:
        # normal exactly 0, and a NaN frame, when the robot's scale was 1e-6 of its frame offsets):
        # then they are coincident.
        if dist > LENGTH_TOL * scale:
            # unit before the sign test: its tie margin is on a cosine, and an unnormalised normal
            # made the choice depend on the length unit (the same robot in mm got the other sign)
            x = _choose_sign(normal / dist, x_prev, y_ref)
            return frame_from_zx(anchor if on == "a" else foot_b, u_self, x)
        rel = AxisRelation.COINCIDENT
    if rel in (AxisRelation.COINCIDENT, AxisRelation.ANTI_COINCIDENT):
        x = x_prev - np.dot(x_prev, u_self) * u_self
        if norm(x) < 1e-6:  # prev x along the axis (cannot happen for a valid chain)
            x = perpendicular(u_self)
        origin = anchor if on == "a" else point_line_foot(anchor, p_b, u_b)
        return frame_from_zx(origin, u_self, x)
    cn = closest_points(p_a, u_a, p_b, u_b)
    x = cross(u_a, u_b)
    x = _choose_sign(x / norm(x), x_prev, y_ref)
    return frame_from_zx(cn.c1 if on == "a" else cn.c2, u_self, x)


def x_line_on(prev: np.ndarray, p: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Where the x axis of ``prev`` meets the line (p, u); the foot of prev's origin if they miss."""
    o, x = prev[:3, 3], prev[:3, 0]
    if norm(cross(x, u)) < ANGLE_TOL:
        return point_line_foot(o, p, u)
    return closest_points(o, x, p, u).c2


def tidy_angle(angle: float) -> float:
    """An angle in (-pi, pi]: -pi (and values within rounding noise of it) become +pi, -0.0 becomes 0."""
    # 1e-12: atan2 of entries that are exactly 0 up to rounding returns +-pi for the same geometry;
    # print one of them. The FK effect of the change is below 1e-12 rad.
    if angle <= -math.pi + 1e-12:
        return math.pi
    return angle + 0.0


def relative_pose(prev: np.ndarray, frame: np.ndarray) -> np.ndarray:
    """prev^-1 frame (4, 4) for rigid poses, with R^T (cheaper than ``se3.inv`` for one pair)."""
    Rt = prev[:3, :3].T
    T = np.empty((4, 4))
    T[:3, :3] = Rt @ frame[:3, :3]
    T[:3, 3] = Rt @ (frame[:3, 3] - prev[:3, 3])
    T[3] = (0.0, 0.0, 0.0, 1.0)
    return T


def dh_params_between(prev: np.ndarray, frame: np.ndarray) -> tuple[float, float, float, float]:
    """(a, d, alpha, theta) with prev^-1 frame = Rz(theta) Tz(d) Tx(a) Rx(alpha) (exact if it is DH)."""
    T = relative_pose(prev, frame)
    theta = math.atan2(T[1, 0], T[0, 0])
    alpha = math.atan2(T[2, 1], T[2, 2])
    a = T[0, 3] * math.cos(theta) + T[1, 3] * math.sin(theta)
    return a, float(T[2, 3]), tidy_angle(alpha), tidy_angle(theta)


def mdh_params_between(prev: np.ndarray, frame: np.ndarray) -> tuple[float, float, float, float]:
    """(a, d, alpha, theta) with prev^-1 frame = Rx(alpha) Tx(a) Rz(theta) Tz(d) (exact if it is MDH)."""
    T = relative_pose(prev, frame)
    alpha = math.atan2(-T[1, 2], T[2, 2])
    theta = math.atan2(-T[0, 1], T[0, 0])
    d = -T[1, 3] * math.sin(alpha) + T[2, 3] * math.cos(alpha)
    return float(T[0, 3]), d, tidy_angle(alpha), tidy_angle(theta)


def approx_dh_params(prev: np.ndarray, target: np.ndarray) -> tuple[float, float, float, float]:
    """A DH row that moves ``prev`` towards a target frame that no DH row reaches exactly.

    This is the conversion paper's rule for the last row (its eqs. 6-7), restated: theta is the angle
    between the two x axes and alpha the angle between the two z axes (each signed by the side the
    other axis lies on), d the distance between the x-axis lines and a the distance between the
    z-axis lines (signed by the direction from one origin to the other). The residual tool
    T_t = (prev A)^-1 target then carries whatever the row could not express. When the target *is*
    DH-reachable the rule returns that exact row.
    """
    o0, x0, y0, z0 = prev[:3, 3], prev[:3, 0], prev[:3, 1], prev[:3, 2]
    o1, x1, y1, z1 = target[:3, 3], target[:3, 0], target[:3, 1], target[:3, 2]
    # Each sign test is a tie when the tested dot product is 0 (e.g. x1 in the x0-z0 plane); ties go
    # to + with a margin of KEEP_TOL (relative), so that rounding noise (~1e-15) of a round trip through
    # the GJD cannot flip the sign and a written table reads back as the same table. (A reachable
    # target with |theta| < KEEP_TOL may get +|theta|: the residual tool absorbs the 2e-12.)
    # lengths: the noise of o1 - o0 is eps times the coordinates, not times |o1 - o0| (a tool 1e-13
    # from the last frame, 1e-3 from the base, had its d sign flipped by 1e-19 of noise)
    reach = float(max(norm(o1 - o0), norm(o0), norm(o1)))
    theta = math.atan2(norm(cross(x0, x1)), np.dot(x0, x1))
    if np.dot(y0, x1) < -KEEP_TOL:
        theta = -theta
    alpha = math.atan2(norm(cross(z0, z1)), np.dot(z0, z1))
    if np.dot(y1, z0) < -KEEP_TOL:
        alpha = -alpha
    d = _line_distance(o0, x0, o1, x1)
    if np.dot(o1 - o0, z0) < -KEEP_TOL * reach:
        d = -d
    a = _line_distance(o0, z0, o1, z1)
    if np.dot(o1 - o0, x1) < -KEEP_TOL * reach:
        a = -a
    return a, d, alpha, theta


def _line_distance(p1: np.ndarray, u1: np.ndarray, p2: np.ndarray, u2: np.ndarray) -> float:
    n = cross(u1, u2)
    nn = norm(n)
    if nn < ANGLE_TOL:
        w = p2 - p1
        return float(norm(w - np.dot(w, u1) * u1))
    return float(abs(np.dot(p2 - p1, n)) / nn)
