"""``robkin convert --to rtb``: the Robotics Toolbox file, run in a fresh process without robkin, against
pinocchio on the source URDF (independent oracle) and robkin's own FK and dynamics: ``fkine`` against pinocchio's frame placements,
``rne(q, qd, qdd)`` against ``rnea`` (plus the URDF's joint damping and Coulomb friction, which the file
gives the toolbox as B and Tc), ``gravload(q)`` against the generalized gravity, for standard and
modified DH, on real arms; joints off the chain locked at neutral (``buildReducedModel``).

All files run in one subprocess (the toolbox takes ~1 s to import; an import problem there cannot break
other tests)."""

from __future__ import annotations

import json
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import robkin
from robkin.io.toolboxes.rtb import rtb_from_robot
from test_dynamics import Pin
from test_toolbox_code import _hostile_robot
from test_urdf import robot_file

pin = pytest.importorskip("pinocchio")

#: (file, base link, tip link): arms with inertials from example-robot-data; a chain ending in a
#: prismatic finger; humanoid/mobile-manipulator arms whose base is mid-tree (the rest locked at
#: neutral, merged into the base or the links they hang from); URDFs with joint damping and friction
ARMS = [
    ("ur_description/urdf/ur3_robot.urdf", None, "tool0"),
    ("ur_description/urdf/ur5_robot.urdf", None, "tool0"),
    ("ur_description/urdf/ur10_robot.urdf", None, "tool0"),
    ("panda_description/urdf/panda.urdf", None, "panda_hand_tcp"),
    ("panda_description/urdf/panda.urdf", "panda_link0", "panda_leftfinger"),
    ("kinova_description/robots/kinova.urdf", None, "j2s6s200_end_effector"),
    ("xarm_description/urdf/xarm7.urdf", None, "link7"),
    ("z1_description/urdf/z1.urdf", None, "gripperMover"),
    ("talos_data/robots/talos_full_v2.urdf", "torso_2_link", "gripper_left_base_link"),
    ("tiago_description/robots/tiago.urdf", "torso_lift_link", "arm_tool_link"),
    ("baxter_description/urdf/baxter.urdf", "torso", "left_gripper"),
    # the Panda with joints 2, 4 and 6 turned to axis -z: robkin reads them as flip (the file's rne must
    # still be right: the toolbox's own flip is not used)
    ("panda_description/urdf/panda.urdf#flip246", None, "panda_hand_tcp"),
    # the UR5 mounted tilted in its world (the file's world_joint turned): gravity is not along base -z
    ("ur_description/urdf/ur5_robot.urdf#tilt", "base_link", "tool0"),
]
CONVENTIONS = ("dh", "mdh")
#: kinematics only (no inertials): the seed SCARA's flipped prismatic joints, and hostile names
KINEMATIC = {"scara": robkin.load(Path(robkin.__file__).parent / "examples" / "scara.yaml"),
             "hostile": _hostile_robot()}
#: Agreement with pinocchio relative to the largest entry (the issue's promise). Observed ~1e-14: the
#: same sums in other frames and order. A wrong frame, sign or inertia term is off by O(1).
REL_TOL = 1e-9
#: what is observed (this machine, 2026-11-28, Robotics Toolbox in the test venv): fkine 1.3e-12, rne
#: 8.2e-12, gravload 8.0e-12 of the largest entry (README and docs/toolboxes.md: "<= 8.2e-12"); 4e-11 is ~5x that (the
#: toolbox's Python sums in its own order; another version may round differently), so that a regression
#: far below the promise still fails.
ROUNDING_REL = 4e-11

#: Run in the fresh process: load each file with robkin made unimportable, evaluate at the given states.
RUNNER = r"""
import json, runpy, sys, warnings
sys.modules["robkin"] = None          # the file must not need robkin
warnings.simplefilter("ignore")
import numpy as np
jobs = json.load(open(sys.argv[1]))
out = []
for job in jobs:
    ns = runpy.run_path(job["file"])
    robot = ns["robot"]
    res = {"fkine": [], "rne": [], "gravload": [], "names": ns["JOINT_NAMES"], "name": robot.name}
    for q, qd, qdd in zip(job["q"], job["qd"], job["qdd"]):
        res["fkine"].append(np.asarray(robot.fkine(q).A).tolist())
        if job["dynamics"]:
            res["rne"].append(np.asarray(robot.rne(q, qd, qdd)).tolist())
            res["gravload"].append(np.asarray(robot.gravload(q)).tolist())
    out.append(res)
json.dump(out, open(sys.argv[2], "w"))
"""


#: the UR5's world joint, and the tilted mount it becomes for 'ur5_robot.urdf#tilt'
_WORLD_JOINT = '<child link="base_link"/>\n    <origin rpy="0.0 0.0 0.0" xyz="0.0 0.0 0.0"/>'
_TILTED = '<child link="base_link"/>\n    <origin rpy="0.3 -0.5 0.2" xyz="0.1 0.0 0.5"/>'


def _arm_path(rel: str, tmp: Path) -> str:
    """The robot file; 'file#flipIJK': a copy whose joints I, J, K (1-based, of those with axis +z) turn
    about -z instead; 'file#tilt': a copy whose world joint tilts the robot."""
    if "#tilt" in rel:
        text = Path(robot_file(rel.split("#")[0])).read_text()
        assert _WORLD_JOINT in text
        out = tmp / "ur5_tilted.urdf"
        out.write_text(text.replace(_WORLD_JOINT, _TILTED))
        return str(out)
    if "#flip" not in rel:
        return robot_file(rel)
    rel, which = rel.split("#flip")
    parts = Path(robot_file(rel)).read_text().split('<axis xyz="0 0 1"/>')
    text = parts[0] + "".join(('<axis xyz="0 0 -1"/>' if str(k) in which else '<axis xyz="0 0 1"/>') + part
                              for k, part in enumerate(parts[1:], start=1))
    out = tmp / Path(rel).name.replace(".urdf", f"_flip{which}.urdf")
    out.write_text(text)
    return str(out)


def _arm_id(arm) -> str:
    return f"{arm[0].split('/')[-1]}:{arm[2]}"


def _pin_pose(ref: Pin, robot, base: str | None, tip: str, q: np.ndarray) -> np.ndarray:
    """pinocchio's pose of the tip frame in the chain's base frame (the root when base is None)."""
    data = ref.model.createData()
    pin.framesForwardKinematics(ref.model, data, ref.q(q))
    T = data.oMf[ref.model.getFrameId(tip)].homogeneous
    if base is not None:
        T = np.linalg.inv(data.oMf[ref.model.getFrameId(base)].homogeneous) @ T
    return T


@pytest.fixture(scope="module")
def rtb_runs(tmp_path_factory):
    """For every arm and convention: (robot, pinocchio reference, states, the toolbox's answers)."""
    pytest.importorskip("roboticstoolbox")
    tmp = tmp_path_factory.mktemp("rtb")
    rng = np.random.default_rng(19)
    cases, jobs = [], []
    for arm in ARMS:
        rel, base, tip = arm
        path = _arm_path(rel, tmp)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")   # robot files held at neutral off the chain
            robot = robkin.load(path, base_link=base, tip_link=tip)
        ref = Pin(path, robot)
        lo, hi = np.maximum(robot.limits[:, 0], -2.0), np.minimum(robot.limits[:, 1], 2.0)
        states = {"q": lo + rng.random((3, robot.n)) * (hi - lo),
                  "qd": rng.uniform(-2, 2, (3, robot.n)), "qdd": rng.uniform(-2, 2, (3, robot.n))}
        for convention in CONVENTIONS:
            f = tmp / f"{len(jobs)}.py"
            f.write_text(rtb_from_robot(robot, convention))
            jobs.append({"file": str(f), "dynamics": True, **{k: v.tolist() for k, v in states.items()}})
            cases.append((arm, convention, robot, ref, states))
    for key, robot in KINEMATIC.items():   # no mass properties: fkine only
        states = {"q": rng.uniform(-2, 2, (3, robot.n)), "qd": np.zeros((3, robot.n)), "qdd": np.zeros((3, robot.n))}
        for convention in CONVENTIONS:
            f = tmp / f"{len(jobs)}.py"
            f.write_text(rtb_from_robot(robot, convention))
            jobs.append({"file": str(f), "dynamics": False, **{k: v.tolist() for k, v in states.items()}})
            cases.append(((key, None, key), convention, robot, None, states))
    (tmp / "jobs.json").write_text(json.dumps(jobs))
    proc = subprocess.run([sys.executable, "-c", RUNNER, str(tmp / "jobs.json"), str(tmp / "out.json")],
                          capture_output=True, text=True, timeout=600, cwd=tmp)
    assert not (tmp / "PWNED").exists()
    assert proc.returncode == 0, proc.stderr[-3000:]
    answers = json.loads((tmp / "out.json").read_text())
    return {(_arm_id(c[0]), c[1]): (*c[2:], a) for c, a in zip(cases, answers)}


def _close(ours, ref, what: str) -> None:
    ours, ref = np.asarray(ours), np.asarray(ref)
    err = np.max(np.abs(ours - ref))
    largest = max(np.max(np.abs(ref)), 1e-300)
    assert err <= REL_TOL * largest, f"{what}: {err:.3g} off (largest {np.max(np.abs(ref)):.3g}): the promise"
    assert err <= ROUNDING_REL * largest, f"{what}: {err:.3g} off (largest {np.max(np.abs(ref)):.3g}): observed"


@pytest.mark.parametrize("convention", CONVENTIONS)
@pytest.mark.parametrize("arm", ARMS, ids=_arm_id)
def test_rtb_file_matches_pinocchio(rtb_runs, arm, convention):
    robot, ref, states, got = rtb_runs[(_arm_id(arm), convention)]
    _, base, tip = arm
    damping = ref.model.damping[ref.order]
    friction = ref.model.friction[ref.order]
    for k, (q, qd, qdd) in enumerate(zip(states["q"], states["qd"], states["qdd"])):
        _close(got["fkine"][k], _pin_pose(ref, robot, base, tip, q), "fkine")
        # the file gives the URDF's damping and Coulomb friction to the toolbox (B, Tc), which adds them
        _close(got["rne"][k], ref.rnea(q, qd, qdd) + damping * qd + friction * np.sign(qd), "rne")
        _close(got["gravload"][k], ref.gravity(q), "gravload")
        # and robkin's own dynamics (the compiled recursive Newton-Euler) agree with both
        _close(got["rne"][k], robot.inverse_dynamics(q, qd, qdd) + damping * qd + friction * np.sign(qd), "robkin rne")
        _close(got["gravload"][k], robot.gravity(q), "robkin gravity")
        _close(got["fkine"][k], robot.fk(q), "robkin fk")


@pytest.mark.parametrize("convention", CONVENTIONS)
@pytest.mark.parametrize("key", list(KINEMATIC))
def test_rtb_file_of_flipped_joints_and_hostile_names(rtb_runs, key, convention):
    """Flipped prismatic joints (the seed SCARA) and names that try to be code: fkine is robkin's FK, the
    names arrive as the very strings, and nothing ran (no PWNED file in the working folder)."""
    robot, _, states, got = rtb_runs[(key + ":" + key, convention)]
    for k, q in enumerate(states["q"]):
        _close(got["fkine"][k], robot.fk(q), "fkine")
    assert got["names"] == [j.name for j in robot.joints] and got["name"] == robot.name


def test_enough_arms_with_dynamics_are_covered():
    """The issue asks for at least 8 real arms with inertials."""
    assert len({a[0] for a in ARMS}) >= 8
