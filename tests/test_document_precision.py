"""Robot documents: floats read back bit-exact, ``angles: degrees``, and the warning for radians that
look like degrees."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import robkin
from robkin.io.documents.reader import AngleUnitWarning, document_from_robot, dump, parse_document

#: A robot with nearly parallel axes 2 and 3 (tilt 1e-7 rad): its DH table is ill-conditioned, so 15
#: significant digits in the written document would cost FK accuracy; repr costs none.
TILTED = """robkin: 1
joints: [revolute, revolute, revolute, revolute]
rpy_xyz:
  rows:
    - [0, 0, 0, 0, 0, 0]
    - [0, 0, 0, 0, 0, 0.3]
    - [pi/2, 0, 0, 0, 0, 0]
    - [1e-7, 0, 0, 0.4, 0.05, 0]
    - [0, 0, 0, 0.3, 0, 0]
    - [0, 0, 0, 0.1, 0, 0]
"""


def _table_values(doc: dict, key: str) -> list[float]:
    sec = doc[key]
    out = [v for row in sec["rows"] for v in (row.values() if isinstance(row, dict) else row)]
    for m in ("base", "tool"):
        if m in sec:
            out += [v for r in sec[m] for v in r]
    return out


@pytest.mark.parametrize("fmt", ["yaml", "json"])
def test_written_floats_read_back_bit_exact(fmt):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the DH table of this robot is ill-conditioned (and says so)
        robot = parse_document(TILTED)
        doc = document_from_robot(robot)
    text = dump(doc, fmt)
    import json

    import yaml

    back = yaml.safe_load(text) if fmt == "yaml" else json.loads(text)
    for key in ("dh", "mdh", "hayati", "rpy_xyz", "poe", "gjd"):
        if key == "poe":
            written = [v for r in doc[key]["M"] + doc[key]["screws"] for v in r]
            read = [v for r in back[key]["M"] + back[key]["screws"] for v in r]
        elif key == "gjd":
            written = [v for F in doc[key]["frames"] for r in F for v in r]
            read = [v for F in back[key]["frames"] for r in F for v in r]
        else:
            written, read = _table_values(doc, key), _table_values(back, key)
        assert all(type(v) is float for v in read)
        assert written == read  # bit for bit, not approximately


def test_dh_rows_in_the_document_are_the_table_bit_for_bit():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = parse_document(TILTED)
        table = robkin.dh_from_robot(robot)
        doc = document_from_robot(robot, ("dh",))
    import yaml

    rows = [[r[k] for k in ("a", "d", "alpha", "theta")] for r in yaml.safe_load(dump(doc))["dh"]["rows"]]
    assert np.array_equal(np.array(rows), table.rows)


DEG = """robkin: 1
angles: degrees
joints:
  - {name: j1, type: revolute, limits: {lower: -170, upper: 170}}
  - {name: j2, type: prismatic, limits: {lower: 0, upper: 0.5}}
  - {name: j3, type: revolute}
dh:
  rows:
    - {a: 0.1, d: 0.3, alpha: 90, theta: 0}
    - {a: 0, d: 0.2, alpha: -90, theta: 45}
    - {a: 0.05, d: 0, alpha: 0, theta: 180}
"""
RAD = DEG.replace("angles: degrees\n", "").replace("-170", f"{-math.radians(170)!r}").replace(
    "upper: 170", f"upper: {math.radians(170)!r}").replace("alpha: 90", "alpha: pi/2").replace(
    "alpha: -90", "alpha: -pi/2").replace("theta: 45", "theta: pi/4").replace("theta: 180", "theta: pi")


def test_angles_in_degrees_mean_the_same_robot():
    a, b = parse_document(DEG), parse_document(RAD)
    np.testing.assert_allclose(a.frames, b.frames, atol=1e-15)
    assert a.joints[0].lower == pytest.approx(-math.radians(170), abs=1e-15)
    assert a.joints[1].upper == 0.5  # a prismatic joint's limits are lengths, not angles


def test_degrees_are_written_when_asked_and_read_back():
    robot = parse_document(RAD)
    doc = document_from_robot(robot, ("dh", "rpy_xyz"), degrees=True)
    assert doc["angles"] == "degrees"
    assert doc["dh"]["rows"][0]["alpha"] == pytest.approx(90.0, abs=1e-12)
    assert doc["joints"][0]["limits"]["upper"] == pytest.approx(170.0, abs=1e-12)
    back = parse_document(dump(doc))
    q = robot.random_q(10, rng=0)
    np.testing.assert_allclose(back.fk(q), robot.fk(q), atol=1e-12)


def test_radians_larger_than_a_turn_warn_naming_the_field():
    text = DEG.replace("angles: degrees\n", "").replace("limits: {lower: -170, upper: 170}",
                                                       "limits: {lower: -3, upper: 3}")
    with warnings.catch_warnings(record=True) as caught:  # every one, none left for the test summary
        warnings.simplefilter("always")
        parse_document(text)
    found = [str(w.message) for w in caught if issubclass(w.category, AngleUnitWarning)]
    assert len(found) == len(caught) and found[0].startswith("dh.rows[0].alpha: 90 rad is more than a full turn")
    assert all(" rad is more than a full turn" in m for m in found)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        parse_document(RAD)  # nothing beyond a turn: no warning


def test_unknown_angle_unit_is_an_input_error():
    with pytest.raises(robkin.InputError, match="angles: 'grad' is not one of radians, degrees"):
        parse_document(DEG.replace("angles: degrees", "angles: grad"))
