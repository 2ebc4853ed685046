"""What standard and modified DH tables share: rows of (a, d, alpha, theta), base, tool, FK.

The two conventions differ only in the link transform (``se3.dh_matrix`` or ``se3.mdh_matrix``) and in
which frame a joint's GJD frame is; everything else lives here once.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from .. import se3
from ..errors import InputError
from ..robot import Joint, check_pose, check_q
from .frames import is_identity

__all__ = ["LinkTable", "check_dh_rows", "flip_frame", "residual_tool", "COLUMNS"]

COLUMNS = ("a", "d", "alpha", "theta")
_FLIP = se3.rot_x(np.pi)


def flip_frame(frame: np.ndarray, flip: bool) -> np.ndarray:
    """A joint frame turned by pi about x when the joint moves against its frame's z (``flip``)."""
    return frame @ _FLIP if flip else frame


def check_dh_rows(rows: ArrayLike, n: int | None = None, field_name: str = "dh.rows") -> np.ndarray:
    """Validate a DH/MDH table as an (n, 4) float array of (a, d, alpha, theta)."""
    try:
        R = np.array(rows, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{field_name}: expected rows of 4 numbers (a, d, alpha, theta)") from None
    if R.ndim != 2 or R.shape[1] != 4:
        raise InputError(f"{field_name}: expected rows of 4 numbers (a, d, alpha, theta), got shape {R.shape}")
    if n is not None and R.shape[0] != n:
        raise InputError(f"{field_name}: expected {n} rows (one per joint), got {R.shape[0]}")
    bad = np.argwhere(~np.isfinite(R))
    if bad.size:
        i, j = bad[0]
        raise InputError(f"{field_name}[{i}].{COLUMNS[j]}: must be a finite number")
    return R


def residual_tool(base: np.ndarray, rows: np.ndarray, link_matrix: Callable[..., np.ndarray],
                  tool_pose: np.ndarray, scale: float) -> np.ndarray:
    """The tool transform that makes base * A_1(0) ... A_n(0) * tool equal ``tool_pose`` exactly.

    Computed from the rows as written (not from the frames they came from), so the table reproduces the
    GJD tool to rounding; a residual that is the identity to rounding is returned as the identity.
    """
    T = base
    for A in link_matrix(*rows.T):
        T = T @ A
    tool = se3.inv(T) @ tool_pose
    return np.eye(4) if is_identity(tool, scale) else tool


@dataclass(frozen=True, eq=False)
class LinkTable:
    """Rows (n, 4) of (a, d, alpha, theta), joints, base and tool (4, 4); FK from the table itself."""

    SECTION: ClassVar[str] = "dh"
    link_matrix: ClassVar[Callable[..., np.ndarray]] = staticmethod(se3.dh_matrix)

    rows: np.ndarray
    joints: tuple[Joint, ...]
    base: np.ndarray = field(default_factory=lambda: np.eye(4))
    tool: np.ndarray = field(default_factory=lambda: np.eye(4))

    def __post_init__(self) -> None:
        object.__setattr__(self, "joints", tuple(self.joints))
        object.__setattr__(self, "rows", check_dh_rows(self.rows, len(self.joints), f"{self.SECTION}.rows"))
        object.__setattr__(self, "base", check_pose(self.base, f"{self.SECTION}.base"))
        object.__setattr__(self, "tool", check_pose(self.tool, f"{self.SECTION}.tool"))

    @property
    def n(self) -> int:
        return len(self.joints)

    def __str__(self) -> str:
        """The table as the CLI prints it (``robkin convert --to dh / mdh``)."""
        from ..io.table_views import table_text

        return table_text(self)

    def to_dict(self) -> dict[str, Any]:
        """A robot document (dict): ``joints`` and this table's section, as ``robkin.load`` reads it."""
        from ..io.document import table_document

        return table_document(self)

    def link_transforms(self, q: ArrayLike) -> np.ndarray:
        """A_i(q_i) for q (..., n) -> (..., n, 4, 4): revolute joints add to theta, prismatic to d
        (flipped joints subtract)."""
        Q = np.asarray(q, dtype=float)
        rev = np.array([j.revolute for j in self.joints])
        sign = np.array([-1.0 if j.flip else 1.0 for j in self.joints])
        a, d, alpha, theta = self.rows.T
        return type(self).link_matrix(a, d + np.where(rev, 0.0, sign * Q), alpha,
                                      theta + np.where(rev, sign * Q, 0.0))

    def fk(self, q: ArrayLike) -> np.ndarray:
        """Tool pose: q (n,) -> (4, 4) or (N, n) -> (N, 4, 4), evaluated from the table itself."""
        Q = check_q(q, self.n)
        A = self.link_transforms(Q)
        T = np.broadcast_to(self.base, Q.shape[:-1] + (4, 4))
        for i in range(self.n):
            T = T @ A[..., i, :, :]
        return T @ self.tool
