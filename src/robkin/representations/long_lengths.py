"""A warning for tables whose lengths dwarf the robot: the sign of nearly parallel axes.

Between two joint axes that are nearly (not exactly) parallel, the common normal of standard and
modified DH lies about offset / tilt away along the axes: a 4.5 cm offset with a 6e-6 rad tilt puts it
7 km out, and the table carries two such lengths of opposite sign. The table is still exact, but a
controller or a paper reader cannot use it (the lengths cancel to a few micrometres only in float64).
``warn_long_lengths`` names the axes responsible and the representation that stays short (Hayati).
"""

from __future__ import annotations

import warnings

import numpy as np

__all__ = ["LONG_FACTOR", "warn_long_lengths"]

#: A length beyond this many robot sizes (``Robot.scale``: the largest distance of an axis or the tool
#: from the base) cannot be the robot's geometry: every real link is shorter than the whole arm; 10
#: leaves room for a tool or base offset larger than the arm's own axes' distances.
LONG_FACTOR = 10.0


def warn_long_lengths(section: str, rows: np.ndarray, base: np.ndarray, tool: np.ndarray, axes: np.ndarray,
                      scale: float, where: str = "", stacklevel: int = 3) -> bool:
    """Warn (ConditioningWarning, one line) when a length of the table exceeds LONG_FACTOR * scale.

    Parameters
    ----------
    section : str
        'dh', 'mdh' or 'hayati' (wording of the column names).
    rows : (n, k) array
        The table's rows, lengths a, d first (robot length units, normally metres).
    base, tool : (4, 4) arrays
        The table's fixed transforms; their offsets count too.
    axes : (n, 3) array
        Unit joint axes in the base frame at q = 0 (to say which pair is nearly parallel).
    scale : float
        The robot's size (length units).
    where : str
        Prefix of the message (which robot of a batch).

    Returns
    -------
    bool
        Whether a warning was issued.
    """
    from ..errors import ConditioningWarning

    limit = LONG_FACTOR * scale
    prev = section in ("mdh",)
    names = []
    for i, row in enumerate(np.asarray(rows)):
        for col, value in zip(("a", "d"), row[:2]):
            if abs(value) > limit:
                idx = i if (prev and col == "a") else i + 1  # Craig's a belongs to the previous link
                names.append((f"{col}{idx}", float(value), i))
    for label, T in (("base", base), ("tool", tool)):
        offset = float(np.linalg.norm(np.asarray(T)[:3, 3]))
        if offset > limit:
            names.append((f"{label} offset", offset, 0 if label == "base" else len(rows) - 1))
    if not names:
        return False
    z = np.vstack([[0.0, 0.0, 1.0], np.asarray(axes, dtype=float)])
    # the nearly parallel pairs next to the long values: (base z, joint 1), (joint i, joint i + 1)
    pairs = []
    for _, _, i in names:
        for k in (i, i + 1):
            if k + 1 < len(z):
                s = float(np.linalg.norm(np.cross(z[k], z[k + 1])))
                # a pair is "nearly parallel" when its tilt would put a common normal > 10 sizes
                # out for an offset of the robot's size: sin(tilt) < 1 / LONG_FACTOR
                if 0.0 < s < 1.0 / LONG_FACTOR:
                    label = "the base z axis and joint 1" if k == 0 else f"joints {k} and {k + 1}"
                    text = f"{label} are {s:.2g} rad from parallel"
                    if text not in pairs:
                        pairs.append(text)
    values = ", ".join(f"{name} = {value:.6g} m" for name, value, _ in names[:4])
    why = ("; ".join(pairs) + ", so their common normal lies far along them") if pairs else \
        "nearly parallel axes put the common normal far along them"
    better = "the hayati table stays short (a tilt beta instead of a long d)" if section != "hayati" else \
        "the poe or rpy-xyz form stays short"
    warnings.warn(f"{where}{section}: {values}: more than {LONG_FACTOR:g} times the robot's size "
                  f"({scale:.3g} m), because {why}; {better}", ConditioningWarning, stacklevel=stacklevel)
    return True
