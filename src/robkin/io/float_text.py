"""Numbers as text that reads back to the very same float, for the URDF writer and the table files."""

from __future__ import annotations

__all__ = ["float_text"]


def float_text(x: float) -> str:
    """Shortest text that reads back to the same float (``repr``), integers without '.0' and zero
    without a sign: 150.0 -> '150', -0.0 -> '0', 0.1 -> '0.1', 1e-20 -> '1e-20'."""
    x = float(x)
    if x == 0:
        return "0"
    text = repr(x)
    return text[:-2] if text.endswith(".0") else text
