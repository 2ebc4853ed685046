"""robkin lint on real robots (example-robot-data): no errors on the arms, the warnings it finds there,
its errors where MuJoCo refuses the file (and only there), and --fix files MuJoCo and pinocchio load
with the same kinematics."""

from __future__ import annotations

import glob
import os
import sys

import numpy as np
import pytest

from robkin.lint import lint_file, lint_urdf
from robkin.lint.fix_urdf import fix_urdf
from robkin.lint.geometry import MeshCache
from robkin.lint.urdf_source import parse_urdf_text, read_urdf

ROBOTS = (glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                 "example-robot-data", "robots")) or [""])[0]

#: the arms, and the warnings lint gives on each (code, element): every one is a real defect of the file
ARMS = {
    "ur_description/urdf/ur5_robot.urdf": {  # wrists: 0.11 kg m^2 on 1.2 kg, 8x what any mass inside can have
        ("inertia-too-large", "link 'wrist_1_link'"), ("inertia-too-large", "link 'wrist_2_link'"),
        ("inertia-too-large", "link 'wrist_3_link'")},
    "panda_description/urdf/panda.urdf": {  # link1: trace 1.42 kg m^2, the geometry holds at most 0.41
        ("inertia-too-large", "link 'panda_link1'"), ("inertia-too-large", "link 'panda_link7'")},
    "kinova_description/robots/kinova.urdf": set(),
    "xarm_description/urdf/xarm7.urdf": set(),
    "z1_description/urdf/z1.urdf": set(),
    "so_arm_description/urdf/so100.urdf": {("inertia-placeholder", "link 'base'")},  # 0.01 * identity, 1 kg
    "so_arm_description/urdf/so101.urdf": set(),
    "talos_data/robots/talos_left_arm.urdf": set(),
}
#: the checks whose error means "MuJoCo refuses this file" (others: pinocchio or the physics)
MUJOCO_REFUSES = {"mass-zero-moving", "inertia-not-positive", "inertia-triangle", "inertia-singular"}
#: files MuJoCo refuses (as shipped, geometry left out) and files it takes, from both sides of the line
ORACLE = ["anymal_b_simple_description/robots/anymal.urdf", "allegro_hand_description/urdf/allegro_left_hand.urdf",
          "icub_description/robots/icub_reduced.urdf", "pr2_description/urdf/pr2.urdf",
          "romeo_description/urdf/romeo.urdf", "tiago_description/robots/tiago.urdf",
          "ur_description/urdf/ur5_robot.urdf", "panda_description/urdf/panda.urdf",
          "talos_data/robots/talos_left_arm.urdf", "so_arm_description/urdf/so101.urdf",
          "double_pendulum_description/urdf/double_pendulum.urdf", "solo_description/robots/solo.urdf"]


def _path(rel):
    path = os.path.join(ROBOTS, rel)
    if not os.path.isfile(path):
        pytest.skip(f"example-robot-data file {rel} not installed")
    return path


def _without_geometry(text: str) -> str:
    """The URDF without <visual>/<collision> (MuJoCo would look for the meshes beside the string)."""
    from lxml import etree

    root = etree.fromstring(text.split("?>", 1)[1].encode() if text.startswith("<?xml") else text.encode())
    for el in list(root.iter("visual", "collision")):
        el.getparent().remove(el)
    return etree.tostring(root, encoding="unicode")


@pytest.mark.parametrize("rel", sorted(ARMS))
def test_arms_no_errors_and_known_warnings(rel):
    found = lint_file(_path(rel))
    assert [f for f in found if f.severity == "error"] == []
    assert {(f.code, f.element) for f in found if f.severity == "warning"} == ARMS[rel]


@pytest.mark.parametrize("rel", ORACLE)
def test_errors_where_mujoco_refuses(rel):
    mujoco = pytest.importorskip("mujoco")
    path = _path(rel)
    with open(path) as fh:
        xml = _without_geometry(fh.read())
    try:
        mujoco.MjModel.from_xml_string(xml)
        refused = None
    except ValueError as exc:
        refused = str(exc)
    errors = {f.code for f in lint_file(path) if f.severity == "error"} & MUJOCO_REFUSES
    assert bool(errors) == bool(refused), (errors, refused)


@pytest.mark.parametrize("rel", ["anymal_b_simple_description/robots/anymal.urdf", "pr2_description/urdf/pr2.urdf",
                                 "allegro_hand_description/urdf/allegro_left_hand.urdf"])
def test_fix_real_files(rel):
    mujoco = pytest.importorskip("mujoco")
    pin = pytest.importorskip("pinocchio")
    path = _path(rel)
    found = lint_file(path)
    assert any(f.code in MUJOCO_REFUSES for f in found)
    text, changes = fix_urdf(read_urdf(path), found, meshes=MeshCache(path))
    assert [f for f in lint_urdf(parse_urdf_text(text, "fixed"), mesh_base=path) if f.severity == "error"] == []
    mujoco.MjModel.from_xml_string(_without_geometry(text))
    with open(path) as fh:
        before = pin.buildModelFromXML(_without_geometry(fh.read()))
    after = pin.buildModelFromXML(_without_geometry(text))
    assert before.nq == after.nq and [f.name for f in before.frames] == [f.name for f in after.frames]
    db, da = before.createData(), after.createData()
    for _ in range(5):
        q = pin.randomConfiguration(before, -np.ones(before.nq), np.ones(before.nq)) if before.nq else np.zeros(0)
        pin.framesForwardKinematics(before, db, q)
        pin.framesForwardKinematics(after, da, q)
        for a, b in zip(db.oMf, da.oMf):
            assert np.array_equal(a.homogeneous, b.homogeneous)
    assert all(": " in c for c in changes) and len(changes) >= 1
