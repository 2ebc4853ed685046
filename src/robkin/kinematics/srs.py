"""Closed-form IK of SRS arms for a given arm angle: ``ik(robot, T, arm_angle=psi)``.

For a 7R arm with a spherical shoulder and a spherical wrist (``srs_geometry``: KUKA LBR iiwa, an ideal
Kinova Gen3) and a tool pose T, every configuration with arm angle psi comes from three steps:

1. the wrist centre W = T w_tool is known, so the elbow angle q4 solves |W - S| = const(q4), an equation
   A cos q4 + B sin q4 = C with two roots (the elbow branches);
2. for each q4 the rotation R of the shoulder (joints 1-3, about S) must carry the home wrist vector
   to W - S and the home elbow to the elbow position that psi prescribes: one rotation, built from the two
   pairs of vectors, then split into three turns about axes 1, 2, 3 (two ways: the shoulder branches);
3. the wrist's rotation R4^T R_T R_home^T split into turns about axes 5, 6, 7 (two ways: the wrist branches).

The steps run compiled (``compiled.ik.closed_form_srs.SRSKernel``, built once per robot); this module checks
inputs, keeps the branch and explains failures.

Up to 8 configurations per target and arm angle; each is wrapped into the joint limits and verified by
forward kinematics (``compiled.ik.solutions.nearest_verified``), sorted by distance to q0. With an explicit
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

from ..compiled.ik.solutions import nearest_verified
from ..errors import InputError
from ..robot import Robot
from .limits import LIMIT_TOL
from .pose_error import check_targets
from .srs_geometry import branch_of, srs_geometry

__all__ = ["METHOD", "solve_arm_angle", "ik_arm_angle", "feasible_arm_angles", "BRANCHES"]

METHOD = "srs-arm-angle"

#: the 8 candidates' branch labels (shoulder, elbow, wrist), in the order ``solve_arm_angle`` returns them
BRANCHES = tuple((s, e, w) for e in (-1, 1) for s in (-1, 1) for w in (-1, 1))
_LABELS = np.array(BRANCHES, dtype=float)

#: per Robot (immutable): the compiled kernel, keyed by id with a weak reference proving identity
_KERNELS: dict[int, tuple[Any, Any]] = {}


def srs_kernel(robot: Robot) -> Any:
    """The compiled kernel (``compiled.ik.closed_form_srs.SRSKernel``) of an SRS arm, built once per robot."""
    import weakref

    from ..compiled.ik.closed_form_srs import SRSKernel
    from .limits import default_preference

    hit = _KERNELS.get(id(robot))
    if hit is not None and hit[0]() is robot:
        return hit[1]
    g = srs_geometry(robot)
    kernel = SRSKernel(robot._chain, robot.limits, default_preference(robot.limits), robot.scale, LIMIT_TOL,
                       g.axes, g.S, g.W0, g.p4, g.E0, g.w_tool, g.R_home, g.z_ref, g.z_alt, g.elbow_A,
                       g.elbow_B, g.elbow_C0)
    key = id(robot)

    def forget(_ref: Any, key: int = key) -> None:
        _KERNELS.pop(key, None)

    _KERNELS[key] = (weakref.ref(robot, forget), kernel)
    return kernel


def solve_arm_angle(robot: Robot, targets: np.ndarray, psi: np.ndarray, q_ref: np.ndarray | None = None
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, np.ndarray]:
    """Every candidate for targets (N, 4, 4) at arm angles psi (N,) (compiled).

    Returns
    -------
    Q : (N, 8, 7) array
        Joint angles, branches in the order of ``BRANCHES``; raw, or with q_ref (N, 7) wrapped into the
        limits nearest q_ref.
    exists : (N, 8) bool array
        The candidate exists geometrically.
    valid : (N, 8) bool array or None
        With q_ref: exists and within the limits.
    code : (N,) int array
        0, or why no candidate exists: 1 out of reach, 2 elbow stretched or folded (psi undefined),
        3 no shoulder or wrist rotation fits.
    """
    return srs_kernel(robot).candidates(targets, psi, q_ref)


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
    from .ik_methods import SAME_SOLUTION_TOL
    from .ik_result import IKResult, settings as checked_settings
    from .ik_methods import preferred_starts

    srs_geometry(robot)                 # the SRS check (InputError naming what fails)
    targets, single = check_targets(T)
    N = len(targets)
    psi_v = _check_psi(psi, N)
    settings = checked_settings(tol_position, tol_orientation, 1, 0)
    q_ref = np.ascontiguousarray(preferred_starts(robot, q0, N))
    Qw, exists, checked, code = solve_arm_angle(robot, targets, psi_v, q_ref)
    valid: np.ndarray = checked if checked is not None else exists    # (never None: q_ref is given)
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
        elif code[i] == 3:
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


def _margins(robot: Robot, target: np.ndarray, psi: np.ndarray) -> np.ndarray:
    """(K, 8) the smallest distance (radians) of any joint to its limits per branch at arm angles psi (K,);
    negative outside the limits, -inf where the branch does not exist. Continuous in psi along a branch."""
    K = len(psi)
    Q, exists, _, _ = solve_arm_angle(robot, np.ascontiguousarray(np.broadcast_to(target, (K, 4, 4))),
                                      np.ascontiguousarray(psi, dtype=float))
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
    srs_geometry(robot)
    targets, single = check_targets(T)
    if not single:
        raise InputError("feasible_arm_angles: expected one target (4, 4)")
    if not (isinstance(step, (int, float)) and 1e-6 <= step <= 0.5):
        raise InputError(f"step: expected a number of radians in [1e-6, 0.5], got {step!r}")
    K = int(math.ceil(2 * math.pi / step))
    grid = -math.pi + 2 * math.pi * np.arange(K + 1) / K          # both ends: -pi and pi
    ok = _margins(robot, targets[0], grid) >= 0               # (K + 1, 8)
    crossings = [(int(i), b) for b in range(8) for i in np.flatnonzero(ok[1:, b] != ok[:-1, b])]
    x = _bisect(robot, targets[0], crossings, grid, ok)
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


def _bisect(robot: Robot, target: np.ndarray, crossings: list[tuple[int, int]],
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
        same = (_margins(robot, target, mid)[np.arange(len(mid)), br] >= 0) == was
        lo = np.where(same, mid, lo)
        hi = np.where(same, hi, mid)
    return 0.5 * (lo + hi)
