"""Calibration time with joint compliance (issue 34): UR5 (6 joints) and xArm7 (7 joints), 60 poses with a
10 kg payload at every other one, stiffnesses 1e4-1e5 N m/rad in the truth, 10 um noise.

Prints per arm: the time of ``calibrate`` without and with ``compliance=True``, the hold-out error of
each (200 fresh configurations with the payload) and the share of the payload-induced error removed.

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


if __name__ == "__main__":
    main()
