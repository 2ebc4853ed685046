"""Initial structure estimation (types A-D), its metrics and ``robkin estimate``.

Reference values come from the estimation paper (Huczala et al., Appl. Sci. 2021): its Table 1 for
Pose(1), the text of its Figs. 11-12 for the comparison, and its warnings about degenerate poses.
Forward kinematics and Jacobians are re-derived here independently (plain DH products and finite
differences) rather than taken from the code under test.
"""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest

from robkin import se3
from robkin.cli import main
from robkin.errors import InputError, ProjectionWarning
from robkin.synthesis.bezier import bezier_points, control_points, curve_points
from robkin.synthesis.estimate import KINDS, estimate, estimate_all

# Pose(1) with 4 decimals, as in the authors' example script; Poses (2) and (3) as printed (eqs. 8-10).
POSE1 = np.array([[-0.5005, -0.1800, -0.8468, -1.0],
                  [-0.0654, 0.9832, -0.1704, 0.9],
                  [0.8633, -0.0299, -0.5039, 0.8],
                  [0, 0, 0, 1]])
POSE2_PRINTED = np.array([[0.81, -0.34, -0.46, -0.4],
                          [0.48, -0.02, 0.87, 0.6],
                          [-0.30, -0.93, 0.14, 0.7],
                          [0, 0, 0, 1]])
POSE3 = np.array([[0, 1, 0, 0.4], [1, 0, 0, 0.6], [0, 0, -1, 0.7], [0, 0, 0, 1.0]])


def _exact(T: np.ndarray) -> np.ndarray:
    """The printed pose with its 2-4 decimal rotation projected onto SO(3) (Pose(2) is 0.018 off)."""
    out = np.array(T, dtype=float)
    out[:3, :3] = se3.nearest_rotation(out[:3, :3])
    return out


POSES = {1: _exact(POSE1), 2: _exact(POSE2_PRINTED), 3: POSE3}

# Table 1 of the paper: (d, a, alpha) per joint for types A-D, Pose(1), n = 4.
TABLE1 = {
    "A": [(0.8, 0.34, 0.79), (0, 0.34, -0.79), (0, 0.34, 0.79), (0, 0.34, -0.79)],
    "B": [(0.64, 0.29, -0.39), (0.32, 0.56, -1.48), (0.46, 0.38, 0), (0, 0, -0.28)],
    "C": [(1.27, 0.36, -0.7), (0, 0.36, -0.7), (0, 0.36, -0.7), (0.93, 0, 0)],
    "D": [(0.64, 0.29, -0.40), (0.32, 0.55, -1.48), (-0.33, 0.30, -0.29), (0.83, 0, 0)],
}


def _dh_fk(rows: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Plain standard-DH product Rz(theta + q) Tz(d) Tx(a) Rx(alpha), written out independently."""
    T = np.eye(4)
    for (a, d, alpha, theta), qi in zip(rows, q):
        th = theta + qi
        ct, st, ca, sa = math.cos(th), math.sin(th), math.cos(alpha), math.sin(alpha)
        T = T @ np.array([[ct, -st * ca, st * sa, a * ct], [st, ct * ca, -ct * sa, a * st],
                          [0, sa, ca, d], [0, 0, 0, 1]])
    return T


def _matches_paper(value: float, printed: float) -> bool:
    """The paper prints 2 decimals, rounded in most cells and truncated in a few (B: alpha_1 -0.399
    -> -0.39, alpha_4 -0.286 -> -0.28; D: a_2 0.557 -> 0.55); accept either."""
    rounded = round(value, 2)
    truncated = math.trunc(value * 100) / 100
    return abs(printed - rounded) < 1e-9 or abs(printed - truncated) < 1e-9


# ------------------------------------------------------------------------------------ paper


@pytest.mark.parametrize("kind", KINDS)
def test_table1_pose1(kind):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ProjectionWarning)  # 4-decimal rotation, projected
        est = estimate(POSE1, 4, kind)
    for i, (d, a, alpha) in enumerate(TABLE1[kind]):
        row = est.rows[i]
        for name, value, printed in (("d", row[1], d), ("a", row[0], a), ("alpha", row[2], alpha)):
            assert _matches_paper(value, printed), f"type {kind} joint {i + 1} {name}: {value} vs {printed}"


def test_projection_warning_names_the_pose():
    with pytest.warns(ProjectionWarning, match="pose"):
        estimate(POSE1, 4, "D")


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("pose", [1, 2, 3])
def test_home_configuration_reaches_target(kind, pose):
    est = estimate(POSES[pose], 4, kind)
    T = _dh_fk(est.rows, np.zeros(4))
    target = POSES[pose]
    # 1e-12: a chain of 4 products of O(1) numbers, rounding ~1e-15, with margin
    np.testing.assert_allclose(T[:3, 3], target[:3, 3], atol=1e-12)
    if kind in "CD":
        np.testing.assert_allclose(T[:3, :3], target[:3, :3], atol=1e-12)
    np.testing.assert_allclose(est.robot.fk(np.zeros(4)), T, atol=1e-12)  # robot == its table
    assert est.reaches == ("pose" if kind in "CD" else "position")


def test_pose1_orientation_not_reached_by_a_and_b():
    # A and B are position-only: for the general Pose(1) their home orientation differs from the target
    for kind in "AB":
        assert estimate(POSES[1], 4, kind).reach_error()[1] > 0.1


def test_pose3_type_b_reaches_full_pose():
    # the paper notes (Fig. 10b) that B reaches Pose(3) completely; here q = 0 does so
    est = estimate(POSE3, 4, "B")
    pos, rot = est.reach_error()
    assert pos < 1e-12 and rot < 1e-12
    assert any("parallel" in n for n in est.notes)


def _fd_manipulability(rows: np.ndarray, rows_sel: slice) -> float:
    """Yoshikawa measure from a finite-difference Jacobian of the independent DH product."""
    n = len(rows)
    h = 1e-6
    T0 = _dh_fk(rows, np.zeros(n))
    J = np.zeros((6, n))
    for i in range(n):
        dq = np.zeros(n)
        dq[i] = h
        Tp, Tm = _dh_fk(rows, dq), _dh_fk(rows, -dq)
        J[:3, i] = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
        dR = (Tp[:3, :3] - Tm[:3, :3]) / (2 * h) @ T0[:3, :3].T
        J[3:, i] = [dR[2, 1], dR[0, 2], dR[1, 0]]
    return float(np.prod(np.linalg.svd(J[rows_sel], compute_uv=False)))


@pytest.mark.parametrize("kind", KINDS)
def test_metrics_against_independent_computation(kind):
    est = estimate(POSES[2], 5, kind)
    rows = est.rows
    assert est.metrics.length == pytest.approx(sum(math.hypot(r[0], r[1]) for r in rows), rel=1e-14)
    # central differences with h = 1e-6: error ~1e-12 relative on O(1) entries; products of 3
    # singular values keep that, so 1e-7 absolute (values are 1e-4..1) is a safe bound.
    wt = _fd_manipulability(rows, slice(0, 3))
    wr = _fd_manipulability(rows, slice(3, 6))
    assert est.metrics.manipulability_translational == pytest.approx(wt, abs=1e-7)
    assert est.metrics.manipulability_rotational == pytest.approx(wr, abs=1e-7)


def test_figures_11_12_qualitatively():
    """The paper's comparison (Sect. 3.2-3.3), metrics at the configuration reaching the target.

    - length: A or B (position only) is the shortest for every pose;
    - manipulability: A is the lowest (singular straight arm); B has D's translational value, but its
      rotational value drops; D has the highest rotational value for the general Poses (1) and (2);
      for Pose(3) (parallel z axes) D drops below C.
    """
    for p in (1, 2, 3):
        est = estimate_all(POSES[p], 4)
        m = {k: e.metrics for k, e in est.items()}
        lengths = {k: v.length for k, v in m.items()}
        assert min(lengths, key=lengths.get) in "AB", (p, lengths)
        for k in "BCD":
            assert m["A"].manipulability_translational <= m[k].manipulability_translational
            assert m["A"].manipulability_rotational <= m[k].manipulability_rotational
        if p in (1, 2):
            assert m["B"].manipulability_translational == pytest.approx(m["D"].manipulability_translational,
                                                                        rel=1e-9)
            assert m["B"].manipulability_rotational < m["D"].manipulability_rotational
            assert max(m, key=lambda k: m[k].manipulability_rotational) == "D"
        else:
            assert m["C"].manipulability_translational > m["D"].manipulability_translational
            assert m["C"].manipulability_translational > 0.01


@pytest.mark.parametrize("pose", [1, 2, 3])
def test_three_poses_n3_to_n8_finite_and_reaching(pose):
    for n in range(3, 9):
        for kind, est in estimate_all(POSES[pose], n).items():
            assert est.rows.shape == (n, 4)
            assert np.all(np.isfinite(est.rows)), (pose, n, kind)
            vals = [est.metrics.length, est.metrics.manipulability_translational,
                    est.metrics.manipulability_rotational]
            assert all(math.isfinite(v) and v >= 0 for v in vals)
            pos, rot = est.reach_error()
            assert pos < 1e-11, (pose, n, kind, pos)
            if kind in "CD":
                assert rot < 1e-11, (pose, n, kind, rot)
            # links are of the order of the target distance, not degenerate or exploding
            dist = np.linalg.norm(POSES[pose][:3, 3])
            assert 0.99 * dist <= est.metrics.length <= 5 * dist


def test_type_a_alphas_sum_to_zero_for_odd_n():
    for n in (3, 5, 7):
        rows = estimate(POSES[1], n, "A").rows
        assert abs(rows[:, 2].sum()) < 1e-15
        assert np.allclose(rows[:, 0], rows[0, 0])  # equal links (eq. 16)


# ------------------------------------------------------------------------------- degenerate


def test_target_on_base_axis():
    T = se3.trans(0, 0, 1.2) @ se3.rot_x(0.4)
    for kind, est in estimate_all(T, 5).items():
        assert np.all(np.isfinite(est.rows))
        pos, rot = est.reach_error()
        assert pos < 1e-12
        if kind in "CD":
            assert rot < 1e-12
    a = estimate(T, 5, "A")
    assert np.allclose(a.rows[:, 0], 0) and any("base z axis" in n for n in a.notes)


def test_target_straight_above_with_parallel_and_antiparallel_axes():
    for T in (se3.trans(0, 0, 1.0), se3.trans(0, 0, 1.0) @ se3.rot_x(math.pi)):
        for kind, est in estimate_all(T, 4).items():
            assert np.all(np.isfinite(est.rows)), kind
            pos, rot = est.reach_error()
            assert pos < 1e-12
            if kind in "CD":
                assert rot < 1e-12, kind
        assert any("coincide" in n for n in estimate(T, 4, "C").notes)


def test_intersecting_axes():
    # the target z axis crosses the base z axis: zero-length common perpendicular, direction z_b x z_p
    T = se3.trans(0, 0, 0.5) @ se3.rot_y(0.7) @ se3.trans(0, 0, 0.8)
    est = estimate(T, 4, "C")
    assert est.rows[0, 0] == pytest.approx(0, abs=1e-12)
    assert est.reach_error()[0] < 1e-12 and est.reach_error()[1] < 1e-12
    assert any("meet" in n for n in est.notes)


def test_coincident_frames_are_an_error():
    with pytest.raises(InputError, match="coincides with the base origin"):
        estimate(np.eye(4), 4, "D")
    with pytest.raises(InputError, match="coincides"):
        estimate(se3.rot_x(1.0), 4, "C")  # same origin, other orientation: still nothing to reach
    B = se3.trans(1, 2, 3) @ se3.rot_z(0.3)
    with pytest.raises(InputError):
        estimate(B @ se3.rot_y(0.2), 4, "B", base=B)


def test_bad_arguments():
    with pytest.raises(InputError, match="joints"):
        estimate(POSES[1], 2, "D")
    with pytest.raises(InputError, match="joints"):
        estimate(POSES[1], 4.0, "D")  # type: ignore[arg-type]
    with pytest.raises(InputError, match="type"):
        estimate(POSES[1], 4, "E")
    with pytest.raises(InputError, match="pose"):
        estimate(np.full((4, 4), np.nan), 4, "A")


def test_base_frame_is_respected():
    B = se3.trans(0.3, -0.2, 0.1) @ se3.rot_z(0.8) @ se3.rot_x(0.2)
    for kind in KINDS:
        local = estimate(POSES[2], 4, kind)
        world = estimate(B @ POSES[2], 4, kind, base=B)
        np.testing.assert_allclose(world.rows, local.rows, atol=1e-12)
        np.testing.assert_allclose(world.robot.world, B, atol=1e-15)
        assert world.metrics.length == pytest.approx(local.metrics.length, rel=1e-12)


# ---------------------------------------------------------------------------------- Bezier


def test_bezier_curve_matches_de_casteljau_and_eqs_11_15():
    target = POSES[1]
    P = control_points(np.eye(4), target)
    half = np.linalg.norm(target[:3, 3]) / 2
    np.testing.assert_allclose(P[1], [0, 0, half])  # eq. 12
    np.testing.assert_allclose(P[2], target[:3, 3] - half * target[:3, 2])  # eq. 13
    t = np.linspace(0, 1, 7)
    pts = bezier_points(P, t)
    for ti, pt in zip(t, pts):
        Q = P.copy()
        for k in range(3, 0, -1):  # de Casteljau
            Q = (1 - ti) * Q[:k] + ti * Q[1:k + 1]
        np.testing.assert_allclose(pt, Q[0], atol=1e-15)
    ends = curve_points(np.eye(4), target, 4)
    assert np.array_equal(ends[0], np.zeros(3)) and np.array_equal(ends[-1], target[:3, 3])


# -------------------------------------------------------------------------------------- CLI
POSE1_ARG = ",".join(f"{v:.4f}" for v in POSE1.ravel())


def test_cli_writes_document_with_metrics(tmp_path, capsys):
    from robkin import load

    out = tmp_path / "d.yaml"
    assert main(["estimate", "--pose", POSE1_ARG, "--joints", "4", "--type", "D", "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "type D" in text and "length" in text
    import yaml

    doc = yaml.safe_load(out.read_text())
    assert set(doc["metrics"]) == {"length", "manipulability_translational", "manipulability_rotational"}
    assert "dh" in doc and len(doc["dh"]["rows"]) == 4
    robot = load(out)
    np.testing.assert_allclose(robot.fk(np.zeros(4)), POSES[1], atol=1e-12)
    est = estimate(POSES[1], 4, "D")
    assert doc["metrics"]["length"] == pytest.approx(est.metrics.length, rel=1e-12)
    # the document's dh section is the estimate's own table (its frames already satisfy DH)
    written = np.array([[r[k] for k in ("a", "d", "alpha", "theta")] for r in doc["dh"]["rows"]])
    np.testing.assert_allclose(written, est.rows, atol=1e-12)


def test_cli_all_table_json_and_folder(tmp_path, capsys):
    assert main(["estimate", "--pose", POSE1_ARG, "--joints", "5", "--type", "all", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert sorted(data) == list("ABCD")
    assert data["D"]["manipulability_rotational"] > 0
    folder = tmp_path / "res"
    assert main(["estimate", "--pose", POSE1_ARG, "--joints", "4", "--type", "all", "-o", str(folder),
                 "--format", "json"]) == 0
    out = capsys.readouterr().out
    assert "estimates (metrics at q = 0)" in out
    assert sorted(p.name for p in folder.iterdir()) == [f"estimate_{k}.json" for k in "ABCD"]
    assert "metrics" in json.loads((folder / "estimate_C.json").read_text())


def test_cli_rpy_pose_and_base(capsys):
    base = "0.1,0.2,0.3,0,0,0.5"
    assert main(["estimate", "--pose", "0.4,0.6,0.7,0,3.14159,1.5708", "--base", base, "--joints", "3",
                 "--type", "C", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["C"]["length"] > 0


@pytest.mark.parametrize("argv, message", [
    (["--pose", "0,0,0,0,0,0", "--joints", "4"], "coincides"),
    (["--pose", "1,0,0,0,0,0", "--joints", "2"], "--joints"),
    (["--pose", "1,0,0,0,0", "--joints", "4"], "--pose"),
    (["--pose", "1,0,0,0,0,0", "--pose", "1,1,0,0,0,0", "--joints", "4"], "--optimize"),
    (["--pose", "1,0,0,0,0,0", "--joints", "4", "-o", "out.txt"], "out.txt"),
    (["--pose", "1,0,0,0,0,0", "--joints", "4", "--plot", "p.png"], "--plot"),
])
def test_cli_bad_input_exit_2_and_nothing_written(tmp_path, capsys, monkeypatch, argv, message):
    monkeypatch.chdir(tmp_path)
    assert main(["estimate", *argv]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []


def test_cli_existing_output_untouched_on_error(tmp_path, capsys):
    out = tmp_path / "keep.yaml"
    out.write_text("original")
    assert main(["estimate", "--pose", "0,0,0,0,0,0", "--joints", "4", "-o", str(out)]) == 2
    assert out.read_text() == "original"


def test_cli_plot(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    pic = tmp_path / "cmp.png"
    assert main(["estimate", "--pose", POSE1_ARG, "--joints", "4", "--type", "all", "--plot", str(pic)]) == 0
    assert pic.stat().st_size > 1000


def test_cli_optimize_two_poses(tmp_path, capsys):
    from robkin import load

    p2 = POSES[1] @ se3.trans(0.05, 0.1, 0.0) @ se3.rot_x(0.2)
    arg2 = ",".join(repr(float(v)) for v in p2.ravel())
    out = tmp_path / "opt.json"
    assert main(["estimate", "--pose", POSE1_ARG, "--pose", arg2, "--joints", "5", "--type", "D",
                 "--optimize", "length", "-o", str(out), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["optimization"]["chosen_start"] == "D"
    robot = load(out)
    np.testing.assert_allclose(robot.fk(np.zeros(5)), POSES[1], atol=1e-6)
