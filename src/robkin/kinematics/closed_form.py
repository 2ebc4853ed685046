"""Closed-form IK: which solver fits a robot (``closed_form_solver``), detected once per robot.

A closed-form solver is built from a Robot by ``detect`` (None when the geometry does not fit) and
returns *every* solution branch for a batch of targets (``kernel_solver.Branches``). Detection looks at
the GJD (joint axes at q = 0), so it works the same whatever representation the robot was read from.
"""

from __future__ import annotations

import weakref

from ..robot import Robot
from .kernel_solver import ClosedFormSolver

__all__ = ["closed_form_solver"]

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
