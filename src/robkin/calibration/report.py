"""The calibration report: residuals before and after, parameters with standard deviations, warnings."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..robot import Robot

__all__ = ["CalibrationResult", "Parameter", "residual_stats"]


def residual_stats(pos: np.ndarray, ori: np.ndarray | None = None) -> dict[str, float]:
    """RMS and max of position residuals (N, 3) (m) and orientation residuals (N, 3) rotation vectors (rad)."""
    e = np.linalg.norm(pos, axis=1)
    out = {"position_rms": float(np.sqrt(np.mean(e ** 2))), "position_max": float(e.max())}
    if ori is not None:
        a = np.linalg.norm(ori, axis=1)
        out.update(orientation_rms=float(np.sqrt(np.mean(a ** 2))), orientation_max=float(a.max()))
    return out


@dataclass
class Parameter:
    """One error parameter: its nominal value and estimate (m or rad) and standard deviation."""

    name: str
    unit: str
    group: str
    nominal: float
    estimate: float
    std: float | None
    identified: bool
    at_bound: bool = False

    def to_dict(self) -> dict[str, Any]:
        return {"name": self.name, "unit": self.unit, "group": self.group, "nominal": self.nominal,
                "estimate": self.estimate, "change": self.estimate - self.nominal, "std": self.std,
                "identified": self.identified, "at_bound": self.at_bound}


@dataclass
class CalibrationResult:
    """What ``robkin.calibrate`` found.

    Attributes
    ----------
    robot : Robot
        The calibrated robot: ``robot.world`` is its base in the measuring frame and its tool origin the
        measured point, so ``robot.world @ robot.fk(q)`` predicts a measurement.
    nominal : Robot
        The nominal model with its best base and marker (what "before" refers to).
    model : str
        The error model ('hayati', 'mdh' or 'poe').
    parameters : list of Parameter
    unidentifiable : list of str
        One sentence per parameter the measurements cannot determine.
    condition : float
        Condition number of the scaled identification Jacobian (NaN if kinematics were not fitted).
    before_fit, before_holdout, after_fit, after_holdout : dict
        Residual statistics (``residual_stats``; empty without a hold-out).
    outliers : list of (row, residual)
        Poses rejected by the robust loss: their row in the measurements (1-based) and residual norm.
    warnings : list of str
    orientation_weight : float or None
        Metres per radian used (None without measured orientations).
    stiffness : dict or None
        With ``compliance``: per joint name, ``stiffness`` (N m/rad, N/m; None where not observable or
        not significant), ``compliance`` (its inverse as fitted, None if not fitted), ``std`` (of the
        compliance) and ``observable``.
    flange : (4, 4) array or None
        The calibrated flange (the nominal tool frame, moved by the calibration) in the robot base frame:
        ``robot.tool`` is the marker on it.
    """

    robot: Robot
    nominal: Robot
    model: str
    parameters: list[Parameter]
    unidentifiable: list[str]
    condition: float
    before_fit: dict[str, float]
    before_holdout: dict[str, float]
    after_fit: dict[str, float]
    after_holdout: dict[str, float]
    outliers: list[tuple[int, float]] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    orientation_weight: float | None = None
    poses_fit: int = 0
    poses_holdout: int = 0
    #: the nominal robot's tool frame (the flange the marker is given in), (4, 4)
    nominal_tool: np.ndarray | None = None
    stiffness: dict[str, dict[str, Any]] | None = None
    flange: np.ndarray | None = None

    def to_dict(self) -> dict[str, Any]:
        """The report as JSON-ready data."""
        return {
            "model": self.model, "poses": {"fit": self.poses_fit, "holdout": self.poses_holdout},
            "residuals": {"before": {"fit": self.before_fit, "holdout": self.before_holdout},
                          "after": {"fit": self.after_fit, "holdout": self.after_holdout}},
            "condition_number": None if np.isnan(self.condition) else self.condition,
            "parameters": [p.to_dict() for p in self.parameters],
            "unidentifiable": self.unidentifiable,
            "outliers": [{"row": r, "residual": e} for r, e in self.outliers],
            "warnings": self.warnings,
            "orientation_weight": self.orientation_weight,
            "world": self.robot.world.tolist(),
            "marker": None if self.nominal_tool is None else
            (np.linalg.inv(self.nominal_tool) @ self.robot.tool).tolist(),
            "stiffness": self.stiffness,
        }

    def text(self) -> str:
        """The report as readable text."""
        out = [f"calibration ({self.model} model): {self.poses_fit} poses fitted"
               + (f", {self.poses_holdout} held out" if self.poses_holdout else "")]
        out.append("residuals                 position RMS   position max" +
                   ("   orientation RMS  orientation max" if "orientation_rms" in self.after_fit else ""))
        for label, st in (("before (fit)", self.before_fit), ("after (fit)", self.after_fit),
                          ("before (hold-out)", self.before_holdout), ("after (hold-out)", self.after_holdout)):
            if st:
                line = f"  {label:<22} {_mm(st['position_rms'])}   {_mm(st['position_max'])}"
                if "orientation_rms" in st:
                    line += f"   {_deg(st['orientation_rms'])}   {_deg(st['orientation_max'])}"
                out.append(line)
        out.append("  (before: the nominal model with its best base and marker)")
        if not np.isnan(self.condition):
            out.append(f"condition number (scaled): {self.condition:.3g}")
        if self.orientation_weight is not None:
            out.append(f"orientation weight: {self.orientation_weight:.4g} m/rad")
        out.append("parameters (change from nominal +- standard deviation):")
        for p in self.parameters:
            if not p.identified or p.group in ("base", "marker") or p.unit not in ("m", "rad"):
                continue   # (compliances: as stiffnesses below)
            scale, unit = (1e3, "mm") if p.unit == "m" else (np.degrees(1.0), "deg")
            std = "" if p.std is None else f" +- {p.std * scale:.3g}"
            out.append(f"  {p.name:<38} {(p.estimate - p.nominal) * scale:+.4g}{std} {unit}")
        for name, k in (self.stiffness or {}).items():
            if k["stiffness"] is not None:
                out.append(f"  {'joint ' + name + ' stiffness':<38} {k['stiffness']:.4g} {k['unit']} "
                           f"+- {100 * k['std'] / k['compliance']:.2g} %")
            elif k["observable"]:
                out.append(f"  {'joint ' + name + ' stiffness':<38} not determined (compliance {k['compliance']:.3g} "
                           f"+- {k['std'] or 0:.2g}: not positive beyond the noise)")
        from .. import se3

        W = self.robot.world
        out.append("robot base in the measuring frame: xyz " + " ".join(f"{v:.6g}" for v in W[:3, 3])
                   + " m, rpy " + " ".join(f"{v:.6g}" for v in se3.rpy_from_matrix(W[:3, :3])) + " rad")
        marker = se3.inv(self.nominal_tool) @ self.robot.tool if self.nominal_tool is not None else None
        if marker is not None:
            out.append("marker in the nominal tool frame: xyz " + " ".join(f"{v:.6g}" for v in marker[:3, 3]) + " m"
                       + (", rpy " + " ".join(f"{v:.6g}" for v in se3.rpy_from_matrix(marker[:3, :3])) + " rad"
                          if self.orientation_weight is not None else ""))
        for sentence in self.unidentifiable:
            out.append(f"not identifiable: {sentence}")
        if self.outliers:
            out.append("outliers (rejected): " + ", ".join(f"row {r} ({_mm(e).strip()})" for r, e in self.outliers))
        for w in self.warnings:
            out.append(f"warning: {w}")
        return "\n".join(out)


def _mm(v: float) -> str:
    return f"{v * 1e3:10.4f} mm"


def _deg(v: float) -> str:
    return f"{np.degrees(v):10.5f} deg"
