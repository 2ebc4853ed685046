"""robkin info of MJCF and SDF trees: the chains they offer are listed, as for a URDF."""

from __future__ import annotations

import json

from robkin.cli import main

MJCF_TREE = """<mujoco model="two_arms"><compiler angle="radian"/><worldbody>
 <body name="torso"><joint name="waist" axis="0 0 1"/>
  <body name="l1" pos="0 0.2 0"><joint name="l_j1" axis="0 1 0"/>
   <body name="l2" pos="0 0 0.3"><joint name="l_j2" type="slide" axis="0 0 1"/><site name="l_tool" pos="0 0 0.1"/></body>
  </body>
  <body name="r1" pos="0 -0.2 0"><joint name="r_ball" type="ball"/>
   <body name="r2" pos="0 0 0.3"><joint name="r_j2" axis="1 0 0"/></body>
  </body>
 </body></worldbody></mujoco>"""

SDF_TREE = """<sdf version="1.9"><model name="fork">
 <link name="base"/><link name="a"><pose>0 0 0.1 0 0 0</pose></link><link name="b"><pose>0 0.2 0.1 0 0 0</pose></link>
 <link name="c"><pose>0 0.2 0.4 0 0 0</pose></link>
 <joint name="ja" type="revolute"><parent>base</parent><child>a</child><axis><xyz>0 0 1</xyz></axis></joint>
 <joint name="jb" type="prismatic"><parent>base</parent><child>b</child><axis><xyz>1 0 0</xyz></axis></joint>
 <joint name="jc" type="continuous"><parent>b</parent><child>c</child><axis><xyz>0 1 0</xyz></axis></joint>
</model></sdf>"""


def test_info_lists_the_chains_of_an_mjcf_tree(tmp_path, capsys):
    path = tmp_path / "two_arms.xml"
    path.write_text(MJCF_TREE)
    assert main(["info", str(path), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["tree"] and [(c["tip"], c["n"], c["types"]) for c in d["chains"]] == [("l_tool", 3, "RRP"),
                                                                                  ("r2", 3, "RRR")]
    assert d["chains"][0]["joints"] == ["waist", "l_j1", "l_j2"] and d["chains"][0]["unsupported"] == []
    assert d["chains"][1]["unsupported"] == ["r_ball"]
    assert main(["info", str(path)]) == 0
    text = capsys.readouterr().out
    assert "2 chains from 'world'" in text and "ball joint r_ball: no chain through it" in text
    # a chosen chain is described; one through the ball joint is refused in one line
    assert main(["info", str(path), "--tip-link", "l_tool", "--json"]) == 0
    assert [j["name"] for j in json.loads(capsys.readouterr().out)["joints"]] == ["waist", "l_j1", "l_j2"]
    assert main(["info", str(path), "--tip-link", "r2"]) == 2
    assert "joint 'r_ball' is a ball joint; only hinge and slide" in capsys.readouterr().err
    assert main(["info", str(path), "--base-link", "r1", "--tip-link", "r2", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["n"] == 1


def test_info_lists_the_chains_of_an_sdf_tree(tmp_path, capsys):
    path = tmp_path / "fork.sdf"
    path.write_text(SDF_TREE)
    assert main(["info", str(path), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert [(c["base"], c["tip"], c["types"], c["joints"]) for c in d["chains"]] == \
        [("base", "a", "R", ["ja"]), ("base", "c", "PR", ["jb", "jc"])]
    assert main(["info", str(path), "--tip-link", "c", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["types"] == "PR"


def test_info_of_a_single_chain_mjcf_describes_it(tmp_path, capsys):
    path = tmp_path / "one.xml"
    path.write_text('<mujoco><worldbody><body name="a"><joint name="j"/></body></worldbody></mujoco>')
    assert main(["info", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["n"] == 1
