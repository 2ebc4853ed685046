"""robkin lint --fix: the corrected URDF changes only what lint reported, says each change in one line,
passes lint, loads in MuJoCo without balanceinertia/boundmass and in pinocchio, and keeps FK."""

from __future__ import annotations

import difflib

import numpy as np
import pytest

from robkin import load
from robkin.cli import main
from robkin.lint import lint_file
from robkin.lint.fix_urdf import nearest_inertia
from robkin.lint.mass_checks import principal
from robkin.samples import unit_sample

from lint_files import L2_INERTIAL, arm, write

mujoco = pytest.importorskip("mujoco")


def _mujoco(path):
    """MuJoCo's model of a URDF with the default compiler: no balanceinertia, no boundmass."""
    text = path.read_text()
    assert "balanceinertia" not in text and "boundmass" not in text
    return mujoco.MjModel.from_xml_path(str(path))


def _fix(tmp_path, text, capsys, *extra):
    src = write(tmp_path, text, "in.urdf")
    out = tmp_path / "out.urdf"
    main(["lint", str(src), "--fix", "-o", str(out), *extra])
    said = capsys.readouterr().out
    return src, out, said


def _changed_lines(a, b):
    return [ln for ln in difflib.unified_diff(a.read_text().splitlines(), b.read_text().splitlines(), lineterm="", n=0)
            if ln[:1] in "+-" and not ln.startswith(("+++", "---"))]


def _same_fk(a, b):
    ra, rb = load(a, tip_link="tool"), load(b, tip_link="tool")
    q = (unit_sample(20, ra.n) * 2 - 1) * 1.5   # inside the joints' limits (+-1.5 rad)
    assert ra.n == rb.n and np.array_equal(ra.fk(q), rb.fk(q))


def _loads_everywhere(out):
    model = _mujoco(out)
    pin = pytest.importorskip("pinocchio")
    pin.buildModelFromUrdf(str(out))
    assert [f for f in lint_file(out) if f.severity == "error"] == []
    return model


@pytest.mark.parametrize("inertia, defect", [
    ("nearest", 'izz="0.0400"'),            # triangle inequality violated
    ("nearest", 'izz="-0.0030"'),           # not positive definite
    ("nearest", 'izz="0"'),                 # rank-deficient
    ("geometry", 'izz="0.0400"'),
])
def test_invalid_inertia_replaced(tmp_path, capsys, inertia, defect):
    text = arm(l2_inertial=L2_INERTIAL.replace('izz="0.0030"', defect))
    src, out, said = _fix(tmp_path, text, capsys, "--inertia", inertia)
    with pytest.raises(Exception, match="inertia"):
        _mujoco(src)                          # MuJoCo refuses the input: the defect is real
    model = _loads_everywhere(out)
    assert "link 'link2': inertia replaced by" in said and said.count("inertia replaced") == 1
    w = principal(np.diag(model.body_inertia[-1]))[0]
    assert w[0] > 0 and w[0] + w[1] >= w[2]
    assert abs(model.body_mass[-1] - 2.0) < 1e-12  # the mass is kept
    changed = _changed_lines(src, out)
    assert len(changed) == 2 and all("<inertia" in ln for ln in changed), changed  # the one <inertial> line
    _same_fk(src, out)


def test_nearest_is_near():
    I = np.diag([0.016, 0.016, 0.040])
    J = nearest_inertia(I, 2.0)
    w = principal(J)[0]
    assert w[0] + w[1] >= w[2] * (1 + 1e-7)
    assert np.linalg.norm(J - I) < 0.01  # the projection moves each moment by (0.04 - 0.032) / 3 ~ 0.0027


def test_missing_mass_from_geometry(tmp_path, capsys):
    src, out, said = _fix(tmp_path, arm(l2_inertial=""), capsys, "--density", "2700")
    volume = 0.08 * 0.08 * 0.3
    # MuJoCo silently gives a link without <inertial> its geoms' mass at 1000 kg/m^3 (what lint says it does)
    assert _mujoco(src).body_mass[-1] == pytest.approx(1000 * volume, rel=1e-12)
    model = _loads_everywhere(out)
    assert model.body_mass[-1] == pytest.approx(2700 * volume, rel=1e-12)
    assert "mass 5.184 kg" in said and "2700 kg/m^3" in said
    _same_fk(src, out)


def test_limits_axis_and_mimic(tmp_path, capsys):
    text = arm(j2_limit='<limit lower="1.5" upper="-1.5" effort="30" velocity="2"/>', j1_axis="0 0 2",
               j2_extra='<mimic joint="nowhere"/>')
    src, out, said = _fix(tmp_path, text, capsys)
    model = _loads_everywhere(out)
    assert model.jnt_limited[1] and list(model.jnt_range[1]) == [-1.5, 1.5]
    lines = [ln for ln in said.splitlines() if ln.startswith(str(src))]
    fixes = [ln for ln in lines if "fix:" not in ln]
    assert len(fixes) == 3
    assert any("limits swapped" in ln for ln in fixes) and any("axis normalised to 0.0 0.0 1.0" in ln for ln in fixes)
    assert any("<mimic> removed (warning" in ln for ln in fixes)
    assert "<mimic" not in out.read_text()
    assert len(_changed_lines(src, out)) == 5  # the limit and axis lines (- and +), the mimic line (-)
    _same_fk(out, write(tmp_path, arm(), "plain.urdf"))


def test_unfixable_said_and_exit_1(tmp_path, capsys):
    src, out, said = _fix(tmp_path, arm(j2_axis="0 0 0"), capsys)
    assert "not fixed (axis-zero)" in said and "1 errors remain" in said
    assert main(["lint", str(src), "--fix", "-o", str(tmp_path / "o2.urdf")]) == 1


def test_fix_other_formats_says_urdf_only(tmp_path, capsys):
    from robkin.examples import EXAMPLES_DIR

    out = tmp_path / "o.yaml"
    assert main(["lint", str(EXAMPLES_DIR / "rrpr.yaml"), "--fix", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "--fix supports URDF" in err and "rrpr.yaml" in err and not out.exists()


def test_fix_needs_one_input_and_output(tmp_path):
    good = write(tmp_path, arm())
    assert main(["lint", str(good), "--fix"]) == 2
    assert main(["lint", str(good), "-o", str(tmp_path / "x.urdf")]) == 2


def test_zero_mass_refused_then_fixed(tmp_path, capsys):
    zero = '<inertial><mass value="0"/><inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial>'
    src, out, said = _fix(tmp_path, arm(l2_inertial=zero), capsys)
    with pytest.raises(Exception, match="mjMINVAL"):
        _mujoco(src)
    model = _loads_everywhere(out)
    assert model.body_mass[-1] == pytest.approx(1000 * 0.08 * 0.08 * 0.3, rel=1e-12)
