"""The general 6R's eigenvalue step: the small-matrix QR routine (``hessenberg_qr.h``) against NumPy's
LAPACK, and the deflation of the 8 spurious roots x = +-i (``kinematics.general6r.spurious_complement``)."""

from __future__ import annotations

import numpy as np
import pytest

import ik_arms as arms
from robkin.compiled.ik.closed_form_general6r import eigenvalues
from robkin.kinematics.closed_form import closed_form_solver
from robkin.kinematics.general6r import General6R, spurious_complement


def matched_error(ours: np.ndarray, reference: np.ndarray) -> float:
    """The largest distance from an eigenvalue of ``reference`` to the nearest unused one of ``ours``
    (a greedy matching: multiple eigenvalues count once each)."""
    left = list(ours)
    worst = 0.0
    for x in sorted(reference, key=lambda z: (z.real, z.imag)):
        d = [abs(x - y) for y in left]
        i = int(np.argmin(d))
        worst = max(worst, d[i])
        left.pop(i)
    return worst


@pytest.mark.parametrize("n", [1, 2, 3, 4, 5, 7, 12, 16, 24, 32])
def test_eigenvalues_match_lapack_on_random_and_badly_scaled_matrices(n):
    rng = np.random.default_rng(n)
    for k in range(40):
        A = rng.standard_normal((n, n))
        if k % 2:                                   # entries spread over six orders of magnitude
            A *= 10.0 ** rng.uniform(-3, 3, (n, n))
        ours = eigenvalues(A)
        ref = np.linalg.eigvals(A)
        assert ours.shape == (n,)
        # backward-stable methods on both sides: errors ~ eps ||A|| times the eigenvalues' condition;
        # 1e-9 relative leaves room for the ill-conditioned ones random matrices have
        assert matched_error(ours, ref) <= 1e-9 * max(1.0, np.abs(ref).max())
        # conjugate pairs come exactly conjugate
        assert np.allclose(np.sort_complex(ours), np.sort_complex(ours.conj()), rtol=0, atol=0)


def test_eigenvalues_of_structured_matrices():
    # a companion matrix of known roots: real, a double root, a complex pair
    roots = np.array([-3.0, -1.0, 0.5, 2.0, 2.0, 1 + 2j, 1 - 2j])
    c = np.poly(roots).real
    C = np.zeros((7, 7))
    C[0] = -c[1:] / c[0]
    C[1:, :-1] = np.eye(6)
    # a double root is found to ~sqrt(eps) only (it splits), the others to rounding
    assert matched_error(eigenvalues(C), roots) < 1e-6
    # the cyclic permutation: every eigenvalue on the unit circle, where plain shifts stall
    # (exceptional shifts, or the LAPACK fallback, must still give every root of unity)
    P = np.roll(np.eye(16), 1, axis=0)
    assert matched_error(eigenvalues(P), np.exp(2j * np.pi * np.arange(16) / 16)) < 1e-10
    assert np.array_equal(eigenvalues(np.zeros((5, 5))), np.zeros(5))
    assert matched_error(eigenvalues(np.triu(np.arange(1.0, 17.0).reshape(4, 4))), [1, 6, 11, 16]) < 1e-12
    assert matched_error(eigenvalues([[0.0, -1.0], [1.0, 0.0]]), [1j, -1j]) < 1e-15


@pytest.mark.parametrize("bad", [np.zeros((0, 0)), np.zeros((2, 3)), np.zeros((33, 33))])
def test_eigenvalues_refuses_other_shapes(bad):
    with pytest.raises(ValueError, match="square matrix of size 1 to 32"):
        eigenvalues(bad)


def companion(M: np.ndarray) -> np.ndarray:
    """The 24 x 24 companion matrix of M0 + M1 x + M2 x^2 (M: (3, 12, 12))."""
    C = np.zeros((24, 24))
    C[:12, 12:] = np.eye(12)
    C[12:] = -np.linalg.solve(M[2], np.hstack([M[0], M[1]]))
    return C


@pytest.mark.parametrize("make", [lambda: arms.generic_6r(1), lambda: arms.parallel_pair_6r(3, 1), arms.jaco2,
                                  arms.xarm6], ids=["generic", "parallel-pair", "jaco2", "xarm6"])
def test_spurious_roots_deflate_to_the_degree_16_problem(make):
    robot = make()
    solver = closed_form_solver(robot)
    assert isinstance(solver, General6R)
    kernel = solver._kernel
    Q2 = spurious_complement(kernel, robot.scale)
    assert Q2 is not None and Q2.shape == (24, 16)
    assert np.allclose(Q2.T @ Q2, np.eye(16), atol=1e-14)
    rng = np.random.default_rng(5)
    lim = robot.limits
    q = rng.uniform(np.maximum(lim[:, 0], -np.pi), np.minimum(lim[:, 1], np.pi), (10, 6))
    for T in robot.fk(q):
        C = companion(kernel.pencil(T))
        full = np.linalg.eigvals(C)
        spurious = np.abs(np.abs(full.imag) - 1.0) + np.abs(full.real) < 1e-6
        assert spurious.sum() == 8                      # four at +i, four at -i
        # the complement's block keeps exactly the 16 others
        assert matched_error(eigenvalues(Q2.T @ C @ Q2), full[~spurious]) < 1e-9 * np.abs(full).max()
        # and the subspace it leaves out is invariant: nothing of C Q1 leaks into the complement
        P1 = np.eye(24) - Q2 @ Q2.T
        assert np.linalg.norm(Q2.T @ C @ P1) < 1e-9 * np.linalg.norm(C)


def test_deflated_and_full_problems_give_the_same_solutions():
    robot = arms.generic_6r(2)
    solver = closed_form_solver(robot)
    kernel = solver._kernel
    Q2 = spurious_complement(kernel, robot.scale)
    rng = np.random.default_rng(11)
    lim = robot.limits
    q = rng.uniform(np.maximum(lim[:, 0], -np.pi), np.minimum(lim[:, 1], np.pi), (60, 6))
    T = robot.fk(q)
    ref = np.zeros_like(q)
    deflated = solver.solve(T, ref)
    kernel.set_deflation(None)
    try:
        full = solver.solve(T, ref)
    finally:
        kernel.set_deflation(Q2)
    assert np.array_equal(deflated.valid.sum(axis=1), full.valid.sum(axis=1))
    assert deflated.valid.sum() >= 2 * len(q)           # generic arms: several branches per target
    for k in range(len(q)):
        a, b = deflated.q[k][deflated.valid[k]], full.q[k][full.valid[k]]
        # both Newton-polished to the same exact solutions: they agree to rounding
        assert np.abs(a[:, None, :] - b[None, :, :]).max(axis=2).min(axis=1).max() < 1e-10


def test_set_deflation_checks_its_shape():
    solver = closed_form_solver(arms.generic_6r(1))
    with pytest.raises(ValueError, match=r"expected a \(24, 16\) array"):
        solver._kernel.set_deflation(np.zeros((24, 8)))
