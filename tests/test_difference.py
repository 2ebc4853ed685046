"""Small differences made visible (robkin.viz.difference): exaggeration, difference arrows, and
their use in ``plot A B --exaggerate`` and the GUI's visual check."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

import robkin
from robkin.cli import main
from robkin.errors import InputError
from robkin.viz import gui_api
from robkin.viz.difference import difference_arrows, exaggerate
from robkin.viz.scene import build_scene

EXAMPLES = Path(robkin.__file__).parent / "examples"
RRPR_TEXT = (EXAMPLES / "rrpr.yaml").read_text()
#: Table I with a_2 6 mm longer: every axis after joint 2 and the tool move by 6 mm (x0 at q = 0)
RRPR_6MM = RRPR_TEXT.replace("{a: 0.3, d: 0,", "{a: 0.306, d: 0,")
Q = np.array([0.3, -0.5, 0.1, 0.2])


def _robot(text: str):
    return gui_api.parse_robot(text, "yaml")[0]


def test_a_6mm_difference_gives_arrows_of_6mm_and_is_drawn_k_times_larger():
    a, b = _robot(RRPR_TEXT), _robot(RRPR_6MM)
    sa, sb = build_scene(a, Q), build_scene(b, Q)
    arrows = difference_arrows(sa, sb, 100)
    assert [x.label for x in arrows] == ["J4", "tool"]  # J3 is prismatic: a direction only
    tool = arrows[-1]
    # the tool moves by exactly the 6 mm of a_2 (a rigid shift of everything after joint 2)
    assert tool.distance == pytest.approx(0.006, abs=1e-12)
    np.testing.assert_allclose(np.linalg.norm(tool.end - tool.start), 0.6, atol=1e-9)
    shown = exaggerate(sa, sb, 100)
    np.testing.assert_allclose(shown.tool[:3, 3], sa.tool[:3, 3] + 100 * (sb.tool[:3, 3] - sa.tool[:3, 3]), atol=1e-12)
    np.testing.assert_allclose(shown.axis_dirs, sb.axis_dirs, atol=1e-12)  # same directions: nothing to turn
    assert "x100" in shown.label and exaggerate(sa, sb, 1) is sb


def test_frames_moved_along_their_axes_are_no_difference():
    # where a description puts a joint frame on its axis is a choice, not a difference
    a = _robot(RRPR_TEXT)
    frames = np.array(a.frames)
    frames[:-1, :3, 3] += 0.05 * frames[:-1, :3, 2]
    b = a.replace(frames=frames)
    sa, sb = build_scene(a, np.zeros(4)), build_scene(b, np.zeros(4))
    assert difference_arrows(sa, sb, 1000) == []
    np.testing.assert_allclose(exaggerate(sa, sb, 1000).axis_points, sa.axis_points, atol=1e-12)


def test_a_turned_axis_is_turned_k_times_at_most_half_a_turn():
    a = _robot(RRPR_TEXT)
    R = np.eye(4)
    t = 1e-3  # rad
    R[:3, :3] = [[1, 0, 0], [0, np.cos(t), -np.sin(t)], [0, np.sin(t), np.cos(t)]]
    b = a.replace(frames=np.array(a.frames) @ R)  # every frame turned 1 mrad about its own x
    sa, sb = build_scene(a, np.zeros(4)), build_scene(b, np.zeros(4))
    for k, expected in [(10, 10 * t), (1e4, np.pi)]:
        dirs = exaggerate(sa, sb, k).axis_dirs
        angles = np.arccos(np.clip(np.sum(dirs * sa.axis_dirs, axis=1), -1, 1))
        np.testing.assert_allclose(angles, expected, atol=1e-9)


def test_different_structures_or_factors_are_refused():
    a = _robot(RRPR_TEXT)
    three = build_scene(_robot((EXAMPLES / "arbitrary_3r.yaml").read_text()), np.zeros(3))
    with pytest.raises(InputError, match="3 and 4 joints|4 and 3 joints"):
        exaggerate(build_scene(a, np.zeros(4)), three, 10)
    with pytest.raises(InputError, match="from 1 to 1e6"):
        exaggerate(build_scene(a, np.zeros(4)), build_scene(a, np.zeros(4)), 0.5)


def test_gui_check_answers_exaggerated_scene_and_arrows():
    res = gui_api.describe(RRPR_TEXT, "yaml", q=list(Q), other={"text": RRPR_6MM, "fmt": "yaml", "exaggerate": 100})
    c = res["check"]
    assert c["exaggerate"] == 100 and [a["label"] for a in c["arrows"]] == ["J4", "tool"]
    assert c["arrows"][-1]["distance"] == pytest.approx(0.006, abs=1e-12)
    tool_b = np.array(c["scene"]["tool"])[:3, 3]
    tool_a = np.array(res["scene"]["tool"])[:3, 3]
    assert np.linalg.norm(tool_b - tool_a) == pytest.approx(0.6, abs=1e-9)
    plain = gui_api.describe(RRPR_TEXT, "yaml", q=list(Q), other={"text": RRPR_6MM, "fmt": "yaml"})["check"]
    assert plain["exaggerate"] == 1 and np.linalg.norm(np.array(plain["scene"]["tool"])[:3, 3] - tool_a) < 0.0061


@pytest.mark.parametrize("value", [0, 1e9, "10", True])
def test_gui_check_bad_exaggeration_is_one_line(value):
    with pytest.raises(InputError, match=r"^other.exaggerate: expected a number from 1 to 1e6"):
        gui_api.describe(RRPR_TEXT, "yaml", other={"text": RRPR_6MM, "fmt": "yaml", "exaggerate": value})


def test_plot_exaggerate_png_and_html(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    b = tmp_path / "b.yaml"
    b.write_text(RRPR_6MM)
    png = tmp_path / "d.png"
    assert main(["plot", str(EXAMPLES / "rrpr.yaml"), str(b), "--exaggerate", "100", "-o", str(png)]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    from robkin.viz.assets import missing_assets

    if not missing_assets():
        html = tmp_path / "d.html"
        assert main(["plot", str(EXAMPLES / "rrpr.yaml"), str(b), "--exaggerate", "100", "-o", str(html)]) == 0
        assert re.search(r'"arrows": ?\[\{"label": ?"J4"', html.read_text())
    assert main(["plot", str(EXAMPLES / "rrpr.yaml"), "--exaggerate", "10", "-o", str(png)]) == 2
    assert "--exaggerate: give two or more INPUTs" in capsys.readouterr().err


def test_gui_exaggerate_needs_robot_b(capsys):
    assert main(["gui", str(EXAMPLES / "rrpr.yaml"), "--exaggerate", "10", "--port", "0"]) == 2
    assert "--exaggerate: give a second robot B" in capsys.readouterr().err
