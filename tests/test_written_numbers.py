"""Numbers in written files (issue 32, item 10): no digit beyond a value's shortest round trip, the
source's zeros stay exactly 0, and a LaTeX table of a 7-joint arm with masses fits an A4 page.

Oracles: Python's ``repr`` (the shortest decimal that reads back to the same float) for the digits; for
the zeros, a source whose inertias have exactly-zero products and whose frames are all turned by exact
multiples of pi/2 from one another (a vendor DH table of the UR5, UR's published masses), so that the
product of inertia is exactly 0 in every frame any table uses, whatever rounding the frame algebra
leaves (cos(pi/2) is 6.1e-17 in floats); for the page, pdflatex's own overfull-box report (skipped
where no TeX engine is installed).
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import warnings

import numpy as np
import pytest

import robkin
from robkin.cli import main
from robkin.io.documents.reader import parse_document
from robkin.io.tables.files import render_table
from robkin.representations import dh_from_robot
from test_urdf import robot_file

ERD = os.path.dirname(os.path.dirname(robot_file("ur_description/urdf/ur5_robot.urdf")))
CASES = {"ur5": ("ur_description/urdf/ur5_robot.urdf", "tool0"),
         "panda": ("panda_description/urdf/panda.urdf", "panda_hand_tcp")}
#: a number in a text: not part of a name (link1, panda_joint7) or a longer token
NUMBER = re.compile(r"(?<![\w.])[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?(?![\w.])")


def significant(text: str) -> str:
    """The significant digits of a decimal ('0.01615' -> '1615', '150.0' -> '15', '1e-06' -> '1')."""
    mantissa = re.split(r"[eE]", text.lstrip("+-"))[0].replace(".", "")
    return mantissa.strip("0") or "0"


def test_significant():
    assert [significant(t) for t in ("0.01615", "150.0", "1e-06", "-0", "0.0002549260522310832")] == \
        ["1615", "15", "1", "0", "2549260522310832"]


@pytest.mark.parametrize("case", sorted(CASES))
def test_no_number_has_more_digits_than_its_round_trip(case, tmp_path, capsys):
    """UR5 and Panda URDF -> every writer (robot files, documents, toolbox code, table files): each
    number written is at most as long as the shortest decimal that reads back to its float."""
    rel, tip = CASES[case]
    writers = [["--to", to] for to in ("urdf", "mjcf", "usd", "yaml", "json", "rtb", "matlab")]
    writers += [["--to", rep, "--format", fmt] + extra for rep in ("dh", "mdh", "poe", "rpy-xyz", "gjd", "hayati")
                for fmt in ("csv", "markdown", "latex") for extra in ([], ["--exact"])]
    for k, argv in enumerate(writers):
        out = tmp_path / str(k)
        out.mkdir()
        code = main(["convert", robot_file(rel), "--tip-link", tip, "--package-path", f"example-robot-data={ERD}",
                     *argv, "-o", str(out) + "/"])
        if code != 0 and "hayati" in argv:  # a robot without a Hayati table says so
            continue
        assert code == 0, (argv, capsys.readouterr().err)
        texts = [p for p in out.rglob("*") if p.suffix in (".urdf", ".xml", ".usda", ".yaml", ".json", ".py", ".m",
                                                             ".csv", ".md", ".tex")]
        assert texts, argv
        for path in texts:
            text = re.sub(r"([-\d.]+) \\times 10\^\{(-?\d+)\}", r"\1e\2", path.read_text())  # LaTeX's 1.5e-12
            for token in NUMBER.findall(text):
                value = float(token)
                if not np.isfinite(value) or value == 0:
                    continue
                assert len(significant(token)) <= len(significant(repr(value))), (argv, path.name, token)
    capsys.readouterr()


#: UR5 as Universal Robots publish it: standard DH, exact right angles, each link's mass, centre of
#: mass and a diagonal inertia in its DH frame, the base's 4 kg (ur5_robot.urdf) too.
UR5_VENDOR = """robkin: 1
name: ur5-vendor
joints: [revolute, revolute, revolute, revolute, revolute, revolute]
dh:
  base_mass: {m: 4, r: [0, 0, 0.01], I: [0.00443333156, 0.00443333156, 0.0072, 0, 0, 0]}
  rows:
    - {a: 0, d: 0.089159, alpha: pi/2, theta: 0, m: 3.7, r: [0, -0.02561, 0.00193], I: [0.0102675, 0.0102675, 0.00666, 0, 0, 0]}
    - {a: -0.425, d: 0, alpha: 0, theta: 0, m: 8.393, r: [0.2125, 0, 0.11336], I: [0.0151074, 0.2268907, 0.2268907, 0, 0, 0]}
    - {a: -0.39225, d: 0, alpha: 0, theta: 0, m: 2.275, r: [0.15, 0, 0.0265], I: [0.004095, 0.0494433, 0.0494433, 0, 0, 0]}
    - {a: 0, d: 0.10915, alpha: pi/2, theta: 0, m: 1.219, r: [0, -0.0018, 0.01634], I: [0.1111728, 0.1111728, 0.21942, 0, 0, 0]}
    - {a: 0, d: 0.09465, alpha: -pi/2, theta: 0, m: 1.219, r: [0, 0.0018, 0.01634], I: [0.1111728, 0.21942, 0.1111728, 0, 0, 0]}
    - {a: 0, d: 0.0823, alpha: 0, theta: 0, m: 0.1879, r: [0, 0, -0.001159], I: [0.0171365, 0.0171365, 0.033822, 0, 0, 0]}
"""


def _read(text: str) -> robkin.Robot:
    return parse_document(text, "yaml")


@pytest.mark.parametrize("rep", ["dh", "mdh", "hayati", "poe", "poe-body", "rpy-xyz"])
def test_zero_products_of_inertia_stay_zero_in_every_table(rep):
    """Every frame a table uses is turned by exact multiples of pi/2 from the DH frames the products
    were 0 in: written with every digit, each product is '0' (it was 1e-18 .. 1e-36 noise: the
    rotations' cos(pi/2) = 6.1e-17, the parallel-axis term of m c / m's last bit)."""
    robot = _read(UR5_VENDOR)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        text = render_table(robot, rep, "csv", digits="exact")
    lines = [line.split(",") for line in text.splitlines()]
    head = lines[0]
    at = head.index("Ixy (kg m^2)")
    rows = [cells for cells in lines[1:] if len(cells) == len(head) and cells[at]]
    assert len(rows) == 7  # the base and the six links
    assert all(cells[at:at + 3] == ["0", "0", "0"] for cells in rows), rows


def test_zero_products_stay_zero_in_documents_code_and_urdf(tmp_path, capsys):
    robot = _read(UR5_VENDOR)
    doc = tmp_path / "ur5.yaml"
    doc.write_text(UR5_VENDOR)
    for to in ("json", "rtb", "matlab", "urdf"):
        out = tmp_path / ("out." + {"rtb": "py", "matlab": "m"}.get(to, to))
        assert main(["convert", str(doc), "--to", to, "-o", str(out)]) == 0
        text = out.read_text()
        if to == "json":
            data = json.loads(text)
            for key in ("dh", "mdh", "hayati", "rpy_xyz"):
                entries = [r for r in data[key]["rows"] if "I" in r]
                assert entries and all(r["I"][3:] == [0.0, 0.0, 0.0] for r in entries), key
            for key in ("poe", "poe_body"):
                assert all(e["I"][3:] == [0.0, 0.0, 0.0] for e in data[key]["masses"]), key
        elif to == "urdf":
            assert text.count('ixy="0" ixz="0"') == 7 and text.count('iyz="0"') == 7
        else:  # I=[[Ixx, 0, 0], [0, Iyy, 0], [0, 0, Izz]] per link, nothing like 2.2e-19 off the diagonal
            assert not re.search(r"\de-(1[5-9]|[2-9]\d)", text), re.findall(r"\S*\de-(?:1[5-9]|[2-9]\d)\S*", text)
    capsys.readouterr()
    assert robot.n == 6


def test_source_products_that_are_not_zero_are_kept():
    """The cleaning zeroes only what is 0 by structure: UR5's URDF tilts (1.57079632679 for pi/2,
    4.9e-12 rad off) give real products of 1e-13, written as they are; Panda's own products stay."""
    ur5 = robkin.load(robot_file(CASES["ur5"][0]), tip_link="tool0")
    text = render_table(ur5, "dh", "csv", digits="exact")
    assert "-8.170114322806101e-14" in text   # link 6's Iyz: 4.9e-12 rad times (Izz - Iyy), not noise
    panda = robkin.load(robot_file(CASES["panda"][0]), tip_link="panda_hand_tcp")
    m = dh_from_robot(panda).masses
    assert np.count_nonzero(m.six[:, 3:]) >= 18  # Panda's inertias are full tensors


def test_latex_of_a_seven_joint_arm_with_masses_fits_an_a4_page(tmp_path):
    """Panda (7 joints, masses) in every table: the kinematics (a PoE's omega then v, a GJD's rotation
    rows then position) and the mass properties in tabulars that fit the text width of an A4 article
    (before: DH's one 17-column tabular was 185 pt too wide, body-frame PoE's 221 pt, GJD's 384 pt).
    Measured by pdflatex: no overfull box."""
    panda = robkin.load(robot_file(CASES["panda"][0]), tip_link="panda_hand_tcp")
    body = "\n".join(render_table(panda, rep, "latex", pi=True) + "\\clearpage"
                     for rep in ("dh", "mdh", "hayati", "poe", "poe-body", "rpy-xyz", "gjd"))
    tex = render_table(panda, "dh", "latex")
    assert tex.count("\\begin{tabular}") == 4  # kinematics; m and r; I's diagonal; I's products
    assert max(len(line.split(" & ")) for line in tex.splitlines() if " & " in line and "bmatrix" not in line) <= 7
    if shutil.which("pdflatex") is None:
        pytest.skip("no TeX engine installed (apt-get install texlive-latex-base)")
    (tmp_path / "t.tex").write_text("\\documentclass[a4paper]{article}\n\\usepackage{amsmath}\n"
                                    "\\begin{document}\n" + body + "\n\\end{document}\n")
    run = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", "t.tex"], cwd=tmp_path,
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stdout[-2000:]
    log = (tmp_path / "t.log").read_text(errors="replace")
    assert "Overfull \\hbox" not in log, re.findall(r"Overfull \\hbox \([\d.]+pt too wide\)", log)
