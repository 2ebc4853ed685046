"""The compiled bounded least-squares solver (``robkin.compiled.runtime.box_lsq``) against scipy's
``least_squares`` (an independent implementation: trust-region reflective) on problems with known optima."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import least_squares

from robkin.compiled.runtime.box_lsq import MESSAGES, solve


def rosenbrock(x):
    return np.array([10.0 * (x[1] - x[0] ** 2), 1.0 - x[0]])


def rosenbrock_jac(x):
    return np.array([[-20.0 * x[0], 10.0], [-1.0, 0.0]])


def test_rosenbrock_unbounded_reaches_the_zero_residual_optimum():
    x, cost, nfev, njev, status = solve(rosenbrock, rosenbrock_jac, [-1.2, 1.0], [-np.inf] * 2, [np.inf] * 2,
                                        rtol=1e-12, max_nfev=500)
    assert status == 4 and MESSAGES[status]
    # |r| <= 1e-12 at the optimum (1, 1), whose Jacobian is well conditioned: x within ~1e-12 of it
    np.testing.assert_allclose(x, [1.0, 1.0], atol=1e-10)
    assert cost <= 0.5e-24 and nfev <= 500 and njev <= nfev


def test_optimum_on_a_bound_matches_scipy():
    """x_0 <= 0.5: the constrained optimum is (0.5, 0.25) with the bound active, as scipy finds."""
    lo, hi = np.array([-2.0, -2.0]), np.array([0.5, 2.0])
    x, cost, *_ , status = solve(rosenbrock, rosenbrock_jac, [-1.2, 1.0], lo, hi, ftol=1e-15, xtol=1e-15,
                                 gtol=1e-12, max_nfev=1000)
    ref = least_squares(rosenbrock, [-1.2, 1.0], jac=rosenbrock_jac, bounds=(lo, hi), method="trf",
                        ftol=1e-15, xtol=1e-15, gtol=1e-15)
    assert status > 0
    # both stop within ~1e-8 of the analytic optimum (bound active, y = x^2), the tolerances' scale
    np.testing.assert_allclose(x, [0.5, 0.25], atol=1e-7)
    np.testing.assert_allclose(ref.x, [0.5, 0.25], atol=1e-7)
    assert cost == pytest.approx(ref.cost, rel=1e-7)


def _exp_fit(seed):
    """Fit y = c0 exp(-c1 t) + c2 exp(-c3 t) to noisy data: a nonzero-residual problem (4 unknowns)."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 4.0, 30)
    y = 2.0 * np.exp(-1.3 * t) + 0.5 * np.exp(-0.2 * t) + 0.01 * rng.normal(size=t.size)

    def fun(c):
        return c[0] * np.exp(-c[1] * t) + c[2] * np.exp(-c[3] * t) - y

    def jac(c):
        e1, e3 = np.exp(-c[1] * t), np.exp(-c[3] * t)
        return np.column_stack([e1, -c[0] * t * e1, e3, -c[2] * t * e3])

    return fun, jac


@pytest.mark.parametrize("seed", range(5))
def test_nonzero_residual_fit_reaches_scipys_cost(seed):
    fun, jac = _exp_fit(seed)
    lo, hi = np.array([0.0, 0.5, 0.0, 0.0]), np.array([5.0, 5.0, 5.0, 0.4])
    x0 = np.array([1.0, 1.0, 1.0, 0.1])
    x, cost, *_, status = solve(fun, jac, x0, lo, hi, ftol=1e-12, xtol=1e-12, max_nfev=1000)
    ref = least_squares(fun, x0, jac=jac, bounds=(lo, hi), ftol=1e-12, xtol=1e-12, gtol=None)
    assert status in (2, 3)
    assert np.all(x >= lo) and np.all(x <= hi)
    # the same local optimum: costs agree to the stopping tolerance, parameters to ~1e-5 (the fit's
    # conditioning times the 1e-12 relative cost tolerance)
    assert cost == pytest.approx(ref.cost, rel=1e-9)
    np.testing.assert_allclose(x, ref.x, atol=1e-4)


def test_every_evaluation_stays_inside_the_box():
    """A pull towards (3, -3) with the box [-1, 1]^2: the solver stops on the corner and never
    evaluates outside."""
    seen = []

    def fun(x):
        seen.append(np.array(x))
        return np.array([x[0] - 3.0, x[1] + 3.0, 0.1 * x[0] * x[1]])

    def jac(x):
        return np.array([[1.0, 0.0], [0.0, 1.0], [0.1 * x[1], 0.1 * x[0]]])

    x, *_, status = solve(fun, jac, [0.2, 0.3], [-1.0, -1.0], [1.0, 1.0], gtol=1e-12, max_nfev=200)
    assert status == 1  # both variables held on a bound: no free gradient left
    np.testing.assert_array_equal(x, [1.0, -1.0])
    assert all(np.all(np.abs(z) <= 1.0) for z in seen)


def test_start_outside_the_box_is_projected():
    x, *_ = solve(rosenbrock, rosenbrock_jac, [5.0, 5.0], [-2.0, -2.0], [0.5, 2.0], gtol=1e-12, max_nfev=1000)
    assert x[0] <= 0.5 and x[1] <= 2.0


def test_evaluation_limit_is_reported():
    x, cost, nfev, njev, status = solve(rosenbrock, rosenbrock_jac, [-1.2, 1.0], [-np.inf] * 2, [np.inf] * 2,
                                        rtol=1e-15, max_nfev=3)
    assert status == 0 and nfev == 3


def test_bad_input():
    with pytest.raises(ValueError, match="lower <= upper"):
        solve(rosenbrock, rosenbrock_jac, [0.0, 0.0], [1.0, 1.0], [0.0, 0.0])
    with pytest.raises(ValueError, match="jac returned shape"):
        solve(rosenbrock, lambda x: np.zeros((3, 2)), [0.0, 0.0], [-1.0, -1.0], [1.0, 1.0])
    with pytest.raises(ValueError, match="not finite"):
        solve(lambda x: np.array([np.nan]), lambda x: np.zeros((1, 2)), [0.0, 0.0], [-1.0, -1.0], [1.0, 1.0])
