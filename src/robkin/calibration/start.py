"""Where the robot stands and where the marker sits, to start a calibration from.

``initial_frame``: the rigid registration (Kabsch) of the nominal tool points onto the measured ones,
alternated with the linear least-squares marker and base position.
"""

from __future__ import annotations

import numpy as np

from .. import se3
from ..errors import InputError
from ..robot import Robot

__all__ = ["initial_frame"]


def initial_frame(robot: Robot, Q: np.ndarray, P: np.ndarray, Rm: np.ndarray | None,
                  world: np.ndarray | None = None, marker: np.ndarray | None = None
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Starting base pose (4, 4) and marker ((3,) point, or (4, 4) pose with orientations).

    Alternates the rigid registration (Kabsch) of the nominal marker points onto the measured ones with
    the linear least-squares marker position given the base's rotation: the marker is small next to the
    robot, so a few rounds settle both.
    """
    T = robot.fk(Q)
    R, t = T[:, :3, :3], T[:, :3, 3]
    m = np.zeros(3) if marker is None else (marker if marker.shape == (3,) else marker[:3, 3])
    W = np.eye(4) if world is None else world
    for _ in range(1 if world is not None and marker is not None else 8):
        pts = t + R @ m
        if world is None:
            W = _kabsch(pts, P)
        if marker is None:
            Rw = W[:3, :3]
            A = np.einsum("ij,njk->nik", Rw, R).reshape(-1, 3)
            b = (P - W[:3, 3] - t @ Rw.T).reshape(-1)
            if world is None:   # the base's position is solved with the marker
                A = np.concatenate([A, np.tile(np.eye(3), (len(Q), 1))], axis=1)
            sol = np.linalg.lstsq(A, b, rcond=None)[0]
            m = sol[:3]
            if world is None:
                W = W.copy()
                W[:3, 3] = sol[3:]
    if Rm is None:
        return W, m if marker is None else marker
    if marker is not None and marker.shape == (4, 4):
        return W, marker
    Rmk = se3.nearest_rotation(np.einsum("nji,jk,nkl->il", R, W[:3, :3].T, Rm))  # mean of R_k^T W^T R_meas
    return W, se3.homogeneous(Rmk, m)


def _kabsch(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """The rigid motion (4, 4) taking points A (N, 3) closest onto B (N, 3)."""
    ca, cb = A.mean(axis=0), B.mean(axis=0)
    H = (A - ca).T @ (B - cb)
    U, S, Vt = np.linalg.svd(H)
    if S[1] <= 1e-9 * max(S[0], 1e-300):  # all points on a line: the rotation about it is unknown
        raise InputError("measurements: the measured points lie on a line; measure poses spread in space")
    D = np.diag([1.0, 1.0, np.sign(np.linalg.det(Vt.T @ U.T))])
    Rot = Vt.T @ D @ U.T
    return se3.homogeneous(Rot, cb - Rot @ ca)
