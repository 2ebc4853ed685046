"""Numbers as text: bit-exact (``float_text``), or the shortest decimal within a tolerance
(``short_text``), for the URDF writer, the table files and the documents.

A value computed through the frame algebra carries rounding noise in its last digits
(0.3839999999999999 for 0.384, -4.16e-18 for 0). ``short_text`` writes the shortest decimal whose
value lies within ``tol`` of the float: with the tolerances of ``decimal_tolerances`` the whole table
then moves FK by at most ``rounding.SNAP_BUDGET`` of the robot's size, the agreement robkin promises
for exact conversions.
"""

from __future__ import annotations

__all__ = ["float_text", "short_text", "digits_text", "decimal_tolerances", "distinct_texts"]


def float_text(x: float) -> str:
    """Shortest text that reads back to the same float (``repr``), integers without '.0' and zero
    without a sign: 150.0 -> '150', -0.0 -> '0', 0.1 -> '0.1', 1e-20 -> '1e-20'."""
    x = float(x)
    if x == 0:
        return "0"
    text = repr(x)
    return text[:-2] if text.endswith(".0") else text


def _tidy(text: str) -> str:
    """'%g' text without a '+' or leading zeros in the exponent, nor a trailing '.0'."""
    mantissa, e, exponent = text.partition("e")
    if mantissa.endswith(".0"):
        mantissa = mantissa[:-2]
    if not e:
        return mantissa
    return f"{mantissa}e{int(exponent)}"


def short_text(x: float, tol: float) -> str:
    """The shortest decimal (fewest significant digits) within ``tol`` of x; '0' when |x| <= tol.

    ``tol`` <= 0 gives ``float_text`` (bit-exact). 0.3839999999999999 with tol 1e-14 -> '0.384'.
    """
    x = float(x)
    if not tol > 0 or x != x or x in (float("inf"), float("-inf")):
        return float_text(x)
    if abs(x) <= tol:
        return "0"
    for digits in range(1, 18):
        text = f"{x:.{digits}g}"
        if abs(float(text) - x) <= tol:
            return _tidy(text)
    return float_text(x)


def digits_text(x: float, digits: int) -> str:
    """x with at most ``digits`` significant digits ('-0' written as '0')."""
    x = float(x)
    text = _tidy(f"{x:.{digits}g}")
    return "0" if float(text) == 0 else text


def decimal_tolerances(scale: float, reach: float, count: int, budget: float) -> tuple[float, float]:
    """Per-value tolerances (lengths, angles) that keep a table within ``budget`` of FK.

    Parameters
    ----------
    scale : float
        The robot's size (``Robot.scale``, length units).
    reach : float
        A bound on every lever in the table: the sum of its lengths (a turn of delta rad anywhere in the
        chain moves the tool by at most delta * reach).
    count : int
        How many values the table writes (each may use its share of the budget).
    budget : float
        Total FK change allowed, relative to ``scale``.

    Returns
    -------
    (float, float)
        The length tolerance (length units) and the angle tolerance (radians): each of ``count``
        values moved within them changes FK by at most budget * scale / count.
    """
    share = budget * scale / max(count, 1)
    return share, share / max(reach, scale, 1e-300)


def distinct_texts(x: float, y: float, digits: int = 6) -> tuple[str, str]:
    """Two values as text with ``digits`` significant digits, or as many more as it takes to tell them
    apart (the shortest decimals that differ; ``float_text`` of each at most): a report of a difference
    never prints '14.5893 kg vs 14.5893 kg'. Equal values print alike."""
    x, y = float(x), float(y)
    for d in range(digits, 18):
        tx, ty = digits_text(x, d), digits_text(y, d)
        if tx != ty or x == y:
            return tx, ty
    return float_text(x), float_text(y)
