"""Long chains through the MJCF and SDF readers, and every MJCF orientation form, judged by peers.

References: MuJoCo's compiler and ``mj_kinematics`` (MJCF up to the depth its XML parser accepts),
and the chain's FK written out by hand from its numbers in NumPy (1000 links: past MuJoCo's nesting
limit, and pinocchio crashes building so deep a URDF; the hand-written product is checked against
pinocchio at 100 links). Speed is measured in ``benchmarks/bench_readers.py``, never here.

Also: an SDF model whose joints close a loop (example-robot-data's Cassie has such leg linkages) is
refused in one line; walking it as a tree never ended.
"""

from __future__ import annotations

import math
import random
import warnings

import numpy as np
import pytest

import robkin
from robkin.errors import InputError
from robkin.io.mjcf.reader import robot_from_mjcf

mujoco = pytest.importorskip("mujoco")
pin = pytest.importorskip("pinocchio")

#: FK of an n-link chain is n rigid products in each reader and in the reference: rounding grows ~n eps
#: times the reach (~0.2 m per link here); observed at n = 1000 (reach 7.3 m): 1.0e-12 (URDF and SDF
#: reads), 2.4e-12 (MJCF). 1e-12 per metre of reach still catches any wrong frame, axis or convention.
TOL_PER_METRE = 1e-12


def _chain(n: int, seed: int) -> list[tuple[list[float], list[float], list[float]]]:
    """(xyz, rpy, unit axis) of n links, at random."""
    rng = random.Random(seed)
    out = []
    for _ in range(n):
        axis = [rng.gauss(0, 1) for _ in range(3)]
        norm = math.sqrt(sum(a * a for a in axis))
        out.append(([rng.uniform(-0.2, 0.2) for _ in range(3)], [rng.uniform(-math.pi, math.pi) for _ in range(3)],
                    [a / norm for a in axis]))
    return out


def _f(v: list[float]) -> str:
    return " ".join(repr(float(x)) for x in v)


def urdf_text(n: int, seed: int) -> str:
    s = ['<robot name="chain"><link name="l0"/>']
    for i, (xyz, rpy, axis) in enumerate(_chain(n, seed)):
        s.append(f'<link name="l{i + 1}"/><joint name="j{i + 1}" type="revolute"><parent link="l{i}"/>'
                 f'<child link="l{i + 1}"/><origin xyz="{_f(xyz)}" rpy="{_f(rpy)}"/><axis xyz="{_f(axis)}"/>'
                 f'<limit lower="-3" upper="3" effort="1" velocity="1"/></joint>')
    return "".join(s + ["</robot>"])


def sdf_text(n: int, seed: int) -> str:
    """SDFormat 1.9, each joint posed relative_to its parent link, each link relative_to its joint: the
    chain of relative_to is n deep."""
    s = ['<sdf version="1.9"><model name="chain"><link name="l0"/>']
    for i, (xyz, rpy, axis) in enumerate(_chain(n, seed)):
        s.append(f'<link name="l{i + 1}"><pose relative_to="j{i + 1}"/></link><joint name="j{i + 1}" '
                 f'type="revolute"><pose relative_to="l{i}">{_f(xyz)} {_f(rpy)}</pose><parent>l{i}</parent>'
                 f'<child>l{i + 1}</child><axis><xyz>{_f(axis)}</xyz><limit><lower>-3</lower><upper>3</upper>'
                 f'</limit></axis></joint>')
    return "".join(s + ["</model></sdf>"])


def mjcf_text(n: int, seed: int) -> str:
    """Nested bodies; a URDF rpy is MJCF euler with eulerseq XYZ (fixed axes: Rz Ry Rx)."""
    s = ['<mujoco model="chain"><compiler angle="radian" eulerseq="XYZ"/><worldbody><body name="l0">']
    for i, (xyz, rpy, axis) in enumerate(_chain(n, seed)):
        s.append(f'<body name="l{i + 1}" pos="{_f(xyz)}" euler="{_f(rpy)}"><joint name="j{i + 1}" '
                 f'axis="{_f(axis)}" range="-3 3"/><geom size="0.01" mass="1"/>')
    return "".join(s + ["</body>" * (n + 1), "</worldbody></mujoco>"])


def _write(tmp_path, name: str, text: str) -> str:
    path = tmp_path / name
    path.write_text(text)
    return str(path)


def _pin_tip(urdf: str, q: np.ndarray) -> np.ndarray:
    model = pin.buildModelFromUrdf(urdf)
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    return data.oMf[model.getFrameId(f"l{len(q)}")].homogeneous


def _rot(axis: np.ndarray, angle: float) -> np.ndarray:
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def _hand_tip(n: int, seed: int, q: np.ndarray) -> np.ndarray:
    """The tip pose written out from the chain's numbers: per link, origin (Rz Ry Rx, xyz), then the
    hinge about its axis (URDF's meaning, which the MJCF and SDF texts spell their own way)."""
    T = np.eye(4)
    for (xyz, (r, p, y), axis), qi in zip(_chain(n, seed), q):
        step = np.eye(4)
        step[:3, :3] = _rot(np.array([0, 0, 1.0]), y) @ _rot(np.array([0, 1.0, 0]), p) @ _rot(np.array([1.0, 0, 0]), r) \
            @ _rot(np.array(axis), qi)
        step[:3, 3] = xyz
        T = T @ step
    return T


def test_hand_written_reference_is_pinocchios(tmp_path):
    """The reference of the long-chain test agrees with pinocchio (which cannot build 1000-deep URDFs:
    it crashes, so that test uses this reference)."""
    n = 100
    q = np.random.default_rng(1).uniform(-3, 3, n)
    ref = _pin_tip(_write(tmp_path, "c.urdf", urdf_text(n, seed=3)), q)
    np.testing.assert_allclose(_hand_tip(n, 3, q), ref, rtol=0, atol=1e-12)


@pytest.mark.parametrize("n", [250, 1000])
def test_long_sdf_and_mjcf_chains_match_the_chain(tmp_path, n):
    q = np.random.default_rng(n).uniform(-3, 3, n)
    ref = _hand_tip(n, n, q)
    reach = max(1.0, float(np.linalg.norm(ref[:3, 3])))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no frame may need projecting: every one rigid to rounding
        sdf = robkin.load(_write(tmp_path, "c.sdf", sdf_text(n, seed=n)))
        mjcf = robkin.load(_write(tmp_path, "c.xml", mjcf_text(n, seed=n)))
    for robot in (sdf, mjcf):
        assert robot.n == n and [j.name for j in robot.joints] == [f"j{i + 1}" for i in range(n)]
        np.testing.assert_allclose(robot.world @ robot.fk(q), ref, rtol=0, atol=TOL_PER_METRE * reach)
        np.testing.assert_allclose(robot.limits, [[-3.0, 3.0]] * n)


def test_mjcf_chain_matches_mujoco_kinematics(tmp_path):
    n = 250  # deep, and within MuJoCo's XML nesting limit
    path = _write(tmp_path, "c.xml", mjcf_text(n, seed=7))
    robot = robkin.load(path)
    model = mujoco.MjModel.from_xml_path(path)
    data = mujoco.MjData(model)
    for seed in range(3):
        q = np.random.default_rng(seed).uniform(-3, 3, n)
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        tip = model.body(f"l{n}").id
        T = robot.world @ robot.fk(q)
        reach = max(1.0, float(np.linalg.norm(data.xpos[tip])))
        np.testing.assert_allclose(T[:3, 3], data.xpos[tip], rtol=0, atol=TOL_PER_METRE * reach)
        np.testing.assert_allclose(T[:3, :3], data.xmat[tip].reshape(3, 3), rtol=0, atol=TOL_PER_METRE * reach)


ORIENTATIONS = ["quat", "axisangle", "xyaxes", "zaxis", "euler", "none"]


def _orientation(kind: str, rng: np.random.Generator, degrees: bool) -> str:
    v = rng.normal(size=6)
    angle = float(rng.uniform(-170, 170) if degrees else rng.uniform(-3, 3))
    return {"quat": f'quat="{_f(list(v[:4]))}"', "axisangle": f'axisangle="{_f(list(v[:3]) + [angle])}"',
            "xyaxes": f'xyaxes="{_f(list(v))}"', "zaxis": f'zaxis="{_f(list(v[:3]))}"',
            "euler": f'euler="{_f([angle, angle / 2, -angle / 3])}"', "none": ""}[kind]


@pytest.mark.parametrize("seq", ["xyz", "XYZ", "zyx", "ZYX", "xYz", "zXy"])
@pytest.mark.parametrize("degrees", [True, False])
def test_every_orientation_form_matches_mujoco(seq, degrees):
    """Each body in its own orientation form; a site with fromto at the tip; MuJoCo's xmat/xpos."""
    rng = np.random.default_rng(sum(map(ord, seq)) + degrees)
    bodies = "".join(f'<body name="b{k}" pos="{_f(list(rng.uniform(-1, 1, 3)))}" {_orientation(kind, rng, degrees)}>'
                     f'<joint name="j{k}" axis="{_f(list(rng.normal(size=3)))}" ref="{rng.uniform(-1, 1)}" '
                     f'pos="{_f(list(rng.uniform(-0.1, 0.1, 3)))}"/><geom size="0.01" mass="1"/>'
                     for k, kind in enumerate(ORIENTATIONS))
    fromto = _f(list(rng.uniform(-1, 1, 6)))
    text = (f'<mujoco><compiler angle="{"degree" if degrees else "radian"}" eulerseq="{seq}"/><worldbody>{bodies}'
            f'<site name="tip" type="capsule" fromto="{fromto}" size="0.01"/>{"</body>" * len(ORIENTATIONS)}</worldbody></mujoco>')
    robot = robot_from_mjcf(text, tip_link="tip")
    model = mujoco.MjModel.from_xml_string(text)
    data = mujoco.MjData(model)
    q = rng.uniform(-2, 2, len(ORIENTATIONS))
    data.qpos[:] = q
    mujoco.mj_kinematics(model, data)
    T = robot.world @ robot.fk(q)
    site = model.site("tip").id
    # MuJoCo computes in float64 too, in its own order: observed ~1e-15; six bodies deep
    np.testing.assert_allclose(T[:3, 3], data.site_xpos[site], rtol=0, atol=1e-12)
    np.testing.assert_allclose(T[:3, :3], data.site_xmat[site].reshape(3, 3), rtol=0, atol=1e-12)


def test_sdf_closed_loop_is_refused_naming_link_and_joints(tmp_path):
    # a four-bar linkage: link c hangs from b (joint jc) and from d (joint loop)
    links = "".join(f'<link name="{x}"/>' for x in "abcd")
    joints = "".join(f'<joint name="{n}" type="revolute"><parent>{p}</parent><child>{c}</child><axis><xyz>0 0 1</xyz>'
                     f'</axis></joint>' for n, p, c in (("jb", "a", "b"), ("jc", "b", "c"), ("jd", "a", "d"),
                                                        ("loop", "d", "c")))
    text = f'<sdf version="1.9"><model name="m">{links}{joints}</model></sdf>'
    with pytest.raises(InputError, match=r"link 'c' is the child of two joints, 'jc' and 'loop'.*kinematic loop"):
        robkin.load(_write(tmp_path, "loop.sdf", text))


def test_sdf_joint_cycle_is_refused(tmp_path):
    links = "".join(f'<link name="{x}"/>' for x in "abc")
    joints = "".join(f'<joint name="{n}" type="fixed"><parent>{p}</parent><child>{c}</child></joint>'
                     for n, p, c in (("jb", "b", "c"), ("jc", "c", "b")))
    text = f'<sdf version="1.9"><model name="m">{links}{joints}</model></sdf>'
    with pytest.raises(InputError, match=r"the joints form a cycle through link\(s\) b, c"):
        robkin.load(_write(tmp_path, "cycle.sdf", text))
