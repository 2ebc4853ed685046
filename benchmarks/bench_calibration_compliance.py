"""Calibration time with joint compliance (issue 34): UR5 (6 joints) and xArm7 (7 joints), 60 poses with a
10 kg payload at every other one, stiffnesses 1e4-1e5 N m/rad in the truth, 10 um noise.

Prints per arm: the time of ``calibrate`` without and with ``compliance=True``, the hold-out error of
each (200 fresh configurations with the payload) and the share of the payload-induced error removed.
Then, per experiment (payload at the marker or its centre of mass 0.2 m off the last axis; positions or
positions + orientations; 60 or 120 poses), the worst stiffness error over 5 seeds on UR5, xArm7 and
Panda (the table in docs/calibration.md, "To identify every joint's stiffness").

    PYTHONPATH=src python benchmarks/bench_calibration_compliance.py
"""

from __future__ import annotations

import os
import time

import numpy as np

import robkin
from robkin.calibration import calibrate, simulate
from robkin.calibration.simulation import random_configurations

ROBOTS = os.path.join(os.path.dirname(np.__file__), "..", "cmeel.prefix", "share", "example-robot-data", "robots")
ARMS = {"UR5": ("ur_description/urdf/ur5_robot.urdf", "tool0"), "xArm7": ("xarm_description/urdf/xarm7.urdf", None)}
PANDA = ("panda_description/urdf/panda.urdf", "panda_link8")
EXPERIMENTS = [("payload at the marker, positions, 60 poses", None, False, 60),
               ("payload at the marker, positions + orientations, 120 poses", None, True, 120),
               ("payload 0.2 m off the axis, positions, 120 poses", (0.2, 0.0, 0.1), False, 120),
               ("payload 0.2 m off the axis, positions + orientations, 60 poses", (0.2, 0.0, 0.1), True, 60),
               ("payload 0.2 m off the axis, positions + orientations, 120 poses", (0.2, 0.0, 0.1), True, 120)]


def rms(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.sum((a - b) ** 2, axis=1))))


def main() -> None:
    print("| arm | rigid fit | with compliance | hold-out rigid | hold-out compliance | noise floor | removed |")
    print("|---|---|---|---|---|---|---|")
    for name, (rel, tip) in ARMS.items():
        robot = robkin.load(os.path.join(ROBOTS, rel), tip_link=tip)
        k = np.exp(np.random.default_rng(0).uniform(np.log(1e4), np.log(1e5), robot.n))
        pay = np.where(np.arange(60) % 2 == 0, 10.0, 0.0)
        sim = simulate(robot, 60, seed=0, stiffness=k, payload=pay, noise=10e-6)
        rigid = simulate(robot, 60, seed=0, noise=10e-6)
        qh = random_configurations(robot, 200, np.random.default_rng(1))
        held = (sim.truth.world @ sim.truth.fk_compliant(qh, 10.0))[:, :3, 3]
        t = time.perf_counter()
        for _ in range(5):
            plain = calibrate(robot, sim.q, sim.positions).robot
        t_plain = (time.perf_counter() - t) / 5
        t = time.perf_counter()
        for _ in range(5):
            comp = calibrate(robot, sim.q, sim.positions, compliance=True, payload=sim.payloads).robot
        t_comp = (time.perf_counter() - t) / 5
        floor = calibrate(robot, rigid.q, rigid.positions).robot
        e_plain = rms((plain.world @ plain.fk(qh))[:, :3, 3], held)
        e_comp = rms((comp.world @ comp.fk_compliant(qh, 10.0))[:, :3, 3], held)
        e_floor = rms((floor.world @ floor.fk(qh))[:, :3, 3], (rigid.truth.world @ rigid.truth.fk(qh))[:, :3, 3])
        print(f"| {name} | {t_plain:.3f} s | {t_comp:.3f} s | {e_plain * 1e6:.1f} um | {e_comp * 1e6:.1f} um | "
              f"{e_floor * 1e6:.1f} um | {100 * (e_plain - e_comp) / (e_plain - e_floor):.1f} % |")


def stiffness_errors(robot: robkin.Robot, seed: int, com: tuple | None, orient: bool,
                     poses: int) -> tuple[np.ndarray, int]:
    """|identified / true - 1| per joint after the first (nan: not determined) and the count not determined."""
    from robkin import se3
    from robkin.calibration.simulation import _rotations

    k = np.exp(np.random.default_rng(seed).uniform(np.log(1e4), np.log(1e5), robot.n))
    pay = np.where(np.arange(poses) % 2 == 0, 10.0, 0.0)
    sim = simulate(robot, poses, seed=seed, stiffness=k, payload=pay, noise=10e-6)
    pos, rot = sim.positions, sim.orientations
    if com is not None:   # the centre of mass in the flange frame; the truth's tool is the marker
        T = sim.truth.world @ sim.truth.fk_compliant(sim.q, pay, (se3.inv(sim.marker) @ np.r_[com, 1.0])[:3])
        rng = np.random.default_rng(seed + 1000)
        pos = T[:, :3, 3] + rng.normal(0.0, 10e-6, (poses, 3))
        rot = T[:, :3, :3] @ _rotations(rng.normal(0.0, np.radians(0.005), (poses, 3)))
    res = calibrate(robot, sim.q, pos, rot if orient else None, compliance=True, payload=pay, payload_com=com)
    found = np.array([res.stiffness[j.name]["stiffness"] or np.nan for j in robot.joints[1:]], dtype=float)
    return np.abs(found / k[1:] - 1), int(np.isnan(found).sum())


def stiffness_table() -> None:
    arms = [robkin.load(os.path.join(ROBOTS, rel), tip_link=tip) for rel, tip in [*ARMS.values(), PANDA]]
    print("\n| experiment | shoulder, elbow | other wrist joints | last joint | runs with a joint not determined |")
    print("|---|---|---|---|---|")
    for label, com, orient, poses in EXPERIMENTS:
        worst, runs, missing = np.zeros(3), 0, 0
        for robot in arms:
            for seed in range(1, 6):
                err, nd = stiffness_errors(robot, seed, com, orient, poses)
                groups = (err[:2], err[2:-1], err[-1:])
                worst = np.maximum(worst, [np.nanmax(g, initial=0.0) for g in groups])
                runs, missing = runs + 1, missing + (nd > 0)
        print(f"| {label} | {100 * worst[0]:.1f} % | {100 * worst[1]:.1f} % | {100 * worst[2]:.1f} % | "
              f"{missing} of {runs} |")


if __name__ == "__main__":
    main()
    stiffness_table()
