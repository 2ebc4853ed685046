"""Estimation results (types A-D) and their metrics as the estimation paper's plots.

The paper compares the structures it estimates by arm length (a bar plot, its Fig. 11) and by
Yoshikawa's manipulability for translation and rotation (a logarithmic plot, its Fig. 12). Here each
result document is one bar; results whose file (or else document) name is ``<group>_<type>`` (e.g.
``pose1_A.yaml``, or ``name: pose1-A``) are grouped like the paper: one group per pose, one bar per
type. If two results would take the same place, every result gets its own bar instead.

A document without a ``metrics`` object gets them computed: length L = sum_i sqrt(a_i^2 + d_i^2) over
its standard DH rows (the paper's eq. 48) and the manipulabilities at q = 0.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Sequence

from ..errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from ..robot import Robot

__all__ = ["MetricEntry", "METRIC_KEYS", "read_metrics", "metrics_of_robot", "plot_metrics"]

METRIC_KEYS = ("length", "manipulability_translational", "manipulability_rotational")
_GROUPED = re.compile(r"^(?P<group>.+?)[-_ ](?P<series>[A-Da-d])$")
#: Manipulability values below this are drawn at this height on the log axis (and labelled "0"):
#: a log scale cannot show 0, and 1e-12 is far below any non-singular structure's value.
LOG_FLOOR = 1e-12


@dataclass(frozen=True)
class MetricEntry:
    """One estimation result: where it goes in the plot and its three metrics."""

    label: str
    group: str
    series: str
    length: float
    manipulability_translational: float
    manipulability_rotational: float


def metrics_of_robot(robot: "Robot") -> dict[str, float]:
    """The paper's metrics of a robot at q = 0, as ``robkin estimate`` computes them.

    Length from the robot's standard DH rows (eq. 48); manipulabilities of the geometric Jacobian,
    0 when it is rank-deficient (see ``robkin.synthesis.metrics``).
    """
    from ..representations import dh_from_robot
    from ..synthesis.metrics import structure_metrics

    return structure_metrics(robot, dh_from_robot(robot).rows).as_dict()


def read_metrics(path: str | Path) -> MetricEntry:
    """Metrics of one result document: its ``metrics`` object, or computed from its robot."""
    from ..io.documents.reader import parse_text, read_text, parse_document

    text, fmt = read_text(path)
    data: Any = parse_text(text, fmt, str(path))
    if not isinstance(data, dict):
        raise InputError(f"{path}: expected a robot document (a mapping with joints and a section)")
    stem, name = Path(path).stem, str(data.get("name") or "")
    raw = data.get("metrics")
    if raw is None:
        values = metrics_of_robot(parse_document(text, fmt, source=str(path)))
    elif isinstance(raw, dict):
        values = {}
        for key in METRIC_KEYS:
            v = raw.get(key)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
                raise InputError(f"{path}: metrics.{key}: expected a number >= 0, got {v!r}")
            values[key] = float(v)
    else:
        raise InputError(f"{path}: metrics: expected a mapping with {', '.join(METRIC_KEYS)}")
    # The file name first (pose1_A.yaml), then the document name (pose1-A): estimates written by one
    # tool often share a generic name, while their files are named by the user.
    for label in (stem, name):
        m = _GROUPED.match(label)
        if m:
            return MetricEntry(label, m["group"], m["series"].upper(), **values)
    return MetricEntry(stem, "", stem, **values)


def plot_metrics(entries: Sequence[MetricEntry], title: str | None = None) -> "Figure":
    """Bar plot of arm length and log-scale bar plots of both manipulabilities, grouped as in the paper.

    Returns a figure with three axes: (a) length [length units], (b) translational and (c) rotational
    manipulability (dimensionless, log scale).
    """
    from matplotlib.figure import Figure

    if not entries:
        raise InputError("no metrics to plot: give at least one result document")
    keys = [(e.group, e.series) for e in entries]
    if len(set(keys)) < len(keys):  # e.g. two pose1_A files from different folders: one bar each
        entries = [MetricEntry(f"{e.label} ({i + 1})", "", f"{e.label} ({i + 1})", e.length,
                               e.manipulability_translational, e.manipulability_rotational)
                   for i, e in enumerate(entries)]
    groups = list(dict.fromkeys(e.group for e in entries))
    series = list(dict.fromkeys(e.series for e in entries))
    width = 0.8 / len(series)
    fig = Figure(figsize=(11, 3.8), dpi=100, layout="constrained")
    axes = fig.subplots(1, 3)
    panels = (("length", "(a) arm length  L = Σ √(aᵢ² + dᵢ²)", False),
              ("manipulability_translational", "(b) manipulability, translation", True),
              ("manipulability_rotational", "(c) manipulability, rotation", True))
    for ax, (key, name, log) in zip(axes, panels):
        for k, s in enumerate(series):
            xs, hs, zero = [], [], []
            for g_i, g in enumerate(groups):
                for e in entries:
                    if e.group == g and e.series == s:
                        v = getattr(e, key)
                        xs.append(g_i + (k - (len(series) - 1) / 2) * width)
                        hs.append(max(v, LOG_FLOOR) if log else v)
                        zero.append(log and v < LOG_FLOOR)
            bars = ax.bar(xs, hs, width=width * 0.95, label=f"type {s}" if len(s) == 1 else s)
            for b, z in zip(bars, zero):
                if z:
                    ax.annotate("0", (b.get_x() + b.get_width() / 2, LOG_FLOOR), ha="center", va="bottom",
                                fontsize=7)
        if log:
            ax.set_yscale("log")
        ax.set_xticks(range(len(groups)), [g or "" for g in groups])
        ax.set_title(name, fontsize=10)
        ax.grid(axis="y", alpha=0.3, which="both" if log else "major")
    axes[0].set_ylabel("length")
    axes[1].set_ylabel("Yoshikawa measure (log)")
    axes[0].legend(fontsize=8)
    if title:
        fig.suptitle(title)
    return fig
