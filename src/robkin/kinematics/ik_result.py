"""The result of inverse kinematics (``IKResult``), ``ik``'s defaults and its checked solver settings.

Shared by ``ik`` (the entry point), ``srs`` (the arm-angle closed form) and ``lock`` (locked joints), which
``ik`` calls: they sit below it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from ..errors import InputError
from .lm import LMSettings

__all__ = ["IKResult", "METHODS", "DEFAULT_TOL", "DEFAULT_MAX_ITERATIONS", "DEFAULT_RESTARTS",
           "DEFAULT_SETTINGS", "settings"]

METHODS = ("auto", "analytic", "numeric")

#: Defaults of ``ik``: 1e-9 (length units, radians) is ~1e6 times the rounding of a closed-form solve
#: and what the numeric method reliably reaches; 40 iterations per attempt and 200 restarts (see
#: ``LMSettings.restarts``).
DEFAULT_TOL = 1e-9
DEFAULT_MAX_ITERATIONS = 40
DEFAULT_RESTARTS = 200


@dataclass(frozen=True)
class IKResult:
    """Outcome of :func:`ik`. Scalars for one target, arrays over targets (leading N) for a batch.

    Attributes
    ----------
    q : (n,) or (N, n) array
        The solution nearest to ``q0`` where ``success``. Where not: for the numeric method the best
        configuration found (smallest residual), for the closed form NaN (no configuration exists).
    success : bool or (N,) bool array
        Reached to the tolerances over the masked components, with every joint within limits.
    iterations : int or (N,) int array
        Levenberg-Marquardt iterations over all attempts (0 for the closed form).
    attempts : int or (N,) int array
        Starts used: 1 + random restarts, including those run side by side (1 for the closed form).
    position_error : float or (N,) array
        |p_d - p| over the masked x, y, z components (length units; inf where q is NaN).
    orientation_error : float or (N,) array
        |log(R_d R^T)| over the masked components (radians; inf where q is NaN).
    method : str
        'scara', 'spherical-wrist-6r', 'three-parallel-6r', 'near-spherical-wrist-6r',
        'near-three-parallel-6r', 'pieper-6r', 'pieper-6r-reversed', 'general-6r', 'srs-arm-angle' (closed forms; targets the closed form could not settle
        are retried numerically in 'auto') or 'numeric'.
    message : str or list of str
        Why a target failed ('' where it succeeded).
    solutions : (S, n) array, list of (S_i, n) arrays, or None
        With ``all_solutions=True``: every distinct solution found, nearest to q0 first.
    """

    q: np.ndarray
    success: np.ndarray | bool
    iterations: np.ndarray | int
    attempts: np.ndarray | int
    position_error: np.ndarray | float
    orientation_error: np.ndarray | float
    method: str
    message: list[str] | str
    solutions: list[np.ndarray] | np.ndarray | None = None

    @classmethod
    def _build(cls, **fields: Any) -> "IKResult":
        """The result from every field, without the frozen dataclass's ``__init__`` (one guarded
        ``object.__setattr__`` per field: ~2.5 us, as much as the closed-form kernel of one target).
        Frozen all the same: attribute assignment still raises."""
        result = object.__new__(cls)
        result.__dict__.update(fields)
        return result

    def __str__(self) -> str:
        """One row per target (success, errors, q), or per solution for one target with solutions."""
        from ..io.tables.text import blocks_text
        from .ik_text import ik_result_blocks

        return blocks_text(ik_result_blocks(self))

    def to_dict(self) -> dict[str, Any]:
        """Every field as plain lists and numbers (JSON-ready; see ``robkin.io.files.jsontext``)."""
        from dataclasses import fields

        from ..io.files.jsontext import plain

        return {f.name: plain(getattr(self, f.name)) for f in fields(self)}


@lru_cache(maxsize=64)
def settings(tol_position: float, tol_orientation: float, max_iterations: int, restarts: int) -> LMSettings:
    """Checked solver settings, cached: building the frozen dataclass costs as much as a closed-form
    solve, and callers repeat the same few values."""
    for name, v in (("tol_position", tol_position), ("tol_orientation", tol_orientation)):
        try:
            usable = math.isfinite(v) and v > 0
        except TypeError:
            usable = False
        if not usable:
            raise InputError(f"{name}: must be a positive number, got {v}")
    if int(max_iterations) < 1 or int(restarts) < 0:
        raise InputError(f"max_iterations must be >= 1 and restarts >= 0, got {max_iterations}, {restarts}")
    return LMSettings(tol_position=float(tol_position), tol_orientation=float(tol_orientation),
                      max_iterations=int(max_iterations), restarts=int(restarts))


DEFAULT_SETTINGS = settings(DEFAULT_TOL, DEFAULT_TOL, DEFAULT_MAX_ITERATIONS, DEFAULT_RESTARTS)
