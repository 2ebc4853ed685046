"""robkin info: joint table with types, limits, axes and axis relations (reference: the URDF text)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from robkin.cli import main
from test_urdf import TILTED_SILENT, robot_file


def test_info_json_of_panda_matches_the_urdf(capsys):
    path = robot_file("panda_description/urdf/panda.urdf")
    assert main(["info", path, "--tip-link", "panda_hand_tcp", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["n"] == 7 and d["types"] == "RRRRRRR"
    # limits straight from the file (panda_joint4: -3.0718 .. -0.0698)
    j4 = d["joints"][3]
    assert (j4["name"], j4["lower"], j4["upper"]) == ("panda_joint4", -3.0718, -0.0698)
    # Panda geometry (Franka's published kinematics): joint 2 meets joint 1 at 0.333 m, joint 4 is
    # 0.0825 off joint 3, joint 7 is 0.088 off joint 6
    rel = [j["relation"] for j in d["joints"]]
    assert rel == ["coincident", "intersecting", "intersecting", "skew", "skew", "intersecting", "skew"]
    np.testing.assert_allclose([j["distance"] for j in d["joints"]], [0, 0, 0, 0.0825, 0.0825, 0, 0.088], atol=1e-12)
    np.testing.assert_allclose(d["joints"][1]["point"], [0, 0, 0.333], atol=1e-12)
    # tool: flange 0.107 below joint 7's frame plus 0.1034 TCP, 0.088 out along x
    np.testing.assert_allclose(d["tool"]["position"], [0.088, 0, 0.333 + 0.316 + 0.384 - 0.107 - 0.1034], atol=1e-12)


def test_info_text_and_prismatic_direction_only(tmp_path, capsys):
    f = tmp_path / "t.urdf"
    f.write_text(TILTED_SILENT())
    assert main(["info", str(f)]) == 0
    out = capsys.readouterr().out
    assert "j2" in out and "prismatic" in out and "(direction only)" in out
    assert "world -> base" in out  # the fixed world link is shown
    assert "-2" in out and "0.3" in out  # limits of j1, j2
    assert main(["info", str(f), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["joints"][1]["point"] is None and d["joints"][2]["distance"] is None
    assert d["joints"][1]["relation"] in ("parallel", "anti-parallel", "not parallel")


def test_info_help_has_examples(capsys):
    with pytest.raises(SystemExit):
        main(["info", "--help"])
    assert "examples:" in capsys.readouterr().out
