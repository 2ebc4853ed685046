"""``robkin check`` compares mass properties (robkin.dynamics.compare) where both sides have them."""

from __future__ import annotations

import json
import re
import warnings

import numpy as np
import pytest

import robkin
from robkin.bodies import Bodies, body_motions
from robkin.body_parts import Inertial
from robkin.cli import main
from robkin.dynamics.compare import compare_masses
from robkin.equivalence import compare
from robkin.io.urdf import urdf_from_robot
from test_urdf import robot_file

UR5 = "ur_description/urdf/ur5_robot.urdf"


def with_inertial(robot: robkin.Robot, link: str, **change) -> robkin.Robot:
    """The robot with one inertial record changed (mass=, pose=)."""
    parts = []
    for p in robot.bodies.inertials:
        if p.link == link:
            p = Inertial(link=p.link, body=p.body, pose=change.get("pose", p.pose), mass=change.get("mass", p.mass),
                         inertia=p.inertia, origin=p.origin)
        parts.append(p)
    return robot.replace(bodies=Bodies(links=robot.bodies.links, chain=robot.bodies.chain, tip=robot.bodies.tip,
                                       shapes=robot.bodies.shapes, inertials=tuple(parts)))


@pytest.fixture(scope="module")
def ur5() -> robkin.Robot:
    return robkin.load(robot_file(UR5), tip_link="tool0")


def test_same_robot_same_masses(ur5):
    result = compare_masses(ur5, ur5, compare(ur5, ur5))
    assert result.checked and result.same
    assert result.mass_matrix_error == 0.0 and result.gravity_error == 0.0
    assert result.total_mass_a == pytest.approx(20.9939)   # the file's links: 4 + 3.7 + 8.393 + 2.275 + 3 x 1.219 + tool 0


def test_first_differing_body_is_named(ur5):
    heavier = with_inertial(ur5, "forearm_link", mass=2.3)
    result = compare_masses(ur5, heavier, compare(ur5, heavier))
    assert result.checked and result.same is False
    assert result.first_difference.startswith("body 3 ('forearm_link' / 'forearm_link'): mass 2.275 kg vs 2.3 kg")
    assert [b.same for b in result.bodies] == [True, True, True, False, True, True, True]
    assert result.mass_matrix_error > 1e-3
    # a centre of mass moved by 1 mm on the wrist
    part = next(p for p in ur5.bodies.inertials if p.link == "wrist_2_link")
    pose = part.pose.copy()
    pose[:3, 3] += [0.001, 0.0, 0.0]
    shifted = with_inertial(ur5, "wrist_2_link", pose=pose)
    result = compare_masses(ur5, shifted, compare(ur5, shifted))
    assert re.match(r"body 5 \('wrist_2_link' / 'wrist_2_link'\): centre of mass 0.001 m apart", result.first_difference)


def test_masses_follow_the_joint_mapping(ur5):
    """B is A with its zero moved to q = delta and joint 2 reversed: the same mechanism under
    q_A = s q_B + delta, with the bodies where they are at that configuration; M and g agree to rounding."""
    delta = np.array([0.3, -0.7, 0.4, 0.0, 1.1, -0.2])
    frames = ur5.frames_at(delta)
    frames[1] = frames[1] @ np.diag([1.0, -1.0, -1.0, 1.0])        # joint 2's axis reversed
    motion = body_motions(ur5, delta)
    moved = tuple(Inertial(link=p.link, body=p.body, pose=motion[p.body] @ p.pose, mass=p.mass, inertia=p.inertia)
                  for p in ur5.bodies.inertials)
    b = ur5.replace(frames=frames, bodies=Bodies(chain=ur5.bodies.chain, inertials=moved))
    kin = compare(ur5, b)
    assert kin.equivalent and not kin.same
    result = compare_masses(ur5, b, kin)
    assert result.checked and result.same, result.first_difference
    assert result.mass_matrix_error < 1e-12 and result.gravity_error < 1e-12


def test_not_compared_without_inertials_or_with_other_kinematics(ur5):
    table = robkin.dh_from_robot(ur5).to_robot()   # a DH table: kinematics only
    result = compare_masses(table, ur5, compare(table, ur5))
    assert not result.checked and result.same is None and result.reason == "A has no inertials"
    longer_tool = np.concatenate([ur5.frames[:-1], (ur5.frames[-1] @ robkin.se3.trans(0.1))[None]])
    other = ur5.replace(frames=longer_tool)
    result = compare_masses(ur5, other, compare(ur5, other))
    assert not result.checked and "kinematics differ" in result.reason


def test_cli_reports_masses_and_exit_status(tmp_path, capsys, ur5):
    src = robot_file(UR5)
    out = tmp_path / "ur5.urdf"
    out.write_text(urdf_from_robot(ur5))
    assert main(["check", src, str(out), "--tip-link", "tool0", "--tip-link", "tool0"]) == 0
    text = capsys.readouterr().out
    assert "mass properties: same (7 bodies" in text
    heavy = out.read_text().replace('<mass value="2.275"', '<mass value="2.5"')
    assert heavy != out.read_text()
    (tmp_path / "heavy.urdf").write_text(heavy)
    assert main(["check", src, str(tmp_path / "heavy.urdf"), "--tip-link", "tool0", "--tip-link", "tool0", "--json"]) == 1
    d = json.loads(capsys.readouterr().out)
    assert d["same"] is True and d["mass"]["same"] is False
    assert d["mass"]["first_difference"].startswith("body 3 ('forearm_link'")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        doc = tmp_path / "ur5_dh.yaml"
        assert main(["convert", src, "--tip-link", "tool0", "--to", "dh", "-o", str(doc)]) == 0
    capsys.readouterr()
    assert main(["check", str(doc), src, "--tip-link", "-", "--tip-link", "tool0"]) == 0
    assert "mass properties: not compared (A has no inertials)" in capsys.readouterr().out
