"""Which poses to measure: an optimal design on the identification Jacobian, by exchange.

The identification Jacobian J (``parameters.ErrorModel.poses``) of the error model in use, at each
candidate configuration, with the measuring device's base and the marker free (as ``calibrate`` fits
them), restricted to the parameters a large spread of poses determines (``identifiability.identify`` on
the candidates: the rest are held at nominal and never estimated). A design is N of the candidates;
its information matrix is M = sum_i J_i^T J_i (the poses' rows, d = 3 per position).

Criteria (Atkinson, Donev and Tobias, *Optimum Experimental Designs*, 2007, ch. 10-12):

- ``D`` (the default): maximise det M. The volume of the parameters' confidence ellipsoid shrinks with
  it; it is invariant to the parameters' units and scaling (metres against radians), which makes it the
  usual criterion for kinematic calibration (Borm and Menq's observability index O1 is det^(1/P)).
- ``I``: minimise trace(M^-1 B), B = the mean of J_e^T J_e over the candidates: the mean squared
  prediction error of the tool point over the candidates per unit noise (the "expected error" below).

The exchange is Fedorov's (1972): start from a greedy sequential design (Wynn: add the candidate that
raises the criterion most, from a small ridge), then, for each design point in turn, swap it with the
candidate that improves the criterion most, until a pass improves nothing. Both the removal of a point
and the addition of a candidate are rank-d updates of M^-1 (Sherman-Morrison-Woodbury), so a pass costs
O(N C d P^2) for C candidates and P parameters (N = 30, C = 2000, P = 35: ~0.1-1 s). A configuration is
used at most once (a repeated pose adds noise averaging, not geometry).

``expected_std`` and ``expected_error`` turn a design into what the report states: the parameters'
standard deviations sigma sqrt(diag M^-1) and the RMS prediction error from noise alone,
sigma sqrt(mean_e trace(J_e M^-1 J_e^T)) over evaluation configurations.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..robot import Robot
from .identifiability import column_scale, identify
from .parameters import ErrorModel, build_model

__all__ = ["DesignProblem", "design_problem", "exchange", "best_design", "CRITERIA", "expected_std", "expected_error"]

CRITERIA = ("D", "I")
#: A swap is taken when it improves the criterion by more than this relative amount: below it, the
#: passes would chase rounding (det ratios are computed to ~1e-12) and not converge.
IMPROVEMENT = 1e-9
#: Most exchange passes: Fedorov's algorithm converges in 3-8 passes from a greedy start on 6-7 joint
#: arms (N = 30); the bound only stops a pathological cycle.
MAX_PASSES = 30
#: Ridge (relative to the mean diagonal of the candidates' information) of the greedy start, so that
#: the first d-row points can be compared before the design has full rank; it vanishes from the
#: exchange, which works on the plain M.
RIDGE = 1e-6
#: A design point whose removal leaves a matrix with det ratio below this is never removed (M would be
#: singular without it; its Woodbury update would divide by ~0).
LEVERAGE_TOL = 1e-10


@dataclass
class DesignProblem:
    """The candidates' identification Jacobians for one robot and error model.

    Attributes
    ----------
    q : (C, n) array
        Candidate configurations (rad / m).
    J : (C, d, K) array
        Their Jacobians in the kept parameters, columns scaled by ``scale`` (d = 3: positions).
    scale : (K,) array
        The column scaling (J_unscaled = J / scale).
    kept : (K,) int array
        Indices of the kept parameters in ``model``.
    model : ErrorModel
    dropped : list of str
        Names of the parameters the candidates cannot determine (held at nominal).
    """

    q: np.ndarray
    J: np.ndarray
    scale: np.ndarray
    kept: np.ndarray
    model: ErrorModel
    dropped: list[str]

    def jacobians(self, q: np.ndarray) -> np.ndarray:
        """Unscaled Jacobians (N, d, K) in the kept parameters at configurations q (N, n)."""
        _, J = self.model.poses(self.model.nominal, np.asarray(q, dtype=float), jacobian=True, columns=self.kept)
        assert J is not None  # asked for
        return J[:, :3]

    @property
    def names(self) -> list[str]:
        return [self.model.names[i] for i in self.kept]

    @property
    def units(self) -> list[str]:
        return [self.model.units[i] for i in self.kept]


def _model(robot: Robot, kind: str, marker: np.ndarray | None, base_known: bool) -> ErrorModel:
    return build_model(robot, kind, world=robot.world if base_known else None,
                       marker=None if marker is None else np.asarray(marker, dtype=float),
                       world_known=base_known)


def design_problem(robot: Robot, candidates: np.ndarray, model: str = "hayati", marker: np.ndarray | None = None,
                   base_known: bool = False) -> DesignProblem:
    """The Jacobians of ``candidates`` (C, n) for the error model ``model`` with the marker at ``marker``
    (3,) in the tool frame (default: the tool origin); the base is free unless ``base_known``."""
    mdl = _model(robot, model, marker, base_known)
    cols = np.arange(mdl.size)
    if base_known:
        cols = np.array([i for i in cols if i not in set(mdl.world_params)], dtype=int)
    Q = np.asarray(candidates, dtype=float)
    _, J = mdl.poses(mdl.nominal, Q, jacobian=True, columns=cols)
    assert J is not None  # asked for
    J = J[:, :3]
    ident = identify(J.reshape(-1, J.shape[2]))
    kept = cols[ident.kept]
    Jk = J[:, :, ident.kept]
    s = column_scale(Jk.reshape(-1, Jk.shape[2]))
    return DesignProblem(Q, Jk * s, s, kept, mdl, [mdl.names[cols[i]] for i in ident.dropped])


def _information(J: np.ndarray) -> np.ndarray:
    """M = sum_i J_i^T J_i of (N, d, K) rows."""
    return np.einsum("ndk,ndl->kl", J, J)


def _quad(J: np.ndarray, A: np.ndarray) -> np.ndarray:
    """(C, d, d) J_c A J_c^T."""
    return np.einsum("cdk,cek->cde", J @ A, J)


def exchange(problem: DesignProblem, count: int, criterion: str = "D", start: np.ndarray | None = None,
             max_passes: int = MAX_PASSES) -> np.ndarray:
    """Indices (count,) of the candidates of an optimal design (see the module doc).

    Parameters
    ----------
    problem : DesignProblem
    count : int
        Poses in the design; count * d must reach the number of parameters K.
    criterion : str
        'D' (maximise det M) or 'I' (minimise the mean prediction variance over the candidates).
    start : (count,) int array, optional
        The starting design (default: the greedy sequential one).
    max_passes : int
        At most this many passes of exchanges over the design (each pass stops early when none improves).

    Returns
    -------
    (count,) int array
    """
    if criterion not in CRITERIA:
        raise ValueError(f"criterion '{criterion}' is not one of {', '.join(CRITERIA)}")
    J = problem.J
    C, d, K = J.shape
    if count * d < K or count > C:
        raise ValueError(f"{count} poses of {C} candidates cannot determine {K} parameters")
    B = _information(J) / C if criterion == "I" else None
    design = _greedy(J, count, B) if start is None else np.array(start, dtype=int)
    for _ in range(max_passes):
        if not _pass(J, design, B):
            break
    return design


def best_design(problem: DesignProblem, count: int, starts: int = 4, seed: int = 0) -> np.ndarray:
    """The yardstick a plan is judged by: the best I-optimal design (least mean prediction variance over
    the candidates) the exchange finds from the D-optimal design, the greedy I design and ``starts``
    random starts. Costs ~(2 + starts) times a plan.

    Parameters
    ----------
    problem : DesignProblem
        The candidates' identification Jacobians.
    count : int
        Poses in the design.
    starts : int
        Random starting designs tried besides the two deterministic ones.
    seed : int
        Seed of the random starts.

    Returns
    -------
    (count,) int array
        Candidate indices.
    """
    rng = np.random.default_rng(seed)
    B = _information(problem.J) / len(problem.J)
    options = [exchange(problem, count, "I", start=exchange(problem, count, "D")), exchange(problem, count, "I")]
    for _ in range(starts):
        start = rng.choice(len(problem.J), size=count, replace=False)
        if np.linalg.matrix_rank(_information(problem.J[start])) == problem.J.shape[2]:
            options.append(exchange(problem, count, "I", start=start))

    def crit(idx: np.ndarray) -> float:
        return float(np.trace(np.linalg.solve(_information(problem.J[idx]), B)))
    return min(options, key=crit)


def _greedy(J: np.ndarray, count: int, B: np.ndarray | None) -> np.ndarray:
    """Wynn's sequential design: from a ridge, add the candidate that improves the criterion most."""
    C, d, K = J.shape
    M = RIDGE * np.trace(_information(J)) / C / K * np.eye(K)
    used = np.zeros(C, dtype=bool)
    out = []
    for _ in range(count):
        A = np.linalg.inv(M)
        score = _add_scores(J, A, B)
        score[used] = -np.inf
        j = int(np.argmax(score))
        used[j] = True
        out.append(j)
        M = M + J[j].T @ J[j]
    return np.array(out)


def _add_scores(J: np.ndarray, A: np.ndarray, B: np.ndarray | None) -> np.ndarray:
    """Per candidate, the improvement of adding it to a design of inverse information A: log det ratio
    (D), or the decrease of trace(A B) (I)."""
    d = J.shape[1]
    H = _quad(J, A) + np.eye(d)
    if B is None:
        return np.linalg.slogdet(H)[1]
    G = _quad(J, A @ B @ A)
    return np.trace(np.linalg.solve(H, G), axis1=1, axis2=2)


def _pass(J: np.ndarray, design: np.ndarray, B: np.ndarray | None) -> bool:
    """One Fedorov pass over the design points, in place; whether anything improved."""
    d = J.shape[1]
    improved = False
    used = np.zeros(len(J), dtype=bool)
    used[design] = True
    for k in range(len(design)):
        i = design[k]
        A = np.linalg.inv(_information(J[design]))
        Ji = J[i]
        D = np.eye(d) - Ji @ A @ Ji.T      # det D = det(M - J_i^T J_i) / det M
        detD = np.linalg.det(D)
        if not detD > LEVERAGE_TOL:
            continue
        Ai = A + A @ Ji.T @ np.linalg.solve(D, Ji @ A)   # (M - J_i^T J_i)^-1
        if B is None:
            # log det of the swapped design minus log det M: log det D + log det(I + J_j Ai J_j^T)
            gain = np.log(detD) + _add_scores(J, Ai, None)
            threshold = np.log1p(IMPROVEMENT)
        else:
            now = float(np.trace(A @ B))
            gain = now - (float(np.trace(Ai @ B)) - _add_scores(J, Ai, B))
            threshold = IMPROVEMENT * now
        gain[used] = -np.inf
        j = int(np.argmax(gain))
        if gain[j] > threshold:
            used[i], used[j] = False, True
            design[k] = j
            improved = True
    return improved


def expected_std(J: np.ndarray, noise: float) -> np.ndarray:
    """Standard deviations (K,) of the parameters fitted from a design's unscaled Jacobian J (N, d, K)
    with Gaussian noise ``noise`` (m per coordinate): noise * sqrt(diag M^-1); inf where M is singular."""
    s = column_scale(J.reshape(-1, J.shape[2]))
    try:
        cov = np.linalg.inv(_information(J * s)) * np.outer(s, s)
    except np.linalg.LinAlgError:
        return np.full(J.shape[2], np.inf)
    return noise * np.sqrt(np.maximum(np.diag(cov), 0.0))


def expected_error(J: np.ndarray, J_eval: np.ndarray, noise: float) -> float:
    """RMS prediction error (m) of the tool point over evaluation configurations (Jacobians J_eval
    (E, d, K)) of parameters fitted from a design (J (N, d, K)) with noise ``noise`` (m per coordinate),
    from noise alone: noise * sqrt(mean_e trace(J_e M^-1 J_e^T)); inf where M is singular."""
    s = column_scale(J.reshape(-1, J.shape[2]))
    try:
        A = np.linalg.inv(_information(J * s))
    except np.linalg.LinAlgError:
        return float("inf")
    Je = J_eval * s
    var = np.einsum("edk,kl,edl->", Je, A, Je) / len(Je)
    return float(noise * np.sqrt(max(var, 0.0)))
