"""The ``<actuator>`` section of a written MJCF: one actuator per joint, the chain's first.

Kinds (``robkin convert --to mjcf --actuators KIND``)
    motor     ``ctrl`` is the joint torque (N m) or force (N); ``ctrlrange`` +-effort
    position  a servo to ``ctrl`` (rad or m) with stiffness ``kp`` and damping ``kv``; ``ctrlrange``
              the joint's range, ``forcerange`` +-effort
    velocity  a servo to ``ctrl`` (rad/s or m/s) with gain ``kv``; ``ctrlrange`` +-velocity,
              ``forcerange`` +-effort
    none      no actuators

Every joint is actuated except those that mimic another (they follow it through an equality). An
effort or velocity limit that is unknown, or 0 (which URDF files use for "not given"), leaves that
range open; the actuator then has ``ctrllimited``/``forcelimited`` false. The actuators are named
as their joints (MuJoCo keeps actuator names apart from joint names), in joint order, so
``data.ctrl[:n]`` drives the chain.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Sequence

from ..files.float_text import float_text as _num
from ..files.xmltext import quoteattr

if TYPE_CHECKING:  # pragma: no cover
    from .tree import JointPlan

__all__ = ["ACTUATOR_KINDS", "actuator_lines", "DEFAULT_KP", "DEFAULT_KV"]

ACTUATOR_KINDS = ("motor", "position", "velocity", "none")
#: Default servo gains (N m/rad, N m s/rad): stiff enough to hold a ~1 m arm of a few kg against
#: gravity within ~0.1 rad, damped enough not to ring at MuJoCo's default 2 ms step.
DEFAULT_KP = 100.0
DEFAULT_KV = 10.0


def _known(v: float | None) -> bool:
    return v is not None and v > 0


def _range(attr: str, lo: float, hi: float) -> str:
    return f'{attr}limited="true" {attr}range="{_num(lo)} {_num(hi)}"'


def _one(kind: str, j: JointPlan, kp: float, kv: float) -> str:
    name = quoteattr(j.name)
    force = _range("force", -j.effort, j.effort) if _known(j.effort) else 'forcelimited="false"'  # type: ignore[operator]
    if kind == "motor":
        ctrl = _range("ctrl", -j.effort, j.effort) if _known(j.effort) else 'ctrllimited="false"'  # type: ignore[operator]
        return f"    <motor name={name} joint={name} {ctrl}/>"
    if kind == "position":
        limited = j.lower is not None and j.upper is not None and j.lower < j.upper
        ctrl = _range("ctrl", j.lower, j.upper) if limited else 'ctrllimited="false"'  # type: ignore[arg-type]
        return f'    <position name={name} joint={name} kp="{_num(kp)}" kv="{_num(kv)}" {ctrl} {force}/>'
    ctrl = _range("ctrl", -j.velocity, j.velocity) if _known(j.velocity) else 'ctrllimited="false"'  # type: ignore[operator]
    return f'    <velocity name={name} joint={name} kv="{_num(kv)}" {ctrl} {force}/>'


def actuator_lines(kind: str, joints: Sequence[JointPlan], kp: float = DEFAULT_KP,
                   kv: float = DEFAULT_KV) -> list[str]:
    """The ``<actuator>`` element (a list of lines; empty for kind 'none' or no joints)."""
    if kind not in ACTUATOR_KINDS:
        raise ValueError(f"actuators: '{kind}' is not one of {', '.join(ACTUATOR_KINDS)}")
    driven = [j for j in joints if j.mimic is None]
    if kind == "none" or not driven:
        return []
    return ["  <actuator>"] + [_one(kind, j, kp, kv) for j in driven] + ["  </actuator>"]
