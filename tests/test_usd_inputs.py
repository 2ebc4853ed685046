"""USD input that robkin must refuse, or read without following anything it names: each bad file gives
exit status 2 and one line naming the file (and prim, field), nothing else is opened, nothing written."""

from __future__ import annotations

import sys

import pytest

import robkin
from robkin.cli import main
from robkin.errors import InputError

pytest.importorskip("pxr")

#: a two-link arm as UsdPhysics text: what every case below spoils in one place
GOOD = """#usda 1.0
(
    defaultPrim = "arm"
    metersPerUnit = 1
    upAxis = "Z"
)

def Xform "arm" (prepend apiSchemas = ["PhysicsArticulationRootAPI"])
{
    def Xform "base" (prepend apiSchemas = ["PhysicsRigidBodyAPI"])
    {
    }
    def Xform "upper" (prepend apiSchemas = ["PhysicsRigidBodyAPI", "PhysicsMassAPI"])
    {
        float physics:mass = 2
        double3 xformOp:translate = (0, 0, 0.3)
        uniform token[] xformOpOrder = ["xformOp:translate"]
        EXTRA
    }
    def PhysicsFixedJoint "root"
    {
        rel physics:body1 = </arm/base>
    }
    def PhysicsRevoluteJoint "j1"
    {
        uniform token physics:axis = "Z"
        rel physics:body0 = </arm/base>
        rel physics:body1 = </arm/upper>
        point3f physics:localPos0 = LOCALPOS
        float physics:lowerLimit = -90
        float physics:upperLimit = 90
    }
}
"""


def usda(extra: str = "", localpos: str = "(0, 0, 0.3)", head: str = "") -> str:
    text = GOOD.replace("EXTRA", extra).replace("LOCALPOS", localpos)
    return text.replace('    upAxis = "Z"\n', f'    upAxis = "Z"\n{head}') if head else text


def _run(tmp_path, capsys, text: str | bytes, name: str = "bad.usda") -> tuple[int, str]:
    path = tmp_path / name
    (path.write_bytes if isinstance(text, bytes) else path.write_text)(text)
    status = main(["info", str(path)])
    return status, capsys.readouterr().err


def test_the_good_file_reads(tmp_path):
    path = tmp_path / "arm.usda"
    path.write_text(usda())
    robot = robkin.load(path)
    assert [j.name for j in robot.joints] == ["j1"] and robot.joints[0].upper == pytest.approx(1.5707963, abs=1e-7)
    assert robot.bodies.inertials[0].mass == 2.0


@pytest.mark.parametrize("text, words", [
    (usda(head='    subLayers = [@/etc/passwd@]\n'), "sublayers"),
    (usda(extra="") .replace('def Xform "base" (', 'def Xform "base" (references = @/etc/passwd@\n'), "reference"),
    (usda().replace('def Xform "base" (', 'def Xform "base" (payload = @other.usd@</x>\n'), "payload"),
    (usda().replace('def Xform "base" (', 'def Xform "base" (clips = {dictionary c = {asset[] assetPaths = '
                                           '[@a.usd@]}}\n'), "clips"),
], ids=["sublayer", "reference", "payload", "clips"])
def test_arcs_to_other_files_are_refused(tmp_path, capsys, text, words):
    status, err = _run(tmp_path, capsys, text)
    assert status == 2 and len(err.strip().splitlines()) == 1, err
    assert words in err and "bad.usda" in err and "usdcat --flatten" in err


def test_a_reference_inside_the_file_composes(tmp_path):
    """An internal reference composes, and an instanced collider (as Isaac Sim's importer instances its
    meshes) is read through its instance proxy."""
    shape = ('def Xform "collisions" (\n    instanceable = true\n    references = </proto>\n)\n{\n}\n')
    text = usda(extra=shape) + ('def Xform "proto"\n{\n    def Cube "box" (prepend apiSchemas = ["PhysicsCollisionAPI"])'
                                '\n    {\n        double size = 0.5\n    }\n}\n')
    path = tmp_path / "inner.usda"
    path.write_text(text)
    robot = robkin.load(path)
    assert robot.n == 1
    (box,) = robot.bodies.collisions()
    assert box.geometry.kind == "box" and box.geometry.size == (0.5, 0.5, 0.5) and box.link == "upper"


@pytest.mark.parametrize("text, name, words", [
    (b"hello", "bad.usda", "neither USD text"),
    (b"PK\x03\x04 zip", "bad.usd", ".usdz archive"),
    (b"PXR-USDC" + b"\x00" * 64, "bad.usdc", "not"),
    (usda().replace("def Xform", "def Xform {", 1), "bad.usda", "not valid USD"),
    (usda(localpos="(0, nan, 0.3)"), "bad.usda", "physics:localPos0"),
    ("#usda 1.0\ndef Xform \"x\"\n{\n}\n", "bad.usda", "no rigid body"),
    (usda().replace("</arm/upper>", "</arm/missing>"), "bad.usda", "physics:body1"),
    (usda().replace('uniform token physics:axis = "Z"', 'uniform token physics:axis = "W"'), "bad.usda", "physics:axis"),
    (usda().replace("float physics:lowerLimit = -90", "float physics:lowerLimit = 95"), "bad.usda", "lowerLimit"),
], ids=["text", "usdz", "crate", "syntax", "nan", "no-bodies", "missing-body", "axis", "limits"])
def test_bad_files_give_one_line(tmp_path, capsys, text, name, words):
    status, err = _run(tmp_path, capsys, text, name)
    assert status == 2 and len(err.strip().splitlines()) == 1, err
    assert words in err and name in err, err


def test_the_byte_cap_holds(tmp_path, monkeypatch):
    from robkin.io.usd import layer

    monkeypatch.setattr(layer, "MAX_BYTES", 100)
    path = tmp_path / "big.usda"
    path.write_text(usda())
    with pytest.raises(InputError, match="at most 100"):
        robkin.load(path)


def test_without_usd_core_one_line_names_the_extra(tmp_path, capsys, monkeypatch):
    path = tmp_path / "arm.usda"
    path.write_text(usda())
    monkeypatch.setitem(sys.modules, "pxr", None)  # import pxr now raises ImportError
    with pytest.raises(InputError, match=r"robkin\[usd\]"):
        robkin.load(path)
    doc = tmp_path / "r.yaml"
    doc.write_text("robkin: 1\njoints: [revolute]\ndh: {rows: [[0.1, 0.2, 0, 0]]}\n")
    out = tmp_path / "r.usda"
    assert main(["convert", str(doc), "--to", "usd", "-o", str(out)]) == 2
    assert "robkin[usd]" in capsys.readouterr().err and not out.exists()


def test_output_named_for_another_format_is_refused(tmp_path, capsys):
    doc = tmp_path / "r.yaml"
    doc.write_text("robkin: 1\njoints: [revolute]\ndh: {rows: [[0.1, 0.2, 0, 0]]}\n")
    assert main(["convert", str(doc), "--to", "usd", "-o", str(tmp_path / "r.usdz")]) == 2
    assert ".usda or .usd or .usdc" in capsys.readouterr().err and not (tmp_path / "r.usdz").exists()


def test_joints_closing_a_loop_are_left_out_with_one_warning(tmp_path):
    """upper -> base after base -> upper: that joint would close a loop (no root left)."""
    text = usda()
    loop = text[:text.rindex("}")] + '''    def PhysicsFixedJoint "back"
    {
        rel physics:body0 = </arm/upper>
        rel physics:body1 = </arm/base>
    }
}
'''
    path = tmp_path / "loop.usda"
    path.write_text(loop)
    with pytest.warns(UserWarning, match="close a loop"):
        robot = robkin.load(path)
    assert robot.n == 1


def test_deep_nesting_is_refused_before_usd_core_parses_it(tmp_path, capsys):
    """usd-core's text parser recurses: ~30 000 nested prims crash the process. Refused first, quickly."""
    import time

    n = 40_000
    path = tmp_path / "deep.usda"
    path.write_text("#usda 1.0\n" + 'def Xform "a" {\n' * n + "}\n" * n)
    start = time.perf_counter()
    assert main(["info", str(path)]) == 2
    assert "nested more than 1000 deep" in capsys.readouterr().err and time.perf_counter() - start < 5


def test_copies_of_copies_are_bounded(tmp_path, capsys, monkeypatch):
    """An internal reference on a prim that is not instanceable is refused (each level could double the
    stage); instances of instances are composed once each, and the prims looked at below the links are
    capped (each level of instance proxies doubles them)."""
    copy = usda(extra='def Xform "c" (\n    references = </proto>\n)\n{\n}\n') + 'def Xform "proto"\n{\n}\n'
    status, err = _run(tmp_path, capsys, copy)
    assert status == 2 and "copies another prim by a reference without being instanceable" in err
    levels = 12  # 2^12 boxes through instance proxies
    protos = 'def Xform "p0"\n{\n    def Cube "box" (prepend apiSchemas = ["PhysicsCollisionAPI"])\n    {\n    }\n}\n'
    for k in range(1, levels + 1):
        protos += (f'def Xform "p{k}"\n{{\n' + "".join(f'    def Xform "i{m}" (\n        instanceable = true\n'
                   f'        references = </p{k - 1}>\n    )\n    {{\n    }}\n' for m in range(2)) + "}\n")
    bomb = usda(extra=f'def Xform "c" (\n    instanceable = true\n    references = </p{levels}>\n)\n{{\n}}\n') + protos
    from robkin.io.usd import shapes_read

    monkeypatch.setattr(shapes_read, "MAX_PRIMS", 1000)
    status, err = _run(tmp_path, capsys, bomb)
    assert status == 2 and "more than 1000 prims below the links" in err, err
