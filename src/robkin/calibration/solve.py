"""The calibration fit: base and marker first, then every identifiable parameter, robustly.

1. A starting base pose (where the robot stands in the measuring frame) and marker (the measured point on
   the tool) from the nominal model: the rigid registration of the nominal tool points onto the measured
   ones (Kabsch), alternated with the linear least-squares marker and base position (``initial_frame``).
2. The nominal model with its best base and marker (a bounded Levenberg-Marquardt fit,
   ``robkin.compiled.box_lsq``, of those parameters alone): the "before" of the report.
3. The identifiable parameters (``identifiability.identify``: QR with column pivoting of the scaled
   identification Jacobian) fitted together, in scaled variables, each kinematic parameter within a box
   around its nominal value (so that nothing runs away), by iteratively reweighted least squares: Huber
   weights per pose from a robust scale of the residuals, poses beyond ``OUTLIER_SIGMAS`` rejected and
   listed. With measured orientations, the weight of orientation against position (metres per radian) is
   estimated from the residuals (variance components) unless given.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike

from .. import se3
from ..errors import InputError
from ..robot import Robot
from .identifiability import ILL_CONDITIONED, column_scale, describe, identify
from .parameters import MODELS, ErrorModel, build_model
from .report import CalibrationResult, Parameter, residual_stats

__all__ = ["calibrate", "initial_frame", "MAX_ANGLE", "MAX_LENGTH"]

#: Box around each nominal angle (rad): calibration corrects a model that is about right, and a larger
#: change means the model or the data are wrong (and would let near-redundant parameters run away).
MAX_ANGLE = 0.2
#: Box around each nominal length, relative to the robot size (``Robot.scale``): 10 %, far beyond any
#: manufacturing error, far below a runaway common normal (the 600 m forearm of a DH fit of a UR).
MAX_LENGTH = 0.1
#: Per-pose residual norms of d Gaussian components of deviation s have medians CHI_MEDIAN[d] * s
#: (chi distribution with 3 and 6 degrees of freedom), used to turn the median into the scale s.
CHI_MEDIAN = {3: 1.5382, 6: 2.3126}
#: Huber's threshold: the 95 % quantile of the chi distribution (so that 95 % of clean poses keep weight 1).
HUBER = {3: 2.7955, 6: 3.5485}
#: A pose is an outlier beyond the 1 - 1e-6 quantile of the chi distribution: it is rejected (weight 0)
#: and listed. So far out because fitted residuals are not independent (a pose at high leverage keeps a
#: larger share of its noise), and a bad measurement (a slipped marker, a swapped line) is off by many
#: times the noise anyway; at the 1e-4 quantile clean 50-pose campaigns showed false alarms.
OUTLIER_SIGMAS = {3: 5.5376, 6: 6.1853}
#: Reweighting rounds (each a full fit from the last estimate; the weights settle in 2-3).
ROUNDS = 4
#: Levenberg-Marquardt stopping: relative cost decrease and step (scaled variables) below these are
#: ~1e-5 of the noise's effect; evaluation limit far beyond the ~10-30 steps a fit takes.
FTOL, XTOL, MAX_NFEV = 1e-12, 1e-10, 400
#: A joint moved over less than this (rad, or robot sizes for a prismatic joint) in the measurements
#: barely excites its parameters: the report warns.
MIN_SPREAD = 0.5


def calibrate(robot: Robot, q: ArrayLike, positions: ArrayLike, orientations: ArrayLike | None = None, *,
              model: str = "hayati", world: ArrayLike | None = None, marker: ArrayLike | None = None,
              orientation_weight: float | None = None, loss: str = "huber",
              holdout: float | ArrayLike | None = None, seed: int = 0, kinematics: bool = True,
              only: Sequence[str] | None = None, rows: Sequence[int] | None = None) -> CalibrationResult:
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
    kinematics : bool
        False: fit only the base and the marker (the nominal model at its best).
    only : sequence of str, optional
        Fit only these joints' parameters (joint names) or these parameters (names as in the report),
        with the base and marker: which joint explains the measurements (``robkin check``).
    rows : sequence of int, optional
        Row numbers of the poses in their file, for the outlier list (default 1..N).

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
    Q, P, Rm = _check_inputs(robot, q, positions, orientations)
    N = len(Q)
    rows = list(range(1, N + 1)) if rows is None else [int(r) for r in rows]
    if len(rows) != N:
        raise InputError(f"rows: {len(rows)} row numbers for {N} poses")
    fit, hold = _split(N, holdout, seed)
    W_known = None if world is None else _pose(world, "world")
    m_known = None if marker is None else _marker(marker, Rm is not None)
    W0, m0 = initial_frame(robot, Q[fit], P[fit], None if Rm is None else Rm[fit], W_known, m_known)
    mdl = build_model(robot, model, world=W0, marker=m0, full_pose=Rm is not None,
                      world_known=W_known is not None, marker_known=m_known is not None)
    data = _Data(mdl, Q[fit], P[fit], None if Rm is None else Rm[fit])
    if orientation_weight is not None:
        if not (np.isfinite(orientation_weight) and orientation_weight > 0):
            raise InputError(f"orientation_weight: {orientation_weight} is not a positive number of metres per radian")
        data.w_o = float(orientation_weight)
    frame_free = ([] if W_known is not None else mdl.world_params) + ([] if m_known is not None else mdl.marker_params)
    p = mdl.nominal.copy()
    if frame_free:
        p = _rounds(data, p, np.array(frame_free), loss, orientation_weight is None)
    nominal_robot = mdl.robot_at(p)
    p_before = p.copy()
    warnings: list[str] = []
    sentences: list[str] = []
    free = np.array(frame_free, dtype=int)
    condition = float("nan")
    if kinematics:
        fixed = set(frame_free) ^ set(mdl.world_params + mdl.marker_params)
        cand = np.array([i for i in range(mdl.size) if i not in fixed and (
            only is None or i in frame_free or mdl.groups[i] in only or mdl.names[i] in only)], dtype=int)
        _, J = data.residuals(p, jacobian=True)
        assert J is not None  # asked for
        ident = identify(J[:, :, cand].reshape(-1, len(cand)) * np.sqrt(data.weights).repeat(data.d)[:, None])
        free, condition = cand[ident.kept], ident.condition
        for d in ident.dropped:
            sentences.append(describe(int(cand[d]), [int(cand[k]) for k in ident.partners.get(int(d), [])],
                                      mdl.names, Rm is None, mdl.groups[cand[d]] not in ("base", "marker")))
        data.weights[:] = 1.0
        p = _rounds(data, p, free, loss, orientation_weight is None)
        if condition > ILL_CONDITIONED:
            warnings.append(f"the poses do not excite the parameters well (condition number {condition:.3g} > "
                            f"{ILL_CONDITIONED:g}): measure more poses, spread over the joint ranges")
    result_robot = mdl.robot_at(p)
    hold_data = _Data(mdl, Q[hold], P[hold], None if Rm is None else Rm[hold], data.w_o)
    inliers = data.weights > 0   # the outliers are listed apart, not mixed into the statistics
    before = (data.stats(p_before, inliers), hold_data.stats(p_before))
    after = (data.stats(p, inliers), hold_data.stats(p))
    std = data.std(p, free)
    lo, hi = _bounds(mdl)
    params = [Parameter(mdl.names[i], mdl.units[i], mdl.groups[i], float(mdl.nominal[i]), float(p[i]),
                        std.get(i), i in set(free.tolist()),
                        bool(i in set(free.tolist()) and (p[i] <= lo[i] + 1e-12 or p[i] >= hi[i] - 1e-12)))
              for i in range(mdl.size)]
    warnings += _warnings(robot, Q[fit], data, len(free), params)
    if model == "mdh" and kinematics:
        warnings += _parallel_warning(robot)
    fit_rows = [rows[i] for i in fit]
    outliers = [(fit_rows[k], float(data.pose_norms(p)[k])) for k in np.flatnonzero(data.weights == 0.0)]
    return CalibrationResult(
        robot=result_robot, nominal=nominal_robot, model=model, parameters=params, unidentifiable=sentences,
        condition=condition, before_fit=before[0], before_holdout=before[1], after_fit=after[0],
        after_holdout=after[1], outliers=outliers, warnings=warnings,
        orientation_weight=data.w_o if Rm is not None else None, poses_fit=len(fit), poses_holdout=len(hold),
        nominal_tool=robot.tool)


class _Data:
    """Measurements of the fit (or the hold-out) and their residuals for an error model."""

    def __init__(self, mdl: ErrorModel, Q: np.ndarray, P: np.ndarray, Rm: np.ndarray | None,
                 w_o: float | None = None) -> None:
        self.mdl, self.Q, self.P, self.Rm = mdl, Q, P, Rm
        self.d = 3 if Rm is None else 6
        #: metres per radian; a rotation of 1 rad counts like the robot's size until estimated
        self.w_o = float(mdl.robot.scale if w_o is None else w_o)
        self.weights = np.ones(len(Q))

    def residuals(self, p: np.ndarray, jacobian: bool = False) -> tuple[np.ndarray, np.ndarray | None]:
        """(N, d) residuals (prediction - measurement; orientation times w_o) and their Jacobian (N, d, P)."""
        T, J = self.mdl.poses(p, self.Q, jacobian=jacobian)
        r = T[:, :3, 3] - self.P
        if self.Rm is not None:
            ro = se3.log_rotation(T[:, :3, :3] @ np.swapaxes(self.Rm, 1, 2))
            r = np.concatenate([r, self.w_o * ro], axis=1)
            if J is not None:
                J = J.copy()
                J[:, 3:] *= self.w_o
        elif J is not None:
            J = J[:, :3]
        return r, J

    def pose_norms(self, p: np.ndarray) -> np.ndarray:
        return np.linalg.norm(self.residuals(p)[0], axis=1)

    def stats(self, p: np.ndarray, use: np.ndarray | None = None) -> dict[str, float]:
        """Residual statistics (``report.residual_stats``) of the poses ``use`` (default all)."""
        use = np.ones(len(self.Q), dtype=bool) if use is None else use
        if not use.any():
            return {}
        T, _ = self.mdl.poses(p, self.Q[use])
        ori = None if self.Rm is None else se3.log_rotation(T[:, :3, :3] @ np.swapaxes(self.Rm[use], 1, 2))
        return residual_stats(T[:, :3, 3] - self.P[use], ori)

    def std(self, p: np.ndarray, free: np.ndarray) -> dict[int, float]:
        """Standard deviations of the free parameters: sigma^2 (J^T W J)^-1 with sigma^2 from the
        weighted residuals over the degrees of freedom left."""
        if free.size == 0:
            return {}
        r, J = self.residuals(p, jacobian=True)
        assert J is not None
        sw = np.sqrt(self.weights)[:, None]
        A = (J[:, :, free] * sw[:, :, None]).reshape(-1, free.size)
        b = (r * sw).ravel()
        dof = int(np.count_nonzero(self.weights)) * self.d - free.size
        if dof <= 0:
            return {}
        s = column_scale(A)
        try:
            cov = np.linalg.inv((A * s).T @ (A * s)) * np.outer(s, s) * (b @ b / dof)
        except np.linalg.LinAlgError:
            return {}
        return {int(i): float(np.sqrt(max(c, 0.0))) for i, c in zip(free, np.diag(cov))}


def _rounds(data: _Data, p: np.ndarray, free: np.ndarray, loss: str, auto_weight: bool) -> np.ndarray:
    """Fit, then re-estimate the orientation weight and the robust weights, and fit again."""
    for k in range(ROUNDS if (loss == "huber" or (auto_weight and data.Rm is not None)) else 1):
        p = _fit(data, p, free)
        changed = False
        if auto_weight and data.Rm is not None:
            changed |= _update_orientation_weight(data, p)
        if loss == "huber":
            changed |= _update_robust_weights(data, p, free.size)
        if not changed:
            break
    return p


def _fit(data: _Data, p: np.ndarray, free: np.ndarray) -> np.ndarray:
    """Bounded Levenberg-Marquardt (``robkin.compiled.box_lsq``) over the free parameters, scaled."""
    from ..compiled.box_lsq import solve

    sw = np.sqrt(data.weights)[:, None]
    _, J0 = data.residuals(p, jacobian=True)
    assert J0 is not None
    s = column_scale((J0[:, :, free] * sw[:, :, None]).reshape(-1, free.size))
    lo, hi = _bounds(data.mdl)
    base = p.copy()

    def params(x: np.ndarray) -> np.ndarray:
        out = base.copy()
        out[free] = base[free] + x * s
        return out

    def fun(x: np.ndarray) -> np.ndarray:
        return (data.residuals(params(x))[0] * sw).ravel()

    def jac(x: np.ndarray) -> np.ndarray:
        J = data.residuals(params(x), jacobian=True)[1]
        assert J is not None
        return ((J[:, :, free] * sw[:, :, None]).reshape(-1, free.size)) * s

    x, *_ = solve(fun, jac, np.zeros(free.size), (lo[free] - base[free]) / s, (hi[free] - base[free]) / s,
                  ftol=FTOL, xtol=XTOL, max_nfev=MAX_NFEV)
    return params(x)


def _update_orientation_weight(data: _Data, p: np.ndarray) -> bool:
    """w_o = noise of positions / noise of orientations, from the residuals of the poses in use."""
    r, _ = data.residuals(p)
    use = data.weights > 0
    pos = np.sqrt(np.mean(r[use, :3] ** 2))
    ori = np.sqrt(np.mean(r[use, 3:] ** 2)) / data.w_o
    if not (pos > 0 and ori > 0):
        return False
    new = float(pos / ori)
    changed = abs(np.log(new / data.w_o)) > 0.05  # within 5 %: the fit would not change visibly
    data.w_o = new
    return changed


def _update_robust_weights(data: _Data, p: np.ndarray, n_free: int) -> bool:
    """Huber weights per pose; poses beyond OUTLIER_SIGMAS robust deviations get weight 0."""
    e = data.pose_norms(p)
    m = len(e) * data.d
    # the fit absorbs n_free of the m residual components: the residuals are smaller than the noise by
    # sqrt((m - n_free) / m) on average, which the scale estimate undoes
    shrink = np.sqrt(max(m - n_free, 1) / m)
    sigma = np.median(e) / CHI_MEDIAN[data.d] / shrink
    if not sigma > 0:
        return False
    w = np.minimum(1.0, HUBER[data.d] * sigma / np.maximum(e, 1e-300))
    w[e > OUTLIER_SIGMAS[data.d] * sigma] = 0.0
    changed = bool(np.any((w == 0) != (data.weights == 0)) or np.abs(w - data.weights).max() > 0.05)
    data.weights = w
    return changed


def _bounds(mdl: ErrorModel) -> tuple[np.ndarray, np.ndarray]:
    """Box of every parameter: kinematic ones around their nominal values, base and marker free."""
    lo = np.full(mdl.size, -np.inf)
    hi = np.full(mdl.size, np.inf)
    free_frame = set(mdl.world_params + mdl.marker_params)
    for i in range(mdl.size):
        if i in free_frame:
            continue
        half = MAX_ANGLE if mdl.units[i] == "rad" else MAX_LENGTH * mdl.robot.scale
        lo[i], hi[i] = mdl.nominal[i] - half, mdl.nominal[i] + half
    return lo, hi


def initial_frame(robot: Robot, Q: np.ndarray, P: np.ndarray, Rm: np.ndarray | None,
                  world: np.ndarray | None = None, marker: np.ndarray | None = None
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Starting base pose (4, 4) and marker ((3,) point, or (4, 4) pose with orientations).

    Alternates the rigid registration (Kabsch) of the nominal marker points onto the measured ones with
    the linear least-squares marker position given the base's rotation: the marker is small next to the
    robot, so a few rounds settle both.
    """
    T = robot.fk(Q)
    R, t = T[:, :3, :3], T[:, :3, 3]
    m = np.zeros(3) if marker is None else (marker if marker.shape == (3,) else marker[:3, 3])
    W = np.eye(4) if world is None else world
    for _ in range(1 if world is not None and marker is not None else 8):
        pts = t + R @ m
        if world is None:
            W = _kabsch(pts, P)
        if marker is None:
            Rw = W[:3, :3]
            A = np.einsum("ij,njk->nik", Rw, R).reshape(-1, 3)
            b = (P - W[:3, 3] - t @ Rw.T).reshape(-1)
            if world is None:   # the base's position is solved with the marker
                A = np.concatenate([A, np.tile(np.eye(3), (len(Q), 1))], axis=1)
            sol = np.linalg.lstsq(A, b, rcond=None)[0]
            m = sol[:3]
            if world is None:
                W = W.copy()
                W[:3, 3] = sol[3:]
    if Rm is None:
        return W, m if marker is None else marker
    if marker is not None and marker.shape == (4, 4):
        return W, marker
    Rmk = se3.nearest_rotation(np.einsum("nji,jk,nkl->il", R, W[:3, :3].T, Rm))  # mean of R_k^T W^T R_meas
    return W, se3.homogeneous(Rmk, m)


def _kabsch(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """The rigid motion (4, 4) taking points A (N, 3) closest onto B (N, 3)."""
    ca, cb = A.mean(axis=0), B.mean(axis=0)
    H = (A - ca).T @ (B - cb)
    U, S, Vt = np.linalg.svd(H)
    if S[1] <= 1e-9 * max(S[0], 1e-300):  # all points on a line: the rotation about it is unknown
        raise InputError("measurements: the measured points lie on a line; measure poses spread in space")
    D = np.diag([1.0, 1.0, np.sign(np.linalg.det(Vt.T @ U.T))])
    Rot = Vt.T @ D @ U.T
    return se3.homogeneous(Rot, cb - Rot @ ca)


def _check_inputs(robot: Robot, q: ArrayLike, positions: ArrayLike, orientations: ArrayLike | None
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    Q = np.asarray(q, dtype=float)
    P = np.asarray(positions, dtype=float)
    if Q.ndim != 2 or Q.shape[1] != robot.n:
        raise InputError(f"q: expected shape (N, {robot.n}) (one column per joint), got {Q.shape}")
    if P.shape != (len(Q), 3):
        raise InputError(f"positions: expected shape ({len(Q)}, 3), got {P.shape}")
    if len(Q) < 3:
        raise InputError(f"measurements: {len(Q)} poses; calibration needs many more (see the guide: 30-100)")
    for name, v in (("q", Q), ("positions", P)):
        bad = np.argwhere(~np.isfinite(v))
        if bad.size:
            raise InputError(f"{name}: pose {bad[0][0] + 1} holds a value that is not a finite number")
    if orientations is None:
        return Q, P, None
    O = np.asarray(orientations, dtype=float)
    if O.shape == (len(Q), 4):
        norms = np.linalg.norm(O, axis=1)
        off = np.flatnonzero(~(np.abs(norms - 1.0) < 1e-3))  # 3-4 digits typed: beyond, not a unit quaternion
        if off.size:
            raise InputError(f"orientations: pose {off[0] + 1}: quaternion (qw, qx, qy, qz) has norm "
                             f"{norms[off[0]]:.6g}, not 1")
        O = _matrix_from_quaternion(O / norms[:, None])
    elif O.shape == (len(Q), 3, 3):
        err = se3.rotation_error(O)
        off = np.flatnonzero(~(err < 1e-6))   # rotation matrices typed or computed to ~1e-9 and better
        if off.size:
            raise InputError(f"orientations: pose {off[0] + 1} is not a rotation matrix")
    else:
        raise InputError(f"orientations: expected ({len(Q)}, 4) quaternions (w, x, y, z) or ({len(Q)}, 3, 3) "
                         f"rotations, got {O.shape}")
    return Q, P, O


def _matrix_from_quaternion(qt: np.ndarray) -> np.ndarray:
    w, x, y, z = qt.T
    return np.stack([np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
                     np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
                     np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], -2)


def _split(N: int, holdout: float | ArrayLike | None, seed: int) -> tuple[np.ndarray, np.ndarray]:
    if holdout is None:
        return np.arange(N), np.arange(0)
    h = np.asarray(holdout)
    if h.ndim == 0:
        f = float(h)
        if not 0 <= f < 1:
            raise InputError(f"holdout: {f} is not a fraction in [0, 1)")
        k = int(round(f * N))
        mask = np.zeros(N, dtype=bool)
        mask[np.random.default_rng(seed).choice(N, size=k, replace=False)] = True
    else:
        if h.shape != (N,) or h.dtype != bool:
            raise InputError(f"holdout: expected a fraction or a boolean mask of {N} poses")
        mask = h
    if N - mask.sum() < 3:
        raise InputError("holdout: leaves fewer than 3 poses to fit")
    return np.flatnonzero(~mask), np.flatnonzero(mask)


def _pose(T: ArrayLike, name: str) -> np.ndarray:
    from ..robot import check_pose

    return check_pose(T, name)


def _marker(m: ArrayLike, full_pose: bool) -> np.ndarray:
    a = np.asarray(m, dtype=float)
    if a.shape == (3,) and np.all(np.isfinite(a)):
        return a
    if a.shape == (4, 4):
        return _pose(a, "marker")
    raise InputError("marker: expected a point (x, y, z) in the tool frame or a 4x4 pose")


def _warnings(robot: Robot, Q: np.ndarray, data: _Data, n_free: int, params: list[Parameter]) -> list[str]:
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
        if prm.at_bound:
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
