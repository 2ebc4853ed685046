"""robkin lint on MJCF, SDF, robot documents and tables: the URDF checks (one implementation each) with the
element's source line; one planted defect per category and format, each named with file:line, element and fix;
MuJoCo's geom-derived masses as MuJoCo compiles them; MuJoCo's own verdict and silent compiler settings."""

from __future__ import annotations

import numpy as np
import pytest

from robkin.cli import main
from robkin.lint import lint_file

from lint_files import line_of
from lint_formats_files import MJ_L2_GEOM, SDF_L2_INERTIAL, mjcf_arm, sdf_arm


def _write(tmp_path, text, name):
    p = tmp_path / name
    p.write_text(text)
    return p


def _one(path, text, code, needle, severity="error", element=None, fix=None, last=False):
    """lint of ``path`` holds ``code`` at the line of ``needle`` (its last line with ``last``)."""
    found = lint_file(path)
    hits = [f for f in found if f.code == code]
    assert hits, f"{code} not found; found {[(f.code, f.line, f.message) for f in found]}"
    f = hits[0]
    lines = [k for k, t in enumerate(text.splitlines(), 1) if needle in t]
    assert (f.severity, f.file, f.line) == (severity, str(path), lines[-1] if last else lines[0])
    assert f.message and f.fix
    if element:
        assert f.element == element
    if fix:
        assert fix in f.fix, f.fix
    return found


def _stl_box(path, extents):
    trimesh = pytest.importorskip("trimesh")
    trimesh.creation.box(extents=extents).export(str(path))


@pytest.mark.parametrize("fmt", ["mjcf", "sdf"])
def test_sound_arms_have_no_findings(tmp_path, fmt):
    path = _write(tmp_path, mjcf_arm() if fmt == "mjcf" else sdf_arm(), "arm.xml" if fmt == "mjcf" else "arm.sdf")
    assert lint_file(path) == []
    assert main(["lint", str(path)]) == 0


# --- MJCF --------------------------------------------------------------------------------------------
def test_mjcf_structure_duplicate_body(tmp_path):
    text = mjcf_arm(extra='<body name="link1" pos="0 0 0.1"><geom type="sphere" size="0.02"/></body>')
    _one(_write(tmp_path, text, "a.xml"), text, "link-duplicate", 'name="link1"', last=True, element="body 'link1'")


def test_mjcf_structure_name_other_tools_reject(tmp_path):
    text = mjcf_arm(l2_name="link 2")
    _one(_write(tmp_path, text, "a.xml"), text, "name-characters", 'name="link 2"', severity="info")


def test_mjcf_joint_axis_not_unit(tmp_path):
    text = mjcf_arm(j1_axis="0 0 2")
    _one(_write(tmp_path, text, "a.xml"), text, "axis-not-unit", 'name="joint1"', severity="warning",
         element="joint 'joint1'", fix='axis="0 0 1"')


def test_mjcf_joint_range_reversed(tmp_path):
    text = mjcf_arm(j2_range="1.5 -1.5")
    _one(_write(tmp_path, text, "a.xml"), text, "limits-reversed", 'name="joint2"', element="joint 'joint2'",
         fix="swap")


def test_mjcf_mass_triangle_said_once(tmp_path):
    text = mjcf_arm(l2_inertial='<inertial pos="0 0 0.15" mass="2" diaginertia="0.01 0.01 0.05"/>')
    path = _write(tmp_path, text, "a.xml")
    found = _one(path, text, "inertia-triangle", 'diaginertia="0.01 0.01 0.05"', element="body 'link2'")
    pytest.importorskip("mujoco")
    # MuJoCo refuses the same defect (at the body's line): said once, with lint's fix
    assert [f.code for f in found if f.severity == "error"] == ["inertia-triangle"]


def test_mjcf_massless_moving_body(tmp_path):
    # no <inertial>, and its only geom has mass 0: MuJoCo's geom-derived mass is 0 and it refuses the body
    text = mjcf_arm(l2_inertial="", l2_geom=MJ_L2_GEOM.replace("/>", ' mass="0"/>'))
    found = _one(_write(tmp_path, text, "a.xml"), text, "mass-zero-moving", 'name="link2"', element="body 'link2'")
    assert "MuJoCo refuses" in [f for f in found if f.code == "mass-zero-moving"][0].message


def test_mjcf_mass_from_geoms_as_mujoco_compiles_it(tmp_path):
    # no <inertial>: MuJoCo takes the body's mass from its geoms (density 1000, or a geom's mass); lint reads
    # the same masses MuJoCo compiles, so a sound geom-massed arm has no findings
    mujoco = pytest.importorskip("mujoco")
    from robkin.lint.model_source import raw_from_model
    from robkin.lint.xml_lines import mjcf_lines, parse_lines
    from robkin.io.mjcf.reader import model_from_mjcf

    text = mjcf_arm(l2_inertial="", l2_geom='<geom type="capsule" size="0.04 0.11" pos="0 0 0.15" density="2700"/>')
    path = _write(tmp_path, text, "a.xml")
    assert lint_file(path) == []
    raw, _ = raw_from_model(model_from_mjcf(path)[0], str(path), "mjcf", mjcf_lines(parse_lines(str(path))))
    m = mujoco.MjModel.from_xml_path(str(path))
    for ln in raw.links:
        if ln.name in ("base", "link1", "link2"):
            b = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, ln.name)
            assert ln.mass == pytest.approx(m.body_mass[b], rel=1e-12)
            assert np.sort(np.linalg.eigvalsh(ln.inertia)) == pytest.approx(np.sort(m.body_inertia[b]), rel=1e-9)


def test_mjcf_mesh_missing(tmp_path):
    asset = '<asset><mesh name="m2" file="gone.stl"/></asset>'
    text = mjcf_arm(asset=asset, l2_geom='<geom type="mesh" mesh="m2"/>')
    _one(_write(tmp_path, text, "a.xml"), text, "mesh-missing", 'file="gone.stl"', element="body 'link2'")


def test_mjcf_mesh_in_millimetres(tmp_path):
    _stl_box(tmp_path / "l2.stl", (80.0, 80.0, 300.0))
    asset = '<asset><mesh name="m2" file="l2.stl"/></asset>'
    text = mjcf_arm(asset=asset, l2_geom='<geom type="mesh" mesh="m2" contype="0" conaffinity="0"/>')
    _one(_write(tmp_path, text, "a.xml"), text, "mesh-unit", 'file="l2.stl"', severity="warning",
         fix='scale="0.001 0.001 0.001"')


def test_mjcf_readiness_silent_compiler_settings(tmp_path):
    text = mjcf_arm(compiler='balanceinertia="true" boundmass="0.01"')
    path = _write(tmp_path, text, "a.xml")
    found = lint_file(path)
    codes = {f.code: f for f in found}
    assert {"mujoco-balanceinertia", "mujoco-boundmass"} <= set(codes)
    assert codes["mujoco-boundmass"].line == line_of(text, "<compiler")
    assert "pinocchio and drake" in codes["mujoco-boundmass"].message
    assert main(["lint", str(path)]) == 0   # warnings only


def test_mjcf_mujoco_verdict_where_lint_has_no_check(tmp_path):
    pytest.importorskip("mujoco")
    # an actuator on a joint that does not exist: MuJoCo refuses the file; lint says so with MuJoCo's line
    text = mjcf_arm().replace("</mujoco>", '<actuator><motor name="m" joint="nope"/></actuator>\n</mujoco>')
    found = _one(_write(tmp_path, text, "a.xml"), text, "mujoco-refuses", 'joint="nope"')
    assert "MuJoCo" in [f for f in found if f.code == "mujoco-refuses"][0].message


# --- SDF ---------------------------------------------------------------------------------------------
def test_sdf_structure_dangling_child(tmp_path):
    text = sdf_arm(j2_child="link9")
    _one(_write(tmp_path, text, "a.sdf"), text, "joint-dangling", 'name="joint2"', element="joint 'joint2'")


def test_sdf_joint_axis_not_unit(tmp_path):
    text = sdf_arm(j2_axis="0 2 0")
    _one(_write(tmp_path, text, "a.sdf"), text, "axis-not-unit", "<xyz>0 2 0</xyz>", severity="warning",
         fix="<xyz>0 1 0</xyz>")


def test_sdf_joint_zero_effort(tmp_path):
    text = sdf_arm(j2_limit="<limit><lower>-1</lower><upper>1</upper><effort>0</effort></limit>")
    _one(_write(tmp_path, text, "a.sdf"), text, "effort-zero", "<effort>0</effort>", severity="warning")


def test_sdf_mass_inertia_not_positive(tmp_path):
    text = sdf_arm(l2_inertial=SDF_L2_INERTIAL.replace("<ixx>0.016</ixx>", "<ixx>-0.016</ixx>"))
    _one(_write(tmp_path, text, "a.sdf"), text, "inertia-not-positive", "<ixx>-0.016</ixx>", element="link 'link2'")


def test_sdf_missing_inertial_is_sdformats_default(tmp_path):
    text = sdf_arm(l2_inertial="")
    found = _one(_write(tmp_path, text, "a.sdf"), text, "mass-default", '<link name="link2">', severity="warning")
    assert "1 kg" in [f for f in found if f.code == "mass-default"][0].message


def test_sdf_mesh_missing(tmp_path):
    text = sdf_arm(l2_geom="<mesh><uri>gone.stl</uri></mesh>")
    _one(_write(tmp_path, text, "a.sdf"), text, "mesh-missing", '<collision name="link2_c">')


# --- documents and tables ----------------------------------------------------------------------------
def test_document_kinematics_only_is_said(tmp_path):
    from robkin.examples import EXAMPLES_DIR

    path = _write(tmp_path, (EXAMPLES_DIR / "rrpr.yaml").read_text(), "rrpr.yaml")
    found = lint_file(path)
    assert [(f.code, f.severity) for f in found] == [("no-mass-properties", "info")]


DOC = """robkin: 1
name: two
joints:
  - {name: joint1, type: revolute, limits: {lower: -2, upper: 2}}
  - {name: joint2, type: revolute, limits: {lower: -1.5, upper: 1.5}}
dh:
  rows:
    - {a: 0,   d: 0.3, alpha: 0, theta: 0, m: 3, r: [0, 0, -0.15], I: [0.025, 0.025, 0.005, 0, 0, 0]}
    - {a: 0.3, d: 0,   alpha: 0, theta: 0, m: 2, r: [-0.15, 0, 0], I: %s}
"""


def test_document_mass_defect_at_its_joints_line(tmp_path):
    good = _write(tmp_path, DOC % "[0.003, 0.016, 0.016, 0, 0, 0]", "good.yaml")
    assert [f.code for f in lint_file(good) if f.severity == "error"] == []
    text = DOC % "[0.003, 0.003, 0.016, 0, 0, 0]"   # 0.003 + 0.003 < 0.016: no body has these moments
    bad = _write(tmp_path, text, "bad.yaml")
    hits = [f for f in lint_file(bad) if f.code == "inertia-triangle"]
    assert hits and hits[0].severity == "error" and hits[0].file == str(bad)
    assert hits[0].line == line_of(text, "name: joint2")
    assert main(["lint", str(bad)]) == 1


def test_table_is_linted_through_its_robot(tmp_path):
    from robkin.examples import EXAMPLES_DIR

    path = tmp_path / "rrpr.csv"
    assert main(["convert", str(EXAMPLES_DIR / "rrpr.yaml"), "--to", "dh", "--format", "csv", "-o", str(path)]) == 0
    assert [f.code for f in lint_file(path) if f.severity != "info"] == []


def test_fix_says_which_formats(tmp_path, capsys):
    from robkin.examples import EXAMPLES_DIR

    path = _write(tmp_path, (EXAMPLES_DIR / "rrpr.yaml").read_text(), "a.yaml")
    assert main(["lint", str(path), "--fix", "-o", str(tmp_path / "out.yaml")]) == 2
    err = capsys.readouterr().err
    assert "--fix supports URDF" in err and "MJCF" in err and "SDF" in err and not (tmp_path / "out.yaml").exists()


# --- the same robot in each format: the same findings ---------------------------------------------
@pytest.mark.parametrize("arm_file, tip", [("ur_description/urdf/ur5_robot.urdf", "tool0"),
                                           ("panda_description/urdf/panda.urdf", "panda_hand_tcp")])
def test_arm_as_mjcf_has_the_urdfs_findings(tmp_path, arm_file, tip):
    import glob
    import os
    import sys

    robots = (glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                     "example-robot-data", "robots")) or [""])[0]
    if not robots:
        pytest.skip("example-robot-data is not installed")
    src = os.path.join(robots, arm_file)
    out = tmp_path / "arm.xml"
    assert main(["convert", src, "--tip-link", tip, "--to", "mjcf", "-o", str(out)]) == 0
    import re

    bodies = set(re.findall(r'<body name="([^"]+)"', out.read_text()))
    urdf = {(f.code, f.element.split("'")[1]) for f in lint_file(src) if f.severity != "info"}
    found = lint_file(out)
    assert [f for f in found if f.severity == "error"] == []
    mjcf = {(f.code, f.element.split("'")[1]) for f in found if f.severity != "info"}
    # the bodies of the MJCF carry the same findings as those links of the URDF (the ARMS warnings of
    # test_lint_robots: inertias the geometry cannot hold), whatever the format
    assert mjcf == {(c, e) for c, e in urdf if e in bodies} and mjcf
