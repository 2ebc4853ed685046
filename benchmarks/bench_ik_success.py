"""Numeric IK success at the default settings on hard targets, against the Robotics Toolbox's ``ik_LM``.

Ten random arms (alternately 6R and 7R; standard DH rows with link lengths and offsets up to 0.5, twists
near 0 and +-pi/2, joint limits +-1.5..3 rad; seeded), 1000 targets each, of which

- 10 % near a joint limit: two joints within 1e-3 rad of one of their limits;
- 10 % near a singularity: the lowest-manipulability tenth of many random configurations;
- 80 % FK of uniform random joint values within the limits.

Solvers, one target at a time, one thread each, joint limits on, timed in two passes over the targets,
each of two solvers interleaved target by target in alternating order (robkin and ik_LM; then robkin's
old default, 50 restarts, and robkin again for the median comparison):
``Robot.ik(T, method="numeric")`` at its defaults, and the Toolbox's C++ ``ik_LM`` (tolerance
|e| <= 1e-9 as robkin's, 100 searches, joint limits) on a ``DHRobot`` of the same rows. Success is
judged by the Toolbox's own ``fkine`` (an implementation independent of robkin's): position and
orientation within 1e-6 of the target and every joint within its limits.

Goal (issue 24): >= 99.9 % success at the default settings, median time no worse than before (the
previous default, 50 restarts, is run beside for that).

Run: ``python benchmarks/bench_ik_success.py [--robots 10] [--targets 1000]``. Exit status 0 whatever
the result.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")  # one thread each: before numpy is imported

import argparse  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402

import robkin  # noqa: E402
from robkin import Joint  # noqa: E402

JUDGE_TOL = 1e-6


def random_arm(n: int, rng: np.random.Generator) -> tuple[robkin.Robot, np.ndarray, np.ndarray]:
    """A robot from random DH rows (a, d, alpha, theta) with symmetric limits; rows and limits too."""
    rows = np.column_stack([rng.uniform(-0.5, 0.5, n), rng.uniform(-0.5, 0.5, n),
                            rng.choice([-np.pi / 2, np.pi / 2, 0.0], n) + rng.normal(0, 0.2, n),
                            rng.uniform(-np.pi, np.pi, n)])
    lim = rng.uniform(1.5, 3.0, n)
    joints = tuple(Joint(f"j{i + 1}", "revolute", -lim[i], lim[i]) for i in range(n))
    return robkin.robot_from_dh(robkin.DHTable(rows, joints)), rows, lim


def hard_targets(robot: robkin.Robot, count: int, rng: np.random.Generator) -> np.ndarray:
    """Joint values: the first tenth near limits, the second near singularities, the rest uniform."""
    Q = robot.random_q(count, rng)
    k = count // 10
    lo, hi = robot.limits[:, 0], robot.limits[:, 1]
    for i in range(k):
        for j in rng.choice(robot.n, 2, replace=False):
            Q[i, j] = lo[j] + 1e-3 * rng.uniform() if rng.uniform() < 0.5 else hi[j] - 1e-3 * rng.uniform()
    candidates = robot.random_q(20 * k, rng)
    Q[k:2 * k] = candidates[np.argsort(robot.manipulability(candidates, "full"))[:k]]
    return Q


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", type=int, default=10)
    parser.add_argument("--targets", type=int, default=1000)
    args = parser.parse_args(argv)
    try:
        import roboticstoolbox as rtb
    except ImportError:
        print("roboticstoolbox-python is not installed (pip install '.[bench]'): nothing to compare with")
        return 0
    rng = np.random.default_rng(2026)
    totals = {"robkin": [], "robkin, 50 restarts": [], "ik_LM": []}
    speed_vs_old: list[tuple[float, float]] = []   # (median at 200 restarts, at 50) per arm, same pass
    print(f"{args.robots} random arms x {args.targets} targets (10 % near limits, 10 % near singularities); "
          f"success by the Toolbox's fkine at {JUDGE_TOL:g}; one thread; times in us per target")
    print("(robkin's median and mean are timed beside ik_LM; '50 rst' beside robkin's default, whose median in\n"
          " that pass is '200 med')")
    print(f"{'arm':<10}{'robkin %':>10}{'median':>9}{'mean':>9}{'50 rst %':>10}{'median':>9}{'200 med':>9}"
          f"{'ik_LM %':>10}{'median':>9}{'mean':>9}")
    for r in range(args.robots):
        n = 6 if r % 2 == 0 else 7
        robot, rows, lim = random_arm(n, rng)
        model = rtb.DHRobot([rtb.RevoluteDH(a=a, d=d, alpha=al, offset=th, qlim=[-l, l])
                             for (a, d, al, th), l in zip(rows, lim)])
        Q = hard_targets(robot, args.targets, rng)
        targets = robot.fk(Q)
        robot.ik(targets[0], method="numeric")          # first call: imports the compiled modules
        out = {k: (np.full((args.targets, n), np.nan), np.empty(args.targets)) for k in totals}
        at_200 = np.empty(args.targets)          # robkin at its default, timed beside the old default

        def solve(name: str, T: np.ndarray) -> tuple[np.ndarray | None, float]:
            t0 = time.perf_counter()
            if name == "ik_LM":
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    sol = model.ik_LM(T, tol=5e-19, joint_limits=True, slimit=100)
                q = sol.q if sol.success else None
            else:
                res = robot.ik(T, method="numeric", restarts=50 if "50" in name else 200)
                q = res.q if res.success else None
            return q, time.perf_counter() - t0

        # Two passes, each of two solvers in alternating order, so that each follows the other as often
        # as itself: a solver that runs right after ik_LM finds colder caches (a rotation over three
        # solvers put robkin after ik_LM twice as often as the 50-restart run: 1.5x its median).
        for pair in (("robkin", "ik_LM"), ("robkin, 50 restarts", "robkin")):
            for k, T in enumerate(targets):
                for name in (pair if k % 2 == 0 else pair[::-1]):
                    q, dt = solve(name, T)
                    if pair[0] != "robkin" and name == "robkin":
                        at_200[k] = dt               # the second pass: timing only
                        continue
                    out[name][1][k] = dt
                    if q is not None:
                        out[name][0][k] = q
        speed_vs_old.append((np.median(at_200), np.median(out["robkin, 50 restarts"][1])))
        line = f"{f'{n}R #{r + 1}':<10}"
        for name in totals:
            q, t = out[name]
            ok = np.zeros(args.targets, bool)
            for k in range(args.targets):
                if np.all(np.isfinite(q[k])) and np.all(np.abs(q[k]) <= lim + 1e-9):
                    T = model.fkine(q[k]).A
                    ok[k] = (np.abs(T[:3, 3] - targets[k][:3, 3]).max() <= JUDGE_TOL
                             and np.abs(T[:3, :3] - targets[k][:3, :3]).max() <= JUDGE_TOL)
            totals[name].append((ok.mean(), np.median(t), t.mean()))
            line += f"{100 * ok.mean():>10.2f}{np.median(t) * 1e6:>9.1f}"
            if name != "robkin, 50 restarts":
                line += f"{t.mean() * 1e6:>9.1f}"
            else:
                line += f"{speed_vs_old[-1][0] * 1e6:>9.1f}"
        print(line)
    for name, rows_ in totals.items():
        ok, med, mean = (np.mean([x[i] for x in rows_]) for i in range(3))
        print(f"{name:<22} success {100 * ok:.2f} %, median {med * 1e6:.1f} us, mean {mean * 1e6:.1f} us")
    ok = np.mean([x[0] for x in totals["robkin"]])
    med_new = np.mean([x[0] for x in speed_vs_old])
    med_old = np.mean([x[1] for x in speed_vs_old])
    print(f"goal >= 99.9 % at the defaults: {'met' if ok >= 0.999 else 'MISSED'}; median time vs the old "
          f"default: {med_new / med_old:.2f}x")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
