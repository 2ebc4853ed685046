"""The ``<actuator>`` section of a written MJCF: one actuator per joint, the chain's first.

The gains, ranges and home come from a servo plan (``robkin.simulation.servos.ServoPlan``: its module
doc states the rule); this module only writes them.

Kinds (``robkin convert --to mjcf --actuators KIND``)
    position  (the default) a servo to ``ctrl`` (rad or m) with stiffness ``kp`` and damping ``kv``;
              ``ctrlrange`` the joint's range, ``forcerange`` +-effort
    velocity  a servo to ``ctrl`` (rad/s or m/s) with gain ``kv``; ``ctrlrange`` +-velocity,
              ``forcerange`` +-effort
    motor     ``ctrl`` is the joint torque (N m) or force (N); ``ctrlrange`` +-effort
    none      no actuators

Every joint is actuated except those that mimic another (they follow it through an equality). An
effort or velocity limit that is unknown, or 0 (which URDF files use for "not given"), leaves that
range open; the actuator then has ``ctrllimited``/``forcelimited`` false. The actuators are named
as their joints (MuJoCo keeps actuator names apart from joint names), in joint order, so
``data.ctrl[:n]`` drives the chain.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Sequence

from ..files.float_text import float_text as _num
from ..files.xmltext import quoteattr

if TYPE_CHECKING:  # pragma: no cover
    from .tree import JointPlan

#: ``robkin.simulation.servos.ServoPlan`` and ``JointServo``: the capabilities layer, above io, makes the
#: plan; io only reads its fields (kind, gravcomp, timestep, integrator; per joint name, home, kp, kv,
#: force, ctrl, actuated), so it names no type of a layer above it.
ServoPlan = Any
JointServo = Any

__all__ = ["ACTUATOR_KINDS", "actuator_lines", "actuated"]

ACTUATOR_KINDS = ("position", "velocity", "motor", "none")


def _range(attr: str, r: tuple[float, float] | None) -> str:
    if r is None:
        return f'{attr}limited="false"'
    return f'{attr}limited="true" {attr}range="{_num(r[0])} {_num(r[1])}"'


def _one(kind: str, s: JointServo) -> str:
    name = quoteattr(s.name)
    force = _range("force", s.force)
    if kind == "motor":
        return f"    <motor name={name} joint={name} {_range('ctrl', s.ctrl)}/>"
    if kind == "position":
        return (f'    <position name={name} joint={name} kp="{_num(s.kp)}" kv="{_num(s.kv)}" '
                f'{_range("ctrl", s.ctrl)} {force}/>')
    return f'    <velocity name={name} joint={name} kv="{_num(s.kv)}" {_range("ctrl", s.ctrl)} {force}/>'


def actuated(plan: ServoPlan, joints: Sequence[JointPlan]) -> list[JointServo]:
    """The plan's entries of the written joints that get an actuator, in the joints' (MuJoCo's) order."""
    if plan.kind == "none":
        return []
    out = []
    for j in joints:
        s = plan.get(j.name)
        if s is not None and s.actuated and j.mimic is None:
            out.append(s)
    return out


def actuator_lines(plan: ServoPlan, joints: Sequence[JointPlan]) -> list[str]:
    """The ``<actuator>`` element (a list of lines; empty for kind 'none' or no joints)."""
    if plan.kind not in ACTUATOR_KINDS:
        raise ValueError(f"actuators: '{plan.kind}' is not one of {', '.join(ACTUATOR_KINDS)}")
    driven = actuated(plan, joints)
    if not driven:
        return []
    return ["  <actuator>"] + [_one(plan.kind, s) for s in driven] + ["  </actuator>"]
