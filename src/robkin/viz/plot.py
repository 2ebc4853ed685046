"""Matplotlib pictures of a robot's structure, in the style of the conversion paper's figures.

Joint axes are blue, the tool frame is pink, the base frame black; links are drawn through the joint
frame origins of each representation, so overlaying e.g. the original DH table and the DH table
rebuilt from PoE screws shows two different link polylines on the same joint axes and one tool pose.
Axes are scaled equally. matplotlib is imported only when a picture is made.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Sequence

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..robot import Robot
from .scene import Scene, disagreement, overlay_scenes

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = ["plot_robot", "plot_scenes", "save_figure", "PICTURE_FORMATS", "AXIS_BLUE", "TOOL_PINK",
           "DIFFERENCE_RED"]

#: Colours of the paper's figures: joint axes blue, tool frame pink.
AXIS_BLUE = "#1f4fe0"
TOOL_PINK = "#ff3fa4"
#: Difference arrows (plot A B --exaggerate): the GUI's colour for a joint that differs.
DIFFERENCE_RED = "#e02020"
_LINK_STYLES = (("#3a3a3a", "-", 4.0), ("#f28e2b", "--", 2.5), ("#2ca02c", ":", 2.5), ("#9467bd", "-.", 2.0),
                ("#8c564b", "--", 1.5), ("#17becf", ":", 1.5))
#: Output formats by file extension.
PICTURE_FORMATS = (".png", ".svg", ".pdf", ".html")
#: Lengths of the drawn axis segments and triads, as fractions of the robot's size (robot.scale):
#: long enough to read the direction, short enough not to hide the links.
_AXIS_BACK, _AXIS_FRONT, _TRIAD, _JOINT_TRIAD = 0.12, 0.22, 0.16, 0.08


def plot_robot(robot: Robot, q: ArrayLike | None = None, overlay: Sequence[str] = ("gjd",), *,
               frames: bool = False, view: tuple[float, float] = (25.0, -60.0),
               title: str | None = None) -> "Figure":
    """A 3D picture of ``robot`` at configuration ``q``, optionally several representations overlaid.

    Parameters
    ----------
    robot : Robot
    q : (n,) array-like, optional
        Joint values (rad / length units); home (zeros) if omitted.
    overlay : sequence of str
        Representations to draw, each rebuilt from its own table: "gjd" (the robot as given), "dh",
        "mdh", "poe", "poe-body", "rpy-xyz".
    frames : bool
        Also draw every joint frame as a small RGB triad.
    view : (elevation, azimuth) in degrees
    title : str, optional
        Defaults to the robot's name and q.
    """
    scenes = overlay_scenes(robot, q, list(overlay) or ["gjd"])
    if len(scenes) == 1 and list(overlay) in ([], ["gjd"]):
        scenes = [_relabel(scenes[0], robot.name or "robot")]
    return plot_scenes(scenes, frames=frames, view=view, title=title or _default_title(robot.name, scenes[0].q))


def _relabel(scene: Scene, label: str) -> Scene:
    from dataclasses import replace

    return replace(scene, label=label)


def _default_title(name: str | None, q: np.ndarray) -> str:
    qs = ", ".join(f"{v:.4g}" for v in q)
    where = "home (q = 0)" if not np.any(q) else f"q = [{qs}]"
    return f"{name or 'robot'} at {where}"


def plot_scenes(scenes: Sequence[Scene], *, frames: bool = False, view: tuple[float, float] = (25.0, -60.0),
                title: str | None = None, exaggerate: float | None = None) -> "Figure":
    """Draw one or more scenes (same robot in several representations, or several robots) in one 3D plot.

    The first scene's joint names and tool axes are labelled; the others are drawn on top with their
    own link style. When several scenes are given, the subtitle states by how much their tool poses
    and joint axes disagree (0 up to rounding for representations of one robot). ``exaggerate``
    (several robots of one structure): the others are drawn with their differences from the first
    multiplied by it, with red arrows labelled with the true distances (``robkin.viz.difference``);
    the subtitle gives the true differences.
    """
    # A bare Figure (no pyplot) renders off-screen with any backend and never opens a window.
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    if not scenes:
        raise InputError("plot: nothing to draw")
    true_scenes, arrows = list(scenes), []
    if exaggerate is not None and len(scenes) > 1:
        from .difference import difference_arrows
        from .difference import exaggerate as exaggerated

        arrows = [a for s in scenes[1:] for a in difference_arrows(scenes[0], s, exaggerate)]
        scenes = [scenes[0]] + [exaggerated(scenes[0], s, exaggerate) for s in scenes[1:]]
    fig = Figure(figsize=(7.5, 7.0), dpi=100, layout="constrained")
    ax = fig.add_subplot(projection="3d")
    L = max(s.scale for s in scenes)
    tips: list[np.ndarray] = [np.zeros((1, 3))]
    handles = []
    for k, s in enumerate(scenes):
        color, style, width = _LINK_STYLES[k % len(_LINK_STYLES)]
        ax.plot(*s.links.T, color=color, linestyle=style, linewidth=width, marker="o", markersize=4 if k else 6,
                label=s.label, zorder=2 + k)
        handles.append(Line2D([], [], color=color, linestyle=style, linewidth=width, marker="o", label=s.label))
        for i in range(len(s.axis_points)):
            p, z = s.axis_points[i], s.axis_dirs[i]
            seg = np.array([p - _AXIS_BACK * L * z, p + _AXIS_FRONT * L * z])
            ax.plot(*seg.T, color=AXIS_BLUE, linewidth=2.0 if k == 0 else 1.2,
                    linestyle="-" if k == 0 else (0, (3, 2)), marker="s" if s.prismatic[i] else None,
                    markevery=[0], markersize=4)
            tips.append(seg)
            if k == 0:
                ax.text(*(p + (_AXIS_FRONT + 0.03) * L * z), s.joint_names[i], color=AXIS_BLUE, fontsize=8)
        if frames:
            for F in s.frames:
                _triad(ax, F, _JOINT_TRIAD * L, ("#d62728", "#2ca02c", "#1f77b4"), width=1.0)
        tips.append(_triad(ax, s.tool, _TRIAD * L, (TOOL_PINK,) * 3, width=2.0 if k == 0 else 1.2,
                           names=("x", "y", "z") if k == 0 else None))
    for arrow in arrows:
        d = arrow.end - arrow.start
        ax.quiver(*arrow.start, *d, color=DIFFERENCE_RED, linewidth=2.0, arrow_length_ratio=0.25, zorder=10)
        ax.text(*arrow.end, f" {arrow.label}: {arrow.distance:.3g}", color=DIFFERENCE_RED, fontsize=8)
        tips.append(arrow.end[None, :])
    if arrows:
        handles.append(Line2D([], [], color=DIFFERENCE_RED, linewidth=2, label="difference (true length)"))
    tips.append(_triad(ax, np.eye(4), _TRIAD * L, ("black",) * 3, width=1.5, names=("x0", "y0", "z0")))
    handles += [Line2D([], [], color=AXIS_BLUE, linewidth=2, label="joint axes (+ direction)"),
                Line2D([], [], color=TOOL_PINK, linewidth=2, label="tool frame"),
                Line2D([], [], color="black", linewidth=1.5, label="base frame")]
    _equal_limits(ax, np.vstack([s.points() for s in scenes] + tips))
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z")
    ax.view_init(elev=view[0], azim=view[1])
    ax.legend(handles=handles, loc="upper left", fontsize=8, framealpha=0.85)
    text = title or _default_title(None, scenes[0].q)
    if len(scenes) > 1:
        pos, rot, axes = disagreement(true_scenes)
        text += (f"\n{len(scenes)} descriptions: tool poses differ by {pos:.1e} (position), {rot:.1e} "
                 f"(rotation); joint axes by {axes:.1e}")
    ax.set_title(text, fontsize=10)
    return fig


def _triad(ax, T: np.ndarray, length: float, colors: Sequence[str], width: float,
           names: Sequence[str] | None = None) -> np.ndarray:
    """Draw the x, y, z axes of pose T as arrows; return the arrow tips (3, 3) for the axis limits."""
    o = T[:3, 3]
    tips = o + length * T[:3, :3].T
    for j in range(3):
        d = tips[j] - o
        ax.quiver(*o, *d, color=colors[j], linewidth=width, arrow_length_ratio=0.18)
        if names:
            ax.text(*(o + 1.12 * d), names[j], color=colors[j], fontsize=8)
    return tips


def _equal_limits(ax, pts: np.ndarray) -> None:
    """Equal scaling on x, y, z: a cube around all drawn points with a 5 % margin."""
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    centre = (lo + hi) / 2
    # 1e-9: a positive extent even if everything drawn is one point (matplotlib refuses equal limits)
    half = max(float(np.max(hi - lo)) / 2 * 1.05, 1e-9)
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.set_box_aspect((1, 1, 1))


def save_figure(fig: "Figure", path: str | os.PathLike, *, caption: str = "") -> Path:
    """Write ``fig`` to ``path`` (.png, .svg, .pdf, or .html with the SVG inline), all-or-nothing.

    Returns the path written. InputError for an unknown extension or an unwritable folder.

    ``caption``: a line of text written under the picture (empty: none).
    """
    import io

    from ..io.files.atomic import atomic_file, write_text_atomic

    p = Path(path)
    ext = p.suffix.lower()
    if ext not in PICTURE_FORMATS:
        raise InputError(f"{p}: unknown picture format '{ext or '(none)'}'; one of {', '.join(PICTURE_FORMATS)}")
    if ext == ".html":
        buf = io.StringIO()
        with _reproducible():
            fig.savefig(buf, format="svg", metadata=_metadata(".svg"))
        write_text_atomic(p, _html_page(buf.getvalue(), caption))
        return p
    with atomic_file(p, binary=True) as fh, _reproducible():
        fig.savefig(fh, format=ext[1:], dpi=150, metadata=_metadata(ext))
    return p


def _reproducible():
    """Fixed SVG id salt, so that regenerating an unchanged picture gives identical bytes."""
    import matplotlib

    return matplotlib.rc_context({"svg.hashsalt": "robkin"})


def _metadata(ext: str) -> dict:
    # No creation dates in the files, so regenerating an unchanged picture gives identical bytes.
    if ext == ".svg":
        return {"Date": None}
    if ext == ".pdf":
        return {"CreationDate": None}
    return {}


def _html_page(svg: str, caption: str) -> str:
    import html

    body = svg[svg.index("<svg"):]  # drop the XML prolog and doctype: inline SVG in HTML5
    cap = f"<pre>{html.escape(caption)}</pre>" if caption else ""
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>robkin plot</title>"
            "<style>body{font-family:sans-serif;margin:1em} svg{max-width:100%;height:auto}</style></head>"
            f"<body>{body}{cap}</body></html>\n")
