"""The default MJCF export starts at rest: no penetrating contact at ``home`` (q = 0 clipped into the
limits) on the arms of the simulation-grade issue, MuJoCo the oracle (``mj_forward``, ``data.contact``
with a negative distance), with the model loaded from a copy of the output folder moved elsewhere."""

from __future__ import annotations

import shutil
import warnings

import pytest

from robkin.cli import main
from test_collision_modes import penetrating
from test_mjcf_sim import CASES
from test_urdf import robot_file

mujoco = pytest.importorskip("mujoco")

#: Panda, UR5, UR10, Kinova, xArm7, Z1, SO-100 and the arms of Baxter, TIAGo and Talos (CASES' entries).
ARMS = [c for c in CASES if (c[0].split("/")[-1], c[2]) in {
    ("panda.urdf", "panda_hand_tcp"), ("ur5_robot.urdf", "tool0"), ("ur10_robot.urdf", "ee_link"),
    ("kinova.urdf", "j2s6s200_end_effector"), ("xarm7.urdf", None), ("z1.urdf", "gripperMover"),
    ("so100.urdf", None), ("baxter.urdf", "right_gripper"), ("tiago.urdf", "hand_tool_link"),
    ("talos_full_v2.urdf", "gripper_left_base_link")}]


def test_the_list_is_the_issues():
    assert len(ARMS) == 10


@pytest.mark.parametrize("case", ARMS, ids=lambda c: f"{c[0].split('/')[-1]}:{c[2]}")
def test_no_penetrating_contact_at_home(case, tmp_path):
    rel, base, tip = case
    argv = ["convert", robot_file(rel), "--to", "mjcf", "-o", str(tmp_path / "made" / "robot.xml")]
    argv += ["--base-link", base] if base else []
    argv += ["--tip-link", tip] if tip else []
    (tmp_path / "made").mkdir()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(argv) == 0
    shutil.move(str(tmp_path / "made"), str(tmp_path / "elsewhere"))
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "elsewhere" / "robot.xml"))
    assert int((model.geom_group == 3).sum()) > 0          # collision geoms are there, and collide
    assert penetrating(model) == []
