"""MuJoCo as the judge of a written MJCF: does it load cleanly, hold ``home``, and move to a step?

MuJoCo is an optional dependency: ``available()`` says whether it imports, and the checks raise
``ImportError`` without it (``robkin convert`` then says the simulation was not checked).

- ``hold_check(path)``: load the model (the warnings MuJoCo's compiler gives are caught), reset to
  the keyframe ``home``, check every joint inside its range, count the contacts between the robot's
  own geoms there, simulate ``seconds`` under the keyframe's controls, and report the largest drift
  from home, the final largest |qvel| and MuJoCo's warnings (``data.warning``). Any warning fails
  the hold but the compiler's about what is only drawn (``COSMETIC_WARNINGS``: an OBJ mesh's texture
  coordinates discarded), which the report still lists.
- ``step_check(path)``: from home, each actuated joint's control stepped by 0.2 rad (0.02 m for a
  slide) toward the inside of its range, one joint at a time; how far it is from the target after
  ``seconds``, how far any joint went past its range, and the warnings.
"""

from __future__ import annotations

import contextlib
import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterator, Sequence

import numpy as np

__all__ = ["available", "HoldReport", "StepReport", "hold_check", "step_check", "HOLD_SECONDS",
           "HOLD_DRIFT", "HOLD_QVEL"]

#: Simulated time of the hold check (s): the issue's "press play" for 5 s.
HOLD_SECONDS = 5.0
#: What "holds" means: every joint within 2 mrad (or 2 mm) of home, and |qvel| below 1e-3 rad/s at the end.
HOLD_DRIFT = 2e-3
HOLD_QVEL = 1e-3
#: How far past a joint's range (rad or m) counts as leaving it: MuJoCo's limits are soft constraints
#: (solref 0.02 s by default) and give way under load. Observed (2026-11-28): 5.5 mrad on the Panda's
#: joint 4, homed on its limit, while joint 2's step saturates at 87 N m; 1e-2 is twice that.
RANGE_SLACK = 1e-2
#: A model lighter than this (kg) carries only the MJCF writer's placeholder masses (1e-9 kg a body).
WEIGHTLESS = 1e-6


def available() -> bool:
    """Whether MuJoCo imports."""
    try:
        import mujoco  # noqa: F401
    except ImportError:
        return False
    return True


@contextlib.contextmanager
def _c_warnings() -> Iterator[list[str]]:
    """MuJoCo's C-level warnings (its compiler's, mj_step's) collected in a list instead of printed and
    logged to MUJOCO_LOG.TXT, where the bindings let a callback take them (``set_mju_user_warning``)."""
    import mujoco

    got: list[str] = []
    setter, getter = getattr(mujoco, "set_mju_user_warning", None), getattr(mujoco, "get_mju_user_warning", None)
    if setter is None or getter is None:
        yield got
        return
    old = getter()
    setter(lambda msg: got.append(str(msg).strip().splitlines()[0] if str(msg).strip() else "warning"))
    try:
        yield got
    finally:
        setter(old)


def _warnings(data: Any) -> list[str]:
    import mujoco

    out = []
    for k in range(len(data.warning)):
        if data.warning[k].number:
            out.append(f"{mujoco.mjtWarning(k).name} x{data.warning[k].number}")
    return out


def _hinge_slide(model: Any) -> np.ndarray:
    import mujoco

    return np.flatnonzero((model.jnt_type == mujoco.mjtJoint.mjJNT_HINGE)
                          | (model.jnt_type == mujoco.mjtJoint.mjJNT_SLIDE))


def _outside(model: Any, qpos: np.ndarray) -> np.ndarray:
    """How far each limited 1-dof joint is past its range (0 inside), by joint index."""
    out = np.zeros(model.njnt)
    j = _hinge_slide(model)
    j = j[model.jnt_limited[j].astype(bool)]
    x = qpos[model.jnt_qposadr[j]]
    lo, hi = model.jnt_range[j, 0], model.jnt_range[j, 1]
    out[j] = np.maximum(np.maximum(lo - x, x - hi), 0.0)
    return out


def _self_contacts(model: Any, data: Any) -> tuple[int, float]:
    """(contacts between two of the robot's bodies, deepest penetration (m, >= 0)); the world body's own
    geoms (a scene's floor) are not the robot's, its bodies welded to the world (the base) are."""
    n, depth = 0, 0.0
    for c in data.contact[: data.ncon]:
        b1, b2 = model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2]
        if b1 != 0 and b2 != 0:
            n += 1
            depth = max(depth, -float(c.dist))
    return n, depth


@dataclass
class HoldReport:
    """What ``hold_check`` saw. Angles rad (lengths m for slides), velocities rad/s."""

    seconds: float
    steps: int
    drift: float                 # largest |q - home| over the run, any joint, any step
    drift_joint: str
    qvel: float                  # largest |qvel| at the end
    warnings: list[str]          # MuJoCo's warnings (data.warning) over the run
    outside: list[str]           # joints outside their range at home
    contacts: int                # contacts between the robot's own bodies at home
    penetration: float           # the deepest of them (m)
    actuators: int
    wall: float                  # wall-clock seconds of the whole check
    step_ms: float               # milliseconds per mj_step
    compile_warnings: list[str] = field(default_factory=list)
    mass: float = math.inf       # the model's total mass (kg)

    @property
    def holds(self) -> bool:
        return (self.drift <= HOLD_DRIFT and self.qvel <= HOLD_QVEL and not self.warnings
                and not self.outside and not any(not _cosmetic(w) for w in self.compile_warnings))

    def line(self) -> str:
        """The one-line summary ``robkin convert`` prints."""
        verdict = "holds home" if self.holds else "does NOT hold home"
        parts = [f"{verdict} for {self.seconds:g} s: max drift {self.drift:.1e} ({self.drift_joint}), "
                 f"final |qvel| {self.qvel:.1e}",
                 "home inside the limits" if not self.outside else f"home outside the limits of {', '.join(self.outside[:4])}",
                 f"{self.contacts} self-contact(s) at home" + (f" (deepest {self.penetration * 1e3:.2g} mm)" if self.contacts else ""),
                 "no MuJoCo warning" if not (self.warnings or self.compile_warnings)
                 else "MuJoCo warnings: " + ", ".join(self.compile_warnings + self.warnings),
                 f"{self.step_ms:.3g} ms per step"]
        if self.mass < WEIGHTLESS:
            parts.insert(1, f"the model weighs {self.mass:.1g} kg (the source gave no masses): nothing to hold")
        return "; ".join(parts)


def hold_check(path: str | Path, seconds: float = HOLD_SECONDS, key: str = "home", contacts: bool = True) -> HoldReport:
    """Load ``path`` in MuJoCo, reset to keyframe ``key``, simulate ``seconds`` (see the module doc);
    ``contacts=False``: with MuJoCo's contacts disabled during the run (they are still counted at home),
    to tell the servos' part from the collision geometry's."""
    import warnings

    import mujoco

    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught, _c_warnings() as printed:
        warnings.simplefilter("always")
        model = mujoco.MjModel.from_xml_path(str(path))
    compile_warnings = [str(w.message).splitlines()[0] for w in caught] + printed
    data = mujoco.MjData(model)
    k = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_KEY, key)
    if k >= 0:
        mujoco.mj_resetDataKeyframe(model, data, k)
    mujoco.mj_forward(model, data)
    home = data.qpos.copy()
    joints = _hinge_slide(model)
    out = _outside(model, home)
    outside = [model.joint(j).name for j in joints if out[j] > 1e-12]
    count, depth = _self_contacts(model, data)
    if not contacts:
        model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
    steps = int(round(seconds / model.opt.timestep))
    adr = model.jnt_qposadr[joints]
    drift = np.zeros(len(joints))
    t1 = time.perf_counter()
    with _c_warnings():  # counted in data.warning; not printed (nor logged to MUJOCO_LOG.TXT)
        for _ in range(steps):
            mujoco.mj_step(model, data)
            np.maximum(drift, np.abs(data.qpos[adr] - home[adr]), out=drift)
    t2 = time.perf_counter()
    worst = int(np.argmax(drift)) if len(drift) else 0
    return HoldReport(seconds, steps, float(drift.max()) if len(drift) else 0.0,
                      model.joint(joints[worst]).name if len(joints) else "", float(np.abs(data.qvel).max(initial=0.0)),
                      _warnings(data), outside, count, depth, model.nu, time.perf_counter() - t0,
                      1e3 * (t2 - t1) / max(steps, 1), compile_warnings, float(model.body_mass.sum()))


#: compiler warnings about what is drawn only, not simulated: MuJoCo dropping an OBJ mesh's texture
#: coordinates changes no mass, contact or joint (they are still listed in the report's line)
COSMETIC_WARNINGS = ("discarding texture coordinates", "invalid or missing face texture coordinate")


def _cosmetic(warning: str) -> bool:
    return any(text in warning for text in COSMETIC_WARNINGS)


@dataclass
class StepReport:
    """What ``step_check`` saw, per actuated joint: target step, final error, largest excursion past the
    range of any joint during the step (rad or m), and MuJoCo's warnings."""

    joints: list[str]
    step: list[float]
    error: list[float]
    overshoot: list[float]
    past_range: list[float]
    past_joint: list[str]
    warnings: list[str]
    #: contacts at the end of each step (a step that drives a link into another one ends in contact)
    contacts: list[int] = field(default_factory=list)

    def worst(self) -> tuple[float, str]:
        k = int(np.argmax(self.error)) if self.error else 0
        return (self.error[k], self.joints[k]) if self.error else (0.0, "")


def step_check(path: str | Path, seconds: float = 2.0, size: float = 0.2, slide_size: float = 0.02,
               key: str = "home", contacts: bool = True, joints: Sequence[str] | None = None) -> StepReport:
    """From keyframe ``key``, step each position actuator's control (see the module doc); ``contacts``
    as for ``hold_check``; ``joints``: the joints stepped, and watched for leaving their range (default:
    every actuated joint).

    ``path``: the MJCF file; ``seconds``: how long each step is watched; ``size``: the step of a revolute
    joint (rad), ``slide_size`` of a prismatic one (m).
    """
    import mujoco

    model = mujoco.MjModel.from_xml_path(str(path))
    if not contacts:
        model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
    data = mujoco.MjData(model)
    k = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_KEY, key)
    steps = int(round(seconds / model.opt.timestep))
    watched = [a for a in range(model.nu) if joints is None or model.joint(model.actuator_trnid[a, 0]).name in joints]
    # the watched joints' ranges, once: (joint ids, qpos addresses, lower, upper) of those limited
    wj = np.array([model.actuator_trnid[a, 0] for a in watched], dtype=int)
    wj = wj[(model.jnt_limited[wj] != 0) & np.isin(wj, _hinge_slide(model))] if wj.size else wj
    wadr, wlo, whi = model.jnt_qposadr[wj], model.jnt_range[wj, 0], model.jnt_range[wj, 1]
    rep = StepReport([], [], [], [], [], [], [])
    for a in watched:
        j = model.actuator_trnid[a, 0]
        adr = model.jnt_qposadr[j]
        mujoco.mj_resetDataKeyframe(model, data, k)
        h = float(data.qpos[adr])
        lo, hi = model.actuator_ctrlrange[a] if model.actuator_ctrllimited[a] else (-math.inf, math.inf)
        if model.jnt_limited[j]:
            lo, hi = max(lo, model.jnt_range[j][0]), min(hi, model.jnt_range[j][1])
        s = slide_size if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_SLIDE else size
        up = (hi - h) >= (h - lo)
        s = min(s, 0.5 * ((hi - h) if up else (h - lo)))
        target = h + (s if up else -s)
        data.ctrl[a] = target
        past, over, who = 0.0, 0.0, ""
        with _c_warnings():
            for _ in range(steps):
                mujoco.mj_step(model, data)
                x = data.qpos[wadr]
                o = np.maximum(wlo - x, x - whi)
                if o.size and o.max() > past:
                    past, who = float(o.max()), model.joint(int(wj[int(np.argmax(o))])).name
                over = max(over, (data.qpos[adr] - target) * (1 if up else -1))
        rep.joints.append(model.joint(j).name)
        rep.step.append(target - h)
        rep.error.append(abs(float(data.qpos[adr]) - target))
        rep.overshoot.append(over)
        rep.past_range.append(past)
        rep.past_joint.append(who)
        rep.contacts.append(int(data.ncon))
        rep.warnings += [f"{model.joint(j).name}: {w}" for w in _warnings(data)]
    return rep
