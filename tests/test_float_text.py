"""The shortest decimal within a tolerance (``float_text.short_text``): within it, and the shortest."""

from __future__ import annotations

import os

from hypothesis import given, settings
from hypothesis import strategies as st

from robkin.io.files.float_text import digits_text, float_text, short_text

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


def test_round_document_shortens_table_values_and_keeps_the_rest():
    from robkin.io.documents.rounding import round_document

    doc = {"robkin": 1, "joints": [{"name": "j1", "type": "revolute", "limits": {"lower": -0.30000000000000004}}],
           "dh": {"base": [[1.0, -4.16e-18, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0, 0, 0, 1.0]],
                  "rows": [{"a": 0.3839999999999999, "d": 0.0, "alpha": 1.5707963267948966, "theta": 0.0,
                            "m": 1.2000000000000002, "r": [0.1, 0.0, 0.30000000000000004]}]}}
    out = round_document(doc, scale=1.0)
    row = out["dh"]["rows"][0]
    assert row["a"] == 0.384 and out["dh"]["base"][0][1] == 0.0
    assert row["alpha"] == float("1.5707963267949")  # within the budget of an angle, 14 digits
    # a link's mass properties and the joints' limits are the user's numbers: untouched
    assert row["m"] == 1.2000000000000002 and row["r"] == [0.1, 0.0, 0.30000000000000004]
    assert out["joints"][0]["limits"]["lower"] == -0.30000000000000004
