"""Closed-form IK, all solutions, against EAIK on the same targets, in the same run.

Arms: UR5 (example-robot-data, tool0; the three-parallel 6R), Kinova Jaco2 6s (example-robot-data; a
spherical-wrist 6R) and the Puma 560 (standard DH; a spherical-wrist 6R without limits). Targets: FK of
random joint values within the limits. EAIK (``pip install EAIK``, C++) gets the same arm: its axes
and points are read from pinocchio's model of the URDF (from the DH table for the Puma).

Measured, per target (CPU time of this process: the machine is shared, see ``_clock``), one thread
each (EAIK's batch call with one worker thread; robkin's batches on one thread: ``OMP_NUM_THREADS=1``),
median of interleaved rounds (robkin, EAIK, robkin, EAIK, ...):

- batch, all solutions: robkin's closed-form solver on the whole batch (``closed_form_solver(robot)
  .solve``: every branch, wrapped into the limits, marked valid) vs EAIK ``calculate_IK_batched``;
- single target, all solutions: the same two, one call per target (``solve`` on a batch of one vs
  ``calculate_IK``);
- ``Robot.ik``, one target per call, and a whole batch with and without ``all_solutions=True``: the
  full user call (validation, the closed form, the forward-kinematics check of the branches - nearest
  first until one reaches the target, or every branch with all solutions - and de-duplication) against
  the same EAIK calls (``calculate_IK`` per target, ``calculate_IK_batched``), which return every
  solution unchecked: robkin's user call must still be no slower.

SCARA (the 5-DOF inverted SCARA of the seed paper, ``robkin/examples/scara.yaml``): ``Robot.ik`` one
target per call, a batch, and a batch with all solutions, robkin alone (EAIK has no SCARA solver).

First use: importing the compiled module in a fresh process, and per robot the detection of its
closed form plus the kernel's construction (cached on the robot) and the first solve.

And the solution sets: per target, robkin's distinct valid solutions against EAIK's exact (not
least-squares) solutions that fit the joint limits, compared modulo 2 pi to 1e-6 rad; and whether
every robkin solution is within the limits.

Goal (issue 10): per target no slower than EAIK in every row, the same solution sets, limits respected.

Run: ``.venv/bin/python benchmarks/bench_closed_form.py [--targets 1000] [--rounds 7]``. Exit status 0
whatever the result (a benchmark, not a test); the last lines say whether the goal is met.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")  # one thread each: before numpy and robkin are imported

import argparse  # noqa: E402
import glob  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import robkin  # noqa: E402
from robkin.kinematics.closed_form import closed_form_solver  # noqa: E402

ROBOTS_DIR = (glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                     "example-robot-data", "robots")) or [""])[0]
URDF_ARMS = {  # name: (file, tip link)
    "UR5": ("ur_description/urdf/ur5_robot.urdf", "tool0"),
    "Kinova Jaco2 6s": ("kinova_description/robots/kinova.urdf", "j2s6s200_end_effector"),
}
#: Solutions are the same when every joint agrees to this modulo 2 pi (rad); both solvers land ~1e-12.
SAME = 1e-6


def _clock() -> float:
    """CPU time of this process: the machine is shared, and CPU time is what a solver costs whatever
    else runs (wall time under load mostly measures the neighbours)."""
    return time.process_time()


# ---------------------------------------------------------------------------------------- the arms
def urdf_arm(name: str):
    """(robkin robot, EAIK solver) for an example-robot-data arm; EAIK's geometry from pinocchio."""
    import eaik.pybindings.EAIK as eaik
    import pinocchio as pin

    path, tip = URDF_ARMS[name]
    path = os.path.join(ROBOTS_DIR, path)
    robot = robkin.load(path, tip_link=tip)
    model = pin.buildModelFromUrdf(path)
    data = model.createData()
    q = pin.neutral(model)
    pin.computeJointJacobians(model, data, q)
    pin.framesForwardKinematics(model, data, q)
    H, P = [], []
    for joint in robot.joints:
        jid = model.getJointId(joint.name)
        col = pin.getJointJacobian(model, data, jid, pin.ReferenceFrame.WORLD)[:, model.joints[jid].idx_v]
        H.append(col[3:])
        P.append(np.cross(col[3:], col[:3]))       # twist v = -w x p: the axis point nearest the origin
    H, P = np.array(H), np.array(P)
    M = data.oMf[model.getFrameId(tip)].homogeneous
    offsets = np.vstack([P[0], np.diff(P, axis=0), M[:3, 3] - P[-1]])
    return robot, eaik.Robot(H.T, offsets.T, M[:3, :3], [], True)


def puma560():
    """Puma 560 (Corke's standard DH parameters) in robkin and in EAIK's DH form."""
    from eaik.IK_DH import DhRobot
    from robkin.robot import default_joints

    a, d = [0, 0.4318, 0.0203, 0, 0, 0], [0, 0, 0.15005, 0.4318, 0, 0]
    alpha = [np.pi / 2, 0, -np.pi / 2, np.pi / 2, -np.pi / 2, 0]
    rows = [[a[i], d[i], alpha[i], 0.0] for i in range(6)]
    robot = robkin.DHTable(rows, default_joints(["revolute"] * 6)).to_robot(name="puma560")
    return robot, DhRobot(np.array(alpha), np.array(a), np.array(d))._robot


# ------------------------------------------------------------------------------------- comparison
def _wrapped_fits(q: np.ndarray, lim: np.ndarray) -> bool:
    k = np.ceil((lim[:, 0] - q) / (2 * np.pi))
    return bool(np.all(q + 2 * np.pi * k <= lim[:, 1] + 1e-12))


def _same(a: np.ndarray, b: np.ndarray) -> bool:
    return bool(np.abs(np.angle(np.exp(1j * (a - b)))).max() <= SAME)


def compare_sets(robot, solver, targets) -> tuple[int, int, int]:
    """(targets with equal solution sets, targets with every solution within limits, solutions)."""
    res = robot.ik(targets, all_solutions=True)
    lim = robot.limits
    equal = within = count = 0
    for T, ours in zip(targets, res.solutions):
        sol = solver.calculate_IK(T)
        theirs = [q for q, ls in zip(np.asarray(sol.Q).reshape(-1, 6), sol.is_LS) if not ls
                  and _wrapped_fits(q, lim)]
        uniq: list[np.ndarray] = []
        for q in theirs:
            if not any(_same(q, u) for u in uniq):
                uniq.append(q)
        equal += len(uniq) == len(ours) and all(any(_same(q, u) for u in uniq) for q in ours)
        within += bool(np.all((ours >= lim[:, 0]) & (ours <= lim[:, 1])))
        count += len(ours)
    return equal, within, count


# ------------------------------------------------------------------------------------------ timing
def import_ms() -> float:
    """Wall milliseconds to import the compiled 6R kernels in a fresh process (robkin already loaded)."""
    code = ("import time, robkin, numpy; t = time.perf_counter(); import robkin.compiled.ik.closed_form_6r; "
            "print((time.perf_counter() - t) * 1e3)")
    return float(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout)


def first_use_us(robot) -> tuple[float, float]:
    """(detection + kernel construction, first solve) in CPU us, on a fresh copy of the robot."""
    fresh = robot.replace()
    T = fresh.fk(np.zeros((1, fresh.n)))
    t0 = _clock()
    cf = closed_form_solver(fresh)
    t1 = _clock()
    cf.solve(T, np.zeros((1, fresh.n)))
    return (t1 - t0) * 1e6, (_clock() - t1) * 1e6


def per_target(fn, n: int) -> float:
    t0 = _clock()
    fn()
    return (_clock() - t0) / n * 1e6


def bench_arm(name: str, robot, solver, n_targets: int, rounds: int) -> list[tuple[str, float, float]]:
    targets = robot.fk(robot.random_q(n_targets, rng=7))
    listed = list(targets)
    cf = closed_form_solver(robot)
    ref = np.zeros((n_targets, 6))
    ref1 = np.zeros((1, 6))

    def ours_batch():
        cf.solve(targets, ref)

    def theirs_batch():
        solver.calculate_IK_batched(listed, 1)

    def ours_single():
        for T in targets:
            cf.solve(T[None], ref1)

    def theirs_single():
        for T in listed:
            solver.calculate_IK(T)

    def ours_ik_single():
        for T in listed:
            robot.ik(T)

    def ours_ik_batch():
        robot.ik(targets)

    def ours_ik_batch_all():
        robot.ik(targets, all_solutions=True)

    cases = [("all solutions, batch", ours_batch, theirs_batch, n_targets, n_targets),
             ("all solutions, one target per call", ours_single, theirs_single, n_targets, n_targets),
             ("Robot.ik(T), one target per call", ours_ik_single, theirs_single, n_targets, n_targets),
             ("Robot.ik(targets), batch", ours_ik_batch, theirs_batch, n_targets, n_targets),
             ("Robot.ik(targets, all_solutions=True)", ours_ik_batch_all, theirs_batch, n_targets, n_targets)]
    cf.solve(targets[:2], ref[:2])                 # first calls (imports, caches) outside the clock
    solver.calculate_IK(listed[0])
    rows = []
    for label, ours, theirs, n1, n2 in cases:
        a, b = [], []
        for _ in range(rounds):
            a.append(per_target(ours, n1))
            b.append(per_target(theirs, n2))
        rows.append((label, float(np.median(a)), float(np.median(b))))
    return rows


def bench_scara(robot, n_targets: int, rounds: int) -> list[tuple[str, float]]:
    """Robot.ik on the SCARA: one target per call, a batch, a batch with all solutions (median us)."""
    targets = robot.fk(robot.random_q(n_targets, rng=7))
    listed = list(targets)
    robot.ik(listed[0])
    cases = [("Robot.ik(T), one target per call", lambda: [robot.ik(T) for T in listed]),
             ("Robot.ik(targets), batch", lambda: robot.ik(targets)),
             ("Robot.ik(targets, all_solutions=True)", lambda: robot.ik(targets, all_solutions=True))]
    return [(label, float(np.median([per_target(fn, n_targets) for _ in range(rounds)]))) for label, fn in cases]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--targets", type=int, default=1000)
    parser.add_argument("--rounds", type=int, default=7)
    args = parser.parse_args()
    try:
        import eaik  # noqa: F401
    except ImportError:
        print("EAIK is not installed (pip install EAIK): nothing to compare with")
        return 0
    arms = [(name, *urdf_arm(name)) for name in URDF_ARMS if os.path.isfile(os.path.join(ROBOTS_DIR,
                                                                                         URDF_ARMS[name][0]))]
    arms.append(("Puma 560", *puma560()))
    print(f"closed-form IK, all solutions: robkin vs EAIK, {args.targets} targets, median of {args.rounds} "
          f"interleaved rounds, CPU us per target, one thread each")
    print(f"first use: importing the compiled kernels {import_ms():.2f} ms (fresh process)")
    goal = True
    for name, robot, solver in arms:
        detect, first = first_use_us(robot)
        print(f"\n{name} ({closed_form_solver(robot).name}; detection + kernel {detect:.0f} us, first solve "
              f"{first:.0f} us, once per robot)")
        for label, ours, theirs in bench_arm(name, robot, solver, args.targets, args.rounds):
            print(f"  {label:40s} robkin {ours:9.2f}  EAIK {theirs:7.2f}  robkin/EAIK {ours / theirs:6.2f}")
            goal &= ours <= theirs
        equal, within, count = compare_sets(robot, solver, robot.fk(robot.random_q(args.targets, rng=8)))
        print(f"  solution sets equal to EAIK's (within limits): {equal}/{args.targets} targets; "
              f"{count} solutions, all within limits on {within}/{args.targets} targets")
        goal &= equal == within == args.targets
    scara = robkin.load(os.path.join(os.path.dirname(robkin.__file__), "examples", "scara.yaml"))
    print(f"\nSCARA, 5-DOF inverted ({closed_form_solver(scara).name}; no peer), CPU us per target")
    for label, us in bench_scara(scara, args.targets, args.rounds):
        print(f"  {label:40s} robkin {us:9.2f}")
    print(f"\ngoal (no slower than EAIK per target in every row, the same solution sets, limits respected): "
          f"{'met' if goal else 'NOT met'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
