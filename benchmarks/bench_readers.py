"""MJCF and SDF load time of robkin against MuJoCo's compile of the same model, measured in the same run.

Serial chains of 7, 100, 250 and 1000 links (random link offsets and orientations, random unit hinge
axes, limits, an inertial and a shape per link) are written three ways into a temporary folder: as MJCF
(nested bodies with ``pos``/``euler``), as SDFormat 1.9 (each joint posed ``relative_to`` its parent
link, each link ``relative_to`` its joint) and as URDF. Per file, per round, one call each, interleaved
(so a busy machine slows all alike), timed in CPU time of this process; the table gives medians:

- robkin MJCF: ``robkin.load(chain.xml)`` (parse, tree, chain selection, the Robot; shapes and
  inertials are parsed on first use);
- robkin SDF: ``robkin.load(chain.sdf)``;
- robkin URDF: ``robkin.load(chain.urdf)`` (the compiled expat scan, for reference);
- MuJoCo: ``mujoco.MjModel.from_xml_path(chain.xml)``, MuJoCo's full compile of the MJCF. MuJoCo does
  not read SDF, so the SDF row's peer is MuJoCo's compile of the same chain as MJCF. MuJoCo's XML parser
  refuses elements nested deeper than its limit (a 1000-body chain), shown as "refused";
- pinocchio: ``pinocchio.buildModelFromUrdf(chain.urdf)`` (the URDF of the same chain), for reference.

The chains' FK (robkin's MJCF, SDF and URDF reads at one random q) agree to 1e-9 relative to the chain's
reach before anything is timed (a benchmark of readers that read different robots would measure
nothing). Real files: MuJoCo's own MJCF of example-robot-data's Talos (whole humanoid, 44 joints) and UR5
URDFs (``mj_saveLastXML`` of its URDF compile, visuals and collisions removed first since their meshes
are not shipped), robkin loading the chain to the given tip.

Goal (ratios, never absolute times): robkin's MJCF and SDF loads no slower than MuJoCo's compile of the
same chain (ratio <= 1) at 7, 100 and 250 links, and the time per link flat from 100 to 1000 links
(linear); the last lines say whether each is met.

Run: ``python benchmarks/bench_readers.py`` (``--rounds N``, default 30; ``--quick``: 7 rounds, no
1000-link chain).
"""

from __future__ import annotations

import argparse
import math
import os
import random
import re
import statistics
import sys
import tempfile
import time
import warnings

import numpy as np

import robkin

SIZES = (7, 100, 250, 1000)
#: example-robot-data URDFs MuJoCo compiles and saves as MJCF: (file, tip link robkin loads the chain to)
REAL = [("talos_data/robots/talos_full_v2.urdf", "gripper_left_fingertip_1_link"),
        ("ur_description/urdf/ur5_robot.urdf", None)]


def _clock() -> float:
    """CPU time of this process (see the module docstring)."""
    return time.process_time()


def _chain(n: int, seed: int = 0) -> list[tuple[list[float], list[float], list[float]]]:
    """(xyz, rpy, unit axis) of n links."""
    rng = random.Random(seed)
    out = []
    for _ in range(n):
        xyz = [rng.uniform(-0.2, 0.2) for _ in range(3)]
        rpy = [rng.uniform(-math.pi, math.pi) for _ in range(3)]
        axis = [rng.gauss(0, 1) for _ in range(3)]
        norm = math.sqrt(sum(a * a for a in axis))
        out.append((xyz, rpy, [a / norm for a in axis]))
    return out


def _f(v: list[float]) -> str:
    return " ".join(repr(x) for x in v)


def urdf_text(n: int) -> str:
    s = ['<robot name="chain">', '<link name="l0"/>']
    for i, (xyz, rpy, axis) in enumerate(_chain(n)):
        s.append(f'<link name="l{i + 1}"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" '
                 f'ixy="0" ixz="0" iyz="0"/></inertial><visual><geometry><cylinder radius="0.03" length="0.2"/>'
                 f'</geometry></visual></link>')
        s.append(f'<joint name="j{i + 1}" type="revolute"><parent link="l{i}"/><child link="l{i + 1}"/>'
                 f'<origin xyz="{_f(xyz)}" rpy="{_f(rpy)}"/><axis xyz="{_f(axis)}"/>'
                 f'<limit lower="-3" upper="3" effort="1" velocity="1"/></joint>')
    return "\n".join(s + ["</robot>"])


def sdf_text(n: int) -> str:
    s = ['<sdf version="1.9"><model name="chain">', '<link name="l0"/>']
    for i, (xyz, rpy, axis) in enumerate(_chain(n)):
        s.append(f'<link name="l{i + 1}"><pose relative_to="j{i + 1}"/><inertial><mass>1</mass><inertia>'
                 f'<ixx>0.01</ixx><iyy>0.01</iyy><izz>0.01</izz></inertia></inertial><visual name="v"><geometry>'
                 f'<cylinder><radius>0.03</radius><length>0.2</length></cylinder></geometry></visual></link>')
        s.append(f'<joint name="j{i + 1}" type="revolute"><pose relative_to="l{i}">{_f(xyz)} {_f(rpy)}</pose>'
                 f'<parent>l{i}</parent><child>l{i + 1}</child><axis><xyz>{_f(axis)}</xyz><limit><lower>-3</lower>'
                 f'<upper>3</upper></limit></axis></joint>')
    return "\n".join(s + ["</model></sdf>"])


def mjcf_text(n: int) -> str:
    # euler="x y z" with MuJoCo's default eulerseq xyz (rotating axes) is R = Rx Ry Rz; a URDF rpy is
    # Rz(yaw) Ry(pitch) Rx(roll) = fixed-axes XYZ: the same rotation with eulerseq="XYZ"
    s = ['<mujoco model="chain"><compiler angle="radian" eulerseq="XYZ"/><worldbody><body name="l0">']
    for i, (xyz, rpy, axis) in enumerate(_chain(n)):
        s.append(f'<body name="l{i + 1}" pos="{_f(xyz)}" euler="{_f(rpy)}"><inertial pos="0 0 0" mass="1" '
                 f'diaginertia="0.01 0.01 0.01"/><joint name="j{i + 1}" axis="{_f(axis)}" range="-3 3"/>'
                 f'<geom type="cylinder" size="0.03 0.1"/>')
    s.append("</body>" * (n + 1))
    return "\n".join(s + ["</worldbody></mujoco>"])


def _check_same(paths: dict[str, str], n: int) -> None:
    """The three reads are the same chain: FK at one random q agrees (1e-9 of the reach; rounding of n
    products is ~1e-13 at n = 1000)."""
    robots = {k: robkin.load(p) for k, p in paths.items()}
    q = np.random.default_rng(n).uniform(-1, 1, n)
    ref = robots["urdf"].fk(q)
    for kind, r in robots.items():
        err = np.abs(r.fk(q) - ref).max()
        if r.n != n or err > 1e-9 * max(1.0, 0.35 * n):
            raise SystemExit(f"{kind} chain of {n} links differs from the URDF's (n = {r.n}, FK error {err:.3g})")


def _real_files(folder: str) -> list[tuple[str, str, str | None]]:
    """(name, MJCF path, tip) of MuJoCo's own MJCF of real robots (empty without example-robot-data)."""
    import glob

    import mujoco

    found = glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                   "example-robot-data", "robots"))
    out = []
    for rel, tip in REAL if found else []:
        with open(os.path.join(found[0], rel), encoding="utf-8") as f:
            text = re.sub(r"<visual>.*?</visual>|<collision>.*?</collision>", "", f.read(), flags=re.S)
        name = os.path.basename(rel).replace(".urdf", "")
        path = os.path.join(folder, f"{name}.xml")
        mujoco.mj_saveLastXML(path, mujoco.MjModel.from_xml_string(text))
        out.append((name, path, tip))
    return out


def _median_ms(times: list[float]) -> float:
    return statistics.median(times) * 1e3


def main(argv: list[str] | None = None) -> int:
    import mujoco
    import pinocchio as pin

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=30)
    parser.add_argument("--quick", action="store_true", help="7 rounds, no 1000-link chain")
    args = parser.parse_args(argv)
    rounds = 7 if args.quick else args.rounds
    sizes = [n for n in SIZES if not (args.quick and n > 250)]
    warnings.simplefilter("ignore")  # talos: the joints above the chosen chain are held at 0
    ratios: dict[str, float] = {}
    per_link: dict[str, dict[int, float]] = {"MJCF": {}, "SDF": {}}
    with tempfile.TemporaryDirectory() as folder:
        print(f"{'chain':<10} {'MJCF ms':>8} {'SDF ms':>8} {'URDF ms':>8} {'MuJoCo ms':>10} {'pin URDF ms':>12} "
              f"{'MJCF/MuJoCo':>11} {'SDF/MuJoCo':>10}")
        for n in sizes:
            paths = {}
            for kind, make in (("xml", mjcf_text), ("sdf", sdf_text), ("urdf", urdf_text)):
                paths[kind] = os.path.join(folder, f"chain{n}.{kind}")
                with open(paths[kind], "w", encoding="utf-8") as f:
                    f.write(make(n))
            _check_same(paths, n)
            try:
                mujoco.MjModel.from_xml_path(paths["xml"])
                has_mj = True
            except ValueError:  # MuJoCo's XML parser: element nesting too deep
                has_mj = False
            pin.buildModelFromUrdf(paths["urdf"])
            t: dict[str, list[float]] = {k: [] for k in ("xml", "sdf", "urdf", "mj", "pin")}
            for _ in range(max(3, rounds // 4) if n >= 1000 else rounds):
                for kind in ("xml", "sdf", "urdf"):
                    t0 = _clock()
                    robkin.load(paths[kind])
                    t[kind].append(_clock() - t0)
                if has_mj:
                    t0 = _clock()
                    mujoco.MjModel.from_xml_path(paths["xml"])
                    t["mj"].append(_clock() - t0)
                t0 = _clock()
                pin.buildModelFromUrdf(paths["urdf"])
                t["pin"].append(_clock() - t0)
            m = {k: _median_ms(v) if v else float("nan") for k, v in t.items()}
            per_link["MJCF"][n], per_link["SDF"][n] = m["xml"] / n, m["sdf"] / n
            mj = f"{m['mj']:>10.2f}" if has_mj else f"{'refused':>10}"
            r_mjcf, r_sdf = m["xml"] / m["mj"], m["sdf"] / m["mj"]
            shown = f"{r_mjcf:>11.2f} {r_sdf:>10.2f}" if has_mj else f"{'-':>11} {'-':>10}"
            print(f"{n:>4} links {m['xml']:>8.2f} {m['sdf']:>8.2f} {m['urdf']:>8.2f} {mj} {m['pin']:>12.2f} {shown}")
            if has_mj:
                ratios[f"MJCF {n}"], ratios[f"SDF {n}"] = r_mjcf, r_sdf
        for name, path, tip in _real_files(folder):
            robkin.load(path, tip_link=tip), mujoco.MjModel.from_xml_path(path)
            ours, theirs = [], []
            for _ in range(rounds):
                t0 = _clock()
                robkin.load(path, tip_link=tip)
                t1 = _clock()
                mujoco.MjModel.from_xml_path(path)
                ours.append(t1 - t0)
                theirs.append(_clock() - t1)
            a, b = _median_ms(ours), _median_ms(theirs)
            print(f"{name + ' (MuJoCo MJCF)':<30} robkin {a:.2f} ms, MuJoCo {b:.2f} ms, ratio {a / b:.2f}")
    missed = [f"{k} ({r:.2f})" for k, r in ratios.items() if r > 1.0]
    print(f"goal (robkin <= MuJoCo on every chain): {'met' if not missed else 'NOT met on ' + ', '.join(missed)}")
    for kind, us in per_link.items():
        big = max(us)
        growth = us[big] / us[100]
        print(f"{kind} per link: " + ", ".join(f"{n}: {v * 1e3:.0f} us" for n, v in us.items())
              + f"; {big}/100 links: {growth:.2f}x per link ({'linear' if growth <= 1.3 else 'NOT linear'})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
