"""robkin lint --fix on SDF: the corrected file changes only what lint reported, passes lint, and robkin's
SDF reader gives it the input's kinematics with the corrected masses."""

from __future__ import annotations

import numpy as np

from robkin.cli import main
from robkin.lint import lint_file

from lint_formats_files import SDF_L2_INERTIAL, sdf_arm

#: an axis of length 2, link2's inertia not positive definite, link1 without <inertial> (SDFormat's 1 kg default)
BAD = sdf_arm(j2_axis="0 2 0", l2_inertial=SDF_L2_INERTIAL.replace("<ixx>0.016</ixx>", "<ixx>-0.016</ixx>"))
BAD = BAD[:BAD.index('<link name="link1">')] + BAD[BAD.index('<link name="link1">'):].replace(
    "<inertial><pose>0 0 0.15 0 0 0</pose><mass>3</mass><inertia><ixx>0.025</ixx><iyy>0.025</iyy><izz>0.005</izz>"
    "<ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>", "", 1)


def test_fix_sdf(tmp_path, capsys):
    bad, out = tmp_path / "bad.sdf", tmp_path / "fixed.sdf"
    bad.write_text(BAD)
    before = {f.code for f in lint_file(bad)}
    assert {"axis-not-unit", "inertia-not-positive", "mass-default"} <= before
    assert main(["lint", str(bad), "--fix", "-o", str(out)]) == 0
    said = capsys.readouterr().out
    assert "axis normalised" in said and "inertia replaced" in said and "<inertial> mass" in said
    assert [f for f in lint_file(out) if f.severity != "info"] == []
    import robkin

    a, b = robkin.load(str(bad), tip_link="link2"), robkin.load(str(out), tip_link="link2")
    qs = a.random_q(20, rng=2)
    assert np.abs(a.fk(qs) - b.fk(qs)).max() < 1e-15
    # link1 now weighs its collision box (0.1 x 0.1 x 0.3 m) at 1000 kg/m^3 about its centre
    m = {i.link: i for i in b.bodies.inertials}
    assert abs(m["link1"].mass - 3.0) < 1e-12
    # only the reported places changed (lxml writes the same text elsewhere): link2's inertial and the axis
    # rewritten, link1's inertial added after its <pose>
    after = out.read_text().splitlines()
    changed = [ln for ln in BAD.splitlines() if ln not in after]
    added = [ln for ln in after if ln not in BAD.splitlines()]
    assert len(changed) == 2 and any("<xyz>0 2 0</xyz>" in c for c in changed), changed
    assert len(added) == 3 and sum("<inertial>" in a for a in added) == 2, added
