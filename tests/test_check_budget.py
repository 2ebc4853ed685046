"""robkin check MODEL MEASUREMENTS: the joint-by-joint fits' bounds (an even subset of the poses, a work
budget in pose evaluations), said when they apply, and no change to a normal diagnosis.

Time is not asserted here (the machines are shared): the work is bounded by counting, and what that
costs in seconds is measured in the closing notes of issue 30 and in ``diagnosis.WORK``'s comment.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import robkin
from robkin.calibration import diagnosis, simulate, write_measurements_csv
from robkin.calibration.fit import Budget
from robkin.calibration.simulation import perturbed
from robkin.cli import main

UR5_DH = ("robkin: 1\njoints: [revolute, revolute, revolute, revolute, revolute, revolute]\n"
          "dh: {rows: [[0, 0.089, 1.5708, 0], [-0.425, 0, 0, 0], [-0.392, 0, 0, 0], [0, 0.109, 1.5708, 0],"
          " [0, 0.095, -1.5708, 0], [0, 0.082, 0, 0]]}\n")


@pytest.fixture(scope="module")
def case(tmp_path_factory):
    """A UR5 whose elbow is 4 mrad off at zero and whose forearm is 1 mm long, measured at 120 poses
    with 50 um of noise: a normal campaign the model does not explain (RMS ~1 mm > the 0.5 mm tol)."""
    folder = tmp_path_factory.mktemp("budget")
    model = folder / "ur5.yaml"
    model.write_text(UR5_DH)
    robot = robkin.load(model)
    motions = np.zeros((6, 6))
    motions[2, 5] = 0.004
    motions[3, 0] = 0.001
    real = perturbed(robot, motions).replace(world=robkin.se3.trans(1.2, -0.3, 0.4))
    Q = simulate(robot, 120, seed=5).q
    P = (real.world @ real.fk(Q))[:, :3, 3] + np.random.default_rng(5).normal(0.0, 50e-6, (120, 3))
    meas = folder / "m.csv"
    write_measurements_csv(meas, robot, Q, P)
    return model, meas, robot, Q, P


class Counting(Budget):
    """A Budget that keeps every instance made, to read what the diagnosis used."""

    made: list["Counting"] = []

    def __init__(self, evaluations: int) -> None:
        super().__init__(evaluations)
        Counting.made.append(self)


def unbounded(monkeypatch: pytest.MonkeyPatch, robot, Q, P) -> diagnosis.Diagnosis:
    with monkeypatch.context() as m:
        m.setattr(diagnosis, "WORK", 10 ** 15)
        m.setattr(diagnosis, "DIAGNOSIS_POSES", 10 ** 9)
        return diagnosis.diagnose(robot, Q, P)


def test_a_normal_diagnosis_is_the_unbounded_one(case, monkeypatch):
    """The defaults leave a campaign of 120 poses as it was without any bound, bit for bit."""
    _, _, robot, Q, P = case
    Counting.made.clear()
    monkeypatch.setattr(diagnosis, "Budget", Counting)
    d = diagnosis.diagnose(robot, Q, P)
    assert not d.same and not d.budget_reached and d.poses == d.poses_ranked == 120
    assert len(d.joints) == 6 and d.joints[0][0] == "joint3" and d.parameters   # the elbow, 4 mrad
    assert 0 < Counting.made[0].used < diagnosis.WORK / 4   # far from the budget (used ~3e5)
    assert d.to_dict() == unbounded(monkeypatch, robot, Q, P).to_dict()
    text = d.text()
    assert "work budget" not in text and "evenly spread" not in text


def test_the_budget_stops_the_fits_and_says_so(case, monkeypatch):
    """A budget a third of what the diagnosis needs: the joints fitted before it are listed with the
    shares of the unbounded diagnosis, the others are not, and the text and JSON say why."""
    _, _, robot, Q, P = case
    full = unbounded(monkeypatch, robot, Q, P)
    Counting.made.clear()
    monkeypatch.setattr(diagnosis, "Budget", Counting)
    monkeypatch.setattr(diagnosis, "WORK", 10 ** 15)
    diagnosis.diagnose(robot, Q, P)
    needed = Counting.made[0].used
    monkeypatch.setattr(diagnosis, "WORK", needed // 3)
    d = diagnosis.diagnose(robot, Q, P)
    assert d.budget_reached and 0 < len(d.joints) < 6 and not d.parameters
    shares = {name: (share, rms) for name, share, rms in full.joints}
    for name, share, rms in d.joints:   # the fits that ended are those of the unbounded run
        assert (share, rms) == shares[name]
    assert Counting.made[-1].used <= needed // 3   # the budget holds the fits and what calibrate does around them
    assert "reached their work budget" in d.text() and "not fitted" in d.text()
    assert d.to_dict()["budget_reached"] is True
    monkeypatch.setattr(diagnosis, "WORK", 1)   # nothing left for even one joint
    d = diagnosis.diagnose(robot, Q, P)
    assert d.budget_reached and d.joints == [] and "reached their work budget" in d.text()


def test_many_poses_rank_on_an_even_subset(case, monkeypatch):
    """More poses than DIAGNOSIS_POSES: the residual is over every pose, the ranking over an even subset
    (the first and last included), which finds the same joint and parameter at fault; the text says so."""
    _, _, robot, Q, P = case
    full = unbounded(monkeypatch, robot, Q, P)
    monkeypatch.setattr(diagnosis, "DIAGNOSIS_POSES", 40)
    d = diagnosis.diagnose(robot, Q, P)
    assert d.residuals == full.residuals   # the base fit saw every pose
    assert (d.poses, d.poses_ranked) == (120, 40) and not d.budget_reached
    assert d.joints[0][0] == full.joints[0][0] == "joint3"
    assert d.parameters[0][0] == full.parameters[0][0] == "joint joint3 zero offset"
    assert d.parameters[0][2] == pytest.approx(full.parameters[0][2], rel=0.1)   # 40 of 120 poses: 6 % off (observed)
    assert d.joints != full.joints   # another set of poses: other shares
    assert "(the shares are from 40 of the 120 poses, evenly spread)" in d.text()


def test_cli_json_carries_the_bounds(case, monkeypatch, capsys):
    model, meas, *_ = case
    monkeypatch.setattr(diagnosis, "DIAGNOSIS_POSES", 60)
    assert main(["check", str(model), str(meas), "--json"]) == 1
    d = json.loads(capsys.readouterr().out)
    assert (d["poses"], d["poses_ranked"], d["budget_reached"]) == (120, 60, False)
    assert d["joints"][0]["joint"] == "joint3"
    monkeypatch.setattr(diagnosis, "WORK", 1)
    assert main(["check", str(model), str(meas)]) == 1
    out = capsys.readouterr().out
    assert "reached their work budget (1 pose evaluations)" in out and "  joint" not in out
