"""MJCF format details shared by its reader and its writer: quaternions in MuJoCo's order (w, x, y, z),
placements as ``pos``/``quat`` attributes, and the noise below which a value is written as zero.
"""

from __future__ import annotations

import numpy as np

__all__ = ["quat_from_matrix", "matrix_from_quat", "place_attrs", "NOISE"]

#: Quaternion components, and positions relative to the robot size, below this are rounding noise of
#: unit-size products (~1e-16 each): written as 0, so that a frame that did not turn reads as such.
NOISE = 1e-15


def matrix_from_quat(q: np.ndarray) -> np.ndarray:
    """Rotation matrix (3, 3) of a unit quaternion (w, x, y, z) (MuJoCo's order)."""
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def quat_from_matrix(R: np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z), w >= 0, of a rotation matrix (3, 3).

    Shepperd's method: take the square root of the largest of the four diagonal combinations, so no
    division by a small number happens (accurate to rounding for every rotation).
    """
    R = np.asarray(R, dtype=float)
    tr = R[0, 0] + R[1, 1] + R[2, 2]
    k = int(np.argmax([tr, R[0, 0], R[1, 1], R[2, 2]]))
    if k == 0:
        s = 2.0 * np.sqrt(1.0 + tr)
        q = [0.25 * s, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s]
    elif k == 1:
        s = 2.0 * np.sqrt(1.0 + R[0, 0] - R[1, 1] - R[2, 2])
        q = [(R[2, 1] - R[1, 2]) / s, 0.25 * s, (R[0, 1] + R[1, 0]) / s, (R[0, 2] + R[2, 0]) / s]
    elif k == 2:
        s = 2.0 * np.sqrt(1.0 + R[1, 1] - R[0, 0] - R[2, 2])
        q = [(R[0, 2] - R[2, 0]) / s, (R[0, 1] + R[1, 0]) / s, 0.25 * s, (R[1, 2] + R[2, 1]) / s]
    else:
        s = 2.0 * np.sqrt(1.0 + R[2, 2] - R[0, 0] - R[1, 1])
        q = [(R[1, 0] - R[0, 1]) / s, (R[0, 2] + R[2, 0]) / s, (R[1, 2] + R[2, 1]) / s, 0.25 * s]
    out = np.array(q)
    out /= np.linalg.norm(out)
    return out if out[0] >= 0 else -out


#: The source's own origin numbers (xyz of a URDF origin) are written when they give the pose to this,
#: relative to the robot size: a pose re-expressed by robkin differs from them by rounding (~1e-16).
SAME_ORIGIN_TOL = 1e-12


def place_attrs(rel: np.ndarray, scale: float = 1.0, origin: tuple[float, ...] | None = None) -> str:
    """`` pos="..." quat="..."`` of a pose (4, 4) relative to its parent, each left out when it is
    the identity up to ``NOISE`` (positions: times ``scale``, the robot size). ``origin``: the
    source's six numbers (xyz, rpy) of the same pose, whose xyz is written when it still gives it."""
    from ..files.float_text import float_text

    p = np.array(rel[:3, 3], dtype=float)
    if origin is not None:
        from ..trees.model import origin_matrix

        if np.abs(origin_matrix(origin[:3], origin[3:]) - rel).max() <= SAME_ORIGIN_TOL * scale:
            p = np.array(origin[:3], dtype=float)
    p[np.abs(p) < NOISE * scale] = 0.0
    q = quat_from_matrix(rel[:3, :3])
    q[np.abs(q) < NOISE] = 0.0
    pos = f' pos="{" ".join(float_text(v) for v in p)}"' if p.any() else ""
    quat = "" if (q[1:] == 0).all() else f' quat="{" ".join(float_text(v) for v in q)}"'
    return pos + quat
