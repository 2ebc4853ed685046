"""ISO 9283 pose accuracy (AP) and pose repeatability (RP), per commanded pose.

ISO 9283:1998 (Manipulating industrial robots - Performance criteria and related test methods), 7.2:
a pose is commanded n times (the standard: 30 cycles) and the attained poses are measured. Here the
measurements of one commanded pose are the rows of a measurement file with the same joint values (a
"cluster"), and the command pose is the model's prediction at those joint values, with its best base
and marker (``calibrate(..., kinematics=False)``: the measuring frame registered to the model, as
``robkin check`` does). With x_j, y_j, z_j the attained positions (j = 1..n) and x_c, y_c, z_c the
command position:

- barycentre: x_bar = (1/n) sum x_j (and y, z);
- position accuracy: AP_p = sqrt((x_bar - x_c)^2 + (y_bar - y_c)^2 + (z_bar - z_c)^2), with its
  components AP_x = x_bar - x_c, AP_y, AP_z;
- orientation accuracy: AP_a = a_bar - a_c, AP_b = b_bar - b_c, AP_c = c_bar - c_c, where a, b, c are
  the rotations about the x, y, z axes of the measuring frame (R = Rz(c) Ry(b) Rx(a)); the differences
  are taken per measurement and wrapped to (-180, 180] deg before averaging, so that a pose near
  +-180 deg does not average to 0;
- position repeatability: RP_l = l_bar + 3 S_l, with l_j = the distance of the attained position j from
  the barycentre, l_bar = (1/n) sum l_j and S_l = sqrt(sum (l_j - l_bar)^2 / (n - 1));
- orientation repeatability: RP_a = +-3 S_a, S_a = sqrt(sum (a_j - a_bar)^2 / (n - 1)) (and b, c).

A cluster of one measurement has AP but no RP (None).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..robot import Robot

__all__ = ["PoseFigures", "Iso9283Report", "clusters", "pose_figures", "iso9283", "abc_angles"]


def clusters(q: np.ndarray) -> list[np.ndarray]:
    """Row indices of each commanded pose: rows with equal joint values (N, n), in order of first
    appearance."""
    _, first, inverse = np.unique(np.asarray(q, dtype=float), axis=0, return_index=True, return_inverse=True)
    inverse = inverse.ravel()
    order = np.argsort(first)
    return [np.flatnonzero(inverse == k) for k in order]


def abc_angles(R: np.ndarray) -> np.ndarray:
    """(N, 3) angles a, b, c (rad) with R = Rz(c) Ry(b) Rx(a), of rotations R (N, 3, 3)."""
    b = np.arcsin(np.clip(-R[:, 2, 0], -1.0, 1.0))
    a = np.arctan2(R[:, 2, 1], R[:, 2, 2])
    c = np.arctan2(R[:, 1, 0], R[:, 0, 0])
    return np.stack([a, b, c], axis=1)


def _wrap(x: np.ndarray) -> np.ndarray:
    return (x + np.pi) % (2 * np.pi) - np.pi


@dataclass
class PoseFigures:
    """ISO 9283 figures of one commanded pose (metres, radians; see the module doc)."""

    rows: list[int]
    q: list[float]
    n: int
    ap_p: float
    ap_xyz: list[float]
    rp_l: float | None
    l_bar: float | None
    s_l: float | None
    ap_abc: list[float] | None = None
    rp_abc: list[float] | None = None

    def to_dict(self) -> dict[str, Any]:
        return {"rows": self.rows, "q": self.q, "n": self.n, "AP_p": self.ap_p,
                "AP_x": self.ap_xyz[0], "AP_y": self.ap_xyz[1], "AP_z": self.ap_xyz[2],
                "RP_l": self.rp_l, "l_bar": self.l_bar, "S_l": self.s_l,
                **({} if self.ap_abc is None else {"AP_a": self.ap_abc[0], "AP_b": self.ap_abc[1],
                                                    "AP_c": self.ap_abc[2]}),
                **({} if self.rp_abc is None else {"RP_a": self.rp_abc[0], "RP_b": self.rp_abc[1],
                                                    "RP_c": self.rp_abc[2]})}


def pose_figures(command: np.ndarray, attained: np.ndarray, command_R: np.ndarray | None = None,
                 attained_R: np.ndarray | None = None, rows: list[int] | None = None,
                 q: ArrayLike | None = None) -> PoseFigures:
    """The ISO 9283 figures of one commanded pose.

    Parameters
    ----------
    command : (3,) array
        The command position (m).
    attained : (n, 3) array
        The attained (measured) positions (m), one per time the pose was commanded.
    command_R : (3, 3) array, optional
        The command orientation; with ``attained_R``, the orientation figures AP_a/b/c and RP_a/b/c.
    attained_R : (n, 3, 3) array, optional
        The attained orientations.
    rows : list of int, optional
        The measurements' line numbers (default 1..n), for the report.
    q : (n_joints,) array, optional
        The commanded joint values (rad, m), for the report.

    Returns
    -------
    PoseFigures
    """
    P = np.asarray(attained, dtype=float)
    n = len(P)
    bary = P.mean(axis=0)
    ap = bary - np.asarray(command, dtype=float)
    rp_l = l_bar = s_l = None
    if n >= 2:
        lj = np.linalg.norm(P - bary, axis=1)
        l_bar = float(lj.mean())
        s_l = float(np.sqrt(np.sum((lj - l_bar) ** 2) / (n - 1)))
        rp_l = l_bar + 3.0 * s_l
    ap_abc = rp_abc = None
    if command_R is not None and attained_R is not None:
        c = abc_angles(np.asarray(command_R, dtype=float)[None])[0]
        dev = _wrap(abc_angles(np.asarray(attained_R, dtype=float)) - c)   # a_j - a_c, wrapped
        ap_abc = [float(v) for v in dev.mean(axis=0)]
        if n >= 2:
            rp_abc = [float(3.0 * np.sqrt(np.sum((dev[:, k] - dev[:, k].mean()) ** 2) / (n - 1))) for k in range(3)]
    return PoseFigures(list(range(1, n + 1)) if rows is None else [int(r) for r in rows],
                       [] if q is None else [float(v) for v in np.asarray(q, dtype=float)], n,
                       float(np.linalg.norm(ap)), [float(v) for v in ap], rp_l, l_bar, s_l, ap_abc, rp_abc)


@dataclass
class Iso9283Report:
    """ISO 9283 figures of every commanded pose, and the command's registration.

    Attributes
    ----------
    poses : list of PoseFigures
        One per commanded pose, in the order of the file.
    joints : list of str
    world : (4, 4) array
        The model's best base pose in the measuring frame (the command's frame).
    orientations : bool
        Whether orientations were measured (AP_a/b/c, RP_a/b/c).
    residuals : (N, 3) array
        Attained minus command position of every measurement (m), in the file's order.
    stats : dict
        Residual statistics of the model with its best base and marker (``report.residual_stats``).
    """

    poses: list[PoseFigures]
    joints: list[str]
    world: np.ndarray
    orientations: bool
    residuals: np.ndarray
    stats: dict[str, float]
    notes: list[str] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        rp = [p.rp_l for p in self.poses if p.rp_l is not None]
        return {"standard": "ISO 9283:1998, 7.2 (pose accuracy AP, pose repeatability RP)",
                "units": {"position": "m", "orientation": "rad"}, "joints": self.joints,
                "command": "the model's prediction with its best base and marker",
                "world": self.world.tolist(), "poses": [p.to_dict() for p in self.poses],
                "AP_p_max": max(p.ap_p for p in self.poses), "RP_l_max": max(rp) if rp else None,
                "notes": self.notes}

    def text(self) -> str:
        ori = self.orientations
        head = f"{'pose':<5} {'first row':<10} {'n':>4} {'AP_p mm':>9} {'AP_x mm':>9} {'AP_y mm':>9} {'AP_z mm':>9} {'RP_l mm':>9}"
        if ori:
            head += f" {'AP_a deg':>9} {'AP_b deg':>9} {'AP_c deg':>9} {'RP_a deg':>9} {'RP_b deg':>9} {'RP_c deg':>9}"
        out = ["ISO 9283 pose accuracy (AP) and repeatability (RP), per commanded pose (rows with equal joint values)",
               "command: the model's prediction with its best base and marker, in the measuring frame", head]
        for k, p in enumerate(self.poses, start=1):
            line = (f"P{k:<4} {p.rows[0]:<10} {p.n:>4} {p.ap_p * 1e3:>9.4f} " + " ".join(f"{v * 1e3:>+9.4f}" for v in p.ap_xyz)
                    + f" {'-' if p.rp_l is None else f'{p.rp_l * 1e3:.4f}':>9}")
            if ori and p.ap_abc is not None:
                line += " " + " ".join(f"{np.degrees(v):>+9.4f}" for v in p.ap_abc)
                line += " " + " ".join(f"{'-' if p.rp_abc is None else f'{np.degrees(v):.4f}':>9}"
                                       for v in (p.rp_abc or [0, 0, 0]))
            out.append(line)
        out.append("AP_p: distance from the barycentre of the attained positions to the command position; "
                   "RP_l = l_bar + 3 S_l (l_j: distance of attained position j from the barycentre)")
        if ori:
            out.append("AP_a/b/c: mean attained minus command angle about x/y/z (R = Rz(c) Ry(b) Rx(a)); RP_a/b/c = 3 S")
        out += self.notes
        return "\n".join(out)


def iso9283(robot: Robot, q: ArrayLike, positions: ArrayLike, orientations: ArrayLike | None = None, *,
            model: str = "hayati", world: ArrayLike | None = None, marker: ArrayLike | None = None,
            rows: list[int] | None = None) -> Iso9283Report:
    """ISO 9283 AP and RP of measurements per commanded pose, the command being the model with its best
    base and marker (see the module doc).

    Parameters
    ----------
    robot : Robot
        The model.
    q : (N, n) array
        Commanded joint values (rad, m); rows with equal values are one commanded pose.
    positions : (N, 3) array
        Measured points in the measuring frame (m).
    orientations : (N, 4) array, optional
        Measured orientations as quaternions (w, x, y, z): adds the orientation figures.
    model : str
        The error model of the base and marker fit (as ``calibrate``'s).
    world : (4, 4) array, optional
        A known base in the measuring frame (as ``calibrate``'s).
    marker : (3,) array, optional
        A known marker in the tool frame (m).
    rows : list of int, optional
        The measurements' line numbers, for the report.

    Returns
    -------
    Iso9283Report
    """
    from .solve import calibrate

    base = calibrate(robot, q, positions, orientations, kinematics=False, model=model, world=world, marker=marker,
                     rows=rows, loss="linear")   # every measurement counts: repeatability is about the spread
    Q = np.asarray(q, dtype=float)
    P = np.asarray(positions, dtype=float)
    T = base.robot.world @ base.robot.fk(Q)
    Rm = None
    if orientations is not None:
        from .inputs import check_measured

        Rm = check_measured(robot, Q, P, orientations)[2]
    rows = list(range(1, len(Q) + 1)) if rows is None else list(rows)
    poses = []
    for idx in clusters(Q):
        poses.append(pose_figures(T[idx[0], :3, 3], P[idx], None if Rm is None else T[idx[0], :3, :3],
                                  None if Rm is None else Rm[idx], [rows[i] for i in idx], Q[idx[0]]))
    notes = []
    if all(p.n == 1 for p in poses):
        notes.append("every pose was measured once: no repeatability (ISO 9283 commands each pose 30 times)")
    return Iso9283Report(poses, [j.name for j in robot.joints], base.robot.world, Rm is not None,
                         P - T[:, :3, 3], base.before_fit, notes)
