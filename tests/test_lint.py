"""robkin lint: one planted defect per category, each named with its file:line, element and fix; the
report formats; the exit statuses of the CLI."""

from __future__ import annotations

import json

import numpy as np
import pytest

from robkin.cli import main
from robkin.lint import lint_file
from robkin.lint.report import as_sarif

from lint_files import BASE_INERTIAL, J2_LIMIT, L2_INERTIAL, arm, line_of, write


def _one(tmp_path, text, code, needle, severity="error", element=None):
    """The findings of ``text`` hold ``code`` at the line of ``needle``, with its severity, file, message, fix."""
    path = write(tmp_path, text)
    found = lint_file(path)
    hits = [f for f in found if f.code == code]
    assert hits, f"{code} not found; found {[(f.code, f.line) for f in found]}"
    f = hits[0]
    assert f.severity == severity
    assert f.file == str(path)
    assert f.line == line_of(text, needle), (f.line, line_of(text, needle))
    assert f.fix and f.message
    if element:
        assert f.element == element
    return found


def test_sound_arm_has_no_findings(tmp_path):
    assert lint_file(write(tmp_path, arm())) == []


# --- structure ---------------------------------------------------------------------------------------
def test_dangling_joint_parent(tmp_path):
    text = arm().replace('<parent link="link1"/>', '<parent link="link9"/>')
    _one(tmp_path, text, "joint-dangling", 'name="joint2"', element="joint 'joint2'")


def test_duplicate_link(tmp_path):
    text = arm(extra='<link name="link1"/>')
    _one(tmp_path, text, "link-duplicate", '<link name="link1"/>', element="link 'link1'")


def test_several_roots(tmp_path):
    found = _one(tmp_path, arm(extra='<link name="stray"/>'), "several-roots", '<link name="stray"/>')
    assert "stray" in [f for f in found if f.code == "several-roots"][0].message


def test_cycle(tmp_path):
    text = arm(extra='<joint name="back" type="fixed"><parent link="link2"/><child link="link1"/></joint>')
    found = lint_file(write(tmp_path, text))
    hit = [f for f in found if f.code == "link-two-parents"]
    assert hit and hit[0].severity == "error" and hit[0].line == line_of(text, 'name="back"')
    assert "joint1" in hit[0].message


def test_pure_cycle_unreachable(tmp_path):
    # two links joined both ways, apart from the tree: a cycle nothing reaches
    extra = ('<link name="a"/><link name="b"/>\n'
             '<joint name="ab" type="fixed"><parent link="a"/><child link="b"/></joint>\n'
             '<joint name="ba" type="fixed"><parent link="b"/><child link="a"/></joint>')
    found = lint_file(write(tmp_path, arm(extra=extra)))
    cyc = [f for f in found if f.code == "joint-cycle"]
    assert cyc and "a" in cyc[0].message and "unreachable" in cyc[0].message


def test_name_other_tools_reject(tmp_path):
    _one(tmp_path, arm(l2_name="link 2"), "name-characters", '<link name="link 2">', severity="info")


# --- joints ------------------------------------------------------------------------------------------
def test_limits_reversed(tmp_path):
    text = arm(j2_limit='<limit lower="1.5" upper="-1.5" effort="30" velocity="2"/>')
    found = _one(tmp_path, text, "limits-reversed", 'lower="1.5"', element="joint 'joint2'")
    assert 'lower="-1.5" upper="1.5"' in [f for f in found if f.code == "limits-reversed"][0].fix


def test_zero_range(tmp_path):
    _one(tmp_path, arm(j2_limit='<limit lower="0" upper="0" effort="30" velocity="2"/>'), "limits-zero-range",
         'lower="0" upper="0"', severity="warning")


def test_effort_missing_and_zero_velocity(tmp_path):
    text = arm(j2_limit='<limit lower="-1" upper="1" velocity="0"/>')
    found = _one(tmp_path, text, "effort-missing", 'lower="-1" upper="1"')
    assert any(f.code == "velocity-zero" and f.severity == "warning" for f in found)


def test_mimic_target_missing(tmp_path):
    text = arm(j2_extra='<mimic joint="joint7" multiplier="1"/>')
    _one(tmp_path, text, "mimic-missing", "<mimic", severity="warning", element="joint 'joint2'")


def test_mimic_cycle(tmp_path):
    text = arm(j2_extra='<mimic joint="joint2"/>')
    _one(tmp_path, text, "mimic-cycle", "<mimic")
    two = arm(j2_extra='<mimic joint="joint1"/>').replace('<axis xyz="0 0 1"/>', '<axis xyz="0 0 1"/><mimic joint="joint2"/>')
    found = [f for f in lint_file(write(tmp_path, two)) if f.code == "mimic-cycle"]
    assert len(found) == 1 and "joint1 -> joint2 -> joint1" in found[0].message


def test_axis_zero_and_not_unit(tmp_path):
    _one(tmp_path, arm(j2_axis="0 0 0"), "axis-zero", '<axis xyz="0 0 0"/>')
    found = _one(tmp_path, arm(j2_axis="0 2 0"), "axis-not-unit", '<axis xyz="0 2 0"/>', severity="warning")
    assert '"0 1 0"' in [f for f in found if f.code == "axis-not-unit"][0].fix


# --- mass properties ---------------------------------------------------------------------------------
def test_moving_link_without_mass(tmp_path):
    _one(tmp_path, arm(l2_inertial=""), "mass-zero-moving", '<link name="link2">', element="link 'link2'")


def test_moving_link_zero_mass(tmp_path):
    text = arm(l2_inertial='<inertial><mass value="0"/><inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial>')
    _one(tmp_path, text, "mass-zero-moving", '<mass value="0"/>')


def test_inertia_not_positive(tmp_path):
    text = arm(l2_inertial=L2_INERTIAL.replace('ixx="0.0160"', 'ixx="-0.0160"'))
    _one(tmp_path, text, "inertia-not-positive", 'ixx="-0.0160"')


def test_inertia_rank_deficient(tmp_path):  # KUKA macros: a moment of exactly zero
    text = arm(l2_inertial=L2_INERTIAL.replace('izz="0.0030"', 'izz="0"'))
    _one(tmp_path, text, "inertia-not-positive", 'izz="0"')


def test_inertia_triangle(tmp_path):
    text = arm(l2_inertial=L2_INERTIAL.replace('izz="0.0030"', 'izz="0.0400"'))
    found = _one(tmp_path, text, "inertia-triangle", 'izz="0.0400"')
    f = [f for f in found if f.code == "inertia-triangle"][0]
    assert "MuJoCo" in f.message and "drake" in f.message and "pinocchio" in f.message


def test_inertia_too_large_for_geometry(tmp_path):  # UR5-style: 100x what the link's box can hold
    text = arm(l2_inertial=L2_INERTIAL.replace('ixx="0.0160" iyy="0.0160" izz="0.0030"',
                                               'ixx="1.6" iyy="1.6" izz="0.3"'))
    _one(tmp_path, text, "inertia-too-large", 'ixx="1.6"', severity="warning")


def test_inertia_near_point_mass(tmp_path):  # the placeholder base inertia: yaw 1000x too easy
    text = arm(l2_inertial=L2_INERTIAL.replace('ixx="0.0160" iyy="0.0160" izz="0.0030"',
                                               'ixx="1.6e-5" iyy="1.6e-5" izz="3e-6"'))
    _one(tmp_path, text, "inertia-vs-geometry", 'ixx="1.6e-5"', severity="warning")


def test_mass_against_volume(tmp_path):  # grams written as kilograms
    text = arm(l2_inertial=L2_INERTIAL.replace('value="2"', 'value="2000"').replace(
        'ixx="0.0160" iyy="0.0160" izz="0.0030"', 'ixx="16" iyy="16" izz="3"'))
    found = _one(tmp_path, text, "mass-vs-volume", 'value="2000"', severity="warning")
    assert "20-25000 kg/m^3" in [f for f in found if f.code == "mass-vs-volume"][0].message


def test_com_far_outside(tmp_path):
    text = arm(l2_inertial=L2_INERTIAL.replace('<origin xyz="0 0 0.15"/>', '<origin xyz="0 0 15"/>'))
    _one(tmp_path, text, "com-outside", '<origin xyz="0 0 15"/>', severity="warning")


def test_placeholder_identity(tmp_path):
    text = arm(base_inertial=BASE_INERTIAL.replace('ixx="0.0083" iyy="0.0083" izz="0.0133"', 'ixx="1" iyy="1" izz="1"'))
    _one(tmp_path, text, "inertia-placeholder", 'ixx="1" iyy="1" izz="1"', severity="warning")


# --- assets --------------------------------------------------------------------------------------------
def _stl(path, V, F):
    from robkin.collision.mesh_data import stl_bytes

    path.write_bytes(stl_bytes(np.asarray(V, float), np.asarray(F)))


_CUBE_V = [[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)]
_CUBE_F = [[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1], [2, 3, 7], [2, 7, 6],
           [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]]


def test_mesh_missing(tmp_path):
    _one(tmp_path, arm(l2_geometry='<mesh filename="meshes/nowhere.stl"/>'), "mesh-missing", "nowhere.stl")


def test_mesh_unreadable(tmp_path):
    (tmp_path / "broken.stl").write_bytes(b"solid nothing here\n")
    _one(tmp_path, arm(l2_geometry='<mesh filename="broken.stl"/>'), "mesh-unreadable", "broken.stl")


def test_mesh_flat(tmp_path):
    _stl(tmp_path / "flat.stl", [[0, 0, 0], [0.1, 0, 0], [0, 0.3, 0], [0.1, 0.3, 0]], [[0, 1, 2], [1, 3, 2]])
    _one(tmp_path, arm(l2_geometry='<mesh filename="flat.stl"/>'), "mesh-flat", "flat.stl", severity="warning")


def test_mesh_open_and_faces_and_unit(tmp_path):
    V = np.array(_CUBE_V) * [80.0, 80.0, 300.0] - [40, 40, 0]  # millimetres
    _stl(tmp_path / "mm.stl", V, _CUBE_F[:-1])                  # one triangle missing: not watertight
    text = arm(l2_geometry='<mesh filename="mm.stl"/>')
    found = lint_file(write(tmp_path, text))
    line = line_of(text, "mm.stl")
    assert {("mesh-unit", "warning"), ("mesh-open", "info")} <= {(f.code, f.severity) for f in found if f.line == line}
    unit = [f for f in found if f.code == "mesh-unit"][0]
    assert 'scale="0.001 0.001 0.001"' in unit.fix
    assert any(f.code == "mesh-faces" for f in lint_file(tmp_path / "arm.urdf", max_faces=5))


# --- reports and the CLI ---------------------------------------------------------------------------------
def test_json_and_exit_status(tmp_path, capsys):
    good = write(tmp_path, arm(), "good.urdf")
    bad = write(tmp_path, arm(j2_limit='<limit lower="1" upper="-1" effort="1" velocity="1"/>'), "bad.urdf")
    assert main(["lint", str(good)]) == 0
    capsys.readouterr()
    assert main(["lint", str(good), str(bad), "--format", "json"]) == 1
    items = json.loads(capsys.readouterr().out)
    assert items and all({"severity", "file", "line", "element", "message", "fix"} <= set(x) for x in items)
    assert {x["file"] for x in items} == {str(bad)} and items[0]["element"] == "joint 'joint2'"
    warn = write(tmp_path, arm(j2_axis="0 3 0"), "warn.urdf")
    assert main(["lint", str(warn)]) == 0  # warnings only
    assert "warning" in capsys.readouterr().out


def test_unreadable_file_is_exit_2(tmp_path, capsys):
    notxml = write(tmp_path, "<robot><link", "broken.urdf")
    assert main(["lint", str(notxml)]) == 2
    assert "not well-formed" in capsys.readouterr().err
    assert main(["lint", str(tmp_path / "absent.urdf")]) == 2
    dtd = write(tmp_path, '<!DOCTYPE r [<!ENTITY e "x">]><robot name="r"/>', "dtd.urdf")
    assert main(["lint", str(dtd)]) == 2


def test_text_line_format(tmp_path, capsys):
    text = arm(j2_axis="0 0 0")
    bad = write(tmp_path, text)
    main(["lint", str(bad)])
    out = capsys.readouterr().out
    line = line_of(text, '<axis xyz="0 0 0"/>')
    assert out.startswith(f"{bad}:{line}: error: joint 'joint2': ")
    assert "; fix: " in out


def test_sarif_required_fields(tmp_path):
    found = lint_file(write(tmp_path, arm(j2_axis="0 0 0", l2_inertial="")))
    doc = json.loads(as_sarif(found, "1.0"))
    # SARIF 2.1.0's required properties: log (version, runs), run (tool), tool (driver), driver (name),
    # result (message), message (text or id), rule (id); levels from its enumeration
    assert doc["version"] == "2.1.0" and "sarif-2.1.0" in doc["$schema"]
    run = doc["runs"][0]
    rules = [r["id"] for r in run["tool"]["driver"]["rules"]]
    assert run["tool"]["driver"]["name"] and len(rules) == len(set(rules))
    assert len(run["results"]) == len(found)
    for r in run["results"]:
        assert r["message"]["text"] and r["level"] in ("none", "note", "warning", "error")
        assert rules[r["ruleIndex"]] == r["ruleId"]
        loc = r["locations"][0]["physicalLocation"]
        assert loc["artifactLocation"]["uri"] and loc["region"]["startLine"] >= 1


def test_other_formats_get_reader_checks(tmp_path, capsys):
    from robkin.examples import EXAMPLES_DIR

    assert main(["lint", str(EXAMPLES_DIR / "rrpr.yaml")]) == 0
    bad = tmp_path / "bad.yaml"
    bad.write_text("robkin: 1\njoints: [{name: a, type: revolute}]\ndh: {rows: [{a: 0, d: 0, alpha: 0, theta: oops}]}\n")
    assert main(["lint", str(bad)]) == 1
    assert "error" in capsys.readouterr().out


def test_reader_projection_is_a_warning(capsys):
    from robkin.examples import EXAMPLES_DIR

    found = lint_file(EXAMPLES_DIR / "arbitrary_3r.yaml")  # the paper's rounded screws: projected by the reader
    warned = [f for f in found if f.code == "reader-changes"]
    assert warned and all(f.severity == "warning" for f in warned) and any("normalised" in f.message for f in warned)
    assert main(["lint", str(EXAMPLES_DIR / "arbitrary_3r.yaml")]) == 0


def test_mjcf_reader_refusal_is_a_finding_with_its_line(tmp_path, capsys):
    bad = tmp_path / "bad.xml"
    bad.write_text('<mujoco model="m">\n  <worldbody>\n    <body name="b1">\n'
                   '      <joint name="j1" type="hinge" axis="0 0 1" range="1 -1" limited="true"/>\n'
                   '      <inertial pos="0 0 0" mass="1" diaginertia="0.1 0.1 0.1"/>\n    </body>\n'
                   '  </worldbody>\n</mujoco>\n')
    found = lint_file(bad)
    assert [(f.severity, f.line, f.element) for f in found] == [("error", 4, "joint 'j1'")]
    assert "range" in found[0].message
    assert main(["lint", str(bad)]) == 1
    (tmp_path / "broken.xml").write_text("<mujoco><worldbody><body")
    assert main(["lint", str(tmp_path / "broken.xml")]) == 2


def test_xacro_needs_opt_in(tmp_path):
    x = write(tmp_path, arm(), "arm.xacro")
    assert main(["lint", str(x)]) == 2
    pytest.importorskip("xacro")
    assert main(["lint", str(x), "--allow-xacro"]) == 0


def test_hostile_mesh_names_read_nothing(tmp_path):
    # a file is untrusted: a mesh name that leads to a non-mesh file, a remote address or out of its
    # package is a finding, and nothing but mesh files is opened
    for name, why in (("/etc/passwd", "not a mesh file"), ("http://example.com/a.stl", "nothing is fetched"),
                      ("package://pkg/../../x.stl", "")):
        found = [f for f in lint_file(write(tmp_path, arm(l2_geometry=f'<mesh filename="{name}"/>')))
                 if f.code == "mesh-missing"]
        assert len(found) == 1 and why in found[0].message
