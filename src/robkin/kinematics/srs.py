"""Closed-form IK of SRS arms for a given arm angle: ``ik(robot, T, arm_angle=psi)``.

For a 7R arm with a spherical shoulder and a spherical wrist (``srs_geometry``: KUKA LBR iiwa, an ideal
Kinova Gen3) and a tool pose T, every configuration with arm angle psi comes from three steps:

1. the wrist centre W = T w_tool is known, so the elbow angle q4 solves |W - S| = const(q4), an equation
   A cos q4 + B sin q4 = C with two roots (the elbow branches);
2. for each q4 the rotation R of the shoulder (joints 1-3, about S) must carry the home wrist vector
   to W - S and the home elbow to the elbow position that psi prescribes: one rotation, built from the two
   pairs of vectors, then split into three turns about axes 1, 2, 3 (two ways: the shoulder branches);
3. the wrist's rotation R4^T R_T R_home^T split into turns about axes 5, 6, 7 (two ways: the wrist branches).

Up to 8 configurations per target and arm angle; each is wrapped into the joint limits and verified by
forward kinematics (``compiled.solutions.nearest_verified``), sorted by distance to q0. With an explicit
q0, ``q`` is the nearest solution on q0's branch (shoulder, elbow, wrist: ``srs_geometry.branch_of``), so a
path of targets solved from the previous answer never changes branch silently; where that branch has
no solution the target fails with a message saying so (``solutions`` still lists the others).

``feasible_arm_angles(robot, T)`` gives, per branch, the arm-angle intervals whose solutions respect the
joint limits: a sweep of psi at ``step`` followed by bisection of every crossing to 1e-12 rad.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..compiled.solutions import nearest_verified
from ..errors import InputError
from ..robot import Robot
from .limits import LIMIT_TOL, wrap_into_limits
from .pose_error import check_targets
from .srs_geometry import SRSGeometry, branch_of, reference_frame, rot, srs_geometry

__all__ = ["METHOD", "solve_arm_angle", "ik_arm_angle", "feasible_arm_angles", "BRANCHES"]

METHOD = "srs-arm-angle"

#: the 8 candidates' branch labels (shoulder, elbow, wrist), in the order ``solve_arm_angle`` returns them
BRANCHES = tuple((s, e, w) for e in (-1, 1) for s in (-1, 1) for w in (-1, 1))
_LABELS = np.array(BRANCHES, dtype=float)

#: |cos| of the elbow equation may exceed 1 by rounding at full stretch: 1e-12 relative is ~1e4 ulps
_REACH_TOL = 1e-12


def _three_axes(R: np.ndarray, w1: np.ndarray, w2: np.ndarray, w3: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Angles (M, 2, 3) with Rot(w1, a) Rot(w2, b) Rot(w3, c) = R (M, 3, 3), for +gamma and -gamma (the two
    branches: the side of the w1-w2 plane that axis 3 turned by b points to), and whether they exist (M, 2)."""
    x = R @ w3                                        # where axis 3 must end up
    k = float(w1 @ w2)
    n12 = np.cross(w1, w2)
    den = k * k - 1.0
    p2 = float(w2 @ w3)
    q1 = x @ w1
    alpha = (k * p2 - q1) / den
    beta = (k * q1 - p2) / den
    g2 = (1.0 - alpha ** 2 - beta ** 2 - 2 * alpha * beta * k) / float(n12 @ n12)
    # -1e-12: rounding of unit vectors makes an aligned pose's gamma^2 a few ulps negative
    exists = g2 > -1e-12
    gamma = np.sqrt(np.maximum(g2, 0.0))
    out = np.empty(R.shape[:-2] + (2, 3))
    y0 = np.cross(w3, [1.0, 0, 0] if abs(w3[0]) < 0.9 else [0, 1.0, 0])
    y0 /= np.linalg.norm(y0)
    for b, sign in enumerate((1.0, -1.0)):
        c = alpha[..., None] * w1 + beta[..., None] * w2 + (sign * gamma)[..., None] * n12
        qb = _turn(w2, w3, c)
        qa = _turn(w1, c, x)
        Rab = rot(w1, qa) @ rot(w2, qb)
        z = np.einsum("...ji,...j->...i", Rab, R @ y0)      # (Ra Rb)^T R y0
        qc = np.arctan2(np.cross(y0, z) @ w3, z @ y0)
        out[..., b, 0], out[..., b, 1], out[..., b, 2] = qa, qb, qc
    return out, np.stack([exists, exists], axis=-1)


def _turn(w: np.ndarray, p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """The angle (...) about w that turns p (3,) or (..., 3) onto q (..., 3) (their parts across w)."""
    pp = p - (p @ w)[..., None] * w if p.ndim > 1 else p - (p @ w) * w
    qq = q - (q @ w)[..., None] * w
    return np.arctan2(np.cross(pp, qq) @ w, np.sum(pp * qq, axis=-1))


def solve_arm_angle(geo: SRSGeometry, targets: np.ndarray, psi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Every candidate for targets (N, 4, 4) at arm angles psi (N,).

    Returns
    -------
    Q : (N, 8, 7) array
        Raw joint angles (not yet wrapped into limits), branches in the order of ``BRANCHES``.
    exists : (N, 8) bool array
        The candidate exists geometrically.
    code : (N,) int array
        0, or why no candidate exists: 1 out of reach, 2 elbow stretched or folded (psi undefined).
    """
    N = len(targets)
    a, p = geo.axes, geo.points
    W = np.einsum("nij,j->ni", targets[:, :3, :3], geo.w_tool) + targets[:, :3, 3]
    w = W - geo.S
    d2 = np.sum(w * w, axis=1)
    r = math.hypot(geo.elbow_A, geo.elbow_B)
    ratio = (geo.elbow_C0 - d2 / 2) / r
    reach = np.abs(ratio) <= 1 + _REACH_TOL
    phi = math.atan2(geo.elbow_B, geo.elbow_A)
    acos = np.arccos(np.clip(ratio, -1.0, 1.0))
    wh, n1, n2 = reference_frame(geo, w)
    n_t = np.cos(psi)[:, None] * n1 + np.sin(psi)[:, None] * n2
    Ft = np.stack([wh, n_t, np.cross(wh, n_t)], axis=-1)      # (N, 3, 3) target frame, columns
    u0 = geo.E0 - geo.S
    Q = np.full((N, 8, 7), np.nan)
    exists = np.zeros((N, 8), bool)
    flat = np.zeros(N, bool)
    Rt = targets[:, :3, :3] @ geo.R_home.T
    for e, sign in enumerate((1.0, -1.0)):
        q4 = phi + sign * acos
        v0 = np.einsum("nij,j->ni", rot(a[3], q4), geo.W0 - p[3]) + p[3] - geo.S
        v0h = v0 / np.linalg.norm(v0, axis=1, keepdims=True)
        u_perp = u0 - (v0h @ u0)[:, None] * v0h
        m = np.linalg.norm(u_perp, axis=1)
        # the elbow within 1e-9 (relative) of the shoulder-wrist line: the arm angle means nothing there
        bent = m > 1e-9 * np.linalg.norm(u0)
        flat |= ~bent & reach
        n0 = u_perp / np.where(bent, m, 1.0)[:, None]
        Fs = np.stack([v0h, n0, np.cross(v0h, n0)], axis=-1)
        R123 = Ft @ np.swapaxes(Fs, 1, 2)
        sh, sh_ok = _three_axes(R123, a[0], a[1], a[2])
        for s in range(2):
            R4 = rot(a[0], sh[:, s, 0]) @ rot(a[1], sh[:, s, 1]) @ rot(a[2], sh[:, s, 2]) @ rot(a[3], q4)
            wr, wr_ok = _three_axes(np.swapaxes(R4, 1, 2) @ Rt, a[4], a[5], a[6])
            for k in range(2):
                j = 4 * e + 2 * s + k
                Q[:, j, :3] = sh[:, s]
                Q[:, j, 3] = q4
                Q[:, j, 4:] = wr[:, k]
                exists[:, j] = reach & bent & sh_ok[:, s] & wr_ok[:, k]
    code = np.where(~reach, 1, np.where(flat & ~exists.any(axis=1), 2, 0))
    return Q, exists, code


def _check_psi(psi: Any, N: int) -> np.ndarray:
    """Arm angles (N,) from a number or N numbers, finite."""
    try:
        v = np.asarray(psi, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"arm_angle: expected a number (radians) or one per target, got {psi!r}") from None
    if v.ndim > 1 or (v.ndim == 1 and len(v) != N):
        raise InputError(f"arm_angle: expected a number or {N} numbers (one per target), got shape {v.shape}")
    if not np.all(np.isfinite(v)):
        raise InputError(f"arm_angle: must be finite, got {psi!r}")
    return np.broadcast_to(v, (N,)).copy()


def _describe(label: np.ndarray) -> str:
    names = ("shoulder", "elbow", "wrist")
    return ", ".join(f"{n} {'+' if x > 0 else '-'}" for n, x in zip(names, label) if x != 0)


def ik_arm_angle(robot: Robot, T: Any, psi: Any, q0: Any, all_solutions: bool, tol_position: float,
                 tol_orientation: float, mask: Any = None, method: str = "auto", lock: Any = None) -> Any:
    """``kinematics.ik.ik`` with ``arm_angle=psi`` (see the module docstring); an ``IKResult``.

    The arm angle fixes the redundancy of a full pose: ``lock``, a partial ``mask`` and the numeric method
    do not combine with it (InputError)."""
    if lock:
        raise InputError("arm_angle and lock: give one or the other (both fix the redundancy of a 7-joint arm)")
    if mask is not None and not (isinstance(mask, str) and mask == "pose"):
        raise InputError("arm_angle: works on full poses only; leave mask out (or 'pose')")
    if method not in ("auto", "analytic"):
        raise InputError(f"arm_angle: is solved in closed form; method must be 'auto' or 'analytic', got {method!r}")
    from .ik import SAME_SOLUTION_TOL, IKResult, _settings, _start

    geo = srs_geometry(robot)
    targets, single = check_targets(T)
    N = len(targets)
    psi_v = _check_psi(psi, N)
    settings = _settings(tol_position, tol_orientation, 1, 0)
    q_ref = np.ascontiguousarray(_start(robot, q0, N))
    Q, exists, code = solve_arm_angle(geo, targets, psi_v)
    Qw, inside = wrap_into_limits(Q.reshape(-1, 7), robot.limits, robot.revolute, np.repeat(q_ref, 8, axis=0))
    Qw = np.ascontiguousarray(Qw.reshape(N, 8, 7))
    valid = exists & inside.reshape(N, 8)
    keep = valid
    if q0 is not None:      # the branch of q0 (its singular labels, 0, accept either side)
        ref_label = branch_of(robot, q_ref).reshape(N, 3)
        clash = (ref_label[:, None, :] * _LABELS[None]) < 0
        keep = valid & ~clash.any(axis=2)
    args = (robot._chain, Qw, np.ascontiguousarray(keep), targets, q_ref, robot.limits, robot.scale,
            settings.tol_position, settings.tol_orientation, LIMIT_TOL)
    q, ok, _, ep, eo, _ = nearest_verified(*args, False, SAME_SOLUTION_TOL)
    sols = None
    if all_solutions:
        sols = nearest_verified(robot._chain, Qw, np.ascontiguousarray(valid), targets, q_ref, robot.limits,
                                robot.scale, settings.tol_position, settings.tol_orientation, LIMIT_TOL, True,
                                SAME_SOLUTION_TOL)[2]
    reasons = [""] * N
    for i in np.flatnonzero(~ok):
        if code[i] == 1:
            reasons[i] = "out of reach: the wrist centre is too near or too far from the shoulder"
        elif code[i] == 2:
            reasons[i] = ("the elbow is on the shoulder-wrist line (stretched or folded): the arm angle is "
                          "undefined; use lock= or the numeric solver")
        elif not exists[i].any():
            reasons[i] = "no rotation of the shoulder or wrist reaches this target at this arm angle"
        elif not valid[i].any():
            reasons[i] = f"every solution at arm angle {psi_v[i]:.6g} rad violates a joint limit"
        elif not keep[i].any():
            reasons[i] = (f"no solution on q0's branch ({_describe(ref_label[i])}) at arm angle {psi_v[i]:.6g} "
                          f"rad (other branches have solutions: all_solutions=True lists them)")
        else:
            reasons[i] = "the closed-form solutions failed the forward-kinematics check (near a singularity)"
    zeros = np.zeros(N, int)
    return IKResult._build(
        q=q[0] if single else q, success=bool(ok[0]) if single else ok,
        iterations=0 if single else zeros, attempts=1 if single else zeros + 1,
        position_error=float(ep[0]) if single else ep, orientation_error=float(eo[0]) if single else eo,
        method=METHOD, message=reasons[0] if single else reasons,
        solutions=None if sols is None else (sols[0] if single else sols))


def _margins(robot: Robot, geo: SRSGeometry, target: np.ndarray, psi: np.ndarray) -> np.ndarray:
    """(K, 8) the smallest distance (radians) of any joint to its limits per branch at arm angles psi (K,);
    negative outside the limits, -inf where the branch does not exist. Continuous in psi along a branch."""
    K = len(psi)
    Q, exists, _ = solve_arm_angle(geo, np.broadcast_to(target, (K, 4, 4)), psi)
    lo, hi = robot.limits[:, 0], robot.limits[:, 1]
    limited = np.isfinite(lo) & np.isfinite(hi) & (hi - lo < 2 * np.pi)
    mid = np.where(limited, (lo + hi) / 2, 0.0)
    qc = mid + np.remainder(Q - mid + np.pi, 2 * np.pi) - np.pi     # the turn nearest the middle
    m = np.where(limited, np.minimum(qc - lo, hi - qc), np.inf).min(axis=2)
    return np.where(exists, m, -np.inf)


def feasible_arm_angles(robot: Robot, T: Any, step: float = math.radians(0.25)
                        ) -> dict[tuple[int, int, int], list[tuple[float, float]]]:
    """The arm angles (radians) whose solutions for target T respect the joint limits, per branch.

    Parameters
    ----------
    robot : Robot
        An SRS arm (``srs_geometry``).
    T : (4, 4) array
        One target tool pose in the robot base frame.
    step : float
        Sweep step (radians, default 0.25 degree). Every crossing of a limit found between two samples is
        refined by bisection to 1e-12 rad; a feasible or infeasible stretch narrower than ``step`` may be
        missed (none is closer to a branch's singular pose than that in practice).

    Returns
    -------
    dict
        (shoulder, elbow, wrist) branch labels (each +1 or -1, see ``srs_geometry.branch_of``) -> sorted list
        of (lo, hi) intervals with -pi <= lo < pi and lo <= hi < lo + 2 pi (an interval through +-pi has
        hi > pi; the whole circle is (-pi, pi)). Branches with no feasible arm angle map to [].
    """
    geo = srs_geometry(robot)
    targets, single = check_targets(T)
    if not single:
        raise InputError("feasible_arm_angles: expected one target (4, 4)")
    if not (isinstance(step, (int, float)) and 1e-6 <= step <= 0.5):
        raise InputError(f"step: expected a number of radians in [1e-6, 0.5], got {step!r}")
    K = int(math.ceil(2 * math.pi / step))
    grid = -math.pi + 2 * math.pi * np.arange(K + 1) / K          # both ends: -pi and pi
    ok = _margins(robot, geo, targets[0], grid) >= 0               # (K + 1, 8)
    crossings = [(i, b) for b in range(8) for i in np.flatnonzero(ok[1:, b] != ok[:-1, b])]
    x = _bisect(robot, geo, targets[0], crossings, grid, ok)
    out: dict[tuple[int, int, int], list[tuple[float, float]]] = {}
    for b, label in enumerate(BRANCHES):
        f = ok[:, b]
        if f.all():
            out[label] = [(-math.pi, math.pi)]
            continue
        mine = [(float(x[k]), bool(f[i])) for k, (i, bb) in enumerate(crossings) if bb == b]
        starts = [v for v, was in mine if not was]
        ends = [v for v, was in mine if was]
        if f[0]:                       # feasible at -pi (= pi): the first stretch continues the last one
            first_end = ends.pop(0)
            ends.append(first_end + 2 * math.pi)
        out[label] = sorted(zip(starts, ends))
    return out


def _bisect(robot: Robot, geo: SRSGeometry, target: np.ndarray, crossings: list[tuple[int, int]],
            grid: np.ndarray, ok: np.ndarray) -> np.ndarray:
    """The arm angles (C,) where branch b's feasibility changes between grid[i] and grid[i + 1], for every
    crossing (i, b), to 1e-12 rad: bisection, all crossings side by side (~40 halvings of a sweep step)."""
    if not crossings:
        return np.zeros(0)
    idx = np.array([i for i, _ in crossings])
    br = np.array([b for _, b in crossings])
    lo, hi = grid[idx].copy(), grid[idx + 1].copy()
    was = ok[idx, br]
    while np.max(hi - lo) > 1e-12:
        mid = 0.5 * (lo + hi)
        same = (_margins(robot, geo, target, mid)[np.arange(len(mid)), br] >= 0) == was
        lo = np.where(same, mid, lo)
        hi = np.where(same, hi, mid)
    return 0.5 * (lo + hi)
