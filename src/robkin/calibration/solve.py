"""The calibration: base and marker first, then every identifiable parameter, robustly; the report.

1. A starting base pose (where the robot stands in the measuring frame) and marker (the measured point on
   the tool) from the nominal model (``start.initial_frame``: Kabsch registration alternated with the
   linear least-squares marker and base position).
2. The nominal model with its best base and marker (``fit.fit_rounds`` over those parameters alone, a
   bounded Levenberg-Marquardt fit, ``robkin.compiled.runtime.box_lsq``): the "before" of the report.
3. The identifiable parameters (``identifiability.identify``: QR with column pivoting of the scaled
   identification Jacobian) fitted together by ``fit.fit_rounds``: scaled variables, each kinematic
   parameter within a box around its nominal value, iteratively reweighted (Huber weights per pose,
   outliers rejected and listed; the orientation weight estimated from the residuals unless given).

With ``compliance``, one more parameter per joint, its compliance (1 / stiffness), enters the same fit
(``parameters``: the joint value becomes q - c tau, tau the holding torques of links and payload from the
nominal model, ``compliance.holding_torques``); a joint whose torque stays ~0 over the poses is left out
as unobservable (``TORQUE_FLOOR``), and a stiffness is written only where the compliance is positive
beyond ``SIGNIFICANT`` standard deviations.

Inputs are checked by ``inputs``; the result is a ``report.CalibrationResult`` with warnings about poses
that excite the parameters poorly.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np
from numpy.typing import ArrayLike

from .. import se3
from ..errors import InputError
from ..robot import Robot
from .fit import MAX_ANGLE, MAX_LENGTH, Budget, FitData, bounds, fit_rounds, stacked
from .identifiability import ILL_CONDITIONED, describe, identify
from .inputs import check_marker, check_measured, check_pose, split_holdout
from .parameters import MODELS, ErrorModel, build_model
from .report import CalibrationResult, Parameter
from .start import initial_frame

__all__ = ["calibrate", "initial_frame", "MAX_ANGLE", "MAX_LENGTH"]

#: A joint moved over less than this (rad, or robot sizes for a prismatic joint) in the measurements
#: barely excites its parameters: the report warns.
MIN_SPREAD = 0.5
#: Pose evaluations of a calibration outside its fits, charged to a budget: the start's FK, the
#: identification's Jacobian, the statistics before and after (fit and hold-out), the standard
#: deviations' Jacobian and the outliers' residuals.
OUTSIDE_FITS = 8
#: A joint whose RMS holding torque over the poses is below this fraction of the most loaded joint's
#: deflects, at equal stiffness, 1000 times less than that joint: below what any tracker resolves next
#: to it (the loaded joints' deflections are ~1e-4 rad), so its stiffness is reported as not observable.
#: A vertical first axis under gravity along it carries ~1e-16 of the others' torque.
TORQUE_FLOOR = 1e-3
#: A compliance is turned into a stiffness only when it is positive by this many standard deviations
#: (a 1-in-1000 chance that noise alone makes a rigid joint look compliant); else "not determined".
SIGNIFICANT = 3.0


def calibrate(robot: Robot, q: ArrayLike, positions: ArrayLike, orientations: ArrayLike | None = None, *,
              model: str = "hayati", world: ArrayLike | None = None, marker: ArrayLike | None = None,
              orientation_weight: float | None = None, loss: str = "huber",
              holdout: float | ArrayLike | None = None, seed: int = 0, kinematics: bool = True,
              only: Sequence[str] | None = None, rows: Sequence[int] | None = None,
              budget: Budget | None = None, compliance: bool = False, payload: ArrayLike | None = None,
              payload_com: ArrayLike | None = None, gravity: ArrayLike | None = None) -> CalibrationResult:
    """Identify the real robot from measured tool points (and orientations).

    Parameters
    ----------
    robot : Robot
        The nominal model. Its tool frame is the flange the marker sits on.
    q : (N, n) array
        Joint values of the measured poses (rad / m).
    positions : (N, 3) array
        The measured point in the measuring device's frame (m).
    orientations : (N, 3, 3) rotations or (N, 4) unit quaternions (w, x, y, z), optional
        The measured orientation of the marker, in the measuring frame.
    model : str
        'hayati' (Hayati rows between nearly parallel axes, DH elsewhere), 'mdh' or 'poe'.
    world : (4, 4) array, optional
        The robot base in the measuring frame, if known (held fixed); identified otherwise.
    marker : (3,) point or (4, 4) pose in the tool frame, optional
        The marker, if known (held fixed); identified otherwise.
    orientation_weight : float, optional
        Metres per radian: how much an orientation residual counts against a position residual.
        Default: estimated from the residuals (the ratio of their noise levels).
    loss : str
        'huber' (default: Huber weights, outliers rejected and listed) or 'linear' (plain least squares).
    holdout : float in [0, 1) or (N,) bool mask, optional
        Poses kept out of the fit to test the result on (a fraction is picked at random with ``seed``).
    seed : int
        The random seed of the held-out poses' choice (the same seed, the same poses).
    kinematics : bool
        False: fit only the base and the marker (the nominal model at its best).
    only : sequence of str, optional
        Fit only these joints' parameters (joint names) or these parameters (names as in the report),
        with the base and marker: which joint explains the measurements (``robkin check``).
    rows : sequence of int, optional
        Row numbers of the poses in their file, for the outlier list (default 1..N).
    budget : fit.Budget, optional
        Pose evaluations the fits may use, shared with other calls given the same budget (``robkin
        check``'s joint-by-joint fits); once it is reached the fits stop where they are and
        ``budget.reached`` is set. The call's evaluations outside the fits (``OUTSIDE_FITS`` per pose)
        are charged too. Default: no limit but each fit's own (``fit.MAX_NFEV``).
    compliance : bool
        Also identify each joint's stiffness (N m/rad, N/m) from the deflections that the gravity torques
        of the links (where the model has masses) and of ``payload`` cause (``compliance``).
    payload : float or (N,) array, optional
        Payload mass (kg) per pose, at the measured point unless ``payload_com`` says otherwise. Without
        ``compliance``, a model whose joints carry a ``stiffness`` is deflected by it (as ``robkin check``).
    payload_com : (3,) array, optional
        The payload's centre of mass in the model's tool (flange) frame (m).
    gravity : (3,) array, optional
        Gravity in the robot base frame (m/s^2), default (0, 0, -9.81).

    Returns
    -------
    CalibrationResult
        ``.robot``: the calibrated robot, ``world @ fk(q)`` predicting the measured point (and
        orientation); the report (``.text()``, ``.to_dict()``).
    """
    if model not in MODELS:
        raise InputError(f"model '{model}' is not one of {', '.join(MODELS)}")
    if loss not in ("huber", "linear"):
        raise InputError(f"loss '{loss}' is not one of huber, linear")
    Q, P, Rm = check_measured(robot, q, positions, orientations)
    N = len(Q)
    rows = list(range(1, N + 1)) if rows is None else [int(r) for r in rows]
    if len(rows) != N:
        raise InputError(f"rows: {len(rows)} row numbers for {N} poses")
    fit, hold = split_holdout(N, holdout, seed)
    W_known = None if world is None else check_pose(world, "world")
    m_known = None if marker is None else check_marker(marker, Rm is not None)
    if payload is not None and not compliance and any(j.stiffness for j in robot.joints):
        from .compliance import compliant_q

        Q = compliant_q(robot, Q, payload, payload_com, gravity)   # the model's own stiffness, as check does
    W0, m0 = initial_frame(robot, Q[fit], P[fit], None if Rm is None else Rm[fit], W_known, m_known)
    torques = _torques(robot, Q, payload, payload_com, m0, gravity) if compliance else None
    mdl = build_model(robot, model, world=W0, marker=m0, full_pose=Rm is not None,
                      world_known=W_known is not None, marker_known=m_known is not None, compliance=compliance)
    data = FitData(mdl, Q[fit], P[fit], None if Rm is None else Rm[fit],
                   torques=None if torques is None else torques[fit])
    if budget is not None:
        budget.left -= OUTSIDE_FITS * N
    if orientation_weight is not None:
        if not (np.isfinite(orientation_weight) and orientation_weight > 0):
            raise InputError(f"orientation_weight: {orientation_weight} is not a positive number of metres per radian")
        data.w_o = float(orientation_weight)
    frame_free = ([] if W_known is not None else mdl.world_params) + ([] if m_known is not None else mdl.marker_params)
    p = mdl.nominal.copy()
    if frame_free:
        p = fit_rounds(data, p, np.array(frame_free), loss, orientation_weight is None, budget)
    nominal_robot = mdl.robot_at(p)
    p_before = p.copy()
    warnings: list[str] = []
    sentences: list[str] = []
    free = np.array(frame_free, dtype=int)
    condition = float("nan")
    if kinematics:
        fixed = set(frame_free) ^ set(mdl.world_params + mdl.marker_params)
        unloaded = _unloaded(mdl, data, sentences)
        cand = np.array([i for i in range(mdl.size) if i not in fixed and i not in unloaded and (
            only is None or i in frame_free or mdl.groups[i] in only or mdl.names[i] in only)], dtype=int)
        _, J = data.residuals(p, jacobian=True, columns=cand)
        assert J is not None  # asked for
        ident = identify(stacked(J) * np.sqrt(data.weights).repeat(data.d)[:, None])
        free, condition = cand[ident.kept], ident.condition
        for d in ident.dropped:
            sentences.append(describe(int(cand[d]), [int(cand[k]) for k in ident.partners.get(int(d), [])],
                                      mdl.names, Rm is None, mdl.groups[cand[d]] not in ("base", "marker")))
        data.weights[:] = 1.0
        p = fit_rounds(data, p, free, loss, orientation_weight is None, budget)
        if condition > ILL_CONDITIONED:
            warnings.append(f"the poses do not excite the parameters well (condition number {condition:.3g} > "
                            f"{ILL_CONDITIONED:g}): measure more poses, spread over the joint ranges")
    result_robot = mdl.robot_at(p)
    hold_data = FitData(mdl, Q[hold], P[hold], None if Rm is None else Rm[hold], data.w_o,
                        None if torques is None else torques[hold])
    inliers = data.weights > 0   # the outliers are listed apart, not mixed into the statistics
    before = (data.stats(p_before, inliers), hold_data.stats(p_before))
    after = (data.stats(p, inliers), hold_data.stats(p))
    std = data.std(p, free)
    lo, hi = bounds(mdl)
    params = [Parameter(mdl.names[i], mdl.units[i], mdl.groups[i], float(mdl.nominal[i]), float(p[i]),
                        std.get(i), i in set(free.tolist()),
                        bool(i in set(free.tolist()) and (p[i] <= lo[i] + 1e-12 or p[i] >= hi[i] - 1e-12)))
              for i in range(mdl.size)]
    warnings += _warnings(robot, Q[fit], data, len(free), params)
    stiffness = _stiffness(mdl, p, std, free) if compliance else None
    if stiffness is not None:
        from dataclasses import replace

        result_robot = result_robot.replace(joints=tuple(
            replace(j, stiffness=stiffness[j.name]["stiffness"]) for j in result_robot.joints))
    # the flange keeps its nominal pose relative to the last joint's axis frame: all that lies beyond
    # that axis (the last link's parameters, the marker) is one rigid offset the measurements cannot split
    flange = result_robot.frames[-2] @ se3.inv(mdl.robot_at(mdl.nominal).frames[-2]) @ robot.tool
    if model == "mdh" and kinematics:
        warnings += _parallel_warning(robot)
    fit_rows = [rows[i] for i in fit]
    rejected = np.flatnonzero(data.weights == 0.0)
    norms = data.pose_norms(p) if len(rejected) else np.empty(0)   # once, not once per outlier
    outliers = [(fit_rows[k], float(norms[k])) for k in rejected]
    return CalibrationResult(
        robot=result_robot, nominal=nominal_robot, model=model, parameters=params, unidentifiable=sentences,
        condition=condition, before_fit=before[0], before_holdout=before[1], after_fit=after[0],
        after_holdout=after[1], outliers=outliers, warnings=warnings,
        orientation_weight=data.w_o if Rm is not None else None, poses_fit=len(fit), poses_holdout=len(hold),
        nominal_tool=robot.tool, stiffness=stiffness, flange=flange)


def _torques(robot: Robot, Q: np.ndarray, payload: ArrayLike | None, payload_com: ArrayLike | None,
             marker: np.ndarray, gravity: ArrayLike | None) -> np.ndarray:
    """Holding torques (N, n) of the nominal robot, the payload at the starting marker (or its com)."""
    from ..mass_properties import link_masses
    from .compliance import check_payloads, holding_torques

    m = check_payloads(0.0 if payload is None else payload, len(Q))
    if link_masses(robot) is None and not np.any(m > 0):
        raise InputError("compliance: nothing loads the joints: the measurements carry no payload (a 'payload' "
                         "column, kg) and the model has no masses")
    com = payload_com if payload_com is not None else (marker if marker.shape == (3,) else marker[:3, 3])
    return holding_torques(robot, Q, m, com, gravity)


def _unloaded(mdl: ErrorModel, data: FitData, sentences: list[str]) -> set[int]:
    """Compliance parameters of joints whose torque stays below ``TORQUE_FLOOR`` of the most loaded
    one's: not observable (a sentence each)."""
    if not mdl.compliance_params or data.torques is None:
        return set()
    rms = np.sqrt(np.mean(data.torques ** 2, axis=0))
    out = set()
    for i, c in enumerate(mdl.compliance_params):
        if not rms[i] > TORQUE_FLOOR * rms.max():
            out.add(c)
            sentences.append(f"joint {mdl.robot.joints[i].name} stiffness is not observable: its gravity torque is "
                             f"~0 at every measured pose ({rms[i]:.2g} N m RMS; e.g. a vertical axis): left unknown")
    return out


def _stiffness(mdl: ErrorModel, p: np.ndarray, std: dict[int, float],
               free: np.ndarray) -> dict[str, dict[str, Any]]:
    """Per joint: compliance, its standard deviation, and the stiffness (None unless significant)."""
    out = {}
    kept = set(free.tolist())
    for j, c in zip(mdl.robot.joints, mdl.compliance_params):
        value, s = float(p[c]), std.get(c)
        ok = c in kept and s is not None and value > SIGNIFICANT * s
        out[j.name] = {"stiffness": 1.0 / value if ok else None, "compliance": value if c in kept else None,
                       "std": s if c in kept else None, "observable": c in kept,
                       "unit": "N m/rad" if j.revolute else "N/m"}
    return out


def _warnings(robot: Robot, Q: np.ndarray, data: FitData, n_free: int, params: list[Parameter]) -> list[str]:
    out = []
    values = len(Q) * data.d
    if values < 2 * n_free:
        out.append(f"{len(Q)} poses give {values} measured values for {n_free} parameters: measure at least "
                   f"{int(np.ceil(3 * n_free / data.d))} poses (3 values per parameter), better 2-3 times that")
    spread = np.ptp(Q, axis=0) / np.where(robot.revolute, 1.0, robot.scale)
    for j, s in zip(robot.joints, spread):
        if s < MIN_SPREAD:
            out.append(f"joint {j.name} moved over only {s:.3g} {'rad' if j.revolute else 'robot sizes'} in the "
                       f"measurements: spread the poses over its range")
    for prm in params:
        if prm.at_bound and prm.unit in ("m", "rad"):   # (a compliance at its bound: "not determined")
            out.append(f"{prm.name} stopped at its bound ({prm.estimate - prm.nominal:+.3g} {prm.unit} from nominal): "
                       f"the model or the measurements are far from each other")
    return out


def _parallel_warning(robot: Robot) -> list[str]:
    """The modified DH model cannot tilt an axis out of the plane it shares with a parallel neighbour
    (that needs Hayati's beta): name the pairs where it falls short."""
    from ..representations.hayati import hayati_frames

    rows = hayati_frames(robot)[2]
    pairs = [f"{robot.joints[i].name}-{robot.joints[i + 1].name}" for i in np.flatnonzero(rows[:-1])]
    if not pairs:
        return []
    return [f"joint axes {', '.join(pairs)} are nearly parallel: the mdh model cannot represent their "
            f"misalignment (use the default hayati model, or poe)"]
