"""USD out and in: ``robkin convert --to usd`` writes a UsdPhysics articulation, proved with usd-core (pxr)
as the independent reader, and ``robkin check`` / ``robkin.load`` read it back.

The oracle is pxr itself: FK computed here from the joint prims' own frames (``physics:localPos0/1``,
``localRot0/1``, ``physics:axis``, ``body0``/``body1``) with Gf matrices, and every link's mass properties
from ``UsdPhysics.MassAPI``, against the source URDF (robkin's reading of it, world in front). USD stores
those numbers as float32; the figures observed are in ``FLOAT32_FK`` and ``FLOAT32_MASS``.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import robkin
from robkin.cli import main
from test_urdf import robot_file

pxr = pytest.importorskip("pxr")
from pxr import Gf, Usd, UsdGeom, UsdPhysics  # noqa: E402

#: (file under example-robot-data/robots, base link, tip link, suffix): the arms of the issue (the
#: CASES of test_mjcf_sim), written as text or crate.
CASES = [
    ("panda_description/urdf/panda.urdf", None, "panda_hand_tcp", ".usda"),
    ("ur_description/urdf/ur5_robot.urdf", None, "tool0", ".usdc"),
    ("ur_description/urdf/ur10_robot.urdf", None, "ee_link", ".usd"),
    ("kinova_description/robots/kinova.urdf", None, "j2s6s200_end_effector", ".usdc"),
    ("xarm_description/urdf/xarm7.urdf", None, None, ".usdc"),
    ("z1_description/urdf/z1.urdf", None, "gripperMover", ".usdc"),
    ("so_arm_description/urdf/so100.urdf", None, None, ".usda"),
    ("baxter_description/urdf/baxter.urdf", None, "right_gripper", ".usdc"),
    ("tiago_description/robots/tiago.urdf", None, "hand_tool_link", ".usdc"),
    ("talos_data/robots/talos_full_v2.urdf", "torso_2_link", "gripper_left_base_link", ".usdc"),
]
#: FK from the USD joint frames against the source, rotation entries and lengths relative to the robot's
#: size: float32 joint frames (~6e-8 relative rounding per number) composed along the chain. Observed on
#: these arms (this machine, 2026-11-28): 8.0e-9 (Baxter) .. 7.6e-8 (xArm7); robkin's check tolerance is
#: 1e-6 (7 significant digits); 5e-7 is 6.6x the worst seen.
FLOAT32_FK = 5e-7
#: mass (relative), centre of mass (relative to the robot's size) and inertia (relative to the link's
#: largest entry) from MassAPI against the source: float32 numbers, the principal axes a float32
#: quaternion. Observed at most 5.4e-8 (mass 5.2e-8, centre 2.3e-8, inertia 5.4e-8).
FLOAT32_MASS = 5e-7


def _ends(base, tip):
    return ["--base-link", base] * bool(base) + ["--tip-link", tip] * bool(tip)


@pytest.fixture(scope="module", params=CASES, ids=lambda c: f"{c[0].split('/')[-1]}:{c[2]}{c[3]}")
def written(request, tmp_path_factory):
    """(source path, robot read from it, USD path written by the CLI, base, tip)."""
    rel, base, tip, suffix = request.param
    path = robot_file(rel)
    out = tmp_path_factory.mktemp("usd") / f"robot{suffix}"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["convert", path, "--to", "usd", "-o", str(out), *_ends(base, tip)]) == 0
        robot = robkin.load(path, base_link=base, tip_link=tip)
    return path, robot, out, base, tip


def _gf(pos, rot) -> np.ndarray:
    """A pose (4, 4, column vectors) from a float3 and a quatf, through Gf (double)."""
    # SetRotate from the quaternion: Gf.Rotation(quat) goes through axis and angle and loses ~1.5e-6
    m = Gf.Matrix4d().SetRotate(Gf.Quatd(rot).GetNormalized()).SetTranslateOnly(Gf.Vec3d(pos))
    return np.array(m).T


def _motion(joint, q: float) -> np.ndarray:
    axis = {"X": Gf.Vec3d(1, 0, 0), "Y": Gf.Vec3d(0, 1, 0), "Z": Gf.Vec3d(0, 0, 1)}[joint.GetAxisAttr().Get()]
    if joint.GetPrim().IsA(UsdPhysics.RevoluteJoint):
        return np.array(Gf.Matrix4d().SetRotate(Gf.Quatd(math.cos(q / 2), axis * math.sin(q / 2)))).T
    return np.array(Gf.Matrix4d().SetTranslate(axis * q)).T


def _name(prim) -> str:
    attr = prim.GetAttribute("robkin:name")
    return attr.Get() if attr and attr.HasAuthoredValue() else prim.GetName()


class Oracle:
    """FK of a USD articulation computed from its joint prims with pxr (robkin takes no part)."""

    def __init__(self, path) -> None:
        self.stage = Usd.Stage.Open(str(path))
        self.cache = UsdGeom.XformCache()
        self.joints = [p for p in self.stage.Traverse() if p.IsA(UsdPhysics.Joint)]
        self.bodies = {p.GetPath(): p for p in self.stage.Traverse() if p.HasAPI(UsdPhysics.RigidBodyAPI)}
        self.by_child = {}
        for p in self.joints:
            j = UsdPhysics.Joint(p)
            self.by_child[j.GetBody1Rel().GetTargets()[0]] = p

    def body_pose(self, path, q: dict[str, float]) -> np.ndarray:
        """World pose of a rigid body at q (joints not in q at 0)."""
        p = self.by_child[path]
        j = UsdPhysics.Joint(p)
        J0 = _gf(j.GetLocalPos0Attr().Get(), j.GetLocalRot0Attr().Get())
        J1 = _gf(j.GetLocalPos1Attr().Get(), j.GetLocalRot1Attr().Get())
        targets = j.GetBody0Rel().GetTargets()
        parent = np.eye(4) if not targets else self.body_pose(targets[0], q)
        move = np.eye(4)
        if p.IsA(UsdPhysics.RevoluteJoint):
            move = _motion(UsdPhysics.RevoluteJoint(p), q.get(_name(p), 0.0))
        elif p.IsA(UsdPhysics.PrismaticJoint):
            move = _motion(UsdPhysics.PrismaticJoint(p), q.get(_name(p), 0.0))
        return parent @ J0 @ move @ np.linalg.inv(J1)

    def link_pose(self, name: str, q: dict[str, float]) -> np.ndarray:
        """World pose at q of the link called ``name`` (a rigid body, or a frame prim inside one)."""
        prim = next(p for p in self.stage.Traverse() if _name(p) == name and p.GetTypeName() == "Xform")
        body = prim
        while body.GetPath() not in self.bodies:
            body = body.GetParent()
        # Gf composes row vectors: prim-to-world * world-to-body is the prim's pose in the body's frame
        rel = self.cache.GetLocalToWorldTransform(prim) * self.cache.GetLocalToWorldTransform(body).GetInverse()
        return self.body_pose(body.GetPath(), q) @ np.array(rel).T


def test_stage_is_an_articulation(written):
    _, robot, out, _, _ = written
    stage = Usd.Stage.Open(str(out))
    assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.z
    assert UsdGeom.GetStageMetersPerUnit(stage) == 1.0
    assert UsdPhysics.GetStageKilogramsPerUnit(stage) == 1.0
    root = stage.GetDefaultPrim()
    assert root and root.HasAPI(UsdPhysics.ArticulationRootAPI)
    joints = {_name(p): p for p in stage.Traverse() if p.IsA(UsdPhysics.Joint)}
    for j in robot.joints:  # every chain joint, its type, limits in degrees or metres, a drive with its effort
        p = joints[j.name]
        revolute = p.IsA(UsdPhysics.RevoluteJoint)
        assert revolute == (j.type == "revolute") and (revolute or p.IsA(UsdPhysics.PrismaticJoint))
        unit = 180 / math.pi if revolute else 1.0
        if j.lower is not None:
            assert p.GetAttribute("physics:lowerLimit").Get() == pytest.approx(j.lower * unit, rel=1e-6, abs=1e-6)
        drive = UsdPhysics.DriveAPI(p, "angular" if revolute else "linear")
        if j.effort:
            assert drive.GetMaxForceAttr().Get() == pytest.approx(j.effort, rel=1e-7)
        if j.velocity:  # PhysX's velocity limit, deg/s (its schema is not usd-core's: read by name)
            assert p.GetAttribute("physxJoint:maxJointVelocity").Get() == pytest.approx(j.velocity * unit, rel=1e-7)
    # no rigid body nested in another (PhysX refuses that)
    bodies = [p for p in stage.Traverse() if p.HasAPI(UsdPhysics.RigidBodyAPI)]
    for b in bodies:
        parent = b.GetParent()
        while parent:
            assert not parent.HasAPI(UsdPhysics.RigidBodyAPI), f"{b.GetPath()} is inside a rigid body"
            parent = parent.GetParent()


def test_drives_are_the_servo_plans(written):
    """convert --to usd drives every actuated joint with the MJCF export's default servo gains
    (robkin.simulation.servo_plan: stiffness and damping per degree for revolute joints, maxForce the
    effort) towards home, and compensates gravity as Isaac Lab does (disableGravity on every body)."""
    from robkin.simulation import servo_plan

    _, robot, out, _, _ = written
    plan = servo_plan(robot)
    stage = Usd.Stage.Open(str(out))
    joints = {_name(p): p for p in stage.Traverse() if p.IsA(UsdPhysics.Joint)}
    checked = 0
    for s in plan.actuated():
        p = joints[s.name]
        revolute = p.IsA(UsdPhysics.RevoluteJoint)
        per = math.pi / 180 if revolute else 1.0  # N m/rad -> N m/deg
        drive = UsdPhysics.DriveAPI(p, "angular" if revolute else "linear")
        # float32 attributes: 6e-8 relative rounding
        assert drive.GetStiffnessAttr().Get() == pytest.approx(s.kp * per, rel=1e-6)
        assert drive.GetDampingAttr().Get() == pytest.approx(s.kv * per, rel=1e-6)
        assert drive.GetTargetPositionAttr().Get() == pytest.approx(s.home / per, rel=1e-6, abs=1e-6)
        assert s.kp > 0
        checked += 1
    assert checked >= robot.n
    bodies = [p for p in stage.Traverse() if p.HasAPI(UsdPhysics.RigidBodyAPI)]
    assert bodies and all(p.GetAttribute("physxRigidBody:disableGravity").Get() is True for p in bodies)


def test_fk_from_the_joint_prims(written):
    """FK at 10 configurations from pxr's own reading of the joints equals the source's."""
    _, robot, out, _, _ = written
    oracle = Oracle(out)
    tip = robot.bodies.tip
    rng = np.random.default_rng(5)
    lim = np.nan_to_num(robot.limits, nan=0.0, posinf=math.pi, neginf=-math.pi)
    worst = 0.0
    for q in rng.uniform(lim[:, 0], lim[:, 1], size=(10, robot.n)):
        want = robot.world @ robot.fk(q)
        got = oracle.link_pose(tip, {j.name: float(v) for j, v in zip(robot.joints, q)})
        err = max(np.abs(got[:3, :3] - want[:3, :3]).max(), np.abs(got[:3, 3] - want[:3, 3]).max() / robot.scale)
        worst = max(worst, err)
    assert worst <= FLOAT32_FK, worst
    assert worst > 0 or robot.n == 0  # float32 frames: exact equality would mean the test compares robkin to itself


def test_mass_properties_from_massapi(written):
    """Every link's mass, centre of mass and inertia (MassAPI, in its prim's frame) equal the source's."""
    _, robot, out, _, _ = written
    stage = Usd.Stage.Open(str(out))
    cache = UsdGeom.XformCache()
    links = {link.name: link for link in robot.bodies.links}
    prims = {_name(p): p for p in stage.Traverse() if p.HasAPI(UsdPhysics.MassAPI)}
    checked = 0
    for m in robot.bodies.inertials:
        if m.mass <= 0:
            continue
        prim = prims[m.link]
        api = UsdPhysics.MassAPI(prim)
        world_prim = np.array(cache.GetLocalToWorldTransform(prim)).T
        link_pose = robot.world @ links[m.link].pose
        # the body's frame, in double precision: the writer's plan (the MJCF export's) places links from the
        # chain's frames, 1e-11 from the reader's link poses on Talos' mid-tree chain
        assert np.abs(world_prim - link_pose).max() <= 1e-9 * robot.scale
        L = np.linalg.inv(links[m.link].pose) @ m.pose  # the source's inertial frame in the link's
        com_want, I_want = L[:3, 3], L[:3, :3] @ m.inertia @ L[:3, :3].T
        R = np.array(Gf.Matrix3d().SetRotate(Gf.Quatd(api.GetPrincipalAxesAttr().Get()).GetNormalized())).T
        I_got = R @ np.diag(list(api.GetDiagonalInertiaAttr().Get())) @ R.T
        assert abs(api.GetMassAttr().Get() - m.mass) <= FLOAT32_MASS * m.mass
        assert np.abs(np.array(api.GetCenterOfMassAttr().Get()) - com_want).max() <= FLOAT32_MASS * robot.scale
        moments = np.linalg.eigvalsh(I_want)
        if moments.min() >= 0 and moments.max() <= moments.sum() - moments.max():  # physical (else repaired)
            assert np.abs(I_got - I_want).max() <= FLOAT32_MASS * max(np.abs(I_want).max(), 1e-12), m.link
        checked += 1
    assert checked > 0


def test_check_reads_it_back(written, capsys):
    path, robot, out, base, tip = written
    assert main(["check", path, str(out), *_ends(base, tip)]) == 0
    back = robkin.load(out, base_link=base, tip_link=tip)
    assert [j.name for j in back.joints] == [j.name for j in robot.joints]
    assert [(j.lower, j.upper) for j in back.joints] == [(j.lower, j.upper) for j in robot.joints]  # robkin:lower/upper
    assert len(back.bodies.collisions()) == len(robot.bodies.collisions())


# ---------------------------------------------------------------- what the writer does, one thing at a time
from hypothesis import given, settings  # noqa: E402

from robkin.io.usd.writer import usd_from_robot, usd_stage  # noqa: E402
from strategies import robots  # noqa: E402


def _stage_of(text: str):
    layer = pxr.Sdf.Layer.CreateAnonymous(".usda")
    layer.ImportFromString(text)
    return Usd.Stage.Open(layer), layer


def _read(tmp_path, text: str, name: str = "r.usda", **chain):
    path = tmp_path / name
    path.write_text(text)
    return robkin.load(path, **chain)


@pytest.mark.filterwarnings("ignore::UserWarning")
@pytest.mark.filterwarnings("ignore::robkin.ConditioningWarning")
@settings(max_examples=25, deadline=None)
@given(robot=robots(max_joints=7))
def test_any_robot_goes_through_usd(robot, tmp_path_factory):
    """Random robots (every axis relation, prismatic joints, a world transform) come back with FK
    within float32 rounding, the same joint names, types and limits (robkin's own double record)."""
    back = _read(tmp_path_factory.mktemp("any"), usd_from_robot(robot), tip_link="tool")
    tol = FLOAT32_FK * max(1.0, robot.scale)
    for q in np.random.default_rng(0).uniform(-1, 1, (4, robot.n)):
        np.testing.assert_allclose(back.fk(q), robot.fk(q), atol=tol, rtol=0)
    assert [(j.name, j.type) for j in back.joints] == [(j.name, j.type) for j in robot.joints]
    np.testing.assert_array_equal(back.limits, robot.limits)


URDF = """<robot name="r">
  <link name="base"/><link name="l 1"><inertial><mass value="1"/><inertia ixx="1e-3" iyy="2e-3" izz="3e-3" ixy="0"
  ixz="0" iyz="0"/></inertial></link><link name="2nd-link"><inertial><mass value="1"/><inertia ixx="1e-3"
  iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial>
  <visual><origin xyz="0.1 0 0" rpy="0.3 0 0"/><geometry><box size="0.1 0.2 0.3"/></geometry></visual>
  <collision><origin xyz="0 0.1 0" rpy="0 0.2 0"/><geometry><cylinder radius="0.05" length="0.4"/></geometry></collision>
  <collision><geometry><sphere radius="0.07"/></geometry></collision></link>
  <link name="ünï"/><link name="finger"><inertial><mass value="0.1"/><inertia ixx="1e-5" iyy="1e-5" izz="1e-5" ixy="0"
  ixz="0" iyz="0"/></inertial></link><link name="finger2"><inertial><mass value="0.1"/><inertia ixx="1e-5"
  iyy="1e-5" izz="1e-5" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="joint 1" type="revolute"><parent link="base"/><child link="l 1"/><origin xyz="0 0 0.3"/>
    <axis xyz="0.6 0 0.8"/><limit lower="0.5" upper="2" effort="40" velocity="1"/></joint>
  <joint name="2" type="prismatic"><parent link="l 1"/><child link="2nd-link"/><origin xyz="0.2 0 0" rpy="0.1 0.2 0.3"/>
    <axis xyz="0 0 -1"/><limit lower="-0.1" upper="0.2" effort="100" velocity="1"/></joint>
  <joint name="tip" type="fixed"><parent link="2nd-link"/><child link="ünï"/><origin xyz="0 0 0.1"/></joint>
  <joint name="f1" type="revolute"><parent link="2nd-link"/><child link="finger"/><origin xyz="0 0.05 0"/>
    <axis xyz="1 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="f2" type="revolute"><parent link="2nd-link"/><child link="finger2"/><origin xyz="0 -0.05 0"/>
    <axis xyz="1 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/><mimic joint="f1" multiplier="-1"
    offset="0.1"/></joint>
</robot>"""


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    """(robot from URDF, its USD text, the stage) of a robot with odd names, an arbitrary and a negative
    axis, primitives and a mimic joint."""
    folder = tmp_path_factory.mktemp("small")
    (folder / "r.urdf").write_text(URDF)
    robot = robkin.load(folder / "r.urdf", tip_link="ünï")
    text = usd_from_robot(robot, drives={"joint 1": (100.0, 10.0, 50.0), "2": (1000.0, 20.0, None)})
    stage, layer = _stage_of(text)
    return robot, text, stage, layer


def _joint(stage, name):
    return next(p for p in stage.Traverse() if p.IsA(UsdPhysics.Joint) and _name(p) == name)


def test_names_become_identifiers_and_come_back(small, tmp_path):
    robot, text, stage, _ = small
    for p in stage.Traverse():
        assert pxr.Sdf.Path.IsValidIdentifier(p.GetName())
    back = _read(tmp_path, text, tip_link="ünï")
    assert [j.name for j in back.joints] == ["joint 1", "2"]
    assert {link.name for link in back.bodies.links} >= {"base", "l 1", "2nd-link", "ünï", "finger", "finger2"}


def test_drive_gains_are_per_degree(small):
    """SI gains in, USD's units out: N m/deg for an angular drive, N/m for a linear one; home in limits."""
    _, _, stage, _ = small
    angular = UsdPhysics.DriveAPI(_joint(stage, "joint 1"), "angular")
    assert angular.GetStiffnessAttr().Get() == pytest.approx(100.0 * math.pi / 180, rel=1e-7)
    assert angular.GetDampingAttr().Get() == pytest.approx(10.0 * math.pi / 180, rel=1e-7)
    assert angular.GetMaxForceAttr().Get() == 50.0
    assert angular.GetTargetPositionAttr().Get() == pytest.approx(math.degrees(0.5), rel=1e-7)  # 0 clipped to lower
    linear = UsdPhysics.DriveAPI(_joint(stage, "2"), "linear")
    assert (linear.GetStiffnessAttr().Get(), linear.GetDampingAttr().Get(), linear.GetMaxForceAttr().Get()) == \
        (1000.0, 20.0, 100.0)  # the effort where no force is given
    finger = UsdPhysics.DriveAPI(_joint(stage, "f1"), "angular")
    assert finger.GetStiffnessAttr().Get() == 0.0 and finger.GetMaxForceAttr().Get() == 1.0  # effort only


def test_axes_map_onto_x_y_z(small):
    """An arbitrary axis is X of a turned joint frame; -z is Z of a frame turned by a half turn."""
    robot, _, stage, _ = small
    j1 = UsdPhysics.RevoluteJoint(_joint(stage, "joint 1"))
    assert j1.GetAxisAttr().Get() == "X"
    R1 = np.array(Gf.Matrix3d().SetRotate(Gf.Quatd(j1.GetLocalRot1Attr().Get()))).T
    np.testing.assert_allclose(R1[:, 0], [0.6, 0, 0.8], atol=1e-7)
    j2 = UsdPhysics.PrismaticJoint(_joint(stage, "2"))
    assert j2.GetAxisAttr().Get() == "Z"
    R2 = np.array(Gf.Matrix3d().SetRotate(Gf.Quatd(j2.GetLocalRot1Attr().Get()))).T
    np.testing.assert_array_equal(R2[:, 2], [0, 0, -1])


def test_mimic_is_physx_coupling_and_robkin_record(small, tmp_path):
    robot, text, stage, _ = small
    f2 = _joint(stage, "f2")
    assert "PhysxMimicJointAPI:rotX" in f2.GetMetadata("apiSchemas").ApplyOperations([])  # not a usd-core schema
    assert f2.GetRelationship("physxMimicJoint:rotX:referenceJoint").GetTargets() == [_joint(stage, "f1").GetPath()]
    assert f2.GetAttribute("physxMimicJoint:rotX:gearing").Get() == 1.0  # q + gearing q_ref + offset = 0
    assert f2.GetAttribute("physxMimicJoint:rotX:offset").Get() == pytest.approx(-0.1)
    assert not f2.HasAPI(UsdPhysics.DriveAPI, "angular")
    back = _read(tmp_path, text, tip_link="ünï")
    mimic = next(link.joint.mimic for link in back.bodies.links if link.name == "finger2")
    assert (mimic.joint, mimic.multiplier, mimic.offset) == ("f1", -1.0, 0.1)


def test_primitives_and_welded_frames(small, tmp_path):
    """Box, cylinder and sphere come back with their sizes and poses (double precision); the massless
    fixed tip link is a frame inside its parent, not a rigid body."""
    robot, text, stage, _ = small
    tip = next(p for p in stage.Traverse() if _name(p) == "ünï")
    assert not tip.HasAPI(UsdPhysics.RigidBodyAPI) and tip.GetAttribute("robkin:frame").Get() is True
    colliders = [p for p in stage.Traverse() if p.HasAPI(UsdPhysics.CollisionAPI)]
    assert sorted(p.GetTypeName() for p in colliders) == ["Cylinder", "Sphere"]
    assert all(UsdGeom.Imageable(p).GetPurposeAttr().Get() == "guide" for p in colliders)
    back = _read(tmp_path, text, tip_link="ünï")
    links_a = {link.name: link.pose for link in robot.bodies.links}
    links_b = {link.name: link.pose for link in back.bodies.links}
    for want, got in zip(robot.bodies.shapes, back.bodies.shapes):
        assert (want.role, want.geometry.kind, want.link) == (got.role, got.geometry.kind, got.link)
        np.testing.assert_allclose(got.geometry.size, want.geometry.size, rtol=1e-15)
        # on its link, in double precision (the link itself is where the float32 joint frames put it)
        np.testing.assert_allclose(np.linalg.solve(links_b[got.link], got.pose),
                                   np.linalg.solve(links_a[want.link], want.pose), atol=1e-15)
    assert len(back.bodies.shapes) == len(robot.bodies.shapes) == 3


def test_revolute_axis_off_the_child_origin_gets_a_link(tmp_path):
    """A foreign file whose joint frame is off the child's origin: FK as pxr composes it."""
    text = """#usda 1.0
def Xform "m" (prepend apiSchemas = ["PhysicsArticulationRootAPI"])
{
    def Xform "a" (prepend apiSchemas = ["PhysicsRigidBodyAPI"])
    {
    }
    def Xform "b" (prepend apiSchemas = ["PhysicsRigidBodyAPI"])
    {
    }
    def PhysicsRevoluteJoint "j"
    {
        uniform token physics:axis = "Y"
        rel physics:body0 = </m/a>
        rel physics:body1 = </m/b>
        point3f physics:localPos0 = (0.1, 0.2, 0.3)
        quatf physics:localRot0 = (0.8, 0.6, 0, 0)
        point3f physics:localPos1 = (0.05, 0, -0.2)
        quatf physics:localRot1 = (0.6, 0, 0, 0.8)
    }
}
"""
    path = tmp_path / "off.usda"
    path.write_text(text)
    robot = robkin.load(path, base_link="a", tip_link="b")
    assert robot.n == 1 and "b/j" in {link.name for link in robot.bodies.links}
    stage = Usd.Stage.Open(str(path))
    j = UsdPhysics.RevoluteJoint(stage.GetPrimAtPath("/m/j"))
    J0 = _gf(j.GetLocalPos0Attr().Get(), j.GetLocalRot0Attr().Get())
    J1 = _gf(j.GetLocalPos1Attr().Get(), j.GetLocalRot1Attr().Get())
    for q in (-1.0, 0.3, 2.0):
        np.testing.assert_allclose(robot.fk([q]), J0 @ _motion(j, q) @ np.linalg.inv(J1), atol=1e-15)


def test_usd_physics_parser_sees_one_articulation(written):
    """usd-core's own UsdPhysics parser (what Newton's importer builds on): one articulation rooted at the
    chain's base by one fixed joint to the world, every joint valid between rigid bodies, every collider
    on a rigid body, drives and limits as written."""
    _, robot, out, _, _ = written
    stage = Usd.Stage.Open(str(out))
    load = getattr(UsdPhysics, "LoadUsdPhysicsFromRange")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        parsed = load(stage, [pxr.Sdf.Path("/")])
    T = UsdPhysics.ObjectType
    (art,) = parsed[T.Articulation][1]
    assert art.isValid and len(art.rootPrims) == 1
    bodies = {str(p) for p in parsed[T.RigidBody][0]}
    joints = [d for kind in (T.RevoluteJoint, T.PrismaticJoint, T.FixedJoint) if kind in parsed for d in parsed[kind][1]]
    assert all(d.isValid and str(d.body1) in bodies and (not d.body0 or str(d.body0) in bodies) for d in joints)
    assert sum(1 for d in joints if not d.body0) == 1
    shapes = [d for kind in (T.MeshShape, T.CubeShape, T.SphereShape, T.CylinderShape, T.CapsuleShape)
              if kind in parsed for d in parsed[kind][1]]
    assert shapes and all(str(d.rigidBody) in bodies for d in shapes)
    by_name = {_name(stage.GetPrimAtPath(d.primPath)): d for d in joints}
    for j in robot.joints:
        d = by_name[j.name]
        if j.effort:
            assert d.drive.forceLimit == pytest.approx(j.effort, rel=1e-7)
        if j.type == "revolute" and j.upper is not None:
            assert d.limit.upper == pytest.approx(math.degrees(j.upper), rel=1e-6)


MJCF_OFF_AXIS = """<mujoco model="off"><worldbody><body name="a"><inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.01"/>
  <body name="b" pos="0.3 0 0.2" quat="0.9 0.1 0.3 0.2">
    <joint name="j1" type="hinge" pos="0.05 0.1 0" axis="0.3 0.4 0.866" range="-60 60"/>
    <inertial pos="0.1 0 0" mass="2" diaginertia="0.02 0.03 0.04"/>
    <body name="c" pos="0.2 0 0"><joint name="j2" type="slide" pos="0 0.1 0" axis="1 0 0" range="-0.1 0.3"/>
      <inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.01"/><site name="tip" pos="0.1 0 0"/></body>
  </body></body></worldbody></mujoco>"""


def test_joint_off_its_body_origin_is_no_extra_body(tmp_path, capsys):
    """An MJCF hinge off its body's origin (robkin's link b/j1 carries it): no massless rigid body in the
    USD, the joint frame off b's origin; read back, the same robot and the link b/j1 again."""
    (tmp_path / "off.xml").write_text(MJCF_OFF_AXIS)
    out = tmp_path / "off.usda"
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no 'moves without mass' warning
        assert main(["convert", str(tmp_path / "off.xml"), "--tip-link", "tip", "--to", "usd", "-o", str(out)]) == 0
    stage = Usd.Stage.Open(str(out))
    assert sorted(_name(p) for p in stage.Traverse() if p.HasAPI(UsdPhysics.RigidBodyAPI)) == ["a", "b", "c"]
    j1 = UsdPhysics.RevoluteJoint(_joint(stage, "j1"))
    assert tuple(j1.GetLocalPos1Attr().Get()) == pytest.approx((0.05, 0.1, 0.0), abs=1e-8)
    assert main(["check", str(tmp_path / "off.xml"), str(out), "--tip-link", "tip"]) == 0
    assert "b/j1" in {link.name for link in robkin.load(out, tip_link="tip").bodies.links}


def test_a_batch_writes_usda_files_and_checks_them(tmp_path, capsys):
    (tmp_path / "r.urdf").write_text(URDF)
    (tmp_path / "d.yaml").write_text("robkin: 1\njoints: [revolute, prismatic]\ndh: {rows: [[0.1, 0.2, 0.3, 0], [0, 0.1, 0, 0]]}\n")
    out = tmp_path / "out"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["convert", str(tmp_path / "r.urdf"), str(tmp_path / "d.yaml"), "--tip-link", "ünï",
                     "--tip-link", "-", "--to", "usd", "-o", f"{out}/"]) == 0
    err = capsys.readouterr().err
    assert (out / "r.usda").is_file() and (out / "d.usda").is_file()
    assert err.count("read back: FK") == 1 and err.count("FK checked; mass properties not checked") == 1


@pytest.mark.parametrize("mode", ["hull", "primitives"])
def test_collision_modes_reach_the_usd_colliders(mode, tmp_path):
    """--collision for --to usd: the colliders are the collision stage's shapes, inline (hull: convex
    meshes; primitives: one UsdGeom primitive per link), and nothing is left beside the file."""
    trimesh = pytest.importorskip("trimesh")
    path = robot_file("ur_description/urdf/ur5_robot.urdf")
    out = tmp_path / "ur5.usda"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["convert", path, "--tip-link", "tool0", "--to", "usd", "--collision", mode, "-o", str(out)]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ur5.usda"]
    stage = Usd.Stage.Open(str(out))
    colliders = [p for p in stage.Traverse() if p.HasAPI(UsdPhysics.CollisionAPI)]
    assert len(colliders) >= 6
    meshes = [p for p in colliders if p.IsA(UsdGeom.Mesh)]
    assert len(meshes) == (7 if mode == "hull" else 0)   # UR5: 7 collision meshes (ee_link's box stays a box)
    for p in colliders:
        if mode == "hull" and p.IsA(UsdGeom.Mesh):
            m = UsdGeom.Mesh(p)
            tri = np.array(m.GetFaceVertexIndicesAttr().Get()).reshape(-1, 3)
            mesh = trimesh.Trimesh(np.array(m.GetPointsAttr().Get(), dtype=float), tri, process=False)
            assert mesh.is_convex, p.GetPath()
        elif mode == "hull":
            assert p.GetTypeName() == "Cube", p.GetPath()
        else:
            assert not p.IsA(UsdGeom.Mesh) and p.GetTypeName() in ("Cube", "Sphere", "Capsule", "Cylinder"), p.GetPath()
