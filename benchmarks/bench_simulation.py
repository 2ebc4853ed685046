"""The exported arms in MuJoCo: ms per ``mj_step``, the time ``convert --to mjcf`` spends simulating its
output, and what each MJCF option costs (docs/simulation.md quotes the numbers).

For each arm of the simulation-grade issue (example-robot-data: Panda, UR5, UR10, Kinova, xArm7, Z1,
SO-100, and the arms of Baxter, TIAGo and Talos), ``robkin convert X --to mjcf -o DIR/robot.xml``
(defaults: position servos, gravity compensation, implicitfast at 2 ms) is timed as a whole, then:

- **ms per step**: 1000 ``mj_step`` from the keyframe ``home``, contacts on (as a user presses play),
  median of 3 rounds of this thread's CPU time (``time.thread_time``: the machine's other load shows up
  less than in wall time);
- **check**: the wall time of the simulation check ``convert`` runs after writing (``hold_check``: load,
  5 s from home), and what it found: the largest drift from home and the final |qvel| (contacts on, and
  off: the servos alone), the self-contacts at home;
- **step**: the worst final error of a 0.2 rad step on each actuated joint after 1 s (contacts off).

Then the options on the Panda and the xArm7 (drift over 5 s from home, contacts off; an unstable run
shows as NaN or a MuJoCo warning): the default; ``--no-gravcomp``; the default gains under MuJoCo's
Euler integrator; ``--kp 500 --kv 50`` under Euler (the issue's report) and under implicitfast;
``--actuators motor`` with ctrl 0; ``--actuators velocity``.

Run: ``python benchmarks/bench_simulation.py [--quick]`` (``--quick``: the Panda and the UR5 only).
Exit status 0 whatever the timings; 1 when a default export does not hold home with contacts off.
"""

from __future__ import annotations

import argparse
import contextlib
import glob
import io
import os
import statistics
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

ARMS = [
    ("Panda", "panda_description/urdf/panda.urdf", None, "panda_hand_tcp"),
    ("UR5", "ur_description/urdf/ur5_robot.urdf", None, "tool0"),
    ("UR10", "ur_description/urdf/ur10_robot.urdf", None, "ee_link"),
    ("Kinova", "kinova_description/robots/kinova.urdf", None, "j2s6s200_end_effector"),
    ("xArm7", "xarm_description/urdf/xarm7.urdf", None, None),
    ("Z1", "z1_description/urdf/z1.urdf", None, "gripperMover"),
    ("SO-100", "so_arm_description/urdf/so100.urdf", None, None),
    ("Baxter arm", "baxter_description/urdf/baxter.urdf", None, "right_gripper"),
    ("TIAGo arm", "tiago_description/robots/tiago.urdf", None, "hand_tool_link"),
    ("Talos arm", "talos_data/robots/talos_full_v2.urdf", "torso_2_link", "gripper_left_base_link"),
]


def robots_dir() -> str:
    found = glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                   "example-robot-data", "robots"))
    return found[0] if found else ""


def convert(src: str, out: Path, base: str | None, tip: str | None, *extra: str) -> float:
    """Run ``robkin convert`` in this process; its wall time (s)."""
    from robkin.cli import main

    argv = ["convert", src, "--to", "mjcf", "-o", str(out), *extra]
    argv += ["--base-link", base] if base else []
    argv += ["--tip-link", tip] if tip else []
    err = io.StringIO()
    t0 = time.perf_counter()
    with warnings.catch_warnings(), contextlib.redirect_stderr(err):
        warnings.simplefilter("ignore")
        status = main(argv)
    if status != 0:
        raise SystemExit(f"convert failed: {err.getvalue()}")
    return time.perf_counter() - t0


def ms_per_step(path: Path, rounds: int = 3, steps: int = 1000) -> float:
    import mujoco

    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    times = []
    for _ in range(rounds):
        mujoco.mj_resetDataKeyframe(model, data, 0)
        t0 = time.thread_time()
        for _ in range(steps):
            mujoco.mj_step(model, data)
        times.append((time.thread_time() - t0) / steps * 1e3)
    return statistics.median(times)


def drift(path: Path, integrator: str | None = None, seconds: float = 5.0) -> tuple[float, float, str]:
    """(largest |q - home| over ``seconds``, final max |qvel|, warnings) with contacts off."""
    import mujoco

    from robkin.simulation.mujoco_check import _warnings

    model = mujoco.MjModel.from_xml_path(str(path))
    model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
    if integrator:
        model.opt.integrator = getattr(mujoco.mjtIntegrator, integrator)
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    home = data.qpos.copy()
    worst = 0.0
    for _ in range(int(seconds / model.opt.timestep)):
        mujoco.mj_step(model, data)
        worst = max(worst, float(np.abs(data.qpos - home).max()))
    return worst, float(np.abs(data.qvel).max()), ", ".join(_warnings(data)) or "-"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="the Panda and the UR5 only")
    args = parser.parse_args()
    try:
        import mujoco
    except ImportError:
        print("MuJoCo is not installed (pip install mujoco): nothing to measure")
        return 0
    from robkin.simulation.mujoco_check import hold_check, step_check

    root = robots_dir()
    if not root:
        print("example-robot-data is not installed: nothing to measure")
        return 0
    arms = ARMS[:2] if args.quick else ARMS
    failed = False
    print(f"MuJoCo {mujoco.__version__}, robkin default export (position servos, gravcomp, implicitfast, 2 ms)\n")
    print("| arm | nq | nu | convert (s) | its sim check (s) | ms / mj_step | drift 5 s, contacts on | "
          "self-contacts at home | drift 5 s, contacts off | final qvel | worst 0.2 rad step error |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for label, rel, base, tip in arms:
            src = os.path.join(root, rel)
            out = Path(tmp) / label.replace(" ", "_") / "robot.xml"
            total = convert(src, out, base, tip)
            full = hold_check(out)
            free = hold_check(out, contacts=False)
            failed |= not free.holds
            steps = step_check(out, seconds=1.0, contacts=False)   # every actuated joint
            err, who = steps.worst()
            model = mujoco.MjModel.from_xml_path(str(out))
            print(f"| {label} | {model.nq} | {model.nu} | {total:.2f} | {full.wall:.2f} | {ms_per_step(out):.4f} | "
                  f"{full.drift:.1e} | {full.contacts} | {free.drift:.1e} | {free.qvel:.1e} | {err:.1e} ({who}) |")
        print("\nOptions (drift over 5 s from home, contacts off; rad)\n")
        print("| arm | export | integrator | max drift | final qvel | MuJoCo warnings |")
        print("|---|---|---|---|---|---|")
        for label, rel, base, tip in (ARMS[0], ARMS[4]):
            src = os.path.join(root, rel)
            for name, extra, integrators in (
                    ("default", (), (None, "mjINT_EULER")),
                    ("--no-gravcomp", ("--no-gravcomp",), (None,)),
                    ("--kp 500 --kv 50", ("--kp", "500", "--kv", "50"), (None, "mjINT_EULER")),
                    ("--actuators motor (ctrl 0)", ("--actuators", "motor"), (None,)),
                    ("--actuators velocity (ctrl 0)", ("--actuators", "velocity"), (None,))):
                out = Path(tmp) / f"opt_{label}_{len(extra)}_{name[:6]}" / "robot.xml"
                convert(src, out, base, tip, *extra)
                for integ in integrators:
                    d, v, w = drift(out, integ)
                    print(f"| {label} | {name} | {'implicitfast' if integ is None else 'Euler'} | {d:.2e} | {v:.1e} | {w} |")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
