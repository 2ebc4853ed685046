"""The base body's mass properties in table files (issue 32, item 4).

DH, MDH, Hayati and PoE tables have no row for the base, so CSV, Markdown and LaTeX files once
dropped body 0's mass: ``robkin convert ur5.urdf --to dh --format csv`` then ``robkin check`` of that
file against the URDF said "mass properties: DIFFER ... body 0: 0 kg vs 4 kg". The tables now write
a row 0 ``(base)`` with the kinematic cells empty and the base's m, r, I (RPY-XYZ's world row carried
them already), and the CSV reader takes it back as the document's ``base_mass``. The oracle is the
source itself: UR5's base_link is 4 kg (its URDF), and ``check`` (kinematics and mass properties)
of each file against its source.
"""

from __future__ import annotations

import csv
import io
import os
import tempfile
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import robkin
from robkin import InputError, se3
from robkin.bodies import Bodies
from robkin.body_parts import Inertial
from robkin.cli import main
from robkin.dynamics.compare import compare_masses
from robkin.equivalence import compare
from robkin.io.tables.files import _tex, render_table
from robkin.io.tables.reader import read_table_file, table_document
from robkin.mass_properties import link_masses
from test_mass_tables import robots_with_masses
from test_properties import SCALE as PROPERTY_SCALE
from test_urdf import robot_file

UR5 = robot_file("ur_description/urdf/ur5_robot.urdf")
#: the table representations whose files carry mass columns (GJD's frames carry none)
MASS_TABLES = ("dh", "mdh", "hayati", "poe", "poe-body", "rpy-xyz")


@pytest.mark.parametrize("rep", MASS_TABLES)
def test_check_passes_on_the_csv_of_its_own_urdf(rep, tmp_path, capsys):
    """The issue's commands: convert to a CSV table, then check the table against the URDF: exit 0,
    the same mass properties, UR5's 4 kg base_link included."""
    out = tmp_path / f"ur5_{rep}.csv"
    assert main(["convert", UR5, "--tip-link", "tool0", "--to", rep, "--format", "csv", "-o", str(out)]) == 0
    capsys.readouterr()
    argv = ["check", str(out), UR5, "--tip-link", "tool0"] + (["--from", rep] if rep.startswith("poe") else [])
    code = main(argv)
    text = capsys.readouterr().out
    assert code == 0, text
    assert "mass properties: same (7 bodies, total 20.9939 kg vs 20.9939 kg" in text


@pytest.mark.parametrize("rep", ["dh", "mdh", "hayati", "poe", "poe-body"])
def test_the_base_row_in_each_format(rep):
    """Row 0 '(base)' in CSV, Markdown and LaTeX: no kinematic value, the base's 4 kg and inertia."""
    robot = robkin.load(UR5, tip_link="tool0")
    rows = list(csv.reader(io.StringIO(render_table(robot, rep, "csv"))))
    start = rows[0].index("m (kg)")
    assert rows[1][:3] == ["0", "(base)", "fixed"] and rows[1][3:start] == [""] * (start - 3)
    # UR5's base_link: mass 4, ixx = iyy = 0.00443333156, izz = 0.0072 (ur5_robot.urdf), at frame 0's origin
    assert rows[2][:2] == ["1", "shoulder_pan_joint"]
    if rep == "poe-body":  # body screws: the base's centre in the home tool frame M
        assert rows[1][start] == "4" and float(rows[1][start + 1]) == pytest.approx(0.81725, abs=1e-9)
        return
    assert rows[1][start:] == ["4", "0", "0", "0", "0.00443333156", "0.00443333156", "0.0072", "0", "0", "0"]
    md = render_table(robot, rep, "markdown")
    assert "| 0 | (base) | fixed |" + "  |" * (start - 3) + " 4 | 0 | 0 | 0 | 0.00443333156 |" in md
    tex = render_table(robot, rep, "latex")
    assert "0 & $4$ & $0$ & $0$ & $0$ \\\\" in tex  # the m, r tabular
    assert "0 & $0.00443333156$ & $0.00443333156$ & $0.0072$ \\\\" in tex  # I's diagonal
    assert "(base)" not in tex.split("\\end{tabular}")[0]  # the kinematic tabular has no base row


def test_old_files_without_a_base_row_still_read():
    """A file written before the base row (no row 0) reads as before: the links' masses, no base."""
    robot = robkin.load(UR5, tip_link="tool0")
    lines = render_table(robot, "dh", "csv").splitlines()
    old = "\n".join([lines[0], *lines[2:]]) + "\n"
    doc = table_document(old)
    assert "base_mass" not in doc["dh"] and len(doc["dh"]["rows"]) == 6
    new = table_document(render_table(robot, "dh", "csv"))
    assert new["dh"]["base_mass"]["m"] == 4.0 and new["dh"]["rows"] == doc["dh"]["rows"]


@pytest.mark.parametrize("edit, message", [
    (lambda c: c[:7] + [""] * 10, "only the base's row"),                       # empty row 0, no masses
    (lambda c: c[:7] + c[7:16] + [""], "need all ten values"),                  # one mass value missing
])
def test_a_bad_base_row_is_one_clear_error(edit, message, tmp_path):
    robot = robkin.load(UR5, tip_link="tool0")
    rows = list(csv.reader(io.StringIO(render_table(robot, "dh", "csv"))))
    rows[1] = edit(rows[1])
    path = tmp_path / "t.csv"
    with open(path, "w", newline="") as f:
        csv.writer(f, lineterminator="\n").writerows(rows)
    with pytest.raises(InputError, match=f"t.csv.*line 2: .*{message}"):
        read_table_file(path)


def test_an_rpy_table_keeps_the_base_on_its_world_row(tmp_path):
    """RPY-XYZ has a row for the base already (world->base): an empty-kinematics row 0 is refused there."""
    robot = robkin.load(UR5, tip_link="tool0")
    rows = list(csv.reader(io.StringIO(render_table(robot, "rpy-xyz", "csv"))))
    start = rows[0].index("m (kg)")
    rows[1][3:start] = [""] * (start - 3)
    path = tmp_path / "t.csv"
    with open(path, "w", newline="") as f:
        csv.writer(f, lineterminator="\n").writerows(rows)
    with pytest.raises(InputError, match="world row carries the base's mass"):
        read_table_file(path)


@st.composite
def robots_with_a_base_mass(draw) -> robkin.Robot:
    """Random robots with random inertials (``test_mass_tables``) and always a part on the base."""
    robot = draw(robots_with_masses())
    m = draw(st.floats(0.1, 20.0))
    unit = robot.scale
    R = se3.matrix_from_rpy([draw(st.floats(-np.pi, np.pi)) for _ in range(3)])
    pose = se3.homogeneous(R, [draw(st.floats(-0.5, 0.5)) * unit for _ in range(3)])
    base = Inertial("base_part", 0, pose, m, np.diag([0.02, 0.03, 0.04]) * m * unit ** 2)
    return robot.replace(bodies=Bodies(inertials=(base, *robot.bodies.inertials)))


@settings(max_examples=max(4, int(15 * PROPERTY_SCALE)), deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(robots_with_a_base_mass(), st.sampled_from(MASS_TABLES), st.sampled_from([None, "exact"]))
def test_random_robots_keep_the_base_mass_through_every_table_file(robot, rep, digits):
    """A random robot with a base mass, written as a CSV table and read back: ``check``'s two verdicts
    (same robot, same mass properties) agree with the source, body 0 included; the Markdown and LaTeX
    files carry the same base row as the CSV."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # conditioning notes of nearly parallel axes
        text = render_table(robot, rep, "csv", digits=digits)
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "t.csv")
            with open(path, "w") as f:
                f.write(text)
            back = read_table_file(path, rep if rep.startswith("poe") else None).replace(world=robot.world)
        kinematics = compare(back, robot)
        masses = compare_masses(back, robot, kinematics)
    assert kinematics.same, kinematics
    assert masses.same, masses.summary()
    # the base's mass as written: within 1e-12 of the table's largest mass (the default decimals), or exact
    total = link_masses(robot).total_mass
    assert masses.bodies[0].same and abs(masses.bodies[0].mass_a - masses.bodies[0].mass_b) <= 1e-12 * total
    assert link_masses(back).total_mass == pytest.approx(total, rel=1e-11)
    rows = list(csv.reader(io.StringIO(text)))
    start = rows[0].index("m (kg)")
    base_cells = rows[1][start:]  # the base row (RPY-XYZ: the world row) leads the table
    md = render_table(robot, rep, "markdown", digits=digits)
    assert " | ".join(base_cells) in md
    tex = render_table(robot, rep, "latex", digits=digits)
    assert "0 & " + " & ".join(f"${_tex(c)}$" for c in base_cells[:4]) + " \\\\" in tex  # the m, r tabular
