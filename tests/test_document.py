"""Robot document reading/writing: schema, numbers, layouts, cross-checked sections, errors."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import robkin
from robkin.errors import InputError, ProjectionWarning
from robkin.io.documents.reader import document_from_robot, dump, parse_document, read_document, read_sections
from robkin.examples import EXAMPLES_DIR

PI = math.pi
RRPR_Q = np.array([3 * PI / 4, -PI / 4, 0.3, -3 * PI / 4])

DOC = """
robkin: 1
name: rrpr
joints:
  - {name: j1, type: revolute, limits: {lower: -2, upper: 2}}
  - {name: j2, type: revolute}
  - {name: j3, type: prismatic, flip: true}
  - {name: j4, type: revolute}
dh:
  rows:
    - [0, 0.2, -pi/2, 0]
    - {a: 0.3, d: 0, alpha: 0, theta: -pi/2}
    - [0.2, 0, pi, pi/2]
    - [0.1, 0, 0, 0]
"""


def test_rrpr_example_matches_paper_eq_10():
    robot = read_document(EXAMPLES_DIR / "rrpr.yaml")
    M = np.array([[1, 0, 0, 0.3], [0, 0, -1, 0], [0, 1, 0, 0.5], [0, 0, 0, 1]])
    np.testing.assert_allclose(robot.tool, M, atol=1e-12)
    assert robot.types == ("revolute", "revolute", "prismatic", "revolute")


def test_expressions_lists_and_named_rows_are_read():
    robot = parse_document(DOC)
    assert [j.name for j in robot.joints] == ["j1", "j2", "j3", "j4"]
    assert robot.joints[0].lower == -2 and robot.joints[0].upper == 2
    assert robot.joints[2].flip
    # flip: the prismatic joint moves against its DH z axis, so +q moves the tool the other way
    up = robot.fk([0, 0, 0.1, 0])[:3, 3] - robot.fk([0, 0, 0, 0])[:3, 3]
    np.testing.assert_allclose(up, [0, -0.1, 0], atol=1e-12)


def test_full_document_round_trip_all_sections_agree(tmp_path):
    robot = read_document(EXAMPLES_DIR / "rrpr.yaml")
    doc = document_from_robot(robot)
    assert list(doc) == ["robkin", "name", "joints", "gjd", "dh", "mdh", "hayati", "rpy_xyz", "poe", "poe_body"]
    for fmt in ("yaml", "json"):
        path = tmp_path / f"r.{fmt}"
        path.write_text(dump(doc, fmt))
        back = read_document(path)  # every section is cross-checked on reading
        np.testing.assert_allclose(back.fk(RRPR_Q), robot.fk(RRPR_Q), atol=1e-12)
        sections = read_sections(path)
        assert set(sections) == {"gjd", "dh", "mdh", "hayati", "rpy_xyz", "poe", "poe_body"}
        for r in sections.values():
            np.testing.assert_allclose(r.fk(RRPR_Q), robot.fk(RRPR_Q), atol=1e-12)


def test_rows_are_objects_with_named_keys_in_output():
    doc = document_from_robot(read_document(EXAMPLES_DIR / "rrpr.yaml"))
    assert set(doc["dh"]["rows"][0]) == {"a", "d", "alpha", "theta"}
    assert set(doc["rpy_xyz"]["rows"][0]) == {"roll", "pitch", "yaw", "x", "y", "z"}
    assert json.loads(dump(doc, "json"))["poe"]["frame"] == "space"


def test_yaml_output_keeps_tiny_and_full_precision_numbers():
    text = dump({"x": [1e-7, 0.123456789012345, 2.5e20]}, "yaml")
    import yaml

    assert yaml.safe_load(text)["x"] == [1e-7, 0.123456789012345, 2.5e20]


def test_paper_layout_first_row_is_base():
    doc = DOC.replace("rows:\n", "rows:\n    - [0.5, 0.1, 0, 0.3]\n")
    robot = parse_document(doc)
    base = robkin.se3.dh_matrix(0.5, 0.1, 0, 0.3)
    np.testing.assert_allclose(robot.frames[0], base, atol=1e-12)


def test_disagreeing_sections_are_named():
    bad = DOC + "poe:\n  M: [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]\n  screws: [[0,0,1,0,0,0],[0,1,0,0,0,0],[0,0,0,0,0,1],[0,0,1,0,0,0]]\n"
    with pytest.raises(InputError, match="sections dh and poe describe different robots"):
        parse_document(bad, source="x.yaml")


def test_projection_warning_names_field():
    # the 3-decimal example: one warning per projected field, each naming it (and none left over for
    # the test summary: pytest.warns would re-emit the ones its match does not take)
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        read_document(EXAMPLES_DIR / "arbitrary_3r.yaml")
    fields = [str(w.message).split(" ", 1)[0] for w in caught if issubclass(w.category, ProjectionWarning)]
    assert fields == ["poe.M:", "poe.screws[0]", "poe.screws[1]", "poe.screws[2]"], fields
    assert len(caught) == len(fields)


@pytest.mark.parametrize("text, message", [
    ("", "document is empty"),
    ("[1, 2]", "must be a mapping"),
    ("robkin: 2\njoints: [revolute]\ndh: {rows: [[0,0,0,0]]}", "version 2 is not supported"),
    ("joints: [revolute]\n", "no representation section"),
    ("dh: {rows: [[0,0,0,0]]}", "joints: missing"),
    ("joints: [{name: a, type: helical}]\ndh: {rows: [[0,0,0,0]]}", "'helical' is not one of revolute, prismatic"),
    ("joints: [revolute, revolute]\ndh: {rows: [[0,0,0,0]]}", "expected 2 rows"),
    ("joints: [revolute]\ndh: {rows: [[0,0,0]]}", r"dh.rows\[0\]: expected 4 numbers"),
    ("joints: [revolute]\ndh: {rows: [[0,0,.nan,0]]}", r"dh.rows\[0\]\[2\]: must be a finite number"),
    ("joints: [revolute]\ndh: {rows: [[0,0,'pi/0',0]]}", r"cannot read 'pi/0'"),
    ("joints: [revolute]\ndh: {rows: [[0,0,'__import__',0]]}", "cannot read"),
    ("joints: [revolute]\ndh: {rows: [{a: 0, d: 0, alpha: 0}]}", "missing theta"),
    ("joints: [revolute]\ndh: {rows: [[0,0,0,0]], colour: red}", "unknown key"),
    ("joints: [revolute]\npoe: {M: [[2,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]], screws: [[0,0,1,0,0,0]]}",
     "poe.M: rotation block"),
    ("joints: [revolute]\npoe: {M: [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]], screws: [[0,0,0,0,0,0]]}",
     r"poe.screws\[0\] \(joint 'joint1', revolute\): w must be a unit vector"),
    ("joints: [prismatic]\npoe: {M: [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]], screws: [[0,0,1,0,0,0]]}",
     "w must be 0 for a prismatic joint"),
    ("joints: [revolute]\nrpy_xyz: {rows: [[0,0,0,0,0,0]]}", "expected n \\+ 2 = 3 rows"),
    ("joints: [revolute]\ngjd: {frames: [[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]]}", "expected 2 frames"),
    ("joints: [revolute]\ndh: {rows: [[0,0,0,0]]}\nunknown: 1", "unknown key"),
    ("joints: [{name: a, type: revolute, limits: {lower: 1, upper: -1}}]\ndh: {rows: [[0,0,0,0]]}", "lower 1.0 > limits.upper"),
    ("joints: [{name: a, type: revolute}, {name: a, type: revolute}]\ndh: {rows: [[0,0,0,0],[0,0,0,0]]}", "duplicate joint name"),
    ("joints: [revolute\n", "not valid YAML"),
])
def test_bad_documents_get_one_clear_line(text, message):
    with pytest.raises(InputError, match=message) as info:
        parse_document(text, source="bad.yaml")
    assert str(info.value).startswith("bad.yaml: ")
    assert "\n" not in str(info.value)


def test_bad_json_reports_line(tmp_path):
    p = tmp_path / "bad.json"
    p.write_text('{"joints": [\n')
    with pytest.raises(InputError, match=r"bad.json: not valid JSON \(line 2"):
        read_document(p)


def test_unknown_extension_and_missing_file(tmp_path):
    with pytest.raises(InputError, match="unknown extension"):
        robkin.load(tmp_path / "robot.dat")
    with pytest.raises(InputError, match="no such file"):
        robkin.load(tmp_path / "missing.yaml")


def test_world_transform_survives_a_dh_only_document(tmp_path):
    from robkin import se3

    robot = read_document(EXAMPLES_DIR / "rrpr.yaml")
    W = se3.trans(1.0, 2.0, 0.5) @ se3.rot_z(0.3)
    moved = robot.replace(world=W)
    doc = document_from_robot(moved, ("dh",))
    path = tmp_path / "w.yaml"
    path.write_text(dump(doc, "yaml"))
    back = read_document(path)
    np.testing.assert_allclose(back.world, W, atol=1e-15)
    np.testing.assert_allclose(back.fk(RRPR_Q), robot.fk(RRPR_Q), atol=1e-12)  # world is not in FK
    # both world and rpy_xyz given: they must agree
    full = document_from_robot(moved)
    full["world"][0][3] = 9.0
    with pytest.raises(InputError, match="world and rpy_xyz"):
        parse_document(dump(full, "json"), "json")
