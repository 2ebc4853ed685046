"""The robust fit of a calibration: bounded Levenberg-Marquardt in scaled variables, reweighted.

``FitData`` holds the measurements (the fit's or the hold-out's) and their residuals for an error model;
``fit_rounds`` fits the free parameters, each kinematic one within a box around its nominal value
(``bounds``: so that nothing runs away), by iteratively reweighted least squares: Huber weights per pose
from a robust scale of the residuals, poses beyond ``OUTLIER_SIGMAS`` rejected (weight 0). With measured
orientations, the weight of orientation against position (metres per radian) is estimated from the
residuals (variance components) unless given.
"""

from __future__ import annotations

import numpy as np

from .. import se3
from .identifiability import column_scale
from .parameters import ErrorModel
from .report import residual_stats

__all__ = ["FitData", "fit_rounds", "bounds", "MAX_ANGLE", "MAX_LENGTH", "CHI_MEDIAN", "HUBER", "OUTLIER_SIGMAS",
           "ROUNDS", "FTOL", "XTOL", "MAX_NFEV", "MAX_COMPLIANCE", "Budget", "stacked"]

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
#: Box of a joint's compliance (rad per N m, m per N) around 0: a stiffness of 100 N m/rad, softer
#: than any arm joint that holds a payload (industrial arms: 1e4-1e6, cobots' strain-wave gears 1e3-1e5);
#: negative values stay allowed so that noise on an unexcited joint shows as such, not as a bound.
MAX_COMPLIANCE = 1e-2


class Budget:
    """Work a group of fits may do, counted in pose evaluations: one residual or one Jacobian evaluated
    at one pose. Deterministic (the same input stops at the same step on any machine), unlike a clock.

    A fit given a budget evaluates at most what is left of it (``_fit`` caps its evaluation limit to
    that); a fit cut short by it, or not run for want of it, sets ``reached``.
    """

    def __init__(self, evaluations: int) -> None:
        self.total = int(evaluations)
        self.left = int(evaluations)
        self.reached = False

    @property
    def used(self) -> int:
        return self.total - self.left


class FitData:
    """Measurements of the fit (or the hold-out) and their residuals for an error model."""

    def __init__(self, mdl: ErrorModel, Q: np.ndarray, P: np.ndarray, Rm: np.ndarray | None,
                 w_o: float | None = None, torques: np.ndarray | None = None) -> None:
        self.mdl, self.Q, self.P, self.Rm = mdl, Q, P, Rm
        #: holding torques (N, n) the compliance parameters multiply (None: a rigid model)
        self.torques = torques
        self.d = 3 if Rm is None else 6
        #: metres per radian; a rotation of 1 rad counts like the robot's size until estimated
        self.w_o = float(mdl.robot.scale if w_o is None else w_o)
        self.weights = np.ones(len(Q))

    def residuals(self, p: np.ndarray, jacobian: bool = False, columns: np.ndarray | None = None
                  ) -> tuple[np.ndarray, np.ndarray | None]:
        """(N, d) residuals (prediction - measurement; orientation times w_o) and their Jacobian (N, d, P),
        or its ``columns`` (N, d, K) only (``ErrorModel.poses``)."""
        T, J = self.mdl.poses(p, self.Q, jacobian=jacobian, columns=columns, torques=self.torques)
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
        T, _ = self.mdl.poses(p, self.Q[use], torques=None if self.torques is None else self.torques[use])
        ori = None if self.Rm is None else se3.log_rotation(T[:, :3, :3] @ np.swapaxes(self.Rm[use], 1, 2))
        return residual_stats(T[:, :3, 3] - self.P[use], ori)

    def std(self, p: np.ndarray, free: np.ndarray) -> dict[int, float]:
        """Standard deviations of the free parameters: sigma^2 (J^T W J)^-1 with sigma^2 from the
        weighted residuals over the degrees of freedom left."""
        if free.size == 0:
            return {}
        r, J = self.residuals(p, jacobian=True, columns=free)
        assert J is not None
        sw = np.sqrt(self.weights)[:, None]
        A = stacked(J * sw[:, :, None])
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


def fit_rounds(data: FitData, p: np.ndarray, free: np.ndarray, loss: str, auto_weight: bool,
               budget: Budget | None = None) -> np.ndarray:
    """Fit, then re-estimate the orientation weight and the robust weights, and fit again; with a
    ``budget``, no further round once it is reached."""
    for k in range(ROUNDS if (loss == "huber" or (auto_weight and data.Rm is not None)) else 1):
        p = _fit(data, p, free, budget)
        if budget is not None and budget.reached:
            break
        changed = False
        if auto_weight and data.Rm is not None:
            changed |= _update_orientation_weight(data, p)
        if loss == "huber":
            changed |= _update_robust_weights(data, p, free.size)
        if not changed:
            break
    return p


def _fit(data: FitData, p: np.ndarray, free: np.ndarray, budget: Budget | None = None) -> np.ndarray:
    """Bounded Levenberg-Marquardt (``robkin.compiled.runtime.box_lsq``) over the free parameters, scaled;
    with a ``budget``, at most the evaluations left of it (a Jacobian counts as one evaluation, like a
    residual: the solver makes at most one per residual, so a limit of k residuals costs <= 2k + 1)."""
    from ..compiled.runtime.box_lsq import solve

    N = len(data.Q)
    max_nfev = MAX_NFEV
    if budget is not None:
        max_nfev = min(MAX_NFEV, (budget.left // max(N, 1) - 1) // 2)
        if max_nfev < 1:
            budget.reached = True
            return p
    sw = np.sqrt(data.weights)[:, None]
    _, J0 = data.residuals(p, jacobian=True, columns=free)
    assert J0 is not None
    s = column_scale(stacked(J0 * sw[:, :, None]))
    lo, hi = bounds(data.mdl)
    base = p.copy()

    def params(x: np.ndarray) -> np.ndarray:
        out = base.copy()
        out[free] = base[free] + x * s
        return out

    def fun(x: np.ndarray) -> np.ndarray:
        return (data.residuals(params(x))[0] * sw).ravel()

    def jac(x: np.ndarray) -> np.ndarray:
        J = data.residuals(params(x), jacobian=True, columns=free)[1]
        assert J is not None
        return stacked(J * sw[:, :, None]) * s

    x, _, nfev, njev, status = solve(fun, jac, np.zeros(free.size), (lo[free] - base[free]) / s,
                                     (hi[free] - base[free]) / s, ftol=FTOL, xtol=XTOL, max_nfev=max_nfev)
    if budget is not None:
        budget.left -= (nfev + njev + 1) * N   # + 1: J0 above
        budget.reached |= status == 0 and max_nfev < MAX_NFEV
    return params(x)


def stacked(J: np.ndarray) -> np.ndarray:
    """(N, d, K) Jacobian rows -> the (N * d, K) matrix of the fit, column-major (each parameter's column
    contiguous, as NumPy's ``J[:, :, free]`` of the whole Jacobian laid it out): NumPy then sums a column
    pairwise, and the fits keep the bits they had when the Jacobian was computed whole."""
    return np.asfortranarray(J.reshape(-1, J.shape[2]))


def _update_orientation_weight(data: FitData, p: np.ndarray) -> bool:
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


def _update_robust_weights(data: FitData, p: np.ndarray, n_free: int) -> bool:
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


def bounds(mdl: ErrorModel) -> tuple[np.ndarray, np.ndarray]:
    """Box of every parameter: kinematic ones around their nominal values, base and marker free."""
    lo = np.full(mdl.size, -np.inf)
    hi = np.full(mdl.size, np.inf)
    free_frame = set(mdl.world_params + mdl.marker_params)
    compliance = set(mdl.compliance_params)
    for i in range(mdl.size):
        if i in free_frame:
            continue
        if i in compliance:
            lo[i], hi[i] = -MAX_COMPLIANCE, MAX_COMPLIANCE
            continue
        half = MAX_ANGLE if mdl.units[i] == "rad" else MAX_LENGTH * mdl.robot.scale
        lo[i], hi[i] = mdl.nominal[i] - half, mdl.nominal[i] + half
    return lo, hi
