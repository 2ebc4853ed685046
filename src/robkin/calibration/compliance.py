"""Joint compliance: what bends under gravity, and where the tool then is.

The model is the elastostatic one of industrial calibration, joints only (links rigid): a joint of
stiffness k (N m/rad, N/m for a prismatic joint) held by its motor at the encoder value q carries the
torque tau that holds the robot still there, and its link side sits at

    q_link = q - tau(q) / k

where tau(q) (``holding_torques``) is the gravity torque of the links (where the model has masses:
``Robot.gravity``) plus that of a payload, a point mass at the tool origin or at ``payload_com`` in the
tool frame. It is first order: tau is taken at q, not at the deflected configuration (the difference is
the deflection, ~1e-4 rad, times the relative change of tau, itself ~1e-4: far below any measurement).

Gravity acts along ``gravity`` in the robot *base* frame, (0, 0, -9.81) m/s^2 by default (an upright
robot). Not ``Robot.world``: a calibrated robot's world is the measuring device's frame, whose z is
anywhere. A wall- or ceiling-mounted robot passes its own vector.

A joint whose gravity torque is ~0 at every pose (a vertical first axis) has no measurable deflection:
its stiffness is not observable from such measurements (``calibrate`` says so and leaves it unknown).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..robot import Robot

__all__ = ["holding_torques", "compliant_q", "fk_compliant", "check_payloads", "STANDARD_GRAVITY"]

#: gravity in the robot base frame (m/s^2) unless given: an upright robot
STANDARD_GRAVITY = (0.0, 0.0, -9.81)
#: heaviest payload read (kg): beyond any serial arm's (the largest industrial arms carry ~2.3 t)
MAX_PAYLOAD = 1e4


def _gravity(gravity: ArrayLike | None) -> np.ndarray:
    g = np.asarray(STANDARD_GRAVITY if gravity is None else gravity, dtype=float)
    if g.shape != (3,) or not np.all(np.isfinite(g)):
        raise InputError(f"gravity: expected 3 finite numbers (m/s^2, robot base frame), got shape {g.shape}")
    return g


def check_payloads(payload: ArrayLike, N: int) -> np.ndarray:
    """Payload masses (N,) (kg) from a scalar or N values, each finite, >= 0 and <= ``MAX_PAYLOAD``."""
    m = np.broadcast_to(np.asarray(payload, dtype=float), (N,)) if np.ndim(payload) == 0 else \
        np.asarray(payload, dtype=float)
    if m.shape != (N,):
        raise InputError(f"payload: expected one mass per pose ({N}), got shape {m.shape}")
    bad = np.flatnonzero(~((m >= 0) & (m <= MAX_PAYLOAD)))
    if bad.size:
        raise InputError(f"payload: pose {bad[0] + 1}: {m[bad[0]]} is not a mass in [0, {MAX_PAYLOAD:g}] kg")
    return m


def _check_com(payload_com: ArrayLike | None) -> np.ndarray:
    c = np.zeros(3) if payload_com is None else np.asarray(payload_com, dtype=float)
    if c.shape != (3,) or not np.all(np.isfinite(c)):
        raise InputError("payload_com: expected 3 finite numbers (x, y, z in the tool frame, m)")
    return c


def holding_torques(robot: Robot, q: ArrayLike, payload: ArrayLike = 0.0, payload_com: ArrayLike | None = None,
                    gravity: ArrayLike | None = None) -> np.ndarray:
    """Joint torques (N m; N for a prismatic joint) that hold the robot still at q against gravity.

    Parameters
    ----------
    robot : Robot
        Its links' masses count where it has them (``Robot.bodies``); without, only the payload does.
    q : (n,) or (N, n) array
        Joint values (rad, m).
    payload : float or (N,) array
        Payload mass (kg) per pose.
    payload_com : (3,) array, optional
        The payload's centre of mass in the tool frame (m); default the tool origin.
    gravity : (3,) array, optional
        Gravity in the robot base frame (m/s^2); default (0, 0, -9.81).

    Returns
    -------
    (n,) or (N, n) array
        The torques, the sign of ``Robot.gravity`` (the torque the joint's motor applies).
    """
    from ..mass_properties import link_masses

    Q = np.atleast_2d(np.asarray(q, dtype=float))
    single = np.ndim(q) == 1
    if Q.shape[1] != robot.n:
        raise InputError(f"q: expected {robot.n} values per configuration, got {Q.shape[1]}")
    g = _gravity(gravity)
    m = check_payloads(payload, len(Q))
    tau = np.zeros(Q.shape)
    if link_masses(robot) is not None:
        tau += robot.gravity(Q, gravity=robot.world[:3, :3] @ g)   # Robot.gravity takes the world frame's
    if np.any(m > 0):
        F = robot.frames_at(Q)                                     # (N, n + 1, 4, 4), base frame
        p = F[:, -1, :3, :3] @ _check_com(payload_com) + F[:, -1, :3, 3]
        z, o = F[:, :-1, :3, 2], F[:, :-1, :3, 3]                  # joint axes and points on them at q
        dp = np.where(robot.revolute[None, :, None], np.cross(z, p[:, None, :] - o), z)   # dp/dq_i (N, n, 3)
        tau -= m[:, None] * (dp @ g)                                # holding: -(dp/dq)^T (m g)
    return tau[0] if single else tau


def compliant_q(robot: Robot, q: ArrayLike, payload: ArrayLike = 0.0, payload_com: ArrayLike | None = None,
                gravity: ArrayLike | None = None) -> np.ndarray:
    """The link-side joint values q - tau(q) / k (see the module doc).

    Parameters
    ----------
    robot : Robot
        Joints with ``stiffness`` (N m/rad, N/m) bend; joints without are rigid (no deflection).
    q : (n,) or (N, n) array
        Commanded (encoder) joint values (rad, m).
    payload : float or (N,) array
        Payload mass (kg), at the tool origin or at ``payload_com``.
    payload_com : (3,) array, optional
        The payload's centre of mass in the tool frame (m).
    gravity : (3,) array, optional
        Gravity in the robot base frame (m/s^2); default (0, 0, -9.81).

    Returns
    -------
    (n,) or (N, n) array
        The deflected joint values (rad, m).
    """
    c = np.array([0.0 if j.stiffness is None else 1.0 / j.stiffness for j in robot.joints])
    Q = np.asarray(q, dtype=float)
    if not c.any():
        return Q.copy()
    return Q - c * holding_torques(robot, Q, payload, payload_com, gravity)


def fk_compliant(robot: Robot, q: ArrayLike, payload: ArrayLike = 0.0, payload_com: ArrayLike | None = None,
                 gravity: ArrayLike | None = None) -> np.ndarray:
    """Tool pose (base frame) with every joint deflected by its gravity torque over its stiffness.

    Parameters
    ----------
    robot : Robot
        Joints with ``stiffness`` (N m/rad, N/m) bend; the others are rigid.
    q : (n,) or (N, n) array
        Commanded (encoder) joint values (rad, m).
    payload : float or (N,) array
        Payload mass (kg), at the tool origin or at ``payload_com``.
    payload_com : (3,) array, optional
        The payload's centre of mass in the tool frame (m).
    gravity : (3,) array, optional
        Gravity in the robot base frame (m/s^2); default (0, 0, -9.81).

    Returns
    -------
    (4, 4) or (N, 4, 4) array
        ``Robot.fk`` at ``compliant_q(q)``.
    """
    return robot.fk(compliant_q(robot, q, payload, payload_com, gravity))
