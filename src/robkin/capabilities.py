"""Facade: the hub's one way up to the capabilities that ``Robot``'s convenience methods offer.

``Robot`` (``robkin.robot``) sits low in the house: representations, readers, IK and dynamics all build
on it. Its convenience methods (``ik``, ``jacobian``, ``manipulability``, ``inverse_dynamics``,
``gravity``, ``mass_matrix``) are defined by the capability packages above it (``robkin.kinematics``,
``robkin.dynamics``). This module is the only place in the hub that imports from them, always on first
use (``import robkin`` stays light), and it is declared as the hub's facade (CONTRIBUTING.md, "Layers";
``tests/test_architecture.py``).

- ``ik_function()``: ``robkin.kinematics.ik.ik``, which *is* ``Robot.ik`` (the robot its first argument;
  ``robot.CapabilityMethod`` puts it in the class on first use);
- ``rigid_body()``, ``jacobian()``: the modules behind the dynamics and Jacobian methods;
- ``compliance()``: ``robkin.calibration.compliance``, behind ``Robot.fk_compliant``;
- ``self_collision_function()``, ``self_collision_distances_function()``: ``robkin.self_collision.build``'s
  functions, which *are* ``Robot.self_collision`` and ``Robot.self_collision_distances``;
- ``servo_plan()``: ``robkin.simulation.servos.servo_plan``, the servos of a simulation model, for the
  writers in io (below the capabilities) that are called without a plan of their caller's.
"""

from __future__ import annotations

from functools import cache
from types import ModuleType
from typing import TYPE_CHECKING, Any, Callable

if TYPE_CHECKING:  # what static type checkers see: the result types of the methods
    from .kinematics.ik import IKResult
    from .simulation.servos import ServoPlan

__all__ = ["ik_function", "jacobian", "rigid_body", "compliance", "servo_plan", "self_collision_function",
           "self_collision_distances_function"]


@cache
def ik_function() -> Callable[..., "IKResult"]:
    """``robkin.kinematics.ik.ik``, imported on first use and then kept."""
    from .kinematics.ik import ik

    return ik


@cache
def jacobian() -> ModuleType:
    """``robkin.kinematics.jacobian``, imported on first use and then kept."""
    from .kinematics import jacobian as module

    return module


@cache
def rigid_body() -> ModuleType:
    """``robkin.dynamics.rigid_body``, imported on first use and then kept."""
    from .dynamics import rigid_body as module

    return module


@cache
def compliance() -> ModuleType:
    """``robkin.calibration.compliance``, imported on first use and then kept."""
    from .calibration import compliance as module

    return module


@cache
def servo_plan() -> Callable[..., "ServoPlan"]:
    """``robkin.simulation.servos.servo_plan``, imported on first use and then kept."""
    from .simulation.servos import servo_plan as function

    return function


@cache
def self_collision_function() -> Callable[..., Any]:
    """``robkin.self_collision.build.self_collision``, imported on first use and then kept."""
    from .self_collision.build import self_collision

    return self_collision


@cache
def self_collision_distances_function() -> Callable[..., Any]:
    """``robkin.self_collision.build.self_collision_distances``, imported on first use and then kept."""
    from .self_collision.build import self_collision_distances

    return self_collision_distances
