"""Forward kinematics and Jacobians of robkin's compiled core against pinocchio, in the same run.

The Franka Panda of example-robot-data (7 joints, tool ``panda_hand_tcp``) is loaded by robkin
(``robkin.load``) and by pinocchio (``buildModelFromUrdf``) from the same file. Measured, each as the
median of interleaved rounds (robkin and pinocchio alternate, so both see the same machine load), one
thread each:

- single FK: ``Robot.fk(q)`` against ``forwardKinematics`` + ``updateFramePlacement`` +
  ``oMf[tool].homogeneous`` (the 4x4 pose, as robkin returns it);
- batch of one: ``Robot.fk(Q)`` for Q of shape (1, 7), against robkin's single call;
- batch FK: ``Robot.fk(Q)`` for N = 1e3, 1e4, 1e5 against a Python loop of the pinocchio calls above;
- Jacobian: ``jacobian_geometric`` ([v; w] at the tool, base frame) for one q and for N = 1e3,
  against ``computeFrameJacobian(..., LOCAL_WORLD_ALIGNED)`` (the same matrix) and a loop of it.

Times are this thread's CPU time (``time.thread_time``), so other processes on a shared machine do not
inflate them; on a quiet machine they equal wall time.

Goals (issue 10): single FK and one-q Jacobian within 2x of pinocchio; batch FK and batch Jacobian at
least 10x faster per configuration than pinocchio's loop at N >= 1e3; a batch of one at most 2x a
single call.

Run: ``python benchmarks/bench_fk.py [--quick]``. Exit status 0 whatever the result (a benchmark).
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")  # one thread each: before numpy is imported

import argparse  # noqa: E402
import glob  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import robkin  # noqa: E402
from robkin.kinematics.jacobian import jacobian_geometric  # noqa: E402

PANDA = ("panda_description/urdf/panda.urdf", "panda_hand_tcp")


def robots_dir() -> str:
    """example-robot-data's robots folder inside this Python's site-packages ('' if not installed)."""
    found = glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                   "example-robot-data", "robots"))
    return found[0] if found else ""


def interleaved(fns: dict, rounds: int) -> dict:
    """Median CPU seconds (this thread's) per call of each function over ``rounds`` interleaved rounds."""
    times: dict = {k: [] for k in fns}
    for _ in range(rounds):
        for k, (fn, reps) in fns.items():
            t0 = time.thread_time()
            for _ in range(reps):
                fn()
            times[k].append((time.thread_time() - t0) / reps)
    return {k: float(np.median(v)) for k, v in times.items()}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer rounds, N up to 1e4")
    args = parser.parse_args(argv)
    import pinocchio as pin

    path = os.path.join(robots_dir(), PANDA[0])
    if not os.path.isfile(path):
        print(f"example-robot-data's {PANDA[0]} is not installed: nothing to measure")
        return 0
    robot = robkin.load(path, tip_link=PANDA[1])
    model = pin.buildModelFromUrdf(path)
    data = model.createData()
    fid = model.getFrameId(PANDA[1])
    extra = np.zeros(model.nq - robot.n)  # the gripper's finger joints, held at 0

    def pin_fk(q: np.ndarray) -> np.ndarray:
        pin.forwardKinematics(model, data, q)
        pin.updateFramePlacement(model, data, fid)
        return data.oMf[fid].homogeneous

    def pin_jac(q: np.ndarray) -> np.ndarray:
        return pin.computeFrameJacobian(model, data, q, fid, pin.LOCAL_WORLD_ALIGNED)

    rng = np.random.default_rng(0)
    Qc = robot.random_q(100, rng)
    Pc = np.hstack([Qc, np.tile(extra, (len(Qc), 1))])
    # sanity: both compute the same things (1e-12: a few products of unit matrices, metre lengths)
    err_fk = max(np.abs(robot.fk(q) - pin_fk(p)).max() for q, p in zip(Qc, Pc))
    err_j = max(np.abs(jacobian_geometric(robot, q) - pin_jac(p)[:, :robot.n]).max() for q, p in zip(Qc, Pc))
    if max(err_fk, err_j) > 1e-12:
        print(f"robkin and pinocchio disagree: FK by {err_fk:.3g}, Jacobian by {err_j:.3g}")
        return 1

    rounds = 5 if args.quick else 15
    q, p = Qc[0], Pc[0]
    Q1 = Qc[:1].copy()
    reps = 2_000 if args.quick else 10_000
    single = interleaved({"rk": (lambda: robot.fk(q), reps), "pin": (lambda: pin_fk(p), reps),
                          "rk1": (lambda: robot.fk(Q1), reps),
                          "rkj": (lambda: jacobian_geometric(robot, q), reps),
                          "pinj": (lambda: pin_jac(p), reps)}, rounds)
    rows = [("FK, one q", single["rk"], single["pin"]),
            ("FK, batch of one", single["rk1"], single["pin"]),
            ("Jacobian, one q", single["rkj"], single["pinj"])]
    sizes = [1_000, 10_000] if args.quick else [1_000, 10_000, 100_000]
    for N in sizes:
        Q = robot.random_q(N, rng)
        n_pin = min(N, 2_000)  # the Python loop is linear in N: time a slice of it
        P = np.hstack([Q[:n_pin], np.tile(extra, (n_pin, 1))])
        reps = max(1, 20_000 // N)  # robkin's batch of 1e3 takes ~0.1 ms: repeat it to time ~2 ms
        t = interleaved({"rk": (lambda: robot.fk(Q), reps), "pin": (lambda: [pin_fk(x) for x in P], 1)},
                        max(3, rounds // 3))
        rows.append((f"FK, batch N={N:,}", t["rk"] / N, t["pin"] / n_pin))
        if N == sizes[0]:
            t = interleaved({"rk": (lambda: jacobian_geometric(robot, Q), reps),
                             "pin": (lambda: [pin_jac(x) for x in P], 1)}, rounds)
            rows.append((f"Jacobian, batch N={N:,}", t["rk"] / N, t["pin"] / n_pin))

    print(f"Panda (7 joints), robkin {robkin.__version__} (compiled core), pinocchio {pin.__version__}; "
          f"medians of interleaved rounds, CPU time of one thread")
    print(f"{'case':<26}{'robkin us/cfg':>15}{'pinocchio us/cfg':>18}{'robkin/pin':>12}")
    for name, a, b in rows:
        print(f"{name:<26}{a * 1e6:>15.3f}{b * 1e6:>18.3f}{a / b:>11.2f}x")
    ratio = {name: a / b for name, a, b in rows}
    goals = [
        ("FK one q within 2x of pinocchio", ratio["FK, one q"] <= 2.0),
        ("Jacobian one q within 2x of pinocchio", ratio["Jacobian, one q"] <= 2.0),
        ("batch of one <= 2x a single call", single["rk1"] <= 2.0 * single["rk"]),
        ("batch FK >= 10x pinocchio's loop", all(r <= 0.1 for k, r in ratio.items() if k.startswith("FK, batch N"))),
        ("batch Jacobian >= 10x pinocchio's loop", ratio[f"Jacobian, batch N={sizes[0]:,}"] <= 0.1),
    ]
    for text, ok in goals:
        print(f"goal {text}: {'met' if ok else 'MISSED'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
