"""Measures that compare estimated structures: total link length and Yoshikawa manipulability.

- ``link_length``: the estimation paper's eq. (48), L = sum_i sqrt(a_i^2 + d_i^2) over the DH rows
  (the distance each DH row moves along its z and x axes), in length units.
- ``manipulability_translational`` / ``_rotational``: Yoshikawa's measure of the linear-velocity and the
  angular-velocity rows of the geometric Jacobian at the tool origin, at q = 0 (the configuration in
  which every estimate reaches its target). Units: length^3 and dimensionless for n >= 3.

Several estimates are singular at q = 0 by construction (type A's straight arm; the axes of type C all
perpendicular to one line). Their manipulability is then a product that includes a singular value of
rounding size (~1e-16 relative); it is reported as exactly 0, so tables show a structural zero rather
than noise.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..robot import Robot

__all__ = ["Metrics", "link_length", "structure_metrics", "RANK_TOL"]

#: A Jacobian block whose smallest singular value is below RANK_TOL times its largest is rank-deficient:
#: entries computed through a chain of n 4x4 products carry ~n * 1e-16 relative rounding, so 1e-10
#: leaves four orders of margin, and a real structure that close to singular is singular in practice.
RANK_TOL = 1e-10


@dataclass(frozen=True)
class Metrics:
    """Length and manipulability of one structure at q = 0.

    Attributes
    ----------
    length : float
        Sum of sqrt(a_i^2 + d_i^2) over the DH rows (length units).
    manipulability_translational : float
        Product of the singular values of the 3 x n linear-velocity Jacobian (length^3 for n >= 3).
    manipulability_rotational : float
        Product of the singular values of the 3 x n angular-velocity Jacobian (dimensionless).
    """

    length: float
    manipulability_translational: float
    manipulability_rotational: float

    def as_dict(self) -> dict[str, float]:
        """The ``metrics`` object of a robot document (plain floats)."""
        return {k: float(v) for k, v in asdict(self).items()}


def link_length(rows: ArrayLike) -> float:
    """Eq. (48) of the estimation paper: sum of sqrt(a^2 + d^2) over DH rows (n, 4) [a, d, alpha, theta]."""
    R = np.asarray(rows, dtype=float)
    return float(np.sum(np.hypot(R[:, 0], R[:, 1])))


def structure_metrics(robot: Robot, rows: ArrayLike, q: ArrayLike | None = None) -> Metrics:
    """Length of the DH ``rows`` and the robot's manipulability at ``q`` (default: home, q = 0)."""
    q0 = np.zeros(robot.n) if q is None else np.asarray(q, dtype=float)
    return Metrics(
        length=link_length(rows),
        manipulability_translational=yoshikawa(robot, q0, "translational"),
        manipulability_rotational=yoshikawa(robot, q0, "rotational"),
    )


def yoshikawa(robot: Robot, q: ArrayLike, kind: str) -> float:
    """Yoshikawa manipulability (``kinematics.jacobian.manipulability``), 0 when rank-deficient."""
    from ..kinematics.jacobian import jacobian_geometric, singular_values

    rows = slice(0, 3) if kind == "translational" else slice(3, 6)
    s = singular_values(jacobian_geometric(robot, q)[rows])
    if s.size == 0 or s[-1] <= RANK_TOL * s[0]:
        return 0.0
    return float(np.prod(s))  # Yoshikawa's measure: the product of the singular values
