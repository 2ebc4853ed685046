"""Hostile and broken MJCF (and SDF) files: exit status 2, one line naming the file and the element.

MJCF ``<include>`` is the one place where an input file names other files, so it gets the most
cases: absolute paths, escapes from the model's folder (``..`` and symbolic links), loops, depth,
count and size limits. Nothing may be read outside the model's folder.
"""

from __future__ import annotations

import os

import pytest

from robkin.cli import main
from robkin.io.mjcf import source as mjcf_source
from robkin.io import load

ARM = '<mujoco><worldbody><body name="a"><joint name="j"/>{}</body></worldbody></mujoco>'


def run(path, capsys, *extra: str) -> str:
    status = main(["fk", str(path), "--q", "0", *extra])
    err = capsys.readouterr().err
    assert status == 2, err
    lines = [ln for ln in err.splitlines() if not ln.startswith("robkin: warning:")]
    assert len(lines) == 1 and lines[0].startswith("robkin: error: ") and "Traceback" not in err, err
    return lines[0]


CASES = [
    ("bad number", ARM.format('<body name="b" pos="0 0 x"/>'), "body 'b': pos: '0 0 x' is not 3 numbers"),
    ("NaN", ARM.format('<site name="s" pos="0 nan 0"/>'), "site 's': pos: '0 nan 0' contains NaN"),
    ("huge number", ARM.format('<body name="b" pos="0 0 1e300"/>'), "has a number beyond"),
    ("two orientations", ARM.format('<body name="b" quat="1 0 0 0" euler="0 0 1"/>'),
     "body 'b': has both quat and euler"),
    ("zero quaternion", ARM.format('<body name="b" quat="0 0 0 0"/>'), "body 'b': quat: is a zero vector"),
    ("zero axis", ARM.replace('<joint name="j"/>', '<joint name="j" axis="0 0 0"/>'),
     "joint 'j' (body 'a'): axis: is a zero vector"),
    ("joint type", ARM.replace('<joint name="j"/>', '<joint name="j" type="screw"/>'),
     "joint 'j' (body 'a'): type 'screw' is not one of hinge, slide, ball, free"),
    ("empty range", ARM.replace('<joint name="j"/>', '<joint name="j" limited="true"/>'),
     "joint 'j' (body 'a'): range '0 0': the lower end must be below the upper end"),
    ("unknown class", ARM.replace('<joint name="j"/>', '<joint name="j" class="big"/>'),
     "joint 'j' (body 'a'): class 'big' is not a <default> class"),
    ("compiler angle", '<mujoco><compiler angle="grad"/><worldbody/></mujoco>',
     "<compiler angle=\"grad\">: expected degree or radian"),
    ("eulerseq", '<mujoco><compiler eulerseq="xyw"/><worldbody/></mujoco>', "eulerseq=\"xyw\">: expected three of"),
    ("root element", '<robot name="r"/>', "root element is <robot>; an MJCF file has <mujoco> (this is a URDF: "
                                          "give it the extension .urdf)"),
    ("entities", '<!DOCTYPE m [<!ENTITY a "b">]><mujoco/>', "refused XML construct"),
    ("not XML", "<mujoco><worldbody>", "not well-formed XML"),
    ("duplicate names", ARM.format('<body name="a"/>'), "two bodies or sites are both called 'a'"),
    ("replicate", ARM.format('<replicate count="3"><body/></replicate>'), "<replicate> is not supported"),
    ("include without file", ARM.format("<include/>"), "<include> has no file attribute"),
    ("absolute include", ARM.format('<include file="/etc/passwd"/>'), "only paths relative to the model's folder"),
    ("include escaping to a non-XML file", ARM.format('<include file="../secret.txt"/>'),
     "leads outside the model's folder"),
    ("missing include", ARM.format('<include file="nope.xml"/>'), "<include file=\"nope.xml\">: no such file"),
    ("include loop", ARM.format('<include file="m.xml"/>'), "includes itself"),
]


@pytest.mark.parametrize("kind, text, expect", CASES, ids=[c[0] for c in CASES])
def test_bad_mjcf(kind, text, expect, tmp_path, capsys):
    (tmp_path / "secret.txt").write_text('<mujoco><body name="stolen"/></mujoco>')
    model = tmp_path / "model"
    model.mkdir()
    path = model / "m.xml"
    path.write_text(text)
    line = run(path, capsys)
    assert expect in line, line
    assert "m.xml" in line


def test_include_through_a_symbolic_link_out_of_the_folder(tmp_path, capsys):
    """A link leading out reads the file it leads to only if that is an .xml file (as MuJoCo reads
    any), and says so once."""
    (tmp_path / "outside.txt").write_text('<mujoco><body name="stolen"/></mujoco>')
    (tmp_path / "outside.xml").write_text('<mujoco><body name="b"><joint name="k"/></body></mujoco>')
    (tmp_path / "model").mkdir()
    try:
        os.symlink(tmp_path / "outside.txt", tmp_path / "model" / "link.xml")
        os.symlink(tmp_path / "outside.xml", tmp_path / "model" / "ok.xml")
    except OSError:
        pytest.skip("no symbolic links here")
    (tmp_path / "model" / "m.xml").write_text(ARM.format('<include file="link.xml"/>'))
    assert "leads outside the model's folder" in run(tmp_path / "model" / "m.xml", capsys)
    (tmp_path / "model" / "m.xml").write_text('<mujoco><worldbody><include file="ok.xml"/></worldbody></mujoco>')
    with pytest.warns(UserWarning, match=r"m.xml: 1 included file\(s\) outside the model's folder are read: ok.xml"):
        robot = load(tmp_path / "model" / "m.xml")
    assert [j.name for j in robot.joints] == ["k"]


def test_include_depth_count_and_size_limits(tmp_path, capsys, monkeypatch):
    for i in range(12):  # a chain of includes deeper than the limit
        (tmp_path / f"d{i}.xml").write_text(f'<mujoco><include file="d{i + 1}.xml"/></mujoco>')
    (tmp_path / "d12.xml").write_text("<mujoco/>")
    (tmp_path / "deep.xml").write_text(ARM.format('<include file="d0.xml"/>'))
    assert f"nests more than {mjcf_source.MAX_INCLUDE_DEPTH} levels" in run(tmp_path / "deep.xml", capsys)

    (tmp_path / "leaf.xml").write_text("<mujoco/>")
    (tmp_path / "wide.xml").write_text(ARM.format("".join(f'<include file="w{i}.xml"/>' for i in range(6))))
    for i in range(6):
        (tmp_path / f"w{i}.xml").write_text("<mujoco/>")
    monkeypatch.setattr(mjcf_source, "MAX_INCLUDES", 4)
    assert "more than 4 included files" in run(tmp_path / "wide.xml", capsys)

    monkeypatch.setattr(mjcf_source, "MAX_BYTES", 1000)
    (tmp_path / "big.xml").write_text("<mujoco>" + " " * 600 + "</mujoco>")
    (tmp_path / "two.xml").write_text(ARM.format('<include file="big.xml"/><include file="big.xml"/>'))
    line = run(tmp_path / "two.xml", capsys)
    assert line.startswith(f"robkin: error: {tmp_path / 'two.xml'}") and "big.xml" in line, line
    (tmp_path / "huge.xml").write_text("<mujoco>" + " " * 2000 + "</mujoco>")
    assert "huge.xml: file is" in run(tmp_path / "huge.xml", capsys)


def test_text_input_cannot_include():
    from robkin.errors import InputError
    from robkin.io.mjcf.reader import robot_from_mjcf

    with pytest.raises(InputError, match="text input cannot include"):
        robot_from_mjcf(ARM.format('<include file="x.xml"/>'))


def test_ball_joint_on_the_chain_via_cli(tmp_path, capsys):
    path = tmp_path / "b.xml"
    path.write_text(ARM.replace('<joint name="j"/>', '<joint name="j" type="ball"/>'))
    assert "b.xml: joint 'j' is a ball joint" in run(path, capsys)


def test_bad_sdf_via_cli(tmp_path, capsys):
    path = tmp_path / "r.sdf"
    path.write_text('<sdf version="1.9"><model name="m"><link name="a"/><link name="b"/>'
                    '<joint name="j" type="revolute"><parent>a</parent><child>b</child>'
                    '<axis><xyz>0 1</xyz></axis></joint></model></sdf>')
    assert "r.sdf: joint 'j': axis xyz: '0 1' has 2 numbers; expected 3" in run(path, capsys)
