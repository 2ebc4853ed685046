"""Forward-kinematics throughput of robkin against pinocchio, measured in the same run.

A 7-joint KUKA LBR iiwa-like arm (standard DH) is built in robkin and, from the same joint frames, as
a URDF string loaded by pinocchio. Measured:

- batch: ``Robot.fk(Q)`` for Q of shape (N, 7), N = 1e3, 1e4, 1e5, against a Python loop of
  ``pin.forwardKinematics`` + ``data.oMi[-1]`` over the same N configurations (pinocchio has no
  batch FK; this loop is how one computes many configurations with it from Python);
- single: ``Robot.fk(q)`` for one q against one ``pin.forwardKinematics`` call.

Goals (ratios, never absolute times, since the machine varies): batch >= 5x pinocchio's
per-configuration throughput; single within 10x of pinocchio's call.

Run: ``python benchmarks/bench_fk.py`` (prints a table; ``--quick`` for a short run).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import robkin
from robkin import se3
from robkin.robot import default_joints

#: KUKA LBR iiwa 14-like standard DH (a, d, alpha, theta), metres and radians
IIWA_DH = np.array([
    [0.0, 0.36, -np.pi / 2, 0.0],
    [0.0, 0.0, np.pi / 2, 0.0],
    [0.0, 0.42, np.pi / 2, 0.0],
    [0.0, 0.0, -np.pi / 2, 0.0],
    [0.0, 0.40, -np.pi / 2, 0.0],
    [0.0, 0.0, np.pi / 2, 0.0],
    [0.0, 0.126, 0.0, 0.0],
])


def iiwa() -> robkin.Robot:
    return robkin.DHTable(IIWA_DH, default_joints(["revolute"] * 7)).to_robot(name="iiwa")


def urdf_of(robot: robkin.Robot) -> str:
    """URDF text whose joint i frame is the GJD frame J_i (axis = local z), tool as the last link."""
    f = lambda v: " ".join(repr(float(x)) for x in v)  # noqa: E731
    rows = robkin.rpy_from_robot(robot).rows  # row 0 world->base (identity here), 1..n joints, n+1 tool
    parts = ['<robot name="bench">', '<link name="base"/>']
    parent = "base"
    for i in range(robot.n):
        parts += [f'<link name="link{i + 1}"/>',
                  f'<joint name="joint{i + 1}" type="revolute"><parent link="{parent}"/>'
                  f'<child link="link{i + 1}"/><origin rpy="{f(rows[i + 1, :3])}" xyz="{f(rows[i + 1, 3:])}"/>'
                  f'<axis xyz="0 0 1"/><limit lower="-10" upper="10" effort="1" velocity="1"/></joint>']
        parent = f"link{i + 1}"
    parts += ['<link name="tool"/>',
              f'<joint name="tool_joint" type="fixed"><parent link="{parent}"/><child link="tool"/>'
              f'<origin rpy="{f(rows[-1, :3])}" xyz="{f(rows[-1, 3:])}"/></joint>', '</robot>']
    return "".join(parts)


def best_of(fn, repeats: int) -> float:
    """Smallest wall time of ``repeats`` runs (the least disturbed by other processes)."""
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="fewer repeats, N up to 1e4")
    args = parser.parse_args(argv)
    import pinocchio as pin

    robot = iiwa()
    model = pin.buildModelFromXML(urdf_of(robot))
    data = model.createData()
    tool_frame = model.frames[model.getFrameId("tool")]
    # oMi[-1] is the last joint's frame; the tool is a fixed placement after it
    tool_in_last = tool_frame.placement

    def pin_fk(q: np.ndarray) -> np.ndarray:
        pin.forwardKinematics(model, data, q)
        return (data.oMi[model.njoints - 1] * tool_in_last).homogeneous

    rng = np.random.default_rng(0)
    # sanity: both compute the same thing (1e-12: products of a few unit matrices and metre lengths)
    Qc = robot.random_q(100, rng)
    err = max(np.abs(robot.fk(q) - pin_fk(q)).max() for q in Qc)
    assert err < 1e-12, f"robkin and pinocchio disagree by {err}"

    sizes = [1_000, 10_000] if args.quick else [1_000, 10_000, 100_000]
    repeats = 3 if args.quick else 5
    rows = []
    for N in sizes:
        Q = robot.random_q(N, rng)
        t_rk = best_of(lambda: robot.fk(Q), repeats)
        n_pin = min(N, 20_000)  # the per-configuration loop is linear in N: time a part of it
        t_pin = best_of(lambda: [pin_fk(q) for q in Q[:n_pin]], max(1, repeats // 2)) * N / n_pin
        rows.append((f"batch N={N:>7,}", t_rk / N * 1e6, t_pin / N * 1e6, t_pin / t_rk))

    q = Qc[0]
    reps = 2_000 if args.quick else 20_000
    t_rk1 = best_of(lambda: [robot.fk(q) for _ in range(reps)], 3) / reps
    t_pin1 = best_of(lambda: [pin_fk(q) for _ in range(reps)], 3) / reps
    rows.append(("single q", t_rk1 * 1e6, t_pin1 * 1e6, t_pin1 / t_rk1))

    print(f"FK of a 7-joint iiwa-like arm; robkin {robkin.__version__}, pinocchio {pin.__version__}")
    print(f"{'case':<18}{'robkin us/cfg':>15}{'pinocchio us/cfg':>18}{'speed-up':>10}")
    for name, a, b, ratio in rows:
        print(f"{name:<18}{a:>15.3f}{b:>18.3f}{ratio:>9.2f}x")
    batch_ok = all(r[3] >= 5.0 for r in rows[:-1])
    single_ok = rows[-1][3] >= 0.1
    print(f"goal batch >= 5x pinocchio's loop: {'met' if batch_ok else 'MISSED'}; "
          f"goal single within 10x of pinocchio: {'met' if single_ok else 'MISSED'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
