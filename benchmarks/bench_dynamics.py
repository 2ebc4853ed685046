"""Rigid-body dynamics of robkin's compiled core against pinocchio, in the same run.

The Franka Panda (7 joints, tool ``panda_hand_tcp``; the hand and fingers merged into link 7 with the
finger joints held at 0) and the UR5 of example-robot-data are loaded by robkin (``robkin.load``) and by
pinocchio (``buildModelFromUrdf``, then ``buildReducedModel`` locking the joints off robkin's chain)
from the same file. Measured, each as the median of interleaved rounds (robkin and pinocchio alternate,
so both see the same machine load), one thread each, CPU time of this thread:

- inverse dynamics, one (q, qd, qdd): ``Robot.inverse_dynamics`` against ``pinocchio.rnea``;
- gravity, one q: ``Robot.gravity`` against ``computeGeneralizedGravity``;
- mass matrix, one q: ``Robot.mass_matrix`` (the full symmetric matrix) against ``crba`` (pinocchio
  fills the upper triangle only: robkin does a little more);
- batches of N = 1e3 and 1e4 of each (``threads=1``: one thread against one) against a Python loop of
  the pinocchio call (timed over 1000 configurations: its cost per call does not depend on N).
  ``benchmarks/bench_threads.py`` measures the same batches on several threads.

Goals (issue 23): gravity and inverse dynamics for one q no slower than pinocchio's ``rnea``, the mass
matrix no slower than ``crba``; batches >= 10x a pinocchio loop.

Run: ``python benchmarks/bench_dynamics.py [--quick]``. Exit status 0 whatever the result (a benchmark),
1 if robkin and pinocchio disagree.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")  # one thread each: before numpy is imported

import argparse  # noqa: E402
import sys  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402

import robkin  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_fk import interleaved, robots_dir  # noqa: E402  (CPU time of this thread, interleaved rounds)

ROBOTS = [("Panda", "panda_description/urdf/panda.urdf", "panda_hand_tcp"),
          ("UR5", "ur_description/urdf/ur5_robot.urdf", "tool0")]


def measure(label: str, path: str, tip: str, quick: bool) -> list[tuple[str, float, float]] | None:
    import pinocchio as pin

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = robkin.load(path, tip_link=tip)
    full = pin.buildModelFromUrdf(path)
    keep = {j.name for j in robot.joints}
    lock = [i for i in range(1, full.njoints) if full.names[i] not in keep]
    model = pin.buildReducedModel(full, lock, pin.neutral(full)) if lock else full
    data = model.createData()
    if model.nq != robot.n or [model.names[i] for i in range(1, model.njoints)] != [j.name for j in robot.joints]:
        print(f"{label}: pinocchio's reduced model is not robkin's chain; skipped")
        return None
    rng = np.random.default_rng(0)
    Q, QD, QDD = (robot.random_q(10_000, rng) for _ in range(3))
    # sanity: both compute the same things (1e-9 of the largest entry, the promise)
    for q, qd, qdd in zip(Q[:50], QD[:50], QDD[:50]):
        ref = pin.rnea(model, data, q, qd, qdd)
        M = pin.crba(model, data, q)
        M = np.triu(M) + np.triu(M, 1).T
        if (np.abs(robot.inverse_dynamics(q, qd, qdd) - ref).max() > 1e-9 * np.abs(ref).max()
                or np.abs(robot.mass_matrix(q) - M).max() > 1e-9 * np.abs(M).max()):
            print(f"{label}: robkin and pinocchio disagree")
            raise SystemExit(1)
    rounds = 5 if quick else 15
    reps = 2_000 if quick else 10_000
    q, qd, qdd = Q[0], QD[0], QDD[0]
    one = interleaved({
        "rk_id": (lambda: robot.inverse_dynamics(q, qd, qdd), reps),
        "pin_id": (lambda: pin.rnea(model, data, q, qd, qdd), reps),
        "rk_g": (lambda: robot.gravity(q), reps),
        "pin_g": (lambda: pin.computeGeneralizedGravity(model, data, q), reps),
        "rk_m": (lambda: robot.mass_matrix(q), reps),
        "pin_m": (lambda: pin.crba(model, data, q), reps),
    }, rounds)
    rows = [(f"{label} inverse dynamics, one", one["rk_id"], one["pin_id"]),
            (f"{label} gravity, one", one["rk_g"], one["pin_g"]),
            (f"{label} mass matrix, one", one["rk_m"], one["pin_m"])]
    n_pin = 1000   # the pinocchio loop's configurations (its time per call does not depend on N)
    P, PD, PDD = Q[:n_pin], QD[:n_pin], QDD[:n_pin]
    for N, tag in ((1_000, "1e3"), (10_000, "1e4")):
        A, AD, ADD = Q[:N], QD[:N], QDD[:N]
        reps_rk = max(1, 5_000 // N)
        batch = interleaved({
            "rk_id": (lambda: robot.inverse_dynamics(A, AD, ADD, threads=1), reps_rk),
            "pin_id": (lambda: [pin.rnea(model, data, a, b, c) for a, b, c in zip(P, PD, PDD)], 1),
            "rk_g": (lambda: robot.gravity(A, threads=1), reps_rk),
            "pin_g": (lambda: [pin.computeGeneralizedGravity(model, data, a) for a in P], 1),
            "rk_m": (lambda: robot.mass_matrix(A, threads=1), reps_rk),
            "pin_m": (lambda: [pin.crba(model, data, a) for a in P], 1),
        }, max(3, rounds // 3))
        rows += [(f"{label} inverse dynamics, N={tag}", batch["rk_id"] / N, batch["pin_id"] / n_pin),
                 (f"{label} gravity, N={tag}", batch["rk_g"] / N, batch["pin_g"] / n_pin),
                 (f"{label} mass matrix, N={tag}", batch["rk_m"] / N, batch["pin_m"] / n_pin)]
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer rounds")
    args = parser.parse_args(argv)
    import pinocchio as pin

    rows = []
    for label, rel, tip in ROBOTS:
        path = os.path.join(robots_dir(), rel)
        if not os.path.isfile(path):
            print(f"example-robot-data's {rel} is not installed: skipped")
            continue
        rows += measure(label, path, tip, args.quick) or []
    if not rows:
        return 0
    print(f"robkin {robkin.__version__} (compiled core), pinocchio {pin.__version__}; medians of interleaved "
          f"rounds, CPU time of one thread")
    print(f"{'case':<34}{'robkin us/cfg':>15}{'pinocchio us/cfg':>18}{'robkin/pin':>12}")
    for name, a, b in rows:
        print(f"{name:<34}{a * 1e6:>15.3f}{b * 1e6:>18.3f}{a / b:>11.2f}x")
    t = {name: (a, b) for name, a, b in rows}
    labels = sorted({name.split(" ")[0] for name in t})
    # the goals: gravity and inverse dynamics for one q no slower than pinocchio's rnea (the
    # gravity row's own peer, computeGeneralizedGravity, is shown beside it), the mass matrix no slower
    # than crba; every batch >= 10x a loop of the same pinocchio call
    one = all(t[f"{r} inverse dynamics, one"][0] <= t[f"{r} inverse dynamics, one"][1]
              and t[f"{r} gravity, one"][0] <= t[f"{r} inverse dynamics, one"][1] for r in labels)
    print(f"goal inverse dynamics and gravity, one q, no slower than rnea: {'met' if one else 'MISSED'}")
    crba = all(t[f"{r} mass matrix, one"][0] <= t[f"{r} mass matrix, one"][1] for r in labels)
    print(f"goal mass matrix, one q, no slower than crba: {'met' if crba else 'MISSED'}")
    for kind in ("inverse dynamics", "gravity", "mass matrix"):
        ok = all(t[f"{r} {kind}, N={tag}"][0] <= 0.1 * t[f"{r} {kind}, N={tag}"][1]
                 for r in labels for tag in ("1e3", "1e4"))
        print(f"goal {kind} batch (one thread) >= 10x a pinocchio loop: {'met' if ok else 'MISSED'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
