"""Facade: the hub's one way up to the capabilities that ``Robot``'s convenience methods offer.

``Robot`` (``robkin.robot``) sits low in the house: representations, readers, IK and dynamics all build
on it. Its convenience methods (``ik``, ``jacobian``, ``manipulability``, ``inverse_dynamics``,
``gravity``, ``mass_matrix``) are defined by the capability packages above it (``robkin.kinematics``,
``robkin.dynamics``). This module is the only place in the hub that imports from them, always on first
use (``import robkin`` stays light), and it is declared as the hub's facade (CONTRIBUTING.md, "Layers";
``tests/test_architecture.py``).

- ``CapabilityMethod``: a method of ``Robot`` that *is* a function of a higher layer: ``Robot.ik`` is
  ``robkin.kinematics.ik.ik`` (``ik_function()``) with the robot as its first argument. ``help(Robot.ik)``
  and ``inspect.signature`` show that function, before and after the first call alike.
- ``rigid_body()``, ``jacobian()``: the modules behind the dynamics and Jacobian methods.
"""

from __future__ import annotations

from functools import cache
from types import MethodType, ModuleType
from typing import TYPE_CHECKING, Any, Callable, Generic, TypeVar, overload

if TYPE_CHECKING:  # what static type checkers see: the result types of the methods
    from .kinematics.ik import IKResult

__all__ = ["CapabilityMethod", "ik_function", "jacobian", "rigid_body"]

F = TypeVar("F", bound=Callable[..., Any])


class CapabilityMethod(Generic[F]):
    """A method of a hub class defined as a function ``f(instance, ...)`` in a higher layer.

    Parameters
    ----------
    load : callable
        Returns the function (importing its module on first use, then kept: ``functools.cache``); its
        first parameter receives the instance.

    Each access through an instance binds the function to it (``types.MethodType``): one descriptor call
    (~0.13 us, measured against a method that is the function itself; ~2-3 % of a closed-form single IK
    call) and no second frame forwarding the keywords. The bound method is not kept on the instance: it
    would refer back to it, and a robot dropped by its last user would then wait for the cyclic garbage
    collector instead of going at once (``tests/test_ik_single.py``, the solver cache).
    """

    def __init__(self, load: Callable[[], F]) -> None:
        self.load = load

    @overload
    def __get__(self, instance: None, owner: type | None = None) -> F: ...

    @overload
    def __get__(self, instance: object, owner: type | None = None) -> F: ...

    def __get__(self, instance: object | None, owner: type | None = None) -> Any:
        function = self.load()
        if instance is None:
            return function
        return MethodType(function, instance)


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
