"""Inverse dynamics, gravity torques and the mass matrix of a robot's chain (compiled kernels).

The chain's bodies are those of ``robkin.bodies``: body i moves with joint i and carries everything
rigidly attached to it at q = 0 (fixed links, the tool, links off the chain, whose joints are held at
0). Their mass properties are merged by ``link_masses`` and expressed in the GJD frames J_i, which
move with the bodies, for ``robkin.compiled.dynamics``. Body 0 (the base) never moves and takes no part.

Gravity is given in the world frame (``Robot.world`` maps world -> robot base); the default is
(0, 0, -9.81) m/s^2, pinocchio's and the Robotics Toolbox's.
"""

from __future__ import annotations

import weakref
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..checks import check_q
from ..errors import InputError
from .mass_properties import link_masses

if TYPE_CHECKING:  # pragma: no cover
    from ..compiled.dynamics import ChainDynamics
    from ..robot import Robot

__all__ = ["inverse_dynamics", "gravity_torques", "mass_matrix", "STANDARD_GRAVITY"]

#: the default gravity vector in the world frame (m/s^2), as pinocchio and the Robotics Toolbox use
STANDARD_GRAVITY = (0.0, 0.0, -9.81)

#: compiled dynamics per robot (a Robot is immutable; the cache dies with it)
_KERNELS: "weakref.WeakKeyDictionary[Robot, ChainDynamics]" = weakref.WeakKeyDictionary()


def _kernel(robot: "Robot") -> "ChainDynamics":
    kernel = _KERNELS.get(robot)
    if kernel is None:
        from ..compiled.dynamics import ChainDynamics

        masses = link_masses(robot)
        if masses is None:
            name = f"robot '{robot.name}'" if robot.name else "the robot"
            raise InputError(f"{name} has no mass properties (its source gave no inertials): dynamics need "
                             f"the links' masses (URDF <inertial>, MJCF inertials, or m, r, I in a table's rows)")
        frames = np.concatenate([np.eye(4)[None], robot.frames[:-1]])
        mass, com, inertia = masses.in_frames(frames)
        kernel = ChainDynamics(robot._local, robot.revolute, mass[1:], com[1:], inertia[1:])
        _KERNELS[robot] = kernel
    return kernel


def _gravity_in_base(robot: "Robot", gravity: ArrayLike | None) -> np.ndarray:
    g = np.asarray(STANDARD_GRAVITY if gravity is None else gravity, dtype=float)
    if g.shape != (3,) or not np.all(np.isfinite(g)):
        raise InputError(f"gravity: expected 3 finite numbers (m/s^2, world frame), got shape {g.shape}")
    return robot.world[:3, :3].T @ g


def _joint_array(robot: "Robot", value: ArrayLike, name: str, shape: tuple[int, ...] | None) -> np.ndarray:
    a = np.ascontiguousarray(check_q(value, robot.n, name=name))
    if shape is not None and a.shape != shape:
        raise InputError(f"{name}: expected shape {shape} like q, got {a.shape}")
    return a


def inverse_dynamics(robot: "Robot", q: ArrayLike, qd: ArrayLike | None = None, qdd: ArrayLike | None = None,
                     gravity: ArrayLike | None = None) -> np.ndarray:
    """Joint torques (N m) / forces (N) that produce qdd at (q, qd) under gravity (recursive Newton-Euler).

    Parameters
    ----------
    q, qd, qdd : (n,) or (N, n) arrays of one shape
        Joint values (rad or m), velocities (rad/s or m/s), accelerations (rad/s^2 or m/s^2); qd and
        qdd default to zero.
    gravity : (3,) array, optional
        Gravity in the world frame (m/s^2); default (0, 0, -9.81). Give zeros for none.

    Returns
    -------
    (n,) or (N, n) array
    """
    kernel = _kernel(robot)
    g = _gravity_in_base(robot, gravity)
    qa = _joint_array(robot, q, "q", None)
    qda = None if qd is None else _joint_array(robot, qd, "qd", qa.shape)
    qdda = None if qdd is None else _joint_array(robot, qdd, "qdd", qa.shape)
    out = kernel.inverse_dynamics(qa, qda, qdda, g)
    assert out is not None  # checked, contiguous float64 arrays of one shape are always usable
    return out


def gravity_torques(robot: "Robot", q: ArrayLike, gravity: ArrayLike | None = None) -> np.ndarray:
    """Joint torques/forces that hold the robot still at q against gravity: (n,) or (N, n).

    ``gravity`` as in ``inverse_dynamics``. Equals ``inverse_dynamics(q)`` with zero velocity and
    acceleration (pinocchio's ``computeGeneralizedGravity``, the Robotics Toolbox's ``gravload``).
    """
    return inverse_dynamics(robot, q, None, None, gravity)


def mass_matrix(robot: "Robot", q: ArrayLike) -> np.ndarray:
    """Joint-space mass (inertia) matrix at q: (n,) -> (n, n), (N, n) -> (N, n, n), symmetric.

    Composite-rigid-body algorithm; units kg m^2 (revolute pairs), kg m (mixed), kg (prismatic pairs).
    """
    kernel = _kernel(robot)
    out = kernel.mass_matrix(_joint_array(robot, q, "q", None))
    assert out is not None  # a checked, contiguous float64 array is always usable
    return out
