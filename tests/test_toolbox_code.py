"""``robkin convert --to matlab | eaik | opw`` against independent peers, and generated code as data.

- MATLAB: GNU Octave runs the scripts (one process for all) and its ``robot_fk`` equals robkin's FK on
  real arms, the flipped prismatic joints of the seed SCARA and random DH/MDH robots.
- EAIK: the solver built from the ``--to eaik`` output (Python file and JSON) solves targets that
  robkin's FK makes, every exact solution reaching the target to 1e-9.
- OPW: arms built from published OPW parameters (KUKA KR6 R700, ABB IRB 2400, Fanuc R-2000iB/200R) with
  a forward kinematics written here from the paper's equations: robkin recovers the seven lengths and
  its offsets, signs, base and tool make that forward kinematics reproduce robkin's FK; arms outside the
  class are refused with the condition they fail.
- Names that try to be code come out as strings, in Python and in Octave.
"""

from __future__ import annotations

import ast
import json
import math
import os
import runpy
import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

import robkin
from robkin.cli import main
from robkin.errors import InputError
from robkin.io.toolboxes.code_literals import m_float, m_str, py_float, py_str
from robkin.io.toolboxes.eaik import eaik_json, eaik_python
from robkin.io.toolboxes.matlab import matlab_from_robot
from robkin.io.toolboxes.opw import opw_document
from robkin.representations.opw import opw_from_robot
from robkin.io.toolboxes.rtb import rtb_from_robot
from robkin.representations.dh import DHTable
from robkin.representations.mdh import MDHTable
from robkin.robot import Joint, Robot
from strategies import robots
from test_properties import SCALE as PROPERTY_SCALE
from test_urdf import robot_file

OCTAVE = shutil.which("octave")
needs_octave = pytest.mark.skipif(OCTAVE is None, reason="GNU Octave is not installed (apt-get install octave)")
EXAMPLES = Path(robkin.__file__).parent / "examples"

#: FK agreement, relative to the robot's size: the script evaluates the same table in another order
#: (observed ~1e-15); 1e-9 is the promise of every robkin conversion.
FK_TOL = 1e-9


def _real(rel: str, tip: str, base: str | None = None) -> Robot:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return robkin.load(robot_file(rel), base_link=base, tip_link=tip)


def _random_table(rng: np.random.Generator, kind: type, n: int) -> Robot:
    """A random DH or MDH robot with random joint types, flips and limits, base and tool."""
    rows = np.column_stack([rng.uniform(-1, 1, n), rng.uniform(-1, 1, n), rng.uniform(-np.pi, np.pi, (n, 2))])
    joints = tuple(Joint(f"j{i}", "prismatic" if rng.random() < 0.3 else "revolute", flip=bool(rng.random() < 0.4),
                         lower=-1.5 if rng.random() < 0.5 else None, upper=1.5) for i in range(n))
    from robkin import se3

    base = se3.homogeneous(se3.matrix_from_rpy(rng.uniform(-1, 1, 3)), rng.uniform(-1, 1, 3))
    tool = se3.homogeneous(se3.matrix_from_rpy(rng.uniform(-1, 1, 3)), rng.uniform(-1, 1, 3))
    return kind(rows, joints, base=base, tool=tool).to_robot()


# -------------------------------------------------------------------------------------------- MATLAB
@needs_octave
def test_octave_runs_the_matlab_scripts_and_their_fk_is_robkins(tmp_path):
    rng = np.random.default_rng(7)
    robots = [_real("ur_description/urdf/ur5_robot.urdf", "tool0"),
              _real("panda_description/urdf/panda.urdf", "panda_leftfinger", "panda_link0"),
              _real("kinova_description/robots/kinova.urdf", "j2s6s200_end_effector"),
              robkin.load(EXAMPLES / "scara.yaml")]
    robots += [_random_table(rng, kind, int(rng.integers(1, 8))) for kind in (DHTable, MDHTable) * 4]
    script, expected = [], []
    for k, robot in enumerate(robots):
        Q = rng.uniform(-2, 2, (3, robot.n))
        for convention in ("dh", "mdh"):
            f = tmp_path / f"r{k}{convention}.m"
            f.write_text(matlab_from_robot(robot, convention))
            script.append(f"clear robot robot_fk; source('{f}');")
            script.append(f"assert(strcmp(robot.convention, '{convention}'));")
            script.append(f"assert(isequal(size(robot.dh), [{robot.n} 4]) && isequal(size(robot.qlim), [{robot.n} 2]));")
            rows = robot.n if robot.bodies.inertials else 0    # mass properties: one row per link, or none
            script.append(f"assert(isequal(size(robot.mass), [{rows} 1]) && isequal(size(robot.com), [{rows} 3]) "
                          f"&& isequal(size(robot.inertia), [{rows} 6]));")
            for q in Q:
                script.append(f"fprintf('%.17g\\n', robot_fk([{' '.join(repr(float(x)) for x in q)}]));")
                expected.append((robot.fk(q).T.ravel(), robot.scale))   # Octave prints column by column
    (tmp_path / "run.m").write_text("\n".join(script) + "\n")
    proc = subprocess.run([OCTAVE, "--no-gui", "--no-window-system", "--quiet", "--norc", str(tmp_path / "run.m")],
                          capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr[-2000:]
    values = np.array(proc.stdout.split(), dtype=float).reshape(-1, 16)
    assert len(values) == len(expected)
    for got, (want, scale) in zip(values, expected):
        assert np.abs(got - want).max() <= FK_TOL * max(scale, 1.0)


def test_matlab_script_holds_the_mass_properties_and_limits():
    robot = _real("ur_description/urdf/ur5_robot.urdf", "tool0")
    text = matlab_from_robot(robot)
    assert "robot.mass = [3.7, 8.393, 2.275, 1.219, 1.219, 0.1879]';" in text   # the URDF's link masses
    assert "robot.qlim = [-6.28318530718, 6.28318530718;" in text
    bare = matlab_from_robot(robkin.load(EXAMPLES / "rrpr.yaml"))
    assert "robot.mass = zeros(0, 1);" in bare and "no mass properties" in bare


# ---------------------------------------------------------------------------------------------- EAIK
def test_eaik_solves_targets_from_the_written_parameters(tmp_path):
    eaik = pytest.importorskip("eaik.pybindings.EAIK")
    rng = np.random.default_rng(3)
    arms = [_real("ur_description/urdf/ur5_robot.urdf", "tool0"), _real("ur_description/urdf/ur10_robot.urdf", "tool0"),
            _real("kinova_description/robots/kinova.urdf", "j2s6s200_end_effector")]
    solved = 0
    for k, robot in enumerate(arms):
        (tmp_path / f"e{k}.py").write_text(eaik_python(robot))
        solver = runpy.run_path(str(tmp_path / f"e{k}.py"))["eaik_robot"]()
        doc = json.loads(eaik_json(robot))
        from_json = eaik.Robot(np.array(doc["H"]).T, np.array(doc["P"]).T, np.array(doc["R6T"]), [], True)
        for q in rng.uniform(-np.pi, np.pi, (20, 6)):
            T = robot.fk(q)
            for s in (solver, from_json):
                sol = s.calculate_IK(T)
                exact = np.asarray(sol.Q).reshape(-1, 6)[~np.asarray(sol.is_LS, bool)]
                assert len(exact) >= 1
                for p in exact:
                    assert np.abs(robot.fk(p) - T).max() <= 1e-9 * max(robot.scale, 1.0)
                solved += len(exact)
    assert solved >= 3 * 20 * 2 * 2


def test_eaik_solves_the_panda_with_joint_4_locked(tmp_path):
    """A 7-joint arm: EAIK solves the Panda in closed form with joint 4 held (``fixed_axes``)."""
    pytest.importorskip("eaik.pybindings.EAIK")
    robot = _real("panda_description/urdf/panda.urdf", "panda_hand_tcp")
    (tmp_path / "panda.py").write_text(eaik_python(robot))
    eaik_robot = runpy.run_path(str(tmp_path / "panda.py"))["eaik_robot"]
    rng = np.random.default_rng(4)
    for q in robot.random_q(10, rng=rng):
        solver = eaik_robot(fixed_axes=[(3, float(q[3]))])
        T = robot.fk(q)
        sol = solver.calculate_IK(T)
        exact = np.asarray(sol.Q).reshape(-1, 7)[~np.asarray(sol.is_LS, bool)]
        assert len(exact) >= 1 and np.allclose(exact[:, 3], q[3])
        for p in exact:
            assert np.abs(robot.fk(p) - T).max() <= 1e-9


def hp_forward_kinematics(H: np.ndarray, P: np.ndarray, R6T: np.ndarray, q: np.ndarray) -> np.ndarray:
    """The tool pose of the H-P description EAIK and the subproblem literature use, written here:
    R_0i = R_0(i-1) rot(h_i, q_i), p = p_01 + R_01 p_12 + ... + R_0n p_nT, R = R_0n R6T."""
    R, p = np.eye(3), P[0].copy()
    for h, qi, off in zip(H, q, P[1:]):
        K = np.array([[0, -h[2], h[1]], [h[2], 0, -h[0]], [-h[1], h[0], 0]])
        R = R @ (np.eye(3) + math.sin(qi) * K + (1 - math.cos(qi)) * K @ K)   # Rodrigues: rotation about h
        p = p + R @ off
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R @ R6T, p
    return T


@settings(max_examples=int(25 * PROPERTY_SCALE), deadline=None)
@given(robots(min_joints=1, max_joints=8, units=(1.0,)), st.data())
def test_eaik_parameters_of_random_robots_give_robkins_fk(robot, data):
    """The H-P forward kinematics of the written H, P, R6T equals robkin's FK on any revolute chain. (Not
    EAIK's own fwdkin here: EAIK 1.2 crashes the process building some chains, e.g. four parallel axes;
    the real arms above are built and solved by EAIK itself.)"""
    from dataclasses import replace

    robot = robot.replace(joints=tuple(replace(j, type="revolute") for j in robot.joints))
    doc = json.loads(eaik_json(robot))
    q = np.array(data.draw(st.lists(st.floats(-np.pi, np.pi), min_size=robot.n, max_size=robot.n)))
    T = hp_forward_kinematics(np.array(doc["H"]), np.array(doc["P"]), np.array(doc["R6T"]), q)
    # 1e-10 of the robot's size: the same rotations multiplied in another order (observed ~1e-15)
    assert np.abs(T - robot.fk(q)).max() <= 1e-10 * max(robot.scale, 1.0)


def test_eaik_refuses_a_prismatic_joint():
    with pytest.raises(InputError, match="joint 'P1' is prismatic; EAIK takes revolute joints only"):
        eaik_json(robkin.load(EXAMPLES / "scara.yaml"))


# ----------------------------------------------------------------------------------------------- OPW
def opw_paper_fk(g: dict, q: np.ndarray) -> np.ndarray:
    """The OPW forward kinematics from Brandstoetter, Angerer, Hofbaur (2014), written here from the
    paper's equations (wrist centre from the planar 2R arm with the a1, b, c1 offsets; orientation
    R_0c R_ce), independent of robkin's code."""
    q1, q2, q3, q4, q5, q6 = q
    psi3 = math.atan2(g["a2"], g["c3"])
    k = math.hypot(g["a2"], g["c3"])
    cx1 = g["c2"] * math.sin(q2) + k * math.sin(q2 + q3 + psi3) + g["a1"]
    cy1 = g["b"]
    cz1 = g["c2"] * math.cos(q2) + k * math.cos(q2 + q3 + psi3)
    c = np.array([cx1 * math.cos(q1) - cy1 * math.sin(q1), cx1 * math.sin(q1) + cy1 * math.cos(q1), cz1 + g["c1"]])
    s1, c1_, s23, c23 = math.sin(q1), math.cos(q1), math.sin(q2 + q3), math.cos(q2 + q3)
    r0c = np.array([[c1_ * c23, -s1, c1_ * s23], [s1 * c23, c1_, s1 * s23], [-s23, 0.0, c23]])
    s4, c4, s5, c5, s6, c6 = (f(a) for a in (q4, q5, q6) for f in (math.sin, math.cos))
    rce = np.array([[c4 * c5 * c6 - s4 * s6, -c4 * c5 * s6 - s4 * c6, c4 * s5],
                    [s4 * c5 * c6 + c4 * s6, -s4 * c5 * s6 + c4 * c6, s4 * s5],
                    [-s5 * c6, s5 * s6, c5]])
    R = r0c @ rce
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, c + g["c4"] * R[:, 2]
    return T


def _opw_axes(g: dict, qm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The six joint axes (directions, points) of the OPW model at model joint values qm, from the
    paper's geometry (joint 1 about z, 2 and 3 about the rotated y, 4 and 6 about the forearm's and the
    flange's z, 5 about the wrist's y), for building a robkin robot of that model."""
    q1, q2, q3, q4, q5, _ = qm
    Rz = lambda a: np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])  # noqa: E731
    Ry = lambda a: np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]])  # noqa: E731
    R1 = Rz(q1)
    j2 = R1 @ np.array([g["a1"], 0, 0]) + [0, 0, g["c1"]]
    j3 = j2 + R1 @ (g["c2"] * np.array([math.sin(q2), 0, math.cos(q2)]))
    wrist = opw_paper_fk({**g, "c4": 0.0}, qm)[:3, 3]
    Rc = R1 @ Ry(q2 + q3)
    dirs = [np.array([0, 0, 1.0]), R1[:, 1], R1[:, 1], Rc[:, 2], (Rc @ Rz(q4))[:, 1], (Rc @ Rz(q4) @ Ry(q5))[:, 2]]
    points = [np.zeros(3), j2, j3, wrist, wrist, wrist]
    return np.array(dirs), np.array(points)


def opw_robot(g: dict, offsets, signs, base=np.eye(4), tool=np.eye(4)) -> Robot:
    """A robkin robot (GJD frames) whose joint values q relate to the model's as opw_kinematics says:
    q_model = sign * q - offset; FK(q) = base @ model(q_model) @ tool."""
    qm = -np.asarray(offsets, float)
    dirs, points = _opw_axes(g, qm)
    frames = np.zeros((7, 4, 4))
    for i, (z, p) in enumerate(zip(dirs * np.asarray(signs)[:, None], points)):
        x = np.cross(z, [0.3, 0.5, 0.8])
        x /= np.linalg.norm(x)
        frames[i, :3, :3] = np.column_stack([x, np.cross(z, x), z])
        frames[i, :3, 3] = p
        frames[i] = base @ frames[i]
        frames[i, 3, 3] = 1.0
    frames[6] = base @ opw_paper_fk(g, qm) @ tool
    return Robot(frames, tuple(Joint(f"a{i + 1}") for i in range(6)))


#: Published OPW parameters (opw_kinematics' examples, from the manufacturers' data sheets)
PUBLISHED = {
    "KUKA KR6 R700 sixx": ({"a1": 0.025, "a2": -0.035, "b": 0.0, "c1": 0.400, "c2": 0.315, "c3": 0.365, "c4": 0.080},
                           [0, -np.pi / 2, 0, 0, 0, np.pi], [-1, 1, 1, -1, 1, -1]),
    "ABB IRB 2400/10": ({"a1": 0.100, "a2": -0.135, "b": 0.0, "c1": 0.615, "c2": 0.705, "c3": 0.755, "c4": 0.085},
                        [0, 0, -np.pi / 2, 0, 0, 0], [1, 1, 1, 1, 1, 1]),
    "Fanuc R-2000iB/200R": ({"a1": 0.720, "a2": -0.225, "b": 0.0, "c1": 0.600, "c2": 1.075, "c3": 1.280, "c4": 0.235},
                            [0, 0, -np.pi / 2, 0, 0, 0], [1, 1, 1, 1, 1, 1]),
    "lateral offset b": ({"a1": 0.15, "a2": 0.05, "b": -0.12, "c1": 0.5, "c2": 0.6, "c3": 0.7, "c4": 0.1},
                         [0.3, -0.2, 0.4, 1.0, -0.5, 2.0], [1, -1, -1, 1, -1, 1]),
}


def _model_of(doc: dict) -> tuple[dict, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    g = doc["opw_kinematics_geometric_parameters"]
    return (g, np.array(doc["opw_kinematics_joint_offsets"]), np.array(doc["opw_kinematics_joint_sign_corrections"]),
            np.array(doc["base"]), np.array(doc["tool"]))


@pytest.mark.parametrize("name", PUBLISHED)
def test_opw_parameters_reproduce_fk(name):
    g, offsets, signs = PUBLISHED[name]
    # the model's check: the robot built from the paper's geometry has the paper's forward kinematics
    robot = opw_robot(g, offsets, signs)
    rng = np.random.default_rng(5)
    Q = rng.uniform(-np.pi, np.pi, (30, 6))
    for q in Q[:5]:
        assert np.abs(robot.fk(q) - opw_paper_fk(g, signs * q - offsets)).max() <= 1e-12
    # robkin's parameters: the same seven lengths, and offsets, signs, base and tool that reproduce FK
    doc = yaml.safe_load(robkin.io.documents.reader.dump(opw_document(robot)))
    got, o, s, base, tool = _model_of(doc)
    assert got == pytest.approx(g, abs=1e-12)
    assert np.allclose(base, np.eye(4), atol=0) and np.allclose(tool, np.eye(4), atol=1e-15)
    for q in Q:
        assert np.abs(base @ opw_paper_fk(got, s * q - o) @ tool - robot.fk(q)).max() <= 1e-12
    # the published offsets and signs describe the same arm (up to a full turn)
    for q in Q[:5]:
        assert np.abs(opw_paper_fk(got, s * q - o) - opw_paper_fk(g, np.asarray(signs) * q - offsets)).max() <= 1e-12


def test_opw_with_a_base_and_tool_of_the_robots_own():
    from robkin import se3

    g, offsets, signs = PUBLISHED["KUKA KR6 R700 sixx"]
    base = se3.homogeneous(se3.matrix_from_rpy([0.2, -0.1, 0.7]), [0.1, -0.3, 0.2])
    tool = se3.homogeneous(se3.matrix_from_rpy([0.5, 0.4, -1.0]), [0.01, 0.02, 0.15])
    robot = opw_robot(g, offsets, signs, base, tool)
    got, o, s, B, E = _model_of(opw_document(robot))
    assert got["c4"] >= 0 and got["c3"] >= 0
    assert got["c2"] == pytest.approx(g["c2"], abs=1e-12) and got["a1"] == pytest.approx(g["a1"], abs=1e-12)
    for q in np.random.default_rng(6).uniform(-np.pi, np.pi, (30, 6)):
        assert np.abs(B @ opw_paper_fk(got, s * q - o) @ E - robot.fk(q)).max() <= 1e-12


def test_opw_from_a_dh_table_of_the_kr6():
    """The KR6 R700 as the DH table its data sheet implies: robkin finds the published lengths."""
    rows = [[0.025, 0.4, -np.pi / 2, 0], [0.315, 0, 0, -np.pi / 2], [0.035, 0, -np.pi / 2, 0],
            [0, 0.365, np.pi / 2, 0], [0, 0, -np.pi / 2, 0], [0, 0.08, 0, 0]]
    robot = DHTable(np.array(rows), tuple(Joint(f"a{i}") for i in range(1, 7))).to_robot()
    p = opw_from_robot(robot)
    assert [p.a1, p.a2, p.b, p.c1, p.c2, p.c3, p.c4] == pytest.approx([0.025, -0.035, 0, 0.4, 0.315, 0.365, 0.08],
                                                                      abs=1e-12)
    for q in np.random.default_rng(8).uniform(-np.pi, np.pi, (20, 6)):
        g = {k: getattr(p, k) for k in ("a1", "a2", "b", "c1", "c2", "c3", "c4")}
        T = p.base @ opw_paper_fk(g, np.asarray(p.sign_corrections) * q - np.asarray(p.offsets)) @ p.tool
        assert np.abs(T - robot.fk(q)).max() <= 1e-12


@settings(max_examples=int(25 * PROPERTY_SCALE), deadline=None)
@given(st.data())
def test_opw_of_random_arms_of_the_class_reproduces_fk(data):
    """Random OPW geometry (lengths of either sign, c2 > 0), offsets, signs, robot base and tool: robkin's
    parameters with their offsets, signs, base and tool reproduce the robot's FK through the paper's FK."""
    from robkin import se3

    length = st.floats(-1.0, 1.0, allow_nan=False, allow_subnormal=False)
    g = {k: data.draw(length) for k in ("a1", "a2", "b", "c1", "c3", "c4")}
    g["c2"] = data.draw(st.floats(0.05, 1.0))
    offsets = data.draw(st.lists(st.floats(-np.pi, np.pi), min_size=6, max_size=6))
    signs = data.draw(st.lists(st.sampled_from([-1, 1]), min_size=6, max_size=6))
    pose = lambda: se3.homogeneous(se3.matrix_from_rpy(data.draw(st.lists(st.floats(-np.pi, np.pi), min_size=3,  # noqa: E731
                                                                                max_size=3))),
                                   data.draw(st.lists(st.floats(-1, 1), min_size=3, max_size=3)))
    robot = opw_robot(g, offsets, signs, pose(), pose())
    with warnings.catch_warnings():
        warnings.simplefilter("error")        # an exact arm of the class: no FK error to report
        got, o, s, B, E = _model_of(opw_document(robot))
    assert got["c2"] == pytest.approx(g["c2"], abs=1e-9) and got["c3"] >= 0 and got["c4"] >= 0
    for q in np.random.default_rng(0).uniform(-np.pi, np.pi, (5, 6)):
        assert np.abs(B @ opw_paper_fk(got, s * q - o) @ E - robot.fk(q)).max() <= 1e-9 * max(robot.scale, 1.0)


@pytest.mark.parametrize("make, why", [
    (lambda: _real("ur_description/urdf/ur5_robot.urdf", "tool0"), "joints 3 and 4 are not perpendicular"),
    (lambda: _real("panda_description/urdf/panda.urdf", "panda_hand_tcp"), "the robot has 7 joints"),
    (lambda: robkin.load(EXAMPLES / "scara.yaml"), "the robot has 5 joints"),
    (lambda: opw_robot(PUBLISHED["ABB IRB 2400/10"][0], [0, 0, 0, 0, 0.1, 0], [1] * 6).replace(
        frames=np.concatenate([opw_robot(PUBLISHED["ABB IRB 2400/10"][0], [0] * 6, [1] * 6).frames[:5],
                               opw_robot(PUBLISHED["ABB IRB 2400/10"][0], [0] * 6, [1] * 6).frames[5:] +
                               np.array([[0, 0, 0, 0.01]] * 3 + [[0, 0, 0, 0]])])),
     "joints 4, 5 and 6 do not meet in one point"),
])
def test_opw_refuses_arms_outside_the_class(make, why):
    with pytest.raises(InputError, match=why) as exc:
        opw_from_robot(make())
    assert "\n" not in str(exc.value)


# ------------------------------------------------------------------------------- generated code is data
HOSTILE = ['x"); import os; os.system("touch PWNED") #', "y'); system('touch PWNED'); %", "z\\'); os.remove('f') #",
           '"""; import os; os.system("touch PWNED"); """ %{',
           "w]; robot=0; disp(1) % \" '''", "\u00e9t\u00e9 \U0001f916 joint", "{{NAME}} %s {0} $(touch PWNED)"]


def _hostile_robot() -> Robot:
    table = DHTable(np.array([[0.1, 0.2, np.pi / 2, 0], [0.3, 0, 0, 0.1], [0, 0.1, -np.pi / 2, 0], [0.2, 0, 0, 0],
                              [0, 0.2, np.pi / 2, 0], [0, 0, -np.pi / 2, 0], [0, 0.1, 0, 0]]),
                    tuple(Joint(name) for name in HOSTILE))
    return table.to_robot(name=HOSTILE[3])   # a name that would end a docstring


def _python_module_is_plain(text: str) -> ast.Module:
    """Only imports, assignments, function definitions and the docstring at the top level; every call
    is to a known constructor."""
    tree = ast.parse(text)
    for node in tree.body:
        assert isinstance(node, (ast.Import, ast.ImportFrom, ast.Assign, ast.FunctionDef, ast.Expr)), ast.dump(node)
        if isinstance(node, ast.Expr):
            assert isinstance(node.value, ast.Constant)
    allowed = {"RevoluteDH", "RevoluteMDH", "PrismaticDH", "PrismaticMDH", "DHRobot", "SE3", "array", "float",
               "Robot", "list"}
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            f = node.func
            assert (f.attr if isinstance(f, ast.Attribute) else f.id) in allowed, ast.dump(f)
    return tree


def _literal(tree: ast.Module, name: str):
    for node in tree.body:
        if isinstance(node, ast.Assign) and getattr(node.targets[0], "id", None) == name:
            return ast.literal_eval(node.value)
    raise AssertionError(name)


@pytest.mark.parametrize("write", [lambda r: rtb_from_robot(r), lambda r: rtb_from_robot(r, "mdh"), eaik_python])
def test_hostile_names_are_python_strings(write, tmp_path):
    robot = _hostile_robot()
    text = write(robot)
    assert text.isascii()
    tree = _python_module_is_plain(text)
    assert _literal(tree, "JOINT_NAMES") == HOSTILE
    assert _literal(tree, "NAME") == HOSTILE[3]
    for name in HOSTILE:     # never outside a literal: not in a comment, not in a docstring
        assert py_str(name) in text and text.count(name) <= text.count(py_str(name))


def test_hostile_names_run_as_data(tmp_path):
    robot = _hostile_robot()
    f = tmp_path / "e.py"
    f.write_text(eaik_python(robot))
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        ns = runpy.run_path(str(f))
    finally:
        os.chdir(cwd)
    assert ns["JOINT_NAMES"] == HOSTILE and not (tmp_path / "PWNED").exists()
    assert json.loads(eaik_json(robot))["joint_names"] == HOSTILE
    kr6 = opw_robot(*PUBLISHED["KUKA KR6 R700 sixx"]).replace(joints=tuple(Joint(n) for n in HOSTILE[:6]),
                                                              name=HOSTILE[3])
    doc = yaml.safe_load(robkin.io.documents.reader.dump(opw_document(kr6)))
    assert doc["joint_names"] == HOSTILE[:6] and doc["name"] == HOSTILE[3]


@needs_octave
def test_hostile_names_are_octave_strings(tmp_path):
    robot = _hostile_robot()
    f = tmp_path / "h.m"
    text = matlab_from_robot(robot)
    assert text.isascii()
    f.write_text(text)
    ascii_names = [n for n in HOSTILE if n.isascii()]
    checks = "".join(f"assert(strcmp(robot.joint_names{{{HOSTILE.index(n) + 1}}}, {m_str(n)}));" for n in ascii_names)
    proc = subprocess.run([OCTAVE, "--no-gui", "--no-window-system", "--quiet", "--norc", "--eval",
                           f"source('{f}'); {checks} assert(strcmp(robot.name, {m_str(HOSTILE[3])})); "
                           f"fprintf('%d\\n', double(robot.joint_names{{1}})); disp(numel(robot.joint_names));"],
                          capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    numbers = proc.stdout.split()
    assert [int(c) for c in numbers[:-1]] == [ord(c) for c in HOSTILE[0]]
    assert numbers[-1] == str(len(HOSTILE))
    assert not (tmp_path / "PWNED").exists()


def test_literals_round_trip_and_refuse_non_finite_numbers():
    for s in HOSTILE + ["", "'", "\\", "a\u202eb"]:
        assert ast.literal_eval(py_str(s)) == s and py_str(s).isascii()
    for x in (0.1, -1e-300, 5e-324, 1.7976931348623157e308, -0.0, 3.0):
        assert float(ast.literal_eval(py_float(x, "x"))) == x
    for bad in (float("nan"), float("inf"), -float("inf")):
        with pytest.raises(InputError, match="m: .* is not a finite number"):
            py_float(bad, "m")
        with pytest.raises(InputError, match="I: .* is not a finite number"):
            m_float(bad, "I")
    assert m_float(float("inf"), "upper", allow_inf=True) == "Inf"
    assert m_str("it's") == "'it''s'" and m_str("\u00e9") == "char([233])" and m_str("") == "''"


# ---------------------------------------------------------------------------------------------- CLI
def test_cli_writes_each_code_format(tmp_path, capsys):
    ur5 = robot_file("ur_description/urdf/ur5_robot.urdf")
    for fmt, name in (("rtb", "a.py"), ("matlab", "a.m"), ("eaik", "a.json"), ("eaik", "b.py")):
        assert main(["convert", ur5, "--tip-link", "tool0", "--to", fmt, "-o", str(tmp_path / name)]) == 0
    assert main(["convert", ur5, "--tip-link", "tool0", "--to", "rtb", "--convention", "mdh",
                 "-o", str(tmp_path / "m.py")]) == 0
    assert "RevoluteMDH(" in (tmp_path / "m.py").read_text()
    assert "RevoluteDH(" in (tmp_path / "a.py").read_text()
    assert json.loads((tmp_path / "a.json").read_text())["H"][0] == [0.0, 0.0, 1.0]
    capsys.readouterr()
    kr6 = EXAMPLES / "kr6_r700.yaml"     # the bundled KR6 R700: its DH table, KUKA's joint directions
    assert main(["convert", str(kr6), "--to", "opw"]) == 0
    doc = yaml.safe_load(capsys.readouterr().out)
    g, offsets, signs = PUBLISHED["KUKA KR6 R700 sixx"]
    assert doc["opw_kinematics_geometric_parameters"] == g   # the data sheet's decimals, no rounding noise
    assert doc["opw_kinematics_joint_offsets"] == pytest.approx(offsets, abs=1e-12)   # the published ones
    assert doc["opw_kinematics_joint_sign_corrections"] == signs
    assert main(["convert", str(kr6), "--to", "opw", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["opw_kinematics_joint_sign_corrections"]
    assert main(["convert", str(kr6), "--to", "opw", "--exact"]) == 0   # every digit of the computation
    exact = yaml.safe_load(capsys.readouterr().out)["opw_kinematics_geometric_parameters"]
    assert exact == {k: float(v) for k, v in opw_document(robkin.load(kr6))["opw_kinematics_geometric_parameters"].items()}
    assert exact == pytest.approx(g, abs=1e-12)


@pytest.mark.parametrize("argv, message", [
    (["--to", "opw", "-o", "{d}/o.yaml"], "--to opw: joints 3 and 4 are not perpendicular"),
    (["--to", "dh", "--convention", "mdh"], "--convention mdh: applies to --to rtb and --to matlab"),
    (["--to", "rtb", "--json"], "--json: --to rtb writes Python or MATLAB code"),
    (["--to", "rtb", "-o", "{d}/robot.txt"], "--to rtb writes a .py file"),
    (["--to", "matlab", "-o", "{d}/robot.py"], "--to matlab writes a .m file"),
    (["--to", "matlab", "--degrees"], "--degrees: --to matlab writes angles in radians"),
])
def test_cli_refuses_with_one_line_and_writes_nothing(tmp_path, capsys, argv, message):
    ur5 = robot_file("ur_description/urdf/ur5_robot.urdf")
    status = main(["convert", ur5, "--tip-link", "tool0", *[a.replace("{d}", str(tmp_path)) for a in argv]])
    err = capsys.readouterr().err
    assert status == 2 and message in err and len(err.strip().splitlines()) == 1, err
    assert list(tmp_path.iterdir()) == []


def test_a_batch_names_the_input_that_cannot_be_written_and_writes_nothing(tmp_path, capsys):
    status = main(["convert", str(EXAMPLES / "kr6_r700.yaml"), str(EXAMPLES / "scara.yaml"), "--to", "opw",
                   "-o", str(tmp_path / "out") + "/"])
    err = capsys.readouterr().err
    assert status == 2 and "scara.yaml: --to opw: the robot has 5 joints" in err and len(err.splitlines()) == 1
    assert list(tmp_path.iterdir()) == []
