"""Making small differences between two robots visible: exaggeration and difference arrows.

Two descriptions 6 mm apart on a 1 m arm look identical in a picture. A joint differs where its axis
differs (where along the axis a description puts its frame is a choice of the representation, not a
difference), so for joint i the difference is from A's axis point ``a_i`` to the nearest point ``b_i``
of B's axis line. ``exaggerate(a, b, k)`` draws B with every axis point at ``a_i + k (b_i - a_i)``,
every axis turned by k times its angle to A's (at most a half turn) and the tool origin moved the same
way, so that a difference of d shows as k d; ``difference_arrows(a, b, k)`` gives an arrow from
``a_i`` to that point for every revolute joint and the tool that differ, with the true distance (a
prismatic joint's axis is a direction only: its line may lie anywhere). ``robkin plot A B --exaggerate K``, its HTML page and the GUI's visual check draw them.

Both scenes must be of robots with the same joint count at the same q (``robkin check`` says what
else differs).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..errors import InputError
from .scene import Scene

__all__ = ["exaggerate", "difference_arrows", "DifferenceArrow", "EXAGGERATIONS"]

#: The factors the GUI offers (1 = as they are).
EXAGGERATIONS = (1, 10, 100, 1000)
#: Points closer than this fraction of the robot's size are "the same" (no arrow): rounding noise of
#: the conversions that made them, far below anything a picture could show.
_SAME = 1e-9


@dataclass(frozen=True)
class DifferenceArrow:
    """From A's point to B's (exaggerated) point; ``distance`` is the true one (length units)."""

    label: str             #: 'J1'.. 'Jn' or 'tool'
    start: np.ndarray      #: (3,) A's point
    end: np.ndarray        #: (3,) B's point, exaggerated like the scene
    distance: float        #: |B - A| before exaggeration

    def to_json(self) -> dict:
        return {"label": self.label, "start": self.start.tolist(), "end": self.end.tolist(),
                "distance": self.distance}


def _check_pair(a: Scene, b: Scene, factor: float) -> None:
    if not (np.isfinite(factor) and 1 <= factor <= 1e6):
        raise InputError(f"exaggerate: expected a factor from 1 to 1e6, got {factor!r}")
    if len(a.axis_points) != len(b.axis_points) or not np.array_equal(a.prismatic, b.prismatic):
        raise InputError(f"exaggerate: the robots have {len(a.axis_points)} and {len(b.axis_points)} joints "
                         f"(or other prismatic joints); differences can be exaggerated between robots of the "
                         f"same structure only")


def _toward(a: np.ndarray, b: np.ndarray, k: float) -> np.ndarray:
    return a + k * (b - a)


def _turned(za: np.ndarray, zb: np.ndarray, k: float) -> np.ndarray:
    """Unit vectors at k times the angle from ``za`` to ``zb`` (rows (m, 3)), in the plane of both."""
    out = np.empty_like(zb)
    for i, (u, v) in enumerate(zip(za, zb)):
        angle = np.arctan2(np.linalg.norm(np.cross(u, v)), u @ v)
        w = v - (u @ v) * u
        nw = np.linalg.norm(w)
        if nw < 1e-15 or angle < 1e-15:  # parallel or opposite: nothing to turn about
            out[i] = v
            continue
        a = min(k * angle, np.pi)  # at most a half turn: beyond that the picture would lie
        out[i] = np.cos(a) * u + np.sin(a) * (w / nw)
    return out


def _nearest_on_axes(a: Scene, b: Scene) -> np.ndarray:
    """(n, 3): the point of each of B's axis lines nearest to A's point on the same joint's axis."""
    d = a.axis_points - b.axis_points
    return b.axis_points + np.sum(d * b.axis_dirs, axis=1)[:, None] * b.axis_dirs


def exaggerate(a: Scene, b: Scene, factor: float) -> Scene:
    """B's scene with its differences from A multiplied by ``factor`` (see the module).

    Parameters
    ----------
    a, b : Scene
        The reference and the other robot, same joint count (and the same joints prismatic), same q.
    factor : float
        1 to 1e6; 1 returns ``b`` unchanged.

    Returns
    -------
    Scene
        Axis points ``a_i + factor (b_i - a_i)`` (see the module), axis directions turned by
        ``factor`` times their angle to A's, the tool origin moved likewise, and the links drawn
        through them; its label says the factor.
    """
    _check_pair(a, b, factor)
    if factor == 1:
        return b
    points = _toward(a.axis_points, _nearest_on_axes(a, b), factor)
    dirs = _turned(a.axis_dirs, b.axis_dirs, factor)
    tool = b.tool.copy()
    tool[:3, 3] = _toward(a.tool[:3, 3], b.tool[:3, 3], factor)
    frames = b.frames.copy()
    frames[:, :3, 3] = points
    links = [np.zeros(3)]
    for i, p in enumerate(points):
        if b.prismatic[i]:
            links.append(p - b.q[i] * dirs[i])  # where the slide starts, as build_scene draws it
        links.append(p)
    links.append(tool[:3, 3])
    return replace(b, label=f"{b.label} (differences x{factor:g})", links=np.array(links), axis_points=points,
                   axis_dirs=dirs, frames=frames, tool=tool)


def difference_arrows(a: Scene, b: Scene, factor: float = 1.0) -> list[DifferenceArrow]:
    """An arrow per joint and for the tool origin where B differs from A (see the module), its end
    exaggerated by ``factor`` like :func:`exaggerate`'s scene; in joint order, the tool last."""
    _check_pair(a, b, factor)
    size = max(a.scale, b.scale, 1e-12)
    starts = np.vstack([a.axis_points, a.tool[None, :3, 3]])
    ends = np.vstack([_nearest_on_axes(a, b), b.tool[None, :3, 3]])
    labels = [f"J{i + 1}" for i in range(len(a.axis_points))] + ["tool"]
    # a prismatic joint is a direction only: where its axis line lies is no difference
    moves = [not p for p in a.prismatic] + [True]
    out = []
    for label, p, e, counts in zip(labels, starts, ends, moves):
        if not counts:
            continue
        d = float(np.linalg.norm(e - p))
        if d > _SAME * size:
            out.append(DifferenceArrow(label, p, _toward(p, e, factor), d))
    return out
