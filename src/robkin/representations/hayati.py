"""Hayati's parameters: DH rows, with a rotation beta about y in place of d between nearly parallel axes.

Row i is (a, d, alpha, theta, beta) with A_i = Rz(theta) Tz(d) Tx(a) Rx(alpha) Ry(beta); joint i moves
about/along z_{i-1} as in standard DH (theta or d is the value at q = 0, the joint adds q_i), and
FK = base A_1(q_1) ... A_n(q_n) tool.

Between two axes that are nearly parallel the DH common normal runs off to ~offset / angle (a tilt of
1e-9 rad puts it 1e8 robot sizes away) and a DH table either drops the tilt or loses accuracy. Hayati's
row (the calibration model of Hayati and Mirmirani, 1985) instead places frame {i} where axis i+1 meets
frame {i-1}'s x-y plane (so d = 0), with x along the direction to that point (``a`` its distance), and
tilts z by alpha about x then beta about y onto axis i+1: every parameter stays small and the row is
exact at every tilt, including exactly parallel axes (beta = 0, the DH row of parallel axes). Rows whose
axes are not nearly parallel (sin of their angle >= ``NEAR_PARALLEL``) are standard DH rows with beta = 0
and follow the DH module's canonical rules; so do frame {0} (the base transform) and the last frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from .. import se3
from ..lines import cross, norm
from ..robot import Robot
from .dh import robot_from_links
from .frames import (TIE_TOL, approx_dh_params, common_normal_frame, dh_params_between, is_identity,
                     relative_pose, satisfies_normal, tidy_angle)
from .link_table import LinkTable, flip_frame, residual_tool, warn_fk_error
from .rounding import snap_rows

__all__ = ["HayatiTable", "hayati_from_robot", "robot_from_hayati", "hayati_matrix", "HAYATI_COLUMNS",
           "NEAR_PARALLEL"]

HAYATI_COLUMNS = ("a", "d", "alpha", "theta", "beta")
#: sin of the angle between consecutive axes below which the row is a Hayati row (beta, d = 0). A DH
#: row between axes at angle t, offset r apart, has |d| up to ~r / t: below sin t = 0.1 (5.7 degrees)
#: that exceeds 10 offsets, while Hayati's parameters stay below the offset (a) and the tilt (alpha,
#: beta) at every angle. Above it DH rows are short and are what people expect to read.
NEAR_PARALLEL = 0.1


def hayati_matrix(a: ArrayLike, d: ArrayLike, alpha: ArrayLike, theta: ArrayLike, beta: ArrayLike) -> np.ndarray:
    """Hayati link transform Rz(theta) Tz(d) Tx(a) Rx(alpha) Ry(beta), broadcast -> (..., 4, 4)."""
    A = se3.dh_matrix(a, d, alpha, theta)
    b = np.asarray(beta, dtype=float)
    cb, sb = np.cos(b)[..., None], np.sin(b)[..., None]
    x, z = A[..., :, 0].copy(), A[..., :, 2].copy()
    # right-multiplying by Ry(beta) mixes columns x and z: x' = cb x - sb z, z' = sb x + cb z
    A[..., :, 0] = cb * x - sb * z
    A[..., :, 2] = sb * x + cb * z
    return A


@dataclass(frozen=True, eq=False)
class HayatiTable(LinkTable):
    """Hayati's parameters: rows (n, 5) of (a, d, alpha, theta, beta), base and tool (4, 4)."""

    SECTION: ClassVar[str] = "hayati"
    COLUMNS: ClassVar[tuple[str, ...]] = HAYATI_COLUMNS
    link_matrix: ClassVar[Callable[..., np.ndarray]] = staticmethod(hayati_matrix)

    def to_robot(self, name: str | None = None) -> Robot:
        return robot_from_hayati(self, name=name)


def robot_from_hayati(table: "HayatiTable | ArrayLike", name: str | None = None, *, joints: Any = None,
                      base: ArrayLike | None = None, tool: ArrayLike | None = None) -> Robot:
    """The GJD of a Hayati table: J_i = frame {i-1} (flip-adjusted), J_{n+1} = frame {n} tool.

    ``table`` may also be the rows alone, an (n, 5) array of (a, d, alpha, theta, beta) (lengths in the robot's unit,
    angles in radians), with ``joints`` (None: all revolute; a type string such as "RRPR"; or n
    ``Joint``) and optional ``base`` / ``tool`` (4, 4); anything else raises one InputError.
    """
    from .table_input import link_table_of

    return robot_from_links(link_table_of(HayatiTable, table, "robot_from_hayati", joints, base, tool),
                            "hayati", name)


def _near_parallel(u_a: np.ndarray, u_b: np.ndarray) -> bool:
    return float(norm(cross(u_a, u_b))) < NEAR_PARALLEL


def _hayati_step(prev: np.ndarray, p: np.ndarray, u: np.ndarray) -> tuple[float, ...]:
    """The Hayati row (a, 0, alpha, theta, beta) from ``prev`` to the line (p, u), nearly parallel to
    prev's z: frame {i} where the line crosses prev's x-y plane, x towards it with |theta| <= pi/2
    (a may be negative, as in DH), z tilted onto u by alpha about x, then beta about y."""
    R, o = prev[:3, :3], prev[:3, 3]
    q, v = R.T @ (p - o), R.T @ u
    P = q - (q[2] / v[2]) * v  # on the line, in the plane z = 0 (|v_z| >= cos of the tilt > 0.99)
    a = math.hypot(P[0], P[1])
    theta = math.atan2(P[1], P[0])  # 0 when the line passes through prev's origin (P = 0)
    theta, flipped = _half_turn(theta)
    a = -a if flipped else a
    c, s = math.cos(theta), math.sin(theta)
    w = np.array([c * v[0] + s * v[1], -s * v[0] + c * v[1], v[2]])  # Rz(theta)^T v
    beta = math.asin(max(-1.0, min(1.0, float(w[0]))))
    alpha = math.atan2(-float(w[1]), float(w[2]))
    return a, 0.0, tidy_angle(alpha), tidy_angle(theta), beta


def _half_turn(theta: float) -> tuple[float, bool]:
    """The DH sign rule: theta or theta - pi, whichever has |theta| <= pi/2 (ties: +pi/2); and whether
    it was turned (x reversed, so a changes sign)."""
    c = math.cos(theta)
    if c < -TIE_TOL or (abs(c) <= TIE_TOL and math.sin(theta) < 0):
        return theta - math.copysign(math.pi, theta), True
    return theta, False


def hayati_params_between(prev: np.ndarray, frame: np.ndarray) -> tuple[float, ...]:
    """(a, d, alpha, theta, beta) with prev^-1 frame = Rz(theta) Tz(d) Tx(a) Rx(alpha) Ry(beta), the
    branch with |theta| <= pi/2 that ``_hayati_step`` builds (exact if the frame is such a successor)."""
    T = relative_pose(prev, frame)
    R, p = T[:3, :3], T[:3, 3]
    # M = Rz(theta)^T R = Rx(alpha) Ry(beta) has M[0, 1] = 0: theta is fixed up to a half turn
    theta, _ = _half_turn(math.atan2(-R[0, 1], R[1, 1]))
    c, s = math.cos(theta), math.sin(theta)
    M = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]]) @ R
    beta = math.atan2(M[0, 2], M[0, 0])
    alpha = math.atan2(M[2, 1], M[1, 1])
    return float(c * p[0] + s * p[1]), float(p[2]), tidy_angle(alpha), tidy_angle(theta), beta


def hayati_frames(robot: Robot) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Frames {0}..{n-1} (n, 4, 4), the last frame {n} (4, 4), and which rows are Hayati rows (n,).

    Frame i is placed from frame i-1 (the base, for frame {0}) by Hayati's rule when their z axes are
    nearly parallel, else by the DH rules. The robot's own frames are kept (when they are valid
    successors) only if they are a Hayati table's frames (``robot.frames_from == 'hayati'``).
    """
    n, scale = robot.n, robot.scale
    cand = np.stack([flip_frame(robot.frames[i], j.flip) for i, j in enumerate(robot.joints)])
    keep = robot.frames_from == "hayati"
    F = np.empty((n, 4, 4))
    beta_row = np.zeros(n, dtype=bool)
    prev = np.eye(4)
    for i in range(n):
        p, u = cand[i, :3, 3], cand[i, :3, 2]
        if _near_parallel(prev[:3, 2], u):
            F[i] = prev @ hayati_matrix(*_hayati_step(prev, p, u))
            if keep and is_identity(relative_pose(prev @ hayati_matrix(*hayati_params_between(prev, cand[i])),
                                                  cand[i]), scale):
                F[i] = cand[i]
        else:
            F[i] = common_normal_frame(prev[:3, 3], prev[:3, 2], p, u, on="b", prev=prev, scale=scale,
                                       keep=cand[i] if keep else None)
        if i > 0:
            beta_row[i - 1] = _near_parallel(prev[:3, 2], u)
        prev = F[i]
    tool = robot.tool
    last = tool if satisfies_normal(tool, prev[:3, 3], prev[:3, 2], scale) else \
        prev @ se3.dh_matrix(*approx_dh_params(prev, tool))
    return F, last, beta_row


def hayati_from_robot(robot: Robot) -> HayatiTable:
    """Hayati table (+ base, + residual tool) of a robot; FK-identical at every q, also where axes are
    nearly parallel (the rows stay short there)."""
    F, last, beta_row = hayati_frames(robot)
    chain = list(F) + [last]
    rows = np.array([hayati_params_between(chain[i], chain[i + 1]) if beta_row[i]
                     else dh_params_between(chain[i], chain[i + 1]) + (0.0,) for i in range(robot.n)])
    if robot.frames_from != "hayati":
        rows = snap_rows(rows, robot.joints, relative_pose(last, robot.tool), robot.scale)
    tool = residual_tool(F[0], rows, hayati_matrix, robot.tool, robot.scale)
    table = HayatiTable(rows, robot.joints, base=F[0], tool=tool)
    warn_fk_error(table.fk, robot, "hayati")
    return table
