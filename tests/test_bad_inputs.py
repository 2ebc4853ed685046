"""Bad inputs through the command line: each gets exit status 2, one line on stderr naming the file,
field or joint, no traceback, and no output file written or clobbered.

The same table is docs/bad-inputs.md; regenerate it with
``.venv/bin/python tests/test_bad_inputs.py > docs/bad-inputs.md`` (a test checks it is current).
"""

from __future__ import annotations

import os
import sys
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from robkin.cli import main
from robkin.errors import MAX_MESSAGE

HERE = Path(__file__).resolve().parent
DOC = HERE.parent / "docs" / "bad-inputs.md"

GOOD_URDF = """<robot name="r"><link name="a"/><link name="b"/><link name="c"/>
<joint name="j1" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0 0 0.3"/>
<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
<joint name="j2" type="revolute"><parent link="b"/><child link="c"/><origin xyz="0.4 0 0"/>
<axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"""
GOOD_DOC = """robkin: 1
joints: [{name: j1, type: revolute}, {name: j2, type: revolute}]
dh: {rows: [[0, 0.3, 1.5707963267948966, 0], [0.4, 0, 0, 0]]}
"""
POE_DOC = """robkin: 1
joints: [revolute, revolute]
poe: {{frame: space, M: {M}, screws: {S}}}
"""
EYE = "[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]"
#: a four-bar linkage (as in Cassie's legs): link c hangs from b and from d; walking it as a tree never ended
LOOP_SDF = ('<sdf version="1.9"><model name="m">' + "".join(f'<link name="{x}"/>' for x in "abcd")
            + "".join(f'<joint name="{n}" type="revolute"><parent>{p}</parent><child>{c}</child><axis><xyz>0 0 1'
                      f'</xyz></axis></joint>' for n, p, c in (("jb", "a", "b"), ("jc", "b", "c"), ("jd", "a", "d"),
                                                               ("loop", "d", "c"))) + "</model></sdf>")
BOMB = """<?xml version="1.0"?>
<!DOCTYPE lolz [<!ENTITY lol "lol"><!ENTITY lol2 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">
<!ENTITY lol3 "&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;">]>
<robot name="&lol3;"><link name="a"/></robot>"""
EXTERNAL = """<?xml version="1.0"?>
<!DOCTYPE r [<!ENTITY xxe SYSTEM "file:///etc/passwd">]>
<robot name="&xxe;"><link name="a"/></robot>"""

#: "Billion laughs" in YAML: 0.5 kB whose aliases nest nine deep (10^9 names once expanded).
ALIAS_BOMB = ("robkin: 1\na: &a [x, x, x, x, x, x, x, x, x, x]\n"
              + "".join(f"{k}: &{k} [{', '.join(['*' + p] * 10)}]\n" for p, k in zip("abcdefgh", "bcdefghi"))
              + "joints: [{name: *i, type: revolute}]\ndh: {rows: [[0, 0, 0, 0]]}\n")
GOOD_JSON = ('{"robkin": 1, "joints": [{"name": "j1", "type": "revolute"}, {"name": "j2", "type": "revolute"}], '
             '"dh": {"rows": [[0, 0.3, 1.5707963267948966, 0], [0.4, 0, 0, 0]]}}')


def urdf_with(joint_xml: str, links: str = '<link name="a"/><link name="b"/>') -> str:
    return f'<robot name="r">{links}{joint_xml}</robot>'


@dataclass
class Case:
    """One bad input: files to create, the command (``{d}`` = the temporary folder) and the expected
    part of the one-line message."""

    kind: str
    files: dict[str, str | bytes]
    argv: list[str]
    expect: str
    writes: bool = True  # the command would write {d}/out.* (pre-filled; must stay untouched)
    extra_files: dict[str, str] = field(default_factory=dict)
    #: special files to make in {d}: name -> "fifo", "folder" or a path to symlink to (e.g. /dev/zero)
    special: dict[str, str] = field(default_factory=dict)


def _leg(name: str, to: str = "dh", out: str = "out.yaml") -> list[str]:
    return ["convert", "{d}/" + name, "--to", to, "-o", "{d}/" + out]


CASES = [
    Case("empty document", {"e.yaml": ""}, _leg("e.yaml"), "e.yaml: document is empty"),
    Case("empty URDF", {"e.urdf": ""}, _leg("e.urdf"), "e.urdf: file is empty"),
    Case("truncated YAML", {"t.yaml": GOOD_DOC[:-20]}, _leg("t.yaml"), "t.yaml: not valid YAML (line 3"),
    Case("truncated JSON", {"t.json": '{"robkin": 1, "joints": ['}, _leg("t.json"), "t.json: not valid JSON"),
    Case("truncated URDF", {"t.urdf": GOOD_URDF[:150]}, _leg("t.urdf"), "t.urdf: not well-formed XML (line"),
    Case("not UTF-8", {"b.yaml": b"robkin: 1\njoints: [\xff\xfe]\n"}, _leg("b.yaml"), "b.yaml: not UTF-8 text"),
    Case("missing file", {}, _leg("nothing.yaml"), "nothing.yaml: no such file"),
    Case("unknown extension", {"r.dat": GOOD_DOC}, _leg("r.dat"), "r.dat: unknown extension '.dat'"),
    Case("document is a list", {"l.json": "[1, 2]"}, _leg("l.json"), "document must be a mapping"),
    Case("NaN in a DH row", {"n.yaml": GOOD_DOC.replace("0.4, 0, 0, 0", "0.4, .nan, 0, 0")}, _leg("n.yaml"),
         "n.yaml: dh.rows[1][1]: must be a finite number"),
    Case("number overflow (1e400)", {"o.yaml": GOOD_DOC.replace("0.4,", "1e400,")}, _leg("o.yaml"), "dh.rows[1]"),
    Case("wrong row count", {"w.yaml": GOOD_DOC.replace(", [0.4, 0, 0, 0]", "")}, _leg("w.yaml"),
         "dh.rows: expected 2 rows"),
    Case("wrong column count", {"c.yaml": GOOD_DOC.replace("[0.4, 0, 0, 0]", "[0.4, 0, 0]")}, _leg("c.yaml"),
         "dh.rows[1]"),
    Case("non-rotation M", {"m.yaml": POE_DOC.format(M="[[1,0,0,0],[0,1,0,0],[0,0,2,0],[0,0,0,1]]",
                                                     S="[[0,0,1,0,0,0],[0,1,0,0,0,0]]")},
         _leg("m.yaml"), "poe.M: rotation block"),
    Case("zero screw", {"z.yaml": POE_DOC.format(M=EYE, S="[[0,0,1,0,0,0],[0,0,0,0,0,0]]")}, _leg("z.yaml"),
         "poe.screws[1] (joint 'joint2', revolute): w must be a unit vector"),
    Case("screw with pitch", {"p.yaml": POE_DOC.format(M=EYE, S="[[0,0,1,0,0,0],[0,1,0,0,1,0]]")},
         _leg("p.yaml"), "is not 0; a revolute joint has no pitch"),
    Case("unknown joint type (document)", {"u.yaml": GOOD_DOC.replace("name: j2, type: revolute",
                                                                      "name: j2, type: spherical")},
         _leg("u.yaml"), "'spherical' is not one of revolute, prismatic"),
    Case("duplicate joint names", {"d.yaml": GOOD_DOC.replace("name: j2", "name: j1")}, _leg("d.yaml"),
         "duplicate joint name"),
    Case("limits lower > upper", {"l.yaml": GOOD_DOC.replace("name: j2, type: revolute",
                                                             "name: j2, type: revolute, limits: {lower: 2, upper: 1}")},
         _leg("l.yaml"), "joint 'j2': limits.lower 2.0 > limits.upper 1.0"),
    Case("sections that disagree", {"s.yaml": GOOD_DOC + "mdh: {rows: [[0, 0.3, 0, 0], [0.4, 0, 0, 0]]}\n"},
         _leg("s.yaml"), "sections dh and mdh describe different robots"),
    Case("unknown joint type (URDF)", {"u.urdf": GOOD_URDF.replace('name="j2" type="revolute"',
                                                                   'name="j2" type="ball"')},
         _leg("u.urdf"), "u.urdf: joint 'j2': unknown type 'ball'"),
    Case("entity expansion bomb", {"bomb.urdf": BOMB}, _leg("bomb.urdf"), "bomb.urdf: refused XML construct"),
    Case("external entity", {"xxe.urdf": EXTERNAL}, _leg("xxe.urdf"), "xxe.urdf: refused XML construct"),
    Case("unexpanded xacro in a .urdf", {"x.urdf": '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
                                                   '<xacro:property name="L" value="1"/><link name="a"/></robot>'},
         _leg("x.urdf"), "contains xacro macros; give the file a .xacro extension"),
    Case("root is not <robot>", {"r.urdf": "<model><link name='a'/></model>"}, _leg("r.urdf"),
         "root element is <model>"),
    Case("cycle of joints", {"cyc.urdf": urdf_with(
        '<joint name="j1" type="revolute"><parent link="a"/><child link="b"/></joint>'
        '<joint name="j2" type="revolute"><parent link="b"/><child link="a"/></joint>')},
        _leg("cyc.urdf"), "the joints form a cycle"),
    Case("two parents for one link", {"two.urdf": urdf_with(
        '<joint name="j1" type="fixed"><parent link="a"/><child link="b"/></joint>'
        '<joint name="j2" type="fixed"><parent link="c"/><child link="b"/></joint>',
        '<link name="a"/><link name="b"/><link name="c"/>')}, _leg("two.urdf"),
        "link 'b' has two parent joints, 'j1' and 'j2'"),
    Case("unknown link", {"ul.urdf": urdf_with(
        '<joint name="j1" type="revolute"><parent link="a"/><child link="hand"/></joint>')},
        _leg("ul.urdf"), "joint 'j1': child link 'hand' is not a <link> of the file"),
    Case("disconnected links", {"dis.urdf": urdf_with("", '<link name="a"/><link name="b"/>')}, _leg("dis.urdf"),
         "the links are not connected"),
    Case("floating joint in the chain", {"f.urdf": urdf_with(
        '<joint name="free" type="floating"><parent link="a"/><child link="b"/></joint>')}, _leg("f.urdf"),
        "joint 'free' is floating"),
    Case("planar joint in the chain", {"pl.urdf": urdf_with(
        '<joint name="slide2d" type="planar"><parent link="a"/><child link="b"/></joint>')}, _leg("pl.urdf"),
        "joint 'slide2d' is planar"),
    Case("mimic joint in the chain", {"mi.urdf": GOOD_URDF.replace(
        '<axis xyz="0 1 0"/>', '<axis xyz="0 1 0"/><mimic joint="j1"/>')}, _leg("mi.urdf"),
        "joint 'j2' mimics another joint"),
    Case("zero joint axis", {"za.urdf": GOOD_URDF.replace('axis xyz="0 1 0"', 'axis xyz="0 0 0"')},
         _leg("za.urdf"), "joint 'j2': axis xyz is zero"),
    Case("NaN in a URDF origin", {"no.urdf": GOOD_URDF.replace('xyz="0.4 0 0"', 'xyz="0.4 nan 0"')},
         _leg("no.urdf"), "joint 'j2': origin xyz: '0.4 nan 0' contains NaN"),
    Case("two numbers for xyz", {"tn.urdf": GOOD_URDF.replace('xyz="0.4 0 0"', 'xyz="0.4 0"')}, _leg("tn.urdf"),
         "joint 'j2': origin xyz: '0.4 0' has 2 numbers; expected 3"),
    Case("no movable joint", {"fx.urdf": urdf_with(
        '<joint name="weld" type="fixed"><parent link="a"/><child link="b"/></joint>')}, _leg("fx.urdf"),
        "no revolute, continuous or prismatic joint"),
    Case("tree without --tip-link", {"tree.urdf": GOOD_URDF.replace(
        "</robot>", '<link name="cam"/><joint name="c" type="fixed"><parent link="b"/><child link="cam"/>'
                    '</joint></robot>')}, _leg("tree.urdf"), "2 leaf links; pick the chain's end with --tip-link, "
                                                             "one of: c, cam"),
    Case("unknown --tip-link", {"g.urdf": GOOD_URDF}, _leg("g.urdf") + ["--tip-link", "hand"],
         "--tip-link 'hand' is not a link of the file"),
    Case("tip not below base", {"g.urdf": GOOD_URDF}, _leg("g.urdf") + ["--base-link", "b", "--tip-link", "a"],
         "--tip-link 'a' is not below --base-link 'b'"),
    Case("--tip-link on a document", {"g.yaml": GOOD_DOC}, _leg("g.yaml") + ["--tip-link", "c"],
         "--base-link/--tip-link apply to robot files (URDF, MJCF, SDF) only"),
    Case("output folder missing", {"g.yaml": GOOD_DOC}, ["convert", "{d}/g.yaml", "--to", "dh", "-o",
                                                          "{d}/no/such/dir/out.yaml"], "does not exist", writes=False),
    Case("unwritable output (name too long)", {"g.yaml": GOOD_DOC},
         ["convert", "{d}/g.yaml", "--to", "dh", "-o", "{d}/" + "x" * 300 + ".yaml"], "cannot write", writes=False),
    Case("output extension wrong for the format", {"g.yaml": GOOD_DOC}, _leg("g.yaml", "urdf", "out.yaml"),
         "--to urdf writes a .urdf file"),
    Case("batch with one bad input", {"g.yaml": GOOD_DOC, "bad.yaml": "robkin: 1\n"},
         ["convert", "{d}/g.yaml", "{d}/bad.yaml", "--to", "yaml", "-o", "{d}/batch"],
         "bad.yaml: joints: missing", writes=False, extra_files={"batch/g.yaml": "precious"}),
    Case("wrong number of joint values", {"g.yaml": GOOD_DOC}, ["fk", "{d}/g.yaml", "--q", "1,2,3"],
         "the robot has 2 joints, got 3", writes=False),
    Case("NaN joint value", {"g.yaml": GOOD_DOC}, ["fk", "{d}/g.yaml", "--q", "nan,0"], "--q", writes=False),
    Case("YAML alias bomb (billion laughs)", {"bomb.yaml": ALIAS_BOMB}, _leg("bomb.yaml"),
         "bomb.yaml: not valid YAML (line 7, column 4): f: more than 200000 values after expanding '*' aliases"),
    Case("recursive YAML alias", {"rec.yaml": "robkin: 1\njoints: &j [*j]\n"}, _leg("rec.yaml"),
         "rec.yaml: not valid YAML (line 2, column 13): joints[0]: found a recursive alias"),
    Case("integer beyond float range (YAML)", {"i.yaml": GOOD_DOC.replace("0.4,", "1" + "0" * 350 + ",")},
         _leg("i.yaml"), "i.yaml: dh.rows[1][0]: must be a finite number of magnitude at most 1e+100"),
    Case("integer over 4300 digits (JSON)", {"i.json": GOOD_JSON.replace("0.4,", "9" * 5000 + ",")},
         _leg("i.json"), "i.json: dh.rows[1][0]: must be a finite number of magnitude at most 1e+100, got inf"),
    Case("URDF mass beyond 1e100", {"m.urdf": GOOD_URDF.replace('<link name="b"/>', '<link name="b"><inertial>'
                                     '<mass value="1e308"/></inertial></link>')}, _leg("m.urdf", "mjcf", "out.xml"),
         "m.urdf: link 'b' inertial: mass value: '1e308' is beyond +-1e+100"),
    Case("servo gain beyond 1e100", {"g.urdf": GOOD_URDF},
         _leg("g.urdf", "mjcf", "out.xml") + ["--actuators", "position", "--kv", "1e308"], "--kv 1e308: a gain"),
    Case("recursive YAML alias under dh", {"ra.yaml": GOOD_DOC.replace("dh: {", "dh: &d {x: *d, ")}, _leg("ra.yaml"),
         "ra.yaml: not valid YAML (line 3, column 12): dh.x: found a recursive alias"),
    Case("more joints than MAX_JOINTS", {"many.json": '{"robkin": 1, "joints": [' + ", ".join(['"revolute"'] * 10001)
                                         + '], "dh": {"rows": [[0, 0, 0, 0]]}}'}, _leg("many.json"),
         "many.json: joints: 10001 entries; at most 10000 joints are read"),
    Case("absurdly large number (1e200)", {"h.yaml": GOOD_DOC.replace("0.4,", "1.0e200,")}, _leg("h.yaml"),
         "h.yaml: dh.rows[1][0]: must be a finite number of magnitude at most 1e+100, got '1.0e200'"),
    Case("control character in a joint name", {"cc.yaml": GOOD_DOC.replace("name: j2", 'name: "j\\e[31m2"')},
         _leg("cc.yaml"), "cc.yaml: joints[1].name: name 'j\\x1b[31m2' contains the unprintable character U+001B"),
    Case("line break in a URDF joint name", {"nl.urdf": GOOD_URDF.replace('name="j2"', 'name="j&#10;2"')},
         _leg("nl.urdf"), "nl.urdf: joints[1].name: name 'j\\n2' contains the unprintable character U+000A"),
    Case("line break in the robot name", {"rn.yaml": "name: \"evil\\nrobot\"\n" + GOOD_DOC}, _leg("rn.yaml"),
         "rn.yaml: name: name 'evil\\nrobot' contains the unprintable character U+000A"),
    Case("lone surrogate in a JSON name", {"s.json": GOOD_JSON.replace('"j2"', '"\\ud800"')}, _leg("s.json"),
         "s.json: joints[1].name: name '\\ud800' contains the unprintable character U+D800"),
    Case("huge attribute quoted in a message", {"long.urdf": GOOD_URDF.replace('type="revolute"', 'type="' + "x" * 100_000 + '"', 1)},
         _leg("long.urdf"), "long.urdf: joint 'j1': unknown type 'xxxxxxxx"),
    Case("FIFO behind a .yaml name", {}, _leg("pipe.yaml"), "pipe.yaml: is a pipe (FIFO), not a regular file",
         special={"pipe.yaml": "fifo"}),
    Case("device behind a .yaml name (/dev/zero)", {}, _leg("zero.yaml"), "zero.yaml: is a device, not a regular file",
         special={"zero.yaml": "/dev/zero"}),
    Case("folder behind a .urdf name", {}, _leg("dir.urdf"), "dir.urdf: is a folder, not a file",
         special={"dir.urdf": "folder"}),
    Case("xacro without --allow-xacro", {"x.xacro": GOOD_URDF}, _leg("x.xacro"),
         "x.xacro: not expanded: a .xacro file is a program (it can run code, read files and environment "
         "variables); if you trust it, pass --allow-xacro"),
    Case("GUI: empty file", {"e.urdf": ""}, ["gui", "{d}/e.urdf", "--port", "0"], "e.urdf: file is empty",
         writes=False),
    Case("GUI: a .xacro file", {"x.xacro": GOOD_URDF}, ["gui", "{d}/x.xacro", "--port", "0"],
         "x.xacro: the GUI never expands xacro", writes=False),
    Case("batch: a later target cannot be written", {"g.yaml": GOOD_DOC, "h.yaml": GOOD_DOC},
         ["convert", "{d}/g.yaml", "{d}/h.yaml", "--to", "yaml", "-o", "{d}/batch"], "h.yaml: is a folder",
         writes=False, extra_files={"batch/g.yaml": "precious"}, special={"batch/h.yaml": "folder"}),
    Case("estimate -o NEWDIR with a bad --plot", {}, ["estimate", "--pose", "0.5,0,0.5,0,0,0", "--joints", "3",
                                                      "--type", "all", "-o", "{d}/newdir", "--plot", "{d}/p.txt"],
         "--plot", writes=False),
    Case("check: bad second input", {"g.yaml": GOOD_DOC, "e.urdf": ""}, ["check", "{d}/g.yaml", "{d}/e.urdf"],
         "e.urdf: file is empty", writes=False),
    Case("SDF joints closing a loop", {"loop.sdf": LOOP_SDF}, _leg("loop.sdf"),
         "loop.sdf: link 'c' is the child of two joints, 'jc' and 'loop'"),
    Case("USD reference to another file", {"ref.usda": '#usda 1.0\ndef Xform "r" (\n    references = @/etc/passwd@\n)\n'
                                                       '{\n}\n'}, _leg("ref.usda"),
         "ref.usda: prim '/r' has a reference to '/etc/passwd'; robkin reads one self-contained USD file"),
    Case("USD sublayer", {"sub.usda": '#usda 1.0\n(\n    subLayers = [@other.usda@]\n)\n'}, _leg("sub.usda"),
         "sub.usda: has sublayers ('other.usda')"),
]


def make_files(case: Case, d: Path) -> None:
    """The case's input files, special files and pre-existing files in ``d``."""
    for name, content in case.files.items():
        (d / name).write_bytes(content if isinstance(content, bytes) else content.encode())
    for name, content in case.extra_files.items():
        (d / name).parent.mkdir(parents=True, exist_ok=True)
        (d / name).write_text(content)
    for name, what in case.special.items():
        if what == "fifo":
            os.mkfifo(d / name)
        elif what == "folder":
            (d / name).mkdir()
        else:
            (d / name).symlink_to(what)


def run_case(case: Case, d: Path, capsys) -> tuple[int, str]:
    make_files(case, d)
    argv = [a.replace("{d}", str(d)) for a in case.argv]
    status = main(argv)
    captured = capsys.readouterr()
    return status, captured.err


@pytest.mark.parametrize("case", CASES, ids=[c.kind for c in CASES])
def test_bad_input(case: Case, tmp_path, capsys):
    out_files = []
    if case.writes:
        for ext in (".yaml", ".json", ".urdf"):
            f = tmp_path / ("out" + ext)
            f.write_text("precious")
            out_files.append(f)
    before = {p.name for p in tmp_path.rglob("*")}
    status, err = run_case(case, tmp_path, capsys)
    assert status == 2, err
    lines = [ln for ln in err.splitlines() if not ln.startswith("robkin: warning:")]
    assert len(lines) == 1, err
    assert lines[0].startswith("robkin: error: ") and "Traceback" not in err
    assert case.expect in lines[0], lines[0]
    assert len(lines[0]) <= len("robkin: error: ") + MAX_MESSAGE  # whatever the input, the line is bounded
    for f in out_files:
        assert f.read_text() == "precious"  # not clobbered
    for name, content in case.extra_files.items():
        assert (tmp_path / name).read_text() == content
    after = {p.name for p in tmp_path.rglob("*")}
    created = (after - before - set(case.files) - set(case.special) - {Path(n).name for n in case.extra_files}
               - {Path(n).parent.name for n in case.extra_files})
    assert not created, f"files written on failure: {created}"


#: A .xacro that reads an environment variable into the robot name and, through ``$(eval ...)``, runs
#: Python that would create a file next to it; without the opt-in neither may happen.
HOSTILE_XACRO = """<?xml version="1.0"?>
<robot name="$(env ROBKIN_TEST_SECRET)" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:property name="made" value="$(eval open('{marker}', 'w').close() or 0.3)"/>
  <link name="a"/><link name="b"/>
  <joint name="j1" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0 0 0.3"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>"""
XACRO_COMMANDS = [["convert", "{x}", "--to", "dh"], ["fk", "{x}", "--q", "0"], ["ik", "{x}", "--pose", "0,0,0.3,0,0,0"],
                  ["check", "{x}", "{x}"], ["info", "{x}"], ["plot", "{x}", "-o", "{d}/p.png"],
                  ["convert", "{x}", "--to", "urdf", "-o", "{d}/out.urdf"]]


@pytest.mark.parametrize("argv", XACRO_COMMANDS, ids=[" ".join(a[:1] + a[2:3]) for a in XACRO_COMMANDS])
def test_xacro_is_refused_without_the_opt_in(argv, tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("ROBKIN_TEST_SECRET", "s3cret")
    marker = tmp_path / "code_ran"
    x = tmp_path / "evil.xacro"
    x.write_text(HOSTILE_XACRO.format(marker=marker))
    status = main([a.replace("{x}", str(x)).replace("{d}", str(tmp_path)) for a in argv])
    err = capsys.readouterr().err
    assert status == 2 and len(err.splitlines()) == 1, err
    assert "a .xacro file is a program" in err and "--allow-xacro" in err and "xacro " in err
    assert not marker.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["evil.xacro"]


def test_xacro_is_refused_in_python_and_expanded_only_on_request(tmp_path, monkeypatch):
    import robkin
    from robkin.errors import InputError
    from robkin.io.urdf import robot_from_urdf

    monkeypatch.setenv("ROBKIN_TEST_SECRET", "s3cret")
    x = tmp_path / "env.xacro"
    x.write_text(HOSTILE_XACRO.replace("$(eval open('{marker}', 'w').close() or 0.3)", "0.3"))
    for load in (robkin.load, robot_from_urdf):
        with pytest.raises(InputError, match="allow_xacro=True"):
            load(x)
    pytest.importorskip("xacro")
    assert robkin.load(x, allow_xacro=True).name == "s3cret"  # the opt-in really expands it


def test_xacro_is_never_expanded_by_the_gui(tmp_path, capsys):
    x = tmp_path / "evil.xacro"
    x.write_text(HOSTILE_XACRO.format(marker=tmp_path / "code_ran"))
    assert main(["gui", str(x), "--port", "0"]) == 2
    err = capsys.readouterr().err
    assert "evil.xacro: the GUI never expands xacro" in err and len(err.splitlines()) == 1, err
    assert not (tmp_path / "code_ran").exists()


def test_bad_inputs_table_is_current():
    assert DOC.is_file(), "docs/bad-inputs.md missing; regenerate it (see the module docstring)"
    text = DOC.read_text()
    missing = [c.kind for c in CASES if f"| {c.kind} |" not in text]
    assert not missing, f"docs/bad-inputs.md lacks {missing}; regenerate it"
    # the messages too: the page quotes what robkin prints today (it had drifted by 12 rows)
    assert text == markdown_table(), "docs/bad-inputs.md differs from what robkin prints; regenerate it"


def _short(word: str) -> str:
    """A very long token (the 300-character file name) shortened for the table."""
    return word if len(word) <= 60 else f"{word[:12]}...({len(word)} characters)...{word[-8:]}"


def markdown_table() -> str:
    """docs/bad-inputs.md: every case with the exact message robkin prints (paths shortened)."""
    import contextlib
    import io
    import tempfile

    rows = []
    for case in CASES:
        with tempfile.TemporaryDirectory() as tmp:
            d = Path(tmp)
            make_files(case, d)
            err = io.StringIO()
            with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
                status = main([a.replace("{d}", str(d)) for a in case.argv])
            line = [ln for ln in err.getvalue().splitlines() if ln.startswith("robkin: error:")][0]
            line = " ".join(_short(w) for w in line.replace(str(d) + os.sep, "").split(" "))
            cmd = " ".join(_short(a.replace("{d}/", "")) for a in case.argv)
        rows.append(f"| {case.kind} | `{cmd}` | {status} | `{line}` |")
    head = ["# Bad inputs and what robkin does with them", "",
            "Every row was run through the command line (generated by `tests/test_bad_inputs.py`, which also",
            "asserts each outcome): exit status 2, exactly one line on stderr naming the file, field or joint",
            "and what would be valid, no traceback, and no output file written or clobbered (outputs are",
            "written to a temporary file and renamed into place only on success; a batch writes every file",
            "first and renames them only when all are complete). An XML file holding a DTD is refused before",
            "parsing, so entity bombs and external entities never reach the parser. Only regular",
            "files are read, up to a byte cap (FIFOs and devices are refused before opening); YAML aliases are",
            "bounded by the size they expand to; a `.xacro` is expanded only with `--allow-xacro`. A robot",
            "has at most 10 000 joints from any input (`MAX_JOINTS`), a batch (`fk --q-file`, `ik --poses`)",
            "at most 500 000 rows (100 000 as JSON), a measurement file (`calibrate`, `check`) at most 200 000",
            "poses, of which `check` ranks the joints on 2000 with a budget of 4 * 10^6 pose evaluations (said in its",
            "output when reached), and every number at most 1e100 in magnitude. Every",
            "message is at most 1000 characters, with control characters escaped. The readers are also fuzzed",
            "(`tests/test_fuzz.py`, which also runs small hostile files under a 500 MB / 5 s limit): any",
            "exception other than robkin's InputError is a bug.", "",
            "| input | command | exit | message |", "|---|---|---|---|"]
    return "\n".join(head + rows) + "\n"


if __name__ == "__main__":  # pragma: no cover - documentation generator
    sys.path.insert(0, str(HERE))
    sys.stdout.write(markdown_table())
