"""The compiled SDF scan (robkin.compiled.scanners.sdf_scan): the elements it keeps are xml.etree's, the ones the
reader does not read are skipped, and XML that is not well-formed is refused as ``_parse_xml`` refuses it."""

from __future__ import annotations

import random

import pytest

from robkin.errors import InputError
from robkin.io.trees.xml_parse import _parse_xml

sdf_scan = pytest.importorskip("robkin.compiled.scanners.sdf_scan")

TEXT = ('<?xml version="1.0"?>\n<sdf version="1.9" xmlns:g="http://g"><world name="w"><model name="m" canonical_link="a">'
        '<pose>1 2 3 0 0 0</pose><plugin name="p"><pose>9 9 9 0 0 0</pose></plugin>'
        '<link name="a"><pose relative_to="__model__"> 0 0 1 <!-- c --> 0 0 0 </pose><inertial><mass>2</mass></inertial>'
        '<visual name="v"><geometry><box><size>1 1 1</size></box></geometry></visual></link>'
        '<link name="b"><pose>0 0 0 0 0 0<g:x/>tail</pose></link><frame name="f" attached_to="a"><pose>0 0 0.1 0 0 0</pose></frame>'
        '<joint name="j" type="revolute"><parent>a</parent><child>b</child><pose relative_to="a">0 0 1 0 0 0</pose>'
        '<axis><xyz expressed_in="a">0 1 0</xyz><use_parent_model_frame>0</use_parent_model_frame><limit><lower>-1</lower>'
        '<upper>&#49;</upper><effort>5</effort><velocity><![CDATA[2]]></velocity></limit>'
        '<dynamics><damping>0.5</damping><friction>0</friction><spring_stiffness>1</spring_stiffness></dynamics></axis>'
        '<sensor name="s"/></joint><model name="inner"><link name="c"/></model><include><uri>model://x</uri></include>'
        '<g:ext g:a="1"/></model></world></sdf>')


def _pairs(kept, full, path="sdf"):
    """(path, kept element, xml.etree element) of every kept element, walked together."""
    yield path, kept, full
    for tag in dict.fromkeys(c.tag for c in full):
        ours, theirs = kept.findall(tag), full.findall(tag)
        assert not ours or len(ours) == len(theirs), f"{path}/{tag}: some of them kept"
        for a, b in zip(ours, theirs):
            yield from _pairs(a, b, f"{path}/{tag}")


def test_kept_elements_are_xml_etrees_and_the_rest_is_skipped():
    kept, full = sdf_scan.kinematic_tree(TEXT, "t"), _parse_xml(TEXT, "t")
    paths = []
    for path, a, b in _pairs(kept, full):
        paths.append(path)
        assert a.tag == b.tag and [a.get(k) for k in b.attrib] == list(b.attrib.values()), path
        if a.text is not None or path.rsplit("/", 1)[-1] in ("pose", "parent", "child", "xyz", "lower", "upper"):
            assert a.text == b.text, path  # text up to the first child, entities and CDATA resolved
    model = "sdf/world/model"
    assert set(paths) == {"sdf", "sdf/world", model, f"{model}/pose", f"{model}/link", f"{model}/link/pose",
                          f"{model}/frame", f"{model}/frame/pose", f"{model}/joint", f"{model}/joint/parent",
                          f"{model}/joint/child", f"{model}/joint/pose", f"{model}/joint/axis", f"{model}/joint/axis/xyz",
                          f"{model}/joint/axis/use_parent_model_frame", f"{model}/joint/axis/limit",
                          f"{model}/joint/axis/limit/lower", f"{model}/joint/axis/limit/upper",
                          f"{model}/joint/axis/limit/effort", f"{model}/joint/axis/limit/velocity",
                          f"{model}/joint/axis/dynamics", f"{model}/joint/axis/dynamics/damping",
                          f"{model}/joint/axis/dynamics/friction", f"{model}/model", f"{model}/model/link",
                          f"{model}/include"}
    link = kept.find("world").find("model").find("link")
    assert link.find("visual") is None and link.find("inertial") is None  # parsed later, only when asked for
    assert kept.get("missing", "d") == "d" and link.findtext("nothing") is None
    assert kept.find("world").find("model").find("joint").findtext("axis") == ""  # an element without text


def test_xml_that_is_not_well_formed_is_refused_where_xml_etree_refuses_it():
    rng = random.Random(3)
    bits = ["<", "&", "&nope;", "]]>", "<a:b/>", '"', "</link>", "<!-- -- -->", "\x00", "<?xml?>"]
    refused = 0
    for _ in range(300):
        text = TEXT
        if rng.random() < 0.3:
            text = text[: rng.randrange(1, len(text))]
        else:
            i = rng.randrange(len(text))
            text = text[:i] + rng.choice(bits) + text[i:]
        try:
            _parse_xml(text, "t")
            expected = None
        except InputError as exc:
            expected = str(exc)
            refused += 1
        if expected is None:
            sdf_scan.kinematic_tree(text, "t")
        else:
            with pytest.raises(InputError) as got:
                sdf_scan.kinematic_tree(text, "t")
            assert str(got.value) == expected
    assert refused > 200  # the mutations above break most texts
