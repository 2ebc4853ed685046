"""A pose plan for a calibration campaign: which N configurations to measure, and what they promise.

``plan_poses`` draws (or takes) candidate configurations (``planning_candidates``), builds their
identification Jacobian for the error model ``calibrate`` will fit (``planning.design_problem``), picks
N of them by Fedorov's exchange on the D criterion (``planning.exchange``) and states, for a given
measurement noise, what the calibration from them should reach: the condition number of the scaled
Jacobian (as ``calibrate`` reports it), every identifiable parameter's standard deviation, and the RMS
position error of the calibrated robot over the candidates from noise alone; the same figures for N
random candidates (the median of ``RANDOM_DRAWS`` draws) say what the plan gains.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import InputError
from ..robot import Robot
from .parameters import MODELS
from .planning import design_problem, exchange, expected_error, expected_std
from .planning_candidates import Region, random_candidates

__all__ = ["Plan", "plan_poses", "DEFAULT_CANDIDATES", "DEFAULT_NOISE", "RANDOM_DRAWS"]

#: Random candidates drawn by default: on UR5, Panda and iiwa 14, 2000 candidates gave plans whose
#: expected error was within 1-3 % of an I-optimal exchange's best (tests/test_calibration_plan.py);
#: the exchange's time grows linearly with them (~0.5 s at 2000 for N = 30).
DEFAULT_CANDIDATES = 2000
#: Default measurement noise (m per coordinate): a laser tracker's, ~10 um at 1-2 m.
DEFAULT_NOISE = 10e-6
#: Random designs the plan is compared with (their median is reported).
RANDOM_DRAWS = 20
#: Random configurations inside the limits that tell how many parameters poses can determine, to warn
#: when given candidates (or a region) determine fewer: 300 x 3 rows are ~10 times the 30-40 parameters.
REFERENCE_CANDIDATES = 300


@dataclass
class Plan:
    """A pose plan and what it promises (see the module doc).

    Attributes
    ----------
    q : (N, n) array
        The configurations to measure (rad / m), in the order chosen.
    joints : list of str
        The joint names (the CSV's columns).
    model : str
        The error model planned for.
    criterion : str
        'D' (det of the information matrix maximised).
    noise : float
        Measurement noise (m per coordinate) the figures assume.
    condition : float
        Condition number of the plan's column-scaled identification Jacobian.
    parameters : list of (name, unit, std)
        The identifiable parameters and their expected standard deviations (m or rad).
    unidentifiable : list of str
        Parameters no pose can determine (held at nominal by ``calibrate``).
    expected_error : float
        RMS position error (m) of the calibrated robot over the candidates, from noise alone.
    random_condition, random_error : float
        The same for N random candidates (median of ``RANDOM_DRAWS``).
    candidates : int
        How many candidates the plan chose from.
    source : str
        Where the candidates came from.
    """

    q: np.ndarray
    joints: list[str]
    model: str
    criterion: str
    noise: float
    condition: float
    parameters: list[tuple[str, str, float]]
    unidentifiable: list[str]
    expected_error: float
    random_condition: float
    random_error: float
    candidates: int
    source: str
    marker: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    warnings: list[str] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        """The report as JSON-ready data (SI units)."""
        return {"poses": len(self.q), "joints": self.joints, "model": self.model,
                "criterion": "D-optimal (det of the information matrix maximised, Fedorov exchange)",
                "noise": self.noise, "marker": self.marker, "candidates": self.candidates, "source": self.source,
                "condition_number": self.condition, "expected_position_error_rms": self.expected_error,
                "random": {"condition_number": self.random_condition,
                           "expected_position_error_rms": self.random_error, "draws": RANDOM_DRAWS},
                "parameters": [{"name": n, "unit": u, "std": s} for n, u, s in self.parameters],
                "unidentifiable": self.unidentifiable, "warnings": self.warnings,
                "q": self.q.tolist()}

    def text(self) -> str:
        """The report as readable text."""
        N = len(self.q)
        out = [f"pose plan ({self.model} model, positions): {N} poses chosen from {self.candidates} candidates "
               f"({self.source})",
               "criterion: D-optimal (det of the information matrix J^T J maximised, Fedorov exchange)",
               f"condition number (scaled): {self.condition:.3g}   ({N} random candidates: "
               f"{self.random_condition:.3g}, median of {RANDOM_DRAWS})",
               f"expected from noise alone ({self.noise * 1e6:.3g} um per coordinate):",
               f"  position error of the calibrated robot over the candidates: RMS {self.expected_error * 1e6:.3g} um"
               f"   ({N} random candidates: {self.random_error * 1e6:.3g} um)",
               "parameters (expected standard deviation):"]
        for name, unit, std in self.parameters:
            shown = f"{std * 1e3:.3g} mm" if unit == "m" else f"{np.degrees(std):.3g} deg"
            out.append(f"  {name:<40} {shown}")
        if self.unidentifiable:
            out.append("not identifiable from positions, one of each redundant group held at nominal (calibrate "
                       "may hold another of the group): " + ", ".join(self.unidentifiable))
        out += [f"warning: {w}" for w in self.warnings]
        return "\n".join(out)


def plan_poses(robot: Robot, count: int, *, model: str = "hayati", candidates: np.ndarray | None = None,
               region: Region | None = None, noise: float = DEFAULT_NOISE, marker: np.ndarray | None = None,
               base_known: bool = False, random_count: int = DEFAULT_CANDIDATES, seed: int = 0,
               source: str | None = None) -> Plan:
    """Choose ``count`` configurations to measure for a calibration (see the module doc).

    Parameters
    ----------
    robot : Robot
        The nominal model; its tool frame is the flange the marker sits on.
    count : int
        Poses to plan (N).
    model : str
        The error model the calibration will fit ('hayati', 'mdh' or 'poe').
    candidates : (C, n) array, optional
        The configurations to choose from (default: ``random_count`` uniform inside the joint limits).
    region : planning_candidates.Region, optional
        Keep only candidates whose marker the measuring device sees (box or cone, model's world frame).
    noise : float
        Measurement noise (m per coordinate) of the expected figures.
    marker : (3,) array, optional
        Where the marker will sit in the tool frame (m); default the tool origin. Off the last axis, it
        makes the last joint's parameters identifiable.
    base_known : bool
        The robot base in the measuring frame will be known (``calibrate(world=...)``).
    random_count : int
        Random candidates drawn when none are given.
    seed : int
        Seed of the random candidates and of the random designs compared with.
    source : str, optional
        Where given candidates come from (a file name), for the report and messages.
    """
    if model not in MODELS:
        raise InputError(f"model '{model}' is not one of {', '.join(MODELS)}")
    if not (isinstance(count, (int, np.integer)) and count >= 1):
        raise InputError(f"--plan: {count!r} is not a positive number of poses")
    if not (np.isfinite(noise) and noise > 0):
        raise InputError(f"--noise: {noise} is not a positive number of metres")
    if marker is not None:
        marker = np.asarray(marker, dtype=float)
    rng = np.random.default_rng(seed)
    if candidates is None:
        Q = random_candidates(robot, max(random_count, count), rng, region, marker, needed=count)
        source = "random inside the joint limits" + (f" with the marker in {region.describe()}" if region else "")
    else:
        Q = np.asarray(candidates, dtype=float)
        source = "given" if source is None else f"from {source}"
        if region is not None:
            from .planning_candidates import marker_points

            Q = Q[region.inside(marker_points(robot, Q, marker))]
            source += f", with the marker in {region.describe()}"
    if len(Q) < count:
        raise InputError(f"--plan {count}: only {len(Q)} candidate configurations ({source}); give more candidates "
                         f"or plan fewer poses")
    problem = design_problem(robot, Q, model, marker, base_known)
    K = problem.J.shape[2]
    if count * 3 < K:
        raise InputError(f"--plan {count}: {count} poses give {3 * count} measured values for the {K} identifiable "
                         f"parameters of the {model} model; plan at least {-(-K // 3)} poses (better 2-3 times that)")
    warnings = []
    if candidates is not None or region is not None:   # do they lose parameters random poses determine?
        full = design_problem(robot, random_candidates(robot, REFERENCE_CANDIDATES, np.random.default_rng(seed)),
                              model, marker, base_known).J.shape[2]
        if K < full:
            warnings.append(f"the candidates determine {K} of the {full} parameters poses spread over the joint "
                            f"limits determine: spread them over the joint ranges (or widen the region)")
    try:
        design = exchange(problem, count, "D")
    except np.linalg.LinAlgError:
        raise InputError(f"--plan {count}: no {count} of the candidates determine the {K} parameters together; "
                         f"plan more poses or give more varied candidates") from None
    J_all = problem.J / problem.scale
    err = expected_error(J_all[design], J_all, noise)
    std = expected_std(J_all[design], noise)
    randoms = [rng.choice(len(Q), size=count, replace=False) for _ in range(RANDOM_DRAWS)]
    r_err = float(np.median([expected_error(J_all[r], J_all, noise) for r in randoms]))
    r_cond = float(np.median([_condition(J_all[r]) for r in randoms]))
    params = [(n, u, float(s)) for n, u, s in zip(problem.names, problem.units, std)]
    return Plan(Q[design], [j.name for j in robot.joints], model, "D", float(noise), _condition(J_all[design]),
                params, problem.dropped, err, r_cond, r_err, len(Q), source,
                [0.0, 0.0, 0.0] if marker is None else [float(v) for v in marker], warnings)


def _condition(J: np.ndarray) -> float:
    """Condition number of the column-scaled (N * d, K) Jacobian, as ``identifiability.identify``."""
    from .identifiability import column_scale

    A = J.reshape(-1, J.shape[2])
    s = np.linalg.svd(A * column_scale(A), compute_uv=False)
    return float(s[0] / s[-1]) if s[-1] > 0 else float("inf")
