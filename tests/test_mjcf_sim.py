"""The whole robot, proved: ``robkin convert X.urdf --to mjcf`` writes a model MuJoCo simulates with the
source's dynamics, on real chains with meshes and inertials.

References: pinocchio's ``crba`` and generalized gravity of the *source URDF*, with the joints off the
chain locked at 0 (``buildReducedModel``, the ``Pin`` helper of test_dynamics), and its forward
kinematics of the tip frame. Each model is converted once by the CLI (meshes copied beside it), the
output folder moved elsewhere, and loaded by MuJoCo from there: MuJoCo's ``mj_fullM`` and ``qfrc_bias``
at zero velocity, its site at the tip, its total mass, actuators and collision geoms are compared. The
same parity is shown for robkin's URDF export and for MJCF -> URDF (the MJCF read back by robkin and
written as URDF), both read by pinocchio.
"""

from __future__ import annotations

import shutil
import warnings
from pathlib import Path

import numpy as np
import pytest

import robkin
from robkin.cli import main
from test_dynamics import Pin
from test_urdf import robot_file

mujoco = pytest.importorskip("mujoco")
pin = pytest.importorskip("pinocchio")

#: (file under example-robot-data/robots, base link, tip link): arms, arms with grippers, humanoid arms and
#: legs (base mid-tree), quadruped legs, mobile manipulators, a hand's finger.
CASES = [
    ("ur_description/urdf/ur3_robot.urdf", None, "tool0"),
    ("ur_description/urdf/ur5_robot.urdf", None, "tool0"),
    ("ur_description/urdf/ur10_robot.urdf", None, "ee_link"),
    ("panda_description/urdf/panda.urdf", None, "panda_hand_tcp"),
    ("panda_description/urdf/panda.urdf", "panda_link0", "panda_leftfinger"),
    ("kinova_description/robots/kinova.urdf", None, "j2s6s200_end_effector"),
    ("xarm_description/urdf/xarm7.urdf", None, None),
    ("z1_description/urdf/z1.urdf", None, "gripperMover"),
    ("so_arm_description/urdf/so100.urdf", None, None),
    ("so_arm_description/urdf/so101.urdf", None, "gripper_frame_link"),
    ("talos_data/robots/talos_full_v2.urdf", "torso_2_link", "gripper_left_base_link"),
    ("talos_data/robots/talos_full_v2.urdf", "base_link", "left_sole_link"),
    ("solo_description/robots/solo12.urdf", None, "FL_FOOT"),
    ("go2_description/urdf/go2.urdf", None, "FL_foot"),
    ("a1_description/urdf/a1.urdf", None, "FR_foot"),
    ("baxter_description/urdf/baxter.urdf", None, "right_gripper"),
    ("tiago_description/robots/tiago.urdf", None, "hand_tool_link"),
    ("g1_description/urdf/g1_29dof_rev_1_0.urdf", None, "left_ankle_roll_link"),
    ("romeo_description/urdf/romeo.urdf", None, "l_sole"),
    ("pr2_description/urdf/pr2.urdf", None, "r_gripper_tool_frame"),
]

#: Files whose mesh files robkin's resolver cannot find (none now; talos' 'package:///...' resolves):
#: their collision meshes would be left out, with a warning, and counted out below.
UNRESOLVED: set[str] = set()

#: Agreement with pinocchio, relative to the largest entry (the issue's promise). Observed ~1e-15: the
#: same sums in another order, and MuJoCo's principal-axis inertia (an eigen-decomposition) read back.
REL_TOL = 1e-9
#: FK agreement, rotation entries and lengths relative to the robot's size (the promise).
FK_TOL = 1e-9
#: what is observed on these chains (this machine, 2026-11-28): M(q) 2.6e-15, g(q) 2.2e-15, MuJoCo's bias
#: forces of the MJCF written again 3.7e-15, the URDF exports' M(q) and g(q) 2.3e-15 of the largest
#: entry, FK 1.8e-15; 1e-14 is 2.7-5.5x that (fixed data; another CPU, BLAS or MuJoCo build rounds
#: differently), so that a regression far below the promise still fails.
ROUNDING_REL = 1e-14


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    """|a - b| relative to b's largest entry; the promise (REL_TOL) asserted here, the caller checks
    the rounding level observed (ROUNDING_REL)."""
    rel = float(np.abs(a - b).max() / max(np.abs(b).max(), 1e-300))
    assert rel <= REL_TOL, f"the promise: {rel:.3g}"
    return rel


def _sample(robot, count: int = 3) -> np.ndarray:
    return np.random.default_rng(7).uniform(-1.5, 1.5, (count, robot.n))


@pytest.fixture(scope="module", params=CASES, ids=lambda c: f"{c[0].split('/')[-1]}:{c[2]}")
def converted(request, tmp_path_factory):
    """(robot, pinocchio reference, MuJoCo model loaded from a moved copy of the output folder, its path,
    the source path)."""
    rel, base, tip = request.param
    path = robot_file(rel)
    folder = tmp_path_factory.mktemp("mjcf")
    argv = ["convert", path, "--to", "mjcf", "-o", str(folder / "made" / "robot.xml")]
    argv += ["--base-link", base] if base else []
    argv += ["--tip-link", tip] if tip else []
    (folder / "made").mkdir()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")   # nearly parallel axes, joints above a mid-tree base held at 0
        assert main(argv) == 0
        robot = robkin.load(path, base_link=base, tip_link=tip)
    moved = folder / "elsewhere"
    shutil.move(str(folder / "made"), str(moved))
    model = mujoco.MjModel.from_xml_path(str(moved / "robot.xml"))
    return robot, Pin(path, robot), model, moved / "robot.xml", path


def test_fk_mass_matrix_and_gravity_equal_pinocchios(converted):
    robot, ref, model, _, _ = converted
    data = mujoco.MjData(model)
    n = robot.n
    assert [model.joint(i).name for i in range(n)] == [j.name for j in robot.joints]  # qpos[:n] = q
    site = model.site(robot.bodies.tip).id
    for q in _sample(robot):
        data.qpos[:] = 0
        data.qpos[:n] = q
        data.qvel[:] = 0
        mujoco.mj_forward(model, data)
        M = np.zeros((model.nv, model.nv))
        mujoco.mj_fullM(model, data, M)
        assert _rel(M[:n, :n], ref.mass_matrix(q)) <= ROUNDING_REL
        assert _rel(data.qfrc_bias[:n], ref.gravity(q)) <= ROUNDING_REL   # zero velocity: gravity only
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = data.site_xmat[site].reshape(3, 3), data.site_xpos[site]
        pq = ref.q(q)
        pin.framesForwardKinematics(ref.model, ref.data, pq)
        P = ref.data.oMf[ref.model.getFrameId(robot.bodies.tip)].homogeneous
        size = max(robot.scale, float(np.abs(P[:3, 3]).max()))
        for tol in (FK_TOL, ROUNDING_REL):          # the promise, and the rounding level observed
            np.testing.assert_allclose(T[:3, :3], P[:3, :3], atol=tol, rtol=0)
            np.testing.assert_allclose(T[:3, 3], P[:3, 3], atol=tol * size, rtol=0)


def test_total_mass_actuators_and_collision_geoms(converted):
    robot, ref, model, _, path = converted
    total = sum(ref.full.inertias[i].mass for i in range(ref.full.njoints))
    assert abs(model.body_mass.sum() - total) <= REL_TOL * total
    driven = {model.joint(model.actuator_trnid[a, 0]).name for a in range(model.nu)}
    assert {j.name for j in robot.joints} <= driven
    from robkin.io.meshes.files import resolve_meshes

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        found = {k for k, m in resolve_meshes(robot, path).items() if m.path is not None}
    collisions = [s for s in robot.bodies.shapes if s.role == "collision"]
    lost = [s for s in collisions if s.geometry.kind == "mesh" and s.geometry.filename not in found]
    assert not lost or Path(path).name in UNRESOLVED
    assert int((model.geom_group == 3).sum()) == len(collisions) - len(lost)
    assert int((model.geom_group == 2).sum()) >= 1   # something to see


def test_urdf_export_mjcf_to_urdf_and_mjcf_to_mjcf_keep_the_dynamics(converted, tmp_path):
    """robkin's URDF of the source, and the URDF of robkin's MJCF read back by robkin: pinocchio's M(q),
    g(q) equal those of the source; and that MJCF read back and written again as MJCF: MuJoCo's equal
    those of the first."""
    from robkin.io.mjcf import mjcf_from_robot
    from robkin.io.urdf import urdf_from_robot

    robot, ref, _, mjcf, _ = converted
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        back = robkin.load(mjcf, base_link=robot.bodies.chain[0], tip_link=robot.bodies.tip)
    for label, r in (("urdf", robot), ("mjcf-urdf", back)):
        file = tmp_path / f"{label}.urdf"
        file.write_text(urdf_from_robot(r))
        other = Pin(str(file), robot)
        for q in _sample(robot, 2):
            assert _rel(other.mass_matrix(q), ref.mass_matrix(q)) <= ROUNDING_REL, label
            assert _rel(other.gravity(q), ref.gravity(q)) <= ROUNDING_REL, label
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        again = mujoco.MjModel.from_xml_string(mjcf_from_robot(back, mesh_files={}))
    first = converted[2]
    assert [again.body(i).name for i in range(again.nbody)] == [first.body(i).name for i in range(first.nbody)]
    np.testing.assert_allclose(again.body_mass, first.body_mass, rtol=REL_TOL, atol=0)
    for model in (first, again):
        assert model.nq == first.nq and model.nu == first.nu and model.neq == first.neq
    d1, d2 = mujoco.MjData(first), mujoco.MjData(again)
    for q in _sample(robot, 2):
        for m, d in ((first, d1), (again, d2)):
            d.qpos[:] = 0
            d.qpos[:robot.n] = q
            mujoco.mj_forward(m, d)
        assert _rel(d2.qfrc_bias, d1.qfrc_bias) <= ROUNDING_REL
