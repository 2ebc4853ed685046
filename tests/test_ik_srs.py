"""Closed-form IK of SRS arms by arm angle (``ik(T, arm_angle=psi)``, ``kinematics.srs``): KUKA iiwa 14 from its
URDF and a Kinova Gen3 from its published DH table with the 11.8 mm / 12.8 mm shoulder and elbow offsets
removed (the real Gen3 is not SRS: it is refused, naming the offset). Every solution is re-checked by
pinocchio's forward kinematics (the iiwa from the original URDF file, the Gen3 built joint by joint from
the DH rows with pinocchio's API), the limits and the arm angle it was asked for."""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import ik_arms as arms
import robkin
from robkin.cli import main
from robkin.errors import InputError
from robkin.kinematics.srs import BRANCHES, feasible_arm_angles
from robkin.kinematics.srs_geometry import arm_angle_of, branch_of
from robkin.robot import Joint

pin = pytest.importorskip("pinocchio")

#: pinocchio's FK of a solution must reach the target to this (m and 4x4 entries): closed-form answers are
#: ~1e-13 off, pinocchio's rounding over a 1.3 m chain ~1e-15
CHECK = 1e-9
IIWA_URDF = arms.os.path.join(arms.DATA, "iiwa14.urdf")

PI = np.pi
GEN3_D = [-0.2848, 0.0, -0.4208, 0.0, -0.3143, 0.0, -0.1674]     # user guide DH, lateral offsets zeroed
GEN3_ALPHA = [PI / 2] * 6 + [PI]
GEN3_THETA = [0.0] + [PI] * 6
GEN3_LIM = [None, 2.2497, None, 2.5796, None, 2.0996, None]
FLIP = np.diag([1.0, -1.0, -1.0, 1.0])                          # the user guide's base: half a turn about x


def gen3_ideal() -> robkin.Robot:
    joints = tuple(Joint(f"joint_{i + 1}", "revolute", None if x is None else -x, x) for i, x in enumerate(GEN3_LIM))
    rows = np.column_stack([np.zeros(7), GEN3_D, GEN3_ALPHA, GEN3_THETA])
    robot = robkin.DHTable(rows, joints).to_robot(name="gen3-ideal")
    return robot.replace(frames=FLIP @ np.array(robot.frames))


def _dh(d: float, alpha: float, theta: float) -> "pin.SE3":
    Rz = pin.utils.rotate("z", theta)
    Rx = pin.utils.rotate("x", alpha)
    return pin.SE3(Rz, np.zeros(3)) * pin.SE3(np.eye(3), np.array([0, 0, d])) * pin.SE3(Rx, np.zeros(3))


def gen3_pin():
    """pinocchio's Gen3 (ideal) from the DH rows: joint i+1 placed by row i's transform after joint i."""
    model = pin.Model()
    parent, place = 0, pin.SE3(FLIP[:3, :3], np.zeros(3))
    for i in range(7):
        parent = model.addJoint(parent, pin.JointModelRZ(), place, f"joint_{i + 1}")
        place = _dh(GEN3_D[i], GEN3_ALPHA[i], GEN3_THETA[i])
    model.addFrame(pin.Frame("tool", parent, 0, place, pin.FrameType.OP_FRAME))
    return model, "tool"


def iiwa_pin():
    model = pin.buildModelFromUrdf(IIWA_URDF)
    return model, model.frames[len(model.frames) - 1].name


ARMS = {"iiwa": (arms.iiwa, iiwa_pin), "gen3-ideal": (gen3_ideal, gen3_pin)}


def pin_fk(model, tip: str, robot: robkin.Robot, Q: np.ndarray) -> np.ndarray:
    data = model.createData()
    out = []
    for q in Q:
        qp = pin.neutral(model)
        for joint, value in zip(robot.joints, q):
            qp[model.joints[model.getJointId(joint.name)].idx_q] = value
        pin.framesForwardKinematics(model, data, qp)
        out.append(data.oMf[model.getFrameId(tip)].homogeneous.copy())
    return np.array(out)


def wrapped(a, b):
    return np.abs((np.asarray(a) - b + np.pi) % (2 * np.pi) - np.pi)


@pytest.mark.parametrize("name", ARMS)
def test_every_solution_at_the_arm_angle(name):
    robot = ARMS[name][0]()
    model, tip = ARMS[name][1]()
    q = robot.random_q(200, rng=7)
    assert np.abs(pin_fk(model, tip, robot, q[:3]) - robot.fk(q[:3])).max() < CHECK   # the same arm
    psi = arm_angle_of(robot, q)
    T = robot.fk(q)
    res = robot.ik(T, arm_angle=psi, all_solutions=True)
    assert res.method == "srs-arm-angle" and res.success.all()
    lim = robot.limits
    counts = []
    for k, sols in enumerate(res.solutions):
        assert 1 <= len(sols) <= 8
        counts.append(len(sols))
        assert wrapped(sols, q[k]).max(axis=1).min() < 1e-9                   # the generating q is there
        assert np.abs(pin_fk(model, tip, robot, sols) - T[k]).max() < CHECK
        assert np.all((sols >= lim[:, 0] - 1e-12) & (sols <= lim[:, 1] + 1e-12))
        assert wrapped(arm_angle_of(robot, sols), psi[k]).max() < 1e-9         # at the arm angle asked for
    assert max(counts) == 8                                                   # every branch shows up
    # q0 = the generating configuration: q is that configuration
    again = robot.ik(T, arm_angle=psi, q0=q)
    assert np.abs(again.q - q).max() < 1e-9


def test_feasible_intervals_hold_the_arm_angles_of_feasible_configurations():
    robot = arms.iiwa()
    rng = np.random.default_rng(3)
    for q in robot.random_q(12, rng=rng):
        T = robot.fk(q)
        spans = feasible_arm_angles(robot, T)
        assert set(spans) == set(BRANCHES)
        psi, label = arm_angle_of(robot, q), tuple(int(x) for x in branch_of(robot, q))
        inside = lambda x, ivs: any(lo - 1e-9 <= x + 2 * np.pi * k <= hi + 1e-9 for lo, hi in ivs for k in (-1, 0, 1))
        assert inside(psi, spans[label])
        # inside an interval the branch has a solution within limits; in a gap between intervals it has none
        for b, ivs in spans.items():
            probes = [(0.5 * (lo + hi), True) for lo, hi in ivs if hi - lo > 1e-6]
            probes += [(0.5 * (ivs[j][1] + ivs[j + 1][0]), False) for j in range(len(ivs) - 1)
                       if ivs[j + 1][0] - ivs[j][1] > 1e-6]
            for x, feasible in probes:
                res = robot.ik(T, arm_angle=x, all_solutions=True)
                labels = {tuple(int(v) for v in branch_of(robot, s)) for s in (res.solutions if res.success else [])}
                assert (b in labels) == feasible, (b, x, feasible)


def test_branch_is_kept_along_a_path():
    robot = arms.iiwa()
    qa = np.array([0.3, 0.6, -0.4, -1.2, 0.5, 0.9, 0.2])
    qb = np.array([1.1, 0.2, 0.5, -0.5, -0.4, 0.3, -0.6])     # q2, q4, q6 keep their signs: one branch
    path = qa + np.linspace(0, 1, 60)[:, None] * (qb - qa)
    psi = arm_angle_of(robot, path)
    q = qa
    for k in range(len(path)):
        res = robot.ik(robot.fk(path[k]), arm_angle=psi[k], q0=q)
        assert res.success and np.array_equal(branch_of(robot, res.q), branch_of(robot, qa))
        assert np.abs(res.q - path[k]).max() < 1e-9
        q = res.q


def test_q0_branch_wins_over_distance():
    robot = arms.iiwa()
    for q in robot.random_q(20, rng=11):
        T, psi = robot.fk(q), arm_angle_of(robot, q)
        sols = robot.ik(T, arm_angle=psi, all_solutions=True).solutions
        labels = branch_of(robot, sols)
        for i in range(len(sols)):
            j = (i + 1) % len(sols)
            if np.array_equal(labels[i], labels[j]):
                continue
            ref = sols[j].copy()          # another solution, with the branch joints given i's signs
            ref[[1, 3, 5]] = 1e-3 * labels[i]
            res = robot.ik(T, arm_angle=psi, q0=ref)
            assert res.success and np.array_equal(branch_of(robot, res.q), labels[i])


def test_no_solution_on_q0_branch_says_so():
    robot = arms.iiwa()
    for q in robot.random_q(50, rng=5):
        T, psi = robot.fk(q), arm_angle_of(robot, q)
        have = {tuple(int(v) for v in branch_of(robot, s))
                for s in robot.ik(T, arm_angle=psi, all_solutions=True).solutions}
        missing = [b for b in BRANCHES if b not in have]
        if missing:
            ref = np.zeros(7)
            ref[[1, 3, 5]] = 0.1 * np.array([missing[0][0], missing[0][1], missing[0][2]])
            res = robot.ik(T, arm_angle=psi, q0=ref, all_solutions=True)
            assert not res.success and "q0's branch" in res.message and len(res.solutions) == len(have)
            return
    pytest.fail("no target with a branch missing")


def test_refusals():
    iiwa = arms.iiwa()
    T = iiwa.fk(np.full(7, 0.3))
    with pytest.raises(InputError, match="axis 3 passes 0.0118"):
        arms.gen3().ik(T, arm_angle=0.0)                     # the real Gen3: offset shoulder
    with pytest.raises(InputError, match="7 revolute joints"):
        arms.xarm6().ik(T, arm_angle=0.0)
    with pytest.raises(InputError, match="lock"):
        iiwa.ik(T, arm_angle=0.0, lock={"iiwa_joint_3": 0.0})
    with pytest.raises(InputError, match="mask"):
        iiwa.ik(T, arm_angle=0.0, mask="position")
    with pytest.raises(InputError, match="method"):
        iiwa.ik(T, arm_angle=0.0, method="numeric")
    with pytest.raises(InputError, match="finite"):
        iiwa.ik(T, arm_angle=float("nan"))
    with pytest.raises(InputError, match="one per target"):
        iiwa.ik(np.stack([T, T]), arm_angle=[0.0, 1.0, 2.0])
    far = T.copy()
    far[:3, 3] = [3.0, 0, 0]
    res = iiwa.ik(far, arm_angle=0.0)
    assert not res.success and "out of reach" in res.message and np.isnan(res.q).all()


def test_cli_arm_angle(capsys):
    assert main(["ik", IIWA_URDF, "--pose", "0.5,0,0.5,0,180,0", "--degrees", "--arm-angle", "30", "--all",
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    Q = np.radians([s["q"] for s in out["solutions"]])
    robot = arms.iiwa()
    assert out["method"] == "srs-arm-angle" and len(Q) == 8
    assert np.allclose(arm_angle_of(robot, Q), np.radians(30), atol=1e-9)
    assert main(["ik", IIWA_URDF, "--pose", "0.5,0,0.5,0,pi,0", "--arm-angle", "0.5", "--position-only"]) == 2
    assert "mask" in capsys.readouterr().err


def test_gui_arm_angle():
    from robkin.viz import gui_api

    text = open(IIWA_URDF).read()
    robot = arms.iiwa()
    q = np.array([0.3, 0.6, -0.4, -1.2, 0.5, 0.9, 0.2])
    shown = gui_api.describe(text, "urdf", q=q.tolist())
    assert shown["srs"] and abs(shown["arm_angle"] - arm_angle_of(robot, q)) < 1e-12
    res = gui_api.solve_ik(text, "urdf", robot.fk(q).tolist(), q.tolist(), arm_angle=shown["arm_angle"] + 0.2)
    assert res["success"] and res["method"] == "srs-arm-angle"
    assert abs(res["arm_angle"] - (shown["arm_angle"] + 0.2)) < 1e-9                 # the elbow swivelled
    assert np.abs(robot.fk(res["q"]) - robot.fk(q)).max() < 1e-9                     # the tool stayed
    assert np.array_equal(branch_of(robot, np.array(res["q"])), branch_of(robot, q))
    with pytest.raises(InputError, match="arm_angle"):
        gui_api.solve_ik(text, "urdf", robot.fk(q).tolist(), q.tolist(), arm_angle="x")
    from robkin.io.documents.reader import document_from_robot, dump

    six = gui_api.describe(dump(document_from_robot(arms.xarm6())), "yaml")
    assert six["srs"] is False and six["arm_angle"] is None


def test_browser_arm_angle_slider():
    """In the page: the slider shows for the iiwa; moving it swivels the elbow with the tool held."""
    import tempfile

    from test_gui import CHROMIUM_FLAGS, _chromium, _pose, _skip_or_fail

    from robkin.viz.gui import make_server

    try:
        from playwright import sync_api
    except ImportError:
        _skip_or_fail("the browser test needs the playwright package (test extra)")
    exe = _chromium()
    if exe is None:
        _skip_or_fail("no Chromium installed (apt-get install chromium); the browser test needs one")
    robot = arms.iiwa()
    srv = make_server(port=0, text=open(IIWA_URDF).read(), fmt="urdf")
    srv.serve_in_thread()
    errors: list[str] = []
    try:
        with sync_api.sync_playwright() as pw, tempfile.TemporaryDirectory() as profile:
            ctx = pw.chromium.launch_persistent_context(profile, executable_path=exe, headless=True,
                                                        args=CHROMIUM_FLAGS)
            pg = ctx.new_page()
            pg.on("pageerror", lambda e: errors.append(str(e)))
            pg.goto(srv.url)
            pg.wait_for_selector("body[data-state=ready]", timeout=15000)
            assert pg.get_attribute("#arm-angle", "hidden") is None
            q = [0.3, 0.6, -0.4, -1.2, 0.5, 0.9, 0.2]
            for i, v in enumerate(q):
                pg.eval_on_selector(f"#q{i}", "(e, v) => { e.value = v; e.dispatchEvent(new Event('input')); }", v)
            for _ in range(300):        # until the page shows the whole of q (each slider asks on its own)
                if np.abs(_pose(pg) - robot.fk(np.array(q))).max() < 1e-9:
                    break
                pg.wait_for_timeout(50)
            pg.wait_for_function("(v) => document.querySelector('#arm-angle-value').textContent.startsWith(v)",
                                 arg=f"{np.degrees(arm_angle_of(robot, np.array(q))):.1f}", timeout=15000)
            pg.eval_on_selector("#arm-angle-slider", "e => { e.value = 80; e.dispatchEvent(new Event('input')); }")
            pg.wait_for_function("() => document.body.dataset.ikSuccess == 'true'", timeout=15000)
            pg.wait_for_function("() => document.querySelector('#arm-angle-value').textContent.startsWith('80.0')",
                                 timeout=15000)
            shown = np.array([float(pg.input_value(f"#q{i}")) for i in range(7)])
            ctx.close()
    finally:
        srv.shutdown()
        srv.server_close()
    assert not errors
    # the sliders' values are the answer to ~1e-13 (their text form): the tool stayed, the elbow turned
    assert np.abs(robot.fk(shown) - robot.fk(np.array(q))).max() < 1e-6
    assert abs(arm_angle_of(robot, shown) - np.radians(80)) < 1e-6


SCALE = int(arms.os.environ.get("ROBKIN_PROPERTY_SCALE", "1"))


@settings(max_examples=15 * SCALE, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(d=st.lists(st.floats(0.1, 0.6), min_size=4, max_size=4),
       alpha=st.lists(st.floats(0.35, PI - 0.35), min_size=7, max_size=7),
       signs=st.lists(st.sampled_from([-1.0, 1.0]), min_size=7, max_size=7),
       seed=st.integers(0, 2**31))
def test_random_srs_geometry(d, alpha, signs, seed):
    """Any SRS arm (a = 0, d2 = d4 = d6 = 0 in DH; twists anywhere between 20 and 160 degrees, so axes are
    oblique, not just perpendicular): every target's generating configuration comes back at its arm angle."""
    rows = np.column_stack([np.zeros(7), [d[0], 0, d[1], 0, d[2], 0, d[3]], np.multiply(alpha, signs), np.zeros(7)])
    robot = robkin.DHTable(rows, tuple(Joint(f"j{i + 1}", "revolute") for i in range(7))).to_robot(name="srs")
    q = np.random.default_rng(seed).uniform(-PI, PI, (20, 7))
    psi = arm_angle_of(robot, q)
    res = robot.ik(robot.fk(q), arm_angle=psi, all_solutions=True)
    for k, sols in enumerate(res.solutions):
        assert wrapped(sols, q[k]).max(axis=1).min() < 1e-7
        assert np.abs(robot.fk(sols) - robot.fk(q[k])).max() < 1e-9


def test_arm_angle_solutions_are_among_the_locked_joint_solutions():
    """The arm angle's solutions against ik-general's closed form with joint 3 locked at each one's value:
    two independent methods on the same arm."""
    robot = arms.iiwa()
    for q in robot.random_q(10, rng=21):
        T = robot.fk(q)
        for s in robot.ik(T, arm_angle=arm_angle_of(robot, q), all_solutions=True).solutions:
            locked = robot.ik(T, lock={"iiwa_joint_3": s[2]}, all_solutions=True)
            assert locked.method != "numeric" and wrapped(locked.solutions, s).max(axis=1).min() < 1e-7


def test_cli_poses_at_one_arm_angle(tmp_path, capsys):
    import csv

    poses = tmp_path / "poses.csv"
    poses.write_text("x,y,z,roll,pitch,yaw\n0.5,0,0.5,0,180,0\n0.4,0.2,0.6,0,180,0\n3,0,0,0,0,0\n")
    out = tmp_path / "q.csv"
    assert main(["ik", IIWA_URDF, "--poses", str(poses), "--degrees", "--arm-angle", "30", "-o", str(out)]) == 0
    rows = list(csv.DictReader(out.open()))
    robot = arms.iiwa()
    assert [r["success"] for r in rows] == ["true", "true", "false"] and "out of reach" in rows[2]["error"]
    for r in rows[:2]:
        q = np.radians([float(r[j.name]) for j in robot.joints])
        assert abs(arm_angle_of(robot, q) - np.radians(30)) < 1e-9
