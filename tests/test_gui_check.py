"""The GUI's visual check judges the whole robot as ``robkin check`` does (issue 32, item 2).

A Franka Panda against a copy whose link 4 is 3.1 kg instead of 3.587895 kg (the same mechanism, other
masses): ``robkin check`` says "mass properties: DIFFER" and exits 1; the page must say DIFFER too, with
the same lines and the same first difference, and show B's masses beside A's. References: the CLI's
own output (text and --json) and the masses written in the two URDF files.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from robkin.cli import main
from robkin.viz import gui_api
from robkin.viz.gui import make_server
from test_gui import PANDA, _serving, _settled, browser  # noqa: F401  (browser: the module's Chromium fixture)

CHAIN = ["--base-link", "panda_link0", "--tip-link", "panda_link8"]
LINK4_MASS = '<mass value="3.587895"/>'  # panda_link4 in example-robot-data's panda.urdf


@pytest.fixture()
def heavy(tmp_path) -> Path:
    """The Panda with link 4 at 3.1 kg: the same kinematics, other mass properties."""
    if not PANDA.is_file():
        pytest.skip("example-robot-data (test extra) is not installed")
    text = PANDA.read_text()
    assert text.count(LINK4_MASS) == 1
    path = tmp_path / "panda_heavy.urdf"
    path.write_text(text.replace(LINK4_MASS, '<mass value="3.1"/>'))
    return path


def _cli(capsys, a: Path, b: Path) -> tuple[int, list[str], dict]:
    """`robkin check A B` with the Panda's chain: exit status, printed lines, and the --json answer."""
    status = main(["check", str(a), str(b), *CHAIN])
    lines = capsys.readouterr().out.strip().splitlines()
    assert main(["check", str(a), str(b), *CHAIN, "--json"]) == status
    return status, lines, json.loads(capsys.readouterr().out)


def _gui_check(a: Path, b: Path) -> dict:
    other = {"text": b.read_text(), "fmt": "urdf", "base_link": "panda_link0", "tip_link": "panda_link8"}
    return gui_api.describe(a.read_text(), "urdf", None, "panda_link0", "panda_link8", other=other)["check"]


def test_api_check_of_masses_is_robkin_checks(heavy, capsys):
    status, lines, cli = _cli(capsys, PANDA, heavy)
    assert status == 1 and cli["same"] and cli["mass"]["same"] is False  # kinematics same, masses DIFFER
    check = _gui_check(PANDA, heavy)
    assert check["same"] is False  # not "same robot" in green
    # the verdict and mass-properties lines exactly as `robkin check` prints them, last two lines
    assert check["lines"] == lines[-2:] and "mass properties: DIFFER" in check["lines"][1]
    assert check["first_difference"] == cli["mass"]["first_difference"]
    assert check["first_difference"].startswith("body 4 ('panda_link4'")
    assert check["mass"] == cli["mass"] and check["comparison"]["verdict"] == cli["verdict"]
    # B's masses beside A's, as the files give them
    body4 = check["masses"][4]
    assert (body4["mass_a"], body4["mass_b"], body4["same"]) == (3.587895, 3.1, False)
    assert all(row["same"] for row in check["masses"] if row["body"] != 4)
    json.dumps(check, allow_nan=False)  # what the server sends must be valid JSON


def test_api_check_same_pair_is_same_as_robkin_check(capsys):
    if not PANDA.is_file():
        pytest.skip("example-robot-data (test extra) is not installed")
    status, lines, cli = _cli(capsys, PANDA, PANDA)
    check = _gui_check(PANDA, PANDA)
    assert status == 0 and check["same"] is True and check["first_difference"] is None
    assert check["lines"] == lines[-2:] and check["mass"]["same"] is True


@pytest.fixture()
def heavy_page(browser, heavy):  # noqa: F811 - the imported fixture, used by name
    srv = make_server(port=0, text=PANDA.read_text(), fmt="urdf", base_link="panda_link0", tip_link="panda_link8",
                      source=str(PANDA), other={"text": heavy.read_text(), "fmt": "urdf", "source": str(heavy),
                                                "base_link": "panda_link0", "tip_link": "panda_link8"})
    yield from _serving(browser, srv)


def test_browser_check_of_masses_is_robkin_checks(heavy_page, heavy, capsys):
    status, lines, cli = _cli(capsys, PANDA, heavy)
    pg = heavy_page
    pg.wait_for_selector("#check:not([hidden])")
    _settled(pg)
    verdict = pg.query_selector("#check-verdict")
    assert "differs" in verdict.get_attribute("class").split()  # red, not the green of "same"
    assert pg.inner_text("#check-verdict .headline").startswith("DIFFER")
    assert [e.inner_text() for e in pg.query_selector_all("#check-verdict .line")] == lines[-2:]
    assert pg.inner_text("#check-first").startswith("first difference: " + cli["mass"]["first_difference"])
    # B's masses beside A's: body 4 is 3.587895 kg in A and 3.1 kg in B, its row red
    row = pg.query_selector_all("#check-masses tr")[1 + 4]
    cells = row.query_selector_all("td")
    assert cells[0].inner_text() == "4" and "panda_link4" in cells[1].inner_text()
    assert (float(cells[2].get_attribute("title")), float(cells[3].get_attribute("title"))) == (3.587895, 3.1)
    assert row.get_attribute("class") == "differs"
