"""Residual plots of a model against measurements: per pose and per joint (PNG bytes, matplotlib).

- ``residuals_per_pose``: the residual (attained minus command position) of every measurement, its
  x, y, z components and its length, against the measurement's row in the file.
- ``residuals_per_joint``: the residual's length against each joint's value, one panel per joint: a
  trend with a joint's angle points at that joint's parameters (a zero offset, a link length).

matplotlib is imported only when a picture is made (the Agg backend: no display needed).
"""

from __future__ import annotations

import io
from typing import Sequence

import numpy as np

__all__ = ["residuals_per_pose", "residuals_per_joint", "figure_png"]

#: Picture width (inches) and resolution: a page-wide figure, sharp on a laptop screen.
WIDTH, DPI = 9.0, 110


def figure_png(fig) -> bytes:
    """A matplotlib figure as PNG bytes."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=DPI, bbox_inches="tight")
    return buf.getvalue()


def residuals_per_pose(rows: Sequence[int], residuals: np.ndarray) -> bytes:
    """PNG of the residuals (N, 3) (m, shown in mm) against the rows (N,) of the measurements."""
    from matplotlib.figure import Figure

    r = np.asarray(residuals, dtype=float) * 1e3
    x = np.asarray(rows)
    fig = Figure(figsize=(WIDTH, 3.6))
    ax = fig.add_subplot()
    for k, (lbl, col) in enumerate(zip("xyz", ("#d62728", "#2ca02c", "#1f77b4"))):
        ax.plot(x, r[:, k], ".", ms=4, color=col, label=lbl)
    ax.plot(x, np.linalg.norm(r, axis=1), "k_", ms=7, label="length")
    ax.axhline(0.0, color="0.6", lw=0.8)
    ax.set_xlabel("row in the measurement file")
    ax.set_ylabel("residual (mm)")
    ax.set_title("residual per pose: attained minus command position")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)   # outside: never over the points
    ax.grid(alpha=0.3)
    return figure_png(fig)


def residuals_per_joint(q: np.ndarray, residuals: np.ndarray, joints: Sequence[str],
                        revolute: Sequence[bool]) -> bytes:
    """PNG of the residual length (mm) against each joint's value (deg, or mm for a prismatic joint)."""
    from matplotlib.figure import Figure

    Q = np.asarray(q, dtype=float)
    e = np.linalg.norm(np.asarray(residuals, dtype=float), axis=1) * 1e3
    n = Q.shape[1]
    cols = min(n, 4)
    rows = -(-n // cols)
    fig = Figure(figsize=(WIDTH, 2.4 * rows))
    axes = fig.subplots(rows, cols, squeeze=False, sharey=True)
    for i in range(rows * cols):
        ax = axes[i // cols][i % cols]
        if i >= n:
            ax.set_visible(False)
            continue
        v = np.degrees(Q[:, i]) if revolute[i] else Q[:, i] * 1e3
        ax.plot(v, e, ".", ms=4, color="#1f4fe0")
        ax.set_title(str(joints[i]), fontsize=9)
        ax.set_xlabel("deg" if revolute[i] else "mm", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3)
        if i % cols == 0:
            ax.set_ylabel("residual (mm)", fontsize=8)
    fig.suptitle("residual length per joint value", fontsize=10)
    fig.tight_layout()
    return figure_png(fig)
