"""Mass properties carried by a table's rows: each moving link's mass, centre of mass and inertia,
expressed in that table's own link frame.

Row i of a table describes link i, the body joint i moves (with everything rigidly attached to it at
q = 0 merged in: fixed links, the tool after the last joint, links off the chain held at 0). Its mass
properties are

- ``m``: the mass (kg);
- ``r``: the centre of mass (3,), in link frame i (the table's length unit, normally m);
- ``I``: the inertia (3, 3) about the centre of mass, in the axes of link frame i (kg m^2), written
  as six numbers (Ixx, Iyy, Izz, Ixy, Iyz, Ixz), the products being the tensor's off-diagonal entries
  (Ixy = -sum m x y, the URDF and Robotics Toolbox convention).

Link frame i is each table's own (``link_frames`` of the table): standard DH and Hayati, frame {i}
after joint i (on axis i+1), as the Robotics Toolbox's DH links use; modified DH, frame {i} at the
start of link i, on axis i (Craig); RPY-XYZ, joint i's frame (the URDF child link frame); PoE, the
PoE's own reference frame (the robot base for space screws, the home tool pose M for body screws),
at q = 0. Body 0 (everything fixed to the robot base) has no joint row; its mass properties, when
known, are kept apart (``MassRows.base``, in link frame 0: the table's frame {0}, the robot base for
RPY-XYZ) so that the robot's total mass survives a table, though they never change the joint torques.
Tables without mass properties (``masses is None``) mean "unknown", never zero mass.

The merging and the change of frame are ``robkin.dynamics``' (``link_masses``, ``in_frames``,
``inertials_from_frames``); this module only carries the numbers and checks them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Sequence

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    from ..bodies import Bodies
    from ..robot import Robot

__all__ = ["MassRows", "INERTIA_KEYS", "MASS_KEYS", "masses_of_robot", "bodies_from_masses", "table_bodies",
           "six_from_tensor", "tensor_from_six"]

#: The six inertia entries of a row, in the order the robot document and the tables write them.
INERTIA_KEYS = ("Ixx", "Iyy", "Izz", "Ixy", "Iyz", "Ixz")
#: A row's optional mass fields in the robot document.
MASS_KEYS = ("m", "r", "I")
#: (row, column) of each of INERTIA_KEYS in the 3 x 3 tensor.
_SIX = ((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2))


def six_from_tensor(I: np.ndarray) -> np.ndarray:
    """(..., 3, 3) inertia tensors -> (..., 6) entries (Ixx, Iyy, Izz, Ixy, Iyz, Ixz).

    ``I``: the tensors (..., 3, 3), kg m^2.
    """
    I = np.asarray(I, dtype=float)
    return np.stack([I[..., r, c] for r, c in _SIX], axis=-1)


def tensor_from_six(six: np.ndarray) -> np.ndarray:
    """(..., 6) entries (Ixx, Iyy, Izz, Ixy, Iyz, Ixz) -> (..., 3, 3) symmetric tensors.

    ``six``: the entries (..., 6), kg m^2.
    """
    six = np.asarray(six, dtype=float)
    I = np.empty(six.shape[:-1] + (3, 3))
    for k, (r, c) in enumerate(_SIX):
        I[..., r, c] = I[..., c, r] = six[..., k]
    return I


@dataclass(frozen=True, eq=False)
class MassRows:
    """Mass properties of links 1..n, each in its table's link frame i (see the module docstring).

    Attributes
    ----------
    mass : (n,) array
        kg; 0 for a massless link.
    com : (n, 3) array
        Centre of mass of link i in link frame i (length unit of the table, normally m).
    inertia : (n, 3, 3) array
        Symmetric, about the centre of mass, in the axes of link frame i (kg m^2).
    base : MassRows of one, optional
        Body 0's (everything fixed to the robot base), in link frame 0; None when unknown.
    """

    mass: np.ndarray
    com: np.ndarray
    inertia: np.ndarray
    base: "MassRows | None" = None

    def __post_init__(self) -> None:
        if self.base is not None and (not isinstance(self.base, MassRows) or self.base.n != 1):
            raise InputError("masses.base: expected the base body's mass properties as a MassRows of one")
        mass = np.array(self.mass, dtype=float).reshape(-1)
        n = mass.shape[0]
        try:
            com = np.array(self.com, dtype=float).reshape(n, 3)
            inertia = np.array(self.inertia, dtype=float).reshape(n, 3, 3)
        except ValueError:
            raise InputError(f"masses: expected com (n, 3) and inertia (n, 3, 3) for n = {n} masses, got "
                             f"shapes {np.shape(self.com)} and {np.shape(self.inertia)}") from None
        for name, values in (("m", mass), ("r", com), ("I", inertia)):
            bad = np.argwhere(~np.isfinite(values.reshape(n, -1)))
            if bad.size:
                raise InputError(f"rows[{bad[0][0]}].{name}: must be finite numbers")
        neg = np.flatnonzero(mass < 0)
        if neg.size:
            raise InputError(f"rows[{neg[0]}].m: {float(mass[neg[0]])!r} kg; a mass is >= 0")
        if not np.array_equal(inertia, np.swapaxes(inertia, -1, -2)):
            raise InputError("masses: each inertia must be a symmetric 3 x 3 matrix")
        for name, values in (("mass", mass), ("com", com), ("inertia", inertia)):
            values.setflags(write=False)
            object.__setattr__(self, name, values)

    @classmethod
    def _checked_already(cls, mass: np.ndarray, com: np.ndarray, inertia: np.ndarray,
                         base: "MassRows | None" = None) -> "MassRows":
        """Rows from arrays that are valid by construction (a robot's merged, symmetric inertials moved
        into link frames): the checks of ``__post_init__`` skipped but finiteness (huge inputs can
        overflow in the merge), the arrays made read-only."""
        if not (np.isfinite(mass).all() and np.isfinite(com).all() and np.isfinite(inertia).all()):
            return cls(mass, com, inertia, base)             # the checks, and their message
        rows = object.__new__(cls)
        for name, values in (("mass", mass), ("com", com), ("inertia", inertia)):
            values = np.array(values, dtype=float)
            values.setflags(write=False)
            object.__setattr__(rows, name, values)
        object.__setattr__(rows, "base", base)
        return rows

    @property
    def n(self) -> int:
        return int(self.mass.shape[0])

    @property
    def six(self) -> np.ndarray:
        """(n, 6) inertia entries (Ixx, Iyy, Izz, Ixy, Iyz, Ixz)."""
        return six_from_tensor(self.inertia)

    @classmethod
    def from_six(cls, mass: ArrayLike, com: ArrayLike, six: ArrayLike, base: "MassRows | None" = None
                 ) -> "MassRows":
        """From masses (n,), centres (n, 3) and inertia entries (n, 6) as the documents write them.

        ``mass`` (n,) kg, ``com`` (n, 3) m in each row's frame, ``six`` (n, 6) kg m^2 (Ixx, Iyy, Izz, Ixy,
        Iyz, Ixz), ``base``: the base's own mass properties (a MassRows of one row), or None.
        """
        return cls(np.asarray(mass, dtype=float), np.asarray(com, dtype=float),
                   tensor_from_six(np.asarray(six, dtype=float).reshape(-1, 6)), base)

    def bodies(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(mass (n+1,), com (n+1, 3), inertia (n+1, 3, 3)) of bodies 0..n, body 0 massless when the
        base is unknown (it never changes the joint torques)."""
        base = self.base or MassRows(np.zeros(1), np.zeros((1, 3)), np.zeros((1, 3, 3)))
        return (np.concatenate([base.mass, self.mass]), np.concatenate([base.com, self.com]),
                np.concatenate([base.inertia, self.inertia]))


def masses_of_robot(robot: "Robot", frames: ArrayLike) -> MassRows | None:
    """The robot's mass properties (``robot.bodies.inertials``, merged per moving link) in link frames
    ``frames`` (n + 1, 4, 4): index 0 a frame on the base, index i a frame that moves with link i,
    all in the robot base frame at q = 0. None when the robot has no mass properties.
    """
    if not robot.bodies.inertials:
        return None
    from ..mass_properties import link_masses

    masses = link_masses(robot)
    if masses is None:
        return None
    m, c, I = masses.in_frames(np.asarray(frames, dtype=float))    # finite, m >= 0, I symmetric
    base = MassRows._checked_already(m[:1], c[:1], I[:1]) \
        if any(p.body == 0 for p in robot.bodies.inertials) else None
    return MassRows._checked_already(m[1:], c[1:], I[1:], base)


def bodies_from_masses(masses: MassRows, frames: np.ndarray, names: Sequence[str] | None = None) -> "Bodies":
    """``Bodies`` holding the inertials of bodies 0..n given in link frames ``frames`` (n + 1, 4, 4) (the
    inverse of ``masses_of_robot``; body 0 gets one when ``masses.base`` is known). ``names``: the n + 1
    link names to file them under (default base, link1..linkN, the names ``robkin convert --to urdf``
    gives such links)."""
    from ..bodies import Bodies
    from ..mass_properties import inertials_from_frames

    n = masses.n
    names = list(names) if names is not None else ["base"] + [f"link{i}" for i in range(1, n + 1)]
    mass, com, inertia = masses.bodies()
    return Bodies(inertials=tuple(inertials_from_frames(np.asarray(frames, dtype=float), mass, com, inertia,
                                                        names)))


def table_bodies(masses: MassRows | None, frames: np.ndarray) -> "Bodies":
    """What a table's ``to_robot`` gives ``Robot.bodies``: the inertials of its rows' ``masses`` (in its
    link frames ``frames`` (n + 1, 4, 4)), or nothing when the table has no mass properties."""
    if masses is None:
        from ..bodies import EMPTY_BODIES

        return EMPTY_BODIES
    return bodies_from_masses(masses, frames)
