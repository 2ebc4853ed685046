"""Inverse dynamics, gravity torques and the mass matrix of a robot's chain (compiled kernels).

The chain's bodies are those of ``robkin.bodies``: body i moves with joint i and carries everything
rigidly attached to it at q = 0 (fixed links, the tool, links off the chain, whose joints are held at
0). Their mass properties are merged by ``link_masses`` and expressed in the GJD frames J_i, which
move with the bodies, for ``robkin.compiled.chain.dynamics``. Body 0 (the base) never moves and takes no part.

Gravity is given in the world frame (``Robot.world`` maps world -> robot base); the default is
(0, 0, -9.81) m/s^2, pinocchio's and the Robotics Toolbox's.

Joint armature (``Joint.armature``: a rotor's reflected inertia, kg m^2 for a revolute joint, kg for a
prismatic one; MJCF ``armature``) is added as MuJoCo adds it: ``mass_matrix`` gets it on its diagonal,
``inverse_dynamics`` adds armature * qdd to each joint's torque, and the gravity torques do not change.
A joint without armature (None, every URDF, SDF or table robot) adds nothing.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..checks import check_q, check_threads
from ..errors import InputError
from ..mass_properties import link_masses

if TYPE_CHECKING:  # pragma: no cover
    from ..compiled.chain.dynamics import ChainDynamics
    from ..robot import Robot

__all__ = ["inverse_dynamics", "gravity_torques", "mass_matrix", "STANDARD_GRAVITY"]

#: the default gravity vector in the world frame (m/s^2), as pinocchio and the Robotics Toolbox use
STANDARD_GRAVITY = (0.0, 0.0, -9.81)

#: the key under which a Robot keeps its compiled dynamics and default gravity (in its ``__dict__``, as
#: ``functools.cached_property`` keeps values: a Robot is immutable, and a dictionary look-up here is a
#: good part of a single call's time)
_CACHE = "_dynamics_kernel"


def _kernel(robot: "Robot") -> "tuple[ChainDynamics, np.ndarray, np.ndarray | None]":
    entry = robot.__dict__.get(_CACHE)
    if entry is None:
        from ..compiled.chain.dynamics import ChainDynamics

        masses = link_masses(robot)
        if masses is None:
            name = f"robot '{robot.name}'" if robot.name else "the robot"
            raise InputError(f"{name} has no mass properties (its source gave no inertials): dynamics need "
                             f"the links' masses (URDF <inertial>, MJCF inertials, or m, r, I in a table's rows)")
        frames = np.concatenate([np.eye(4)[None], robot.frames[:-1]])
        mass, com, inertia = masses.in_frames(frames)
        kernel = ChainDynamics(robot._local, robot.revolute, mass[1:], com[1:], inertia[1:])
        entry = robot.__dict__[_CACHE] = (kernel, _gravity_in_base(robot, STANDARD_GRAVITY), armature(robot))
    return entry


def armature(robot: "Robot") -> np.ndarray | None:
    """The joints' armature (n,) (kg m^2 or kg; a joint without one: 0), or None when no joint has any."""
    a = np.array([j.armature or 0.0 for j in robot.joints], dtype=float)
    if not np.all(np.isfinite(a)):
        raise InputError("joint armature: expected finite numbers")
    return a if a.any() else None


def _gravity_in_base(robot: "Robot", gravity: ArrayLike | None) -> np.ndarray:
    g = np.asarray(STANDARD_GRAVITY if gravity is None else gravity, dtype=float)
    if g.shape != (3,) or not np.all(np.isfinite(g)):
        raise InputError(f"gravity: expected 3 finite numbers (m/s^2, world frame), got shape {g.shape}")
    return np.ascontiguousarray(robot.world[:3, :3].T @ g)


def _joint_array(robot: "Robot", value: ArrayLike, name: str, shape: tuple[int, ...] | None) -> np.ndarray:
    a = np.ascontiguousarray(check_q(value, robot.n, name))
    if shape is not None and a.shape != shape:
        raise InputError(f"{name}: expected shape {shape} like q, got {a.shape}")
    return a


def inverse_dynamics(robot: "Robot", q: ArrayLike, qd: ArrayLike | None = None, qdd: ArrayLike | None = None,
                     gravity: ArrayLike | None = None, threads: int | None = None) -> np.ndarray:
    """Joint torques (N m) / forces (N) that produce qdd at (q, qd) under gravity (recursive Newton-Euler).

    Parameters
    ----------
    robot : Robot
        Its inertials (``robkin.mass_properties``) and joints' armature.
    q, qd, qdd : (n,) or (N, n) arrays of one shape
        Joint values (rad or m), velocities (rad/s or m/s), accelerations (rad/s^2 or m/s^2); qd and
        qdd default to zero.
    gravity : (3,) array, optional
        Gravity in the world frame (m/s^2); default (0, 0, -9.81). Give zeros for none.
    threads : int, optional
        At most that many threads for a large batch (default automatic, see ``robkin.threads``).

    Returns
    -------
    (n,) or (N, n) array
        Including each joint's armature times its acceleration (see the module doc).
    """
    kernel, g, arm = robot.__dict__.get(_CACHE) or _kernel(robot)
    if gravity is not None:
        g = _gravity_in_base(robot, gravity)
    t = 0 if threads is None else check_threads(threads)
    out = kernel.inverse_dynamics(q, qd, qdd, g, t)   # float64 arrays as they are: no copies, no checks
    if out is None:
        out = _checked_call(robot, kernel, q, qd, qdd, g, t)
    if arm is not None and qdd is not None:
        out += arm * _joint_array(robot, qdd, "qdd", out.shape)
    return out


def _checked_call(robot: "Robot", kernel: "ChainDynamics", q: ArrayLike, qd: ArrayLike | None,
                  qdd: ArrayLike | None, g: np.ndarray, threads: int) -> np.ndarray:
    """The kernel on validated, converted arrays (anything but contiguous float64 arrays of one shape, or
    bad values, which get one clear error naming the argument)."""
    qa = _joint_array(robot, q, "q", None)
    qda = None if qd is None else _joint_array(robot, qd, "qd", qa.shape)
    qdda = None if qdd is None else _joint_array(robot, qdd, "qdd", qa.shape)
    out = kernel.inverse_dynamics(qa, qda, qdda, g, threads)
    assert out is not None  # checked, contiguous float64 arrays of one shape are always usable
    return out


def gravity_torques(robot: "Robot", q: ArrayLike, gravity: ArrayLike | None = None,
                    threads: int | None = None) -> np.ndarray:
    """Joint torques/forces that hold the robot still at q against gravity: (n,) or (N, n).

    ``gravity`` and ``threads`` as in ``inverse_dynamics``. Equals ``inverse_dynamics(q)`` with zero velocity and
    acceleration (pinocchio's ``computeGeneralizedGravity``, the Robotics Toolbox's ``gravload``).
    """
    kernel, g, _ = robot.__dict__.get(_CACHE) or _kernel(robot)
    if gravity is not None:
        g = _gravity_in_base(robot, gravity)
    t = 0 if threads is None else check_threads(threads)
    out = kernel.inverse_dynamics(q, None, None, g, t)
    return _checked_call(robot, kernel, q, None, None, g, t) if out is None else out


def mass_matrix(robot: "Robot", q: ArrayLike, threads: int | None = None) -> np.ndarray:
    """Joint-space mass (inertia) matrix at q: (n,) -> (n, n), (N, n) -> (N, n, n), symmetric.

    Composite-rigid-body algorithm; units kg m^2 (revolute pairs), kg m (mixed), kg (prismatic pairs).
    The joints' armature is on the diagonal (see the module doc). ``threads`` as in ``inverse_dynamics``.

    ``robot``: the Robot (its inertials, ``mass_properties``); ``q`` (n,) or (N, n) joint values.
    """
    kernel, _, arm = robot.__dict__.get(_CACHE) or _kernel(robot)
    t = 0 if threads is None else check_threads(threads)
    out = kernel.mass_matrix(q, t)
    if out is None:
        out = kernel.mass_matrix(_joint_array(robot, q, "q", None), t)
        assert out is not None  # a checked, contiguous float64 array is always usable
    if arm is not None:
        i = np.arange(robot.n)
        out[..., i, i] += arm
    return out
