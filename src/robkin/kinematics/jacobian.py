"""Geometric Jacobians and manipulability measures, for one configuration or a batch.

Three forms, all 6 x n:

- ``jacobian_space``: columns are the joint screws at q in the base (space) frame, ordered (w, v);
  the spatial twist of the tool is J_s(q) dq (Modern Robotics, eq. 5.11).
- ``jacobian_body``: the same in the tool frame, J_b = Ad_{T^-1} J_s.
- ``jacobian_geometric``: the form most people expect, [v; w] with v the linear velocity of the tool
  origin and w the angular velocity, both in the base frame.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..checks import check_out, check_threads
from ..compiled.chain.jacobian import jacobian, manipulability as _manipulability
from ..errors import InputError
from ..robot import Robot, check_q

__all__ = ["jacobian_space", "jacobian_body", "jacobian_geometric", "manipulability",
           "singular_values", "inverse_condition_number", "min_singular_value", "measures"]


def _compiled(robot: Robot, q: ArrayLike, kind: int, threads: int | None, out: np.ndarray | None) -> np.ndarray:
    """The compiled Jacobian (``robkin.compiled.chain.jacobian``) of the given kind at q (n,) or (N, n), on
    at most ``threads`` threads (None: automatic, see ``robkin.threads``), into ``out`` if given."""
    t = 0 if threads is None else check_threads(threads)
    J = jacobian(robot._chain, q, kind, t, out)
    if J is None:   # not a float64 array of finite values as it is: validate, convert, explain
        qa = np.ascontiguousarray(check_q(q, robot.n))
        J = jacobian(robot._chain, qa, kind, t, None if out is None else check_out(out, qa.shape[:-1] + (6, robot.n)))
    assert J is not None  # a checked, contiguous float64 array is always usable
    return J


def jacobian_space(robot: Robot, q: ArrayLike, threads: int | None = None,
                   out: np.ndarray | None = None) -> np.ndarray:
    """Space Jacobian (6, n) for q (n,), or (N, 6, n) for q (N, n); rows (w, v).

    Column i is joint i's unit screw at q in the base frame: revolute (z_i, p_i x z_i), prismatic
    (0, z_i), with z_i the axis and p_i a point on it. Compiled.

    ``robot``: the Robot; ``threads``: at most that many threads for a batch (default automatic, see
    ``robkin.threads``); ``out``: an array of the result's shape to write into (float64, C-contiguous), else a
    new one.
    """
    return _compiled(robot, q, 1, threads, out)


def jacobian_body(robot: Robot, q: ArrayLike, threads: int | None = None,
                  out: np.ndarray | None = None) -> np.ndarray:
    """Body Jacobian (6, n) or (N, 6, n): the space Jacobian seen from the tool frame,
    Ad_{T^-1} J_s; rows (w, v). Compiled.

    ``robot``: the Robot; ``q`` (n,) or (N, n) joint values; ``threads``: at most that many threads for a
    batch (default automatic); ``out``: an array of the result's shape to write into, else a new one.
    """
    return _compiled(robot, q, 2, threads, out)


def jacobian_geometric(robot: Robot, q: ArrayLike, threads: int | None = None,
                       out: np.ndarray | None = None) -> np.ndarray:
    """Base-frame geometric Jacobian (6, n) or (N, 6, n), rows [v; w] at the tool origin.

    Revolute column (z_i x (p_tool - p_i); z_i), prismatic (z_i; 0). Length units per radian in the
    v rows of revolute joints. Compiled.

    ``robot``: the Robot; ``q`` (n,) or (N, n) joint values; ``threads``: at most that many threads for a
    batch (default automatic, see ``robkin.threads``); ``out``: an array of the result's shape to write into
    (float64, C-contiguous), else a new one.
    """
    return _compiled(robot, q, 0, threads, out)


def singular_values(J: ArrayLike) -> np.ndarray:
    """Singular values (..., min(m, n)) in descending order.

    ``J``: the matrices (..., m, n).
    """
    return np.linalg.svd(np.asarray(J, dtype=float), compute_uv=False)


#: rows of the geometric Jacobian [v; w] each measure looks at
_ROWS = {"translational": slice(0, 3), "rotational": slice(3, 6), "full": slice(0, 6)}


def _selected_singular_values(robot: Robot, q: ArrayLike, kind: str) -> np.ndarray:
    if kind not in _ROWS:
        raise InputError(f"manipulability kind '{kind}' is not one of {', '.join(_ROWS)}")
    J = jacobian_geometric(robot, q)
    return singular_values(J[..., _ROWS[kind], :])


def _scalar(x: np.ndarray) -> np.ndarray | float:
    return float(x) if np.ndim(x) == 0 else x


def manipulability(robot: Robot, q: ArrayLike, kind: str = "translational",
                   threads: int | None = None) -> np.ndarray | float:
    """Yoshikawa's manipulability of the geometric Jacobian at the tool origin.

    Parameters
    ----------
    robot : Robot
    q : (n,) or (N, n) array
        Joint values (radians / length units).
    kind : {'translational', 'rotational', 'full'}
        Rows used: v (3 x n), w (3 x n) or both (6 x n).
    threads : int, optional
        At most that many threads for a batch (default automatic, see ``robkin.threads``).

    Returns
    -------
    float or (N,) array
        The product of the singular values of the selected rows: sqrt(det(J J^T)) when n >= rows,
        and sqrt(det(J^T J)) otherwise (the volume of the image of the unit ball within its span).
        Units: length^3 (translational), 1 (rotational), length^3 (full, mixed rows).

    ``threads`` bounds the threads of a large batch (see ``robkin.threads``); the values are the same
    bits on any number of threads. A batch is measured block by block in per-thread scratch, so its
    memory is the (N,) result whatever N (no N x 6 x n Jacobians).
    """
    if kind not in _ROWS:
        raise InputError(f"manipulability kind '{kind}' is not one of {', '.join(_ROWS)}")
    # compiled Householder QR of the selected rows: the same product as the SVD's, several times cheaper
    t = 0 if threads is None else check_threads(threads)
    rows = _ROWS[kind]
    w = _manipulability(robot._chain, q, rows.start, rows.stop - rows.start, t)
    if w is None:   # not a float64 array of finite values as it is: validate, convert, explain
        w = _manipulability(robot._chain, np.ascontiguousarray(check_q(q, robot.n)), rows.start,
                            rows.stop - rows.start, t)
    assert w is not None  # a checked, contiguous float64 array is always usable
    return _scalar(w)


def inverse_condition_number(robot: Robot, q: ArrayLike, kind: str = "translational") -> np.ndarray | float:
    """sigma_min / sigma_max of the selected rows of the geometric Jacobian, in [0, 1].

    1 is isotropic, 0 singular. For ``kind='full'`` the rows mix length and angle units, so the value
    depends on the length unit (the measure is most meaningful per kind). Shapes as ``manipulability``.
    Only the first min(rows, n) singular values exist: an arm with fewer joints than selected rows is
    measured within the span of its Jacobian.

    ``robot``: the Robot; ``q`` (n,) or (N, n) joint values; ``kind``: 'translational', 'rotational' or
    'full', the rows used.
    """
    s = _selected_singular_values(robot, q, kind)
    smax = s[..., 0]
    return _scalar(np.where(smax > 0, s[..., -1] / np.where(smax > 0, smax, 1.0), 0.0))


def min_singular_value(robot: Robot, q: ArrayLike, kind: str = "translational") -> np.ndarray | float:
    """Smallest singular value of the selected rows of the geometric Jacobian (0 at a singularity).

    Units: length per radian (translational rows of revolute joints), 1 (rotational). Shapes as
    ``manipulability``.

    ``robot``: the Robot; ``q`` (n,) or (N, n) joint values; ``kind``: 'translational', 'rotational' or
    'full', the rows used.
    """
    return _scalar(_selected_singular_values(robot, q, kind)[..., -1])


def measures(robot: Robot, q: ArrayLike) -> dict[str, np.ndarray | float]:
    """All measures at q: Yoshikawa manipulability (translational, rotational, full), inverse
    condition number and minimum singular value (translational and rotational).

    ``robot``: the Robot; ``q`` (n,) or (N, n) joint values; each value a float, or (N,) for a batch.
    """
    out: dict[str, np.ndarray | float] = {}
    for kind in _ROWS:
        out[f"manipulability_{kind}"] = manipulability(robot, q, kind)
    for kind in ("translational", "rotational"):
        out[f"inverse_condition_{kind}"] = inverse_condition_number(robot, q, kind)
        out[f"min_singular_value_{kind}"] = min_singular_value(robot, q, kind)
    return out
