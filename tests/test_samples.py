"""The fixed sample points of the FK cross-checks (robkin.samples)."""

import math

import numpy as np
import pytest

from robkin.samples import unit_sample


def test_one_dimension_is_the_golden_ratio_sequence():
    """d = 1: phi_1 is the golden ratio, so the points are frac(1/2 + k / phi) (computed independently)."""
    phi = (1 + math.sqrt(5)) / 2
    expected = [(0.5 + k / phi) % 1.0 for k in range(1, 11)]
    np.testing.assert_allclose(unit_sample(10, 1)[:, 0], expected, rtol=0, atol=1e-14)


def test_two_dimensions_use_the_plastic_number():
    """d = 2: phi_2 is the plastic number 1.3247179572447460... (the real root of x^3 = x + 1)."""
    rho = 1.3247179572447460260
    U = unit_sample(5, 2)
    k = np.arange(1, 6)
    np.testing.assert_allclose(U[:, 0], np.mod(0.5 + k / rho, 1.0), rtol=0, atol=1e-13)
    np.testing.assert_allclose(U[:, 1], np.mod(0.5 + k / rho**2, 1.0), rtol=0, atol=1e-13)


@pytest.mark.parametrize("d", [1, 6, 7, 44, 103])
def test_points_lie_in_the_cube_spread_out_and_repeat(d):
    U = unit_sample(8, d)
    assert U.shape == (8, d)
    assert ((U >= 0) & (U < 1)).all()
    assert unit_sample(8, d) is U and not U.flags.writeable  # cached, cannot be changed by a caller
    # spread: no two points close together, no coordinate repeated within a column
    gaps = np.linalg.norm(U[:, None, :] - U[None, :, :], axis=2)[np.triu_indices(8, 1)]
    assert gaps.min() > 0.1 * math.sqrt(d / 6)  # a tenth of the mean distance of two random points
    assert all(len(np.unique(np.round(U[:, j], 12))) == 8 for j in range(d))
