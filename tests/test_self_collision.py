"""The self-collision model: conservative capsules, the allowed-collision matrix against the SRDFs the
Panda's and UR5's maintainers ship (example-robot-data), the compiled batch check against coal's exact
mesh check, and collision-aware IK.

Sample counts here are the test's (2e4 configurations for the "Never" verification, 2e3 for the
no-false-free check); benchmarks/bench_self_collision.py runs 1e5 of each.
"""

from __future__ import annotations

import os
import re

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import robkin
from robkin.errors import InputError

from ik_arms import ROBOTS_DIR
from test_properties import SCALE as PROPERTY_SCALE

coal = pytest.importorskip("coal")

PANDA = os.path.join(ROBOTS_DIR, "panda_description", "urdf", "panda.urdf")
PANDA_SRDF = os.path.join(ROBOTS_DIR, "panda_description", "srdf", "panda.srdf")
UR5 = os.path.join(ROBOTS_DIR, "ur_description", "urdf", "ur5_joint_limited_robot.urdf")
UR5_SRDF = os.path.join(ROBOTS_DIR, "ur_description", "srdf", "ur5_joint_limited_robot.srdf")

pytestmark = pytest.mark.skipif(not os.path.isfile(PANDA), reason="example-robot-data is not installed")


def _model(path, tip, samples=20000):
    from robkin.self_collision import self_collision_model

    robot = robkin.load(path, tip_link=tip)
    return robot, self_collision_model(robot, path, samples=samples)


@pytest.fixture(scope="module")
def panda():
    return _model(PANDA, "panda_hand_tcp")


@pytest.fixture(scope="module")
def ur5():
    return _model(UR5, "tool0")


def _srdf_pairs(path):
    return {frozenset(p) for p in re.findall(r'link1="([^"]+)" link2="([^"]+)"', open(path).read())}


def _agreement(model, path):
    links = model.links
    every = [frozenset((a, b)) for i, a in enumerate(links) for b in links[i + 1:]]
    mine = {frozenset((d.link1, d.link2)) for d in model.disabled}
    theirs = _srdf_pairs(path)
    return sum((p in mine) == (p in theirs) for p in every) / len(every), mine - theirs, theirs - mine


def test_capsules_contain_the_links_surfaces(panda, ur5):
    """A link's capsules together contain every vertex of its geometry and points spread over its
    surface triangles (random barycentric points): a cut link's parts leave no gap."""
    from robkin.self_collision.capsules import point_segment_distance
    from robkin.self_collision.geometry import enclosing_triangles, link_geometry

    rng = np.random.default_rng(8)
    for (robot, model), path in ((panda, PANDA), (ur5, UR5)):
        geo = {g.name: g for g in link_geometry(robot, path)}
        for link in model.links:
            T = np.concatenate([enclosing_triangles(s) for s in geo[link].shapes])
            W = rng.dirichlet(np.ones(3), size=(len(T), 4))
            X = np.einsum("tkj,tjd->tkd", W, T).reshape(-1, 3)
            caps = [c for c in model.capsules if c.link == link]
            for pts in (T.reshape(-1, 3), X):
                inside = np.zeros(len(pts), dtype=bool)
                for c in caps:
                    inside |= point_segment_distance(pts, c.a, c.b) <= c.radius
                assert inside.all(), link
    assert len(panda[1].capsules) > len(panda[1].links)    # some links are cut into parts
    assert len([c for c in ur5[1].capsules if c.link == "base_link"]) > 1   # the flat base: strips


def test_segment_distance_against_dense_sampling():
    from robkin.compiled.collision.capsules import segment_distance

    rng = np.random.default_rng(4)
    t = np.linspace(0.0, 1.0, 401)
    for k in range(200):
        p1, q1, p2, q2 = rng.normal(size=(4, 3))
        if k % 10 == 0:
            q2 = p2.copy()          # a point (sphere)
        A = p1 + t[:, None] * (q1 - p1)
        B = p2 + t[:, None] * (q2 - p2)
        dense = np.sqrt(((A[:, None] - B[None]) ** 2).sum(-1)).min()
        got = segment_distance(p1, q1, p2, q2)
        # the dense grid's step (1/400 of each segment) bounds how far its minimum sits above the true one
        assert got <= dense + 1e-12
        assert dense - got <= (np.linalg.norm(q1 - p1) + np.linalg.norm(q2 - p2)) / 400 + 1e-12


def test_parts_apart_only_when_a_plane_separates():
    """The GJK test answers "apart" only for point sets a plane separates, and finds the plane for
    every pair that a linear program (an independent check) finds strictly separable."""
    from scipy.optimize import linprog

    from robkin.compiled.collision.parts import parts_apart

    rng = np.random.default_rng(0)
    frames = np.eye(4)[None, None]                      # one configuration, the base frame only
    separable = proven = 0
    for _ in range(400):
        A = rng.normal(size=(30, 3))
        B = rng.normal(size=(25, 3)) * rng.uniform(0.3, 1.5) + rng.normal(size=3) * rng.uniform(0, 5)
        V = np.vstack([A, B])
        # each part's bound: a capsule of no length (a ball) around its points
        ball = np.array([[*c, *c, np.linalg.norm(P - c, axis=1).max()] for P in (A, B) for c in [P.mean(axis=0)]])
        # each link one part
        got = parts_apart(frames, V, [0, 30, 55], [0, 0], ball, [0, 1, 2], [0, 1], [[0, 0, 1]])[0]
        # separable iff some w, b: A w <= b - 1 and B w >= b + 1
        lp = linprog(np.zeros(4), A_ub=np.vstack([np.c_[A, -np.ones(30)], np.c_[-B, np.ones(25)]]),
                     b_ub=-np.ones(55), bounds=[(None, None)] * 4)
        sep = lp.status == 0
        assert not (got and not sep)
        separable += sep
        proven += bool(got)
    assert separable > 100 and proven == separable

    # bad index arrays: one clear error, never a read out of bounds
    args = (frames, V, [0, 30, 55], [0, 0], ball, [0, 1, 2], [0, 1])
    with pytest.raises(ValueError, match="queries out of range"):
        parts_apart(*args, [[1, 0, 1]])
    with pytest.raises(ValueError, match="queries out of range"):
        parts_apart(*args, [[0, 0, 2]])
    with pytest.raises(ValueError, match="link parts"):
        parts_apart(frames, V, [0, 30, 55], [0, 0], ball, [0, 2, 1], [0, 1], [[0, 0, 1]])
    with pytest.raises(ValueError, match="part rows"):
        parts_apart(frames, V, [0, 30, 56], [0, 0], ball, [0, 1, 2], [0, 1], [[0, 0, 1]])
    with pytest.raises(ValueError, match="every link needs parts"):
        parts_apart(frames, V, [0, 30, 55], [0, 0], ball, [0, 2, 2], [0, 1], [[0, 0, 1]])
    with pytest.raises(ValueError, match="share one frame"):
        parts_apart(np.repeat(frames, 2, axis=1), V, [0, 30, 55], [0, 1], ball, [0, 2], [0, 1], [[0, 0, 0]])


def test_overlaps_kernel_agrees_with_capsule_distances_and_the_maps(ur5, panda):
    """``capsules.overlaps`` (the 'parts' level's first pass) gives, per configuration, exactly the link
    pairs whose capsules overlap by ``distances`` (deepest first) less those ``pairmaps.cleared``
    proves apart: the slower path it replaced, on random configurations."""
    from robkin.compiled.collision.capsules import overlaps
    from robkin.self_collision.pairmaps import cleared

    for robot, model in (ur5, panda):
        Q = robot.random_q(3000, rng=21)
        d = model.distances(Q)
        args = list(model._map_arrays())
        maps = model.pair_maps()
        for with_maps in (True, False):
            if not with_maps:
                args[2] = np.full(len(model.pairs), -1, dtype=np.intc)
            got = overlaps(robot._chain, Q, model._caps, model._frame, model._pairs, *args, 1)
            rows, cols = np.nonzero(d <= 0.0)
            if with_maps and maps:
                keep = ~cleared(maps, Q, rows, cols)
                rows, cols = rows[keep], cols[keep]
            want = {(int(r), *map(int, model._link_pairs[c])) for r, c in zip(rows, cols)}
            assert {tuple(map(int, g)) for g in got} == want
            assert len(got) == len(want)
            assert (np.diff(got[:, 0]) >= 0).all()
            index = {tuple(map(int, p)): k for k, p in enumerate(model._link_pairs)}
            depth = d[got[:, 0], [index[(int(u), int(v))] for u, v in got[:, 1:]]]
            same = np.flatnonzero(np.diff(got[:, 0]) == 0)
            assert (depth[same] <= depth[same + 1]).all()     # deepest overlap first within a configuration
        assert len(want) > 100
    robot, model = ur5
    with pytest.raises(ValueError, match="map joints"):
        bad = list(model._map_arrays())
        bad[3] = np.full_like(bad[3], robot.n)
        overlaps(robot._chain, robot.random_q(1, rng=0), model._caps, model._frame, model._pairs, *bad, 1)
    assert overlaps(robot._chain, np.full((1, robot.n), np.nan), model._caps, model._frame, model._pairs,
                    *model._map_arrays(), 1) is None


def test_panda_acm_agrees_with_the_maintainers_srdf(panda):
    _, model = panda
    fraction, only_mine, only_theirs = _agreement(model, PANDA_SRDF)
    assert fraction >= 0.95, (only_mine, only_theirs)
    reasons = {frozenset((d.link1, d.link2)): d.reason for d in model.disabled}
    assert reasons[frozenset(("panda_link0", "panda_link1"))] == "Adjacent"
    assert reasons[frozenset(("panda_link7", "panda_hand"))] == "Adjacent"   # across the empty link 8
    assert reasons[frozenset(("panda_leftfinger", "panda_rightfinger"))] == "Default"


def test_ur5_acm_and_the_pairs_its_srdf_disables_that_collide(ur5):
    """The UR5's SRDF disables three pairs that the shipped collision meshes do make touch (coal finds
    contacts at a few per cent of random configurations): the matrix keeps them checked, which costs the
    agreement those three pairs (25 of 28); every other pair agrees."""
    robot, model = ur5
    fraction, only_mine, only_theirs = _agreement(model, UR5_SRDF)
    assert not only_mine
    assert only_theirs <= {frozenset(p) for p in [("base_link", "upper_arm_link"), ("forearm_link", "wrist_2_link"),
                                                   ("forearm_link", "wrist_3_link")]}
    assert fraction >= 25 / 28
    names = model.links
    Q = robot.random_q(3000, rng=11)
    for pair in only_theirs:
        u, v = (names.index(x) for x in sorted(pair))
        assert any(model.exact.pair_collides(q, u, v) for q in Q), pair


def _verified_never(robot, model, count, seed):
    """Every 'Never' pair checked exactly at ``count`` new configurations (where its capsules meet: the
    capsules are conservative, so elsewhere the meshes cannot touch). Returns the pairs found touching."""
    from robkin.self_collision.model import SelfCollisionModel

    every = SelfCollisionModel(robot, model.capsules, [])
    index = {frozenset(p): k for k, p in enumerate(every.pairs)}
    never = [d for d in model.disabled if d.reason == "Never"]
    cols = [index[frozenset((d.link1, d.link2))] for d in never]
    Q = robot.random_q(count, rng=seed)
    meet = every.distances(Q)[:, cols] <= 0.0
    names = model.links
    found = []
    for j, d in enumerate(never):
        u, v = names.index(d.link1), names.index(d.link2)
        if any(model.exact.pair_collides(Q[k], u, v) for k in np.flatnonzero(meet[:, j])):
            found.append((d.link1, d.link2))
    return found


def test_never_pairs_are_collision_free_on_new_samples(panda, ur5):
    for robot, model in (panda, ur5):
        assert _verified_never(robot, model, 20000, seed=123) == []


def test_no_false_free_verdict_against_the_mesh_check(panda, ur5):
    """No configuration the capsules call free touches by the meshes. (The UR5's capsules of the base and
    the upper arm meet at every configuration, so its model calls none free: conservative, and the reason
    ``collides(level="parts")`` and collision-aware IK refine with the links' convex parts.)"""
    for robot, model in (panda, ur5):
        Q = robot.random_q(2000, rng=7)
        free = ~np.asarray(model.collides(Q))
        names = model.links
        pairs = [(names.index(a), names.index(b)) for a, b in model.pairs]
        false_free = [k for k in np.flatnonzero(free) if model.exact.colliding_pairs(Q[k], pairs, first=True)]
        assert false_free == []
        freed = ~np.asarray(model.collides(Q, level="parts")) & ~free     # the parts test's own verdicts
        assert not [k for k in np.flatnonzero(freed) if model.exact.colliding_pairs(Q[k], pairs, first=True)]
        assert free.mean() > 0.5 if robot.name == "panda" else True


def test_levels_parts_and_exact(ur5, panda):
    """'parts' is conservative (never free where the meshes touch) and tighter than the capsules; 'exact'
    is coal's verdict on every checked pair."""
    for robot, model in (ur5, panda):
        Q = robot.random_q(400, rng=2)
        rough = np.asarray(model.collides(Q))
        parts = np.asarray(model.collides(Q, level="parts"))
        exact = np.asarray(model.collides(Q, level="exact"))
        assert (exact <= parts).all() and (parts <= rough).all()
        names = model.links
        pairs = [(names.index(a), names.index(b)) for a, b in model.pairs]
        for k in range(len(Q)):
            assert exact[k] == bool(model.exact.colliding_pairs(Q[k], pairs, first=True))
    assert parts.sum() < rough.sum() or not rough.any()
    robot, model = ur5
    Q = robot.random_q(400, rng=3)
    assert np.asarray(model.collides(Q, level="parts")).mean() < 0.5 < np.asarray(model.collides(Q)).mean()
    with pytest.raises(InputError, match="level"):
        model.collides(Q, level="meshes")


def test_robot_methods_shapes_batches_and_threads(panda):
    robot, model = panda
    Q = robot.random_q(500, rng=3)
    one = robot.self_collision(Q[0])
    assert isinstance(one, bool)
    many = robot.self_collision(Q)
    assert many.dtype == bool and many.shape == (500,)
    assert [robot.self_collision(q) for q in Q[:50]] == list(many[:50])
    assert np.array_equal(robot.self_collision(Q, threads=1), robot.self_collision(Q, threads=2))
    d = robot.self_collision_distances(Q)
    assert d.shape == (500, len(model.pairs))
    assert np.array_equal((d <= 0).any(axis=1), many)
    assert np.array_equal(robot.self_collision_distances(Q[4]), d[4])
    near = model.closest(Q[4], 3)
    assert [x[2] for x in near] == sorted(d[4])[:3]
    with pytest.raises(InputError):
        robot.self_collision(np.zeros(3))
    with pytest.raises(InputError):
        robot.self_collision(np.full(robot.n, np.nan))


def test_with_disabled_from_the_shipped_srdf(panda):
    from robkin.io.srdf import read_srdf
    from robkin.self_collision.model import DisabledPair

    robot, model = panda
    _, pairs = read_srdf(PANDA_SRDF)
    other = model.with_disabled([DisabledPair(*p) for p in pairs])
    assert len(other.pairs) == 55 - len(pairs)
    with pytest.raises(InputError, match="no collision geometry"):
        model.with_disabled([DisabledPair("panda_link1", "nowhere", "Never")])


@pytest.fixture(scope="module")
def iiwa():
    """rtbdata's KUKA LBR iiwa 14 R820, which has collision meshes (tests/data/iiwa14.urdf has none)."""
    rtbdata = pytest.importorskip("rtbdata")
    from pathlib import Path

    from robkin.self_collision import self_collision_model

    folder = Path(rtbdata.__file__).parent / "xacro" / "kuka_description" / "kuka_lbr_iiwa"
    urdf = folder / "urdf" / "lbr_iiwa_14_r820.urdf"
    if not urdf.is_file():
        pytest.skip("rtbdata has no iiwa")
    robot = robkin.load(urdf)
    return robot, self_collision_model(robot, urdf, package_paths={"kuka_lbr_iiwa_support": folder}, samples=5000)


@pytest.mark.parametrize("which", ["panda", "ur5", "iiwa"])
def test_collision_free_ik(which, request):
    robot, model = request.getfixturevalue(which)
    rng = np.random.default_rng(5)
    Q = robot.random_q(1500, rng=rng)
    free = ~np.asarray(model.collides(Q, level="exact"))
    T = robot.fk(Q[free][:150])
    plain = robot.ik(T)
    res = robot.ik(T, avoid_self_collision=True)
    assert res.success.mean() >= 0.99
    ok = res.success
    assert not np.asarray(model.collides(res.q[ok], level="exact")).any()
    lo, hi = robot.limits.T
    assert ((res.q[ok] >= lo) & (res.q[ok] <= hi)).all()
    assert (res.position_error[ok] <= 1e-9).all() and (res.orientation_error[ok] <= 1e-9).all()
    assert np.allclose(robot.fk(res.q[ok]), T[ok], atol=1e-8)
    if which == "ur5":   # the closed form's preferred branch collides for some targets: another one is taken
        moved = np.asarray(model.collides(plain.q[plain.success], level="exact"))
        assert moved.any()
    one = robot.ik(T[0], avoid_self_collision=True, all_solutions=True)
    assert one.success and not np.asarray(model.collides(one.solutions, level="exact")).any()


def test_ur5_pair_maps_never_call_a_touching_configuration_free(ur5):
    """The 'parts' level's tables (pairs one or two joints move against each other, once a link turned about
    a joint's axis takes that joint out): the UR5's upper arm over its base, forearm beside its second
    wrist link and flange are mapped, most of their joint box is proven apart, and no configuration in a
    proven cell touches by coal's exact check (an independent peer)."""
    from robkin.self_collision.pairmaps import cleared

    robot, model = ur5
    maps = {model.pairs[m.pair]: m for m in model.pair_maps()}
    assert ("base_link", "upper_arm_link") in maps and ("forearm_link", "wrist_2_link") in maps
    # three joints apart, mapped over two with the flange turned about its own joint's axis
    assert [model.links[k] for k in maps[("forearm_link", "wrist_3_link")].revolved] == ["wrist_3_link"]
    links = model.links
    Q = robot.random_q(3000, rng=11)
    for (a, b), m in maps.items():
        assert m.free.mean() > 0.5, (a, b)
        proven = cleared([m], Q, np.arange(len(Q)), np.full(len(Q), m.pair))
        # where the capsules meet (elsewhere they already prove the pair apart)
        near = np.flatnonzero(proven & (model.distances(Q)[:, m.pair] <= 0.0))[:300]
        assert len(near) > 10 or (a, b) not in (("base_link", "upper_arm_link"), ("forearm_link", "wrist_2_link"))
        touching = [k for k in near if model.exact.pair_collides(Q[k], links.index(a), links.index(b))]
        assert not touching, (a, b, Q[touching[:3]])


def test_the_model_kept_for_a_robot_goes_with_it():
    """The model ``Robot.self_collision`` uses is kept on the robot object, so a robot no longer used is
    freed with its model (a WeakKeyDictionary keyed by the robot never freed them: the model refers to
    its robot)."""
    import gc
    import weakref

    robot, model = _model(UR5, "tool0", samples=50)
    assert robot.self_collision(np.zeros(robot.n)) == model.collides(np.zeros(robot.n))
    gone = weakref.ref(robot)
    del robot, model
    gc.collect()
    assert gone() is None


@settings(max_examples=max(20, 40 * PROPERTY_SCALE), deadline=None)
@given(st.integers(0, 2**32 - 1), st.floats(-np.pi, np.pi), st.integers(3, 40))
def test_revolved_polytope_contains_every_turned_copy(seed, angle, k):
    """``revolve.revolved`` contains the points turned by any angle about z (each point's circle inside
    its polygon, the hull of the polygons around them all), and turning by ``axis`` reaches a joint's
    axis in a body's frame: the turned points of a link about joint 1 of the UR5 stay inside."""
    from scipy.spatial import ConvexHull

    from robkin.self_collision.revolve import revolved

    rng = np.random.default_rng(seed)
    P = rng.normal(size=(k, 3)) * rng.uniform(0.01, 2.0, size=3) + rng.normal(size=3)
    assume(np.linalg.matrix_rank(P - P.mean(axis=0), tol=1e-6) == 3)
    R = revolved(P)
    c, s = np.cos(angle), np.sin(angle)
    turned = P @ np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
    hull = ConvexHull(R)
    # every facet's inequality n . x + d <= 0 holds (to rounding of the coordinates' size)
    slack = hull.equations[:, :3] @ turned.T + hull.equations[:, 3:]
    assert slack.max() <= 1e-9 * (1.0 + np.abs(P).max())


def test_axis_frame_is_the_next_joints_axis_in_the_bodys_frame(ur5):
    """``revolve.axis_frame``: joint b+1's frame in body b's coordinates; turning joint b+1 by any angle
    moves body b+1 exactly as a rotation about that frame's z axis (checked with the robot's own
    frames at random configurations)."""
    from robkin.self_collision.revolve import axis_frame

    robot, _ = ur5
    rng = np.random.default_rng(3)
    for body in range(robot.n):
        A = axis_frame(robot.frames, body, body + 1)
        q = robot.random_q(1, rng=rng)[0]
        q2 = q.copy()
        q2[body] += 0.7
        F1, F2 = robot.frames_at(q), robot.frames_at(q2)
        base = np.eye(4) if body == 0 else F1[body - 1]
        assert np.allclose(base, np.eye(4) if body == 0 else F2[body - 1], atol=1e-12)
        # body b+1's frame, seen from body b, turned about A's z axis by 0.7
        c, s = np.cos(0.7), np.sin(0.7)
        Rz = np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])
        rel1 = np.linalg.solve(base, F1[body])
        rel2 = np.linalg.solve(base, F2[body])
        assert np.allclose(rel2, A @ Rz @ np.linalg.solve(A, rel1), atol=1e-9)


def test_numeric_retry_only_where_the_closed_form_may_not_list_every_solution(ur5):
    """The UR5's closed form (three-parallel-6r) lists every solution of a regular target: a target with
    the elbow folded back (every branch colliding) fails at once, "every solution found is in self
    collision", with no numeric retry; the same target with the wrist straight (q5 = 0, a continuum of
    wrist solutions) is retried numerically."""
    from robkin.kinematics.ik import ik
    from robkin.self_collision.ik import MESSAGE, collision_free_ik

    robot, model = ur5
    calls: list[str | None] = []

    def counting(*args, **kwargs):
        calls.append(kwargs.get("method"))
        return ik(*args, **kwargs)

    folded = np.array([-0.575, -2.857, -2.835, 3.136, 0.957, -1.668])
    every = robot.ik(robot.fk(folded), all_solutions=True).solutions
    assert len(every) == 8 and np.asarray(model.collides(every, level="parts")).all()
    res = collision_free_ik(counting, robot, robot.fk(folded), model=model)
    assert not res.success and res.message == MESSAGE and np.isnan(res.q).all()
    assert "numeric" not in calls and res.method == "three-parallel-6r"
    calls.clear()
    straight = folded.copy()
    straight[4] = 0.0
    assert np.asarray(model.collides(robot.ik(robot.fk(straight), all_solutions=True).solutions, level="parts")).all()
    collision_free_ik(counting, robot, robot.fk(straight), model=model)
    assert "numeric" in calls


def test_first_free_is_each_groups_first_collision_free_row(ur5):
    """``self_collision.ik._first_free`` (rounds, then the few rows left at once) gives each group's first
    row that the model calls free, or -1: the same as checking every row, on groups of random sizes."""
    from robkin.self_collision.ik import _first_free

    robot, model = ur5
    rng = np.random.default_rng(8)
    for _ in range(20):
        counts = rng.integers(0, 9, size=rng.integers(1, 40))
        G = robot.random_q(int(counts.sum()), rng=rng)
        hit = np.asarray(model.collides(G, level="parts"), dtype=bool) if len(G) else np.zeros(0, bool)
        want, at = [], 0
        for c in counts:
            free = np.flatnonzero(~hit[at:at + c])
            want.append(at + free[0] if len(free) else -1)
            at += c
        assert _first_free(model, G, counts, "parts", None).tolist() == want


def test_branch_source_lists_the_solutions_all_solutions_lists(ur5):
    """``kinematics.ik.solve_with_branches`` answers as ``ik`` and keeps the closed-form branches: its
    ``solutions(rows)`` are, for those targets, exactly the rows ``ik(..., all_solutions=True)`` lists (no
    second solve); collision-free IK through it (a batch: the folded target of the test above among
    free ones) makes no numeric retry either, and the same answers as without it."""
    from robkin.kinematics.ik import ik, solve_with_branches
    from robkin.self_collision.ik import MESSAGE, collision_free_ik

    robot, model = ur5
    T = robot.fk(robot.random_q(40, rng=4))
    res, source = solve_with_branches(robot, T)
    plain = ik(robot, T)
    assert np.array_equal(res.q, plain.q) and source is not None
    rows = np.array([3, 7, 21])
    every = ik(robot, T, all_solutions=True).solutions
    for got, want in zip(source.solutions(rows), [every[i] for i in rows]):
        assert np.array_equal(got, want)
    folded = np.array([-0.575, -2.857, -2.835, 3.136, 0.957, -1.668])
    batch = np.concatenate([T[:5], robot.fk(folded)[None]])
    calls: list[str] = []

    def counting_solve(*args, **kwargs):
        calls.append("solve")
        return solve_with_branches(*args, **kwargs)

    def counting_ik(*args, **kwargs):
        calls.append(f"ik {kwargs.get('method')} all={kwargs.get('all_solutions')}")
        return ik(*args, **kwargs)

    with_source = collision_free_ik(counting_ik, robot, batch, model=model, solve=counting_solve)
    assert calls == ["solve"]       # no second solve for the other branches, no numeric retry
    calls.clear()
    without = collision_free_ik(counting_ik, robot, batch, model=model)
    assert calls[0] == "ik None all=False" and "ik numeric all=False" not in calls
    assert with_source.message[5] == MESSAGE and not with_source.success[5]
    assert np.array_equal(with_source.success, without.success)
    assert np.array_equal(with_source.q[with_source.success], without.q[without.success])


def test_cli_ik_collision_free(ur5, capsys):
    """``robkin ik --collision-free``: a target whose every solution collides (the folded UR5) is answered
    with no solution and that reason (exit 0, as any target without a solution), a free one with a
    solution the meshes call free; --srdf reads the matrix (the maintainers' SRDF), and --srdf alone is
    refused (exit 2, one line)."""
    import json

    from robkin.cli import main

    robot, model = ur5
    path = os.path.join(ROBOTS_DIR, "ur_description/urdf/ur5_joint_limited_robot.urdf")
    srdf = os.path.join(ROBOTS_DIR, "ur_description/srdf/ur5_joint_limited_robot.srdf")

    def pose(q):
        return ",".join(repr(float(v)) for v in robot.fk(np.asarray(q, dtype=float)).ravel())

    folded = pose([-0.575, -2.857, -2.835, 3.136, 0.957, -1.668])
    assert main(["ik", path, "--tip-link", "tool0", "--pose", folded, "--collision-free", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert not out["success"] and "self collision" in out["reason"]
    free = pose([0.3, -1.2, 1.4, -1.8, -1.5, 0.2])
    assert main(["ik", path, "--tip-link", "tool0", "--pose", free, "--collision-free", "--srdf", srdf,
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    q = np.array(out["solutions"][0]["q"])
    assert out["success"] and not model.collides(q, level="exact")
    assert main(["ik", path, "--tip-link", "tool0", "--pose", free, "--srdf", srdf]) == 2
    err = capsys.readouterr().err.strip()
    assert err == "robkin: error: --srdf: goes with --collision-free"


def test_near_singular_sees_a_redundant_arm_and_a_straight_wrist(ur5):
    """``self_collision.ik._near_singular`` (which keeps the numeric retry): the bundled 5-joint SCARA,
    whose two joints along its axis share the travel (a continuum of solutions at every target), is
    near singular everywhere; the UR5 with its wrist straight (q5 = 0) is, and at a generic
    configuration it is not; a target with no solution found is not."""
    from robkin.examples import EXAMPLES_DIR
    from robkin.self_collision.ik import _near_singular

    scara = robkin.load(os.path.join(EXAMPLES_DIR, "scara.yaml"))
    assert _near_singular(scara, [q[None] for q in scara.random_q(20, rng=1)]).all()
    robot, _ = ur5
    generic = np.array([0.3, -1.2, 1.4, -0.8, 1.1, 0.5])
    straight = generic.copy()
    straight[4] = 0.0
    assert _near_singular(robot, [generic[None], straight[None], np.empty((0, 6))]).tolist() == [False, True, False]
