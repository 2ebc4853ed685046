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
from typing import Any, Callable, ClassVar, Iterable

import numpy as np
from numpy.typing import ArrayLike

from .. import se3
from ..lines import cross, norm
from ..robot import Robot
from .dh import robot_from_links
from ..compiled.conversions.tolerances import TIE_TOL
from .frames import (approx_dh_params, common_normal_frame, dh_params_between, is_identity,
                     relative_pose, satisfies_normal, tidy_angle)
from .link_table import WARN_TOL, LinkTable, chain_poses, flip_frame, joint_links, residual_tool
from .mass_rows import masses_of_robot

__all__ = ["HayatiTable", "hayati_from_robot", "hayati_from_robots", "robot_from_hayati", "hayati_matrix", "HAYATI_COLUMNS",
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
        """The robot this table describes (``robot_from_hayati``); ``name``: the robot's name (default: none)."""
        return robot_from_hayati(self, name=name)


def robot_from_hayati(table: "HayatiTable | ArrayLike", name: str | None = None, *, joints: Any = None,
                      base: ArrayLike | None = None, tool: ArrayLike | None = None) -> Robot:
    """The GJD of a Hayati table: J_i = frame {i-1} (flip-adjusted), J_{n+1} = frame {n} tool.

    ``table`` may also be the rows alone, an (n, 5) array of (a, d, alpha, theta, beta) (lengths in the robot's unit,
    angles in radians), with ``joints`` (None: all revolute; a type string such as "RRPR"; or n
    ``Joint``) and optional ``base`` / ``tool`` (4, 4); anything else raises one InputError.

    ``name``: the robot's name (default: none).
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
    nearly parallel (the rows stay short there). With the robot's mass properties in frames {i}.
    The same as ``hayati_from_robots([robot])[0]``."""
    return _hayati_tables([robot], label=False, stacklevel=3, threads=None)[0]


def hayati_from_robots(robots: Iterable[Robot], *, threads: int | None = None) -> list[HayatiTable]:
    """Hayati tables of many robots at once (e.g. the candidates of a synthesis run), in order.

    Each table is the one ``hayati_from_robot`` gives for that robot, bit for bit. The frames are
    placed robot by robot; the rounding of near-round values, the residual tool, the validation of the
    base and tool poses and the FK self-check run for all robots with the same joint count as whole
    arrays. A table that reproduces its robot's FK only to more than WARN_TOL gets a
    ConditioningWarning starting with ``robots[i]:``.

    Parameters
    ----------
    robots : iterable of Robot
        Any joint counts.
    threads : int >= 1, optional
        At most this many threads for the robots' compiled FK in the self-check (default: automatic,
        ``robkin.threads``); the tables are the same bits with any number.

    Returns
    -------
    list of HayatiTable
        One per robot, in the order given.
    """
    return _hayati_tables(list(robots), label=True, stacklevel=3, threads=threads)


def _hayati_rows(robot: Robot) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A robot's unrounded Hayati rows (n, 5), frame {0} (the base) and last frame (``hayati_frames``)."""
    F, last, beta_row = hayati_frames(robot)
    chain = list(F) + [last]
    rows = np.array([hayati_params_between(chain[i], chain[i + 1]) if beta_row[i]
                     else dh_params_between(chain[i], chain[i + 1]) + (0.0,) for i in range(robot.n)])
    return rows, F[0], last


def _hayati_tables(robots: list[Robot], label: bool, stacklevel: int, threads: int | None) -> list[HayatiTable]:
    """``hayati_from_robots``: robots grouped by joint count, every stage after the frame placement
    on whole arrays (as ``placement.tables_from_robots`` does for DH tables)."""
    from ..checks import check_poses, check_threads
    from ..compiled.conversions.frames import robots_fk
    from ..errors import InputError
    from ..frame_stacks import local_transforms
    from .link_table import pose_difference, report_fk_error, sample_configurations
    from .rounding import snap_many, travel

    t = 0 if threads is None else check_threads(threads)
    for i, r in enumerate(robots):
        if not isinstance(r, Robot):
            raise InputError(f"robots[{i}]: expected a robkin.Robot, got {type(r).__name__}")
    out: list[HayatiTable | None] = [None] * len(robots)
    groups: dict[int, list[int]] = {}
    for i, r in enumerate(robots):
        groups.setdefault(r.n, []).append(i)
    for idx in groups.values():
        group = [robots[i] for i in idx]
        B = len(group)
        parts = [_hayati_rows(r) for r in group]
        rows = np.stack([p[0] for p in parts])  # (B, n, 5)
        base = np.stack([p[1] for p in parts])
        last = np.stack([p[2] for p in parts])
        tool_pose = np.stack([r.tool for r in group])
        scale = np.array([r.scale for r in group])
        revolute = np.stack([r.revolute for r in group])
        limits = np.stack([r.limits for r in group])
        snap = np.array([r.frames_from != "hayati" for r in group])
        if snap.any():
            rows[snap] = snap_many(rows[snap], travel(revolute[snap], limits[snap]),
                                   relative_pose(last[snap], tool_pose[snap]), scale[snap])
        tool = residual_tool(base, rows, hayati_matrix, tool_pose, scale)
        for k in range(B):
            if not np.isfinite(rows[k]).all():  # cannot happen for a valid robot: let the table explain
                HayatiTable(rows[k], group[k].joints, base=base[k], tool=tool[k])
        poses = check_poses(np.concatenate([base, tool]), lambda k: f"hayati.{'base' if k < B else 'tool'}")
        base, tool = poses[:B], poses[B:]
        tables = [HayatiTable._from_checked(rows[k], r.joints, base[k], tool[k]) for k, r in enumerate(group)]
        # the FK self-check: each table's FK from its rows against the robot's compiled FK
        Q = sample_configurations(revolute, limits, scale)  # (B, m, n)
        sign = np.stack([np.where([j.flip for j in r.joints], -1.0, 1.0) for r in group])
        links = joint_links(hayati_matrix, rows[:, None], revolute[:, None], sign[:, None], Q)
        table_fk = chain_poses(base[:, None], links, tool[:, None])
        L = np.stack([r._local for r in group]) if B == 1 else local_transforms(np.stack([r.frames for r in group]))
        err = pose_difference(table_fk, robots_fk(L, revolute, Q, t), scale)
        for bad in np.flatnonzero(err > WARN_TOL * scale):
            report_fk_error(float(err[bad]), group[bad], "hayati", where=f"robots[{idx[bad]}]: " if label else "",
                            stacklevel=stacklevel + 1)
        for k, (i, r) in enumerate(zip(idx, group)):
            if r.bodies.inertials:  # the mass properties, in the table's own link frames {i}
                tables[k] = tables[k].with_masses(masses_of_robot(r, tables[k].link_frames()))
            out[i] = tables[k]
    return out  # type: ignore[return-value]  # every slot filled above
