"""CSV, Markdown and LaTeX tables: full precision, exact multiples of pi, read back or rendered."""

from __future__ import annotations

import csv
import io
import json
import math
import shutil
import subprocess
import warnings

import numpy as np
import pytest

from robkin import Joint, Robot
from robkin.cli import main
from robkin.errors import InputError
from robkin.io.files.numbers import number
from robkin.io.tables.files import pi_text, render_table, table_of
from robkin.io.urdf import robot_from_urdf
from robkin.representations import DHTable, MDHTable, PoE, RPYTable, dh_from_robot

from test_urdf import robot_file, sample_q

UR5 = "ur_description/urdf/ur5_robot.urdf"
PANDA = "panda_description/urdf/panda.urdf"


def ur5() -> Robot:
    return robot_from_urdf(robot_file(UR5), "base", "tool0")


def parse_csv(text: str):
    """(header, rows, transforms) of robkin's CSV: joint rows, an empty line, then 3x4 blocks."""
    lines = list(csv.reader(io.StringIO(text)))
    head, rest = lines[0], lines[1:]
    cut = rest.index([]) if [] in rest else len(rest)
    rows = [r for r in rest[:cut] if r[:2] != ["0", "(base)"]]  # the base body's row: its masses only
    transforms = {}
    for line in rest[cut + 2:]:
        T = np.eye(4)
        T[:3] = np.array([number(v, line[0]) for v in line[1:]]).reshape(3, 4)
        transforms[line[0]] = T
    return head, rows, transforms


def joints_of(rows) -> tuple[Joint, ...]:
    return tuple(Joint(r[1], r[2].split()[0], flip="(flip)" in r[2]) for r in rows)  # type: ignore[arg-type]


@pytest.mark.parametrize("rep", ["dh", "mdh", "poe", "poe-body", "rpy-xyz", "gjd"])
@pytest.mark.parametrize("pi", [False, True])
def test_csv_reads_back_to_the_same_fk(rep, pi):
    robot = ur5()
    head, rows, transforms = parse_csv(render_table(robot, rep, "csv", pi=pi, digits="exact"))
    # the representation's own columns; UR5's mass columns (m (kg), ...) follow them
    end = head.index("m (kg)") if "m (kg)" in head else len(head)
    values = np.array([[number(v, "cell") for v in r[3:end]] for r in rows])
    Q = sample_q(robot, 6, seed=1)
    if rep in ("dh", "mdh"):
        cls = DHTable if rep == "dh" else MDHTable
        table = cls(values, joints_of(rows), transforms["base"], transforms["tool"])
        # every number read back bit for bit: the same table, so the very same FK
        expected = (dh_from_robot(robot) if rep == "dh" else __import__("robkin").mdh_from_robot(robot))
        np.testing.assert_array_equal(table.rows, expected.rows)
        fk = table.fk
    elif rep in ("poe", "poe-body"):
        fk = PoE(transforms["M"], values, joints_of(rows), "space" if rep == "poe" else "body").fk
    elif rep == "rpy-xyz":
        assert len(rows) == robot.n + 2
        fk = RPYTable(values, joints_of(rows[1:-1])).fk
    else:
        frames = np.tile(np.eye(4), (robot.n + 1, 1, 1))
        frames[:, :3] = values.reshape(-1, 3, 4)
        fk = Robot(frames, joints_of(rows[:-1])).fk
    np.testing.assert_allclose(fk(Q), robot.fk(Q), atol=1e-12)


def test_pi_multiples_only_where_exact():
    for k, m, text in ((1, 2, "pi/2"), (-1, 2, "-pi/2"), (1, 1, "pi"), (3, 4, "3*pi/4"), (-2, 3, "-2*pi/3"),
                       (1, 12, "pi/12")):
        x = k * math.pi / m
        assert pi_text(x) == text
        assert number(text, "t") == x  # reads back to the very same float
    for x in (0.0, 1.57079632679, 1.0, math.pi / 2 + 1e-16 * 8, 0.089159, 2 * math.pi + 1e-9):
        assert pi_text(x) is None, x
    # lengths never become multiples of pi, even when they happen to equal one
    robot = Robot(np.stack([np.eye(4), np.diag([1.0, 1, 1, 1]) + np.eye(4, k=3) * (math.pi / 2)]),
                  (Joint("j", "prismatic"),))
    _, rows, _ = parse_csv(render_table(robot, "dh", "csv", pi=True))
    assert "pi" not in ",".join(rows[0][3:5])


def test_ur5_dh_with_pi_shows_exact_angles_as_multiples_of_pi():
    robot = ur5()
    _, rows, _ = parse_csv(render_table(robot, "dh", "csv", pi=True, digits="exact"))
    table = dh_from_robot(robot).rows
    for r, values in zip(rows, table):
        for cell, x in zip(r[5:7], values[2:4]):  # alpha, theta
            assert cell == (pi_text(x) or ("0" if x == 0 else repr(float(x))))
    assert any("pi" in r[5] for r in rows)


def test_markdown_carries_full_precision_when_exact():
    robot = ur5()
    text = render_table(robot, "dh", "markdown", digits="exact")
    lines = [ln for ln in text.splitlines() if ln.startswith("| ") and ln[2].isdigit()][1:1 + robot.n]
    cells = np.array([[float(c) for c in ln.strip("| ").split(" | ")[3:]] for ln in lines])
    table = dh_from_robot(robot)
    np.testing.assert_array_equal(cells[:, :4], table.rows)
    # then UR5's mass properties, as full-precision as the rows: m, r (3), I (6)
    m = table.masses
    np.testing.assert_array_equal(cells[:, 4:], np.column_stack([m.mass, m.com, m.six]))
    assert "base [R | p]:" in text and "tool [R | p]:" in text


def test_latex_compiles(tmp_path):
    robot = robot_from_urdf(robot_file(PANDA), tip_link="panda_hand_tcp")
    body = "\n".join(render_table(robot, rep, "latex", pi=True) for rep in ("mdh", "dh", "rpy-xyz", "poe"))
    assert r"\frac{\pi}{2}" in body and "panda\\_joint1" in body
    if shutil.which("pdflatex") is None:
        pytest.skip("no TeX engine installed (apt-get install texlive-latex-base)")
    doc = tmp_path / "t.tex"
    doc.write_text("\\documentclass{article}\n\\usepackage{amsmath}\n\\begin{document}\n" + body +
                   "\\end{document}\n")
    run = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", "t.tex"], cwd=tmp_path,
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stdout[-2000:]
    assert (tmp_path / "t.pdf").stat().st_size > 1000


def test_hayati_table_or_a_clear_error():
    robot = ur5()
    try:
        import robkin.representations.hayati  # noqa: F401
    except ImportError:
        with pytest.raises(InputError, match="no Hayati representation"):
            table_of(robot, "hayati")
    else:
        assert [c[0] for c in table_of(robot, "hayati").columns][:5] == ["a", "d", "alpha", "theta", "beta"]


# ------------------------------------------------------------------------------------------ CLI
def test_convert_format_to_stdout_and_file(tmp_path, capsys):
    path = robot_file(UR5)
    assert main(["convert", path, "--base-link", "base", "--tip-link", "tool0", "--to", "dh", "--format", "csv",
                 "--pi"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("i,joint,type,a,d,alpha,theta,m (kg),rx (m),ry (m),rz (m),Ixx (kg m^2),Iyy (kg m^2),"
                          "Izz (kg m^2),Ixy (kg m^2),Iyz (kg m^2),Ixz (kg m^2)\n0,(base),fixed,,,,,4,0,0,0,0.00443333156,"
                          "0.00443333156,0.0072,0,0,0\n1,shoulder_pan_joint,revolute,")
    target = tmp_path / "ur5.tex"
    assert main(["convert", path, "--tip-link", "tool0", "--to", "mdh", "--format", "latex", "-o", str(target)]) == 0
    assert target.read_text().startswith("\\begin{table}")
    for argv, msg in (([path, "--tip-link", "tool0", "--to", "dh", "--format", "csv", "-o", str(tmp_path / "x.tex")],
                       "writes a .csv file"),
                      ([path, "--tip-link", "tool0", "--to", "urdf", "--format", "csv"], "is not a table"),
                      ([path, "--tip-link", "tool0", "--to", "dh", "--pi"], "--pi: applies to --format")):
        assert main(["convert"] + argv) == 2
        assert msg in capsys.readouterr().err


def test_batch_with_a_chain_per_input_into_a_new_folder(tmp_path, capsys):
    doc = tmp_path / "rrpr.yaml"
    doc.write_text(open(__import__("robkin").__path__[0] + "/examples/rrpr.yaml").read())
    out = tmp_path / "tables"
    argv = ["convert", robot_file(UR5), robot_file(PANDA), str(doc), "--tip-link", "tool0", "--tip-link",
            "panda_hand_tcp", "--tip-link", "-", "--to", "mdh", "--format", "csv", "-o", str(out)]
    assert main(argv) == 0
    assert sorted(p.name for p in out.iterdir()) == ["panda.csv", "rrpr.csv", "ur5_robot.csv"]
    _, rows, _ = parse_csv((out / "panda.csv").read_text())
    assert [r[1] for r in rows] == [f"panda_joint{i}" for i in range(1, 8)]
    capsys.readouterr()
    # all or nothing: a bad chain for one input leaves no folder behind
    bad = tmp_path / "other"
    argv[argv.index("panda_hand_tcp")] = "no_such_link"
    argv[-1] = str(bad)
    assert main(argv) == 2 and not bad.exists()
    assert "no_such_link" in capsys.readouterr().err
    # counts must match, and a document takes '-'
    for tips, msg in ((["tool0", "x"], "given 2 times for 3 inputs"), (["tool0", "panda_hand_tcp", "x"],
                                                                       "give '-' for it")):
        args = ["convert", robot_file(UR5), robot_file(PANDA), str(doc), "--to", "dh", "-o", str(bad)]
        for t in tips:
            args += ["--tip-link", t]
        assert main(args) == 2 and msg in capsys.readouterr().err
    # a file where the folder should be
    (tmp_path / "f").write_text("x")
    assert main(["convert", str(doc), str(doc), "--to", "dh", "-o", str(tmp_path / "f")]) == 2


def test_check_takes_a_chain_per_input(tmp_path):
    out = tmp_path / "ur5_flange.urdf"
    assert main(["convert", robot_file(UR5), "--tip-link", "tool0", "--to", "urdf", "-o", str(out)]) == 0
    assert main(["check", robot_file(UR5), str(out), "--tip-link", "tool0"]) == 0
    assert main(["check", robot_file(UR5), str(out), "--tip-link", "tool0", "--tip-link", "tool0"]) == 0
    # tool0 against ee_link: the same arm with another tool frame
    assert main(["check", robot_file(UR5), str(out), "--tip-link", "tool0", "--tip-link", "ee_link"]) == 1


def test_info_lists_the_chains_of_a_tree(capsys):
    assert main(["info", robot_file(PANDA), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["tree"] and [c["tip"] for c in d["chains"]] == ["panda_hand_tcp", "panda_leftfinger",
                                                            "panda_rightfinger"]
    assert [c["n"] for c in d["chains"]] == [7, 8, 8] and d["chains"][2]["mimic"] == ["panda_finger_joint2"]
    assert main(["info", robot_file(UR5)]) == 0
    text = capsys.readouterr().out
    assert "2 chains from 'base_link'" in text and "tool0" in text and "ee_link" in text
    assert main(["info", robot_file(UR5), "--base-link", "base", "--tip-link", "tool0", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["n"] == 6
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["info", robot_file("talos_data/robots/talos_full_v2.urdf"), "--base-link", "torso_2_link"]) == 0
    assert "gripper_left_base_link" not in capsys.readouterr().out  # not a leaf: the gripper hangs below it


def test_a_single_input_into_a_new_folder(tmp_path):
    import os

    doc = __import__("robkin").__path__[0] + "/examples/rrpr.yaml"
    out = tmp_path / "a"
    assert main(["convert", doc, "--to", "dh", "-o", str(out) + os.sep]) == 0
    assert [p.name for p in out.iterdir()] == ["rrpr.yaml"]
    assert main(["convert", doc, "--to", "dh", "-o", str(tmp_path / "b" / "c") + os.sep]) == 2  # one level only


#: Panda (example-robot-data) values that the frame algebra leaves with noise in the last digit
PANDA_NOISY = {"0.384", "0.316", "0.0825", "-0.0825", "0.088", "0.2104"}


@pytest.mark.parametrize("fmt", ["csv", "markdown", "latex"])
def test_default_numbers_are_short_and_within_the_fk_budget(fmt):
    """No machine noise (0.3839999999999999, -4.16e-18) by default, and the table as written still
    reproduces FK to the budget of exact conversions (1e-12 of the robot's size)."""
    from robkin.io.tables.reader import table_document
    from robkin.io.documents.reader import robot_from_data

    robot = robot_from_urdf(robot_file(PANDA), tip_link="panda_hand_tcp")
    text = render_table(robot, "mdh", fmt)
    assert "99999" not in text and "00000" not in text and "e-18" not in text and "10^{-18}" not in text
    assert all(v in text for v in PANDA_NOISY)
    if fmt == "latex":
        assert r"$\mathrm{base} = " in text and r"$\mathrm{tool} = " in text
    if fmt == "csv":
        back = robot_from_data(table_document(text))
        Q = sample_q(robot, 20, seed=4)
        np.testing.assert_allclose(back.fk(Q), robot.fk(Q), rtol=0, atol=1e-12 * robot.scale)
    exact = render_table(robot, "mdh", fmt, digits="exact")
    assert "0.3839999999999999" in exact or "0.38399999999999995" in exact


def test_digits_n():
    robot = robot_from_urdf(robot_file(PANDA), tip_link="panda_hand_tcp")
    _, rows, transforms = parse_csv(render_table(robot, "mdh", "csv", digits=3))
    assert [r[5] for r in rows] == ["0", "-1.57", "1.57", "1.57", "-1.57", "1.57", "1.57"]
    assert transforms["tool"][0, 0] == 0.707 and transforms["tool"][1, 3] == 0  # noise stays 0
