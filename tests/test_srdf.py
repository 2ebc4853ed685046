"""SRDF <disable_collisions>: written, read back, hostile names kept as data, bad files refused in one line;
and the ``robkin collision`` command."""

from __future__ import annotations

import os

import pytest

from robkin.cli import main
from robkin.errors import InputError
from robkin.io.srdf import parse_srdf, read_srdf, srdf_text

from ik_arms import ROBOTS_DIR


def test_round_trip_and_hostile_names():
    pairs = [("a&b", 'c"<d>', "Never"), ("x", "y", "Adjacent"), ("-->", "]]>", "Default")]
    text = srdf_text('r"<', pairs, comment="made -- here")
    name, back = parse_srdf(text)
    assert name == 'r"<' and [tuple(p) for p in back] == pairs


def test_reads_the_maintainers_srdf():
    path = os.path.join(ROBOTS_DIR, "panda_description", "srdf", "panda.srdf")
    if not os.path.isfile(path):
        pytest.skip("example-robot-data is not installed")
    name, pairs = read_srdf(path)
    assert name == "panda" and len(pairs) == 35
    assert ("panda_link0", "panda_link1", "Adjacent") in [tuple(p) for p in pairs]


@pytest.mark.parametrize("text, match", [
    ("<robot><disable_collisions link1='a'/></robot>", "disable_collisions\\[0\\]: needs link1 and link2"),
    ("<robt/>", "root element"),
    ("<robot><", "not well-formed"),
    ('<!DOCTYPE r [<!ENTITY e "x">]><robot/>', "refused XML construct"),
])
def test_bad_srdf(text, match):
    with pytest.raises(InputError, match=match):
        parse_srdf(text, "f.srdf")


def test_missing_file(tmp_path):
    with pytest.raises(InputError, match="nothing.srdf"):
        read_srdf(tmp_path / "nothing.srdf")


def test_collision_command(tmp_path, capsys):
    urdf = os.path.join(ROBOTS_DIR, "panda_description", "urdf", "panda.urdf")
    if not os.path.isfile(urdf):
        pytest.skip("example-robot-data is not installed")
    pytest.importorskip("coal")
    out = tmp_path / "panda.srdf"
    srdf = os.path.join(ROBOTS_DIR, "panda_description", "srdf", "panda.srdf")
    assert main(["collision", urdf, "--tip-link", "panda_hand_tcp", "--samples", "3000", "-o", str(out),
                 "--compare", srdf]) == 0
    text = capsys.readouterr().out
    assert "11 links with collision geometry, 55 pairs" in text and "agreement with" in text
    _, pairs = read_srdf(out)
    assert {p.reason for p in pairs} <= {"Adjacent", "Default", "Always", "Never"} and len(pairs) > 30


def test_collision_command_bad_input(tmp_path, capsys):
    bad = tmp_path / "r.urdf"
    bad.write_text("<robot name='r'><link name='a'/></robot>")
    assert main(["collision", str(bad), "-o", str(tmp_path / "o.srdf")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert not (tmp_path / "o.srdf").exists()
    with pytest.raises(SystemExit) as exc:   # argparse's one-line usage error
        main(["collision", str(bad), "--samples", "0"])
    assert exc.value.code == 2


def test_collision_command_names_a_missing_mesh_and_a_robot_without_geometry(tmp_path, capsys):
    urdf = tmp_path / "two.urdf"
    urdf.write_text("""<robot name="two">
  <link name="a"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <link name="b"><collision><geometry><mesh filename="nowhere.stl"/></geometry></collision></link>
  <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>""")
    assert main(["collision", str(urdf), "-o", str(tmp_path / "o.srdf")]) == 2
    err = capsys.readouterr().err
    assert "link 'b'" in err and "nowhere.stl" in err and err.count("\n") == 1
    from robkin.examples import EXAMPLES_DIR

    assert main(["collision", str(EXAMPLES_DIR / "rrpr.yaml")]) == 2
    assert "collision geometry" in capsys.readouterr().err

