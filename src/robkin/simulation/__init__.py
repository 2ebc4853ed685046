"""Simulating a robot: the servos a simulation model holds a pose and moves with, and MuJoCo's proof.

- ``servos``: ``servo_plan(robot, kind=..., home=..., kp=..., kv=..., gravcomp=...) -> ServoPlan``, the
  per-joint home, reflected inertia, gains, force and control ranges every simulation writer (MJCF, USD)
  turns into its syntax (the gain rule: that module's doc).
- ``mujoco_check``: ``hold_check(path)`` loads a written MJCF in MuJoCo (an optional dependency), resets
  it to its keyframe ``home``, simulates and reports drift, velocity, warnings and contacts; ``step_check``
  steps each joint and reports how it settles.

A capability package (above io): the MJCF writer gets the plan through the hub's facade
(``robkin.capabilities.servo_plan``) or from its caller.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..lazy_exports import lazy_exports

__all__ = ["ServoPlan", "JointServo", "servo_plan"]

__getattr__, __dir__ = lazy_exports(__name__, globals(), dict.fromkeys(__all__, ".servos"))

if TYPE_CHECKING:  # what static type checkers and IDEs see
    from .servos import JointServo, ServoPlan, servo_plan
