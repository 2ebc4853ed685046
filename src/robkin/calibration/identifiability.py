"""Which error parameters the measurements determine: QR with column pivoting of the scaled Jacobian.

Parameters of different units (metres, radians) and lever arms are compared after scaling every column
of the identification Jacobian to unit length (Hollerbach and Wampler's column scaling), so that the
decision does not depend on the units. QR with column pivoting (Golub and Van Loan, sec. 5.4.2) orders
the columns from the most to the least independent; a column whose remaining part |R_kk| is below
``RANK_TOL`` of the first is a combination of the ones before it: its parameter is held at its nominal
value, and the parameters it cannot be told apart from are named (the least-squares combination of the
kept columns that reproduces it).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Identifiability", "identify", "RANK_TOL", "ILL_CONDITIONED"]

#: |R_kk| / |R_00| below which a scaled column counts as a combination of the kept ones. Exact
#: redundancies (a zero offset against the base's rotation, d of consecutive parallel axes) leave
#: ~1e-15; at 1e-6 the least-squares solution would amplify measurement noise a million-fold
#: (20 um noise -> 20 m parameter error), so such a parameter carries no information either.
RANK_TOL = 1e-6
#: Condition number of the kept scaled Jacobian above which the poses are reported as not exciting
#: the parameters: noise is amplified up to this factor into the parameter estimates; well-spread
#: poses of a 6-7 joint arm give ~10-100.
ILL_CONDITIONED = 1e3
#: A kept parameter is named as a partner of a redundant one when its coefficient in the combination
#: is at least this fraction of the largest (smaller ones are incidental).
PARTNER_SHARE = 0.2


@dataclass
class Identifiability:
    """Which parameters (indices into the free ones) are kept, which not, and why.

    Attributes
    ----------
    kept, dropped : (k,), (P - k,) int arrays
        Indices into the free parameters.
    partners : dict int -> list of int
        For each dropped parameter, the kept ones (largest share first) whose combination it is.
    condition : float
        Condition number of the scaled Jacobian of the kept parameters.
    scale : (P,) array
        The column scaling (1 / column norm; 1 where a column is zero).
    """

    kept: np.ndarray
    dropped: np.ndarray
    partners: dict[int, list[int]]
    condition: float
    scale: np.ndarray


def column_scale(J: np.ndarray) -> np.ndarray:
    """1 / the norm of each column of J (m, P); 1 for an all-zero column."""
    norms = np.linalg.norm(J, axis=0)
    return np.where(norms > 0, 1.0 / np.where(norms > 0, norms, 1.0), 1.0)


def identify(J: np.ndarray) -> Identifiability:
    """Rank-revealing QR of the column-scaled Jacobian J (m, P); see the module doc."""
    from scipy.linalg import qr

    scale = column_scale(J)
    Js = J * scale
    _, R, piv = qr(Js, mode="economic", pivoting=True)
    diag = np.abs(np.diag(R))
    top = diag[0] if diag.size and diag[0] > 0 else 1.0
    rank = int(np.sum(diag > RANK_TOL * top))
    kept, dropped = np.sort(piv[:rank]), np.sort(piv[rank:])
    partners: dict[int, list[int]] = {}
    Jk = Js[:, kept]
    if dropped.size and rank:
        from scipy.linalg import solve_triangular

        # J P = Q [R11 R12]: a dropped column (of R12) is the kept columns' combination R11^-1 R12
        coef = solve_triangular(R[:rank, :rank], R[:rank, rank:])
        for c, d in enumerate(piv[rank:]):
            share = np.abs(coef[:, c])
            order = np.argsort(-share)
            big = [int(piv[i]) for i in order if share[i] >= PARTNER_SHARE * share[order[0]]]
            partners[int(d)] = big[:3]
    # singular values of Jk from the eigenvalues of its k x k Gram matrix (an SVD of the m x k matrix
    # costs ~10x more): squaring loses digits only beyond a condition number of ~1e7, past RANK_TOL
    ev = np.linalg.eigvalsh(Jk.T @ Jk) if kept.size else np.array([1.0])
    condition = float(np.sqrt(ev[-1] / ev[0])) if ev[0] > 0 else float("inf")
    return Identifiability(kept, dropped, partners, condition, scale)


def describe(dropped: int, partners: list[int], names: list[str], positions_only: bool,
             kinematic: bool = True) -> str:
    """A sentence: which parameter cannot be told apart from which, and what is done with it."""
    what = " and ".join(names[p] for p in partners) if partners else "the others"
    how = " from positions alone" if positions_only else ""
    held = "held at its nominal value" if kinematic else "held: the other carries it"
    return f"{names[dropped]} cannot be told apart from {what}{how}: {held}"
