"""Closed-form IK solvers' common parts: the result type (``Branches``), the solver protocol, the base class
of the compiled-kernel solvers, and the detection tolerances.

Each solver family (``scara``, ``analytic6r``, ``pieper``, ``general6r``, ``near_class``) builds on these;
``closed_form.closed_form_solver`` picks the one that fits a robot.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Protocol

import numpy as np

__all__ = ["Branches", "ClosedFormSolver", "KernelSolver", "embedded", "reasons_from_codes",
           "DETECT_ANGLE_TOL", "DETECT_LENGTH_TOL"]

#: Axes count as parallel when the sine of their angle is below this, and as meeting when their
#: distance is below DETECT_LENGTH_TOL * robot size. Both 1e-9: far above the rounding of exact
#: geometry (~1e-15) and far below real offsets; a near-fit (a URDF typed with 1.5708 for pi/2) is
#: not taken, so it falls back to the numeric solver instead of giving answers ~1e-5 off.
DETECT_ANGLE_TOL = 1e-9
DETECT_LENGTH_TOL = 1e-9


@dataclass
class Branches:
    """All solution branches of a batch of targets.

    Attributes
    ----------
    q : (N, S, n) array
        S candidate configurations per target (revolute angles wrapped into the limits).
    valid : (N, S) bool array
        Branches that exist geometrically and respect the joint limits.
    reason : list of str
        Per target, why no branch is valid ('' when one is).
    uncertain : (N,) bool array, optional
        Targets at a singularity where a free joint took its preferred value and no branch came out:
        other values might work, so "no solution" is not proven (``ik`` retries them numerically).
    """

    q: np.ndarray
    valid: np.ndarray
    reason: list[str]
    uncertain: np.ndarray | None = None


class ClosedFormSolver(Protocol):
    name: str

    def solve(self, targets: np.ndarray, q_ref: np.ndarray, threads: int = 0) -> Branches:
        """All branches for targets (N, 4, 4), preferring q_ref (N, n) where a joint is free; the
        targets split over at most ``threads`` threads (0: automatic), the same bits on any."""

    def nearest(self, target: Any, q_ref: np.ndarray | None, tol_position: Any, tol_orientation: Any,
                every: bool, same_tol: float, result_type: type, method: str,
                embed: tuple[np.ndarray, np.ndarray] | None = None) -> Any:
        """One target: the finished result, or None (see ``compiled.ik.closed_form_kernel``); with
        ``embed`` (template, where) its configurations as rows of a longer arm (``embedded``)."""


def embedded(q: np.ndarray, embed: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """Configurations q (..., n) of a reduced arm as rows of the longer one: ``embed`` = (template (m,),
    where (n,) intp), each row the template with q[..., j] at where[j] (what ``nearest`` does in C)."""
    template, where = embed
    out = np.empty(q.shape[:-1] + template.shape)
    out[...] = template
    out[..., where] = q
    return out


class KernelSolver:
    """What every closed-form solver shares: a compiled kernel (a ``compiled.ik.closed_form_kernel
    .ClosedFormKernel`` built per robot by the subclass, which then calls ``_use``) and the messages for
    its outcome codes.

    ``nearest`` is the kernel's own single-target entry (an attribute: no Python frame in between):
    ``nearest(target (4, 4), q_ref (n,) or None, tol_position, tol_orientation, every, same_tol,
    result_type, method, embed=None)`` -> the finished result of one target, or None when no branch counts or an
    input is not a plain float64 4x4 exact pose / float tolerance (the caller then takes the general
    path). The same solve and choice as ``solve`` followed by ``solutions.nearest_verified``.
    """

    name: str
    _kernel: Any
    nearest: Callable[..., Any]
    #: per kernel outcome code, the message for a failed target ('' for code 0)
    messages: tuple[str | Callable[[float], str], ...]

    def _use(self, kernel: Any) -> None:
        """Take the compiled kernel built for this robot."""
        self._kernel = kernel
        self.nearest = kernel.nearest

    def solve(self, targets: np.ndarray, q_ref: np.ndarray, threads: int = 0) -> Branches:
        """Every branch (N, S, n) for targets (N, 4, 4); q_ref (N, n) decides the free choices; the
        targets split over at most ``threads`` threads (0: automatic, see ``robkin.threads``)."""
        Q, valid, code, detail, uncertain, failed = self._kernel.solve(targets, q_ref, threads)
        reasons = reasons_from_codes(code, detail, self.messages) if failed else [""] * len(Q)
        return Branches(Q, valid, reasons, uncertain)


def reasons_from_codes(code: np.ndarray, detail: np.ndarray,
                       messages: tuple[str | Callable[[float], str], ...]) -> list[str]:
    """Per target, the message for its kernel outcome code (N,) ('' for code 0).

    ``messages[k]`` explains code k; a function of the target's ``detail`` value quotes a number.
    """
    out = [""] * len(code)
    for i in np.flatnonzero(code):
        text = messages[code[i]]
        out[i] = text if isinstance(text, str) else text(float(detail[i]))
    return out
