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
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..robot import Robot
from .solve import calibrate

__all__ = ["Diagnosis", "diagnose", "DEFAULT_TOL", "INCONSISTENT"]

#: Default RMS position residual (m) a model may leave, with its best base and marker, and still count
#: as the measured robot: between a calibrated robot's accuracy (0.05-0.3 mm) and an uncalibrated
#: one's (1-5 mm).
DEFAULT_TOL = 5e-4
#: Position RMS left by the base fit, as a fraction of the robot's size (``Robot.scale``), beyond which
#: the measurements are taken as not of this model: no joint-by-joint diagnosis (it would explain nothing
#: and take 1 + n + 6 full fits that each run to their evaluation limit).
INCONSISTENT = 0.25


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
    """

    residuals: dict[str, float]
    joints: list[tuple[str, float, float]]
    parameters: list[tuple[str, float, float, str]]
    tol: float
    world: np.ndarray | None = None
    outliers: list[tuple[int, float]] = field(default_factory=list)
    note: str | None = None

    @property
    def same(self) -> bool:
        return self.residuals["position_rms"] <= self.tol

    def to_dict(self) -> dict[str, Any]:
        return {"same": self.same, "tol": self.tol, "residuals": self.residuals,
                "joints": [{"joint": j, "share": s, "position_rms_after": r} for j, s, r in self.joints],
                "parameters": [{"parameter": n, "share": s, "change": c, "unit": u} for n, s, c, u in self.parameters],
                "outliers": [{"row": r, "residual": e} for r, e in self.outliers],
                "world": None if self.world is None else self.world.tolist(), "note": self.note}

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
            out.append("run 'robkin calibrate' to fit every parameter at once")
        if self.outliers:
            out.append("outliers (left out): " + ", ".join(f"row {r} ({e * 1e3:.4f} mm)" for r, e in self.outliers))
        return "\n".join(out)


def diagnose(robot: Robot, q: ArrayLike, positions: ArrayLike, orientations: ArrayLike | None = None, *,
             model: str = "hayati", world: ArrayLike | None = None, marker: ArrayLike | None = None,
             tol: float = DEFAULT_TOL, rows: list[int] | None = None) -> Diagnosis:
    """Compare a model with measured samples (arguments as ``calibrate``'s); see the module doc."""
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
        for j in robot.joints:
            fit = calibrate(robot, q, positions, orientations, only=[j.name], **kw)
            left = fit.after_fit["position_rms"]
            joints.append((j.name, max(0.0, 1.0 - left ** 2 / total), left))   # a fit never adds error
        joints.sort(key=lambda t: -t[1])
        best = joints[0][0]
        full = calibrate(robot, q, positions, orientations, only=[best], **kw)
        for prm in full.parameters:
            if prm.group != best or not prm.identified:
                continue
            fit = calibrate(robot, q, positions, orientations, only=[prm.name], **kw)
            one = next(x for x in fit.parameters if x.name == prm.name)
            params.append((prm.name, 1.0 - fit.after_fit["position_rms"] ** 2 / total, one.estimate - one.nominal,
                           prm.unit))
        params.sort(key=lambda t: -t[1])
    return Diagnosis(res, joints, params, tol, base.robot.world, base.outliers, note)
