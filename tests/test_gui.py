"""The browser GUI: its JSON API, its server, and the page driven for real in headless Chromium.

References are independent of the code under test: forward kinematics written out by hand from the
conversion paper's Table I (with the errata in docs/conventions.md), and pinocchio for the downloaded URDF.
The browser test needs the ``playwright`` package and a Chromium binary (Debian's ``chromium``);
without them it is skipped with the reason.
"""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import urllib.error
import urllib.request
import warnings
from pathlib import Path

import numpy as np
import pytest

import robkin
from robkin.cli import main
from robkin.viz import gui_api
from robkin.viz.gui import make_server

EXAMPLES = Path(robkin.__file__).parent / "examples"
RRPR_TEXT = (EXAMPLES / "rrpr.yaml").read_text()
PI = math.pi
TABLE_I = [(0, 0.2, -PI / 2, 0), (0.3, 0, 0, -PI / 2), (0.2, 0, PI, PI / 2), (0.1, 0, 0, 0)]
PRISMATIC = [False, False, True, False]
#: Exact up to float rounding of a few 4x4 products of metre-scale numbers.
EXACT = 1e-12
DOCS = Path(__file__).resolve().parent.parent / "docs"


def dh(a, d, alpha, theta):
    ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
    return np.array([[ct, -st * ca, st * sa, a * ct], [st, ct * ca, -ct * sa, a * st], [0, sa, ca, d], [0, 0, 0, 1]])


def rrpr_fk(q):
    """Tool pose of the RRPR robot from Table I, by hand."""
    T = np.eye(4)
    for (a, d, alpha, theta), prism, qi in zip(TABLE_I, PRISMATIC, q):
        T = T @ (dh(a, d + qi, alpha, theta) if prism else dh(a, d, alpha, theta + qi))
    return T


def pinocchio_tool(urdf_text: str, q) -> np.ndarray:
    """Pose of the URDF's last link at q, computed by pinocchio (an independent URDF reader)."""
    pin = pytest.importorskip("pinocchio")
    model = pin.buildModelFromXML(urdf_text)
    data = model.createData()
    config = pin.neutral(model)
    assert model.njoints - 1 == len(q)
    for joint, value in zip(model.joints[1:], q):  # joints in chain order, base to tip
        if joint.nq == 2:  # continuous joint (no limits): pinocchio stores (cos q, sin q)
            config[joint.idx_q:joint.idx_q + 2] = math.cos(value), math.sin(value)
        else:
            config[joint.idx_q] = value
    pin.framesForwardKinematics(model, data, config)
    tool = model.getFrameId("tool")
    return data.oMf[tool].homogeneous


# ------------------------------------------------------------------------------ the API, no browser
def test_describe_rrpr_at_q():
    q = [3 * PI / 4, -PI / 4, 0.3, -3 * PI / 4]
    res = gui_api.describe(RRPR_TEXT, "auto", q)
    np.testing.assert_allclose(res["T"], rrpr_fk(q), atol=EXACT)
    assert [j["type"] for j in res["joints"]] == ["revolute", "revolute", "prismatic", "revolute"]
    assert {"dh", "mdh", "poe", "poe_body", "rpy_xyz", "gjd"} <= set(res["document"])
    # eq. (11) of the paper: the space screws
    S = [[0, 0, 1, 0, 0, 0], [0, 1, 0, -0.2, 0, 0], [0, 0, 0, 0, 1, 0], [0, -1, 0, 0.5, 0, -0.2]]
    np.testing.assert_allclose(res["document"]["poe"]["screws"], S, atol=EXACT)
    json.dumps(res, allow_nan=False)  # what the server sends must be valid JSON


def test_describe_projects_rounded_input_and_reports_it():
    res = gui_api.describe((EXAMPLES / "arbitrary_3r.yaml").read_text())
    assert any("projected" in w or "normalised" in w for w in res["warnings"])


@pytest.mark.parametrize("text, fmt, message", [
    ("", "auto", "input: empty"),
    ("robkin: 1\njoints: [{name: a, type: revolute}]\ndh: {rows: [[0.1, 0, 0]]}\n", "auto", "dh.rows[0]"),
    ("robkin: 1\njoints: [{name: a, type: hinge}]\ndh: {rows: [[0.1, 0, 0, 0]]}\n", "auto", "hinge"),
    ("joints: [", "auto", "not valid YAML"),
    ("<robot name='x'><link name='a'/>", "auto", "input: not well-formed XML"),
    ("robkin: 1", "urdf", "urdf: expected XML"),
    ("x", "toml", "format: 'toml' is not one of"),
])
def test_bad_input_is_an_input_error(text, fmt, message):
    with pytest.raises(robkin.InputError, match=None) as err:
        gui_api.describe(text, fmt)
    assert message.lower() in str(err.value).lower()


def test_overlays_agree_with_the_robot():
    """DH, MDH, DH-from-PoE and RPY-XYZ overlays of the RRPR robot at Fig. 2's q: same tool, same axes."""
    q = [3 * PI / 4, -PI / 4, 0.3, -3 * PI / 4]
    res = gui_api.describe(RRPR_TEXT, q=q, overlay=["dh", "mdh", "poe", "rpy-xyz"])
    assert [o["label"] for o in res["overlays"]][2] == "DH rebuilt from PoE (space)"
    assert max(res["agreement"].values()) < EXACT
    for o in res["overlays"]:
        np.testing.assert_allclose(o["tool"], rrpr_fk(q), atol=EXACT, err_msg=o["label"])
    # the PoE-rebuilt chain has other link points (the paper's Table III), the DH one the same
    assert np.allclose(res["overlays"][0]["links"], res["scene"]["links"], atol=EXACT)
    assert not np.allclose(res["overlays"][2]["links"], res["scene"]["links"], atol=1e-3)
    assert gui_api.describe(RRPR_TEXT)["overlays"] == []
    with pytest.raises(robkin.InputError, match="unknown representation 'xyz'"):
        gui_api.describe(RRPR_TEXT, overlay=["xyz"])
    with pytest.raises(robkin.InputError, match="overlay: expected a list"):
        gui_api.describe(RRPR_TEXT, overlay="dh")


def test_pasted_bare_tables_are_the_papers_robot():
    """Table I pasted as DH rows and Table II as RPY-XYZ rows: both are the RRPR robot (hand FK)."""
    table_i = """# Table I of the conversion paper, with the errata
    0    0.2  -pi/2  0
    0.3  0    0      -pi/2
    0.2  0    pi     pi/2   P
    0.1, 0,   0,     0
    """
    table_ii = """-0 0 0 0 0 0
    0 0 0 0 0 0
    -pi/2 0 0 0 0 0.2
    0 0 -pi/2 0 -0.3 0  P
    pi 0 pi/2 0 0.2 0
    0 0 0 0.1 0 0"""
    q = [0.7, -1.2, 0.15, 2.1]
    for text, fmt in ((table_i, "dh-rows"), (table_ii, "rpy-rows")):
        res = gui_api.describe(text, fmt, q)
        assert [j["type"] for j in res["joints"]] == ["revolute", "revolute", "prismatic", "revolute"]
        np.testing.assert_allclose(res["T"], rrpr_fk(q), atol=EXACT, err_msg=fmt)
    with pytest.raises(robkin.InputError, match="line 2: expected 4 numbers"):
        gui_api.describe("0 0.2 0 0\n0 1 2\n", "dh-rows")
    with pytest.raises(robkin.InputError, match="line 1: cannot read 'x'"):
        gui_api.describe("x 0 0 0", "mdh-rows")
    with pytest.raises(robkin.InputError, match="at least 3"):
        gui_api.describe("0 0 0 0 0 0", "rpy-rows")


def test_export_urdf_matches_pinocchio_and_document_round_trips():
    q = [0.4, -1.1, 0.25, 2.0]
    name, mime, urdf = gui_api.export(RRPR_TEXT, "auto", "urdf")
    assert name == "rrpr.urdf" and mime == "application/xml"
    np.testing.assert_allclose(pinocchio_tool(urdf, q), rrpr_fk(q), atol=1e-9)  # 1e-9: URDF text round trip
    for to in ("yaml", "json", "dh", "mdh", "poe", "poe-body", "rpy-xyz", "gjd"):
        name, _, content = gui_api.export(RRPR_TEXT, "auto", to)
        from robkin.io.documents.reader import parse_document

        robot = parse_document(content, "json" if to == "json" else "yaml")
        np.testing.assert_allclose(robot.fk(q), rrpr_fk(q), atol=EXACT, err_msg=to)
    with pytest.raises(robkin.InputError, match="download: 'xls'"):
        gui_api.export(RRPR_TEXT, "auto", "xls")


def test_describe_pasted_urdf_chain_matches_pinocchio():
    """A pasted URDF tree with base/tip links picked: the tool pose is pinocchio's."""
    import glob

    found = glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                   "example-robot-data", "robots", "panda_description", "urdf", "panda.urdf"))
    if not found:
        pytest.skip("example-robot-data (test extra) is not installed")
    pin = pytest.importorskip("pinocchio")
    text = Path(found[0]).read_text()
    q = [0.1, -0.7, 0.2, -2.2, 0.3, 1.5, 0.6]
    res = gui_api.describe(text, "auto", q, base_link="panda_link0", tip_link="panda_link8")
    assert res["n"] == 7 and res["joints"][0]["lower"] is not None  # the Panda's joints have limits
    model = pin.buildModelFromUrdf(found[0])
    data = model.createData()
    config = pin.neutral(model)
    for name, value in zip([j["name"] for j in res["joints"]], q):
        config[model.joints[model.getJointId(name)].idx_q] = value
    pin.framesForwardKinematics(model, data, config)
    base = data.oMf[model.getFrameId("panda_link0")].homogeneous
    tool = np.linalg.inv(base) @ data.oMf[model.getFrameId("panda_link8")].homogeneous
    np.testing.assert_allclose(res["T"], tool, atol=1e-9)  # 1e-9: both parse the URDF's decimal text
    with pytest.raises(robkin.InputError, match="no_such_link"):
        gui_api.describe(text, "urdf", None, tip_link="no_such_link")


@pytest.mark.parametrize("example", sorted(p.name for p in EXAMPLES.glob("*.yaml")))
def test_every_bundled_example_shows_and_exports(example):
    """Each example the page offers: described without error, and its URDF download agrees with pinocchio."""
    text = (EXAMPLES / example).read_text()
    res = gui_api.describe(text)
    q = np.linspace(0.2, 0.5, res["n"])
    res = gui_api.describe(text, q=q.tolist())
    _, _, urdf = gui_api.export(text, "auto", "urdf")
    # 1e-9: the URDF is text; both readers compose the same decimal origins in different orders
    np.testing.assert_allclose(pinocchio_tool(urdf, q), res["T"], atol=1e-9)


def test_pasted_tables_with_a_flange_row_and_poe_screws():
    """Franka's MDH table: its flange row is a joint unless tagged or asked; PoE screws (eq. 11) + M paste."""
    q = [0.3, -0.5, 0.2, -2.0, 0.1, 1.6, 0.7]
    as_joint = gui_api.describe(FRANKA_MDH, "mdh-rows")
    assert as_joint["n"] == 8  # nothing guessed: an untagged row is a joint
    for text, tool_row in ((FRANKA_MDH, True), (FRANKA_MDH.strip() + " flange\n", False)):
        res = gui_api.describe(text, "mdh-rows", q, tool_row=tool_row)
        assert res["n"] == 7
        if PANDA.is_file():
            np.testing.assert_allclose(res["T"], _panda_fk(q), atol=1e-9)  # vendor table = URDF, to 1e-9
    with pytest.raises(robkin.InputError, match="line 1: only the last row"):
        gui_api.describe("0 0 0 0 tool\n0 0 0 0\n", "dh-rows")
    # The RRPR robot's space screws (eq. 11) and its home tool pose M
    poe = """0 0 1 0 0 0
    0 1 0 -0.2 0 0
    0 0 0 0 1 0
    0 -1 0 0.5 0 -0.2
    M 1 0 0 0.3  0 0 -1 0  0 1 0 0.5  0 0 0 1"""  # the tool at home, by hand from Table I
    qr = [0.4, -1.1, 0.25, 2.0]
    res = gui_api.describe(poe, "poe-rows", qr)
    assert [j["type"] for j in res["joints"]] == ["revolute", "revolute", "prismatic", "revolute"]
    np.testing.assert_allclose(res["T"], rrpr_fk(qr), atol=EXACT)
    with pytest.raises(robkin.InputError, match="ends with a line 'M'"):
        gui_api.describe("0 0 1 0 0 0\n", "poe-rows")
    with pytest.raises(robkin.InputError, match="line 2: expected M and 12 or 16 numbers"):
        gui_api.describe("0 0 1 0 0 0\nM 1 0 0\n", "poe-rows")


def test_ik_follows_a_target_and_lists_closed_form_branches():
    """solve_ik on the UR5 (closed form: 8 branches) and the Panda (numeric), checked with pinocchio FK."""
    ur5 = ERD / "ur_description" / "urdf" / "ur5_robot.urdf"
    if not ur5.is_file():
        pytest.skip("example-robot-data (test extra) is not installed")
    text = ur5.read_text()
    q = [0.3, -1.2, 1.4, -0.8, 1.1, 0.5]
    target = gui_api.describe(text, "urdf", q, tip_link="tool0")["T"]
    res = gui_api.solve_ik(text, "urdf", target, [0.25, -1.1, 1.3, -0.7, 1.0, 0.4], tip_link="tool0")
    assert res["success"] and len(res["solutions"]) == 8
    np.testing.assert_allclose(res["q"], q, atol=1e-9)  # the branch nearest the configuration shown
    for sol in res["solutions"]:
        np.testing.assert_allclose(pinocchio_tool_at(ur5, "tool0", sol), target, atol=1e-9)
    np.testing.assert_allclose(res["T"], target, atol=1e-9)
    np.testing.assert_allclose(res["scene"]["tool"], res["T"], atol=EXACT)  # the drawn tool is the pose
    far = np.array(target)
    far[:3, 3] *= 10  # ten times the reach
    out = gui_api.solve_ik(text, "urdf", far.tolist(), q, tip_link="tool0")
    assert not out["success"] and not out["found"] and out["q"] == q
    # the Panda, dragged 2 cm from a ready pose: one numeric step seeded with the q shown
    panda = PANDA.read_text()
    q0 = [0, -PI / 4, 0, -3 * PI / 4, 0, PI / 2, PI / 4]
    T = _panda_fk(q0)
    T[:3, 3] += [0.02, -0.01, 0.01]
    res = gui_api.solve_ik(panda, "urdf", T.tolist(), q0, "panda_link0", "panda_link8")
    assert res["success"] and res["method"] == "numeric" and res["at_limit"] == []
    np.testing.assert_allclose(_panda_fk(res["q"]), T, atol=1e-6)  # 1e-6: IK tolerance + URDF decimals
    # pushed against joint 4's upper limit (-0.0698 rad): reported
    res = gui_api.solve_ik(panda, "urdf", _panda_fk([0, 0.3, 0, -0.0698, 0, 0.5, 0]).tolist(),
                           [0, 0.3, 0, -0.2, 0, 0.5, 0], "panda_link0", "panda_link8")
    assert 3 in res["at_limit"]
    for bad, message in (("x", "target: expected a 4x4"), ([[1, 0], [0, 1]], "target: expected a 4x4")):
        with pytest.raises(robkin.InputError, match=message):
            gui_api.solve_ik(panda, "urdf", bad, q0, "panda_link0", "panda_link8")


def pinocchio_tool_at(urdf: Path, tip: str, q) -> np.ndarray:
    pin = pytest.importorskip("pinocchio")
    model = pin.buildModelFromUrdf(str(urdf))
    data = model.createData()
    config = pin.neutral(model)
    config[:len(q)] = q
    pin.framesForwardKinematics(model, data, config)
    return data.oMf[model.getFrameId(tip)].homogeneous


def test_visual_check_names_the_first_joint_that_differs():
    """RRPR against itself (same); against copies with joint 3's zero moved (an offset: J3) and with
    link 2 longer (joint 4's axis moves: J4)."""
    same = gui_api.describe(RRPR_TEXT, other={"text": RRPR_TEXT})
    assert same["check"]["comparison"]["same"] and same["check"]["first_joint"] is None
    rows = ["0 0.2 -pi/2 0", "0.3 0 0 -pi/2", "0.2 0 pi pi/2 P", "0.1 0 0 0"]
    offset = "\n".join(rows).replace("0.2 0 pi", "0.2 0.05 pi")
    res = gui_api.describe(RRPR_TEXT, q=[0.1, 0.2, 0.1, 0.3], other={"text": offset, "fmt": "dh-rows"})
    check = res["check"]
    assert check["comparison"]["equivalent"] and check["first_joint"] == 2
    assert check["comparison"]["joints"][2]["offset"] == pytest.approx(0.05, abs=EXACT)
    np.testing.assert_allclose(check["scene"]["q"], [0.1, 0.2, 0.1, 0.3])
    longer = "\n".join(rows).replace("0.3 0 0", "0.35 0 0")
    check = gui_api.describe(RRPR_TEXT, other={"text": longer, "fmt": "dh-rows"})["check"]
    assert not check["comparison"]["equivalent"] and check["first_joint"] == 3
    with pytest.raises(robkin.InputError, match="robot B: .*line 1"):
        gui_api.describe(RRPR_TEXT, other={"text": "x", "fmt": "dh-rows"})
    fewer = gui_api.describe(RRPR_TEXT, other={"text": "0 0.2 -pi/2 0\n", "fmt": "dh-rows"})
    assert fewer["check"]["first_joint"] is not None and "joint counts differ" in fewer["check"]["comparison"]["verdict"]


@pytest.fixture()
def server():
    srv = make_server(port=0, text=RRPR_TEXT, fmt="yaml")
    srv.serve_in_thread()
    yield srv
    srv.shutdown()
    srv.server_close()


def ur5_server():
    """A started GUI server on example-robot-data's UR5 (its meshes found by package path); skips the test
    without example-robot-data. The caller shuts it down."""
    ur5 = ERD / "ur_description" / "urdf" / "ur5_robot.urdf"
    if not ur5.is_file():
        pytest.skip("example-robot-data (test extra) is not installed")
    srv = make_server(port=0, text=ur5.read_text(), fmt="urdf", tip_link="tool0", source=str(ur5),
                      package_paths={"example-robot-data": ERD.parent})
    srv.serve_in_thread()
    return srv


def _post(url, payload, headers=None):
    req = urllib.request.Request(url, data=json.dumps(payload).encode(), method="POST",
                                 headers={"Content-Type": "application/json", **(headers or {})})
    with urllib.request.urlopen(req, timeout=10) as r:
        return json.loads(r.read())


def test_server_answers_errors_in_json_and_keeps_serving(server):
    bad = _post(server.url + "api/describe", {"text": "robkin: 1\njoints: 3\n"})
    assert bad["ok"] is False and "joints" in bad["error"]
    good = _post(server.url + "api/describe", {"text": RRPR_TEXT, "q": [0, 0, 0, 0]})
    assert good["ok"] is True
    np.testing.assert_allclose(good["T"], rrpr_fk([0, 0, 0, 0]), atol=EXACT)
    wrong_q = _post(server.url + "api/describe", {"text": RRPR_TEXT, "q": [0, 0]})
    assert wrong_q["ok"] is False and "q: expected 4 numbers" in wrong_q["error"]
    lenient = _post(server.url + "api/describe", {"text": RRPR_TEXT, "q": [0, 0], "strict_q": False})
    assert lenient["ok"] is True and lenient["q"] == [0, 0, 0, 0]
    assert server.url.startswith("http://127.0.0.1:")


def test_plot_html_is_the_viewer_in_one_file(tmp_path):
    """`plot -o x.html`: scene data and every module inline (nothing fetched); the tool is Fig. 2's."""
    out = tmp_path / "rrpr.html"
    q = [3 * PI / 4, -PI / 4, 0.3, -3 * PI / 4]
    assert main(["plot", str(EXAMPLES / "rrpr.yaml"), "--q", "3*pi/4,-pi/4,0.3,-3*pi/4", "--overlay", "dh,poe",
                 "-o", str(out)]) == 0
    page = out.read_text()
    data = json.loads(re.search(r'<script type="application/json" id="robkin-data">(.*?)</script>', page, re.S)
                      .group(1))
    np.testing.assert_allclose(data["scene"]["tool"], rrpr_fk(q), atol=EXACT)
    assert [o["label"] for o in data["overlays"]] == ["DH", "DH rebuilt from PoE (space)"]
    for o in data["overlays"]:
        np.testing.assert_allclose(o["tool"], rrpr_fk(q), atol=EXACT)
    names = re.findall(r'<script type="text/x-robkin-module" data-name="([^"]+)">', page)
    assert {"three", "three/core", "three/addons/controls/OrbitControls.js", "robkin/viewer.js"} <= set(names)
    assert not re.search(r"""\b(src|href)=["']?(https?:|//)""", page)  # no external resources
    assert page.count("</script>") == len(names) + 2  # embedded text never ends its script early
    # two robots of different joint counts cannot share q: refused, nothing written
    bad = tmp_path / "bad.html"
    assert main(["plot", str(EXAMPLES / "rrpr.yaml"), str(EXAMPLES / "arbitrary_3r.yaml"), "-o", str(bad)]) == 2
    assert not bad.exists()


def test_server_serves_vendored_modules_and_meshes_by_id_only(server, tmp_path):
    from robkin.viz.meshes import MeshRegistry

    with urllib.request.urlopen(server.url, timeout=10) as r:
        csp = r.headers["Content-Security-Policy"]
        page = r.read().decode()
    assert "script-src 'self' 'sha256-" in csp and '<script type="importmap">' in page  # only that inline script
    with urllib.request.urlopen(server.url + "static/vendor/addons/controls/TransformControls.js", timeout=10) as r:
        assert r.headers["Content-Type"].startswith("text/javascript")
    stl = tmp_path / "link.stl"
    stl.write_bytes(b"solid x\nendsolid x\n")
    server.meshes = MeshRegistry(files={"m0": stl})
    with urllib.request.urlopen(server.url + "api/mesh/m0", timeout=10) as r:
        assert r.read() == stl.read_bytes() and r.headers["Content-Type"] == "model/stl"
    for path in ("api/mesh/m1", "api/mesh/" + str(stl), "api/mesh/../static/app.js", "static/vendor/LICENSE",
                 "static/vendor/../gui.py"):
        with pytest.raises(urllib.error.HTTPError) as err:
            urllib.request.urlopen(server.url + path, timeout=10)
        assert err.value.code == 404, path


def test_gui_refuses_to_start_without_three_js(monkeypatch, tmp_path, capsys):
    from robkin.viz import assets

    monkeypatch.setattr(assets, "VENDOR_DIR", tmp_path / "vendor")
    assert main(["gui", "--port", "0"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "three.js" in err and "make assets" in err
    page = tmp_path / "r.html"
    assert main(["plot", str(EXAMPLES / "rrpr.yaml"), "-o", str(page)]) == 2 and not page.exists()
    assert "make assets" in capsys.readouterr().err
    # what `make assets` runs after `npm ci`: copies exactly the listed modules, or says what is missing
    fake = tmp_path / "node_modules"
    for name, src in assets.VENDOR.items():
        (fake / src).parent.mkdir(parents=True, exist_ok=True)
        (fake / src).write_text(f"// {name}\n")
    assert assets.main([str(fake)]) == 0 and assets.missing_assets() == []
    assert (tmp_path / "vendor" / "three.module.js").read_text() == "// three.module.js\n"
    (fake / assets.VENDOR["three.core.js"]).unlink()
    assert assets.main([str(fake)]) == 2 and "npm ci" in capsys.readouterr().err


def test_start_payload_has_the_default_example_and_robot_b(tmp_path):
    srv = make_server(port=0, text=RRPR_TEXT, fmt="yaml", other={"text": RRPR_TEXT, "fmt": "yaml", "source": "b.yaml"})
    try:
        assert srv.start_payload["other"]["source"] == "b.yaml" and srv.start_payload["visuals"] == []
        assert srv.start_payload["default_example"] in srv.start_payload["examples"]  # what --help promises
    finally:
        srv.server_close()
    bad = tmp_path / "b.yaml"
    bad.write_text("robkin: 1\njoints: []\n")
    assert main(["gui", str(EXAMPLES / "rrpr.yaml"), str(bad), "--port", "0"]) == 2


def test_server_refuses_foreign_hosts_and_paths(server):
    req = urllib.request.Request(server.url, headers={"Host": "attacker.example"})
    with pytest.raises(urllib.error.HTTPError) as err:
        urllib.request.urlopen(req, timeout=10)
    assert err.value.code == 403
    for path in ("static/../gui.py", "static/%2e%2e/gui.py", "etc/passwd", "static/.hidden.js"):
        with pytest.raises(urllib.error.HTTPError) as err:
            urllib.request.urlopen(server.url + path, timeout=10)
        assert err.value.code == 404, path
    with pytest.raises(urllib.error.HTTPError) as err:
        _post(server.url + "api/describe", "not an object")
    assert err.value.code == 400
    with urllib.request.urlopen(server.url + "api/start", timeout=10) as r:
        start = json.loads(r.read())
    assert start["text"] == RRPR_TEXT and "rrpr" in start["examples"]


def _get(url):
    with urllib.request.urlopen(url, timeout=10) as r:
        return json.loads(r.read())


@pytest.fixture()
def toy():
    """The toy representation of test_registry (a standard DH table in millimetres), registered for one test."""
    from robkin.representations import registry
    from test_registry import TOY

    registry.register(TOY)
    try:
        yield TOY
    finally:
        registry.unregister(TOY.name)


def test_the_page_is_told_the_registry(server, toy):
    """GET /api/representations: each table as the page shows it, the overlay checkboxes and the download
    buttons, with today's labels and order; a registered representation follows, read on each request."""
    reps = _get(server.url + "api/representations")
    by = {r["name"]: r for r in reps["representations"]}
    assert list(by) == ["dh", "mdh", "hayati", "poe", "poe-body", "rpy-xyz", "gjd", "dh-mm"]
    assert [(r["section"], r["layout"]) for r in reps["representations"]][3:6] == [
        ("poe", "screws"), ("poe_body", "screws"), ("rpy_xyz", "rpy")]
    assert [c["label"] for c in by["mdh"]["columns"]] == ["a(i-1)", "d", "α(i-1)", "θ"]
    assert [c["label"] for c in by["hayati"]["columns"]] == ["a", "d", "α", "θ", "β"]
    assert [c["label"] for c in by["poe"]["columns"]] == ["ωx", "ωy", "ωz", "vx", "vy", "vz"]
    assert [c["angle"] for c in by["rpy-xyz"]["columns"]] == [True] * 3 + [False] * 3
    assert by["dh"]["title"] == "Standard DH  A = Rz(θ) Tz(d) Tx(a) Rx(α)"
    assert by["poe-body"]["mass_frame"] == "the tool frame M at home"
    # the toy declares no GUI wording: its title, the registry's mass frame, its name as button text
    assert by["dh-mm"]["title"] == "standard DH (mm)" and by["dh-mm"]["mass_frame"].startswith("link frame {i}")
    assert [(o["name"], o["label"]) for o in reps["overlays"]] == [
        ("dh", "DH"), ("mdh", "modified DH"), ("poe", "DH from PoE"), ("rpy-xyz", "RPY-XYZ"), ("dh-mm", "DH (mm)")]
    assert [(d["name"], d["label"]) for d in reps["downloads"]] == [
        ("dh", "DH"), ("mdh", "MDH"), ("poe", "PoE"), ("poe-body", "PoE body"), ("rpy-xyz", "RPY-XYZ"),
        ("hayati", "Hayati"), ("gjd", "GJD"), ("dh-mm", "dh-mm")]
    from robkin.representations import registry

    registry.unregister(toy.name)
    try:
        assert "dh-mm" not in [r["name"] for r in _get(server.url + "api/representations")["representations"]]
    finally:
        registry.register(toy)


def test_cli_gui_serves_then_stops():
    """`robkin gui --port 0` in a subprocess: prints its address, serves the page, stops on SIGINT."""
    import signal

    proc = subprocess.Popen([sys.executable, "-m", "robkin.cli", "gui", str(EXAMPLES / "rrpr.yaml"), "--port", "0"],
                            stderr=subprocess.PIPE, text=True)
    try:
        line = proc.stderr.readline()
        assert "serving on http://127.0.0.1:" in line
        url = line.split("serving on ")[1].split()[0]
        with urllib.request.urlopen(url, timeout=10) as r:
            assert b"<div id=\"view\"" in r.read()
        proc.send_signal(signal.SIGINT)
        assert proc.wait(timeout=10) == 0
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def test_cli_gui_two_urdfs_share_the_chain():
    """`robkin gui A.urdf B.urdf --base-link --tip-link`: B gets the same chain; the page's check says same."""
    import signal

    if not PANDA.is_file():
        pytest.skip("example-robot-data (test extra) is not installed")
    proc = subprocess.Popen([sys.executable, "-m", "robkin.cli", "gui", str(PANDA), str(PANDA), "--base-link",
                             "panda_link0", "--tip-link", "panda_link8", "--port", "0"], stderr=subprocess.PIPE, text=True)
    try:
        url = proc.stderr.readline().split("serving on ")[1].split()[0]
        with urllib.request.urlopen(url + "api/start", timeout=10) as r:
            start = json.loads(r.read())
        other = start["other"]
        assert (other["base_link"], other["tip_link"]) == ("panda_link0", "panda_link8")
        res = _post(url + "api/describe", {"text": start["text"], "base_link": "panda_link0", "tip_link": "panda_link8",
                                           "other": other})
        assert res["ok"] and res["check"]["comparison"]["same"], res.get("error")
        proc.send_signal(signal.SIGINT)
        assert proc.wait(timeout=10) == 0
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def test_cli_gui_bad_input(tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    bad.write_text("robkin: 1\njoints: []\n")
    assert main(["gui", str(bad), "--port", "0"]) == 2
    err = capsys.readouterr().err
    assert str(bad) in err and err.count("\n") == 1
    assert main(["gui", "--port", "70000"]) == 2


# ------------------------------------------------------------------------------ the page, in Chromium
# WebGL through Chromium's software renderer (SwiftShader): no GPU needed, same pictures everywhere.
CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
                  "--ignore-gpu-blocklist", "--disable-quic", "--no-first-run",
                  "--disable-background-networking", "--disable-component-update", "--disable-sync"]


def _chromium() -> str | None:
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


def _skip_or_fail(reason: str) -> None:
    """Skip, unless CI (which installs Chromium) says the browser test must run."""
    if os.environ.get("ROBKIN_REQUIRE_BROWSER") == "1":
        pytest.fail(f"ROBKIN_REQUIRE_BROWSER=1 but {reason}")
    pytest.skip(reason)


@pytest.fixture(scope="module")
def browser():
    """One headless Chromium for the module's browser tests (each gets its own page)."""
    try:
        from playwright import sync_api
    except ImportError:
        _skip_or_fail("the browser test needs the playwright package (test extra)")
    exe = _chromium()
    if exe is None:
        _skip_or_fail("no Chromium installed (apt-get install chromium); the browser test needs one")
    with sync_api.sync_playwright() as pw, tempfile.TemporaryDirectory() as profile:
        ctx = pw.chromium.launch_persistent_context(profile, executable_path=exe, headless=True, args=CHROMIUM_FLAGS,
                                                    accept_downloads=True, viewport={"width": 1500, "height": 950})
        yield ctx
        ctx.close()


def _serving(browser, srv):
    """Start the GUI server ``srv``, yield a page on it (``_open``), then shut the server down."""
    srv.serve_in_thread()
    try:
        yield from _open(browser, srv.url)
    finally:
        srv.shutdown()
        srv.server_close()


def _open(browser, url: str):
    """A page at ``url``, ready; after the test, no JavaScript or console errors may have happened."""
    pg = browser.new_page()
    errors: list[str] = []
    pg.on("pageerror", lambda e: errors.append(str(e)))
    pg.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    pg.goto(url)
    pg.wait_for_selector("body[data-state=ready]", timeout=15000)
    yield pg
    pg.close()
    assert not errors, f"JavaScript or console errors in the page: {errors}"


@pytest.fixture()
def page(browser, server):
    yield from _open(browser, server.url)


def _wait_update(pg, before: int) -> None:
    # A function, not a string: the page's Content-Security-Policy forbids eval of strings.
    pg.wait_for_function("(n) => Number(document.body.dataset.updates) > n && document.body.dataset.state != 'busy'",
                         arg=before, timeout=15000)


def _updates(pg) -> int:
    return int(pg.get_attribute("body", "data-updates"))


def _pose(pg) -> np.ndarray:
    T = np.eye(4)
    for cell in pg.query_selector_all("#pose-table td[data-rc]"):
        r, c = map(int, cell.get_attribute("data-rc").split(","))
        T[r, c] = float(cell.get_attribute("title"))  # the title holds the full-precision number
    return T


def test_browser_load_move_check_download(page, tmp_path):
    pg = page
    # The robot given on the command line is shown: Table I in the DH table, eq. (11) in the PoE table.
    dh_cells = [c.inner_text() for c in pg.query_selector_all("#table-dh tr:nth-child(2) td")]
    assert dh_cells[1:] == ["0", "0.2", "-1.570796327", "0"]  # rounded for display: 10 digits
    pg.select_option("#units", "deg")  # display only: the tables show degrees, the robot is unchanged
    pg.wait_for_function("() => document.querySelector('#table-dh tr:nth-child(2) td:nth-child(4)').textContent == '-90'")
    assert "α (°)" in pg.inner_text("#table-dh")
    pg.select_option("#units", "rad")
    pg.wait_for_function("() => document.querySelector('#table-dh tr:nth-child(2) td:nth-child(4)').textContent != '-90'")
    assert len(pg.query_selector_all("#sliders input[type=range]")) == 4
    np.testing.assert_allclose(_pose(pg), rrpr_fk([0, 0, 0, 0]), atol=EXACT)

    # Move joint 1's slider with the mouse: click at 3/4 of its track.
    before = _updates(pg)
    box = pg.query_selector("#q0").bounding_box()
    pg.mouse.click(box["x"] + 0.75 * box["width"], box["y"] + box["height"] / 2)
    _wait_update(pg, before)
    q = [float(pg.input_value(f"#q{i}")) for i in range(4)]
    # the slider moved; the others stayed at 0 (up to the slider's step grid rounding, ~1e-16)
    assert 0.5 < q[0] < 2.5 and np.allclose(q[1:], 0, atol=1e-12)
    np.testing.assert_allclose(_pose(pg), rrpr_fk(q), atol=EXACT)
    # and the prismatic joint with the keyboard
    before = _updates(pg)
    pg.focus("#q2")
    for _ in range(40):
        pg.keyboard.press("ArrowRight")
    _wait_update(pg, before)
    pg.wait_for_function("() => document.body.dataset.state == 'ready'")
    q = [float(pg.input_value(f"#q{i}")) for i in range(4)]
    assert q[2] > 0
    np.testing.assert_allclose(_pose(pg), rrpr_fk(q), atol=EXACT)

    # Bad input: a message in the page, no crash; fixing it brings the robot back.
    before = _updates(pg)
    pg.fill("#robot-text", RRPR_TEXT.replace("type: prismatic", "type: slider"))
    pg.wait_for_selector("#error:not([hidden])", timeout=15000)
    assert "slider" in pg.inner_text("#error") and "prismatic" in pg.inner_text("#error")
    pg.fill("#robot-text", RRPR_TEXT)
    _wait_update(pg, before)
    assert pg.is_hidden("#error")

    # A bare DH table pasted from the paper (Table I), with its format chosen in the page.
    before = _updates(pg)
    pg.select_option("#format", "dh-rows")
    pg.fill("#robot-text", "0 0.2 -pi/2 0\n0.3 0 0 -pi/2\n0.2 0 pi pi/2 P\n0.1 0 0 0\n")
    _wait_update(pg, before)
    pg.wait_for_function("() => document.body.dataset.state == 'ready'")
    q = [float(pg.input_value(f"#q{i}")) for i in range(4)]
    np.testing.assert_allclose(_pose(pg), rrpr_fk(q), atol=EXACT)
    assert "(P)" in pg.inner_text("#sliders")

    # Overlay the DH table rebuilt from PoE: drawn, and the page states that it agrees.
    before = _updates(pg)
    pg.check("#ov-poe")
    _wait_update(pg, before)
    pg.wait_for_function("() => document.body.dataset.state == 'ready'")
    text = pg.inner_text("#agreement")
    assert "DH rebuilt from PoE (space)" in text
    diffs = [float(x) for x in re.findall(r"by (\S+?) \(position\), (\S+?) \(rotation\); joint axes by (\S+?)\.$",
                                            text)[0]]
    assert max(diffs) < EXACT
    before = _updates(pg)
    pg.uncheck("#ov-poe")
    _wait_update(pg, before)
    assert pg.is_hidden("#agreement")

    # Paste another robot (the arbitrary 3R): sliders and tables follow, warnings are shown.
    before = _updates(pg)
    pg.select_option("#example", "arbitrary_3r")
    _wait_update(pg, before)
    assert len(pg.query_selector_all("#sliders input[type=range]")) == 3
    assert "projected" in pg.inner_text("#warnings")
    assert len(pg.query_selector_all("#table-rpy_xyz tr")) == 1 + 3 + 2

    # Downloads: the URDF agrees with pinocchio, the YAML document reads back to the same robot.
    # Load a file (the RRPR robot as a JSON document): the format follows the file's extension.
    from robkin.io.documents.reader import document_from_robot, dump

    json_file = tmp_path / "rrpr_in.json"
    json_file.write_text(dump(document_from_robot(robkin.load(EXAMPLES / "rrpr.yaml"), ("poe",)), "json"))
    before = _updates(pg)
    pg.set_input_files("#file", str(json_file))
    _wait_update(pg, before)
    assert pg.input_value("#format") == "json" and pg.is_hidden("#error")
    assert len(pg.query_selector_all("#sliders input[type=range]")) == 4
    with pg.expect_download() as dl:
        pg.click("#dl-urdf")
    urdf_path = tmp_path / dl.value.suggested_filename
    dl.value.save_as(urdf_path)
    assert urdf_path.name == "rrpr.urdf"
    qt = [0.3, -0.7, 0.15, 1.2]
    np.testing.assert_allclose(pinocchio_tool(urdf_path.read_text(), qt), rrpr_fk(qt), atol=1e-9)
    with pg.expect_download() as dl:
        pg.click("#dl-yaml")
    yaml_path = tmp_path / dl.value.suggested_filename
    dl.value.save_as(yaml_path)
    np.testing.assert_allclose(robkin.load(yaml_path).fk(qt), rrpr_fk(qt), atol=EXACT)

    # A screenshot of Table I's robot at the paper's Fig. 2 configuration with the DH table rebuilt
    # from PoE overlaid, like the paper's Fig. 2 (docs/ if ROBKIN_UPDATE_DOCS=1).
    before = _updates(pg)
    pg.select_option("#example", "rrpr")
    _wait_update(pg, before)
    before = _updates(pg)
    pg.check("#ov-poe")
    _wait_update(pg, before)
    before = _updates(pg)
    pg.evaluate("""(q) => q.forEach((v, i) => { const s = document.getElementById('q' + i);
                                                s.value = String(v); s.dispatchEvent(new Event('input')); })""",
                [3 * PI / 4, -PI / 4, 0.3, -3 * PI / 4])
    _wait_update(pg, before)
    pg.wait_for_function("() => document.body.dataset.state == 'ready'")
    pg.click("#view-fit")
    shot = (DOCS if os.environ.get("ROBKIN_UPDATE_DOCS") == "1" else tmp_path) / "gui.png"
    pg.screenshot(path=str(shot), full_page=True)
    assert shot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"

    # The self-contained page of `plot -o robot.html`, opened from disk: it draws (WebGL) without errors.
    page_file = tmp_path / "rrpr_q.html"
    assert main(["plot", str(EXAMPLES / "rrpr.yaml"), "--q", "3*pi/4,-pi/4,0.3,-3*pi/4", "--overlay", "dh,poe",
                 "-o", str(page_file)]) == 0
    pg.goto(page_file.as_uri())
    pg.wait_for_selector("body[data-state=ready]", timeout=15000)
    assert int(pg.get_attribute("#view", "data-frames")) >= 1 and "DH rebuilt from PoE" in pg.inner_text(".legend")
    _shot(pg, tmp_path, "plot_html.png")


@pytest.fixture()
def toy_page(toy, browser, server):
    """The page, opened after the toy representation was registered (the server runs in this process)."""
    yield from _open(browser, server.url)


def test_browser_shows_a_registered_representation(toy_page, tmp_path):
    """A representation registered in the library (a DH table in mm), with no change to the page's code:
    its section (after the GJD's, before the URDF), its download and its overlay checkbox."""
    pg = toy_page
    sections = [e.get_attribute("id") for e in pg.query_selector_all("#tables > details")]
    assert sections == ["section-" + s for s in ("dh", "mdh", "hayati", "poe", "poe_body", "rpy_xyz", "gjd", "dh_mm",
                                                 "urdf")]
    assert pg.inner_text("#section-dh_mm summary") == "standard DH (mm)"
    head = [c.inner_text() for c in pg.query_selector_all("#table-dh_mm tr:first-child th")]
    assert head == ["joint", "a_mm", "d_mm", "alpha", "theta"]
    rows = pg.query_selector_all("#table-dh_mm tr")[1:]
    want = [[a * 1000, d * 1000, alpha, theta] for a, d, alpha, theta in TABLE_I]
    got = [[float(c.get_attribute("title")) for c in r.query_selector_all("td")[1:]] for r in rows]
    np.testing.assert_allclose(got, want, atol=1e-9)  # mm: 1e-9 of a 300 mm length is rounding
    assert "base" in pg.inner_text("#section-dh_mm") and "tool" in pg.inner_text("#section-dh_mm")
    pg.select_option("#units", "deg")  # its angle columns follow the unit
    pg.wait_for_function("() => document.querySelector('#table-dh_mm tr:nth-child(2) td:nth-child(4)').textContent == '-90'")
    assert "alpha (°)" in pg.inner_text("#table-dh_mm")

    assert pg.inner_text("#dl-dh-mm") == "dh-mm"
    with pg.expect_download() as dl:
        pg.click("#dl-dh-mm")
    path = tmp_path / dl.value.suggested_filename
    dl.value.save_as(path)
    assert path.name == "rrpr_dh_mm.yaml"
    qt = [0.3, -0.7, 0.15, 1.2]
    np.testing.assert_allclose(robkin.load(path).fk(qt), rrpr_fk(qt), atol=1e-9)

    assert pg.inner_text("label:has(#ov-dh-mm)").strip() == "DH (mm)"
    before = _updates(pg)
    pg.check("#ov-dh-mm")
    _wait_update(pg, before)
    _settled(pg)
    text = pg.inner_text("#agreement")
    assert "DH (mm) vs. the robot as given" in text  # after the legend's dashes in the overlay's colour
    diffs = [float(x) for x in re.findall(r"by (\S+?) \(position\), (\S+?) \(rotation\); joint axes by (\S+?)\.$",
                                            text)[0]]
    assert max(diffs) < 1e-9


# ------------------------------------------------------------------------------ a real arm, in Chromium
ERD = Path(sys.prefix) / "lib" / f"python{sys.version_info.major}.{sys.version_info.minor}" / "site-packages" / \
    "cmeel.prefix" / "share" / "example-robot-data" / "robots"
PANDA = ERD / "panda_description" / "urdf" / "panda.urdf"
#: Franka's published modified-DH table (a(i-1), d, alpha(i-1), theta) with its flange row last.
FRANKA_MDH = """0 0.333 0 0
0 0 -pi/2 0
0 0.316 pi/2 0
0.0825 0 pi/2 0
-0.0825 0.384 -pi/2 0
0 0 pi/2 0
0.088 0 pi/2 0
0 0.107 0 0
"""


def _panda_fk(q) -> np.ndarray:
    """pinocchio: panda_link8 in panda_link0 at q (the 7 arm joints; fingers at 0)."""
    pin = pytest.importorskip("pinocchio")
    model = pin.buildModelFromUrdf(str(PANDA))
    data = model.createData()
    config = pin.neutral(model)
    for i, value in enumerate(q):
        config[model.joints[model.getJointId(f"panda_joint{i + 1}")].idx_q] = value
    pin.framesForwardKinematics(model, data, config)
    base = data.oMf[model.getFrameId("panda_link0")].homogeneous
    return np.linalg.inv(base) @ data.oMf[model.getFrameId("panda_link8")].homogeneous


@pytest.fixture()
def panda_page(browser):
    if not PANDA.is_file():
        pytest.skip("example-robot-data (test extra) is not installed")
    srv = make_server(port=0, text=PANDA.read_text(), fmt="urdf", base_link="panda_link0", tip_link="panda_link8",
                      source=str(PANDA))
    yield from _serving(browser, srv)


def _shot(pg, tmp_path, name: str) -> None:
    """Screenshot of the page (into docs/ with ROBKIN_UPDATE_DOCS=1, for the README and docs/gui.md)."""
    path = (DOCS if os.environ.get("ROBKIN_UPDATE_DOCS") == "1" else tmp_path) / name
    pg.screenshot(path=str(path))
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def _settled(pg) -> None:
    pg.wait_for_function("() => document.body.dataset.state == 'ready'", timeout=15000)


def test_browser_shows_each_links_mass_properties(panda_page):
    """Under DH, modified DH, Hayati, PoE and RPY-XYZ: one row per link with m, r, I (headers with units),
    each cell's title the full-precision number of the table (in the frame the caption names)."""
    pg = panda_page
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = robkin.load(str(PANDA), base_link="panda_link0", tip_link="panda_link8")
    for key, table in (("dh", robkin.dh_from_robot(robot)), ("mdh", robkin.mdh_from_robot(robot)),
                       ("rpy_xyz", robkin.rpy_from_robot(robot))):
        # three narrow tables side by side or stacked: m and r, the moments, the products of inertia
        parts = [pg.query_selector_all(f"#{part}-{key} tr") for part in ("mass", "inertia", "products")]
        # the header, the base (panda_link0's 0.63 kg), the links
        assert [len(rows) for rows in parts] == [2 + robot.n] * 3
        head = [c.inner_text() for rows in parts for c in rows[0].query_selector_all("th")[1:]]
        assert head[:4] == ["m (kg)", "rx (m)", "ry (m)", "rz (m)"] and head[-1] == "Ixz (kg m²)" and len(head) == 10
        m = table.masses
        assert all(rows[1].query_selector("td").inner_text() == "base" for rows in parts)
        expected = [[m.base.mass[0], *m.base.com[0], *m.base.six[0]]] + \
            [[m.mass[i], *m.com[i], *m.six[i]] for i in range(robot.n)]
        for i, want in enumerate(expected):
            got = [float(c.get_attribute("title")) for rows in parts for c in rows[1 + i].query_selector_all("td")[1:]]
            assert got == want
    assert pg.query_selector("#mass-hayati") and pg.query_selector("#mass-poe") and pg.query_selector("#mass-poe_body")
    assert "frame {i} (after joint i)" in pg.inner_text("#section-dh")


_LAYOUT = """() => {
  const out = {page: document.documentElement.scrollWidth - window.innerWidth, over: [], wrapped: []};
  for (const sec of document.querySelectorAll("main > section")) {
    const right = sec.getBoundingClientRect().right + 1;  // 1 px: sub-pixel rounding of the layout
    for (const e of sec.querySelectorAll("select, input, textarea, table, pre, .matrices")) {
      const r = e.getBoundingClientRect();
      if (r.width && r.right > right) out.over.push(`${sec.id} ${e.tagName} ${e.id} ${r.right - right}`);
    }
  }
  for (const tr of document.querySelectorAll("#table-dh tr, #table-hayati tr")) {
    const cells = tr.querySelectorAll("td");
    if (cells.length > 1 && cells[0].getBoundingClientRect().height > 1.5 * cells[1].getBoundingClientRect().height)
      out.wrapped.push(cells[0].textContent);
  }
  return out;
}"""


@pytest.mark.parametrize("width", [1280, 1400])
def test_browser_layout_fits_1280_and_1400_wide(panda_page, width, tmp_path):
    # The page never scrolls sideways; form fields and tables stay inside their panels (a table wider
    # than its panel scrolls inside it); joint names are not wrapped.
    pg = panda_page
    pg.set_viewport_size({"width": width, "height": 900})
    pg.wait_for_timeout(200)  # one layout pass after the resize
    found = pg.evaluate(_LAYOUT)
    assert found["page"] <= 0, f"the page scrolls sideways by {found['page']} px at {width} px"
    assert not found["over"], found["over"]
    assert not found["wrapped"], found["wrapped"]


def test_browser_panda_orbit_drag_paste_check(panda_page, tmp_path):
    pg = panda_page
    view = pg.query_selector("#view")
    assert len(pg.query_selector_all("#sliders input[type=range]")) == 7
    names = pg.inner_text("#sliders")
    assert all(f"panda_joint{i}" in names for i in range(1, 8))  # untruncated
    assert "panda_link8" in [o.get_attribute("value") for o in pg.query_selector_all("#tip-link option")]
    q = [float(pg.input_value(f"#q{i}")) for i in range(7)]
    np.testing.assert_allclose(_pose(pg), _panda_fk(q), atol=1e-9)  # 1e-9: both read the URDF's decimals
    import importlib.util

    if importlib.util.find_spec("robkin.bodies"):  # robots carry their visuals: the Panda's 11 meshes load
        pg.wait_for_function("() => document.body.dataset.meshes == '11'", timeout=30000)
    _shot(pg, tmp_path, "gui_panda.png")

    # Orbit: a left drag on empty space turns the camera (the picture changes, the robot does not).
    box = view.bounding_box()
    before = view.screenshot()
    pg.mouse.move(box["x"] + 40, box["y"] + box["height"] - 40)
    pg.mouse.down()
    pg.mouse.move(box["x"] + 160, box["y"] + box["height"] - 60, steps=8)
    pg.mouse.up()
    assert view.screenshot() != before
    assert [float(pg.input_value(f"#q{i}")) for i in range(7)] == q
    pg.click("#view-reset")

    # Drag the tool frame's centre handle: the robot follows by IK; the q shown puts the tool at the target.
    # (From Franka's "ready" pose: at home the arm is stretched up with joint 4 on its limit.)
    before = _updates(pg)
    pg.evaluate("""(q) => q.forEach((v, i) => { const s = document.getElementById('q' + i);
                                                s.value = String(v); s.dispatchEvent(new Event('input')); })""",
                [0, -PI / 4, 0, -3 * PI / 4, 0, PI / 2, PI / 4])
    _wait_update(pg, before)
    _settled(pg)
    q = [float(pg.input_value(f"#q{i}")) for i in range(7)]
    x, y = map(float, view.get_attribute("data-tool-xy").split(","))
    before = _updates(pg)
    pg.mouse.move(box["x"] + x, box["y"] + y)
    pg.mouse.down()
    pg.mouse.move(box["x"] + x - 40, box["y"] + y + 30, steps=15)
    pg.mouse.up()
    _wait_update(pg, before)
    _settled(pg)
    assert int(pg.get_attribute("body", "data-ik-updates")) >= 2
    target = np.array(json.loads(view.get_attribute("data-target")))
    q2 = [float(pg.input_value(f"#q{i}")) for i in range(7)]
    assert np.linalg.norm(target[:3, 3] - _panda_fk(q)[:3, 3]) > 0.01  # the target moved by centimetres
    assert pg.get_attribute("body", "data-ik-success") == "true", pg.inner_text("#ik-status")
    np.testing.assert_allclose(_panda_fk(q2), target, atol=1e-6)  # 1e-6: IK tolerance 1e-9 + URDF decimals
    np.testing.assert_allclose(_pose(pg), _panda_fk(q2), atol=1e-9)
    _shot(pg, tmp_path, "gui_drag.png")

    # Paste Franka's modified-DH table with its flange row, answered as "the tool": 7 joints, the same arm.
    before = _updates(pg)
    pg.select_option("#format", "mdh-rows")
    pg.select_option("#last-row", "tool")
    pg.fill("#robot-text", FRANKA_MDH)
    _wait_update(pg, before)
    _settled(pg)
    assert len(pg.query_selector_all("#sliders input[type=range]")) == 7
    q3 = [float(pg.input_value(f"#q{i}")) for i in range(7)]
    np.testing.assert_allclose(_pose(pg), _panda_fk(q3), atol=1e-9)  # published table = URDF to 1e-9
    # copies are full precision: the d column of the DH table has 0.107, not a rounded number
    pg.click("#section-mdh button.copy")
    assert "0.316" in pg.get_attribute("body", "data-copied")
    # the Hayati table is shown too: a header row and one row per joint
    assert len(pg.query_selector_all("#table-hayati tr")) == 8
    before = _updates(pg)
    pg.select_option("#last-row", "joint")
    _wait_update(pg, before)
    assert len(pg.query_selector_all("#sliders input[type=range]")) == 8  # not silently: only when asked

    # Visual check: B = the same table with row 5's d 6 mm longer, drawn over A; the joint check names is red.
    before = _updates(pg)
    pg.select_option("#last-row", "tool")
    pg.click("#check-panel summary")
    pg.select_option("#other-format", "mdh-rows")
    pg.fill("#other-text", FRANKA_MDH.replace("0.384", "0.39").replace("0 0.107 0 0", "0 0.107 0 0 flange"))
    _wait_update(pg, before)
    _settled(pg)
    pg.wait_for_selector("#check:not([hidden])")
    assert "different robots" in pg.inner_text("#check-verdict")
    assert pg.inner_text("#check-first").startswith("first joint that differs: J")
    first = int(pg.inner_text("#check-first").split("J")[1].split()[0])
    from robkin.equivalence import compare
    from robkin.viz.table_text import document_from_table
    from robkin.io.documents.reader import parse_document

    a = parse_document(json.dumps(document_from_table(FRANKA_MDH, "mdh-rows", True)), "json")
    b = parse_document(json.dumps(document_from_table(FRANKA_MDH.replace("0.384", "0.39"), "mdh-rows", True)), "json")
    expected = next(m.index for m in compare(a, b).joints if m.status != "same")
    assert first == expected + 1
    assert pg.query_selector(f"#check-joints tr.differs td") is not None
    _shot(pg, tmp_path, "gui_check.png")


def _ur5_copy(tmp_path) -> Path:
    """example-robot-data's UR5 URDF copied out of its package (as the README's tour does)."""
    src = PANDA.parents[2] / "ur_description" / "urdf" / "ur5_robot.urdf"
    if not src.is_file():
        pytest.skip("example-robot-data (test extra) is not installed")
    path = tmp_path / "ur5.urdf"
    path.write_text(src.read_text())
    return path


def test_browser_gui_says_which_meshes_were_not_found(browser, tmp_path):
    """A URDF whose meshes cannot be found is no silent stick figure: the page names them and why."""
    path = _ur5_copy(tmp_path)
    srv = make_server(port=0, text=path.read_text(), fmt="urdf", tip_link="tool0", source=str(path))
    assert srv.start_payload["visuals"] == [] and len(srv.start_payload["missing_meshes"]) == 7
    srv.serve_in_thread()
    try:
        for pg in _open(browser, srv.url):
            pg.wait_for_function("() => document.getElementById('warnings').textContent.includes('not found')",
                                 timeout=15000)
            text = pg.inner_text("#warnings")
            assert "7 of 7 mesh files not found" in text and "--package-path example-robot-data=DIR" in text
            assert pg.is_visible("#warnings")
    finally:
        srv.shutdown()
        srv.server_close()


def test_browser_plot_page_draws_the_urdf_meshes(browser, tmp_path, capsys):
    """`plot -o x.html` draws the meshes the GUI draws (embedded; the page works from a file), and with
    meshes not found says so on stderr (one line) and in the page."""
    path = _ur5_copy(tmp_path)
    robots = PANDA.parents[3]  # .../share/example-robot-data: the package the URDF names
    out = tmp_path / "ur5.html"
    assert main(["plot", str(path), "--tip-link", "tool0", "--package-path", f"example-robot-data={robots}",
                 "-o", str(out)]) == 0
    assert "warning" not in capsys.readouterr().err
    for pg in _open(browser, out.as_uri()):
        pg.wait_for_function("() => document.body.dataset.meshes == '7'", timeout=30000)
        assert not pg.query_selector("#missing-meshes")
        _shot(pg, tmp_path, "plot_ur5_meshes.png")
    bare = tmp_path / "bare.html"
    assert main(["plot", str(path), "--tip-link", "tool0", "-o", str(bare)]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 2 and "7 of 7 mesh files not found" in err[0] and err[1].startswith("wrote")
    for pg in _open(browser, bare.as_uri()):
        assert "7 of 7 mesh files not found" in pg.inner_text("#missing-meshes")


def test_gui_command_names_missing_meshes_on_stderr(tmp_path, monkeypatch, capsys):
    """`robkin gui ur5.urdf` with meshes found nowhere: one warning line on stderr before serving."""
    from robkin.viz.gui import GuiServer

    path = _ur5_copy(tmp_path)

    def stop(self, *args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(GuiServer, "serve_forever", stop)
    assert main(["gui", str(path), "--tip-link", "tool0", "--port", "0"]) == 0
    err = capsys.readouterr().err.splitlines()
    warned = [line for line in err if "mesh files not found" in line]
    assert len(warned) == 1 and warned[0].startswith("robkin: warning: ") and "7 of 7" in warned[0]
    assert main(["gui", str(path), "--tip-link", "tool0", "--port", "0", "--package-path",
                 f"example-robot-data={PANDA.parents[3]}"]) == 0
    assert "mesh files not found" not in capsys.readouterr().err


# ------------------------------------------------------------------------------ the visual check, exaggerated
RRPR_6MM = RRPR_TEXT.replace("{a: 0.3, d: 0,", "{a: 0.306, d: 0,")


def _look_at(pg) -> np.ndarray:
    return np.array([float(v) for v in pg.get_attribute("#view", "data-look-at").split(",")])


def test_browser_differences_exaggerated_and_zoomed(page):
    pg = page
    before = _updates(pg)
    pg.click("#check-panel summary")
    pg.fill("#other-text", RRPR_6MM)
    _wait_update(pg, before)
    _settled(pg)
    pg.wait_for_selector("#check:not([hidden])")
    labels = [e.inner_text() for e in pg.query_selector_all(".label3d.differs")]
    assert "J4: 0.006" in labels and "tool: 0.006" in labels  # true distances, whatever the factor
    before = _updates(pg)
    pg.select_option("#exaggerate", "100")
    _wait_update(pg, before)
    _settled(pg)
    assert "differences ×100" in pg.inner_text("#check")
    assert "J4: 0.006" in [e.inner_text() for e in pg.query_selector_all(".label3d.differs")]
    # zoom: the camera looks at the middle of J4's arrow (A's J4 point and 100 x 6 mm further)
    pg.click("#zoom-first")
    target = _look_at(pg)
    from robkin.viz import gui_api

    res = gui_api.describe(RRPR_TEXT, "yaml", q=[0, 0, 0, 0], other={"text": RRPR_6MM, "fmt": "yaml",
                                                                     "exaggerate": 100})
    arrow = next(a for a in res["check"]["arrows"] if a["label"] == "J%d" % (res["check"]["first_joint"] + 1))
    np.testing.assert_allclose(target, (np.array(arrow["start"]) + arrow["end"]) / 2, atol=1e-5)


def test_browser_camera_follows_a_robot_that_leaves_the_view(page):
    pg = page
    pg.click("[data-view=fit]")
    follows = int(pg.get_attribute("#view", "data-follows") or 0)
    before = _updates(pg)
    pg.fill("#robot-text", RRPR_TEXT.replace("{a: 0.2, d: 0,   alpha: pi,", "{a: 3.0, d: 0,   alpha: pi,"))
    _wait_update(pg, before)
    _settled(pg)
    assert int(pg.get_attribute("#view", "data-follows") or 0) > follows
    x, y = map(float, pg.get_attribute("#view", "data-tool-xy").split(","))
    box = pg.query_selector("#view").bounding_box()
    assert 0 <= x <= box["width"] and 0 <= y <= box["height"]  # the tool (3 m out) is in the picture


def test_browser_locked_joint_slider_cannot_move(browser, tmp_path):
    """Equal limits mean locked in the GUI too: the joint's slider is disabled and says why."""
    path = tmp_path / "z.urdf"
    path.write_text('<robot name="z"><link name="a"/><link name="b"/><link name="c"/>'
                    '<joint name="j1" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>'
                    '<limit lower="0" upper="0" effort="1" velocity="1"/></joint>'
                    '<joint name="j2" type="revolute"><parent link="b"/><child link="c"/><origin xyz="0 0 1"/>'
                    '<axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>')
    srv = make_server(port=0, text=path.read_text(), fmt="urdf", source=str(path))
    srv.serve_in_thread()
    try:
        for pg in _open(browser, srv.url):
            assert pg.is_disabled("#q0") and not pg.is_disabled("#q1")
            assert "locked" in pg.get_attribute("#q0", "title")
            assert "equal lower and upper limits" in pg.inner_text("#warnings")  # the reader's line, in the page
    finally:
        srv.shutdown()
        srv.server_close()


#: Two joints, the second's range excluding 0 (as the Panda's joint 4): its home is its upper limit.
HOME_URDF = """<robot name="home_arm">
  <link name="base"/><link name="l1"/><link name="l2"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="-0.5" effort="1" velocity="1"/></joint>
</robot>"""


def test_browser_home_button_goes_to_robot_home(page):
    """The home button: Robot.home() (q = 0 clipped into the limits), the MJCF keyframe 'home' too."""
    pg = page
    before = _updates(pg)
    pg.select_option("#format", "urdf")
    pg.fill("#robot-text", HOME_URDF)
    _wait_update(pg, before)
    pg.wait_for_function("() => document.body.dataset.state == 'ready'")
    box = pg.query_selector("#q0").bounding_box()      # move joint 1 away from home
    before = _updates(pg)
    pg.mouse.click(box["x"] + 0.8 * box["width"], box["y"] + box["height"] / 2)
    _wait_update(pg, before)
    assert float(pg.input_value("#q0")) > 0.5
    before = _updates(pg)
    pg.click("#home")
    _wait_update(pg, before)
    assert [float(pg.input_value(f"#q{i}")) for i in range(2)] == [0.0, -0.5]
