"""Batch inverse kinematics against peers on the same targets, in the same run.

Solvers, each given the same targets (FK of random joint values within limits) and judged by the same
check (robkin FK of the answer within 1e-9 m and 1e-9 rad of the target, every joint within limits):

Times are CPU seconds of this process per target (the machines are shared; see ``_clock``).

- robkin: ``Robot.ik`` on the whole batch (vectorised Levenberg-Marquardt, or the closed form where
  one fits), default tolerances 1e-9 m / 1e-9 rad, 20 random restarts;
- robkin, one call per target (the same solver without the batch);
- pinocchio: the damped-least-squares loop of pinocchio's own IK example (step 0.1, damping 1e-12,
  log6 error with Jlog6), run per target in Python to 1e-9, with random restarts (up to 20) when it
  fails or leaves the limits; and the same loop with full steps (step 1.0), which converges faster;
- Robotics Toolbox (``roboticstoolbox-python``, where it installs): its compiled ``ik_LM`` (Chan's
  method), per target, tol 5e-19 on E = e.e/2 (|e| <= 1e-9), joint limits on, 100 searches.

Goal (issue 4): robkin batch IK amortised well under 100 us per target on a 6-7 joint arm with at
least 99 % success, faster than the Toolbox's compiled ik_LM. Absolute times depend on the machine
(and its load); the ratios in one run much less.

Run: ``.venv/bin/python benchmarks/bench_ik.py [--targets 1000] [--peer-targets 300]``. Exit status 0
whatever the result (a benchmark, not a test); the last lines say whether the goal is met.
"""

from __future__ import annotations

import argparse
import glob
import os
import sys
import tempfile
import time
import warnings
import xml.etree.ElementTree as ET  # noqa: S405 - our own files from example-robot-data, not untrusted input

import numpy as np

import robkin
from robkin.kinematics.pose_error import residual

GOAL_US = 100.0
TOL = 1e-9


def _clock() -> float:
    """CPU time of this process: the machines this runs on are shared, and CPU time is what a solver
    costs whatever else runs (wall time under load mostly measures the neighbours)."""
    return time.process_time()

ROBOTS_DIR = (glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                     "example-robot-data", "robots")) or [""])[0]
ARMS = {  # name: (file, tip link)
    "UR5": ("ur_description/urdf/ur5_robot.urdf", "tool0"),
    "Panda": ("panda_description/urdf/panda.urdf", "panda_hand_tcp"),
    "Kinova Jaco2 6s": ("kinova_description/robots/kinova.urdf", "j2s6s200_end_effector"),
}


def check(robot: robkin.Robot, Q: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """(N,) bool: Q reaches the targets within TOL (m, rad) and lies within the joint limits (after
    whole turns of revolute joints, which change no pose, are taken into the limits: fair to every
    solver)."""
    from robkin.kinematics.limits import wrap_into_limits

    ok = np.isfinite(Q).all(axis=1)
    Qs, within = wrap_into_limits(np.where(ok[:, None], Q, 0.0), robot.limits, robot.revolute)
    e = residual(robot.fk(Qs), targets)
    return ok & within & (np.linalg.norm(e[:, :3], axis=1) <= TOL) & (np.linalg.norm(e[:, 3:], axis=1) <= TOL)


# ----------------------------------------------------------------------------------------- robkin
def run_robkin_batch(robot, targets, method="auto"):
    t0 = _clock()
    res = robot.ik(targets, method=method)
    dt = _clock() - t0
    return res.q, dt, float(np.mean(res.iterations)), res.method


def run_robkin_single(robot, targets):
    Q = np.empty((len(targets), robot.n))
    t0 = _clock()
    for i, T in enumerate(targets):
        Q[i] = robot.ik(T).q
    return Q, _clock() - t0


# -------------------------------------------------------------------------------------- pinocchio
def run_pinocchio(path, tip, robot, targets, step, rng, restarts=20, max_it=1000):
    """pinocchio's IK example (damped least squares on log6 with Jlog6), per target, with restarts."""
    import pinocchio as pin

    model = pin.buildModelFromUrdf(path)
    data = model.createData()
    fid = model.getFrameId(tip)
    idx_q = [model.joints[model.getJointId(j.name)].idx_q for j in robot.joints]
    cont = [model.joints[model.getJointId(j.name)].nq == 2 for j in robot.joints]
    lim = robot.limits
    span = np.where(np.isfinite(lim), lim, np.array([-np.pi, np.pi]))
    damp = 1e-12
    Q = np.full((len(targets), robot.n), np.nan)
    iters = 0

    def to_pin(q):
        qp = pin.neutral(model)
        for k, (i, c) in enumerate(zip(idx_q, cont)):
            if c:
                qp[i], qp[i + 1] = np.cos(q[k]), np.sin(q[k])
            else:
                qp[i] = q[k]
        return qp

    def from_pin(qp):
        return np.array([np.arctan2(qp[i + 1], qp[i]) if c else qp[i] for i, c in zip(idx_q, cont)])

    t0 = _clock()
    for n, T in enumerate(targets):
        oMdes = pin.SE3(T[:3, :3], T[:3, 3])
        q = to_pin(np.clip(np.zeros(robot.n), lim[:, 0], lim[:, 1]))
        for attempt in range(restarts + 1):
            if attempt:
                q = to_pin(rng.uniform(span[:, 0], span[:, 1]))
            for _ in range(max_it):
                pin.framesForwardKinematics(model, data, q)
                iMd = data.oMf[fid].actInv(oMdes)
                err = pin.log(iMd).vector
                iters += 1
                if np.linalg.norm(err) < 0.5 * TOL:
                    break
                J = pin.computeFrameJacobian(model, data, q, fid)
                J = -np.dot(pin.Jlog6(iMd.inverse()), J)
                v = -J.T.dot(np.linalg.solve(J.dot(J.T) + damp * np.eye(6), err))
                q = pin.integrate(model, q, v * step)
            qa = from_pin(q)
            if np.linalg.norm(err) < 0.5 * TOL and np.all((qa >= lim[:, 0]) & (qa <= lim[:, 1])):
                Q[n] = qa
                break
    return Q, _clock() - t0, iters / len(targets)


# ----------------------------------------------------------------------------------- Robotics Toolbox
def stripped_urdf(path: str) -> str:
    """A copy without visual/collision elements (the Toolbox cannot resolve their package:// meshes)."""
    tree = ET.parse(path)  # noqa: S314
    for link in tree.getroot().iter("link"):
        for tag in ("visual", "collision"):
            for el in link.findall(tag):
                link.remove(el)
    fd, out = tempfile.mkstemp(suffix=".urdf")
    os.close(fd)
    tree.write(out)
    return out


def run_rtb(path, tip, robot, targets):
    import roboticstoolbox as rtb

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = rtb.Robot.URDF(stripped_urdf(path))
    Q = np.full((len(targets), robot.n), np.nan)
    iters = 0
    t0 = _clock()
    for i, T in enumerate(targets):
        sol = model.ik_LM(T, end=tip, tol=0.5 * TOL ** 2, joint_limits=True, slimit=100)
        iters += sol.iterations
        if sol.success:
            Q[i] = sol.q[: robot.n]
    dt = _clock() - t0
    return Q, dt, iters / len(targets)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--targets", type=int, default=2000, help="targets per arm for robkin's batch solver")
    ap.add_argument("--peer-targets", type=int, default=300,
                    help="targets per arm for the per-target solvers (a subset of the same targets)")
    args = ap.parse_args()
    try:
        import roboticstoolbox  # noqa: F401

        have_rtb = True
    except ImportError:
        have_rtb = False
        print("roboticstoolbox-python is not installed (pip install 'robkin[bench]'): Toolbox rows skipped")

    rows = []
    goal_lines = []
    for name, (rel, tip) in ARMS.items():
        path = os.path.join(ROBOTS_DIR, rel)
        if not os.path.isfile(path):
            print(f"{name}: {rel} not installed, skipped")
            continue
        robot = robkin.load(path, tip_link=tip)
        rng = np.random.default_rng(2024)
        targets = robot.fk(robot.random_q(args.targets, rng=rng))
        sub = targets[: args.peer_targets]
        results = {}

        Q, dt, it, method = run_robkin_batch(robot, targets)
        results[f"robkin batch ({method})"] = (check(robot, Q, targets).mean(), dt / len(targets), it)
        if method != "numeric":
            Q, dt, it, _ = run_robkin_batch(robot, targets, method="numeric")
            results["robkin batch (numeric)"] = (check(robot, Q, targets).mean(), dt / len(targets), it)
        Q, dt = run_robkin_single(robot, sub)
        results["robkin, one call per target"] = (check(robot, Q, sub).mean(), dt / len(sub), float("nan"))
        for step in (0.1, 1.0):
            Q, dt, it = run_pinocchio(path, tip, robot, sub, step, np.random.default_rng(1))
            results[f"pinocchio DLS example, step {step}"] = (check(robot, Q, sub).mean(), dt / len(sub), it)
        if have_rtb:
            Q, dt, it = run_rtb(path, tip, robot, sub)
            results["Toolbox ik_LM (C++)"] = (check(robot, Q, sub).mean(), dt / len(sub), it)

        rtb_t = results.get("Toolbox ik_LM (C++)", (None, None))[1]
        print(f"\n{name} ({robot.n} joints), {len(targets)} targets (per-target solvers: first {len(sub)})")
        print(f"  {'solver':36s} {'success':>8s} {'us/target':>10s} {'iter/target':>12s} {'vs Toolbox':>11s}")
        for solver, (succ, t, it) in results.items():
            ratio = f"{t / rtb_t:.2f}x" if rtb_t else "-"
            print(f"  {solver:36s} {100 * succ:7.2f}% {t * 1e6:10.1f} {it:12.1f} {ratio:>11s}")
            rows.append((name, solver, succ, t))
        numeric = results.get("robkin batch (numeric)") or results[next(iter(results))]
        succ, t, _ = numeric
        met = succ >= 0.99 and t * 1e6 < GOAL_US and (rtb_t is None or t < rtb_t)
        goal_lines.append(f"{name}: robkin numeric batch {t * 1e6:.1f} us/target, {100 * succ:.2f}% success"
                          f"{'' if rtb_t is None else f', {rtb_t / t:.1f}x faster than Toolbox ik_LM'}"
                          f": {'goal met' if met else 'GOAL MISSED'}")
    print()
    for line in goal_lines:
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
