"""SE(3)/SO(3) helpers against independent references: scipy's Rotation and matrix exponential,
numpy's general inverse, and products of elementary matrices written out by hand."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm, polar
from scipy.spatial.transform import Rotation

from robkin import se3

#: rounding noise of a few products of unit-size numbers, with margin
EXACT = 1e-12


def random_poses(rng: np.random.Generator, size: int) -> np.ndarray:
    R = Rotation.random(size, random_state=rng).as_matrix()
    return se3.homogeneous(R, rng.normal(size=(size, 3)))


def twist_matrix(S: np.ndarray) -> np.ndarray:
    """[S] in se(3) as a 4x4 matrix, S = (w, v)."""
    out = np.zeros((4, 4))
    out[:3, :3] = se3.skew(S[:3])
    out[:3, 3] = S[3:]
    return out


# ----------------------------------------------------------------------------- elementary
def test_elementary_rotations_and_translation():
    c, s = np.cos(0.3), np.sin(0.3)
    np.testing.assert_allclose(se3.rot_x(0.3)[:3, :3], [[1, 0, 0], [0, c, -s], [0, s, c]], atol=EXACT)
    np.testing.assert_allclose(se3.rot_y(0.3)[:3, :3], [[c, 0, s], [0, 1, 0], [-s, 0, c]], atol=EXACT)
    np.testing.assert_allclose(se3.rot_z(0.3)[:3, :3], [[c, -s, 0], [s, c, 0], [0, 0, 1]], atol=EXACT)
    for f, axis in ((se3.rot_x, "x"), (se3.rot_y, "y"), (se3.rot_z, "z")):
        np.testing.assert_allclose(f(-1.2)[:3, :3], Rotation.from_euler(axis, -1.2).as_matrix(), atol=EXACT)
    T = se3.trans(1.0, 2.0, 3.0)
    np.testing.assert_array_equal(T, [[1, 0, 0, 1], [0, 1, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]])


def test_elementary_batches_broadcast():
    angles = np.linspace(-3, 3, 6).reshape(2, 3)
    R = se3.rot_z(angles)
    assert R.shape == (2, 3, 4, 4)
    np.testing.assert_allclose(R[1, 2], se3.rot_z(angles[1, 2]), atol=0)
    T = se3.trans(np.arange(3.0), 0.0, 5.0)
    assert T.shape == (3, 4, 4)
    np.testing.assert_array_equal(T[:, :3, 3], [[0, 0, 5], [1, 0, 5], [2, 0, 5]])


def test_skew_is_the_cross_product():
    rng = np.random.default_rng(0)
    w, v = rng.normal(size=(5, 3)), rng.normal(size=(5, 3))
    np.testing.assert_allclose(np.einsum("nij,nj->ni", se3.skew(w), v), np.cross(w, v), atol=EXACT)
    np.testing.assert_array_equal(se3.skew(w), -np.swapaxes(se3.skew(w), -1, -2))


def test_homogeneous_broadcasts_rotation_and_translation():
    R = Rotation.random(4, random_state=1).as_matrix()
    T = se3.homogeneous(R, [1.0, 2.0, 3.0])
    assert T.shape == (4, 4, 4)
    np.testing.assert_array_equal(T[:, :3, :3], R)
    np.testing.assert_array_equal(T[:, 3], np.broadcast_to([0, 0, 0, 1.0], (4, 4)))


def test_inverse_matches_general_inverse_single_and_batch():
    rng = np.random.default_rng(2)
    T = random_poses(rng, 10).reshape(2, 5, 4, 4)
    np.testing.assert_allclose(se3.inv(T), np.linalg.inv(T), atol=EXACT)
    np.testing.assert_allclose(se3.inv(T[0, 0]) @ T[0, 0], np.eye(4), atol=EXACT)
    np.testing.assert_array_equal(se3.inv(T)[..., 3, :], np.broadcast_to([0, 0, 0, 1.0], (2, 5, 4)))


# ----------------------------------------------------------------------------- RPY
def test_matrix_from_rpy_is_urdf_convention():
    """R = Rz(yaw) Ry(pitch) Rx(roll): scipy's extrinsic 'xyz' (x first, about fixed axes)."""
    rng = np.random.default_rng(3)
    rpy = rng.uniform(-np.pi, np.pi, size=(20, 3))
    np.testing.assert_allclose(se3.matrix_from_rpy(rpy), Rotation.from_euler("xyz", rpy).as_matrix(), atol=EXACT)
    r, p, y = rpy[0]
    np.testing.assert_allclose(se3.matrix_from_rpy(rpy[0]),
                               (se3.rot_z(y) @ se3.rot_y(p) @ se3.rot_x(r))[:3, :3], atol=EXACT)


def test_rpy_round_trip_away_from_gimbal_lock():
    rng = np.random.default_rng(4)
    rpy = np.column_stack([rng.uniform(-np.pi, np.pi, 500), rng.uniform(-1.5, 1.5, 500),
                           rng.uniform(-np.pi, np.pi, 500)])
    back = se3.rpy_from_matrix(se3.matrix_from_rpy(rpy))
    np.testing.assert_allclose(back, rpy, atol=1e-12)  # |pitch| <= 1.5: cos(pitch) >= 0.07
    # and scipy agrees on the angles
    np.testing.assert_allclose(back, Rotation.from_matrix(se3.matrix_from_rpy(rpy)).as_euler("xyz"), atol=1e-10)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_rpy_at_gimbal_lock_sets_roll_zero_and_rebuilds_the_matrix(sign):
    rng = np.random.default_rng(5)
    for roll, yaw in rng.uniform(-np.pi, np.pi, size=(50, 2)):
        R = se3.matrix_from_rpy([roll, sign * np.pi / 2, yaw])
        r, p, y = se3.rpy_from_matrix(R)
        assert r == 0.0
        assert p == pytest.approx(sign * np.pi / 2, abs=1e-15)
        np.testing.assert_allclose(se3.matrix_from_rpy([r, p, y]), R, atol=EXACT)
        # only yaw - sign * roll is defined at the lock (Rz(y) Ry(+-pi/2) Rx(r) = Rz(y -+ r) Ry(+-pi/2))
        assert np.cos(y - (yaw - sign * roll)) == pytest.approx(1.0, abs=1e-12)


@pytest.mark.parametrize("cos_pitch", [1e-4, 1e-6, 6e-8, 1e-9, 1e-11, 1e-13])
def test_rpy_near_gimbal_lock_rebuilds_the_matrix_to_rounding(cos_pitch):
    """Regression: roll and yaw were read independently near the lock, so R rebuilt from them was off
    by up to ~eps / cos(pitch) (1e-7 at cos(pitch) = 1e-9). Matrices built by scipy (other rounding)."""
    rng = np.random.default_rng(6)
    worst = 0.0
    for _ in range(300):
        roll, yaw = rng.uniform(-np.pi, np.pi, 2)
        pitch = rng.choice([-1.0, 1.0]) * (np.pi / 2 - cos_pitch)
        R = Rotation.from_euler("xyz", [roll, pitch, yaw]).as_matrix()
        worst = max(worst, np.abs(se3.matrix_from_rpy(se3.rpy_from_matrix(R)) - R).max())
    assert worst < 4 * np.finfo(float).eps * 3  # a few roundings of unit-size entries


def test_rpy_batch_equals_stacked_single():
    rng = np.random.default_rng(7)
    R = Rotation.random(24, random_state=rng).as_matrix()
    R[3] = se3.matrix_from_rpy([0.3, np.pi / 2, -1.0])  # one at the lock inside the batch
    batch = se3.rpy_from_matrix(R.reshape(4, 6, 3, 3))
    assert batch.shape == (4, 6, 3)
    np.testing.assert_array_equal(batch.reshape(24, 3), np.stack([se3.rpy_from_matrix(r) for r in R]))


# ----------------------------------------------------------------------------- exponential and adjoint
def random_screws(rng: np.random.Generator, size: int, revolute: bool) -> np.ndarray:
    if revolute:
        w = rng.normal(size=(size, 3))
        w /= np.linalg.norm(w, axis=1, keepdims=True)
        p = rng.normal(size=(size, 3))
        return np.hstack([w, -np.cross(w, p)])
    v = rng.normal(size=(size, 3))
    return np.hstack([np.zeros((size, 3)), v / np.linalg.norm(v, axis=1, keepdims=True)])


@pytest.mark.parametrize("revolute", [True, False])
def test_exp_twist_matches_matrix_exponential(revolute):
    rng = np.random.default_rng(8)
    S = random_screws(rng, 20, revolute)
    q = rng.uniform(-4, 4, 20)
    E = se3.exp_twist(S, q)
    for Si, qi, Ei in zip(S, q, E):
        np.testing.assert_allclose(Ei, expm(twist_matrix(Si) * qi), atol=1e-11)  # expm's own accuracy


def test_exp_twist_batches_broadcast_screws_against_angles():
    rng = np.random.default_rng(9)
    S = random_screws(rng, 3, True)
    Q = rng.uniform(-3, 3, size=(5, 3))
    E = se3.exp_twist(S, Q)  # (5, 3, 4, 4): every row of Q against the 3 screws
    assert E.shape == (5, 3, 4, 4)
    np.testing.assert_allclose(E[4, 1], se3.exp_twist(S[1], Q[4, 1]), atol=0)
    np.testing.assert_allclose(se3.exp_twist(S[0], 0.0), np.eye(4), atol=0)


def test_exp_twist_of_revolute_screw_rotates_about_its_axis():
    """A point on the axis stays; the axis direction is kept; a quarter turn about z through (1, 0, 0)."""
    S = np.array([0, 0, 1.0, 0, -1.0, 0])  # w = z, p = (1, 0, 0): v = -w x p = (0, -1, 0)
    E = se3.exp_twist(S, np.pi / 2)
    np.testing.assert_allclose(E @ [1, 0, 5, 1], [1, 0, 5, 1], atol=EXACT)
    np.testing.assert_allclose(E @ [2, 0, 0, 1], [1, 1, 0, 1], atol=EXACT)


def test_adjoint_maps_twists_by_conjugation():
    """[Ad_T S] = T [S] T^-1 for random poses and twists."""
    rng = np.random.default_rng(10)
    T = random_poses(rng, 20)
    S = rng.normal(size=(20, 6))
    AdS = np.einsum("nij,nj->ni", se3.adjoint(T), S)
    for Ti, Si, AdSi in zip(T, S, AdS):
        np.testing.assert_allclose(twist_matrix(AdSi), Ti @ twist_matrix(Si) @ np.linalg.inv(Ti), atol=EXACT)
    # Ad is a homomorphism: Ad_{AB} = Ad_A Ad_B, Ad_{T^-1} = Ad_T^-1
    np.testing.assert_allclose(se3.adjoint(T[0] @ T[1]), se3.adjoint(T[0]) @ se3.adjoint(T[1]), atol=EXACT)
    np.testing.assert_allclose(se3.adjoint(se3.inv(T)), np.linalg.inv(se3.adjoint(T)), atol=1e-10)


def test_exp_of_adjoint_screw_is_conjugated_exp():
    """exp([Ad_T S] q) = T exp([S] q) T^-1: the identity behind body-frame PoE."""
    rng = np.random.default_rng(11)
    T = random_poses(rng, 1)[0]
    S = random_screws(rng, 1, True)[0]
    lhs = se3.exp_twist(se3.adjoint(T) @ S, 0.7)
    np.testing.assert_allclose(lhs, T @ se3.exp_twist(S, 0.7) @ se3.inv(T), atol=EXACT)


# ----------------------------------------------------------------------------- projections
def test_nearest_rotation_is_the_polar_factor():
    rng = np.random.default_rng(12)
    R = Rotation.random(20, random_state=rng).as_matrix()
    M = R + rng.normal(scale=1e-2, size=R.shape)
    P = se3.nearest_rotation(M)
    for Mi, Pi in zip(M, P):
        U, _ = polar(Mi)  # the orthogonal polar factor is the nearest orthogonal matrix
        np.testing.assert_allclose(Pi, U, atol=1e-12)
        assert np.linalg.det(Pi) == pytest.approx(1.0)
    np.testing.assert_allclose(se3.nearest_rotation(R), R, atol=EXACT)  # rotations are fixed points


def test_nearest_rotation_of_a_reflection_is_a_proper_rotation():
    M = np.diag([1.0, 1.0, -1.0]) + 1e-3
    P = se3.nearest_rotation(M)
    np.testing.assert_allclose(P @ P.T, np.eye(3), atol=EXACT)
    assert np.linalg.det(P) == pytest.approx(1.0)
    # no rotation sampled at random is closer to M
    rng = np.random.default_rng(13)
    best = np.linalg.norm(M - P)
    assert all(np.linalg.norm(M - Q) >= best for Q in Rotation.random(2000, random_state=rng).as_matrix())


def test_rotation_error():
    R = Rotation.random(3, random_state=14).as_matrix()
    np.testing.assert_allclose(se3.rotation_error(R), 0.0, atol=EXACT)
    M = R[0].copy()
    M[0, 0] += 1e-3
    assert 1e-4 < se3.rotation_error(M) < 1e-3
    assert se3.rotation_error(np.diag([1.0, 1.0, -1.0])) == np.inf


def test_log_rotation_inverts_the_exponential():
    rng = np.random.default_rng(15)
    v = rng.normal(size=(50, 3))
    v *= (rng.uniform(0, np.pi - 1e-3, 50) / np.linalg.norm(v, axis=1))[:, None]
    R = np.stack([expm(se3.skew(vi)) for vi in v])
    np.testing.assert_allclose(se3.log_rotation(R), v, atol=1e-10)
    assert se3.log_rotation(R.reshape(5, 10, 3, 3)).shape == (5, 10, 3)


# ----------------------------------------------------------------------------- DH link transforms
def test_dh_matrix_is_the_product_of_its_four_motions():
    rng = np.random.default_rng(16)
    a, d, alpha, theta = rng.uniform(-2, 2, size=(4, 10))
    expected = se3.rot_z(theta) @ se3.trans(0, 0, d) @ se3.trans(a, 0, 0) @ se3.rot_x(alpha)
    np.testing.assert_allclose(se3.dh_matrix(a, d, alpha, theta), expected, atol=EXACT)


def test_mdh_matrix_is_the_product_of_its_four_motions():
    rng = np.random.default_rng(17)
    a, d, alpha, theta = rng.uniform(-2, 2, size=(4, 10))
    expected = se3.rot_x(alpha) @ se3.trans(a, 0, 0) @ se3.rot_z(theta) @ se3.trans(0, 0, d)
    np.testing.assert_allclose(se3.mdh_matrix(a, d, alpha, theta), expected, atol=EXACT)


def test_quaternion_from_matrix_matches_scipy():
    """(w, x, y, z), w >= 0, against scipy's Rotation, including the four branches of the method
    (trace largest, and each diagonal entry largest: rotations by pi about x, y, z)."""
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(5)
    R = np.concatenate([Rotation.random(200, random_state=rng).as_matrix(),
                        [se3.rot_x(np.pi)[:3, :3], se3.rot_y(np.pi - 1e-9)[:3, :3], se3.rot_z(-np.pi)[:3, :3],
                         np.eye(3)]])
    xyzw = Rotation.from_matrix(R).as_quat()
    expected = np.where(xyzw[:, 3:] < 0, -xyzw, xyzw)[:, [3, 0, 1, 2]]
    got = se3.quaternion_from_matrix(R)
    # Shepperd's method is accurate to rounding in every component (no square root of a small number)
    np.testing.assert_allclose(got, expected, atol=1e-15)
    np.testing.assert_allclose(se3.quaternion_from_matrix(R[3]), got[3])
    assert np.all(got[:, 0] >= 0)


def test_cross_equals_numpy_cross_with_broadcasting():
    rng = np.random.default_rng(11)
    a, b = rng.normal(size=(5, 4, 3)), rng.normal(size=(4, 3))
    np.testing.assert_allclose(se3.cross(a, b), np.cross(a, b), rtol=0, atol=1e-15)
    assert se3.cross([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]).tolist() == [0.0, 0.0, 1.0]
