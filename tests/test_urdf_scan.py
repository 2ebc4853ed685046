"""The compiled URDF scan (robkin.compiled.scanners.urdf_scan): XML edge cases, the numbers it reads, and random
URDF trees read as an independent reader (yourdfpy, on lxml) reads them."""

from __future__ import annotations

import io
import math
import warnings
from xml.etree.ElementTree import ParseError, XMLParser

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from robkin.errors import InputError
from robkin.compiled.scanners.vocabulary import MAX_ABS
from robkin.io.urdf import parse_urdf_text, robot_from_urdf

urdf_scan = pytest.importorskip("robkin.compiled.scanners.urdf_scan")
attribute_numbers = pytest.importorskip("robkin.compiled.scanners.attribute_numbers")

CHAIN = ('<robot name="r"><link name="a"/><link name="b"/>'
         '<joint name="j" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0 0 0.5" rpy="0 0 1"/>'
         '<axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="2" velocity="3"/></joint></robot>')


def joints_of(text: str) -> list[tuple]:
    return [(j.name, j.type, j.parent, j.child, j.xyz_rpy, j.axis_xyz(), j.lower, j.upper)
            for j in parse_urdf_text(text).joints]


def test_bom_comments_pis_cdata_and_whitespace_change_nothing():
    noisy = ('\ufeff<?xml version="1.0"?>\n<!-- c --><robot name="r"><?pi x?><link name="a"><![CDATA[<joint/>]]></link>'
             '\n\t<link name="b"/><!-- <joint name="fake"/> --><joint name="j" type="revolute">'
             '<!-- c --><parent link="a"/>\n<child link="b"/><?pi?><origin rpy="0 0 1" xyz="0 0 0.5"/>'
             '<axis xyz="0 1 0"/><limit velocity="3" effort="2" upper="1" lower="-1"/></joint></robot>\n<!-- end -->')
    assert joints_of(noisy) == joints_of(CHAIN)


def test_an_xml_declaration_naming_another_encoding_does_not_re_decode_the_text(tmp_path):
    """The text is already decoded (a file as UTF-8): a declared encoding is ignored, as xml.etree does
    for a string; a file that is not UTF-8 is refused by the file reader, naming it."""
    text = CHAIN.replace('"b"', '"Glied_ä_関節"')
    declared = '<?xml version="1.0" encoding="ISO-8859-1"?>' + text
    assert parse_urdf_text(declared).links == ("a", "Glied_ä_関節")
    f = tmp_path / "latin.urdf"
    f.write_bytes(declared.encode("latin-1", "replace"))
    with pytest.raises(InputError, match="latin.urdf"):
        robot_from_urdf(f)


@pytest.mark.parametrize("bad", [CHAIN[:120], CHAIN.replace("</joint>", ""), "<robot><link name='a'></robot>",
                                 "", "\x00<robot/>", "<robot>\n\n  <link name='a' name='b'/></robot>",
                                 "<robot><x:link/></robot>", "<robot/>junk", "<r\u00e9bot>\n<a></b>"])
def test_malformed_xml_names_the_line_and_column_xml_etree_gives(bad):
    parser = XMLParser()
    with pytest.raises(ParseError) as oracle:
        parser.feed(bad)
        parser.close()
    line, col = oracle.value.position
    with pytest.raises(InputError, match=rf"^s\.urdf: not well-formed XML \(line {line}, column {col + 1}\)$"):
        parse_urdf_text(bad, "s.urdf")


def test_a_lone_surrogate_is_refused_in_one_line():
    with pytest.raises(InputError, match="not valid XML"):
        parse_urdf_text(CHAIN.replace('"r"', '"\ud800"'))


def test_deep_nesting_is_refused_beyond_the_limit_and_read_within_it():
    depth = urdf_scan.MAX_DEPTH
    inside = lambda n: CHAIN.replace("</robot>", "<x>" * n + "</x>" * n + "</robot>")  # noqa: E731
    assert len(parse_urdf_text(inside(depth - 1)).joints) == 1  # robot + depth - 1 levels
    with pytest.raises(InputError, match=f"nest more than {depth} deep"):
        parse_urdf_text(inside(depth))
    # far deeper than the limit: refused after the first piece handed to expat, the rest never read
    with pytest.raises(InputError, match="nest more than"):
        parse_urdf_text("<robot>" + "<x>" * 2_000_000)


def test_a_dtd_is_refused_even_when_the_text_test_is_bypassed(monkeypatch):
    import robkin.io.urdf.parser as urdf

    monkeypatch.setattr(urdf, "_refuse_dtd", lambda text, src: None)
    with pytest.raises(InputError, match="refused XML construct"):
        parse_urdf_text('<!DOCTYPE robot [<!ENTITY a "b">]>' + CHAIN)


def test_namespaces_are_as_xml_etree_sees_them():
    """A tag in a namespace is not a URDF tag (the same for the scan and the content parse): a default
    xmlns on <robot> is refused by name, an element in another namespace is not a joint, xacro's are
    refused wherever they are, an undeclared prefix is not well-formed."""
    with pytest.raises(InputError, match=r"root element is <\{http://example.com/u\}robot>; a URDF has <robot>"):
        parse_urdf_text(CHAIN.replace('<robot name="r">', '<robot xmlns="http://example.com/u" name="r">'))
    other = CHAIN.replace("</robot>", '<o:joint xmlns:o="http://example.com/o" name="k" type="fixed"/></robot>')
    model = parse_urdf_text(other)
    assert [j.name for j in model.joints] == ["j"] and len(model.extras) == 1
    deep_xacro = CHAIN.replace('<link name="b"/>', '<link name="b"><visual><q:if xmlns:q="http://www.ros.org/wiki/xacro"'
                                                   ' value="1"/></visual></link>')
    with pytest.raises(InputError, match="contains xacro macros"):
        parse_urdf_text(deep_xacro)
    with pytest.raises(InputError, match="not well-formed XML"):
        parse_urdf_text(CHAIN.replace("<link name=\"a\"/>", "<xacro:property name='a'/><link name=\"a\"/>"))


def test_a_load_for_kinematics_builds_no_tree(monkeypatch):
    import robkin.io.urdf.parser as urdf

    calls = []
    real = urdf._parse_urdf_xml
    monkeypatch.setattr(urdf, "_parse_urdf_xml", lambda text, src: calls.append(src) or real(text, src))
    text = CHAIN.replace('<link name="b"/>', '<link name="b"><visual><geometry><box size="1 2 3"/></geometry></visual>'
                                             '</link><gazebo reference="b"/>')
    robot = robot_from_urdf(text, tip_link="b")
    np.testing.assert_allclose(robot.fk([0.0])[:3, 3], [0, 0, 0.5])
    assert calls == []
    model = parse_urdf_text(text)
    assert model.content["b"].shapes[0].geometry.size == (1.0, 2.0, 3.0)
    assert len(model.extras) == 1 and model.extras[0].startswith('<gazebo reference="b"')
    assert len(calls) == 1  # one tree for both


def test_a_hundred_thousand_joints():
    n = 100_000
    links = "".join(f'<link name="l{i}"/>' for i in range(n + 1))
    joints = "".join(f'<joint name="j{i}" type="continuous"><parent link="l{i}"/><child link="l{i + 1}"/>'
                     f'<origin xyz="0 0 0.001"/><axis xyz="0 0 1"/></joint>' for i in range(n))
    model = parse_urdf_text(f'<robot name="big">{links}{joints}</robot>')
    assert len(model.joints) == n and model.joints[-1].child == f"l{n}" and model.joints[n // 2].xyz_rpy[2] == 0.001


# ------------------------------------------------------------------------------------------ numbers
_DIGITS = st.text("0123456789", min_size=1, max_size=25)
_NUMBERISH = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.floats(-1e6, 1e6).map(lambda x: f"{x:.{abs(hash(x)) % 19}f}"),
    st.builds(lambda s, a, b, e: f"{s}{a}.{b}{e}", st.sampled_from(["", "-", "+"]), _DIGITS | st.just(""),
              _DIGITS | st.just(""), st.sampled_from(["", "e5", "E-300", "e+22", "e-23", "e", "e400", "e-0"])),
    st.text("0123456789.+-eE_ a\u0663", max_size=12),
)


def _float_semantics(text: str, count: int):
    """What the URDF reader promised before it was compiled: Python's float() on each token."""
    try:
        values = tuple(map(float, text.split()))
    except ValueError:
        return None
    if len(values) != count or not all(-1e100 <= v <= 1e100 for v in values):
        return None
    return values


@given(st.lists(_NUMBERISH, min_size=1, max_size=4), st.sampled_from([" ", "  ", "\t", "\n "]))
@settings(max_examples=400, deadline=None)
def test_numbers_read_exactly_as_float_does(parts, sep):
    text = sep.join(parts)
    for count in (1, len(text.split()) or 1):
        expected = _float_semantics(text, count)
        if expected is None:
            with pytest.raises(InputError, match="^f: x: "):
                attribute_numbers.numbers(text, count, "f", "x", ())
        else:
            got = attribute_numbers.numbers(text, count, "f", "x", ())
            assert [math.copysign(1, v) for v in got] == [math.copysign(1, v) for v in expected]
            assert got == expected
    try:
        single = float(text)
    except ValueError:
        single = None
    if single is None or math.isnan(single) or (math.isfinite(single) and abs(single) > MAX_ABS):
        with pytest.raises(InputError):  # beyond the bound too (a mass of 1e308 is none; infinity: "no limit")
            attribute_numbers.number(text, "f", "x", True)
    else:
        assert attribute_numbers.number(text, "f", "x", True) == single


def test_numbers_near_the_fast_paths_edges():
    for text in ("\ud800", "9007199254740993", "9007199254740992e22", "1e22", "1e23", "123456789012345678", "0.1e-22",
                 "4.9406564584124654e-324", "-0", "-0.0e5", "1_000", "\u0663", "1.7976931348623157e308"):
        expected = _float_semantics(text, 1)
        if expected is None:
            with pytest.raises(InputError):
                attribute_numbers.numbers(text, 1, "f", None, ())
        else:
            assert attribute_numbers.numbers(text, 1, "f", None, ()) == expected, text


# ------------------------------------------------------------------------------------------ random trees
_NAMES = st.text(st.characters(codec="utf-8", exclude_categories=("Cs", "Cc", "Zl", "Zp")), min_size=1, max_size=8)
_NUM = st.floats(-3, 3, allow_subnormal=False).map(lambda x: repr(x) if x else "0")


@st.composite
def urdf_trees(draw):
    """A random valid URDF tree: names (any script), attribute order, comments, whitespace and the
    optional elements vary; returns the text."""
    n_links = draw(st.integers(2, 7))
    names = draw(st.lists(_NAMES.filter(lambda s: s.strip() == s), min_size=2 * n_links, max_size=2 * n_links,
                          unique=True))
    links, jnames = names[:n_links], names[n_links:2 * n_links - 1]
    ws = st.sampled_from([" ", "\n  ", "\t", "  "])

    def attrs(pairs):
        pairs = draw(st.permutations(pairs))
        return "".join(f'{draw(ws)}{k}="{v}"' for k, v in pairs)

    def esc(s):
        return s.replace("&", "&amp;").replace("<", "&lt;").replace('"', "&quot;")

    parts = [f'<link name="{esc(name)}"/>' for name in links]
    for i in range(1, n_links):
        jtype = draw(st.sampled_from(["revolute", "continuous", "prismatic", "fixed"]))
        kids = [f'<parent link="{esc(links[draw(st.integers(0, i - 1))])}"/>', f'<child link="{esc(links[i])}"/>']
        if draw(st.booleans()):
            kids.append(f"<origin{attrs([('xyz', ' '.join(draw(_NUM) for _ in range(3))), ('rpy', ' '.join(draw(_NUM) for _ in range(3)))])}/>")
        if draw(st.booleans()):
            axis = draw(st.sampled_from(["1 0 0", "0 1 0", "0 0 1", "0 0 -1", "0.6 0.8 0"]))
            kids.append(f'<axis xyz="{axis}"/>')
        if jtype in ("revolute", "prismatic") or draw(st.booleans()):
            lo = draw(st.floats(-3, 0))
            kids.append(f"<limit{attrs([('lower', repr(lo)), ('upper', repr(lo + draw(st.floats(0, 3)))), ('effort', '10'), ('velocity', '2.5')])}/>")
        if draw(st.booleans()):
            kids.append(f'<dynamics{attrs([("damping", draw(_NUM).lstrip("-")), ("friction", "0.1")])}/>')
        if draw(st.booleans()):
            kids.insert(draw(st.integers(0, len(kids))), "<!-- a comment -->")
        kids = draw(st.permutations(kids))
        parts.append(f'<joint{attrs([("name", esc(jnames[i - 1])), ("type", jtype)])}>{draw(ws).join(kids)}</joint>')
    parts = draw(st.permutations(parts))
    return f'<?xml version="1.0"?>\n<robot name="rnd">\n{draw(ws).join(parts)}\n</robot>'


@given(urdf_trees())
@settings(max_examples=60, deadline=None)
def test_random_trees_read_as_yourdfpy_reads_them(text):
    yourdfpy = pytest.importorskip("yourdfpy")
    model = parse_urdf_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        oracle = yourdfpy.URDF.load(io.StringIO(text), build_scene_graph=False, load_meshes=False).robot
    assert list(model.links) == [link.name for link in oracle.links]
    assert [(j.name, j.type, j.parent, j.child) for j in model.joints] == \
        [(j.name, j.type, j.parent, j.child) for j in oracle.joints]
    for ours, theirs in zip(model.joints, oracle.joints):
        # yourdfpy composes the same rpy with numpy: equal to rounding (a few ulps of a unit rotation)
        np.testing.assert_allclose(ours.origin, np.eye(4) if theirs.origin is None else theirs.origin, atol=1e-14)
        np.testing.assert_array_equal(ours.axis, [1, 0, 0] if theirs.axis is None else theirs.axis)
        if theirs.limit is not None and ours.type in ("revolute", "prismatic"):
            assert (ours.lower, ours.upper) == (theirs.limit.lower, theirs.limit.upper)
            assert (ours.effort, ours.velocity) == (theirs.limit.effort, theirs.limit.velocity)
        if theirs.dynamics is not None:
            assert (ours.damping, ours.friction) == (float(theirs.dynamics.damping), float(theirs.dynamics.friction))

