"""Simulated calibration problems: a perturbed "real" robot, its measurements, and the noise-limit fit.

How many poses, how spread, what noise: try it here before measuring. The truth moves every joint
frame of the GJD (``perturbed``) by a small rigid motion: a translation of ``offset`` per component
and a rotation of ``angle`` per component, the rotation about the joint's own axis being its zero
offset (the links after it turn); it stands somewhere in the measuring frame (``world``) and carries a marker off its flange.
With ``stiffness`` its joints bend under gravity (``robkin.calibration.compliance``: the links' weight where
the robot has masses, and a ``payload`` at the marker), gravity along -z of its base.

``reference_fit`` is the yardstick the calibration is judged by: a plain Gauss-Newton least-squares fit
(central finite differences, minimum-norm steps by SVD) with the very parameterisation that made the
truth, independent of ``calibrate``'s code; its error on fresh configurations is what the noise allows.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import se3
from ..robot import Robot

__all__ = ["Simulation", "perturbed", "simulate", "random_configurations", "reference_fit", "prediction_error"]


@dataclass
class Simulation:
    """A simulated calibration problem.

    Attributes
    ----------
    truth : Robot
        The "real" robot: ``truth.world`` its base in the measuring frame, its tool the marker.
    q : (N, n) array
    positions : (N, 3) array
        Measured marker positions (with noise).
    orientations : (N, 3, 3) array
        Measured marker orientations (with noise).
    frame_motions : (n, 6) array
        The perturbation of each joint (``perturbed``).
    marker : (4, 4) array
        The marker in the nominal flange frame.
    payloads : (N,) array
        Payload mass of each pose (kg), at the marker.
    """

    truth: Robot
    q: np.ndarray
    positions: np.ndarray
    orientations: np.ndarray
    frame_motions: np.ndarray
    marker: np.ndarray
    payloads: np.ndarray | None = None


def random_configurations(robot: Robot, count: int, rng: np.random.Generator) -> np.ndarray:
    """Configurations (count, n) uniform within the joint limits (+-pi, or +-robot size, where none)."""
    lim = np.array(robot.limits, dtype=float)
    free = ~np.isfinite(lim)
    lim[free] = np.where(robot.revolute[:, None], np.pi, robot.scale).repeat(2, 1)[free] * np.sign(lim[free])
    return rng.uniform(lim[:, 0], lim[:, 1], size=(count, robot.n))


def perturbed(robot: Robot, motions: np.ndarray) -> Robot:
    """The robot with joint i's axis moved and its zero shifted by ``motions[i]`` = (x, y, z, rx, ry, rz):
    joint frame J_i is moved by the translation (x, y, z) and turned by the rotation vector (rx, ry, 0),
    in its own frame, and the joint's zero moves by rz (the later links turn about the moved axis)."""
    F = robot.frames.copy()
    for i, m in enumerate(motions):
        w = np.array([m[3], m[4], 0.0])
        F[i] = F[i] @ se3.homogeneous(_rotations(w[None])[0], m[:3])
    moved = robot.replace(frames=F)
    # frames_at(q) holds every frame moved to configuration q: at q = the offsets it is the new home
    return moved.replace(frames=moved.frames_at(np.asarray(motions, dtype=float)[:, 5]))


def simulate(robot: Robot, poses: int = 60, *, offset: float = 1e-3, angle: float = 1e-3,
             noise: float = 20e-6, angle_noise: float = np.radians(0.005), distance: tuple[float, float] = (1.0, 2.0),
             marker: tuple[float, float] = (0.02, 0.08), seed: int = 0, stiffness: float | np.ndarray | None = None,
             payload: float | np.ndarray = 0.0) -> Simulation:
    """A perturbed robot, standing ``distance`` (m) from the measuring frame's origin at a random rotation,
    with a marker ``marker`` (m) off its flange at a random orientation, measured at ``poses`` random
    configurations with Gaussian noise ``noise`` (m, per coordinate) and ``angle_noise`` (rad, per axis).

    ``stiffness`` (a value or one per joint, N m/rad or N/m) makes the truth's joints bend under gravity
    (``Robot.fk_compliant``), with ``payload`` (kg, a value or one per pose) at the marker.

    The perturbation (``perturbed``): each joint's frame moved by a Gaussian translation of standard deviation
    ``offset`` (m) per component and a rotation of ``angle`` (rad) per component; ``seed``: the random seed
    (the same seed, the same robot and samples).
    """
    rng = np.random.default_rng(seed)
    motions = np.concatenate([rng.normal(0.0, offset, (robot.n, 3)), rng.normal(0.0, angle, (robot.n, 3))], axis=1)
    u = rng.normal(size=3)
    W = se3.homogeneous(_random_rotation(rng), u / np.linalg.norm(u) * rng.uniform(*distance))
    v = rng.normal(size=3)
    M = se3.homogeneous(_random_rotation(rng), v / np.linalg.norm(v) * rng.uniform(*marker))
    real = perturbed(robot, motions)
    truth = real.replace(frames=np.concatenate([real.frames[:-1], (real.tool @ M)[None]]), world=W)
    q = random_configurations(robot, poses, rng)
    masses = np.broadcast_to(np.asarray(payload, dtype=float), (poses,)).copy()
    if stiffness is not None:
        from dataclasses import replace

        k = np.broadcast_to(np.asarray(stiffness, dtype=float), (robot.n,))
        truth = truth.replace(joints=tuple(replace(j, stiffness=float(v)) for j, v in zip(truth.joints, k)))
        T = W @ truth.fk_compliant(q, masses)
    else:
        T = W @ truth.fk(q)
    pos = T[:, :3, 3] + rng.normal(0.0, noise, (poses, 3))
    rot = T[:, :3, :3] @ _rotations(rng.normal(0.0, angle_noise, (poses, 3)))
    return Simulation(truth, q, pos, rot, motions, M, masses)


def prediction_error(model: Robot, truth: Robot, q: np.ndarray) -> np.ndarray:
    """Distance (N,) between the tool points both robots predict in the measuring frame."""
    a = model.world @ model.fk(q)
    b = truth.world @ truth.fk(q)
    return np.linalg.norm(a[:, :3, 3] - b[:, :3, 3], axis=1)


def reference_fit(robot: Robot, q: np.ndarray, positions: np.ndarray, orientations: np.ndarray | None,
                  start: Robot, orientation_weight: float = 1.0) -> Robot:
    """Least squares over the truth's own parameterisation (joint frame motions, base, marker) from
    ``start`` (a robot whose world and tool are the starting base and marker).

    Gauss-Newton with minimum-norm steps (``numpy.linalg.lstsq``; singular values below ``1e-7`` of the
    largest are dropped, which removes the parameterisation's exact redundancies: finite differences
    leave them at ~1e-9 relative) and central differences of step 1e-6 (truncation error ~1e-12 m).
    """
    n = robot.n
    Wt, Mt = start.world, se3.inv(robot.tool) @ start.tool

    def build(x: np.ndarray) -> Robot:
        real = perturbed(robot, x[:6 * n].reshape(n, 6))
        W = Wt @ _pose6(x[6 * n:6 * n + 6])
        M = Mt @ _pose6(x[6 * n + 6:])
        return real.replace(frames=np.concatenate([real.frames[:-1], (real.tool @ M)[None]]), world=W)

    def fun(x: np.ndarray) -> np.ndarray:
        r = build(x)
        T = r.world @ r.fk(q)
        res = [T[:, :3, 3] - positions]
        if orientations is not None:
            res.append(orientation_weight * se3.log_rotation(T[:, :3, :3] @ np.swapaxes(orientations, 1, 2)))
        return np.concatenate(res, axis=1).ravel()

    x = np.zeros(6 * n + 12)
    h = 1e-6
    for _ in range(8):  # converges quadratically from a start within ~mm: 3-4 steps reach rounding
        r0 = fun(x)
        J = np.stack([(fun(x + h * e) - fun(x - h * e)) / (2 * h) for e in np.eye(len(x))], axis=1)
        step = np.linalg.lstsq(J, -r0, rcond=1e-7)[0]
        x = x + step
        if np.abs(step).max() < 1e-12:
            break
    return build(x)


def _pose6(x: np.ndarray) -> np.ndarray:
    return se3.homogeneous(_rotations(x[3:][None])[0], x[:3])


def _rotations(v: np.ndarray) -> np.ndarray:
    a = np.linalg.norm(v, axis=1)
    axis = v / np.where(a > 0, a, 1.0)[:, None]
    S = np.concatenate([axis, np.zeros_like(axis)], axis=1)
    return se3.exp_twist(S, a)[:, :3, :3]


def _random_rotation(rng: np.random.Generator) -> np.ndarray:
    qt = rng.normal(size=4)
    w, x, y, z = qt / np.linalg.norm(qt)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
