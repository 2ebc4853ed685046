"""How far a model is from measurements, and which joint or parameter explains most of it.

The model is first given its best base and marker (``calibrate(..., kinematics=False)``): what remains
is the model's own error. Then each joint's parameters (its zero offset and its link's parameters) are
fitted alone, with the base and marker; the share of the squared residual each one removes ranks the
joints. Within the best joint, each parameter is tried alone the same way. This is ``robkin check``'s
joint-by-joint diagnosis, against measured samples instead of a second model.

Measurements that are not of this model at all (random poses, another robot, wrong units) leave a
residual of the robot's own size after the base fit; fitting each joint alone then explains nothing and
every fit runs to its evaluation limit (1000 random poses of a UR5: 12 fits, > 60 s). When the RMS left
exceeds ``INCONSISTENT`` times the robot's size, the diagnosis says so and stops after the base fit.

Data in between (noisy, or a little off) at the size a file may have (200 000 poses) made the 1 + n + 6
fits slow all the same. So the joint-by-joint fits use at most ``DIAGNOSIS_POSES`` poses (evenly spread
through the file; the shares are ratios, which that many poses settle) and share a ``WORK`` budget of
pose evaluations (``fit.Budget``: deterministic, the same result on any machine). When the budget runs
out, the joints and parameters fitted so far are listed and the text says the rest were not fitted.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..robot import Robot
from .fit import Budget
from .solve import calibrate

__all__ = ["Diagnosis", "diagnose", "DEFAULT_TOL", "INCONSISTENT", "DIAGNOSIS_POSES", "WORK"]

#: Default RMS position residual (m) a model may leave, with its best base and marker, and still count
#: as the measured robot: between a calibrated robot's accuracy (0.05-0.3 mm) and an uncalibrated
#: one's (1-5 mm).
DEFAULT_TOL = 5e-4
#: Position RMS left by the base fit, as a fraction of the robot's size (``Robot.scale``), beyond which
#: the measurements are taken as not of this model: no joint-by-joint diagnosis (it would explain nothing
#: and take 1 + n + 6 full fits that each run to their evaluation limit).
INCONSISTENT = 0.25
#: Most poses the joint-by-joint fits use: the base fit (the residual reported) uses every pose, the
#: ranking an evenly spaced subset of this many (a campaign has 30-1000 poses). On 200 000 poses of a
#: UR5 with a 5 mm link error under 2 cm of noise, 2000 and 5000 poses ranked the joints and the first
#: joint's parameters alike (shares 2.0 / 1.8 % for the link at fault).
DIAGNOSIS_POSES = 2000
#: Pose evaluations (one residual or Jacobian of the chain at one pose) all joint-by-joint fits together
#: may use, their calibrations' evaluations outside the fits included: ~3x what they used on 2000 poses
#: with 2 cm of noise (UR5 1.2 * 10^6, 2026-11-28; 1000 noisy poses: UR5 0.55, iiwa 0.71 * 10^6; clean
#: 40-pose campaigns ~10^5), so that normal data never meet it. The evaluations of a pose grow with the
#: joints; 5000 poses of a UR5 took ~6 us of CPU each (fits and all).
WORK = 4_000_000


@dataclass
class Diagnosis:
    """What ``diagnose`` found.

    Attributes
    ----------
    residuals : dict
        Residual statistics of the model with its best base and marker (``report.residual_stats``).
    joints : list of (joint name, share, RMS after fitting it)
        Every joint, the one whose parameters explain most of the squared residual first.
    parameters : list of (parameter name, share, change)
        For the first joint: each of its parameters alone, and the change (m or rad) it would need.
    tol : float
        The RMS position residual (m) below which the model counts as the measured robot.
    world : (4, 4) array
        The model's best base pose in the measuring frame.
    outliers : list of (row, residual)
        Poses left out as bad measurements (their line in the file, residual in m).
    note : str or None
        Why there is no joint-by-joint diagnosis (measurements not of this model), or None.
    poses, poses_ranked : int
        Poses measured, and those the joint-by-joint fits used (``DIAGNOSIS_POSES`` at most; 0 without
        those fits).
    budget_reached : bool
        The joint-by-joint fits stopped at their ``WORK`` budget: ``joints`` (and ``parameters``) hold
        those fitted before it.
    """

    residuals: dict[str, float]
    joints: list[tuple[str, float, float]]
    parameters: list[tuple[str, float, float, str]]
    tol: float
    world: np.ndarray | None = None
    outliers: list[tuple[int, float]] = field(default_factory=list)
    note: str | None = None
    poses: int = 0
    poses_ranked: int = 0
    budget_reached: bool = False

    @property
    def same(self) -> bool:
        return self.residuals["position_rms"] <= self.tol

    def to_dict(self) -> dict[str, Any]:
        return {"same": self.same, "tol": self.tol, "residuals": self.residuals,
                "joints": [{"joint": j, "share": s, "position_rms_after": r} for j, s, r in self.joints],
                "parameters": [{"parameter": n, "share": s, "change": c, "unit": u} for n, s, c, u in self.parameters],
                "outliers": [{"row": r, "residual": e} for r, e in self.outliers],
                "world": None if self.world is None else self.world.tolist(), "note": self.note,
                "poses": self.poses, "poses_ranked": self.poses_ranked, "budget_reached": self.budget_reached}

    def text(self) -> str:
        r = self.residuals
        out = [f"model vs measurements (with its best base and marker): position RMS {r['position_rms'] * 1e3:.4f} mm, "
               f"max {r['position_max'] * 1e3:.4f} mm"
               + (f"; orientation RMS {np.degrees(r['orientation_rms']):.4f} deg" if "orientation_rms" in r else "")]
        if self.same:
            out.append(f"the model is the measured robot (RMS <= {self.tol * 1e3:g} mm)")
        else:
            out.append(f"the model is NOT the measured robot (RMS > {self.tol * 1e3:g} mm)")
        if self.note:
            out.append(self.note)
        elif not self.same:
            out.append("share of the error each joint's parameters explain (fitted alone, with base and marker):")
            for name, share, rms in self.joints:
                out.append(f"  {name:<28} {share * 100:6.1f} %   (RMS left {rms * 1e3:.4f} mm)")
            if self.parameters:
                out.append(f"within joint {self.joints[0][0]}, each parameter alone:")
                for name, share, change, unit in self.parameters:
                    shown = f"{change * 1e3:+.4g} mm" if unit == "m" else f"{np.degrees(change):+.4g} deg"
                    out.append(f"  {name:<38} {share * 100:6.1f} %   (change {shown})")
            out += self._limits()
            out.append("run 'robkin calibrate' to fit every parameter at once")
        if self.outliers:
            out.append("outliers (left out): " + ", ".join(f"row {r} ({e * 1e3:.4f} mm)" for r, e in self.outliers))
        return "\n".join(out)

    def _limits(self) -> list[str]:
        """What bounded the joint-by-joint fits, when something did."""
        out = []
        if 0 < self.poses_ranked < self.poses:
            out.append(f"(the shares are from {self.poses_ranked} of the {self.poses} poses, evenly spread)")
        if self.budget_reached:
            out.append(f"the joint-by-joint fits reached their work budget ({WORK:,} pose evaluations): the "
                       f"joints and parameters not listed were not fitted")
        return out


def diagnose(robot: Robot, q: ArrayLike, positions: ArrayLike, orientations: ArrayLike | None = None, *,
             model: str = "hayati", world: ArrayLike | None = None, marker: ArrayLike | None = None,
             tol: float = DEFAULT_TOL, rows: list[int] | None = None) -> Diagnosis:
    """Compare a model with measured samples (arguments as ``calibrate``'s); see the module doc.

    ``robot`` (the model), ``q`` (N, n), ``positions`` (N, 3) m, ``orientations`` (N, 3, 3) or (N, 4),
    optional, ``model``, ``world`` (4, 4), ``marker`` (3,) m and ``rows`` as for ``calibrate``; ``tol``: the
    RMS position error (m) below which the model explains the samples.
    """
    # the robust loss of calibrate: a bad measurement (5.5 robust deviations off) is listed, not blamed
    # on a joint; a model's systematic error spreads smoothly over the poses and is not cut off
    kw: dict[str, Any] = dict(model=model, world=world, marker=marker, rows=rows)
    base = calibrate(robot, q, positions, orientations, kinematics=False, **kw)
    res = base.before_fit
    joints: list[tuple[str, float, float]] = []
    params: list[tuple[str, float, float, str]] = []
    total = res["position_rms"] ** 2
    note = None
    if res["position_rms"] > max(tol, INCONSISTENT * robot.scale):
        note = (f"the measurements are not of this model: the RMS left ({res['position_rms'] * 1e3:.4g} mm) is more "
                f"than {INCONSISTENT:g} of the robot's size ({robot.scale * 1e3:.4g} mm); no joint-by-joint "
                f"diagnosis (check the model, the joint order and units of the file, the base and tip links)")
    elif res["position_rms"] > tol and total > 0:
        budget = Budget(WORK)
        Q, P, O, kw, total = _ranking_poses(robot, q, positions, orientations, kw, total)
        ranked = len(Q)
        for j in robot.joints:
            fit = calibrate(robot, Q, P, O, only=[j.name], budget=budget, **kw)
            if budget.reached:   # cut short: its RMS is not what the joint explains
                break
            left = fit.after_fit["position_rms"]
            joints.append((j.name, max(0.0, 1.0 - left ** 2 / total), left))   # a fit never adds error
        joints.sort(key=lambda t: -t[1])
        best = joints[0][0] if joints and not budget.reached else None
        full = None if best is None else calibrate(robot, Q, P, O, only=[best], budget=budget, **kw)
        for prm in [] if full is None or budget.reached else full.parameters:
            if prm.group != best or not prm.identified:
                continue
            fit = calibrate(robot, Q, P, O, only=[prm.name], budget=budget, **kw)
            if budget.reached:
                break
            one = next(x for x in fit.parameters if x.name == prm.name)
            params.append((prm.name, 1.0 - fit.after_fit["position_rms"] ** 2 / total, one.estimate - one.nominal,
                           prm.unit))
        params.sort(key=lambda t: -t[1])
        return Diagnosis(res, joints, params, tol, base.robot.world, base.outliers, note, base.poses_fit, ranked,
                         budget.reached)
    return Diagnosis(res, joints, params, tol, base.robot.world, base.outliers, note, base.poses_fit)


def _ranking_poses(robot: Robot, q: ArrayLike, positions: ArrayLike, orientations: ArrayLike | None,
                   kw: dict[str, Any], total: float) -> tuple[np.ndarray, np.ndarray, np.ndarray | None,
                                                          dict[str, Any], float]:
    """The poses of the joint-by-joint fits: all of them, or ``DIAGNOSIS_POSES`` evenly spaced ones
    (the first and last included) with the base fit's squared RMS on those, the shares' denominator."""
    Q, P = np.asarray(q, dtype=float), np.asarray(positions, dtype=float)
    O = None if orientations is None else np.asarray(orientations, dtype=float)
    if len(Q) <= DIAGNOSIS_POSES:
        return Q, P, O, kw, total
    k = np.unique(np.linspace(0, len(Q) - 1, DIAGNOSIS_POSES).round().astype(int))
    rows = kw.get("rows")
    kw = {**kw, "rows": None if rows is None else [rows[i] for i in k]}
    Q, P, O = Q[k], P[k], None if O is None else O[k]
    base = calibrate(robot, Q, P, O, kinematics=False, **kw)
    return Q, P, O, kw, base.before_fit["position_rms"] ** 2
