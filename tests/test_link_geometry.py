"""Stand-in link shapes (robkin.link_geometry, ``convert --link-geometry capsules``): capsules between
joint frame origins, checked in MuJoCo and pinocchio reading the written URDF."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import robkin
from robkin.cli import main
from robkin.link_geometry import link_capsules, with_link_capsules

EXAMPLES = Path(robkin.__file__).parent / "examples"


def _urdf(tmp_path, name: str = "rrpr", *extra: str) -> Path:
    out = tmp_path / f"{name}.urdf"
    assert main(["convert", str(EXAMPLES / f"{name}.yaml"), "--to", "urdf", "--link-geometry", "capsules",
                 "-o", str(out), *extra]) == 0
    return out


def test_shapes_one_capsule_per_body_one_housing_per_joint():
    robot = robkin.load(EXAMPLES / "rrpr.yaml")
    shapes = link_capsules(robot)
    visual = [s for s in shapes if s.role == "visual"]
    assert len(visual) == 2 * robot.n + 1 and len(shapes) == 2 * len(visual)
    assert {s.body for s in visual} == set(range(robot.n + 1))
    assert all(s.material is None for s in shapes if s.role == "collision")
    more = with_link_capsules(with_link_capsules(robot))
    assert len(more.bodies.shapes) == 2 * len(shapes)  # added to the shapes already there
    assert len(with_link_capsules(more, replace=True).bodies.shapes) == len(shapes)
    np.testing.assert_array_equal(more.fk(np.ones(robot.n)), robot.fk(np.ones(robot.n)))  # kinematics untouched


def test_mujoco_places_the_capsules_between_the_joint_origins_at_any_q(tmp_path):
    mujoco = pytest.importorskip("mujoco")
    robot = robkin.load(EXAMPLES / "rrpr.yaml")
    model = mujoco.MjModel.from_xml_string(_urdf(tmp_path).read_text())
    data = mujoco.MjData(model)
    rng = np.random.default_rng(7)
    for _ in range(5):
        q = rng.uniform(-1, 1, robot.n) * [2, 2, 0.1, 2]
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        origins = np.vstack([np.zeros(3), robot.frames_at(q)[:, :3, 3]])  # P_0 .. P_{n+1} at q
        for b in range(1, robot.n + 1):
            if b < robot.n and not robot.joints[b].revolute:
                continue  # a prismatic joint b+1 slides its frame origin away from body b's capsule end
            g = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, f"link{b}_link")
            half = model.geom_size[g, 1]  # MuJoCo's cylinder size: radius, half-length
            z = data.geom_xmat[g].reshape(3, 3)[:, 2]
            ends = sorted([data.geom_xpos[g] - half * z, data.geom_xpos[g] + half * z],
                          key=lambda p: np.linalg.norm(p - origins[b]))
            # 1e-12 m: the same point through two FK implementations, rounding only
            np.testing.assert_allclose(ends[0], origins[b], atol=1e-12)
            np.testing.assert_allclose(ends[1], origins[b + 1], atol=1e-12)
            for k in (1, 2):  # the caps: spheres on the ends
                c = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, f"link{b}_link_cap{k}")
                assert min(np.linalg.norm(data.geom_xpos[c] - e) for e in ends) < 1e-12


def test_pinocchio_reads_the_visual_and_collision_shapes(tmp_path):
    pin = pytest.importorskip("pinocchio")
    robot = robkin.load(EXAMPLES / "scara.yaml")
    text = _urdf(tmp_path, "scara", "--link-radius", "0.05").read_text()
    model = pin.buildModelFromXML(text)
    per_role = 3 * (robot.n + 1) + robot.n  # a capsule: cylinder + 2 spheres; a housing per joint
    for kind in (pin.GeometryType.VISUAL, pin.GeometryType.COLLISION):
        geoms = pin.buildGeomFromUrdfString(model, text, kind)
        # a body whose segment has zero length gets one sphere instead of three shapes
        assert per_role - 2 * (robot.n + 1) <= geoms.ngeoms <= per_role
    assert 'radius="0.05"' in text


@pytest.mark.parametrize("args, message", [
    (["--to", "dh", "--link-geometry", "capsules"], "--link-geometry capsules: shapes are written by --to urdf"),
    (["--to", "urdf", "--link-radius", "0.1"], "--link-radius: applies with --link-geometry capsules"),
    (["--to", "urdf", "--link-geometry", "capsules", "--link-radius", "-1"], "--link-radius: must be a positive"),
    (["--to", "urdf", "--link-geometry", "capsules", "--link-radius", "nan"], "--link-radius"),
])
def test_bad_link_geometry_options_are_one_line_errors(tmp_path, capsys, args, message):
    out = tmp_path / "x.urdf"
    assert main(["convert", str(EXAMPLES / "rrpr.yaml"), *args, "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1 and not out.exists()
