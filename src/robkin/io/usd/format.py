"""What the USD writer and reader share: the pxr import, names as USD identifiers, units, quaternions.

Units
    The stage is in metres and kilograms (``metersPerUnit = 1``, ``kilogramsPerUnit = 1``), Z up, as
    robkin's robots are. UsdPhysics states angles in **degrees**: a revolute joint's limits, a drive's
    target position, and an angular drive's stiffness (N m/deg) and damping (N m s/deg); ``drive_gains``
    converts robkin's SI gains (N m/rad, N m s/rad) by pi/180. Linear drives are in N/m and N s/m.

Precision
    UsdPhysics declares joint frames (``localPos``: float3, ``localRot``: quatf), limits, drive gains
    and mass properties (mass, ``centerOfMass``, ``diagonalInertia``, ``principalAxes``) as 32-bit
    floats; only the prims' transforms (``xformOp:translate`` double3, ``xformOp:orient`` quatd) and
    robkin's own attributes (``robkin:*``) hold doubles. A simulator reads the kinematics from the
    joint frames, and so does robkin's reader: a robot goes through USD with float32 rounding
    (relative ~6e-8 per number).

Names
    A prim name is a USD identifier (letters, digits, ``_``; not starting with a digit): a link or joint
    name that is not one is written with every other character as ``_`` (and a ``_`` in front of a
    leading digit, a suffix ``_2`` where two names would meet), and its own name kept in the string
    attribute ``robkin:name``, which the reader prefers, so names come back exactly.
"""

from __future__ import annotations

import math
import re
from typing import Any

import numpy as np

from ...errors import InputError

__all__ = ["pxr", "identifier", "unique_identifier", "NAME_ATTR", "DEG", "quat_wxyz", "matrix_of_quat",
           "matrix_of_gf", "without_scale", "authored", "api_schemas", "USD_EXTENSIONS", "INSTALL_HINT"]

USD_EXTENSIONS = (".usda", ".usd", ".usdc")
INSTALL_HINT = "pip install 'robkin[usd]'"
#: The original name of a link or joint whose prim name had to change (and of every robkin link).
NAME_ATTR = "robkin:name"
#: Degrees per radian: UsdPhysics' angular unit.
DEG = 180.0 / math.pi

_IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")


def pxr() -> Any:
    """The ``pxr`` package (usd-core); InputError naming the extra when it is not installed."""
    try:
        import pxr as package
        from pxr import Gf, Sdf, Usd, UsdGeom, UsdPhysics  # noqa: F401 - the modules robkin uses
    except ImportError:
        raise InputError(f"USD needs usd-core, which is not installed: {INSTALL_HINT}") from None
    return package


def identifier(name: str) -> str:
    """``name`` as a USD identifier (see the module doc); '_' for an empty name."""
    if _IDENT.match(name):
        return name
    out = re.sub(r"[^A-Za-z0-9_]", "_", name) or "_"
    return "_" + out if out[0].isdigit() else out


def unique_identifier(name: str, taken: set[str]) -> str:
    """``identifier(name)``, with a suffix ``_2``, ``_3`` ... if it is in ``taken``; added to ``taken``."""
    base = identifier(name)
    out, k = base, 2
    while out in taken:
        out, k = f"{base}_{k}", k + 1
    taken.add(out)
    return out


def quat_wxyz(R: np.ndarray) -> tuple[float, float, float, float]:
    """Unit quaternion (w, x, y, z), w >= 0, of a rotation matrix (3, 3) (Shepperd's method)."""
    from ..mjcf.format import quat_from_matrix

    q = quat_from_matrix(R)
    return float(q[0]), float(q[1]), float(q[2]), float(q[3])


def matrix_of_quat(w: float, x: float, y: float, z: float) -> np.ndarray:
    """Rotation matrix (3, 3) of a quaternion (w, x, y, z), normalised first (a float32 one is off by ~1e-7)."""
    n = math.sqrt(w * w + x * x + y * y + z * z)
    if not n > 0 or not math.isfinite(n):
        raise InputError(f"quaternion ({w}, {x}, {y}, {z}) is not a rotation")
    w, x, y, z = w / n, x / n, y / n, z / n
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def matrix_of_gf(m: Any) -> np.ndarray:
    """A Gf.Matrix4d (row vectors, translation in the last row) as a column-vector pose (4, 4)."""
    return np.array(m, dtype=float).T


def without_scale(T: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(the transform (4, 4) with the scale of its columns removed, that scale (3,))."""
    s = np.linalg.norm(T[:3, :3], axis=0)
    out = T.copy()
    out[:3, :3] = T[:3, :3] / np.where(s > 0, s, 1.0)
    return out, s


def authored(prim: Any, name: str) -> Any:
    """The value of a prim's attribute where the file gives one (None: absent or not authored)."""
    attr = prim.GetAttribute(name)
    return attr.Get() if attr and attr.HasAuthoredValue() else None


def api_schemas(prim: Any) -> list[str]:
    """The API schemas applied to a prim as the file names them, those usd-core does not know too
    (``GetAppliedSchemas`` leaves out PhysX's, which are not in usd-core)."""
    ops = prim.GetMetadata("apiSchemas")
    return list(ops.ApplyOperations([])) if ops is not None else []
