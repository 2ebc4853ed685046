"""Property tests of the core promise: every representation converts to every other, exactly.

Random robots (``strategies.robot_specs``: 1-8 joints, revolute and prismatic, flip flags, every axis
relation drawn on purpose, random base and tool, mm/m/km) are written in each representation (GJD, DH,
modified DH, PoE space, PoE body, RPY-XYZ), optionally with the input rounded to 6 decimals as a person
would type it, read back through the GJD hub and written in every other representation. Forward
kinematics of all of them must agree at random q, single and batch.
"""

from __future__ import annotations

import os
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import robkin
from robkin import se3
from robkin.errors import ProjectionWarning
from robkin.lines import ANGLE_TOL, classify
from robkin.representations.dh import dh_frames
from robkin.representations.frames import KEEP_TOL, satisfies_normal
from robkin.robot import Joint, Robot

from strategies import RobotSpec, angles, dh_rows, joint_lists, robot_specs

#: FK agreement, relative to the robot's size for positions (rotation entries are dimensionless).
#: Conversions are closed-form: a chain of ~10 products per joint, each rounding at ~1e-16, so 1e-9
#: leaves a margin of ~1e5 for the lever arms of frames placed on far common-normal feet.
FK_TOL = 1e-9
#: Quantities that are copied or recomputed by a short closed-form chain (round-tripped tables, axis
#: lines): rounding noise only, ~1e-15, with margin.
EXACT = 1e-12

#: Rounding inputs to 6 decimals turns exactly parallel axes into axes ~1e-7 apart in angle, whose common
#: normal lies ~offset / sin away. DH-style frames placed there carry lengths that large, and FK through
#: them loses ~eps * offset / sin per frame: a property of the DH parameterisation, not of the
#: conversion. For such robots the FK tolerance grows with 1 / sin of the most nearly parallel
#: non-parallel consecutive axes (see ``conditioning_tol``); for all others it is FK_TOL.
EPS = float(np.finfo(float).eps)

REPRESENTATIONS = ("gjd", "dh", "mdh", "hayati", "poe", "poe_body", "rpy")

# Nearly parallel axes (rounded inputs) make the DH/MDH writers warn, as documented; here that is
# expected, and the accuracy it warns about is what the tolerances above account for.
pytestmark = pytest.mark.filterwarnings("ignore::robkin.errors.ConditioningWarning")

SETTINGS = dict(deadline=None, print_blob=True,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
#: ROBKIN_PROPERTY_SCALE=20 multiplies every example count, for a deep search before a release.
SCALE = int(os.environ.get("ROBKIN_PROPERTY_SCALE", "1"))


# ----------------------------------------------------------------------------- helpers
def write(robot: Robot, rep: str):
    """The robot in one representation (an object with .fk and .to_robot)."""
    if rep == "gjd":
        return robot
    if rep == "dh":
        return robkin.dh_from_robot(robot)
    if rep == "mdh":
        return robkin.mdh_from_robot(robot)
    if rep == "hayati":
        return robkin.hayati_from_robot(robot)
    if rep == "poe":
        return robkin.poe_from_robot(robot, "space")
    if rep == "poe_body":
        return robkin.poe_from_robot(robot, "body")
    return robkin.rpy_from_robot(robot)


def read(rep_obj) -> Robot:
    return rep_obj if isinstance(rep_obj, Robot) else rep_obj.to_robot()


def rounded(rep_obj, unit: float = 1.0, decimals: int = 6):
    """The same representation with every number rounded to ``decimals`` as typed by hand, lengths
    in the robot's own unit (a mm robot typed in mm), then validated again."""
    def r(a, lengths=None):
        """Round; ``lengths`` is a mask (or index) of the entries that are lengths."""
        a = np.array(a, dtype=float)
        scale = np.ones_like(a)
        if lengths is not None:
            scale[lengths] = unit
        return np.round(a / scale, decimals) * scale

    pose = (..., slice(0, 3), 3)  # translation column of a (..., 4, 4) pose
    with warnings.catch_warnings():
        # rounded rotations are ~1e-6 from orthonormal: projected with a ProjectionWarning, on purpose
        warnings.simplefilter("ignore", ProjectionWarning)
        if isinstance(rep_obj, Robot):
            return Robot(r(rep_obj.frames, pose), rep_obj.joints, world=r(rep_obj.world, pose))
        if isinstance(rep_obj, (robkin.DHTable, robkin.MDHTable, robkin.HayatiTable)):
            return type(rep_obj)(r(rep_obj.rows, (..., slice(0, 2))), rep_obj.joints, base=r(rep_obj.base, pose),
                                 tool=r(rep_obj.tool, pose))
        if isinstance(rep_obj, robkin.PoE):
            # v of a revolute screw is a length (-w x p); of a prismatic one a unit direction
            lengths = np.zeros(rep_obj.screws.shape, dtype=bool)
            lengths[[j.revolute for j in rep_obj.joints], 3:] = True
            return robkin.PoE(r(rep_obj.M, pose), r(rep_obj.screws, lengths), rep_obj.joints, rep_obj.frame)
        return robkin.RPYTable(r(rep_obj.rows, (..., slice(3, 6))), rep_obj.joints)


def assert_poses_close(A: np.ndarray, B: np.ndarray, scale: float, tol: float = FK_TOL, what: str = ""):
    """Rotation blocks to ``tol``, translations to ``tol * scale``."""
    rot = np.abs(A[..., :3, :3] - B[..., :3, :3]).max()
    pos = np.abs(A[..., :3, 3] - B[..., :3, 3]).max()
    assert rot <= tol and pos <= tol * scale, f"{what}: rotation error {rot:.3g}, position error {pos:.3g} " \
                                              f"(scale {scale:.3g}, tol {tol:.0e})"
    np.testing.assert_array_equal(A[..., 3, :], np.broadcast_to([0.0, 0.0, 0.0, 1.0], A[..., 3, :].shape))


def extent(robot: Robot) -> float:
    """The size of the numbers a robot's conversions compute with: rounding noise is eps times this.

    Usually Robot.scale. But Robot.scale measures axis distances and the tool, so a robot whose axes
    all pass through the base origin, with the tool there too, has a tiny scale (seen: 2e-9) while
    its frames sit 1e-3 apart along the axes; tolerances relative to that scale fall below rounding.
    """
    return max(robot.scale, float(np.linalg.norm(robot.frames[:, :3, 3], axis=1).max()))


def well_scaled(robot: Robot) -> bool:
    """Is Robot.scale within 1e3 of the coordinates? The core's own decisions (keep a frame, do axes
    meet) use tolerances relative to Robot.scale; for robots where it is far below the coordinates
    those decisions sit on rounding noise, FK stays exact but tables need not round-trip unchanged
    (a reported limitation). Tests of table identity assume this."""
    return robot.scale >= 1e-3 * extent(robot)


def fk_scale(robot: Robot, T: np.ndarray) -> float:
    """Length scale of an FK comparison: the robot's size, or the reach at q if larger (prismatic)."""
    return max(extent(robot), float(np.abs(T[..., :3, 3]).max()))


def conditioning_tol(robot: Robot) -> float:
    """FK tolerance for a robot whose consecutive axes may be nearly (not exactly) parallel.

    Two effects, both properties of the DH/MDH parameterisation rather than of the conversion:

    - axes at sin >= ANGLE_TOL are skew: their common normal lies ~offset / sin away and FK through
      frames there loses ~eps / sin robot sizes per frame: 16 * n * eps / sin_min (16: margin for the
      few products per frame), plus n * KEEP_TOL / sin_min for given frames kept because they meet
      the convention to KEEP_TOL (seen: a kept frame 1.2e-13 off, times a 1e6 lever, 2e-7);
    - axes at sin < ANGLE_TOL are treated as parallel, so the table's axis is off by that angle:
      rotation error ~2 sin per such pair (the frame's tilt, then the motion about it): 4 * sum(sin).

    Equals FK_TOL unless some sin is below ~1e-2. The rounding terms never exceed ~1e-7 (at
    sin = ANGLE_TOL both are ~sqrt(eps), which is why ANGLE_TOL is where it is); the KEEP_TOL term
    can reach n * 1e-4 and is a reported weakness (kept frames are not snapped onto the convention).
    """
    axes = np.vstack([[0.0, 0.0, 1.0], robot.axes])
    sines = np.linalg.norm(np.cross(axes[:-1], axes[1:]), axis=1)
    skew = sines[sines >= ANGLE_TOL]
    tol = FK_TOL
    if skew.size:
        # a frame the input gave is kept when it meets the convention to KEEP_TOL; what it misses by
        # (up to KEEP_TOL in rotation) is carried by the far frames' lever arms like rounding is
        tol = max(tol, robot.n * (16 * EPS + KEEP_TOL) / float(skew.min()))
    return max(tol, 4 * float(sines[sines < ANGLE_TOL].sum()))


def same_line(p1, u1, p2, u2, scale: float, tol: float = EXACT) -> bool:
    """Do two lines coincide (same direction, distance ~0 relative to scale)?"""
    if np.abs(u1 - u2).max() > tol:
        return False
    d = p2 - p1
    return bool(np.linalg.norm(d - np.dot(d, u1) * u1) <= tol * scale)


def wrap(angle: np.ndarray) -> np.ndarray:
    """Angles to (-pi, pi], so that pi and -pi (and rounding around them) compare equal."""
    return -((-np.asarray(angle) + np.pi) % (2 * np.pi) - np.pi)


def angles_close(a, b, tol: float = EXACT) -> bool:
    diff = wrap(np.asarray(a) - np.asarray(b))
    return bool(diff.size == 0 or np.abs(diff).max() <= tol)


# ----------------------------------------------------------------------------- every pair
@settings(max_examples=250 * SCALE, **SETTINGS)
@given(spec=robot_specs(), src=st.sampled_from(REPRESENTATIONS), round_input=st.booleans(),
       seed=st.integers(0, 2**32 - 1))
def test_every_representation_converts_to_every_other(spec: RobotSpec, src: str, round_input: bool,
                                                       seed: int):
    """src -> GJD -> every representation -> GJD: FK identical at random q (single and batch)."""
    given_rep = write(spec.robot, src)
    if round_input:
        given_rep = rounded(given_rep, spec.unit)
    hub = read(given_rep)
    Q = hub.random_q(5, seed)
    reference = given_rep.fk(Q)  # FK evaluated from the input representation itself
    scale = fk_scale(spec.robot, reference)
    tol = conditioning_tol(hub) if round_input else FK_TOL
    for dst in REPRESENTATIONS:
        out = write(hub, dst)
        assert_poses_close(out.fk(Q), reference, scale, tol, what=f"{src} -> {dst}")
        assert_poses_close(read(out).fk(Q), reference, scale, tol, what=f"{src} -> {dst} -> gjd")
        assert_poses_close(out.fk(Q[0]), reference[0], scale, tol, what=f"{src} -> {dst} single q")


@settings(max_examples=30 * SCALE, **SETTINGS)
@given(spec=robot_specs(), seed=st.integers(0, 2**32 - 1))
def test_batch_fk_equals_stacked_single_fk(spec: RobotSpec, seed: int):
    robot = spec.robot
    Q = robot.random_q(7, seed)
    scale = fk_scale(robot, robot.fk(Q))
    for rep in REPRESENTATIONS:
        obj = write(robot, rep)
        stacked = np.stack([obj.fk(q) for q in Q])
        # the batch and single paths are different code (GEMM on stacked rows vs 4x4 products), so
        # they agree to rounding, not bit for bit
        assert_poses_close(obj.fk(Q), stacked, scale, tol=EXACT, what=rep)
    assert_poses_close(robot.frames_at(Q)[:, -1], robot.fk(Q), scale, tol=EXACT, what="frames_at")


@settings(max_examples=30 * SCALE, **SETTINGS)
@given(spec=robot_specs(), seed=st.integers(0, 2**32 - 1))
def test_fk_at_zero_is_the_tool_and_joint_motion_is_about_the_axis(spec: RobotSpec, seed: int):
    """FK(0) = J_{n+1}; moving one joint moves the tool by exp([S_i] q_i) about the GJD axis."""
    robot = spec.robot
    assert_poses_close(robot.fk(np.zeros(robot.n)), robot.tool, extent(robot), tol=EXACT, what="fk(0)")
    rng = np.random.default_rng(seed)
    S = robot.screws()
    i = int(rng.integers(robot.n))
    q = np.zeros(robot.n)
    q[i] = rng.uniform(-3, 3) * (1.0 if robot.joints[i].revolute else spec.unit)
    expected = se3.exp_twist(S[i], q[i]) @ robot.tool
    assert_poses_close(robot.fk(q), expected, fk_scale(robot, expected), tol=EXACT)


# ----------------------------------------------------------------------------- round trips
@settings(max_examples=150 * SCALE, **SETTINGS)
@given(spec=robot_specs())
def test_round_trips_through_the_hub_keep_the_joint_axes(spec: RobotSpec):
    """robot -> X -> GJD keeps every joint axis line (PoE: prismatic axes keep only their direction)."""
    robot = spec.robot
    for rep in REPRESENTATIONS:
        back = read(write(robot, rep))
        assert back.n == robot.n and back.joints == robot.joints
        # the DH writer takes a residual tool within KEEP_TOL of the identity as the identity
        # (dh.is_identity): the tool may move by that much, plus rounding
        assert_poses_close(back.tool, robot.tool, extent(robot), tol=EXACT + KEEP_TOL, what=f"{rep} tool")
        for i, joint in enumerate(robot.joints):
            u0, p0 = robot.axes[i], robot.points[i]
            u1, p1 = back.axes[i], back.points[i]
            if rep.startswith("poe") and not joint.revolute:
                np.testing.assert_allclose(u1, u0, atol=EXACT, err_msg=f"{rep} joint {i + 1} direction")
            else:
                # a given frame that meets the DH convention to KEEP_TOL is kept as it is; what it
                # misses by (<= KEEP_TOL in rotation) tilts the axes after it, once per joint at most
                assert same_line(p0, u0, p1, u1, extent(robot), tol=EXACT + robot.n * KEEP_TOL), \
                    f"{rep}: joint {i + 1} axis moved"


@settings(max_examples=60 * SCALE, **SETTINGS)
@given(spec=robot_specs(tiny=False))
def test_written_dh_tables_are_fixed_points(spec: RobotSpec):
    """DH -> GJD -> DH (and MDH, RPY) returns the same table: frames that satisfy the convention are kept."""
    robot = spec.robot
    assume(well_scaled(robot))
    dh = robkin.dh_from_robot(robot)
    dh2 = robkin.dh_from_robot(dh.to_robot())
    assert_tables_equal(dh2.rows[:-1], dh.rows[:-1], robot.scale)
    assert_poses_close(dh2.base, dh.base, robot.scale, tol=EXACT, what="dh base")
    # The last row moves towards a tool that no DH row may reach (the paper's eqs. 6-7); its d and a
    # are distances between nearly parallel lines when the tool's x (or z) is nearly parallel to the
    # last frame's, which amplifies the rounding of the round trip by 1 / sin of that angle.
    frames, _ = dh_frames(robot)
    kappa = last_row_conditioning(frames[-1], robot.tool)
    if np.isfinite(kappa):
        assert_tables_equal(dh2.rows[-1:], dh.rows[-1:], robot.scale, tol=EXACT * kappa)
        assert_poses_close(dh2.tool, dh.tool, robot.scale, tol=EXACT * kappa, what="dh tool")
    # whatever the last row, the table ends at the tool
    assert_poses_close(dh2.fk(np.zeros(robot.n)), robot.tool, robot.scale, tol=1e-10, what="dh fk(0)")
    mdh = robkin.mdh_from_robot(robot)
    mdh2 = robkin.mdh_from_robot(mdh.to_robot())
    assert_tables_equal(mdh2.rows, mdh.rows, robot.scale)
    assert_poses_close(mdh2.base, mdh.base, robot.scale, tol=EXACT, what="mdh base")
    assert_poses_close(mdh2.tool, mdh.tool, robot.scale, tol=EXACT, what="mdh tool")
    # Hayati: every row but the last (which moves towards the tool, as in DH) reads back unchanged
    hay = robkin.hayati_from_robot(robot)
    hay2 = robkin.hayati_from_robot(hay.to_robot())
    assert_tables_equal(hay2.rows[:-1], hay.rows[:-1], robot.scale)
    assert_poses_close(hay2.base, hay.base, robot.scale, tol=EXACT, what="hayati base")


def assert_tables_equal(rows: np.ndarray, expected: np.ndarray, scale: float, tol: float = EXACT) -> None:
    """(a, d, alpha, theta) tables equal: lengths to tol * scale, angles to tol modulo 2 pi."""
    np.testing.assert_allclose(rows[:, :2], expected[:, :2], atol=tol * scale)
    assert angles_close(rows[:, 2:], expected[:, 2:], tol), f"angles differ:\n{rows[:, 2:]}\n{expected[:, 2:]}"


def last_row_conditioning(prev: np.ndarray, target: np.ndarray) -> float:
    """1 + 1 / sin of the x-x and z-z angles between two frames (where not treated as parallel).

    inf when an angle is within a factor 2 of ANGLE_TOL: the last row's d (or a) is the distance of
    two lines taken as parallel below ANGLE_TOL and as crossing above it, and rounding noise decides
    on which side of the threshold an angle that sits on it falls (hypothesis finds such angles).
    """
    kappa = 1.0
    for k in (0, 2):
        sin = float(np.linalg.norm(np.cross(prev[:3, k], target[:3, k])))
        if ANGLE_TOL / 2 <= sin <= 2 * ANGLE_TOL:
            return np.inf
        if sin >= ANGLE_TOL:
            kappa += 1.0 / sin
    return kappa


@st.composite
def dh_tables(draw, max_joints: int = 8):
    """A hand-written DH table: special alpha/a/d values, base a DH row or identity, no residual tool."""
    n = draw(st.integers(1, max_joints))
    unit = draw(st.sampled_from([1e-3, 1.0, 1e3]))
    joints = draw(joint_lists(n))
    rows = draw(dh_rows(n, unit, tiny=False))
    base = se3.dh_matrix(*draw(dh_rows(1, unit, tiny=False))[0]) if draw(st.booleans()) else np.eye(4)
    return robkin.DHTable(rows, joints, base=base)


@settings(max_examples=60 * SCALE, **SETTINGS)
@given(table=dh_tables())
def test_hand_written_dh_table_round_trips_unchanged(table: robkin.DHTable):
    """A DH table read into the hub and written out again is the same table (angles modulo 2 pi)."""
    robot = table.to_robot()
    assume(well_scaled(robot))
    back = robkin.dh_from_robot(robot)
    assert_tables_equal(back.rows, table.rows, robot.scale)
    assert_poses_close(back.base, table.base, robot.scale, tol=EXACT, what="base")
    assert_poses_close(back.tool, np.eye(4), robot.scale, tol=EXACT, what="tool")


@st.composite
def rpy_tables(draw, max_joints: int = 8):
    """An RPY-XYZ table with angles in the canonical ranges (pitch away from gimbal lock)."""
    n = draw(st.integers(1, max_joints))
    unit = draw(st.sampled_from([1e-3, 1.0, 1e3]))
    joints = draw(joint_lists(n))
    # 1e-3 from +-pi/2: nearer gimbal lock roll and yaw are recovered with error ~eps / cos(pitch),
    # and exactly at it only their sum is defined (tested in test_se3)
    pitch = st.floats(-np.pi / 2 + 1e-3, np.pi / 2 - 1e-3)
    # roll and yaw at exactly +-pi come back as either sign; compared modulo 2 pi below
    rows = [[draw(angles), draw(pitch), draw(angles)] + [draw(st.floats(-1, 1)) * unit for _ in range(3)]
            for _ in range(n + 2)]
    return robkin.RPYTable(np.array(rows), joints)


@settings(max_examples=60 * SCALE, **SETTINGS)
@given(table=rpy_tables())
def test_rpy_table_round_trips_unchanged(table: robkin.RPYTable):
    back = robkin.rpy_from_robot(table.to_robot())
    scale = max(1.0, float(np.abs(table.rows[:, 3:]).max()))
    # angle error of a round trip through a rotation matrix: eps / cos(pitch) <= 1e-13 here
    assert angles_close(back.rows[:, :3], table.rows[:, :3], tol=1e-11)
    np.testing.assert_allclose(back.rows[:, 3:], table.rows[:, 3:], atol=EXACT * scale)


@settings(max_examples=40 * SCALE, **SETTINGS)
@given(spec=robot_specs())
def test_dh_frames_satisfy_the_convention(spec: RobotSpec):
    """Each written DH frame's x axis is the common normal: it crosses the previous z axis at 90 deg."""
    robot = spec.robot
    dh = robkin.dh_from_robot(robot)
    frames = dh.to_robot().frames
    chain = [np.eye(4)] + [f if not j.flip else f @ se3.rot_x(np.pi) for f, j in zip(frames[:-1], robot.joints)]
    for i in range(1, robot.n):
        assert satisfies_normal(chain[i + 1], chain[i][:3, 3], chain[i][:3, 2], extent(robot), tol=1e-10)


@settings(max_examples=30 * SCALE, **SETTINGS)
@given(spec=robot_specs(units=(1.0,), tiny=False))
def test_scaling_the_robot_scales_the_dh_table(spec: RobotSpec):
    """The same robot in millimetres gives the same DH table with lengths x1000 (relative tolerances)."""
    robot = spec.robot
    assume(well_scaled(robot))
    F = np.array(robot.frames)
    F[:, :3, 3] *= 1000.0
    big = Robot(F, robot.joints)
    dh, dh_mm = robkin.dh_from_robot(robot), robkin.dh_from_robot(big)
    # rows placed on the axes (all but the last): identical up to the unit
    np.testing.assert_allclose(dh_mm.rows[:-1, :2], 1000.0 * dh.rows[:-1, :2], atol=1000.0 * 1e-10 * robot.scale)
    assert angles_close(dh_mm.rows[:-1, 2:], dh.rows[:-1, 2:], tol=1e-10)
    # the last row only moves towards a tool no row may reach; its signs come from dot products that
    # can sit at the tie margin (1e-12 relative), so only the magnitudes are compared
    np.testing.assert_allclose(np.abs(dh_mm.rows[-1, :2]), 1000.0 * np.abs(dh.rows[-1, :2]),
                               atol=1000.0 * 1e-10 * robot.scale)
    Q = robot.random_q(3, 0)
    Q_mm = np.where(robot.revolute, Q, 1000.0 * Q)
    scaled = dh.fk(Q)
    scaled[:, :3, 3] *= 1000.0
    assert_poses_close(dh_mm.fk(Q_mm), scaled, 1000.0 * fk_scale(robot, dh.fk(Q)), what="mm vs m")
    relations = [classify(robot.points[i - 1], robot.axes[i - 1], robot.points[i], robot.axes[i], robot.scale)
                 for i in range(1, robot.n)]
    relations_mm = [classify(big.points[i - 1], big.axes[i - 1], big.points[i], big.axes[i], big.scale)
                    for i in range(1, robot.n)]
    assert relations == relations_mm
    assert list(relations) == [r for r in spec.relations[1:]]


# ----------------------------------------------------------------------------- regressions found here
def test_poe_prismatic_axis_after_nearly_parallel_axes_stays_near_the_robot():
    """Regression (found by test_every_representation_converts_to_every_other, rounded input).

    An RPY-XYZ table typed with 6 decimals (pi -> 3.141593) makes axes 1-2 nearly parallel, so DH-style
    frames sit ~1e6 robot sizes away. PoE -> GJD placed the prismatic joint 3
    through that far frame origin; axis 4, nearly parallel to it, then got its frame ~6e9 away and FK
    lost 1e-6 (5e-4 of the 2 mm robot). The axis now goes through the previous axis's point (the
    paper's q_i = q_{i-1}).
    """
    rows = [[0, 0, 0, 0, 0, 0], [0, 0, 1.570796, 0, 0, 0], [3.141593, 0, 2.141593, 1e-3, 0, 0],
            [1.570796, 0, 1.570796, 0, 0, 0], [3.141593, 0, 0, 1e-3, 0, 0], [-3.141593, 0, 0, 0, 0, 0],
            [0, 0, 0, 0, 0, 0]]
    joints = (Joint("j1"), Joint("j2"), Joint("j3", "prismatic"), Joint("j4", flip=True), Joint("j5"))
    table = robkin.RPYTable(rows, joints)
    robot = table.to_robot()
    Q = robot.random_q(5, 0) * np.array([1, 1, 1e-3, 1, 1])  # prismatic travel in the robot's mm size
    expected = table.fk(Q)
    tol = 1e-7  # sin ~ 3.5e-7 between the nearly parallel axes: ~eps / sin = 6e-10 expected
    for frame in ("space", "body"):
        back = robkin.poe_from_robot(robot, frame).to_robot()
        assert_poses_close(back.fk(Q), expected, robot.scale, tol, what=f"poe {frame} -> gjd")
        assert np.abs(back.frames[:, :3, 3]).max() < 1e7 * robot.scale


def test_scale_of_a_robot_along_one_line_is_its_offsets_not_rounding_noise():
    """Regression (found by test_hand_written_dh_table_round_trips_unchanged): every axis on the base
    z axis and the tool back at the origin gave Robot.scale = 1e-28 (rounding noise of the tool
    position), so every relative tolerance collapsed and a DH table no longer read back unchanged."""
    joints = (Joint("j1"), Joint("j2"), Joint("j3"))
    table = robkin.DHTable([[0, 1e-3, np.pi, 1.5], [0, 1e-3, 0, 1.0], [0, 0, 0, 0]], joints)
    robot = table.to_robot()
    assert robot.scale == pytest.approx(1e-3)
    back = robkin.dh_from_robot(robot)
    assert_tables_equal(back.rows, table.rows, robot.scale)


def test_poe_pitch_tolerance_is_relative_to_the_robot_not_to_each_screw():
    """Regression (found with PoE inputs rounded to 6 decimals, mm robot): an axis 10 um from the
    origin typed to the um has a pitch 5 % of its own |v| but 1e-3 of the robot; it is projected
    with a warning, not refused. A visibly wrong pitch is still refused."""
    joints = (Joint("j1"), Joint("j2"))
    w = np.array([0.6, 0.0, 0.8])
    near = np.concatenate([w, np.round(-np.cross(w, [0.0, 1.2e-5, 0.0]), 6)])  # pitch 4e-7
    far = np.concatenate([[0.0, 0.0, 1.0], -np.cross([0.0, 0.0, 1.0], [0.01, 0.0, 0.0])])
    with pytest.warns(ProjectionWarning, match=r"poe.screws\[0\].*pitch"):
        poe = robkin.PoE(np.eye(4), [near, far], joints)
    assert abs(np.dot(poe.screws[0, :3], poe.screws[0, 3:])) < 1e-15
    with pytest.raises(robkin.InputError, match=r"poe.screws\[0\].*pitch"):
        robkin.PoE(np.eye(4), [np.concatenate([w, [0.0, 0.0, 0.005]]), far], joints)


@settings(max_examples=5 * SCALE, **SETTINGS)
@given(spec=robot_specs(), seed=st.integers(0, 2**32 - 1))
def test_batch_fk_equals_single_fk(spec: RobotSpec, seed: int):
    """Batch FK (one compiled loop over configurations) gives each configuration's single FK, and a
    batch of one the single pose."""
    robot = spec.robot
    N = 2055
    Q = robot.random_q(N, seed)
    batch = robot.fk(Q)
    assert batch.shape == (N, 4, 4)
    pick = np.random.default_rng(seed).choice(N, 40, replace=False)
    pick[:2] = [0, N - 1]
    stacked = np.stack([robot.fk(Q[k]) for k in pick])
    assert_poses_close(batch[pick], stacked, fk_scale(robot, stacked), tol=EXACT, what="batch")
    assert_poses_close(robot.fk(Q[:1])[0], robot.fk(Q[0]), fk_scale(robot, stacked), tol=EXACT,
                       what="batch of one")


def test_coincident_axes_of_a_tiny_robot_do_not_make_a_nan_frame():
    """Regression (found by test_written_dh_tables_are_fixed_points): two anti-coincident axes on the
    base z axis and a tool 1e-9 from the base give Robot.scale = 1e-9 while the frames sit 1e-3 apart.
    The axes were classified parallel (rounding noise above LENGTH_TOL * scale), but measured from the
    anchor their normal was exactly zero: 0 / 0 made a NaN frame and mdh_from_robot raised."""
    z_down = np.diag([1.0, -1.0, -1.0])  # rot_x(pi), exactly
    frames = np.array([se3.homogeneous(se3.rot_z(np.pi / 2)[:3, :3], [0, 0, 1e-3]),
                       se3.homogeneous(se3.rot_z(np.pi / 2)[:3, :3] @ z_down, [0, 0, 0]),
                       se3.homogeneous(se3.rot_z(np.pi / 2)[:3, :3] @ z_down, [0, 0, -1e-9])])
    robot = Robot(frames, (Joint("j1"), Joint("j2", flip=True)))
    again = robkin.dh_from_robot(robot).to_robot()  # the same robot through a DH table
    Q = robot.random_q(5, 0)
    for hub in (robot, again):
        for rep in REPRESENTATIONS:
            out = write(hub, rep)
            assert np.all(np.isfinite(read(out).frames))
            assert_poses_close(out.fk(Q), robot.fk(Q), 1e-3, tol=FK_TOL, what=rep)
