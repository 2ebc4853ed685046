"""The robot zoo's machinery (benchmarks/zoo.py, which ``make zoo`` runs to write docs/zoo.md) on two small
chains, so that the script does not rot between regenerations: every format written and read back, the
figures at rounding level, the page rendered with its summary."""

from __future__ import annotations

import importlib.util
import os
import sys
from pathlib import Path

import pytest

pytest.importorskip("pinocchio")
pytest.importorskip("mujoco")
pytest.importorskip("pxr")

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def zoo():
    spec = importlib.util.spec_from_file_location("zoo", ROOT / "benchmarks" / "zoo.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["zoo"] = module   # dataclasses look the module up
    spec.loader.exec_module(module)
    if not module.robots_dir():
        pytest.skip("example-robot-data is not installed")
    return module


def test_the_chains_are_fifty_distinct_and_present(zoo):
    chains = {(rel, base, tip) for _, _, rel, base, tip in zoo.CHAINS}
    assert len(chains) == len(zoo.CHAINS) >= 50
    assert len({label for label, *_ in zoo.CHAINS}) == len(zoo.CHAINS)
    # pybullet_data's chains are checked where pybullet is installed (the 'zoo' extra)
    present = [rel for _, _, rel, _, _ in zoo.CHAINS if not rel.startswith(zoo.PYBULLET) or zoo.pybullet_dir()]
    missing = [rel for rel in present if not os.path.exists(zoo.source_path(rel, zoo.robots_dir()))]
    assert not missing
    assert sum(rel.startswith(zoo.PYBULLET) for _, _, rel, _, _ in zoo.CHAINS) >= 10


def test_package_folders_beside_the_file(zoo, tmp_path):
    # pybullet resolves package://NAME/ against the URDF's folder; the zoo tells robkin the same
    (tmp_path / "meshes").mkdir()
    urdf = tmp_path / "r.urdf"
    urdf.write_text('<robot name="r"><link name="a"><visual><geometry><mesh filename="package://meshes/a.obj"/>'
                    '</geometry></visual></link><link name="b"><visual><geometry>'
                    '<mesh filename="package://elsewhere/b.obj"/></geometry></visual></link></robot>')
    assert zoo.local_packages(str(urdf)) == ["--package-path", f"meshes={tmp_path / 'meshes'}"]


def test_failures_caused_by_the_source_are_explained(zoo):
    row = zoo.Row("x", "leg", "pybullet:x.urdf", None, "t")
    row.mjcf["error"] = "MuJoCo: ValueError: Error: size 0 must be positive in geom"
    row.tables["dh"] = "refused: x.urdf: not well-formed XML (line 1, column 20)"
    kinds = {f.split(":", 1)[0] for f in zoo.failures(row)}
    assert kinds == {"xml", "zero-size"} and kinds <= set(zoo.REASONS)


def test_two_chains_measured_in_every_format(zoo, tmp_path):
    picked = [c for c in zoo.CHAINS if c[0] in ("Two-DoF arm (ASR)", "Double pendulum")]
    rows = []
    for i, (label, kind, rel, base, tip) in enumerate(picked):
        folder = tmp_path / str(i)
        folder.mkdir()
        rows.append(zoo.measure(zoo.Row(label, kind, rel, base, tip), os.path.join(zoo.robots_dir(), rel), folder,
                                2, False))
    for row in rows:
        assert not row.notes, row.notes   # no measurement failed
        assert row.n >= 2
        assert max(row.tables.values()) <= 1e-11                      # YAML documents, default digits
        for figures in (row.source, {k: row.urdf[k] for k in ("robkin", "fk", "M", "g")},
                        {k: row.mjcf[k] for k in ("robkin", "fk", "M", "g")}):
            assert max(figures.values()) <= 1e-12, figures           # doubles: rounding
        assert row.usd["robkin"] <= 1e-6 and row.usd["pxr"] <= 1e-6  # float32
        assert row.usd["physics"] == "ok" and row.mjcf["hold"] is True and row.mjcf["scene"] is True
        assert row.code["rtb"] == row.code["matlab"] == "ok"
    text = zoo.page(rows, 1.0, False, 2, "pytest")
    assert "## Summary" in text and text.count("\n| 1 | ") == 1 and "| 2 | " in text
    assert "Do not edit" in text


def test_a_warning_only_hold_failure_is_said_with_its_warning(zoo):
    row = zoo.Row("x", "arm", "pybullet:x.urdf", None, "t")
    row.mjcf.update(hold=False, drift=3.2e-19, drift_joint="j4", hold_line=(
        "does NOT hold home for 5 s: max drift 3.2e-19 (j4), final |qvel| 2.4e-33; home inside the limits; "
        "MuJoCo warnings: obj_decoder: invalid or missing face texture coordinate in 'link5.obj'; 0.01 ms per step"))
    row.chain_joints = ("j4",)
    (f,) = zoo.failures(row)
    assert f.startswith("texture: ") and "obj_decoder" in f and "texture" in zoo.REASONS
