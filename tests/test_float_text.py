"""The shortest decimal within a tolerance (``float_text.short_text``): within it, and the shortest."""

from __future__ import annotations

import os

from hypothesis import given, settings
from hypothesis import strategies as st

from robkin.io.float_text import digits_text, float_text, short_text

SCALE = int(os.environ.get("ROBKIN_PROPERTY_SCALE", "1"))


def _digits(text: str) -> int:
    mantissa = text.lstrip("-").split("e")[0].replace(".", "").lstrip("0")
    return len(mantissa)


@settings(max_examples=300 * SCALE, deadline=None)
@given(st.floats(-1e6, 1e6, allow_nan=False), st.floats(1e-16, 1e-3))
def test_short_text_is_within_tol_and_shortest(x, tol):
    text = short_text(x, tol)
    assert abs(float(text) - x) <= tol
    if text != "0":
        k = _digits(text)
        if k > 1:  # one digit fewer would not do
            assert abs(float(f"{x:.{k - 1}g}") - x) > tol


def test_examples():
    assert short_text(0.3839999999999999, 1e-14) == "0.384"
    assert short_text(-4.16e-18, 1e-14) == "0"
    assert short_text(-4.89657334287251e-12, 1e-14) == "-4.9e-12"
    assert short_text(0.1, 0) == float_text(0.1) == "0.1"
    assert digits_text(1.5707963267948966, 3) == "1.57" and digits_text(-1e-20, 3) == "-1e-20"
