"""The registry of representations: today's representations in today's order, and a new one (a toy
standard DH table with its lengths in millimetres, defined here) registered with one call shows up in
``robkin convert --to``, in robot documents, in table files and in ``robkin check``."""

from __future__ import annotations

import subprocess
import sys
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
import pytest
import yaml

from robkin import se3
from robkin.cli import main
from robkin.examples import EXAMPLES_DIR
from robkin.representations import registry
from robkin.representations.link_table import LinkTable, joint_links, joint_signs
from robkin.representations.registry import Column, Representation

ARM = str(EXAMPLES_DIR / "iiwa14.yaml")
CLI_ORDER = ("dh", "mdh", "hayati", "poe", "poe-body", "rpy-xyz", "gjd")
DOCUMENT_ORDER = ("gjd", "dh", "mdh", "hayati", "rpy_xyz", "poe", "poe_body")

# ------------------------------------------------------------------------------- the toy representation
#: rows in millimetres (a, d) and radians (alpha, theta) -> metres and radians
MM = np.array([1e-3, 1e-3, 1.0, 1.0])


@dataclass(frozen=True, eq=False)
class DHmmTable(LinkTable):
    """A standard DH table whose lengths (a, d) are in millimetres."""

    SECTION: ClassVar[str] = "dh_mm"
    COLUMNS: ClassVar[tuple[str, ...]] = ("a_mm", "d_mm", "alpha", "theta")

    def link_transforms(self, q: Any) -> np.ndarray:
        revolute, sign = joint_signs(self.joints)
        return joint_links(se3.dh_matrix, self.rows * MM, revolute, sign, np.asarray(q, dtype=float))

    def to_robot(self, name: str | None = None):
        return robot_from_dhmm(self, name=name)


def dhmm_from_robot(robot) -> DHmmTable:
    from robkin.representations import dh_from_robot

    t = dh_from_robot(robot)
    return DHmmTable(t.rows / MM, t.joints, t.base, t.tool, t.masses)


def robot_from_dhmm(table: DHmmTable, name: str | None = None):
    from robkin.representations.dh import DHTable

    return DHTable(table.rows * MM, table.joints, table.base, table.tool, table.masses).to_robot(name)


TOY = Representation(
    "dh-mm", "dh_mm", "standard DH table, lengths in mm (+ base and tool)", "standard DH (mm)", "link-table",
    module=__name__, from_robot="dhmm_from_robot", to_robot="robot_from_dhmm", table_class="DHmmTable",
    columns=(Column("a_mm", "a_mm", "$a_i$ (mm)", "length"), Column("d_mm", "d_mm", "$d_i$ (mm)", "length"),
             Column("alpha", "alpha", r"$\alpha_i$", "angle"), Column("theta", "theta", r"$\theta_i$", "angle")),
    frame_based=True, help="standard DH, lengths in millimetres", overlay_label="DH (mm)")


@pytest.fixture
def toy():
    registry.register(TOY)
    try:
        yield TOY
    finally:
        registry.unregister(TOY.name)


# ------------------------------------------------------------------------------- today's registry
def test_the_registry_lists_todays_representations_in_todays_order():
    from robkin.io.documents.vocabulary import ANGLE_COLUMNS, SECTIONS
    from robkin.io.tables.files import TABLE_REPRESENTATIONS
    from robkin.io.tables.reader import TABLE_INPUTS
    from robkin.io.tables.terminal import FORMATS

    assert registry.names() == CLI_ORDER
    assert registry.sections() == DOCUMENT_ORDER
    assert tuple(SECTIONS) == DOCUMENT_ORDER and SECTIONS == DOCUMENT_ORDER
    assert tuple(FORMATS) == CLI_ORDER == tuple(TABLE_REPRESENTATIONS) == tuple(TABLE_INPUTS)
    assert dict(ANGLE_COLUMNS) == {"dh": ("alpha", "theta"), "mdh": ("alpha", "theta"),
                                   "hayati": ("alpha", "theta", "beta"), "rpy_xyz": ("roll", "pitch", "yaw")}
    assert [r.section for r in registry.representations()] == ["dh", "mdh", "hayati", "poe", "poe_body",
                                                              "rpy_xyz", "gjd"]
    assert [r.name for r in registry.representations() if r.frame_based] == ["dh", "mdh", "hayati"]


def test_tables_know_their_representation():
    from robkin import load
    from robkin.representations import dh_from_robot, hayati_from_robot, poe_from_robot, rpy_from_robot

    robot = load(ARM)
    assert registry.of_table(dh_from_robot(robot)).name == "dh"
    assert registry.of_table(hayati_from_robot(robot)).name == "hayati"
    assert registry.of_table(poe_from_robot(robot, "body")).name == "poe-body"
    assert registry.of_table(rpy_from_robot(robot)).section == "rpy_xyz"
    with pytest.raises(TypeError, match="no registered representation"):
        registry.of_table(object())


def test_register_refuses_a_taken_name_or_section_and_an_unknown_layout():

    with pytest.raises(ValueError, match="already registered"):
        registry.register(TOY._replace(name="dh"))
    with pytest.raises(ValueError, match="already registered"):
        registry.register(TOY._replace(section="poe_body"))
    with pytest.raises(ValueError, match="layout"):
        registry.register(TOY._replace(layout="sheet"))
    assert registry.names() == CLI_ORDER


def test_the_registry_imports_nothing_heavy():
    code = ("import sys, robkin.representations.registry as r; r.by_name('poe').columns; "
            "print(sorted(m for m in sys.modules if m.startswith('robkin.representations.')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert out == "['robkin.representations.registry']"


# ------------------------------------------------------------------------------- a registered toy
def test_a_registered_table_is_a_convert_target(toy, capsys):
    from robkin import load
    from robkin.representations import dh_from_robot

    assert main(["convert", ARM, "--to", "dh-mm"]) == 0
    out = capsys.readouterr().out
    assert ": standard DH table, lengths in mm (+ base and tool)" in out.splitlines()[0]
    heads = out.splitlines()[1].split()
    assert heads == ["i", "joint", "type", "a_mm", "d_mm", "alpha", "theta"]
    table = dhmm_from_robot(load(ARM))
    assert str(table).splitlines()[1:] == out.splitlines()[1:]  # the same table; str() has no robot name
    np.testing.assert_allclose(table.rows[:, :2], dh_from_robot(load(ARM)).rows[:, :2] * 1000)
    with pytest.raises(SystemExit):
        main(["convert", ARM, "--help"])
    assert "dh-mm     standard DH, lengths in millimetres" in capsys.readouterr().out


def test_a_registered_table_is_a_document_section(toy, capsys, tmp_path):
    from robkin import load

    assert main(["convert", ARM, "--to", "yaml"]) == 0
    doc = yaml.safe_load(capsys.readouterr().out)
    assert [k for k in doc if k in (*DOCUMENT_ORDER, "dh_mm")] == [*DOCUMENT_ORDER, "dh_mm"]
    assert set(doc["dh_mm"]["rows"][0]) == {"a_mm", "d_mm", "alpha", "theta"}
    out = tmp_path / "arm_mm.yaml"
    assert main(["convert", ARM, "--to", "dh-mm", "-o", str(out), "--degrees"]) == 0
    written = yaml.safe_load(out.read_text())
    assert "dh_mm" in written and not set(DOCUMENT_ORDER) & set(written)
    assert written["angles"] == "degrees"
    robot, back = load(ARM), load(out)
    Q = np.random.default_rng(0).uniform(-3, 3, (5, robot.n))
    np.testing.assert_allclose(back.fk(Q), robot.fk(Q), atol=1e-9)
    assert dhmm_from_robot(robot).to_dict()["dh_mm"]["rows"][0].keys() == {"a_mm", "d_mm", "alpha", "theta"}


def test_check_reads_a_document_of_the_registered_section_only(toy, tmp_path, capsys):
    doc = tmp_path / "only_mm.yaml"
    assert main(["convert", ARM, "--to", "dh-mm", "-o", str(doc)]) == 0
    assert "dh_mm" in yaml.safe_load(doc.read_text())
    capsys.readouterr()
    assert main(["check", str(doc), ARM]) == 0
    assert "verdict: same robot" in capsys.readouterr().out
    # and a wrong one is caught
    text = doc.read_text().replace("theta: ", "theta: 0.1 + ", 1)
    doc.write_text(text)
    assert main(["check", str(doc), ARM]) == 1


def test_a_registered_table_is_a_table_file(toy, tmp_path, capsys):
    from robkin import load

    out = tmp_path / "arm_mm.csv"
    assert main(["convert", ARM, "--to", "dh-mm", "--format", "csv", "-o", str(out)]) == 0
    assert out.read_text().splitlines()[0] == "i,joint,type,a_mm,d_mm,alpha,theta"
    robot, back = load(ARM), load(out)
    Q = np.random.default_rng(1).uniform(-3, 3, (5, robot.n))
    np.testing.assert_allclose(back.fk(Q), robot.fk(Q), atol=1e-9)
    assert main(["convert", ARM, "--to", "dh-mm", "--format", "latex"]) == 0
    assert "$a_i$ (mm)" in capsys.readouterr().out


def test_unregistered_the_toy_is_gone(toy):
    registry.unregister(TOY.name)
    try:
        assert registry.names() == CLI_ORDER
        with pytest.raises(SystemExit):
            main(["convert", ARM, "--to", "dh-mm"])
    finally:
        registry.register(TOY)
