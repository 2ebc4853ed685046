"""What standard and modified DH tables share: rows of (a, d, alpha, theta), base, tool, FK.

The two conventions differ only in the link transform (``se3.dh_matrix`` or ``se3.mdh_matrix``) and in
which frame a joint's GJD frame is; everything else lives here once.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable, ClassVar, Sequence, TypeVar

import numpy as np
from numpy.typing import ArrayLike

from .. import se3
from ..errors import InputError
from ..robot import Joint, Robot, check_pose, check_q, identity_pose
from ..samples import unit_sample
from .frames import identity_mask, is_identity, relative_pose

if TYPE_CHECKING:  # pragma: no cover
    from .mass_rows import MassRows

__all__ = ["LinkTable", "check_dh_rows", "flip_frame", "residual_tool", "fk_error", "warn_fk_error",
           "report_fk_error", "check_masses", "check_configurations", "sample_configurations",
           "pose_difference", "joint_signs", "joint_links", "chain_poses", "placement_notes", "COLUMNS", "FLIP_X",
           "WARN_TOL"]

COLUMNS = ("a", "d", "alpha", "theta")
_Table = TypeVar("_Table", bound="LinkTable")
#: The turn by pi about x that takes a joint frame to a flipped joint's frame (``flip_frame``).
FLIP_X = se3.rot_x(np.pi)


def flip_frame(frame: np.ndarray, flip: bool) -> np.ndarray:
    """A joint frame turned by pi about x when the joint moves against its frame's z (``flip``)."""
    return frame @ FLIP_X if flip else frame


def check_dh_rows(rows: ArrayLike, n: int | None = None, field_name: str = "dh.rows",
                  columns: tuple[str, ...] = COLUMNS) -> np.ndarray:
    """Validate a DH/MDH (or Hayati) table as an (n, len(columns)) float array."""
    want = f"rows of {len(columns)} numbers ({', '.join(columns)})"
    try:
        R = np.array(rows, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{field_name}: expected {want}") from None
    if R.ndim != 2 or R.shape[1] != len(columns):
        raise InputError(f"{field_name}: expected {want}, got shape {R.shape}")
    if n is not None and R.shape[0] != n:
        raise InputError(f"{field_name}: expected {n} rows (one per joint), got {R.shape[0]}")
    bad = np.argwhere(~np.isfinite(R))
    if bad.size:
        i, j = bad[0]
        raise InputError(f"{field_name}[{i}].{columns[j]}: must be a finite number")
    return R


def residual_tool(base: np.ndarray, rows: np.ndarray, link_matrix: Callable[..., np.ndarray],
                  tool_pose: np.ndarray, scale: float | np.ndarray) -> np.ndarray:
    """The tool transform that makes base * A_1(0) ... A_n(0) * tool equal ``tool_pose`` exactly.

    Computed from the rows as written (not from the frames they came from), so the table reproduces the
    GJD tool to rounding; a residual that is the identity to rounding is returned as the identity.
    Batched over leading axes: base and tool_pose (..., 4, 4), rows (..., n, k), scale (...).
    """
    A = link_matrix(*np.moveaxis(rows, -1, 0))
    T = base
    for i in range(rows.shape[-2]):
        T = T @ A[..., i, :, :]
    tool = relative_pose(T, tool_pose)
    tool[identity_mask(tool, np.asarray(scale))] = np.eye(4)
    return tool


#: A table whose FK differs from the robot's by more than this (relative to the robot's size) at any
#: of the sampled configurations is reported with its measured error (ConditioningWarning). Exact
#: tables agree to ~1e-15; nearly parallel axes cost ~tilt * offset (a dropped tilt) or ~eps * offset /
#: tilt (a far common normal). 1e-10 is 10x inside the 1e-9 agreement promised without a warning, so
#: a configuration the sample misses is still within the promise.
WARN_TOL = 1e-10
#: Configurations at which a converted table is compared with the robot: q = 0 and a fixed sample
#: (revolute joints in [-pi, pi], prismatic joints within their limits or +-1 robot size).
_CHECK_SAMPLES = 8


def check_configurations(robot: Robot) -> np.ndarray:
    """The configurations (1 + _CHECK_SAMPLES, n) at which a converted table is compared with the
    robot (``sample_configurations`` of one robot)."""
    return sample_configurations(robot.revolute[None], robot.limits[None], np.array([robot.scale]))[0]


def sample_configurations(revolute: np.ndarray, limits: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """The check configurations (B, 1 + _CHECK_SAMPLES, n) of B robots with n joints each: q = 0, then
    the fixed sample scaled to each joint's range (revolute within [-pi, pi], prismatic within +-1
    robot size, both inside the joint's limits).

    Parameters
    ----------
    revolute : (B, n) bool array
    limits : (B, n, 2) array
        Lower and upper limits, -inf / +inf where none are given.
    scale : (B,) array
        Each robot's size.
    """
    B, n = revolute.shape
    span = np.where(revolute, np.pi, scale[:, None])
    lo = np.where(np.isfinite(limits[..., 0]), np.maximum(limits[..., 0], -span), -span)
    hi = np.where(np.isfinite(limits[..., 1]), np.minimum(limits[..., 1], span), span)
    Q = np.zeros((B, 1 + _CHECK_SAMPLES, n))
    Q[:, 1:] = lo[:, None] + unit_sample(_CHECK_SAMPLES, n) * (hi - lo)[:, None]
    return Q


def pose_difference(A: np.ndarray, B: np.ndarray, scale: float | np.ndarray) -> np.ndarray:
    """Largest difference of two pose sets (..., m, 4, 4) over their m poses, in length units (...):
    position difference plus the rotation difference (largest matrix entry) times ``scale`` (...)."""
    pos = np.linalg.norm(A[..., :3, 3] - B[..., :3, 3], axis=-1)
    rot = np.abs(A[..., :3, :3] - B[..., :3, :3]).max(axis=(-2, -1))
    return (pos + rot * np.asarray(scale)[..., None]).max(axis=-1)


def fk_error(fk: Callable[[np.ndarray], np.ndarray], robot: Robot) -> float:
    """Largest FK difference of a table from the robot, in length units (``pose_difference``), over
    the ``check_configurations``."""
    Q = check_configurations(robot)
    return float(pose_difference(fk(Q), robot.fk(Q), robot.scale))


def warn_fk_error(fk: Callable[[np.ndarray], np.ndarray], robot: Robot, section: str) -> float:
    """Measure ``fk_error`` and issue a ConditioningWarning stating it when above WARN_TOL; returns it."""
    err = fk_error(fk, robot)
    report_fk_error(err, robot, section, stacklevel=4)
    return err


def report_fk_error(err: float, robot: Robot, section: str, *, where: str = "",
                    stacklevel: int = 3) -> None:
    """Issue a ConditioningWarning stating a measured ``fk_error`` when it is above WARN_TOL (relative to
    the robot's size), saying why (nearly parallel axes, or rounding); ``where`` prefixes the message
    (which robot of a batch)."""
    if err > WARN_TOL * robot.scale:
        import warnings

        from ..errors import ConditioningWarning
        from ..lines import ANGLE_TOL

        # sqrt(ANGLE_TOL) ~ 1.2e-4 rad: nearer than that to parallel, a DH common normal lies more
        # than ~1e4 offsets away, or (below ANGLE_TOL) the tilt is dropped: the pairs worth naming
        tilts = _tilted_pairs(robot, ANGLE_TOL ** 0.5)
        why = (", ".join(tilts) if tilts else
               "of rounding in the table's parameters")
        hint = "" if section == "hayati" else "; the hayati table is exact there"
        warnings.warn(f"{where}{section}: this table reproduces the robot's FK only to {err:.2g} m (robot "
                      f"size {robot.scale:.3g} m; measured at q = 0 and {_CHECK_SAMPLES} configurations) because "
                      f"{why}{hint}", ConditioningWarning, stacklevel=stacklevel)


def _tilted_pairs(robot: Robot, below: float) -> list[str]:
    """'joints i and i+1 are (angle) rad from parallel' for consecutive joint axes (the first pair: the base z axis
    and joint 1) closer than ``below`` (sin of the angle) to parallel but not exactly parallel."""
    from ..lines import cross, norm

    z = np.vstack([[0.0, 0.0, 1.0], robot.axes])
    out = []
    for i in range(robot.n):
        s = norm(cross(z[i], z[i + 1]))
        if 0.0 < s < below:
            pair = "the base z axis and joint 1" if i == 0 else f"joints {i} and {i + 1}"
            out.append(f"{pair} are {s:.2g} rad from parallel")
    return out


def placement_notes(table: "LinkTable") -> list[str]:
    """Why a table needs a base or a tool transform (one line each; none when they are identities)."""
    # the table's own size (its lengths and offsets) as the scale of "identity to rounding"
    scale = float(np.abs(table.rows[:, :2]).sum() + np.linalg.norm(table.base[:3, 3])
                  + np.linalg.norm(table.tool[:3, 3])) or 1.0
    notes = []
    if not is_identity(table.base, scale):
        why = ("the robot base frame's x axis does not meet joint 1's axis at a right angle, or joint 1's "
               "axis is tilted from the base z axis" if table.SECTION == "mdh" else
               "joint 1's axis is not the robot base z axis")
        notes.append(f"base: {why}, so frame {{0}} is reached by this fixed transform")
    if not is_identity(table.tool, scale):
        notes.append("tool: the tool frame is not the table's last frame (its x axis does not cross the "
                     "last joint axis at a right angle, or it is turned about or shifted along that axis), "
                     "so the rest is this fixed transform")
    return notes


@dataclass(frozen=True, eq=False)
class LinkTable:
    """Rows (n, 4) of (a, d, alpha, theta), joints, base and tool (4, 4); FK from the table itself.

    A subclass may add columns after theta (Hayati's beta): ``link_matrix`` takes them all.
    ``masses`` (optional, ``mass_rows.MassRows``): each link's mass, centre of mass and inertia in the
    table's own link frame i (``link_frames``); None when unknown.
    """

    SECTION: ClassVar[str] = "dh"
    COLUMNS: ClassVar[tuple[str, ...]] = COLUMNS
    link_matrix: ClassVar[Callable[..., np.ndarray]] = staticmethod(se3.dh_matrix)

    rows: np.ndarray
    joints: tuple[Joint, ...]
    base: np.ndarray = field(default_factory=identity_pose)
    tool: np.ndarray = field(default_factory=identity_pose)
    masses: "MassRows | None" = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "joints", tuple(self.joints))
        object.__setattr__(self, "rows", check_dh_rows(self.rows, len(self.joints), f"{self.SECTION}.rows",
                                                                type(self).COLUMNS))
        object.__setattr__(self, "base", check_pose(self.base, f"{self.SECTION}.base"))
        object.__setattr__(self, "tool", check_pose(self.tool, f"{self.SECTION}.tool"))
        if self.masses is not None:
            check_masses(self.masses, len(self.joints), self.SECTION)

    @property
    def n(self) -> int:
        return len(self.joints)

    def __str__(self) -> str:
        """The table as the CLI prints it (``robkin convert --to dh / mdh``)."""
        from .presentation import table_text

        return table_text(self)

    def to_dict(self) -> dict[str, Any]:
        """A robot document (dict): ``joints`` and this table's section, as ``robkin.load`` reads it."""
        from .presentation import table_document

        return table_document(self)

    def link_transforms(self, q: ArrayLike) -> np.ndarray:
        """A_i(q_i) for q (..., n) -> (..., n, 4, 4): revolute joints add to theta, prismatic to d
        (flipped joints subtract)."""
        revolute, sign = joint_signs(self.joints)
        return joint_links(type(self).link_matrix, self.rows, revolute, sign, np.asarray(q, dtype=float))

    def fk(self, q: ArrayLike) -> np.ndarray:
        """Tool pose: q (n,) -> (4, 4) or (N, n) -> (N, 4, 4), evaluated from the table itself."""
        Q = check_q(q, self.n)
        return chain_poses(self.base, self.link_transforms(Q), self.tool)

    def link_frames(self) -> np.ndarray:
        """The table's frames {0}..{n} at q = 0 (n + 1, 4, 4) in the robot base frame: {0} = base,
        {i} = base A_1(0) ... A_i(0). Frame {i} moves with link i (joint i turns or slides it): the
        frame the mass properties of row i are expressed in (``masses``)."""
        A = self.link_transforms(np.zeros(self.n))
        F = np.empty((self.n + 1, 4, 4))
        F[0] = self.base
        for i in range(self.n):
            F[i + 1] = F[i] @ A[i]
        return F

    def with_masses(self: _Table, masses: "MassRows | None") -> _Table:
        """The same table carrying ``masses`` (each link's in its frame {i}), or none."""
        if masses is not None:
            check_masses(masses, self.n, self.SECTION)
        # the rows, base and tool are this table's, already validated: not checked again
        table = type(self)._from_checked(self.rows, self.joints, self.base, self.tool)
        object.__setattr__(table, "masses", masses)
        return table

    @classmethod
    def _from_checked(cls: type[_Table], rows: np.ndarray, joints: tuple[Joint, ...], base: np.ndarray,
                      tool: np.ndarray) -> _Table:
        """A table from parts already validated as ``__post_init__`` would (finite float rows of the
        right shape, poses through ``check_pose(s)``), without validating them again."""
        table = cls.__new__(cls)
        for name, value in (("rows", rows), ("joints", joints), ("base", base), ("tool", tool),
                            ("masses", None)):
            object.__setattr__(table, name, value)
        return table


def check_masses(masses: Any, n: int, section: str) -> None:
    """InputError unless ``masses`` is a ``MassRows`` of n links (one per row of a table with n joints)."""
    from .mass_rows import MassRows

    if not isinstance(masses, MassRows):
        raise InputError(f"{section}.masses: expected a robkin.representations.mass_rows.MassRows, got "
                         f"{type(masses).__name__}")
    if masses.n != n:
        raise InputError(f"{section}.masses: {masses.n} links' mass properties for {n} rows")


def joint_signs(joints: Sequence[Joint]) -> tuple[np.ndarray, np.ndarray]:
    """Which joints are revolute (n,) bool, and the sign (n,) with which each adds its value (-1 for a
    flipped joint)."""
    return (np.array([j.revolute for j in joints], dtype=bool),
            np.array([-1.0 if j.flip else 1.0 for j in joints]))


def joint_links(link_matrix: Callable[..., np.ndarray], rows: np.ndarray, revolute: np.ndarray,
                sign: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """Link transforms (..., n, 4, 4) of rows (..., n, k) at joint values Q (..., n), all broadcast
    together with ``joint_signs`` (..., n): revolute joints add to theta, prismatic ones to d."""
    a, d, alpha, theta, *extra = np.moveaxis(rows, -1, 0)
    return link_matrix(a, d + np.where(revolute, 0.0, sign * Q), alpha,
                       theta + np.where(revolute, sign * Q, 0.0), *extra)


def chain_poses(base: np.ndarray, links: np.ndarray, tool: np.ndarray) -> np.ndarray:
    """base A_1 ... A_n tool for links (..., n, 4, 4) and base, tool broadcastable to (..., 4, 4)."""
    T = np.broadcast_to(base, links.shape[:-3] + (4, 4))
    for i in range(links.shape[-3]):
        T = T @ links[..., i, :, :]
    return T @ tool
