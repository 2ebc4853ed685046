"""Numeric inverse kinematics of robkin's compiled core against the Robotics Toolbox's C++ ``ik_LM``.

Two 7-joint arms with joint limits: the Franka Panda of example-robot-data (tool ``panda_hand_tcp``)
and a KUKA LBR iiwa 14 (URDF written here from the published kinematics). For each, 1000 targets are
the FK of random joint values within the limits. Solvers, each with joint limits on:

- robkin, one call per target: ``Robot.ik(T, method="numeric")`` (default tolerances 1e-9 m / rad,
  up to 200 restarts);
- robkin, batch: ``Robot.ik(targets, method="numeric")`` for all targets at once (time per target);
- Robotics Toolbox (``roboticstoolbox-python``): ``ik_LM`` (C++, Chan's method) per target, tol
  5e-19 on E = e.e / 2 (|e| <= 1e-9), ``joint_limits=True``, 100 searches.

Success is judged by an independent forward kinematics (pinocchio, from the same URDF file): position
and orientation within 1e-6 (m, rad) of the target and every joint within its limits (after whole turns
of revolute joints, which change no pose). Per-target solvers are timed call by call, alternating
robkin and the Toolbox target by target (both see the same load); reported: median and mean. One
thread each.

Goals (issue 10): robkin's single-target median no slower than ``ik_LM`` with success >= 99.9 %; the
batch at least 2x faster per target than ``ik_LM``.

Run: ``python benchmarks/bench_ik.py [--targets 1000]``. Exit status 0 whatever the result.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")  # one thread each: before numpy is imported

import argparse  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
import xml.etree.ElementTree as ET  # noqa: E402,S405 - our own files, not untrusted input

import numpy as np  # noqa: E402

import robkin  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_fk import PANDA, robots_dir  # noqa: E402

JUDGE_TOL = 1e-6

#: KUKA LBR iiwa 14 R820: joint origins (xyz, rpy) and limits (rad), every axis the local z
IIWA = [((0, 0, 0.1575), (0, 0, 0), 2.9668), ((0, 0, 0.2025), (np.pi / 2, 0, np.pi), 2.0944),
        ((0, 0.2045, 0), (np.pi / 2, 0, np.pi), 2.9668), ((0, 0, 0.2155), (np.pi / 2, 0, 0), 2.0944),
        ((0, 0.1845, 0), (-np.pi / 2, np.pi, 0), 2.9668), ((0, 0, 0.2155), (np.pi / 2, 0, 0), 2.0944),
        ((0, 0.081, 0), (-np.pi / 2, np.pi, 0), 3.0543)]
IIWA_TOOL = (0, 0, 0.045)


def iiwa_urdf(folder: str) -> str:
    """Write the iiwa as URDF into folder; returns its path (tool link 'tool')."""
    f = lambda v: " ".join(repr(float(x)) for x in v)  # noqa: E731
    parts = ['<robot name="iiwa14">', '<link name="base"/>']
    parent = "base"
    for i, (xyz, rpy, lim) in enumerate(IIWA, start=1):
        parts += [f'<link name="link{i}"/>',
                  f'<joint name="a{i}" type="revolute"><parent link="{parent}"/><child link="link{i}"/>'
                  f'<origin xyz="{f(xyz)}" rpy="{f(rpy)}"/><axis xyz="0 0 1"/>'
                  f'<limit lower="{-lim}" upper="{lim}" effort="100" velocity="1"/></joint>']
        parent = f"link{i}"
    parts += ['<link name="tool"/>', f'<joint name="tool_joint" type="fixed"><parent link="{parent}"/>'
              f'<child link="tool"/><origin xyz="{f(IIWA_TOOL)}" rpy="0 0 0"/></joint>', '</robot>']
    path = os.path.join(folder, "iiwa14.urdf")
    with open(path, "w") as fh:
        fh.write("".join(parts))
    return path


def stripped_urdf(path: str, folder: str) -> str:
    """A copy without visual/collision elements (the Toolbox cannot resolve package:// meshes)."""
    tree = ET.parse(path)  # noqa: S314
    for link in tree.getroot().iter("link"):
        for tag in ("visual", "collision"):
            for el in link.findall(tag):
                link.remove(el)
    out = os.path.join(folder, "stripped_" + os.path.basename(path))
    tree.write(out)
    return out


class Judge:
    """Independent check of answers with pinocchio's FK from the same URDF."""

    def __init__(self, path: str, tip: str, robot: robkin.Robot) -> None:
        import pinocchio as pin

        self.pin = pin
        self.model = pin.buildModelFromUrdf(path)
        self.data = self.model.createData()
        self.fid = self.model.getFrameId(tip)
        self.robot = robot

    def __call__(self, Q: np.ndarray, targets: np.ndarray) -> np.ndarray:
        from robkin.kinematics.limits import wrap_into_limits

        pin, n = self.pin, self.robot.n
        finite = np.isfinite(Q).all(axis=1)
        Qw, within = wrap_into_limits(np.where(finite[:, None], Q, 0.0), self.robot.limits, self.robot.revolute)
        ok = finite & within
        for k in np.flatnonzero(ok):
            q = np.zeros(self.model.nq)
            q[:n] = Qw[k]
            pin.framesForwardKinematics(self.model, self.data, q)
            M = self.data.oMf[self.fid]
            ep = np.linalg.norm(M.translation - targets[k, :3, 3])
            eo = np.linalg.norm(pin.log3(targets[k, :3, :3].T @ M.rotation))
            ok[k] = ep <= JUDGE_TOL and eo <= JUDGE_TOL
        return ok


def run(name: str, path: str, tip: str, n_targets: int, folder: str) -> list[str]:
    import roboticstoolbox as rtb

    robot = robkin.load(path, tip_link=tip)
    judge = Judge(path, tip, robot)
    targets = robot.fk(robot.random_q(n_targets, rng=np.random.default_rng(2024)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = rtb.Robot.URDF(stripped_urdf(path, folder))
    robot.ik(targets[0], method="numeric")          # first call: imports the compiled modules

    Q_rk = np.full((n_targets, robot.n), np.nan)
    Q_tb = np.full((n_targets, robot.n), np.nan)
    t_rk, t_tb = np.empty(n_targets), np.empty(n_targets)
    for k, T in enumerate(targets):                  # interleaved, target by target
        t0 = time.perf_counter()
        res = robot.ik(T, method="numeric")
        t_rk[k] = time.perf_counter() - t0
        Q_rk[k] = res.q
        t0 = time.perf_counter()
        sol = model.ik_LM(T, end=tip, tol=5e-19, joint_limits=True, slimit=100)
        t_tb[k] = time.perf_counter() - t0
        if sol.success:
            Q_tb[k] = sol.q[:robot.n]
    batch = []
    for _ in range(3):
        t0 = time.perf_counter()
        res = robot.ik(targets, method="numeric")
        batch.append((time.perf_counter() - t0) / n_targets)
    t_batch = float(np.median(batch))

    ok_rk, ok_tb, ok_batch = judge(Q_rk, targets).mean(), judge(Q_tb, targets).mean(), judge(res.q, targets).mean()
    med_rk, med_tb = float(np.median(t_rk)), float(np.median(t_tb))
    print(f"\n{name} ({robot.n} joints, limits), {n_targets} targets; success by pinocchio FK at {JUDGE_TOL:g}")
    print(f"  {'solver':34s}{'success':>9s}{'median us':>11s}{'mean us':>10s}{'vs ik_LM median':>17s}")
    for solver, ok, med, mean in (("robkin Robot.ik, one target", ok_rk, med_rk, t_rk.mean()),
                                  ("robkin Robot.ik, batch (per target)", ok_batch, t_batch, t_batch),
                                  ("Toolbox ik_LM (C++), one target", ok_tb, med_tb, t_tb.mean())):
        print(f"  {solver:34s}{100 * ok:8.2f}%{med * 1e6:11.1f}{mean * 1e6:10.1f}{med / med_tb:16.2f}x")
    return [f"{name}: single-target median {med_rk * 1e6:.1f} us vs ik_LM {med_tb * 1e6:.1f} us, success "
            f"{100 * ok_rk:.2f}%: {'met' if med_rk <= med_tb and ok_rk >= 0.999 else 'MISSED'}",
            f"{name}: batch {t_batch * 1e6:.1f} us/target, {med_tb / t_batch:.1f}x faster than ik_LM's median, "
            f"success {100 * ok_batch:.2f}%: {'met' if 2 * t_batch <= med_tb and ok_batch >= 0.999 else 'MISSED'}"]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--targets", type=int, default=1000, help="targets per arm (default 1000)")
    args = ap.parse_args(argv)
    try:
        import pinocchio  # noqa: F401
        import roboticstoolbox  # noqa: F401
    except ImportError as e:
        print(f"{e.name} is not installed (pip install 'robkin[test,bench]'): nothing to compare")
        return 0
    lines = []
    with tempfile.TemporaryDirectory() as folder:
        panda = os.path.join(robots_dir(), PANDA[0])
        if os.path.isfile(panda):
            lines += run("Panda", panda, PANDA[1], args.targets, folder)
        else:
            print(f"example-robot-data's {PANDA[0]} is not installed: Panda skipped")
        lines += run("KUKA iiwa 14", iiwa_urdf(folder), "tool", args.targets, folder)
    print()
    for line in lines:
        print("goal " + line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
