"""A robot's error parameters for calibration, as a chain of elementary motions, with their Jacobian.

A model is the measured pose written as one product of constant transforms and elementary motions
(a translation along, or a rotation about, one axis of the current frame), each elementary motion
carrying one parameter and, for the joints, the joint value:

    world * W(6) * base * row_1(q_1) * ... * row_n(q_n) * tool * marker(3 or 6)

- ``hayati`` (default): the robot's Hayati table (``robkin.representations.hayati``): a Hayati row
  Rz(theta + q) Tx(a) Rx(alpha) Ry(beta) where consecutive axes are nearly parallel (its parameters stay
  small and exact there, where a DH row's d and the position of its common normal run off), a standard
  DH row Rz(theta + q) Tz(d) Tx(a) Rx(alpha) elsewhere (Hayati and Mirmirani, 1985).
- ``mdh``: the modified DH table, Rx(alpha) Tx(a) Rz(theta + q) Tz(d) per row.
- ``poe``: every joint frame of the GJD moved by a full small rigid motion Tx Ty Tz Rx Ry then the joint
  Rz(theta + q), the local product-of-exponentials model (Chen and Yang's), free of singular rows.

Prismatic joints add q to d (Tz) instead of theta. With ``compliance``, each joint gets one more
parameter c_i (rad per N m, m per N: 1 / stiffness, ``robkin.calibration.compliance``) and its value
becomes q_i - c_i tau_i, tau the holding torques of the pose (given with the joint values): the pose is
linear in c_i to first order, its Jacobian column -tau_i times the joint's. The base W is the robot base in the measuring frame
(identified unless known); the marker is the measured point on the tool (its position; with measured
orientations, its full pose), identified unless known.

The derivative of the measured point p with respect to a parameter of an elementary motion whose frame
F (after the motion, in the measuring frame) has axis u = F e and origin o is u x (p - o) for a
rotation and u for a translation; the derivative of the orientation (a rotation vector in the
measuring frame) is u for a rotation and 0 for a translation. One pass over the chain gives all of them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Sequence

import numpy as np

from .. import se3
from ..robot import Robot

if TYPE_CHECKING:  # pragma: no cover
    from ..representations.link_table import LinkTable

__all__ = ["ErrorModel", "build_model", "MODELS", "KINDS"]

MODELS = ("hayati", "mdh", "poe")
#: elementary motions: translations along and rotations about the current frame's x, y, z
KINDS = ("Tx", "Ty", "Tz", "Rx", "Ry", "Rz")
_FLIP_X = np.diag([1.0, -1.0, -1.0, 1.0])
#: Poses per block of the Jacobian's pass: the pass keeps every frame of the chain (128 bytes a pose per
#: elementary motion; ~30 motions for a 6-joint arm), which at the 200 000 poses a measurement file may
#: hold was ~0.8 GB at once; 4096 poses hold ~16 MB, and the blocks' Python overhead (~40 numpy calls
#: each) is lost in their work.
JACOBIAN_BLOCK = 4096


@dataclass
class Op:
    """One step of the chain: a constant transform (``kind`` None) or an elementary motion."""

    kind: str | None
    const: np.ndarray | None = None   # (4, 4) when kind is None
    param: int = -1                  # index into the parameter vector
    joint: int = -1                  # joint whose value adds to the parameter (-1: none)
    sign: float = 1.0                # +1, or -1 for a flipped joint
    comp: int = -1                   # index of the joint's compliance parameter (-1: none)


@dataclass
class ErrorModel:
    """A robot's calibration model: the chain, the parameters' nominal values, names and groups.

    Attributes
    ----------
    robot : Robot
        The nominal robot.
    kind : str
        One of ``MODELS``.
    ops : list of Op
        The chain after the measuring frame -> world part (see the module doc).
    nominal : (P,) array
        Parameter values of the nominal robot (world and marker: the starting estimate).
    names : list of str
        A readable name per parameter ("joint 2 zero offset", "link 3 alpha", "base x", "marker z").
    units : list of str
        'm' or 'rad' per parameter.
    groups : list of str
        What each parameter belongs to: "base", "marker", or the joint's name.
    joint_ops : list of int
        Index in ``ops`` of each joint's motion (n,).
    full_pose : bool
        Whether the marker has an orientation too (measured orientations).
    """

    robot: Robot
    kind: str
    ops: list[Op]
    nominal: np.ndarray
    names: list[str]
    units: list[str]
    groups: list[str]
    joint_ops: list[int]
    full_pose: bool
    world_params: list[int] = field(default_factory=list)
    marker_params: list[int] = field(default_factory=list)
    #: index of each joint's compliance parameter (n,), empty without ``compliance``
    compliance_params: list[int] = field(default_factory=list)

    @property
    def size(self) -> int:
        return len(self.nominal)

    # ------------------------------------------------------------------ evaluation
    def poses(self, p: np.ndarray, Q: np.ndarray, *, jacobian: bool = False, columns: np.ndarray | None = None,
              torques: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray | None]:
        """Measured poses (N, 4, 4) at joint values Q (N, n) for parameters p (P,), and optionally the
        Jacobian (N, 6, P) of (position, orientation rotation vector) in the measuring frame; with
        ``columns`` (K,) parameter indices, only those columns of it (N, 6, K), the same values.
        ``torques`` (N, n): the holding torques of the poses (N m, N), which the compliance parameters
        multiply (ignored by a model without them).

        With the Jacobian, the poses go through the chain in blocks of ``JACOBIAN_BLOCK``: each pose is
        computed on its own, so the blocks give the same bits as one pass."""
        N = Q.shape[0]
        col = None if columns is None else {int(c): k for k, c in enumerate(columns)}
        if not jacobian or N <= JACOBIAN_BLOCK:
            return self._poses(p, Q, jacobian, col, torques)
        T, J = np.empty((N, 4, 4)), np.empty((N, 6, len(p) if col is None else len(col)))
        for s in range(0, N, JACOBIAN_BLOCK):
            block = slice(s, s + JACOBIAN_BLOCK)
            T[block], J[block] = self._poses(p, Q[block], True, col, None if torques is None else torques[block])
        return T, J

    def _poses(self, p: np.ndarray, Q: np.ndarray, jacobian: bool, col: dict[int, int] | None = None,
               torques: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray | None]:
        N = Q.shape[0]
        T = np.broadcast_to(np.eye(4), (N, 4, 4))
        frames: list[tuple[int, str, np.ndarray, np.ndarray | None]] = []
        bends = torques is not None and bool(self.compliance_params)
        for op in self.ops:
            if op.kind is None:
                T = T @ _const(op)
                continue
            if op.joint >= 0:
                q = Q[:, op.joint]
                if bends and op.comp >= 0:
                    q = q - p[op.comp] * torques[:, op.joint]   # type: ignore[index]  # the link side: q - c tau (bends: torques given)
                T = T @ _elementary(op.kind, p[op.param] + op.sign * q, N)
            else:  # the same motion at every pose: one 4x4
                T = T @ _elementary(op.kind, p[op.param], 1)[0]
            if jacobian and (col is None or op.param in col):   # the frames of the columns asked for only
                frames.append((op.param if col is None else col[op.param], op.kind, T, None))
            if jacobian and bends and op.comp >= 0 and (col is None or op.comp in col):
                frames.append((op.comp if col is None else col[op.comp], op.kind, T,
                               -op.sign * torques[:, op.joint]))   # type: ignore[index]  # d(value)/dc, per pose
        if not jacobian:
            return T, None
        J = np.zeros((N, 6, len(p) if col is None else len(col)))
        tip = T[:, :3, 3]
        for param, kind, F, factor in frames:   # param: the column of J
            u = F[:, :3, "xyz".index(kind[1])]
            if factor is not None:
                u = u * factor[:, None]
            if kind[0] == "T":
                J[:, :3, param] += u
            else:
                d = tip - F[:, :3, 3]
                J[:, 0, param] += u[:, 1] * d[:, 2] - u[:, 2] * d[:, 1]   # u x d, without np.cross's overhead
                J[:, 1, param] += u[:, 2] * d[:, 0] - u[:, 0] * d[:, 2]
                J[:, 2, param] += u[:, 0] * d[:, 1] - u[:, 1] * d[:, 0]
                J[:, 3:, param] += u
        return T, J

    def robot_at(self, p: np.ndarray, name: str | None = None) -> Robot:
        """The robot these parameters describe: GJD frames from the chain at q = 0, ``world`` the base in
        the measuring frame, the tool at the marker; names, limits and bodies of the nominal robot."""
        world = np.eye(4)
        T = np.eye(4)
        frames = []
        ji = 0
        for k, op in enumerate(self.ops):
            if ji < len(self.joint_ops) and k == self.joint_ops[ji]:
                frames.append(T @ _FLIP_X if op.sign < 0 else T.copy())
                ji += 1
            if op.kind is None:
                T = T @ _const(op)
            else:
                T = T @ _elementary(op.kind, np.array([p[op.param]]), 1)[0]
            if op.param >= 0 and op.param == self.world_params[-1]:
                world, T = T, np.eye(4)   # the base's own motion ends the world part
        frames.append(T)
        return self.robot.replace(frames=np.stack(frames), world=world, name=name or self.robot.name,
                                  frames_from="hayati" if self.kind == "hayati" else None)


def _const(op: Op) -> np.ndarray:
    if op.const is None:  # pragma: no cover - the builder gives every constant step its matrix
        raise ValueError("a constant step without its matrix")
    return op.const


def _elementary(kind: str, v: np.ndarray | float, N: int) -> np.ndarray:
    """(N, 4, 4) elementary motions of one kind by values v (N,) or a scalar."""
    out = np.zeros((N, 4, 4))
    out[:, 0, 0] = out[:, 1, 1] = out[:, 2, 2] = out[:, 3, 3] = 1.0
    axis = "xyz".index(kind[1])
    if kind[0] == "T":
        out[:, axis, 3] = v
        return out
    i, j = ((1, 2), (2, 0), (0, 1))[axis]
    c, s = np.cos(v), np.sin(v)
    out[:, i, i] = c
    out[:, i, j] = -s
    out[:, j, i] = s
    out[:, j, j] = c
    return out


class _Builder:
    def __init__(self) -> None:
        self.ops: list[Op] = []
        self.nominal: list[float] = []
        self.names: list[str] = []
        self.units: list[str] = []
        self.groups: list[str] = []
        self.joint_ops: list[int] = []

    def const(self, M: np.ndarray) -> None:
        self.ops.append(Op(None, const=np.asarray(M, dtype=float)))

    def elem(self, kind: str, value: float, name: str, group: str, joint: int = -1, sign: float = 1.0) -> int:
        idx = len(self.nominal)
        if joint >= 0:
            self.joint_ops.append(len(self.ops))
        self.ops.append(Op(kind, param=idx, joint=joint, sign=sign))
        self.nominal.append(float(value))
        self.names.append(name)
        self.units.append("m" if kind[0] == "T" else "rad")
        self.groups.append(group)
        return idx

    def pose6(self, prefix: str, group: str, values: Sequence[float]) -> list[int]:
        """Tx Ty Tz Rx Ry Rz with the given starting values."""
        return [self.elem(k, v, f"{prefix} {lbl}", group)
                for k, v, lbl in zip(KINDS, values, ("x", "y", "z", "rx", "ry", "rz"))]


def build_model(robot: Robot, kind: str = "hayati", *, world: np.ndarray | None = None,
                marker: np.ndarray | None = None, full_pose: bool = False, world_known: bool = False,
                marker_known: bool = False, compliance: bool = False) -> ErrorModel:
    """The error model of ``robot`` (see the module doc).

    Parameters
    ----------
    robot : Robot
        The nominal robot; its tool J_{n+1} is the flange the marker is given in.
    kind : str
        'hayati', 'mdh' or 'poe'.
    world : (4, 4) array, optional
        Starting estimate of the robot base in the measuring frame (identity if absent).
    marker : (3,) or (4, 4) array, optional
        Starting estimate of the marker in the tool frame: a point, or a pose with ``full_pose``.
    full_pose : bool
        Orientations are measured: the marker has six parameters (else three).
    world_known, marker_known : bool
        The base pose (marker) is known and held: the first joint's frame relative to the base (the
        flange relative to the last joint) gets six parameters of its own, which a free base (marker)
        would otherwise stand for.
    compliance : bool
        One compliance parameter per joint (rad/(N m), m/N; nominal 0), see the module doc.
    """
    b = _Builder()
    W = np.eye(4) if world is None else np.asarray(world, dtype=float)
    b.const(W)
    world_params = b.pose6("base", "base", (0.0,) * 6)
    n = robot.n
    names = [j.name for j in robot.joints]
    if kind == "poe":
        L = robot._local
        for i, j in enumerate(robot.joints):
            b.const(L[i])
            for k in ("Tx", "Ty", "Tz", "Rx", "Ry") + (() if j.revolute else ("Rz",)):
                b.elem(k, 0.0, f"joint {names[i]} frame {k[1]}" if k[0] == "T" else
                       f"joint {names[i]} axis tilt {k[1]}", names[i])
            _joint_elem(b, j.revolute, 0.0, names[i], i, 1.0)
        flange = L[n]
    else:
        table: LinkTable
        if kind == "hayati":
            from ..representations.hayati import hayati_from_robot, hayati_frames

            table = hayati_from_robot(robot)
            beta_row = hayati_frames(robot)[2]
        elif kind == "mdh":
            from ..representations.mdh import mdh_from_robot

            table = mdh_from_robot(robot)
            beta_row = np.zeros(n, dtype=bool)
        else:
            raise ValueError(f"model '{kind}' is not one of {', '.join(MODELS)}")
        b.const(table.base)
        if world_known:   # (the local PoE model's first frame motion already is this)
            b.pose6(f"joint {names[0]} frame", names[0], (0.0,) * 6)
        for i, j in enumerate(robot.joints):
            a, d, alpha, theta = (float(v) for v in table.rows[i, :4])
            sign = -1.0 if j.flip else 1.0
            g, nm = names[i], names[i]
            if kind == "mdh":
                b.elem("Rx", alpha, f"link {nm} alpha", g)
                b.elem("Tx", a, f"link {nm} a", g)
                _joint_elem(b, j.revolute, theta if j.revolute else d, nm, i, sign)
                b.elem("Tz" if j.revolute else "Rz", d if j.revolute else theta,
                       f"link {nm} {'d' if j.revolute else 'theta'}", g)
            else:
                _joint_elem(b, j.revolute, theta if j.revolute else d, nm, i, sign)
                if beta_row[i]:
                    if not j.revolute:  # a prismatic joint's d is its motion: theta is the free one
                        b.elem("Rz", theta, f"link {nm} theta", g)
                    elif abs(d) > 0:
                        b.const(se3.trans(0.0, 0.0, d))
                else:
                    b.elem("Tz" if j.revolute else "Rz", d if j.revolute else theta,
                           f"link {nm} {'d' if j.revolute else 'theta'}", g)
                b.elem("Tx", a, f"link {nm} a", g)
                b.elem("Rx", alpha, f"link {nm} alpha", g)
                if beta_row[i]:
                    b.elem("Ry", float(table.rows[i, 4]), f"link {nm} beta", g)
        flange = table.tool
    b.const(flange)
    if marker_known:
        b.pose6("flange", names[-1], (0.0,) * 6)
    m = np.zeros(3) if marker is None else np.asarray(marker, dtype=float)
    if full_pose:
        M = se3.trans(*m) if m.shape == (3,) else m
        rpy_free = _xyz_angles(M[:3, :3])
        marker_params = b.pose6("marker", "marker", (*M[:3, 3], *rpy_free))
    else:
        point = m if m.shape == (3,) else m[:3, 3]
        marker_params = [b.elem(k, v, f"marker {k[1]}", "marker") for k, v in zip(KINDS[:3], point)]
    compliance_params = []
    if compliance:
        for i, j in enumerate(robot.joints):
            idx = len(b.nominal)
            b.ops[b.joint_ops[i]].comp = idx
            b.nominal.append(0.0)
            b.names.append(f"joint {names[i]} compliance")
            b.units.append("rad/(N m)" if j.revolute else "m/N")
            b.groups.append(names[i])
            compliance_params.append(idx)
    return ErrorModel(robot, kind, b.ops, np.array(b.nominal), b.names, b.units, b.groups, b.joint_ops,
                      full_pose, world_params, marker_params, compliance_params)


def _joint_elem(b: _Builder, revolute: bool, value: float, name: str, joint: int, sign: float) -> None:
    if revolute:
        b.elem("Rz", value, f"joint {name} zero offset", name, joint=joint, sign=sign)
    else:
        b.elem("Tz", value, f"joint {name} zero offset", name, joint=joint, sign=sign)


def _xyz_angles(R: np.ndarray) -> tuple[float, float, float]:
    """(a, b, c) with R = Rx(a) Ry(b) Rz(c), the order of the marker's and base's rotation parameters."""
    b = float(np.arcsin(np.clip(R[0, 2], -1.0, 1.0)))
    a = float(np.arctan2(-R[1, 2], R[2, 2]))
    c = float(np.arctan2(-R[0, 1], R[0, 0]))
    return a, b, c
