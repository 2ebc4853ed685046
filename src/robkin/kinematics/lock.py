"""IK with joints held at given values: ``ik(robot, T, lock={name: value})``.

Locking joints of an arm gives a shorter arm: the locked joint's motion at its value becomes part of
the fixed link it sits in. On the GJD that is one product per locked joint k at value v: every frame
after k is carried by exp([S_k] v) = J_k Z(v) J_k^-1, and J_k is dropped. A 7-joint arm with one joint
locked is then a 6R arm and gets a closed form (``closed_form.closed_form_solver``: a special class or
``general6r``), with every solution for that value; any other arm gets whatever fits its reduced form,
the numeric solver included. Returned configurations are full length, the locked values in place.

The reduced arms are cached per (robot, locked joints, values), and the elimination formulation chosen
for one value of the locked joints is tried first for the next (``general6r``), so a path that sweeps
a locked value costs one reduced arm per value, not a fresh detection. A call repeating a ``lock``
mapping already seen for that robot (the same names and values) skips even the checks: its plan
(``LockPlan``: indices, reduced arm, where the free joints go) is kept per robot and mapping.
"""

from __future__ import annotations

import math
import weakref
from collections import OrderedDict
from typing import Any, Mapping

import numpy as np

from ..errors import InputError, quote
from ..robot import Robot
from .kernel_solver import embedded

__all__ = ["check_lock", "locked_robot", "ik_locked", "LockPlan", "lock_plan"]

#: reduced arms kept (per robot, locked joints and values): a path's worth of locked values; the
#: plans (per robot and ``lock`` mapping as given) likewise
_CACHE_SIZE = 256
_CACHE: "OrderedDict[tuple[Any, ...], tuple[weakref.ref[Robot], Robot]]" = OrderedDict()
_PLANS: "OrderedDict[tuple[Any, ...], tuple[weakref.ref[Robot], LockPlan]]" = OrderedDict()


def check_lock(robot: Robot, lock: Mapping[str, float]) -> tuple[tuple[int, ...], tuple[float, ...]]:
    """The locked joints' indices (ascending) and values, checked: names of the robot's joints, finite
    numbers within the joints' limits, at least one joint left free."""
    if not isinstance(lock, Mapping):
        raise InputError(f"lock: expected a mapping of joint name to value, got {type(lock).__name__}")
    names = [j.name for j in robot.joints]
    limits = robot.limits
    items = []
    for name, value in lock.items():
        if name not in names:
            raise InputError(f"lock: no joint {quote(str(name))}; the joints are {', '.join(names)}")
        try:
            v = float(value)
        except (TypeError, ValueError):
            raise InputError(f"lock: joint {quote(name)}: expected a number, got {value!r}") from None
        if not math.isfinite(v):
            raise InputError(f"lock: joint {quote(name)}: value {v} is not finite")
        i = names.index(name)
        lo, hi = float(limits[i, 0]), float(limits[i, 1])
        if not lo - 1e-12 <= v <= hi + 1e-12:      # the limits' own rounding slack (LIMIT_TOL scale)
            raise InputError(f"lock: joint {quote(name)}: value {v} is outside its limits [{lo}, {hi}]")
        items.append((i, v))
    if len(items) >= robot.n:
        raise InputError(f"lock: every joint is locked; leave at least one of {', '.join(names)} free")
    items.sort()
    return tuple(i for i, _ in items), tuple(v for _, v in items)


def _build(robot: Robot, idx: tuple[int, ...], values: tuple[float, ...]) -> Robot:
    """The reduced arm: the GJD with each locked joint's motion folded into the frames after it."""
    F = np.array(robot.frames)
    for k, v in zip(idx, values):
        Z = np.eye(4)
        if robot.joints[k].revolute:
            c, s = math.cos(v), math.sin(v)
            Z[:2, :2] = [[c, -s], [s, c]]
        else:
            Z[2, 3] = v
        E = F[k] @ Z @ np.linalg.inv(F[k])
        F[k + 1:] = E @ F[k + 1:]
    keep = [i for i in range(robot.n) if i not in idx]
    frames = np.concatenate([F[keep], F[-1:]])
    reduced = Robot(frames, tuple(robot.joints[i] for i in keep), world=robot.world, name=robot.name)
    # the key of the formulation memo in general6r: the same arm and locked joints, any values
    object.__setattr__(reduced, "_formulation_key", (id(robot), idx))
    return reduced


def locked_robot(robot: Robot, idx: tuple[int, ...], values: tuple[float, ...]) -> Robot:
    """The reduced arm of ``robot`` with joints ``idx`` held at ``values`` (cached)."""
    key = (id(robot), idx, values)
    hit = _CACHE.get(key)
    if hit is not None and hit[0]() is robot:
        _CACHE.move_to_end(key)
        return hit[1]
    reduced = _build(robot, idx, values)
    _CACHE[key] = (weakref.ref(robot), reduced)
    if len(_CACHE) > _CACHE_SIZE:
        _CACHE.popitem(last=False)
    return reduced


class LockPlan:
    """What ``ik`` needs for one robot and one ``lock`` mapping: the checked locked indices (ascending)
    and values, the reduced arm, and the indices of the free joints (to pick q0's free part)."""

    __slots__ = ("idx", "values", "reduced", "free", "embed")

    def __init__(self, robot: Robot, idx: tuple[int, ...], values: tuple[float, ...]) -> None:
        self.idx, self.values = idx, values
        self.reduced = locked_robot(robot, idx, values)
        self.free = np.array([i for i in range(robot.n) if i not in idx], dtype=np.intp)
        template = np.full(robot.n, np.nan)
        template[list(idx)] = values
        #: what the closed forms' single-target entry takes to answer full length (``nearest``'s embed)
        self.embed = (template, self.free)


def lock_plan(robot: Robot, lock: Mapping[str, float]) -> LockPlan:
    """The plan of ``lock`` for ``robot``: checked (``check_lock``) the first time this robot sees this
    mapping (the same names and values, in any order of insertion that gives the same items), then
    taken from the cache. A mapping whose items cannot be hashed is checked on every call."""
    try:
        key: tuple[Any, ...] | None = (id(robot), tuple(lock.items()))
        hit = _PLANS.get(key)
    except (TypeError, AttributeError):     # unhashable values, or not a mapping: check_lock explains
        key = hit = None
    if hit is not None and hit[0]() is robot:
        return hit[1]
    plan = LockPlan(robot, *check_lock(robot, lock))
    if key is not None:
        _PLANS[key] = (weakref.ref(robot), plan)
        if len(_PLANS) > _CACHE_SIZE:
            _PLANS.popitem(last=False)
    return plan


def ik_locked(ik_function: Any, robot: Robot, T: Any, lock: Mapping[str, float], q0: Any, **kwargs: Any) -> Any:
    """``ik_function`` (``kinematics.ik.ik``) on the reduced arm, its result made full length."""
    from .ik_methods import clipped_into_limits, single_closed_form

    plan = lock_plan(robot, lock)
    q_ref = None
    if q0 is not None:
        from ..robot import check_q

        q0 = check_q(q0, robot.n)[..., plan.free]
        if q0.ndim == 1:    # the preference of one target, clipped into the limits as ik's own
            q_ref = clipped_into_limits(plan.reduced, q0)
    if q0 is None or q_ref is not None:     # one target: answered full length by the compiled entry, if it can
        one = single_closed_form(plan.reduced, T, kwargs["mask"], kwargs["method"], kwargs["all_solutions"],
                                 kwargs["tol_position"], kwargs["tol_orientation"], kwargs["max_iterations"],
                                 kwargs["restarts"], q_ref, plan.embed)
        if one is not None:
            return one
    res = ik_function(plan.reduced, T, q0=q0, **kwargs)
    sols = res.solutions
    if sols is not None:
        sols = embedded(sols, plan.embed) if isinstance(sols, np.ndarray) else \
            [embedded(s, plan.embed) for s in sols]
    fields = res.__dict__.copy()
    fields["q"], fields["solutions"] = embedded(res.q, plan.embed), sols
    return type(res)._build(**fields)
