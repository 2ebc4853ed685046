"""Arms for the general closed-form IK tests and benchmark: published DH tables (JACO2, xArm6, Gen3),
generic and one-parallel-pair 6R arms from seeded random DH tables, and 7-joint arms from files."""

from __future__ import annotations

import glob
import os
import sys

import numpy as np

import robkin
from robkin.robot import Joint, default_joints

ROBOTS_DIR = (glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                     "example-robot-data", "robots")) or [""])[0]
DATA = os.path.join(os.path.dirname(__file__), "data")


def dh_arm(a, d, alpha, name: str, limits=None, theta=None) -> robkin.Robot:
    """A revolute arm from standard DH columns (a, d, alpha, theta offsets), optional limits (n, 2)."""
    n = len(a)
    theta = np.zeros(n) if theta is None else theta
    rows = np.column_stack([a, d, alpha, theta])
    joints = default_joints(["revolute"] * n) if limits is None else \
        tuple(Joint(f"joint{i + 1}", "revolute", lo, hi) for i, (lo, hi) in enumerate(limits))
    return robkin.DHTable(rows, joints).to_robot(name=name)


def generic_6r(seed: int) -> robkin.Robot:
    """A 6R arm with random DH parameters (no special geometry): up to 16 solutions."""
    rng = np.random.default_rng(seed)
    return dh_arm(rng.uniform(-0.5, 0.5, 6), rng.uniform(-0.5, 0.5, 6), rng.uniform(-np.pi, np.pi, 6),
                  f"generic{seed}")


def parallel_pair_6r(seed: int, pair: int = 1) -> robkin.Robot:
    """A random 6R arm whose axes pair+1 and pair+2 are parallel (alpha = 0) and nothing else special."""
    rng = np.random.default_rng(seed)
    alpha = rng.uniform(-np.pi, np.pi, 6)
    alpha[pair] = 0.0
    return dh_arm(rng.uniform(-0.5, 0.5, 6), rng.uniform(-0.5, 0.5, 6), alpha, f"parallel{seed}")


def jaco2() -> robkin.Robot:
    """Kinova JACO2 6-DOF with the curved (non-spherical, 55 degree) wrist, Kinova's published DH
    parameters (j2n6s300): axes 2 || 3, wrist axes not meeting - no known class."""
    D1, D2, D3, D4, D5, D6, e2 = 0.2755, 0.41, 0.2073, 0.0741, 0.0741, 0.16, 0.0098
    aa = 11 * np.pi / 72
    k = np.sin(aa) / np.sin(2 * aa)
    return dh_arm([0, D2, 0, 0, 0, 0], [D1, 0, -e2, -(D3 + k * D4), -(k * D4 + k * D5), -(k * D5 + D6)],
                  [np.pi / 2, np.pi, np.pi / 2, 2 * aa, 2 * aa, np.pi], "jaco2",
                  theta=np.array([0, -np.pi / 2, np.pi / 2, 0, -np.pi, np.pi / 2]))


def xarm6() -> robkin.Robot:
    """UFACTORY xArm6, its published DH parameters and limits: axes 2 || 3, an offset wrist."""
    lim = [(-2 * np.pi, 2 * np.pi), (-2.059, 2.0944), (-3.927, 0.19198), (-2 * np.pi, 2 * np.pi),
           (-1.69297, np.pi), (-2 * np.pi, 2 * np.pi)]
    return dh_arm([0, 0.2895, 0.0775, 0, 0.076, 0], [0.267, 0, 0, 0.3425, 0, 0.097],
                  [-np.pi / 2, 0, -np.pi / 2, np.pi / 2, -np.pi / 2, 0], "xarm6", limits=lim,
                  theta=np.array([0, -1.3849, 1.3849, 0, 0, 0]))


def gen3() -> robkin.Robot:
    """Kinova Gen3 7-DOF, the classic DH parameters of its user guide (base frame turned half a turn
    about x, as there), with its limits (joints 1, 3, 5, 7 turn endlessly)."""
    pi = np.pi
    d = [-0.2848, -0.0118, -0.4208, -0.0128, -0.3143, 0.0, -0.1674]
    alpha = [pi / 2] * 6 + [pi]
    theta = [0.0] + [pi] * 6
    lim = [None, 2.2497, None, 2.5796, None, 2.0996, None]
    joints = tuple(Joint(f"joint_{i + 1}", "revolute", None if x is None else -x, x) for i, x in enumerate(lim))
    robot = robkin.DHTable(np.column_stack([np.zeros(7), d, alpha, theta]), joints).to_robot(name="gen3")
    return robot.replace(frames=np.diag([1.0, -1.0, -1.0, 1.0]) @ np.array(robot.frames))


def iiwa() -> robkin.Robot:
    return robkin.load(os.path.join(DATA, "iiwa14.urdf"))


def erd_arm(path: str, tip: str | None) -> robkin.Robot | None:
    """An example-robot-data arm, or None when the package is absent."""
    full = os.path.join(ROBOTS_DIR, path)
    return robkin.load(full, tip_link=tip) if os.path.isfile(full) else None


def panda() -> robkin.Robot | None:
    return erd_arm("panda_description/urdf/panda.urdf", "panda_hand_tcp")


def xarm7() -> robkin.Robot | None:
    return erd_arm("xarm_description/urdf/xarm7.urdf", None)


def ur5() -> robkin.Robot | None:
    return erd_arm("ur_description/urdf/ur5_robot.urdf", "tool0")


def perturbed(robot: robkin.Robot, size: float, seed: int) -> robkin.Robot:
    """The robot with every joint frame moved by ~size (metres) and turned by ~size (radians): a
    calibrated arm."""
    rng = np.random.default_rng(seed)
    F = np.array(robot.frames)
    for i in range(robot.n):
        k = rng.normal(size=3)
        k *= size / np.linalg.norm(k)
        K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
        F[i, :3, :3] = (np.eye(3) + K + K @ K / 2) @ F[i, :3, :3]
        u, _, vt = np.linalg.svd(F[i, :3, :3])
        F[i, :3, :3] = u @ vt
        F[i, :3, 3] += rng.normal(scale=size, size=3)
    return robot.replace(frames=F)


#: the 7-joint arms and the joint each test locks: the one their analytic IK literature takes as the
#: redundancy parameter (the Panda's q7, the others' q3)
SEVEN = {"panda": (panda, "panda_joint7"), "iiwa": (iiwa, "iiwa_joint_3"), "xarm7": (xarm7, "joint3"),
         "gen3": (gen3, "joint_3")}
