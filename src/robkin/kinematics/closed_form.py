"""Closed-form IK: the common result type and the detection of which solver fits a robot.

A closed-form solver is built from a Robot by ``detect`` (None when the geometry does not fit) and
returns *every* solution branch for a batch of targets. Detection looks at the GJD (joint axes at
q = 0), so it works the same whatever representation the robot was read from.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass
from typing import Any, Callable, Protocol

import numpy as np

from ..robot import Robot

__all__ = ["Branches", "ClosedFormSolver", "KernelSolver", "closed_form_solver", "embedded", "reasons_from_codes",
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
        """One target: the finished result, or None (see ``compiled.closed_form_kernel``); with
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
    """What every closed-form solver shares: a compiled kernel (a ``compiled.closed_form_kernel
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


#: detection result per Robot (robots are immutable), so repeated single-target calls detect once:
#: keyed by id(robot), with a weak reference that proves the robot is the same one and whose callback
#: drops the entry when the robot goes (a WeakKeyDictionary lookup costs twice as much, on every call)
_SOLVERS: dict[int, tuple[weakref.ref[Robot], ClosedFormSolver | None]] = {}


def closed_form_solver(robot: Robot) -> ClosedFormSolver | None:
    """The closed-form solver that fits the robot's geometry, or None."""
    key = id(robot)
    cached = _SOLVERS.get(key)          # one lookup: this runs on every single-target call
    if cached is not None and cached[0]() is robot:
        return cached[1]
    found = None
    from .analytic6r import SphericalWrist6R, ThreeParallel6R
    from .general6r import General6R
    from .near_class import NearClass
    from .pieper import Pieper6R
    from .scara import ScaraSolver

    # the special classes first (fastest), then an arm within calibration error of one of them (its
    # closed form on the ideal arm, polished on the real one), then 6R arms with three axes meeting
    # (Pieper's case, where the elimination degenerates), then any 6R by elimination
    for detect in (ScaraSolver.detect, SphericalWrist6R.detect, ThreeParallel6R.detect, NearClass.detect,
                   Pieper6R.detect, General6R.detect):
        found = detect(robot)
        if found is not None:
            break

    def forget(ref: weakref.ref[Robot], key: int = key, solvers: dict = _SOLVERS) -> None:
        # (the dict bound here: at interpreter exit the module's globals may be gone before a cached
        # robot, e.g. a reduced arm of kinematics.lock, is collected)
        if solvers.get(key, (None,))[0] is ref:        # not an entry of a later robot with the same id
            del solvers[key]

    _SOLVERS[key] = (weakref.ref(robot, forget), found)
    return found


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
