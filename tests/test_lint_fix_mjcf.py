"""robkin lint --fix on MJCF: the corrected file changes only what lint reported, loads in MuJoCo (no
balanceinertia or boundmass in it) and in pinocchio's MJCF parser, keeps MuJoCo's forward kinematics of the
input, and passes lint."""

from __future__ import annotations

import numpy as np
import pytest

from robkin.cli import main
from robkin.lint import lint_file

from lint_formats_files import mjcf_arm

#: one defect per fixable check: an axis of length 2, link2's moments breaking A + B >= C, link1 massless
#: (no <inertial>, a geom of mass 0)
BAD = mjcf_arm(j1_axis="0 0 2", l2_inertial='<inertial pos="0 0 0.15" mass="2" diaginertia="0.01 0.01 0.05"/>') \
    .replace('<inertial pos="0 0 0.15" mass="3" diaginertia="0.025 0.025 0.005"/>', "") \
    .replace('<geom type="box" size="0.05 0.05 0.15" pos="0 0 0.15"/>',
             '<geom type="box" size="0.05 0.05 0.15" pos="0 0 0.15" mass="0"/>')


def _fixed(tmp_path, text=BAD, *extra):
    bad, out = tmp_path / "bad.xml", tmp_path / "fixed.xml"
    bad.write_text(text)
    status = main(["lint", str(bad), "--fix", "-o", str(out), *extra])
    return bad, out, status


def test_fix_mjcf_loads_everywhere_and_keeps_fk(tmp_path, capsys):
    mujoco = pytest.importorskip("mujoco")
    bad, out, status = _fixed(tmp_path)
    said = capsys.readouterr().out
    assert status == 0 and "0 errors remain" in said
    assert all(w in said for w in ("axis normalised", "inertia replaced", "<inertial> mass"))
    with pytest.raises(ValueError):
        mujoco.MjModel.from_xml_path(str(bad))   # MuJoCo refuses the input (massless body, A + B < C)
    text = out.read_text()
    assert "balanceinertia" not in text and "boundmass" not in text
    m = mujoco.MjModel.from_xml_path(str(out))
    assert m.body_mass[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "link1")] > 0
    assert [f for f in lint_file(out) if f.severity == "error"] == []
    # forward kinematics: MuJoCo on the fixed file against robkin's reading of the input
    from robkin.io.mjcf.reader import robot_from_mjcf

    robot = robot_from_mjcf(bad, tip_link="tool")
    d = mujoco.MjData(m)
    site = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, "tool")
    for q in np.random.default_rng(3).uniform(-1.4, 1.4, (20, 2)):
        d.qpos[:] = q
        mujoco.mj_kinematics(m, d)
        T = robot.world @ robot.fk(q)
        assert np.allclose(T[:3, 3], d.site_xpos[site], atol=1e-12)
        assert np.allclose(T[:3, :3], d.site_xmat[site].reshape(3, 3), atol=1e-12)


def test_fix_mjcf_loads_in_pinocchio(tmp_path):
    pin = pytest.importorskip("pinocchio")
    _, out, status = _fixed(tmp_path)
    assert status == 0
    model = pin.buildModelFromMJCF(str(out))
    assert model.nq == 2
    masses = sorted(round(i.mass, 9) for i in model.inertias[1:])
    assert masses[0] > 0   # the body that had none has its geometry's mass


def test_fix_mjcf_changes_nothing_else(tmp_path):
    _, out, _ = _fixed(tmp_path)
    # lxml writes an empty element's end as "/>" (the template's "<compiler ... />" loses its space): the
    # only change of form; comments, attributes' order and indentation stay
    before, after = BAD.replace(" />", "/>").splitlines(), out.read_text().splitlines()
    changed = [b for b in before if b not in after]
    # the axis, link2's <inertial>, and (a new line) link1's <inertial>: nothing else
    assert len(changed) == 2 and any('axis="0 0 2"' in c for c in changed) and any("diaginertia" in c for c in changed)
    assert len(after) == len(before) + 1


def test_fix_mjcf_geometry_inertia(tmp_path, capsys):
    text = mjcf_arm(l2_inertial='<inertial pos="0 0 0.15" mass="2" diaginertia="1 1 1"/>')  # a placeholder
    bad = tmp_path / "p.xml"
    bad.write_text(text)
    assert "inertia-too-large" in [f.code for f in lint_file(bad)]
    _, out, status = _fixed(tmp_path, text, "--inertia", "geometry")
    assert status == 0 and "collision geometry's" in capsys.readouterr().out
    # the box 0.08 x 0.08 x 0.3 m at 2 kg: ixx = m (b^2 + c^2) / 12
    hit = [f for f in lint_file(out) if f.code.startswith("inertia")]
    assert hit == []
    assert "0.016" in out.read_text()
