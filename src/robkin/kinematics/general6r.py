"""Closed-form IK of any revolute 6R arm: every real solution (up to 16), by elimination.

The solver of last resort among the closed forms (``closed_form.closed_form_solver`` tries the faster
special classes first): Raghavan and Roth's 14 equations, eliminated as Manocha and Canny do to a
quadratic 12 x 12 matrix polynomial whose eigenvalues are the roots of the degree-16 polynomial (the 8
spurious roots x = +-i deflated once per arm: ``spurious_complement``), then every root back-substituted
and polished by Newton steps on the exact forward kinematics (see ``robkin.compiled.ik.closed_form_general6r``
for the steps).

The elimination is written for a *formulation*: which joint is eliminated first and in which direction
the kinematic loop is read (6 cyclic shifts x 2 directions). The generic formulation degenerates on
special geometry (parallel or intersecting axes in the wrong places: its 14 x 8 block loses rank, or the
matrix polynomial becomes singular for every value). So ``detect`` tries the formulations on a few
targets of random configurations within the limits and keeps the first that finds every original
configuration on all of them (the formulations are tried in a fixed order, the half-angle offsets are
fixed random numbers: detection is deterministic). A robot no formulation solves is left to the
numeric solver.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..robot import Robot
from .kernel_solver import KernelSolver
from .limits import LIMIT_TOL, default_preference

__all__ = ["General6R"]

#: Targets per formulation at detection: 12 random configurations, each must come back among the
#: solutions (a degenerate formulation fails on nearly every target, a good one on none).
_TRIAL_TARGETS = 12
#: A trial's configuration counts as found when some solution is within 1e-6 rad of it in every joint
#: (solutions are polished to ~1e-15; 1e-6 is ``ik.SAME_SOLUTION_TOL``).
_FOUND_TOL = 1e-6


#: M(i)'s null space: singular values below _NULL_TOL x the largest are zero (rounding leaves ~1e-16;
#: a million-fold margin), and the last non-zero one must stay above _GAP_TOL x the largest (an
#: eigenspace of exactly four dimensions, well separated: ~0.07 on generic arms) for the space to be
#: well defined. Two targets' spaces agree to rounding (~1e-15); _SAME_SPACE_TOL leaves room for
#: conditioning and still rejects a target-dependent space.
_NULL_TOL = 1e-10
_GAP_TOL = 1e-6
_SAME_SPACE_TOL = 1e-9

#: per (arm, locked joints) of ``kinematics.lock``, the formulation that last worked: tried first for
#: the next locked value (a dict of a few tuples; entries are never large)
_HINTS: dict[tuple, tuple[int, bool]] = {}


def spurious_complement(kernel: Any, scale: float) -> np.ndarray | None:
    """The orthonormal complement (24, 16) of the spurious roots' invariant subspace, or None.

    Of M(x)'s 24 eigenvalues, 8 are x = +-i for every target (four each, from the half-angle
    substitution). Their eigenvectors [v; x v] of the companion matrix are the arm's, not the
    target's: v spans the null space of M(i), the same 4-dimensional space at any target (it is found
    here at two unrelated poses and must agree). The real and imaginary parts of the four [v; i v] span
    an 8-dimensional invariant subspace; on its complement the eigenvalue problem is 16 x 16, the
    degree of the problem, with (16 / 24)^3 ~ 0.3 of the full one's arithmetic. ``kernel``: a
    ``compiled.ik.closed_form_general6r.General6RKernel``; ``scale``: the robot's size. None when M(i)'s
    null space is not exactly four-dimensional or depends on the target (a special formulation): the
    kernel then solves the full 24 x 24 problem.
    """
    rng = np.random.default_rng(20261128)
    bases = []
    for _ in range(2):
        T = np.eye(4)
        T[:3, :3] = np.linalg.qr(rng.standard_normal((3, 3)))[0]
        T[:3, 3] = scale * rng.standard_normal(3)
        M = kernel.pencil(T)
        if M is None:
            return None
        _, sv, vh = np.linalg.svd(M[0] - M[2] + 1j * M[1])
        if not (sv[8] <= _NULL_TOL * sv[0] and sv[7] > _GAP_TOL * sv[0]):
            return None
        bases.append(vh[8:].conj().T)
    first, second = bases
    if np.linalg.norm(second - first @ (first.conj().T @ second)) > _SAME_SPACE_TOL:
        return None
    a, b = first.real, first.imag
    basis = np.block([[a, b], [-b, a]])                 # Re and Im of [v; i v]: (24, 8), rank 8
    return np.linalg.qr(basis, mode="complete")[0][:, 8:]


def _formulations() -> list[tuple[int, bool]]:
    """(shift, reverse) pairs in the order they are tried: Raghavan and Roth's own choice first
    (joints 3, 4, 5 on one side), then the other shifts, then the inverse loop."""
    shifts = [2, 0, 1, 3, 4, 5]
    return [(s, False) for s in shifts] + [(s, True) for s in shifts]


class General6R(KernelSolver):
    """All real closed-form solutions of any 6R arm (see the module docstring)."""

    name = "general-6r"

    def __init__(self, robot: Robot, shift: int, reverse: bool, delta: np.ndarray) -> None:
        from ..compiled.ik.closed_form_general6r import General6RKernel

        self.shift, self.reverse = shift, reverse
        kernel = General6RKernel(robot._chain, robot.limits, default_preference(robot.limits), robot.scale,
                                 LIMIT_TOL, robot._local, shift, reverse, delta)
        kernel.set_deflation(spurious_complement(kernel, robot.scale))
        self._use(kernel)
        self.messages = (
            "",
            "no solution found: the elimination was ill-conditioned at this target (a singular or "
            "special configuration)",
            "out of reach: no real solution",
            "solutions exist but violate the joint limits",
        )

    @classmethod
    def detect(cls, robot: Robot) -> "General6R | None":
        """A solver if the robot is 6R (revolute) and some formulation solves trial targets, else None."""
        if robot.n != 6 or not robot.revolute.all():
            return None
        rng = np.random.default_rng(20261125)
        lim = robot.limits
        lo = np.where(np.isfinite(lim[:, 0]), lim[:, 0], -np.pi)
        hi = np.where(np.isfinite(lim[:, 1]), lim[:, 1], np.pi)
        q = rng.uniform(lo, hi, (_TRIAL_TARGETS, 6))
        targets = robot.fk(q)
        delta = rng.uniform(-np.pi, np.pi, 6)
        key = getattr(robot, "_formulation_key", None)      # set by kinematics.lock on reduced arms
        hint = _HINTS.get(key) if key is not None else None
        order = _formulations()
        if hint is not None:
            order.remove(hint)
            order.insert(0, hint)
        best, best_found = None, -1
        for shift, reverse in order:
            solver = cls(robot, shift, reverse, delta)
            branches = solver.solve(targets, q)
            found = 0
            for k in range(len(q)):
                Q = branches.q[k][branches.valid[k]]
                if len(Q) and np.abs(Q - q[k]).max(axis=1).min() < _FOUND_TOL:
                    found += 1
            if found == len(q):
                if key is not None:
                    _HINTS[key] = (shift, reverse)
                return solver
            if found > best_found:
                best, best_found = solver, found
        return best if best_found >= len(q) - 1 else None
