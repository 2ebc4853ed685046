"""The GUI's workspace overlay: the reachable voxels of the robot shown, for ``POST /api/workspace``.

A coarse map, quick enough for a click (``robkin.workspace.reachability_map``; ~0.1-0.5 s at the
defaults): voxels of 1/15 of the robot's size (``Robot.scale``), 8 approach directions, 2e5 samples.
The answer lists the reachable voxels' centres and how many directions reach each, which
``static/workspace_overlay.js`` draws as points. Like the rest of the GUI's API, a function of the
request's fields (the robot text travels with every request); the last few maps are kept.
"""

from __future__ import annotations

import functools
from typing import Any

import numpy as np

from ..errors import InputError

__all__ = ["workspace_overlay", "DEFAULT_SAMPLES", "MAX_SAMPLES", "ORIENTATIONS"]

#: Samples of an overlay map unless the request says: ~0.1-0.5 s, and every voxel of a 15-voxel-wide
#: arm reached by ~100 samples on average.
DEFAULT_SAMPLES = 200_000
#: Most samples a request may ask for: the server answers one request at a time, a few seconds at most.
MAX_SAMPLES = 5_000_000
#: Approach-direction bins of an overlay map (the colour is the fraction reached).
ORIENTATIONS = 8
#: Voxels across the robot's size (``Robot.scale``) by default, and at most.
_ACROSS, _MAX_ACROSS = 15, 60


def workspace_overlay(text: str, fmt: str = "auto", base_link: str | None = None, tip_link: str | None = None,
                      tool_row: bool = False, voxel: Any = None, samples: Any = None) -> dict[str, Any]:
    """The reachable voxels of the robot in ``text`` (as ``gui_api.describe`` reads it).

    Returns
    -------
    dict
        ``voxel`` (edge, length units), ``orientations`` (K), ``samples``, ``points`` (M x 3 voxel
        centres, robot base frame), ``counts`` (M directions reached, 1..K), ``volume``.
    """
    from .gui_api import parse_robot

    robot, _ = parse_robot(text, fmt, base_link, tip_link, tool_row=tool_row)
    size = robot.scale
    v = size / _ACROSS if voxel is None else voxel
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v) or not size / _MAX_ACROSS <= v:
        raise InputError(f"voxel: expected a length of at least {size / _MAX_ACROSS:.3g} (1/{_MAX_ACROSS} of the "
                         f"robot's size), got {voxel!r}")
    n = DEFAULT_SAMPLES if samples is None else samples
    if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= MAX_SAMPLES:
        raise InputError(f"samples: expected a whole number from 1 to {MAX_SAMPLES}, got {samples!r}")
    return _overlay(text, fmt, base_link, tip_link, tool_row, float(v), int(n))


@functools.lru_cache(maxsize=4)
def _overlay(text: str, fmt: str, base_link: str | None, tip_link: str | None, tool_row: bool, voxel: float,
             samples: int) -> dict[str, Any]:
    from ..workspace import reachability_map
    from .gui_api import parse_robot

    robot, _ = parse_robot(text, fmt, base_link, tip_link, tool_row=tool_row)
    wmap = reachability_map(robot, voxel, ORIENTATIONS, samples=samples, seed=0, threads=1)
    idx = np.argwhere(wmap.reachable > 0)
    points = wmap.origin + voxel * (idx + 0.5)
    return {"voxel": voxel, "orientations": ORIENTATIONS, "samples": samples, "points": points.tolist(),
            "counts": wmap.reachable[tuple(idx.T)].tolist(), "volume": float(len(idx)) * voxel ** 3}
