"""robkin's MJCF against MuJoCo's own URDF compiler, both against pinocchio, on real robot files.

For each chain (example-robot-data's URDFs): pinocchio's joint-space mass matrix M(q) (``crba``) and
gravity torques g(q) of the source URDF, the joints off the chain locked at 0 (``buildReducedModel``),
are the reference. Two MuJoCo models of the same file are compared with it at the same q:

- robkin: ``robkin.io.mjcf.mjcf_from_robot`` of the chain (``mj_fullM`` after ``mj_forward``, and
  ``qfrc_bias`` at zero velocity), qpos[:n] = q;
- MuJoCo: ``mujoco.MjModel.from_xml_string`` of the URDF itself, with MuJoCo's default compiler options
  (as a user would load it), qpos of the chain's joints by name, every other joint at 0. The URDF's
  ``<visual>`` and ``<collision>`` elements are removed first (their ``package://`` meshes are not
  found by MuJoCo's compiler; for links that carry an ``<inertial>`` they do not change the dynamics).

Reported per chain: the largest difference of M and of g from pinocchio's, relative to pinocchio's
largest entry, and the total mass difference (kg); "refused" where MuJoCo does not load the URDF. An
accuracy comparison, not a timing: nothing is timed, so one run is the result.

Run: ``.venv/bin/python benchmarks/compare_mujoco_urdf_compile.py [--samples 5] [--markdown]``.
"""

from __future__ import annotations

import argparse
import glob
import os
import re
import sys
import warnings

import numpy as np

#: (file under example-robot-data/robots, base link, tip link)
CHAINS = [
    ("ur_description/urdf/ur3_robot.urdf", None, "tool0"),
    ("ur_description/urdf/ur5_robot.urdf", None, "tool0"),
    ("ur_description/urdf/ur10_robot.urdf", None, "ee_link"),
    ("panda_description/urdf/panda.urdf", None, "panda_hand_tcp"),
    ("kinova_description/robots/kinova.urdf", None, "j2s6s200_end_effector"),
    ("xarm_description/urdf/xarm7.urdf", None, None),
    ("z1_description/urdf/z1.urdf", None, "gripperMover"),
    ("so_arm_description/urdf/so100.urdf", None, None),
    ("so_arm_description/urdf/so101.urdf", None, "gripper_frame_link"),
    ("talos_data/robots/talos_full_v2.urdf", "torso_2_link", "gripper_left_base_link"),
    ("talos_data/robots/talos_full_v2.urdf", "base_link", "left_sole_link"),
    ("solo_description/robots/solo12.urdf", None, "FL_FOOT"),
    ("go1_description/urdf/go1.urdf", None, "FR_foot"),
    ("go2_description/urdf/go2.urdf", None, "FL_foot"),
    ("a1_description/urdf/a1.urdf", None, "FR_foot"),
    ("b1_description/urdf/b1-z1.urdf", None, "FR_foot"),
    ("baxter_description/urdf/baxter.urdf", None, "right_gripper"),
    ("tiago_description/robots/tiago.urdf", None, "hand_tool_link"),
    ("g1_description/urdf/g1_29dof_rev_1_0.urdf", None, "left_ankle_roll_link"),
    ("romeo_description/urdf/romeo.urdf", None, "l_sole"),
    ("pr2_description/urdf/pr2.urdf", None, "r_gripper_tool_frame"),
]


def _robots_dir() -> str:
    found = glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                   "example-robot-data", "robots"))
    if not found:
        sys.exit("example-robot-data is not installed (pip install 'robkin[test]')")
    return found[0]


def _without_shapes(urdf: str) -> str:
    urdf = re.sub(r"<(visual|collision)\b.*?</\1>", "", urdf, flags=re.S)
    return re.sub(r"<(visual|collision)\b[^>]*/>", "", urdf)


class Reference:
    """pinocchio's reduced model of the source URDF (robkin's chain; other joints locked at 0)."""

    def __init__(self, path: str, names: list[str]) -> None:
        import pinocchio as pin

        self.pin = pin
        full = pin.buildModelFromUrdf(path)
        lock = [i for i in range(1, full.njoints) if full.names[i] not in names]
        self.model = pin.buildReducedModel(full, lock, pin.neutral(full)) if lock else full
        self.data = self.model.createData()
        self.total_mass = sum(full.inertias[i].mass for i in range(full.njoints))
        self.joints = [self.model.joints[self.model.getJointId(n)] for n in names]
        self.order = [jm.idx_v for jm in self.joints]

    def _q(self, q: np.ndarray) -> np.ndarray:
        out = self.pin.neutral(self.model)
        for jm, v in zip(self.joints, q):
            if jm.nq == 2:
                out[jm.idx_q], out[jm.idx_q + 1] = np.cos(v), np.sin(v)
            else:
                out[jm.idx_q] = v
        return out

    def mass_matrix(self, q: np.ndarray) -> np.ndarray:
        M = self.pin.crba(self.model, self.data, self._q(q))
        M = np.triu(M) + np.triu(M, 1).T
        return M[np.ix_(self.order, self.order)]

    def gravity(self, q: np.ndarray) -> np.ndarray:
        return self.pin.computeGeneralizedGravity(self.model, self.data, self._q(q))[self.order]


def _mujoco_errors(model, names: list[str], ref: Reference, Q: np.ndarray) -> tuple[float, float, float]:
    """(max rel. error of M, of g, total mass difference kg) of a MuJoCo model against the reference."""
    import mujoco

    data = mujoco.MjData(model)
    qadr = [model.jnt_qposadr[model.joint(n).id] for n in names]
    vadr = [model.jnt_dofadr[model.joint(n).id] for n in names]
    eM = eg = 0.0
    for q in Q:
        data.qpos[:] = model.qpos0
        data.qpos[qadr] = q
        data.qvel[:] = 0
        mujoco.mj_forward(model, data)
        M = np.zeros((model.nv, model.nv))
        mujoco.mj_fullM(model, data, M)
        Mr, gr = ref.mass_matrix(q), ref.gravity(q)
        eM = max(eM, float(np.abs(M[np.ix_(vadr, vadr)] - Mr).max() / np.abs(Mr).max()))
        eg = max(eg, float(np.abs(data.qfrc_bias[vadr] - gr).max() / max(np.abs(gr).max(), 1e-300)))
    return eM, eg, float(model.body_mass.sum() - ref.total_mass)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--samples", type=int, default=5, help="configurations per chain (default 5)")
    parser.add_argument("--markdown", action="store_true", help="print the table as Markdown")
    args = parser.parse_args()
    import mujoco

    import robkin
    from robkin.io.mjcf import mjcf_from_robot

    root = _robots_dir()
    rows = []
    for rel, base, tip in CHAINS:
        path = os.path.join(root, rel)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            robot = robkin.load(path, base_link=base, tip_link=tip)
            ours = mujoco.MjModel.from_xml_string(mjcf_from_robot(robot, mesh_files={}))
        names = [j.name for j in robot.joints]
        ref = Reference(path, names)
        Q = np.random.default_rng(0).uniform(-1.5, 1.5, (args.samples, robot.n))
        r = _mujoco_errors(ours, names, ref, Q)
        try:
            with open(path) as f:
                theirs = mujoco.MjModel.from_xml_string(_without_shapes(f.read()))
            m = _mujoco_errors(theirs, names, ref, Q)
        except Exception as exc:  # noqa: BLE001 - MuJoCo's refusal is the result
            m = str(exc).splitlines()[0].replace("Error: ", "")[:60]
        rows.append((f"{rel.split('/')[-1].removesuffix('.urdf')}:{robot.bodies.tip}", robot.n, r, m))
    head = ("chain", "n", "robkin M", "robkin g", "robkin mass", "MuJoCo M", "MuJoCo g", "MuJoCo mass (kg)")
    fmt = "| " + " | ".join(["{}"] * len(head)) + " |" if args.markdown else "{:44s} {:>2} " + "{:>10} " * 6
    print(fmt.format(*head))
    if args.markdown:
        print("|" + "---|" * len(head))
    for name, n, r, m in rows:
        ours = [f"{r[0]:.1e}", f"{r[1]:.1e}", f"{r[2]:+.1e}"]
        theirs = [f"{m[0]:.1e}", f"{m[1]:.1e}", f"{m[2]:+.1e}"] if isinstance(m, tuple) else [f"refused: {m}", "", ""]
        print(fmt.format(name, n, *ours, *theirs))
    worst = max(max(r[0], r[1]) for _, _, r, _ in rows)
    print(f"robkin's MJCF: M(q) and g(q) within {worst:.1e} of pinocchio's largest entry on {len(rows)} chains")
    return 0


if __name__ == "__main__":
    sys.exit(main())
