"""Per-joint servo gains a simulator can hold a pose and move with: ``servo_plan(robot) -> ServoPlan``.

One plan for every writer of a simulation model (MJCF today, USD's drives): the home each joint holds,
its reflected inertia there, position-servo stiffness ``kp`` and damping ``kv`` (or a velocity servo's
gain), force and control ranges, and whether gravity is compensated. The writers turn it into their
own syntax; nothing here knows a file format.

The rule (``servo_plan``)
    I     the joint's reflected inertia at home: M(home)[j, j] of the chain (``robkin.dynamics``, the
          rigid bodies alone) plus the joint's armature; a joint off the chain (a finger) the inertia of
          the links below it about its axis (their mass for a slide), plus its armature; a joint that
          another one mimics adds the follower's inertia times the multiplier squared.
    kp    I * (2 pi BANDWIDTH_HZ)^2, raised to friction / FRICTION_ERROR where the source's joint
          friction would stall the servo further than that from its target, and to damping * 2 pi
          BANDWIDTH_HZ where the source's joint damping alone overdamps the servo (its time constant
          damping / kp then stays within 1 / (2 pi BANDWIDTH_HZ): TIAGo's fingers, 0.5 N m s/rad on
          1e-3 kg m^2, would otherwise take 0.5 s).
    kv    2 sqrt(kp I) - damping (critically damped with the source's joint damping counted), raised
          where the time step needs more damping for the servo to be stable (``_stable_damping``), never
          below 0. A velocity servo's gain: max(I * 2 pi BANDWIDTH_HZ, friction / VELOCITY_FRICTION_ERROR).
    force +-effort of the source (open where it gave none, or 0); ctrl: the joint's limits (position),
          +-velocity (velocity), +-effort (motor).

``--kp``/``--kv`` (``kp=``, ``kv=``) replace the rule's value on every joint; with ``kp`` alone, kv still
follows the rule from the given stiffness. Gains are rounded to 4 significant digits (they are design
values, not data).

Gravity compensation (``gravcomp``, on by default for position and velocity servos) is meant as an ideal
counterbalance, outside the actuators' effort: MuJoCo's body ``gravcomp`` as a passive force, not routed
through the actuators (``actuatorgravcomp``). Routed through them, it would count against the source's
effort, and the Baxter's shoulder (56 N m of gravity at home, 50 N m of effort: the real arm carries
springs for it) could not hold its own arm up.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Sequence

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    from ..body_parts import Mimic
    from ..robot import Robot

__all__ = ["ServoPlan", "JointServo", "servo_plan", "SERVO_KINDS", "BANDWIDTH_HZ", "FRICTION_ERROR",
           "VELOCITY_FRICTION_ERROR", "TIMESTEP", "INTEGRATOR", "moving_joints"]

SERVO_KINDS = ("position", "velocity", "motor", "none")
#: The servos' bandwidth (Hz): a critically damped position servo reaches a small step in ~0.19 s
#: (2 % settling, 5.8 / omega). 5 Hz is about what MuJoCo Menagerie's hand-tuned Panda gives its big
#: joints (kp 4500 N m/rad on ~3 kg m^2); stiffer than needed to hold a pose under gravity compensation,
#: soft enough that a 0.2 rad step saturates only the joints whose effort is small.
BANDWIDTH_HZ = 5.0
#: Largest error (rad or m) a position servo may be stalled at by the source's joint friction
#: (MuJoCo's ``frictionloss``): kp >= friction / this. 1 mrad is half the 2 mrad a held pose may drift.
FRICTION_ERROR = 1e-3
#: The same for a velocity servo (rad/s or m/s).
VELOCITY_FRICTION_ERROR = 1e-2
#: The time step (s) the gains are made for and the MJCF states: MuJoCo's default.
TIMESTEP = 0.002
#: MuJoCo's integrator that integrates the servos' damping (kv) and the joints' damping implicitly: the
#: default Euler treats kv explicitly and diverges on small inertias (a 15 g finger, a wrist).
INTEGRATOR = "implicitfast"
#: The smallest inertia a joint is given (kg m^2 or kg): MuJoCo's placeholder mass of a body with none.
MIN_INERTIA = 1e-12
#: URDF joint types that move (others off the chain are welded).
_MOVING = ("revolute", "continuous", "prismatic")


@dataclass(frozen=True)
class JointServo:
    """One joint of the plan (SI units: rad or m, N m or N, kg m^2 or kg).

    name, prismatic, chain: the joint's name, whether it slides, its index in the chain (None off it)
    home: the value it holds; inertia: reflected inertia there (see the module doc)
    kp, kv: position servo stiffness (N m/rad, N/m) and damping (N m s/rad, N s/m) of the actuator
        (for a velocity servo, kv is its gain and kp 0; for a motor both 0); the source's joint damping
        (``damping``) acts besides kv
    damping, friction, armature: the source's (0 where it gave none)
    force: (lower, upper) actuator force limits, None when open
    ctrl: (lower, upper) control range of the actuator, None when open
    actuated: False for a joint that follows another (``mimic``: its leader's name)
    """

    name: str
    prismatic: bool
    chain: int | None
    home: float
    inertia: float
    kp: float
    kv: float
    damping: float
    friction: float
    armature: float
    force: tuple[float, float] | None
    ctrl: tuple[float, float] | None
    actuated: bool
    mimic: str | None = None


@dataclass(frozen=True)
class ServoPlan:
    """Servos for every moving joint of a robot's simulation model (``servo_plan``).

    kind: 'position', 'velocity', 'motor' or 'none'
    joints: the chain's joints in order, then the joints off it (the source's link order)
    gravcomp: gravity compensated (MuJoCo: body ``gravcomp`` routed through the actuators)
    timestep, integrator: what the gains are stable with (s; MuJoCo's integrator name)
    bandwidth: Hz; inertia_known: False when the robot has no mass properties (gains from MIN_INERTIA)
    """

    kind: str
    joints: tuple[JointServo, ...]
    gravcomp: bool
    timestep: float = TIMESTEP
    integrator: str = INTEGRATOR
    bandwidth: float = BANDWIDTH_HZ
    inertia_known: bool = True

    def __getitem__(self, name: str) -> JointServo:
        for j in self.joints:
            if j.name == name:
                return j
        raise KeyError(name)

    def get(self, name: str) -> JointServo | None:
        """The servo of joint ``name``, or None when the joint has none."""
        return next((j for j in self.joints if j.name == name), None)

    @property
    def home(self) -> np.ndarray:
        """The chain's home (n,)."""
        return np.array([j.home for j in self.joints if j.chain is not None])

    def ctrl_home(self) -> list[float]:
        """Each actuator's control that holds home, in the order of ``actuated()``: the home for position
        servos, 0 for velocity servos and motors."""
        return [j.home if self.kind == "position" else 0.0 for j in self.actuated()]

    def actuated(self) -> list[JointServo]:
        return [j for j in self.joints if j.actuated] if self.kind != "none" else []


@dataclass(frozen=True)
class _Moving:
    """A joint of the model: what the plan needs of a chain ``Joint`` or a ``LinkJoint`` off the chain."""

    name: str
    prismatic: bool
    chain: int | None
    lower: float | None
    upper: float | None
    effort: float | None
    velocity: float | None
    damping: float | None
    friction: float | None
    armature: float | None
    mimic: Mimic | None
    link: str | None = None      # off the chain: the link it moves
    axis: np.ndarray | None = None   # off the chain: unit axis in the base frame at q = 0
    point: np.ndarray | None = None


def moving_joints(robot: Robot) -> list[_Moving]:
    """The joints a simulation model of ``robot`` moves: the chain's, then those of links hanging from
    the chain or from the links above its base (not those on the path from the base up to the root,
    which a mid-tree base welds), in the source's order."""
    out = [_Moving(j.name, not j.revolute, i, j.lower, j.upper, j.effort, j.velocity, j.damping, j.friction,
                   j.armature, j.mimic) for i, j in enumerate(robot.joints)]
    b = robot.bodies
    if not b.links or not b.chain:
        return out
    by_name = {lk.name: lk for lk in b.links}
    welded = {b.chain[0]}
    lk = by_name.get(b.chain[0])
    while lk is not None and lk.parent is not None:
        welded.add(lk.parent)
        lk = by_name.get(lk.parent)
    chain = set(b.chain)
    for lk in b.links:
        lj = lk.joint
        if lj is None or lj.type not in _MOVING or lk.name in chain or lk.name in welded:
            continue
        axis = lk.pose[:3, :3] @ np.asarray(lj.axis, dtype=float)
        cont = lj.type == "continuous"
        out.append(_Moving(lj.name, lj.type == "prismatic", None, None if cont else lj.lower,
                           None if cont else lj.upper, lj.effort, lj.velocity, lj.damping, lj.friction,
                           lj.armature, lj.mimic, lk.name, axis / np.linalg.norm(axis), lk.pose[:3, 3].copy()))
    return out


def _chain_inertia(robot: Robot, home: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """(M(home)'s diagonal, 1 / diag(M^-1)) with the armature, or None without mass properties. M of the
    rigid bodies alone (armature stripped, so that it counts once whatever the dynamics do with it)."""
    from ..dynamics.rigid_body import mass_matrix

    if not robot.bodies.inertials:
        return None
    rigid = robot.replace(joints=tuple(replace(j, armature=None) for j in robot.joints))
    try:
        M = mass_matrix(rigid, home)
    except InputError:
        return None
    M = M + np.diag([j.armature or 0.0 for j in robot.joints])
    try:
        coupled = 1.0 / np.diag(np.linalg.inv(M))
    except np.linalg.LinAlgError:
        coupled = np.diag(M).copy()
    return np.diag(M).copy(), coupled


def _subtree_moments(robot: Robot) -> dict[str, tuple[float, np.ndarray, np.ndarray]]:
    """For every link: (mass, first moment m c, inertia about the base origin) of the link and the links
    below it, at q = 0 in the base frame; one pass from the leaves up (O(links + inertials))."""
    b = robot.bodies
    kids: dict[str, list[str]] = {}
    for lk in b.links:
        if lk.parent is not None:
            kids.setdefault(lk.parent, []).append(lk.name)
    own: dict[str, tuple[float, np.ndarray, np.ndarray]] = {}
    for m in b.inertials:
        if m.mass <= 0:
            continue
        R, c = m.pose[:3, :3], m.pose[:3, 3]
        I_o = R @ m.inertia @ R.T + m.mass * (float(c @ c) * np.eye(3) - np.outer(c, c))
        mass, first, inertia = own.get(m.link, (0.0, np.zeros(3), np.zeros((3, 3))))
        own[m.link] = (mass + m.mass, first + m.mass * c, inertia + I_o)
    out: dict[str, tuple[float, np.ndarray, np.ndarray]] = {}
    roots = [lk.name for lk in b.links if lk.parent is None]
    stack: list[tuple[str, bool]] = [(r, False) for r in roots]
    while stack:  # post-order: a link's sum after its children's
        name, done = stack.pop()
        if not done:
            stack.append((name, True))
            stack.extend((k, False) for k in kids.get(name, []))
            continue
        mass, first, inertia = own.get(name, (0.0, np.zeros(3), np.zeros((3, 3))))
        for k in kids.get(name, []):
            km, kf, ki = out[k]
            mass, first, inertia = mass + km, first + kf, inertia + ki
        out[name] = (mass, first, inertia)
    return out


def _subtree_inertia(moments: dict[str, tuple[float, np.ndarray, np.ndarray]], j: _Moving) -> float:
    """The inertia of the links below ``j`` (its own link included) about its axis, at q = 0 (kg m^2),
    or their mass for a slide (kg)."""
    if j.link is None or j.axis is None or j.point is None or j.link not in moments:
        return 0.0
    mass, first, inertia = moments[j.link]
    if mass <= 0 or j.prismatic:
        return max(mass, 0.0)
    c = first / mass
    I_c = inertia - mass * (float(c @ c) * np.eye(3) - np.outer(c, c))  # parallel axes: to the centre,
    d = c - j.point                                                      # then to the axis's point
    I_p = I_c + mass * (float(d @ d) * np.eye(3) - np.outer(d, d))
    return float(j.axis @ I_p @ j.axis)


def _stable_damping(kp: float, inertia: float, h: float) -> float:
    """The least total damping (N m s/rad) with which a spring ``kp`` on ``inertia`` stays stable at time
    step ``h`` when the damping is integrated implicitly and the spring explicitly (MuJoCo's
    ``implicitfast``): the update is stable while h^2 kp < 4 I + 2 h b; this asks for half of it (a
    margin of 2 for the coupling between joints, whose inertia here is the least one, 1 / M^-1[j, j])."""
    return max(0.0, h * kp - 2.0 * inertia / h)


def _round(x: float) -> float:
    return float(f"{x:.4g}")


def _range(lo: float | None, hi: float | None) -> tuple[float, float] | None:
    if lo is None or hi is None or not (math.isfinite(lo) and math.isfinite(hi)) or lo >= hi:
        return None
    return (float(lo), float(hi))


def _sym(v: float | None) -> tuple[float, float] | None:
    return (-float(v), float(v)) if v is not None and v > 0 and math.isfinite(v) else None


def servo_plan(robot: Robot, *, kind: str = "position", home: ArrayLike | None = None, kp: float | None = None,
               kv: float | None = None, gravcomp: bool | None = None, bandwidth: float = BANDWIDTH_HZ,
               timestep: float = TIMESTEP) -> ServoPlan:
    """The servos of ``robot``'s simulation model (the rule: the module doc).

    Parameters
    ----------
    robot : Robot
    kind : 'position' | 'velocity' | 'motor' | 'none'
    home : (n,) array_like, optional
        The chain's home (checked against the limits, ``Robot.home``); default q = 0 clipped into them.
        Joints off the chain are homed at 0 clipped into their limits, a mimic joint where its leader
        puts it.
    kp, kv : float, optional
        Replace the rule's stiffness / damping (or a velocity servo's gain) on every joint.
    gravcomp : bool, optional
        Compensate gravity; default: yes for position and velocity servos, no for motors and none (a
        motor's ``ctrl`` is the whole torque).
    bandwidth : float
        Hz (``BANDWIDTH_HZ``).
    timestep : float
        s, the step the gains must be stable at (``TIMESTEP``).

    Returns
    -------
    ServoPlan
    """
    if kind not in SERVO_KINDS:
        raise InputError(f"actuators: '{kind}' is not one of {', '.join(SERVO_KINDS)}")
    for label, v in (("kp", kp), ("kv", kv)):
        if v is not None and not (0 <= v < math.inf):
            raise InputError(f"{label} {v}: a gain is a finite number >= 0")
    if not (bandwidth > 0 and timestep > 0):
        raise InputError("bandwidth and timestep: positive numbers")
    q0 = robot.home(home)
    joints = moving_joints(robot)
    chain = _chain_inertia(robot, q0)
    w = 2.0 * math.pi * bandwidth
    homes: dict[str, float] = {}
    for j in joints:
        if j.chain is not None:
            homes[j.name] = float(q0[j.chain])
        elif j.mimic is None:
            lo = -math.inf if j.lower is None else j.lower
            hi = math.inf if j.upper is None else j.upper
            homes[j.name] = float(min(max(0.0, lo), hi))
    for _ in range(len(joints)):  # mimic joints (chains of them resolved in at most len passes)
        for j in joints:
            if j.mimic is not None and j.name not in homes and j.mimic.joint in homes:
                homes[j.name] = j.mimic.offset + j.mimic.multiplier * homes[j.mimic.joint]
    inertia: dict[str, float] = {}
    coupled: dict[str, float] = {}
    moments = _subtree_moments(robot) if any(j.chain is None for j in joints) else {}
    for j in joints:
        if j.chain is not None:
            own = chain[0][j.chain] if chain is not None else 0.0
            coupled[j.name] = chain[1][j.chain] if chain is not None else 0.0
        else:
            own = _subtree_inertia(moments, j) + (j.armature or 0.0)
            coupled[j.name] = own
        inertia[j.name] = own
    names = {j.name for j in joints}
    for j in joints:  # a leader moves its followers: their inertia is its own, scaled
        if j.mimic is not None and j.mimic.joint in names:
            inertia[j.mimic.joint] += inertia[j.name] * j.mimic.multiplier ** 2
    out = []
    for j in joints:
        I = max(inertia[j.name], MIN_INERTIA)
        Ic = max(min(coupled[j.name], I), MIN_INERTIA)
        d, f = j.damping or 0.0, j.friction or 0.0
        k = v = 0.0
        if kind == "position":
            k = kp if kp is not None else max(I * w * w, f / FRICTION_ERROR, d * w)
            v = kv if kv is not None else max(2.0 * math.sqrt(k * I), _stable_damping(k, Ic, timestep)) - d
        elif kind == "velocity":
            v = kv if kv is not None else max(I * w, f / VELOCITY_FRICTION_ERROR)
        ctrl = {"position": _range(j.lower, j.upper), "velocity": _sym(j.velocity),
                "motor": _sym(j.effort)}.get(kind)
        out.append(JointServo(j.name, j.prismatic, j.chain, homes.get(j.name, 0.0), I, _round(k),
                              _round(max(v, 0.0)), d, f, j.armature or 0.0, _sym(j.effort), ctrl,
                              j.mimic is None or j.mimic.joint not in names,
                              None if j.mimic is None else j.mimic.joint))
    if gravcomp is None:
        gravcomp = kind in ("position", "velocity")
    return ServoPlan(kind, tuple(out), bool(gravcomp), timestep, INTEGRATOR, bandwidth, chain is not None)


def step_targets(plan: ServoPlan, size: float = 0.2, slide_size: float = 0.02) -> dict[str, float]:
    """For each actuated joint, a target ``size`` rad (``slide_size`` m for a slide) from its home, toward
    the inside of its range and at most half of it: the step a servo is checked on."""
    out = {}
    for j in plan.actuated():
        s = slide_size if j.prismatic else size
        lo, hi = j.ctrl if (j.ctrl is not None and plan.kind == "position") else (-math.inf, math.inf)
        room_up, room_down = hi - j.home, j.home - lo
        up = room_up >= room_down
        s = min(s, 0.5 * (room_up if up else room_down))
        out[j.name] = j.home + (s if up else -s)
    return out
