"""The robot zoo, proved in every format robkin writes: ``make zoo`` regenerates docs/zoo.md.

Each robot is a serial chain of a robot file (a file plus its base and tip links: an arm, a gripper's
finger, a hand's finger, a humanoid's arm or leg, a quadruped's leg) from a package pip installs
(example-robot-data). For each chain, robkin reads the file, then ``robkin convert`` (in this process,
the default options a user gets) writes it in every format, and:

- **tables** (``--to dh, mdh, hayati, poe, rpy-xyz, gjd`` as YAML robot documents, default digits: the
  shortest decimals that keep FK within 1e-12 of the robot's size): read back by robkin, FK against the
  source's;
- **URDF**: read back by robkin (FK) and by pinocchio (FK of the tip frame, M(q), g(q)), against robkin's
  reading of the source and pinocchio's model of the source (``buildReducedModel``: joints off the chain
  locked at 0);
- **MJCF**: read back by robkin (FK) and loaded by MuJoCo from the written file (the tip site's pose,
  ``mj_fullM``, ``qfrc_bias`` at zero velocity) against pinocchio's model of the source; and the line
  ``robkin convert`` prints after simulating its own output (``hold_check``: 5 s from the keyframe
  ``home``, contacts on, as a user pressing play): does it hold home;
- **USD**: read back by robkin (FK) and by pxr (FK composed from the joint prims with Gf matrices, the
  oracle of tests/test_usd.py), and usd-core's ``UsdPhysics.LoadUsdPhysicsFromRange`` parse: one valid
  articulation;
- **code** (``--to rtb, matlab, eaik, opw``): written or refused (robkin reads none of them back, and the
  toolboxes are not run here: tests/test_toolboxes.py runs them on a few arms);
- **source**: robkin's FK, M(q), g(q) of the source against pinocchio's.

FK errors: the largest over the draws of |rotation entry| and |translation| / the robot's size
(``Robot.scale``); M and g: the largest |difference| / the largest |entry| of pinocchio's. Joint values are
drawn uniformly within the limits (``Robot.random_q``, fixed seed).

Run: ``python benchmarks/zoo.py [--out docs/zoo.md] [--only LABEL ...] [--draws N]``. Nothing is cached
between runs: every output is written again in a temporary folder. Exit status 0 when every row was
measured (failures are rows of the page, with their explanation), 1 when the script itself broke.
"""

from __future__ import annotations

import argparse
import contextlib
import datetime
import glob
import io
import math
import os
import platform
import re
import sys
import tempfile
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

#: (label, kind, file under example-robot-data/robots, base link or None for the file's root, tip link)
CHAINS = [
    # arms (and arms on mobile bases and drones)
    ("UR3", "arm", "ur_description/urdf/ur3_robot.urdf", None, "tool0"),
    ("UR5", "arm", "ur_description/urdf/ur5_robot.urdf", None, "tool0"),
    ("UR10", "arm", "ur_description/urdf/ur10_robot.urdf", None, "ee_link"),
    ("UR3 (gripper file)", "arm", "ur_description/urdf/ur3_gripper.urdf", None, "tool0"),
    ("UR5 (gripper file)", "arm", "ur_description/urdf/ur5_gripper.urdf", None, "tool0"),
    ("UR10 (joint-limited)", "arm", "ur_description/urdf/ur10_joint_limited_robot.urdf", None, "tool0"),
    ("Panda", "arm", "panda_description/urdf/panda.urdf", None, "panda_hand_tcp"),
    ("Kinova Gen2", "arm", "kinova_description/robots/kinova.urdf", None, "j2s6s200_end_effector"),
    ("xArm7", "arm", "xarm_description/urdf/xarm7.urdf", None, "link_eef"),
    ("Z1", "arm", "z1_description/urdf/z1.urdf", None, "gripperMover"),
    ("SO-100", "arm", "so_arm_description/urdf/so100.urdf", None, "jaw"),
    ("SO-101", "arm", "so_arm_description/urdf/so101.urdf", None, "gripper_frame_link"),
    ("Z1 on B1", "arm", "b1_description/urdf/b1-z1.urdf", None, "gripperMover"),
    ("Kinova on ANYmal B", "arm", "anymal_b_simple_description/robots/anymal-kinova.urdf", None,
     "j2s6s200_end_effector"),
    ("TIAGo arm", "arm", "tiago_description/robots/tiago.urdf", None, "hand_tool_link"),
    ("TIAGo (no hand) arm", "arm", "tiago_description/robots/tiago_no_hand.urdf", None, "wrist_ft_tool_link"),
    ("TIAGo dual, right arm", "arm", "tiago_description/robots/tiago_dual.urdf", None, "hand_right_tool_link"),
    ("Baxter right arm", "arm", "baxter_description/urdf/baxter.urdf", None, "right_gripper"),
    ("Baxter left arm", "arm", "baxter_description/urdf/baxter.urdf", None, "left_gripper"),
    ("PR2 right arm", "arm", "pr2_description/urdf/pr2.urdf", None, "r_gripper_tool_frame"),
    ("Centauro arm", "arm", "centauro_description/urdf/centauro.urdf", None, "arm1_8"),
    ("Hextilt flying arm", "arm", "hextilt_description/urdf/hextilt_flying_arm_5.urdf", None,
     "flying_arm_5__gripper"),
    ("Borinot flying arm", "arm", "borinot_description/urdf/borinot_flying_arm_2.urdf", None, "flying_arm_2__ee"),
    ("Two-DoF arm (ASR)", "arm", "asr_twodof_description/urdf/TwoDofs.urdf", None, "Tip"),
    ("Double pendulum", "arm", "double_pendulum_description/urdf/double_pendulum.urdf", None, "link2"),
    ("Double pendulum (continuous)", "arm", "double_pendulum_description/urdf/double_pendulum_continuous.urdf",
     None, "link2"),
    # grippers: a finger of a parallel or three-finger gripper, through the arm
    ("Panda left finger", "gripper", "panda_description/urdf/panda.urdf", None, "panda_leftfinger"),
    ("Panda right finger (mimic)", "gripper", "panda_description/urdf/panda.urdf", None, "panda_rightfinger"),
    ("Kinova finger 1", "gripper", "kinova_description/robots/kinova.urdf", None, "j2s6s200_link_finger_tip_1"),
    ("Kinova finger 2", "gripper", "kinova_description/robots/kinova.urdf", None, "j2s6s200_link_finger_tip_2"),
    ("SO-101 moving jaw", "gripper", "so_arm_description/urdf/so101.urdf", None, "moving_jaw_so101_v1_link"),
    ("Baxter gripper finger", "gripper", "baxter_description/urdf/baxter.urdf", None, "r_gripper_l_finger_tip"),
    ("PR2 gripper finger", "gripper", "pr2_description/urdf/pr2.urdf", None, "r_gripper_l_finger_link"),
    ("TALOS gripper finger", "gripper", "talos_data/robots/talos_left_arm.urdf", None,
     "gripper_left_fingertip_1_link"),
    ("TIAGo Pro gripper finger", "gripper", "tiago_pro_description/robots/tiago_pro.urdf", None,
     "gripper_left_outer_finger_left_link"),
    ("TriFinger finger (finger_edu)", "gripper", "finger_edu_description/robots/finger_edu.urdf", None,
     "finger_tip_link"),
    # hands: one finger each
    ("Allegro right, index", "hand", "allegro_hand_description/urdf/allegro_right_hand.urdf", None, "link_3.0_tip"),
    ("Allegro right, middle", "hand", "allegro_hand_description/urdf/allegro_right_hand.urdf", None, "link_7.0_tip"),
    ("Allegro right, ring", "hand", "allegro_hand_description/urdf/allegro_right_hand.urdf", None, "link_11.0_tip"),
    ("Allegro right, thumb", "hand", "allegro_hand_description/urdf/allegro_right_hand.urdf", None, "link_15.0_tip"),
    ("Allegro left, thumb", "hand", "allegro_hand_description/urdf/allegro_left_hand.urdf", None, "link_15.0_tip"),
    ("G1 hand, thumb", "hand", "g1_description/urdf/g1_29dof_with_hand_rev_1_0.urdf", None, "left_hand_thumb_2_link"),
    ("G1 hand, index", "hand", "g1_description/urdf/g1_29dof_with_hand_rev_1_0.urdf", None, "left_hand_index_1_link"),
    ("TIAGo hand, index", "hand", "tiago_description/robots/tiago.urdf", None, "hand_index_flex_3_link"),
    ("Romeo hand, thumb (mimic)", "hand", "romeo_description/urdf/romeo.urdf", None, "LThumb3Link"),
    ("Alex (PSYONIC hand), index (mimic)", "hand", "alex_description/urdf/alex_psyonic_hands.urdf", None, "Left_index_anchor"),
    ("Alex (SAKE hand), finger", "hand", "alex_description/urdf/alex_sake_hands.urdf", None, "RightSakeFingerTip1"),
    # humanoid limbs
    ("TALOS left arm", "humanoid arm", "talos_data/robots/talos_full_v2.urdf", "torso_2_link", "gripper_left_base_link"),
    ("TALOS left leg", "humanoid leg", "talos_data/robots/talos_full_v2.urdf", "base_link", "left_sole_link"),
    ("TALOS right leg", "humanoid leg", "talos_data/robots/talos_full_v2.urdf", "base_link", "right_sole_link"),
    ("G1 left leg", "humanoid leg", "g1_description/urdf/g1_29dof_rev_1_0.urdf", None, "left_ankle_roll_link"),
    ("G1 left arm", "humanoid arm", "g1_description/urdf/g1_29dof_rev_1_0.urdf", None, "left_rubber_hand"),
    ("Romeo left leg", "humanoid leg", "romeo_description/urdf/romeo.urdf", None, "l_sole"),
    ("Romeo left arm", "humanoid arm", "romeo_description/urdf/romeo.urdf", None, "l_gripper"),
    ("iCub left arm", "humanoid arm", "icub_description/robots/icub.urdf", None, "l_gripper"),
    ("iCub right leg", "humanoid leg", "icub_description/robots/icub.urdf", None, "r_sole"),
    ("Simple humanoid left arm", "humanoid arm", "simple_humanoid_description/urdf/simple_humanoid.urdf", None,
     "l_wrist"),
    ("Human model right arm", "humanoid arm", "human_description/robots/human.urdf", None, "right_hand"),
    ("Alex left arm", "humanoid arm", "alex_description/urdf/alex_nub_hands.urdf", None, "leftNub"),
    ("Alexander left leg", "humanoid leg", "alexander_description/urdf/alexander_v1.lowerBodyOnly.urdf", None,
     "LEFT_FOOT_IMU_LINK"),
    # legs of legged robots
    ("Solo12 front-left leg", "leg", "solo_description/robots/solo12.urdf", None, "FL_FOOT"),
    ("Solo8 hind-left leg", "leg", "solo_description/robots/solo.urdf", None, "HL_FOOT"),
    ("Bolt right leg", "leg", "bolt_description/robots/bolt.urdf", None, "FR_FOOT"),
    ("Go2 front-left leg", "leg", "go2_description/urdf/go2.urdf", None, "FL_foot"),
    ("Go1 rear-right leg", "leg", "go1_description/urdf/go1.urdf", None, "RR_foot"),
    ("A1 front-right leg", "leg", "a1_description/urdf/a1.urdf", None, "FR_foot"),
    ("B1 rear-left leg", "leg", "b1_description/urdf/b1.urdf", None, "RL_foot"),
    ("Laikago front-left leg", "leg", "laikago_description/urdf/laikago.urdf", None, "FL_foot"),
    ("ANYmal C left-front leg", "leg", "anymal_c_simple_description/urdf/anymal.urdf", None, "LF_FOOT"),
    ("ANYmal B right-hind leg", "leg", "anymal_b_simple_description/robots/anymal.urdf", None, "RH_FOOT"),
    ("HyQ left-front leg", "leg", "hyq_description/robots/hyq_no_sensors.urdf", None, "lf_foot"),
    ("Quadruped (planar) front-left leg", "leg", "quadruped_description/urdf/quadruped.urdf", None, "FL_contact"),
    ("Centauro leg (wheel)", "leg", "centauro_description/urdf/centauro.urdf", None, "wheel_1"),
    # a second source: the robots pybullet ships in pybullet_data (pip install pybullet)
    ("KUKA iiwa (pybullet)", "arm", "pybullet:kuka_iiwa/model.urdf", None, "lbr_iiwa_link_7"),
    ("Panda (pybullet)", "arm", "pybullet:franka_panda/panda.urdf", None, "panda_grasptarget"),
    ("xArm6 (pybullet)", "arm", "pybullet:xarm/xarm6_robot.urdf", None, "link6"),
    ("Panda finger (pybullet)", "gripper", "pybullet:franka_panda/panda.urdf", None, "panda_leftfinger"),
    ("xArm6 gripper drive (pybullet)", "gripper", "pybullet:xarm/xarm6_with_gripper.urdf", None,
     "left_outer_knuckle"),
    ("PR2 gripper jaw (pybullet)", "gripper", "pybullet:pr2_gripper.urdf", None, "left_tip"),
    ("A1 front-right leg (pybullet)", "leg", "pybullet:a1/a1.urdf", None, "FR_toe"),
    ("Aliengo front-left leg (pybullet)", "leg", "pybullet:aliengo/aliengo.urdf", None, "FL_toe"),
    ("Mini Cheetah front-right leg (pybullet)", "leg", "pybullet:mini_cheetah/mini_cheetah.urdf", None, "toe_fr"),
    ("Laikago front-right leg (pybullet)", "leg", "pybullet:laikago/laikago_toes.urdf", None, "toeFR"),
    ("Minitaur front-right leg (pybullet)", "leg", "pybullet:quadruped/minitaur.urdf", None,
     "lower_leg_front_rightR_link"),
    ("Spirit 40 leg (pybullet)", "leg", "pybullet:quadruped/spirit40.urdf", None, "toe0"),
    ("Vision 60 leg (pybullet)", "leg", "pybullet:quadruped/vision60.urdf", None, "toe0"),
]
#: where each source's files are: example-robot-data (cmeel prefix) and pybullet_data (``pybullet:`` paths)
PYBULLET = "pybullet:"

TABLES = ("dh", "mdh", "hayati", "poe", "rpy-xyz", "gjd")
CODES = ("rtb", "matlab", "eaik", "opw")
#: a parity figure at or below this is "exact" in the summary: rounding (observed ~1e-15 for doubles).
#: The YAML documents' default digits keep FK within 1e-12 of the size (see ``--digits``); USD stores
#: float32 (relative rounding ~6e-8 per number, composed along the chain).
ROUNDING = 1e-12
FLOAT32 = 1e-6


def robots_dir() -> str:
    found = glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                   "example-robot-data", "robots"))
    return found[0] if found else ""


def pybullet_dir() -> str:
    """pybullet_data's folder (a data package: importing it loads no compiled code), or "" without pybullet."""
    import importlib.util

    spec = importlib.util.find_spec("pybullet_data")
    return str(Path(spec.origin).parent) if spec is not None and spec.origin else ""


def source_path(rel_: str, root: str) -> str:
    """The file of a CHAINS entry: under example-robot-data's robots, or pybullet_data's folder."""
    if rel_.startswith(PYBULLET):
        return os.path.join(pybullet_dir(), rel_[len(PYBULLET):])
    return os.path.join(root, rel_)


def local_packages(path: str) -> list[str]:
    """``--package-path NAME=DIR`` for each ``package://NAME/`` whose DIR is a folder beside the file: how
    pybullet finds them (it resolves package:// against the URDF's folder); example-robot-data's own
    names are found by robkin without help."""
    folder = Path(path).parent
    names = sorted(set(re.findall(r"package://([A-Za-z0-9_.\-]+)/", Path(path).read_text(errors="replace"))))
    out = []
    for name in names:
        if (folder / name).is_dir():
            out += ["--package-path", f"{name}={folder / name}"]
    return out


def cpu_name() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def lint_available() -> bool:
    import importlib.util

    from robkin import cli

    return "lint" in getattr(cli, "COMMANDS", ()) or importlib.util.find_spec("robkin.commands.lint") is not None


_LINTED: dict[str, str] = {}
_CODES: dict[str, set] = {}   # file -> the codes of lint's findings


def lint_status(path: str) -> str:
    """``robkin lint`` of the whole file (once per file: several chains share it): 'ok', the warnings'
    count, or the errors' count and the first error (exit 1), or why it could not be read (exit 2)."""
    if path not in _LINTED:
        import json

        status, text = cli(["lint", path, "--format", "json", *local_packages(path)])
        if status == 2:
            _LINTED[path] = f"unreadable: {first_error(text)}"
        else:
            start = text.find("[")
            found = json.loads(text[start:text.rindex("]") + 1]) if start >= 0 else []
            _CODES[path] = {f.get("code") for f in found}
            errors = [f for f in found if f.get("severity") == "error"]
            warns = [f for f in found if f.get("severity") == "warning"]
            if errors:
                _LINTED[path] = f"{len(errors)} error(s): {errors[0].get('element', '')}: {errors[0].get('message', '')}"
            else:
                _LINTED[path] = f"{len(warns)} warning(s)" if warns else "ok"
    return _LINTED[path]


@dataclass
class Row:
    label: str
    kind: str
    rel: str
    base: str | None
    tip: str
    n: int = 0
    joints: str = ""
    source: dict = field(default_factory=dict)      # robkin vs pinocchio on the source: fk, M, g
    tables: dict = field(default_factory=dict)      # representation -> FK error, or a refusal string
    urdf: dict = field(default_factory=dict)        # robkin, pin_fk, M, g
    mjcf: dict = field(default_factory=dict)        # robkin, fk, M, g, hold (bool), hold_line
    usd: dict = field(default_factory=dict)         # robkin, pxr, physics (bool or message)
    code: dict = field(default_factory=dict)        # format -> "ok" or refusal string
    lint: str = "n/a (lint not on this branch)"
    notes: list = field(default_factory=list)      # failures of the measurement itself
    info: list = field(default_factory=list)       # explanations of figures (not failures)
    warned: dict = field(default_factory=dict)     # format -> robkin convert's warning lines
    seconds: float = 0.0
    chain_joints: tuple = ()


def warnings_of(text: str) -> list[str]:
    # (the MJCF's hold line is a warning when it does not hold: it has a column of its own)
    return [ln.split("warning:", 1)[1].strip() for ln in text.splitlines()
            if "robkin: warning:" in ln and "MuJoCo: " not in ln]


def cli(argv: list[str]) -> tuple[int, str]:
    """``robkin`` in this process; (status, what it printed on stderr and stdout)."""
    from robkin.cli import main

    out, err = io.StringIO(), io.StringIO()
    with warnings.catch_warnings(), contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
        warnings.simplefilter("ignore")
        try:
            status = main(argv)
        except SystemExit as e:   # argparse
            status = e.code if isinstance(e.code, int) else 2
    return int(status or 0), err.getvalue() + out.getvalue()


def first_error(text: str) -> str:
    for line in text.splitlines():
        if "error" in line:
            return line.split("error:", 1)[-1].strip()
    return text.strip().splitlines()[-1] if text.strip() else "failed"


def fk_error(A: np.ndarray, B: np.ndarray, size: float) -> float:
    """Largest rotation-entry difference and translation difference / size over stacks of poses."""
    A, B = np.asarray(A).reshape(-1, 4, 4), np.asarray(B).reshape(-1, 4, 4)
    return float(max(np.abs(A[:, :3, :3] - B[:, :3, :3]).max(), np.abs(A[:, :3, 3] - B[:, :3, 3]).max() / size))


def rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(np.asarray(a) - b).max() / max(float(np.abs(b).max()), 1e-300))


def load(path, base, tip):
    import robkin

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return robkin.load(str(path), base_link=base, tip_link=tip)


class Pin:
    """A URDF in pinocchio reduced to robkin's chain, in robkin's joint order (tests/test_dynamics.Pin)."""

    def __init__(self, path: str, robot) -> None:
        import pinocchio as pin

        self.pin = pin
        full = pin.buildModelFromUrdf(str(path))
        keep = {j.name for j in robot.joints}
        lock = [i for i in range(1, full.njoints) if full.names[i] not in keep]
        self.reduced = True
        try:
            self.model = pin.buildReducedModel(full, lock, pin.neutral(full)) if lock else full
        except ValueError as e:
            # pinocchio refuses to reduce a model with two frames of one name (a joint and a link): the full
            # model then, the others joints at 0 (neutral): the chain's rows and columns of M(q) and g(q)
            # are the reduced model's (locking a joint at 0 leaves the chain's composite inertias as they are)
            self.model, self.reduced = full, str(e).split(" - ")[0]
        self.data = self.model.createData()
        self.joints = [self.model.joints[self.model.getJointId(j.name)] for j in robot.joints]
        self.order = [jm.idx_v for jm in self.joints]
        self.tip = robot.bodies.tip

    def q(self, q: np.ndarray) -> np.ndarray:
        out = self.pin.neutral(self.model)
        for jm, value in zip(self.joints, q):
            if jm.nq == 2:   # continuous joint: (cos, sin)
                out[jm.idx_q], out[jm.idx_q + 1] = np.cos(value), np.sin(value)
            else:
                out[jm.idx_q] = value
        return out

    def fk(self, q: np.ndarray) -> np.ndarray:
        self.pin.framesForwardKinematics(self.model, self.data, self.q(q))
        return self.data.oMf[self.model.getFrameId(self.tip, self.pin.BODY)].homogeneous.copy()

    def gravity(self, q) -> np.ndarray:
        return self.pin.computeGeneralizedGravity(self.model, self.data, self.q(q))[self.order].copy()

    def mass_matrix(self, q) -> np.ndarray:
        M = self.pin.crba(self.model, self.data, self.q(q))
        M = np.triu(M) + np.triu(M, 1).T
        return M[np.ix_(self.order, self.order)]


def dynamics_vs(ref: Pin, mass_matrix, gravity, qs) -> tuple[float, float]:
    return (max(rel(mass_matrix(q), ref.mass_matrix(q)) for q in qs),
            max(rel(gravity(q), ref.gravity(q)) for q in qs))


def pxr_fk(path: Path, robot, qs) -> np.ndarray:
    """The tip's pose at each q from the USD joint prims (pxr's Gf only; tests/test_usd.Oracle)."""
    from pxr import Gf, Usd, UsdGeom, UsdPhysics

    stage = Usd.Stage.Open(str(path))
    cache = UsdGeom.XformCache()
    prims = list(stage.Traverse())

    def name(p):
        a = p.GetAttribute("robkin:name")
        return a.Get() if a and a.HasAuthoredValue() else p.GetName()

    def gf(pos, rot):
        return np.array(Gf.Matrix4d().SetRotate(Gf.Quatd(rot).GetNormalized()).SetTranslateOnly(Gf.Vec3d(pos))).T

    bodies = {p.GetPath() for p in prims if p.HasAPI(UsdPhysics.RigidBodyAPI)}
    by_child = {UsdPhysics.Joint(p).GetBody1Rel().GetTargets()[0]: p for p in prims if p.IsA(UsdPhysics.Joint)}
    axes = {"X": Gf.Vec3d(1, 0, 0), "Y": Gf.Vec3d(0, 1, 0), "Z": Gf.Vec3d(0, 0, 1)}

    def body_pose(path, q):
        p = by_child[path]
        j = UsdPhysics.Joint(p)
        J0 = gf(j.GetLocalPos0Attr().Get(), j.GetLocalRot0Attr().Get())
        J1 = gf(j.GetLocalPos1Attr().Get(), j.GetLocalRot1Attr().Get())
        targets = j.GetBody0Rel().GetTargets()
        parent = np.eye(4) if not targets else body_pose(targets[0], q)
        move = np.eye(4)
        value = q.get(name(p), 0.0)
        if p.IsA(UsdPhysics.RevoluteJoint):
            axis = axes[UsdPhysics.RevoluteJoint(p).GetAxisAttr().Get()]
            move = np.array(Gf.Matrix4d().SetRotate(Gf.Quatd(math.cos(value / 2), axis * math.sin(value / 2)))).T
        elif p.IsA(UsdPhysics.PrismaticJoint):
            axis = axes[UsdPhysics.PrismaticJoint(p).GetAxisAttr().Get()]
            move = np.array(Gf.Matrix4d().SetTranslate(axis * value)).T
        return parent @ J0 @ move @ np.linalg.inv(J1)

    tip = next(p for p in prims if name(p) == robot.bodies.tip and p.GetTypeName() == "Xform")
    body = tip
    while body.GetPath() not in bodies:
        body = body.GetParent()
    offset = cache.GetLocalToWorldTransform(tip) * cache.GetLocalToWorldTransform(body).GetInverse()
    names = [j.name for j in robot.joints]
    return np.array([body_pose(body.GetPath(), dict(zip(names, map(float, q)))) @ np.array(offset).T for q in qs])


def usd_physics(path: Path) -> str:
    """'ok' when usd-core's UsdPhysics parser finds one valid articulation with valid joints, else why not."""
    import pxr
    from pxr import Usd, UsdPhysics

    stage = Usd.Stage.Open(str(path))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        parsed = UsdPhysics.LoadUsdPhysicsFromRange(stage, [pxr.Sdf.Path("/")])
    T = UsdPhysics.ObjectType
    arts = parsed[T.Articulation][1] if T.Articulation in parsed else []
    if len(arts) != 1 or not arts[0].isValid:
        return f"{len(arts)} articulations"
    joints = [d for k in (T.RevoluteJoint, T.PrismaticJoint, T.FixedJoint) if k in parsed for d in parsed[k][1]]
    bad = [d for d in joints if not d.isValid]
    return "ok" if not bad else f"{len(bad)} invalid joints"


def guard(row: Row, what: str, fn, *args):
    """Run one measurement; a failure becomes a note of the row instead of stopping the zoo."""
    try:
        return fn(*args)
    except Exception as e:   # noqa: BLE001 - every failure is a row's note
        text = str(e).splitlines()[0] if str(e) else ""
        root = robots_dir()
        row.notes.append(f"{what}: {type(e).__name__}: {text.replace(root + os.sep, '') if root else text}")
        return None


HOLD = re.compile(r"MuJoCo: (holds home|does NOT hold home)[^;]*max drift ([0-9.e+-]+) \(([^)]*)\)")


def measure(row: Row, path: str, tmp: Path, draws: int, lint: bool) -> Row:
    t0 = time.perf_counter()
    ends = ["--base-link", row.base] * bool(row.base) + ["--tip-link", row.tip] + local_packages(path)
    robot = guard(row, "robkin load", load, path, row.base, row.tip)
    if robot is None:
        return row
    row.chain_joints = tuple(j.name for j in robot.joints)
    row.n, row.joints = robot.n, "".join("R" if j.revolute else "P" for j in robot.joints)
    size = robot.scale
    qs = robot.random_q(draws, rng=7)
    F = robot.fk(qs)
    W = robot.world @ F   # the tip in the file's world frame (a mid-tree base's pose in front)
    ref = guard(row, "pinocchio (source)", Pin, path, robot)
    if ref is not None and ref.reduced is not True:
        row.info.append(f"pinocchio's buildReducedModel refuses the file ({ref.reduced}): its full model is the "
                        "reference, the joints off the chain at 0 (the same M, g rows)")
    if ref is not None:
        row.source["fk"] = fk_error(W, np.array([ref.fk(q) for q in qs]), size)
        got = guard(row, "robkin dynamics (source)", dynamics_vs, ref, robot.mass_matrix, robot.gravity, qs)
        if got is not None:
            row.source["M"], row.source["g"] = got

    def back(out: Path, document: bool = False) -> float:
        """FK of the output read back by robkin (a robot file: the same chain, from the same base)."""
        again = load(out, None, None) if document else load(out, robot.bodies.chain[0], robot.bodies.tip)
        return fk_error(again.fk(qs), F, size)

    for rep in TABLES:
        out = tmp / f"{rep}.yaml"
        status, text = cli(["convert", path, *ends, "--to", rep, "-o", str(out)])
        row.tables[rep] = guard(row, f"{rep} read back", back, out, True) if status == 0 else "refused: " + first_error(text)
        err = row.tables[rep]
        if isinstance(err, float) and err > ROUNDING:   # above the documents' digit budget: the digits, or not?
            status, text = cli(["convert", path, *ends, "--to", rep, "--exact", "-o", str(out)])
            exact = guard(row, f"{rep} --exact read back", back, out, True) if status == 0 else None
            if exact is not None:
                row.info.append(f"{rep}: FK {fmt(err)} of the size with default digits, {fmt(exact)} with --exact: "
                                + ("the digits" if exact <= ROUNDING else "the conversion itself, not the digits "
                                   "(within robkin's 1e-9 promise, above rounding; reported)"))

    out = tmp / "robot.urdf"
    status, text = cli(["convert", path, *ends, "--to", "urdf", "-o", str(out)])
    row.warned["URDF"] = warnings_of(text)
    if status:
        row.urdf["error"] = first_error(text)
    else:
        row.urdf["robkin"] = guard(row, "URDF read back", back, out)
        other = guard(row, "pinocchio (URDF)", Pin, out, robot)
        if other is not None:
            row.urdf["fk"] = fk_error(np.array([other.fk(q) for q in qs]), W, size)
            if ref is not None:
                row.urdf["M"], row.urdf["g"] = dynamics_vs(ref, other.mass_matrix, other.gravity, qs)

    out = tmp / "mjcf" / "robot.xml"
    status, text = cli(["convert", path, *ends, "--to", "mjcf", "--scene", "-o", str(out)])
    row.warned["MJCF"] = warnings_of(text)
    if status:
        row.mjcf["error"] = first_error(text)
    else:
        found = HOLD.search(text)
        row.mjcf["hold"] = None if not found else found.group(1) == "holds home"
        row.mjcf["drift_joint"] = found.group(3) if found else None
        row.mjcf["drift"] = float(found.group(2)) if found else None
        row.mjcf["hold_line"] = next((ln.split("MuJoCo: ", 1)[1] for ln in text.splitlines() if "MuJoCo: " in ln), "")
        row.mjcf["robkin"] = guard(row, "MJCF read back", back, out)
        scene = guard(row, "MuJoCo scene", scene_hold, out.parent / "scene.xml")
        if scene is not None:
            row.mjcf["scene"], row.mjcf["scene_line"] = scene.holds, scene.line()
            row.mjcf["scene_joint"] = scene.drift_joint
            row.mjcf["floor"] = scene.floor
        guard(row, "MuJoCo", mujoco_parity, row, out, robot, ref, qs, W, size)
        if lint and (lint_status(path) and "inertia-without-mass" in _CODES.get(path, ())):
            row.info.append("MJCF M: the source has links of mass 0 with a nonzero inertia (`robkin lint`: "
                            "inertia-without-mass), which pinocchio keeps and MuJoCo's model of the export does not: "
                            "that is the M difference (physically, no mass has an inertia)")
            row.mjcf["unphysical_source"] = True
        if row.mjcf["hold"] is False and lint and "error" in lint_status(path):
            got = guard(row, "lint --fix, then MJCF", fixed_hold, path, tmp / "fixed", ends)
            if got is not None:
                row.mjcf["fixed_hold"], row.mjcf["fixed_line"] = got

    out = tmp / "robot.usdc"
    status, text = cli(["convert", path, *ends, "--to", "usd", "-o", str(out)])
    row.warned["USD"] = warnings_of(text)
    if status:
        row.usd["error"] = first_error(text)
    else:
        row.usd["robkin"] = guard(row, "USD read back", back, out)
        P = guard(row, "pxr FK", pxr_fk, out, robot, qs)
        if P is not None:
            row.usd["pxr"] = fk_error(P, W, size)
        row.usd["physics"] = guard(row, "UsdPhysics", usd_physics, out)

    for code in CODES:
        ext = {"rtb": "py", "matlab": "m", "eaik": "py", "opw": "yaml"}[code]
        status, text = cli(["convert", path, *ends, "--to", code, "-o", str(tmp / f"{code}.{ext}")])
        row.code[code] = "ok" if status == 0 else "refused: " + first_error(text)
    if lint:
        row.lint = lint_status(path)
    row.seconds = time.perf_counter() - t0
    return row


def fixed_hold(path: str, tmp: Path, ends: list[str]) -> tuple[bool, str] | None:
    """``robkin lint --fix`` of the source, then the same MJCF export of the fixed file: (holds home, the
    line ``robkin convert`` printed); None where the fixed file could not find the source's meshes (only
    ``package://`` names are found from elsewhere, with --package-path)."""
    if "package://" not in Path(path).read_text(errors="replace") or not robots_dir():
        return None
    tmp.mkdir(parents=True, exist_ok=True)
    fixed = tmp / Path(path).name
    cli(["lint", path, "--fix", "-o", str(fixed)])
    if not fixed.exists():
        return None
    pkg = ["--package-path", f"example-robot-data={Path(robots_dir()).parent}"]
    status, text = cli(["convert", str(fixed), *ends, "--to", "mjcf", "-o", str(tmp / "mjcf" / "robot.xml"), *pkg])
    found = HOLD.search(text)
    if status or not found:
        return None
    return found.group(1) == "holds home", next(ln.split("MuJoCo: ", 1)[1] for ln in text.splitlines()
                                                 if "MuJoCo: " in ln).split("; home")[0]


def scene_hold(path: Path):
    """The written scene (a floor, a light, the robot) pressed play: 5 s from the keyframe home, contacts on."""
    from robkin.simulation.mujoco_check import hold_check

    import mujoco

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        report = hold_check(path)
        model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    key = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_KEY, "home")
    if key >= 0:
        mujoco.mj_resetDataKeyframe(model, data, key)
    mujoco.mj_forward(model, data)
    floor = [c for c in data.contact[:data.ncon] if "floor" in (model.geom(c.geom1).name, model.geom(c.geom2).name)]
    report.floor = (len(floor), -min((c.dist for c in floor), default=0.0))
    return report


def mujoco_parity(row: Row, out: Path, robot, ref, qs, F, size) -> None:
    import mujoco

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = mujoco.MjModel.from_xml_path(str(out))
    data = mujoco.MjData(model)
    n = robot.n
    site = model.site(robot.bodies.tip).id
    T, Ms, gs = [], [], []
    for q in qs:
        data.qpos[:] = 0
        data.qpos[:n] = q
        data.qvel[:] = 0
        mujoco.mj_forward(model, data)
        M = np.zeros((model.nv, model.nv))
        mujoco.mj_fullM(model, data, M)
        Ms.append(M[:n, :n].copy())
        gs.append(data.qfrc_bias[:n].copy())
        P = np.eye(4)
        P[:3, :3], P[:3, 3] = data.site_xmat[site].reshape(3, 3), data.site_xpos[site]
        T.append(P)
    row.mjcf["fk"] = fk_error(np.array(T), F, size)
    if ref is not None:
        row.mjcf["M"] = max(rel(M, ref.mass_matrix(q)) for M, q in zip(Ms, qs))
        row.mjcf["g"] = max(rel(g, ref.gravity(q)) for g, q in zip(gs, qs))


def fmt(x) -> str:
    if x is None:
        return "—"
    if isinstance(x, str):
        return "refused" if x.startswith("refused") else x
    return "0" if x == 0 else f"{x:.0e}".replace("e-0", "e-")


def worst(values) -> float | None:
    nums = [v for v in values if isinstance(v, float)]
    return max(nums) if nums else None


def hold_cell(row: Row) -> str:
    def word(h):
        return "—" if h is None else "holds" if h else "**no**"

    return "error" if "error" in row.mjcf else f"{word(row.mjcf.get('hold'))} / {word(row.mjcf.get('scene'))}"


MIMIC = "mimics another joint"
#: convert's warnings that explain a figure, in a few words (the rest are quoted as they are)
KNOWN = [
    ("inertia not physical", "the source's inertia of {bodies} is not physical (a principal moment above the sum of "
     "the other two, or negative): clipped to the nearest valid one{why}"),
    ("move without mass or inertia", "massless moving bodies ({bodies}) given 1e-9 kg / 1e-12 kg m^2 so that MuJoCo "
     "loads the model"),
    ("move without mass: written without MassAPI", "massless links written without MassAPI values (a simulator "
     "derives them from the colliders)"),
    ("read back, its mass properties differ", None),   # the consequence of the two above, said once
    ("PhysX couples rotations only", "a prismatic mimic joint off the chain: written free, its coupling kept as "
     "robkin:mimic attributes (PhysX couples rotations only)"),
]


def _bodies(line: str) -> str:
    found = re.search(r"(?:body\(ies\)|link\(s\)) (.*?)(?::| move)", line)
    return found.group(1) if found else "some bodies"


#: the kinds of failure seen, each explained once on the page (a row's note names its kind and its figures)
REASONS = {
    "mimic": "refused by robkin, by design: a joint on the way to the tip mimics another (a coupled finger); "
             "robkin reads chains of independent joints, and its message says to end the chain before that joint",
    "finger": "the MJCF model does not hold home: the drifting joint is off the chain, a finger joint coupled to "
              "another by an equality constraint (a URDF mimic) whose bodies are massless in the source (given "
              "1e-9 kg so that MuJoCo loads them): it does not settle in 5 s. A robkin export issue, reported",
    "finger-fixed": "the MJCF model does not hold home: the drifting joint is off the chain, a finger joint "
                    "coupled to another by an equality constraint (a URDF mimic) whose links are massless in the "
                    "source (`robkin lint`: mass-zero-moving errors); `robkin convert` gives them 1e-9 kg so that "
                    "MuJoCo loads the model, and bodies that light on an equality constraint do not settle in 5 s. "
                    "The source's defect: `robkin lint --fix` gives those links their collision geometry's mass "
                    "(1000 kg/m^3), and the same export of the fixed file holds home (the row's note has both lines)",
    "texture": "the model holds still (its drift is rounding), but MuJoCo warned while decoding the source's OBJ "
               "meshes (pybullet's Panda link5.obj, link6.obj: invalid or missing face texture coordinates, "
               "discarded), and `hold_check` counts any MuJoCo warning as not holding. The source's meshes; that "
               "a texture warning fails the hold is robkin's rule, reported (whether MuJoCo warns depends on which "
               "call decodes the mesh first in a process: alone, this chain holds with no warning)",
    "xml": "the source is not XML 1.0: it declares `<?xml version=\"0.0\" ?>`, which libxml2 (lxml) refuses "
           "(`robkin lint`: unreadable); robkin's kinematic scanner reads the joints, so the chain loads, but the "
           "links' contents (masses, shapes) cannot be parsed and every conversion that needs them stops. The "
           "source's defect (write version=\"1.0\"); robkin reading the kinematics of a file it then calls "
           "malformed is reported",
    "zero-size": "the source has a visual sphere of radius 0 (`robkin lint`: geom-size); `robkin convert --to "
                 "mjcf` writes it and MuJoCo refuses the model ('size 0 must be positive in geom'). The source's "
                 "defect, and a robkin export issue (it could leave such a shape out, as it leaves unreadable "
                 "meshes out), reported",
    "floor": "the model holds home, the scene written beside it (`--scene`) does not: the scene lays its floor under "
             "the lowest link *origin* at q = 0 (`robkin.io.mjcf.scene.floor_height`), not under the robot's "
             "geometry at home, so meshes that reach below that origin (a wrist, a foot, a hand's palm) start inside "
             "the floor, which pushes them and the servos give way. A robkin scene issue, reported",
}


def failures(row: Row) -> list[str]:
    """What failed in this row: '<kind>: <figures>' for a kind of REASONS, else the failure as it is."""
    out = []
    for note in row.notes:
        joint = re.search(r"joint '([^']+)' mimics", note)
        out.append(f"mimic: joint {joint.group(1)}" if MIMIC in note and joint else note)
    for k, v in row.tables.items():
        if isinstance(v, str):
            out.append(f"{k} {v}")
    for name, d in (("URDF", row.urdf), ("MJCF", row.mjcf), ("USD", row.usd)):
        if "error" in d:
            out.append(f"{name} refused: {d['error']}")
    if row.mjcf.get("hold") is False:
        joint = row.mjcf.get("drift_joint")
        kind = "finger" if joint and joint not in row.chain_joints else "MuJoCo"
        full = row.mjcf.get("hold_line", "")
        line = full.split("; home")[0]
        warned = re.search(r"MuJoCo warnings: ([^;]*)", full)
        if warned:   # the verdict counts MuJoCo's warnings: say which
            line += f"; MuJoCo warnings: {warned.group(1)[:200]}"
            # 2e-3: hold_check's HOLD_DRIFT; below it the joints did not move, only the warning failed the hold
            if "obj_decoder" in warned.group(1) and (row.mjcf.get("drift") or 1.0) <= 2e-3:
                kind = "texture"
        if row.mjcf.get("fixed_hold"):
            kind, line = kind + "-fixed", f"{line}; after `robkin lint --fix` of the source: {row.mjcf['fixed_line']}"
        out.append(f"{kind}: {line}")
    if row.mjcf.get("scene") is False and row.mjcf.get("hold") is not False:
        count, depth = row.mjcf.get("floor", (0, 0.0))
        line = row.mjcf.get("scene_line", "").split("; home")[0]
        out.append(f"floor: the floor cuts {depth * 1e3:.2g} mm into the robot at home ({count} contacts); {line}"
                   if count else f"scene: {line}")
    if row.usd.get("physics") not in (None, "ok"):
        out.append(f"UsdPhysics: {row.usd['physics']}")
    # failures whose cause is the source file, each said once with what lint says of it
    for k, f in enumerate(out):
        if "not well-formed XML (line 1," in f:
            out[k] = "xml: " + f
        elif "size 0 must be positive in geom" in f:
            out[k] = "zero-size: " + f
    return out


def explanations(row: Row) -> list[str]:
    """Why a figure is above rounding or a format was not written, where that is by design."""
    out = list(row.info)
    for fmt_, lines in row.warned.items():
        for line in lines:
            known = next((k for k in KNOWN if k[0] in line), None)
            if known is None:
                out.append(f"{fmt_}: {line[:200]}")
            elif known[1]:
                why = ", as MuJoCo requires: that is the M, g difference" if fmt_ == "MJCF" else ""
                out.append(f"{fmt_}: " + known[1].format(bodies=_bodies(line), why=why))
    for k, v in row.code.items():
        if k != "opw" and v != "ok":
            out.append(f"{k} {v}")
    seen = set()
    return [x for x in out if not (x in seen or seen.add(x))]


def explain(row: Row) -> list[str]:
    return failures(row) + explanations(row)


def page(rows: list[Row], seconds: float, lint: bool, draws: int, command: str, cpu: float | None = None) -> str:
    import mujoco
    import pinocchio

    files = sorted({r.rel for r in rows})
    when = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    machine = f"{platform.machine()}, {cpu_name()}, {os.cpu_count()} CPUs"
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    machine += (f", run on {cores} of them (CPU affinity)" if cores != os.cpu_count() else "")
    machine += f", load average {os.getloadavg()[0]:.1f} at the end, Python {platform.python_version()}"
    try:
        import importlib.metadata as md
        erd = md.version("example-robot-data")
    except Exception:   # noqa: BLE001
        erd = "?"
    try:
        pyb = md.version("pybullet")
    except Exception:   # noqa: BLE001
        pyb = "not installed"
    out = [
        "# The robot zoo",
        "",
        f"*Generated by `{command}` ({'benchmarks/zoo.py'}) on {when}, {machine}; MuJoCo {mujoco.__version__}, "
        f"pinocchio {pinocchio.__version__}, example-robot-data {erd}, pybullet {pyb}. Do not edit: run `make zoo` "
        "again.*",
        "",
        f"{len(rows)} serial chains of {len(files)} robot files from example-robot-data (pip install "
        f"example-robot-data; {sum(not r.rel.startswith(PYBULLET) for r in rows)} chains) and pybullet's "
        f"pybullet_data (pip install pybullet; {sum(r.rel.startswith(PYBULLET) for r in rows)} chains, "
        "labelled (pybullet)): arms, grippers' fingers, hands' fingers, humanoid arms and legs, legs of "
        f"legged robots. Each is converted by `robkin convert` (default options) to every format robkin "
        f"writes, and each output is read back: by robkin, and by the format's own peer. {draws} joint "
        "vectors are drawn within the limits (fixed seed). The whole page took "
        f"{seconds:.0f} s to regenerate (wall time"
        + (f"; {cpu:.0f} s of CPU time in this process" if cpu is not None else "") + "), nothing cached.",
        "",
        "How to read it (benchmarks/zoo.py's docstring has the details):",
        "",
        "- **FK** figures: the largest difference of a rotation entry, or of a position divided by the "
        "robot's size, between the output read back and robkin's reading of the source. **M**, **g**: "
        "the largest difference of the mass matrix, the gravity torques, relative to the largest entry "
        "of pinocchio's, for the *source* URDF (the joints off the chain locked at 0).",
        "- **source**: robkin's own FK / M / g against pinocchio on the source file.",
        "- **tables**: the worst FK of dh, mdh, hayati, poe, rpy-xyz and gjd robot documents (YAML, "
        "default digits: within 1e-12 of the size by design) read back by robkin.",
        "- **URDF**: robkin read back / pinocchio's FK, M, g of the written URDF. **MJCF**: robkin read "
        "back / MuJoCo's FK (tip site), M (`mj_fullM`), g (`qfrc_bias` at rest) of the written MJCF, and "
        "**hold**: the line `robkin convert` prints after simulating its own output for 5 s from the "
        "keyframe home with contacts on (`robkin.simulation.mujoco_check.hold_check`), for the model and for "
        "the scene `--scene` writes beside it (a floor, a light). **USD**: robkin "
        "read back / pxr's FK from the joint prims (float32 numbers: ~1e-7 expected) and **physics**: "
        "usd-core's UsdPhysics parser sees one valid articulation.",
        "- **code**: the rtb, matlab, eaik, opw files written (robkin reads none back; the toolboxes are run "
        "on a few arms by the tests). OPW is one arm class, so most chains are refused it, by design; EAIK "
        "takes revolute joints only.",
        "- **notes**: failures in bold, with their reason; then the warnings `robkin convert` printed that explain "
        "a figure above rounding (MuJoCo's mass rules: the M, g differences of a few rows are the source's own "
        "unphysical or missing inertias, changed so that MuJoCo loads the model).",
        f"- **lint**: {'`robkin lint FILE --format json` on the source file (the whole file, not only the chain): ok, its warnings, or its errors' if lint else 'n/a: `robkin lint` is not on this branch'}.",
        "",
    ]
    out += summary(rows)
    out += ["", "## Every robot", "",
            "| # | robot | kind | file: base → tip | joints | source FK / M / g | tables FK | "
            "URDF robkin / pin FK / M / g | MJCF robkin / MuJoCo FK / M / g | hold | USD robkin / pxr FK | "
            "physics | code | lint | s | notes |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for i, r in enumerate(rows, 1):
        src = r.source
        code = ", ".join(k for k, v in r.code.items() if v == "ok") or "—"
        notes = "; ".join([f"**{x}**" for x in failures(r)] + explanations(r)).replace("|", "/") or "—"
        out.append(
            f"| {i} | {r.label} | {r.kind} | `{r.rel.split('/')[-1]}`: {r.base or '(root)'} → {r.tip} | "
            f"{r.n} {r.joints} | {fmt(src.get('fk'))} / {fmt(src.get('M'))} / {fmt(src.get('g'))} | "
            f"{fmt(worst(r.tables.values()))} | "
            f"{fmt(r.urdf.get('robkin'))} / {fmt(r.urdf.get('fk'))} / {fmt(r.urdf.get('M'))} / {fmt(r.urdf.get('g'))} | "
            f"{fmt(r.mjcf.get('robkin'))} / {fmt(r.mjcf.get('fk'))} / {fmt(r.mjcf.get('M'))} / {fmt(r.mjcf.get('g'))} | "
            f"{hold_cell(r)} | {fmt(r.usd.get('robkin'))} / {fmt(r.usd.get('pxr'))} | {fmt(r.usd.get('physics'))} | "
            f"{code} | {r.lint} | {r.seconds:.1f} | {notes} |")
    return "\n".join(out) + "\n"


def clean(row: Row) -> bool:
    """The MJCF carries the source's masses as they are (no inertia clipped, no placeholder mass)."""
    return not row.mjcf.get("unphysical_source") and \
        not any(k in line for line in row.warned.get("MJCF", []) for k in ("inertia not physical", "without mass"))


def summary(rows: list[Row]) -> list[str]:
    def col(get):
        vals = [(get(r), r.label) for r in rows]
        vals = [(v, label) for v, label in vals if isinstance(v, float)]
        if not vals:
            return "—", 0
        v, label = max(vals)
        return f"{fmt(v)} ({label})", len(vals)

    lines = ["## Summary", "", "| format | read back by | FK worst | M worst | g worst | chains measured |",
             "|---|---|---|---|---|---|"]
    spec = [("source", "robkin vs pinocchio", lambda r: r.source.get("fk"), lambda r: r.source.get("M"),
             lambda r: r.source.get("g"))]
    for rep in TABLES:
        spec.append((rep, "robkin", lambda r, rep=rep: r.tables.get(rep), None, None))
    spec += [("urdf", "robkin", lambda r: r.urdf.get("robkin"), None, None),
             ("urdf", "pinocchio", lambda r: r.urdf.get("fk"), lambda r: r.urdf.get("M"), lambda r: r.urdf.get("g")),
             ("mjcf", "robkin", lambda r: r.mjcf.get("robkin"), None, None),
             ("mjcf", "MuJoCo", lambda r: r.mjcf.get("fk"), lambda r: r.mjcf.get("M"), lambda r: r.mjcf.get("g")),
             ("mjcf", "MuJoCo, source masses unchanged", lambda r: r.mjcf.get("fk") if clean(r) else None,
              lambda r: r.mjcf.get("M") if clean(r) else None, lambda r: r.mjcf.get("g") if clean(r) else None),
             ("usd", "robkin", lambda r: r.usd.get("robkin"), None, None),
             ("usd", "pxr", lambda r: r.usd.get("pxr"), None, None)]
    for name, who, f, m, g in spec:
        fk, count = col(f)
        lines.append(f"| {name} | {who} | {fk} | {col(m)[0] if m else '—'} | {col(g)[0] if g else '—'} | {count} |")
    holds = sum(1 for r in rows if r.mjcf.get("hold") is True)
    scenes = sum(1 for r in rows if r.mjcf.get("scene") is True)
    scened = sum(1 for r in rows if r.mjcf.get("scene") is not None)
    measured = sum(1 for r in rows if r.mjcf.get("hold") is not None)
    loaded_mj = sum(1 for r in rows if "fk" in r.mjcf)
    loaded_pin = sum(1 for r in rows if "fk" in r.urdf)
    physics = sum(1 for r in rows if r.usd.get("physics") == "ok")
    codes = {c: sum(1 for r in rows if r.code.get(c) == "ok") for c in CODES}
    failed = [r for r in rows if failures(r)]
    explained = sum(1 for r in rows if explanations(r))
    lines += ["", f"Loads: MuJoCo loads {loaded_mj}/{len(rows)} MJCF files, pinocchio {loaded_pin}/{len(rows)} "
              f"URDF files, UsdPhysics parses {physics}/{len(rows)} USD stages as one valid articulation. "
              f"Pressing play: {holds}/{measured} MJCF exports hold home for 5 s with contacts on, and "
              f"{scenes}/{scened} of the scenes written beside them (`--scene`: a floor and a light added). Code written: "
              + ", ".join(f"{c} {k}/{len(rows)}" for c, k in codes.items())
              + f" (OPW is one class of 6R arms: the others are refused it, by design). {len(failed)} rows carry "
              f"a failure (bold in the notes, listed below), {explained} an explanation of a figure.",
              *(["", "Failures, by reason (each row's note gives its figures):", ""] if failed else [])]
    kinds: dict[str, list[str]] = {}
    for r in failed:
        for f in failures(r):
            kind = f.split(":", 1)[0]
            kinds.setdefault(kind if kind in REASONS else f, []).append(r.label)
    for kind, labels in kinds.items():
        unique = list(dict.fromkeys(labels))
        lines.append(f"- **{REASONS.get(kind, kind)}** ({len(unique)}): " + ", ".join(unique))
    return lines


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="docs/zoo.md", help="the page to write ('-': stdout)")
    parser.add_argument("--only", nargs="*", help="only the chains whose label contains one of these")
    parser.add_argument("--draws", type=int, default=5, help="joint vectors per chain (default 5)")
    args = parser.parse_args()
    root = robots_dir()
    if not root:
        print("example-robot-data is not installed (pip install example-robot-data): no zoo", file=sys.stderr)
        return 1
    chains = [c for c in CHAINS if not args.only or any(o.lower() in c[0].lower() for o in args.only)]
    if not pybullet_dir():
        skipped = [c for c in chains if c[2].startswith(PYBULLET)]
        chains = [c for c in chains if not c[2].startswith(PYBULLET)]
        if skipped:
            print(f"pybullet is not installed (pip install pybullet, or the 'zoo' extra): {len(skipped)} of its "
                  "chains left out", file=sys.stderr)
    lint = lint_available()
    rows = []
    t0, c0 = time.perf_counter(), time.process_time()
    with tempfile.TemporaryDirectory() as tmp:
        for i, (label, kind, rel_, base, tip) in enumerate(chains):
            folder = Path(tmp) / f"r{i}"
            folder.mkdir()
            row = measure(Row(label, kind, rel_, base, tip), source_path(rel_, root), folder, args.draws, lint)
            rows.append(row)
            print(f"[{i + 1}/{len(chains)}] {label}: {row.seconds:.1f} s"
                  + (f"; FAILED: {'; '.join(failures(row))[:300]}" if failures(row) else ""), file=sys.stderr)
    seconds, cpu = time.perf_counter() - t0, time.process_time() - c0
    command = "make zoo" if os.environ.get("ROBKIN_ZOO_MAKE") else "python benchmarks/zoo.py " + " ".join(sys.argv[1:])
    text = page(rows, seconds, lint, args.draws, command.strip(), cpu)
    # the page names files by their package, not by where this machine keeps them
    text = text.replace(root + "/", "example-robot-data/robots/")
    if pybullet_dir():
        text = text.replace(pybullet_dir() + "/", "pybullet_data/")
    text = re.sub(r"(?:/private)?/tmp/tmp[\w]+/r\d+/", "OUT/", text)
    if args.out == "-":
        sys.stdout.write(text)
    else:
        Path(args.out).write_text(text)
        print(f"wrote {args.out}: {len(rows)} chains in {seconds:.0f} s ({cpu:.0f} s CPU)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
