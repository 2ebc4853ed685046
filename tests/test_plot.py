"""Pictures (robkin plot): the drawn geometry against the conversion paper and independent FK.

References: the RRPR robot's Table I (with the errata in docs/conventions.md) and eq. (10), the altered Table III
(DH rebuilt from PoE), and forward kinematics / finite-difference Jacobians written out here with
plain numpy, independently of robkin's own code.
"""

from __future__ import annotations

import json
import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("matplotlib")

import robkin  # noqa: E402
from robkin.cli import main  # noqa: E402
from robkin.viz.metrics import read_metrics  # noqa: E402
from robkin.viz.plot import AXIS_BLUE, TOOL_PINK, plot_robot  # noqa: E402
from robkin.viz.scene import build_scene, disagreement, overlay_scenes  # noqa: E402

EXAMPLES = Path(robkin.__file__).parent / "examples"
RRPR = EXAMPLES / "rrpr.yaml"
PI = math.pi
Q_PAPER = [3 * PI / 4, -PI / 4, 0.3, -3 * PI / 4]  # the configuration of the paper's Fig. 2
#: Table I with the errata: (a, d, alpha, theta) per joint, joint types R R P R.
TABLE_I = [(0, 0.2, -PI / 2, 0), (0.3, 0, 0, -PI / 2), (0.2, 0, PI, PI / 2), (0.1, 0, 0, 0)]
PRISMATIC = [False, False, True, False]
#: Tight tolerance for results that are exact up to float rounding of a few 4x4 products (~1e-16
#: per operation, a few dozen operations, metre-scale numbers).
EXACT = 1e-12


def dh(a, d, alpha, theta):
    """Standard DH link transform written out by hand (Rz Tz Tx Rx)."""
    ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
    return np.array([[ct, -st * ca, st * sa, a * ct], [st, ct * ca, -ct * sa, a * st], [0, sa, ca, d], [0, 0, 0, 1]])


def rrpr_frames(q, table=TABLE_I):
    """DH frames {0}..{4} of a table at q, by hand."""
    T = np.eye(4)
    out = [T]
    for (a, d, alpha, theta), prism, qi in zip(table, PRISMATIC, q):
        T = T @ (dh(a, d + qi, alpha, theta) if prism else dh(a, d, alpha, theta + qi))
        out.append(T)
    return out


@pytest.fixture(scope="module")
def rrpr():
    return robkin.load(RRPR)


def test_home_tool_is_the_papers_M(rrpr):
    """At home the drawn tool pose is eq. (10)'s M (exact numbers in the paper)."""
    M = np.array([[1, 0, 0, 0.3], [0, 0, -1, 0], [0, 1, 0, 0.5], [0, 0, 0, 1]])
    scene = build_scene(rrpr)
    np.testing.assert_allclose(scene.tool, M, atol=EXACT)
    np.testing.assert_allclose(scene.links[-1], [0.3, 0, 0.5], atol=EXACT)


def test_scene_at_fig2_configuration_matches_hand_written_dh(rrpr):
    """Links go through the DH frame origins; axes are the z axes of frames {0}..{3} at q."""
    frames = rrpr_frames(Q_PAPER)
    scene = build_scene(rrpr, Q_PAPER)
    np.testing.assert_allclose(scene.tool, frames[-1], atol=EXACT)
    for i in range(4):
        # joint i+1 moves about/along z of frame {i}: same line (revolute) / direction (prismatic)
        np.testing.assert_allclose(scene.axis_dirs[i], frames[i][:3, 2], atol=EXACT)
    origins = np.array([F[:3, 3] for F in frames])
    # The prismatic joint 3 adds the start of its slide; every hand-computed origin is on the polyline.
    for o in origins:
        assert np.min(np.linalg.norm(scene.links - o, axis=1)) < EXACT
    assert len(scene.links) == 1 + 4 + 1 + 1  # base, 4 joints, slide start, tool


def test_overlay_dh_and_poe_draws_table_iii_on_the_same_axes(rrpr):
    """DH rebuilt from PoE (the paper's Table III) has other link lines but the same tool and axes."""
    dh_scene, poe_scene = overlay_scenes(rrpr, Q_PAPER, ["dh", "poe"])
    pos, rot, axes = disagreement([dh_scene, poe_scene])
    assert pos < EXACT and rot < EXACT and axes < EXACT
    # Table III, printed with 3 decimals: its frame origins are where the orange polyline bends.
    table_iii = [(0, 0.2, -PI / 2, 0), (0, 0, 0, 0), (-0.361, 0, PI, 2.159), (0.1, 0, 0, 2.159)]
    origins = np.array([F[:3, 3] for F in rrpr_frames(Q_PAPER, table_iii)])
    for o in origins:
        # 3-decimal rounding of a and theta moves points by up to ~1e-3 (0.361 m * 5e-4 rad + 5e-4 m)
        assert np.min(np.linalg.norm(poe_scene.links - o, axis=1)) < 2e-3
    # ...and they differ from the original table's: the link lines are not the same
    assert np.max(np.abs(poe_scene.links - dh_scene.links)) > 0.1


def test_figure_draws_the_scene_with_paper_colours_and_equal_axes(rrpr):
    from matplotlib.colors import to_hex

    fig = plot_robot(rrpr, Q_PAPER, overlay=["dh", "poe"], frames=True)
    ax = fig.axes[0]
    scene = build_scene(rrpr, Q_PAPER)
    link = ax.lines[0]
    np.testing.assert_allclose(np.array(link.get_data_3d()).T, scene.links, atol=EXACT)
    blue = [ln for ln in ax.lines if to_hex(ln.get_color()) == AXIS_BLUE]
    assert len(blue) == 2 * rrpr.n  # one segment per joint per overlaid description
    for ln, p, z in zip(blue[:rrpr.n], scene.axis_points, scene.axis_dirs):
        seg = np.array(ln.get_data_3d()).T
        d = seg[1] - seg[0]
        assert np.linalg.norm(np.cross(d / np.linalg.norm(d), z)) < EXACT and np.dot(d, z) > 0
    pink = [c for c in ax.collections if to_hex(c.get_edgecolor()[0]) == TOOL_PINK]
    assert len(pink) == 3 * 2  # x, y, z arrows of the tool, for both descriptions
    # frames=True: an x, y, z arrow per joint frame per description, plus the tool and base triads
    assert len(ax.collections) == 3 * (2 * rrpr.n + 2 + 1)
    spans = [np.diff(lim)[0] for lim in (ax.get_xlim(), ax.get_ylim(), ax.get_zlim())]
    np.testing.assert_allclose(spans, spans[0], rtol=1e-12)
    assert "tool poses differ by" in ax.get_title()
    texts = {t.get_text() for t in ax.texts}
    assert {"joint1", "joint2", "joint3", "joint4"} <= texts


def test_cli_svg_png_html(tmp_path, capsys):
    svg, png, html = tmp_path / "r.svg", tmp_path / "r.png", tmp_path / "r.html"
    assert main(["plot", str(RRPR), "--q", "3*pi/4,-pi/4,0.3,-3*pi/4", "--overlay", "dh,poe", "-o", str(svg)]) == 0
    root = ET.parse(svg).getroot()
    assert root.tag.endswith("svg")
    assert "joint4" in svg.read_text()
    assert main(["plot", str(RRPR), "-o", str(png)]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert main(["plot", str(RRPR), "--q", "0,0,0.3,0", "-o", str(html)]) == 0
    page = html.read_text()
    assert page.startswith("<!DOCTYPE html>") and 'id="robkin-data"' in page  # the interactive 3D page
    # caption: the tool pose at q, from the hand-written DH product
    T = rrpr_frames([0, 0, 0.3, 0])[-1]
    assert f"{T[0, 3]: .6f}" in page and f"{T[2, 3]: .6f}" in page
    # the same command twice gives the same bytes (no dates, fixed ids)
    again = tmp_path / "again.svg"
    main(["plot", str(RRPR), "--q", "3*pi/4,-pi/4,0.3,-3*pi/4", "--overlay", "dh,poe", "-o", str(again)])
    assert again.read_bytes() == svg.read_bytes()


@pytest.mark.parametrize("argv, message", [
    (["--q", "1,2"], "--q: the robot has 4 joints, got 2 values"),
    (["--overlay", "dh,foo"], "--overlay: unknown representation 'foo'"),
    (["--view", "1"], "--view"),
    (["--metrics", "--q", "0,0,0,0"], "--metrics"),
])
def test_cli_bad_input_is_one_line_and_writes_nothing(tmp_path, capsys, argv, message):
    out = tmp_path / "x.png"
    assert main(["plot", str(RRPR), *argv, "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert not out.exists()


def test_cli_unknown_output_format(tmp_path, capsys):
    assert main(["plot", str(RRPR), "-o", str(tmp_path / "x.txt")]) == 2
    assert "unknown picture format '.txt'" in capsys.readouterr().err
    assert not (tmp_path / "x.txt").exists()


def test_metrics_read_and_drawn(tmp_path):
    """Given metrics are drawn as bar heights (log scale for manipulability), grouped per pose."""
    values = {"A": (1.36, 1e-4, 0.0), "B": (1.2, 2e-2, 1e-3), "C": (2.6, 5e-2, 3e-2), "D": (1.3, 3e-2, 8e-2)}
    paths = []
    for pose in ("pose1", "pose2"):
        for t, (L, mt, mr) in values.items():
            p = tmp_path / f"{pose}_{t}.json"
            doc = {"robkin": 1, "joints": [{"name": "j1", "type": "revolute"}],
                   "dh": {"rows": [[0, 0.5, 0, 0]]},
                   "metrics": {"length": L, "manipulability_translational": mt, "manipulability_rotational": mr}}
            p.write_text(json.dumps(doc))
            paths.append(p)
    from robkin.viz.metrics import plot_metrics

    entries = [read_metrics(p) for p in paths]
    assert [e.group for e in entries[:4]] == ["pose1"] * 4 and [e.series for e in entries[:4]] == list("ABCD")
    fig = plot_metrics(entries)
    a, b, c = fig.axes
    assert b.get_yscale() == "log" and c.get_yscale() == "log" and a.get_yscale() == "linear"
    heights_a = sorted(round(p.get_height(), 12) for p in a.patches)
    assert heights_a == sorted([v[0] for v in values.values()] * 2)
    # a zero manipulability sits on the log floor and is labelled "0"
    assert min(p.get_height() for p in c.patches) == pytest.approx(1e-12)
    assert any(t.get_text() == "0" for t in c.texts)
    out = tmp_path / "m.svg"
    assert main(["plot", "--metrics", *map(str, paths), "-o", str(out)]) == 0
    assert ET.parse(out).getroot().tag.endswith("svg")


def test_metrics_grouping_prefers_file_names_and_never_stacks_bars(tmp_path):
    from robkin.viz.metrics import plot_metrics

    doc = {"robkin": 1, "name": "estimate-A", "joints": [{"name": "j1", "type": "revolute"}],
           "dh": {"rows": [[0, 0.5, 0, 0]]},
           "metrics": {"length": 1.0, "manipulability_translational": 0.1, "manipulability_rotational": 0.2}}
    for stem in ("pose1_A", "pose2_A", "other"):
        (tmp_path / f"{stem}.json").write_text(json.dumps(doc))
    e1, e2, e3 = (read_metrics(tmp_path / f"{s}.json") for s in ("pose1_A", "pose2_A", "other"))
    assert (e1.group, e1.series, e2.group) == ("pose1", "A", "pose2")
    assert (e3.group, e3.series) == ("estimate", "A")  # no pattern in the file name: the document name
    # the same place twice: one bar each, side by side
    fig = plot_metrics([e1, e1])
    xs = sorted(p.get_x() for p in fig.axes[0].patches)
    assert len(xs) == 2 and xs[1] - xs[0] > fig.axes[0].patches[0].get_width() * 0.9


def test_metrics_computed_when_absent():
    """RRPR without a metrics object: length from Table I (eq. 48), manipulability by finite differences."""
    entry = read_metrics(RRPR)
    assert entry.length == pytest.approx(0.2 + 0.3 + 0.2 + 0.1, abs=EXACT)  # sum sqrt(a^2 + d^2)
    # translational Jacobian at q = 0 by central differences of the hand-written DH FK
    h = 1e-6
    J = np.empty((3, 4))
    for i in range(4):
        dq = np.zeros(4)
        dq[i] = h
        J[:, i] = (rrpr_frames(dq)[-1][:3, 3] - rrpr_frames(-dq)[-1][:3, 3]) / (2 * h)
    expected = math.sqrt(np.linalg.det(J @ J.T))
    # central differences: error ~h^2 * |third derivative| ~ 1e-12, far inside 1e-8
    assert entry.manipulability_translational == pytest.approx(expected, abs=1e-8)


def test_metrics_bad_value(tmp_path, capsys):
    p = tmp_path / "bad.yaml"
    p.write_text("robkin: 1\njoints: [{name: j1, type: revolute}]\ndh: {rows: [[0, 0.5, 0, 0]]}\n"
                 "metrics: {length: -1, manipulability_translational: 0, manipulability_rotational: 0}\n")
    assert main(["plot", "--metrics", str(p), "-o", str(tmp_path / "m.png")]) == 2
    assert "metrics.length: expected a number >= 0" in capsys.readouterr().err


def _ur5_urdf() -> Path:
    import glob
    import sys

    found = glob.glob(str(Path(sys.prefix) / "lib" / "python*" / "site-packages" / "cmeel.prefix" / "share" /
                          "example-robot-data" / "robots" / "ur_description" / "urdf" / "ur5_robot.urdf"))
    if not found:
        pytest.skip("example-robot-data (test extra) is not installed")
    return Path(found[0])


def test_real_urdf_arm_drawn_where_pinocchio_puts_it():
    """UR5 from example-robot-data: drawn joint axes and tool agree with pinocchio's FK."""
    pin = pytest.importorskip("pinocchio")
    path = _ur5_urdf()
    robot = robkin.load(path, tip_link="tool0")
    q = np.array([0.0, -PI / 2, PI / 2, -PI / 2, -PI / 2, 0.0]) + np.array([0.3, 0.2, -0.1, 0.4, 0.5, -0.6])
    model = pin.buildModelFromUrdf(str(path))
    data = model.createData()
    config = pin.neutral(model)
    for name, value in zip([j.name for j in robot.joints], q):
        joint = model.joints[model.getJointId(name)]
        if joint.nq == 2:  # continuous joint: (cos q, sin q)
            config[joint.idx_q:joint.idx_q + 2] = math.cos(value), math.sin(value)
        else:
            config[joint.idx_q] = value
    pin.framesForwardKinematics(model, data, config)
    base = data.oMf[model.getFrameId("base_link")].homogeneous
    tool = np.linalg.inv(base) @ data.oMf[model.getFrameId("tool0")].homogeneous
    for s in overlay_scenes(robot, q, ["gjd", "dh", "poe"]):
        # 1e-9: both read the URDF's decimal text but compose the transforms in different orders
        np.testing.assert_allclose(s.tool, tool, atol=1e-9, err_msg=s.label)
    # Joint axes as the URDF states them (read here with ElementTree), placed by pinocchio's FK.
    axes = {j.get("name"): np.array(j.find("axis").get("xyz").split(), dtype=float)
            for j in ET.parse(path).getroot().iter("joint") if j.find("axis") is not None}
    scene = build_scene(robot, q)
    for i, joint in enumerate(robot.joints):
        M = np.linalg.inv(base) @ data.oMi[model.getJointId(joint.name)].homogeneous
        z = M[:3, :3] @ axes[joint.name]
        assert np.linalg.norm(np.cross(scene.axis_dirs[i], z)) < 1e-9 and scene.axis_dirs[i] @ z > 0, joint.name
        d = scene.axis_points[i] - M[:3, 3]
        assert np.linalg.norm(d - np.dot(d, z) * z) < 1e-9, joint.name  # a point of the same line
    fig = plot_robot(robot, q, overlay=["gjd", "dh"])
    assert "tool poses differ by" in fig.axes[0].get_title()


def test_missing_matplotlib_is_one_clear_line(monkeypatch, capsys, tmp_path):
    import sys

    monkeypatch.setitem(sys.modules, "matplotlib", None)  # as if not installed
    assert main(["plot", str(RRPR), "-o", str(tmp_path / "x.png")]) == 2
    assert "pip install 'robkin[plot]'" in capsys.readouterr().err
