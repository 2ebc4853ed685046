"""The physics of a USD articulation: joint frames, limits and drives, mass properties.

Joint frames
    UsdPhysics turns a revolute joint about, and slides a prismatic joint along, the X, Y or Z axis of
    its joint frame, given in both bodies (``localPos0``/``localRot0`` in body0, ``localPos1``/
    ``localRot1`` in body1). ``joint_frames`` keeps the child link's own axes where the joint's axis is
    one of them (``physics:axis`` X, Y or Z; a negative one turned by a half turn about another axis,
    exact in any precision), else turns the X axis onto the joint's axis (the smallest rotation), and
    puts the joint frame at the child link's origin when the axis passes through it (URDF), else at
    the point of the axis nearest to it.

Drives
    One ``DriveAPI`` per joint (instance ``angular`` or ``linear``), of type ``force``: with the gains
    given (stiffness, damping, largest force; SI), a position servo; without them, effort only
    (stiffness and damping 0, ``maxForce`` = the joint's effort where known), a place for the gains of
    the simulation that uses the asset. The target is the home position: q = 0 moved into the limits.

PhysX
    ``PhysxJointAPI`` (applied by name: PhysX's schemas are not in usd-core) with the joint's velocity
    limit (``physxJoint:maxJointVelocity``, deg/s or m/s) and rotor inertia (``physxJoint:armature``)
    where the source gives them. Every joint also keeps robkin's exact record (``robkin:lower``,
    ``upper``, ``effort``, ``velocity``, ``damping``, ``friction``, ``armature``: doubles, SI units).

Mass properties
    ``MassAPI``: mass, ``centerOfMass`` in the body frame, and the inertia as principal moments
    (``diagonalInertia``) about principal axes (``principalAxes``, a rotation of the body frame):
    the source's own inertial frame where the inertia is diagonal in it, else its eigenvectors.
    Moments no simulator accepts (a negative one, or one above the sum of the other two) are repaired
    as the MJCF export repairs them, and the writer says which links.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Mapping, Sequence

import numpy as np

from ... import se3
from .format import DEG, quat_wxyz

if TYPE_CHECKING:  # pragma: no cover
    from ..mjcf.inertial import BodyMass
    from ..mjcf.tree import JointPlan

__all__ = ["joint_frames", "drive_gains", "home_position", "principal_inertia", "AXES", "ON_AXIS"]

AXES = ("X", "Y", "Z")
#: An axis or a point this close (relative to 1, to the robot's size) to a unit axis or the link's
#: origin is that axis or origin: rounding of the source's products, not a different joint.
ON_AXIS = 1e-12
#: A half turn about the next axis: maps +X, +Y, +Z onto -X, -Y, -Z and keeps the frame right-handed.
_FLIP = {0: np.diag([-1.0, -1.0, 1.0]), 1: np.diag([1.0, -1.0, -1.0]), 2: np.diag([-1.0, 1.0, -1.0])}


def _turn_x_onto(a: np.ndarray) -> np.ndarray:
    """The smallest rotation taking +X onto the unit vector ``a``."""
    x = np.array([1.0, 0.0, 0.0])
    v = np.cross(x, a)
    s, c = float(np.linalg.norm(v)), float(np.dot(x, a))
    if s < ON_AXIS:
        return np.eye(3) if c > 0 else _FLIP[0]
    K = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]]) / s
    angle = math.atan2(s, c)
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def joint_frames(j: JointPlan, parent: np.ndarray, child: np.ndarray, scale: float
                 ) -> tuple[str, np.ndarray, np.ndarray]:
    """(axis token, joint frame (4, 4) in the parent body's frame, joint frame in the child's), for a
    joint of axis ``j.axis`` through ``j.point`` (base frame) between bodies at ``parent`` and
    ``child`` (4, 4, base frame at q = 0)."""
    a = child[:3, :3].T @ (np.asarray(j.axis, dtype=float) / np.linalg.norm(j.axis))
    token, R1 = "X", None
    for k in range(3):
        if abs(abs(a[k]) - 1.0) < ON_AXIS and all(abs(a[m]) < ON_AXIS for m in range(3) if m != k):
            token, R1 = AXES[k], (np.eye(3) if a[k] > 0 else _FLIP[k])
            break
    if R1 is None:
        R1 = _turn_x_onto(a / np.linalg.norm(a))
    inv_child = se3.inv(child)
    p = inv_child[:3, :3] @ np.asarray(j.point, dtype=float) + inv_child[:3, 3]
    p = p - a * float(a @ p)  # the point of the axis nearest to the child's origin
    if np.linalg.norm(p) <= ON_AXIS * scale:
        p = np.zeros(3)
    J1 = np.eye(4)
    J1[:3, :3], J1[:3, 3] = R1, p
    J0 = se3.inv(parent) @ child @ J1
    J0[:3, 3][np.abs(J0[:3, 3]) < ON_AXIS * 1e-3 * scale] = 0.0
    return token, J0, J1


def home_position(lower: float | None, upper: float | None) -> float:
    """q = 0 moved into the limits (the home the MJCF export's keyframe holds)."""
    q = 0.0
    if lower is not None and q < lower:
        q = lower
    if upper is not None and q > upper:
        q = upper
    return q


def drive_gains(revolute: bool, gains: Sequence[float | None] | None, effort: float | None
                ) -> dict[str, float]:
    """The DriveAPI values (USD units: per degree for an angular drive) of a joint.

    ``gains``: (stiffness, damping, largest force) in SI units (N m/rad, N m s/rad, N m; or N/m,
    N s/m, N), any of them None; None: effort only (see the module doc).
    """
    per = 1.0 / DEG if revolute else 1.0  # N m/rad -> N m/deg
    stiffness, damping, force = (None, None, None) if gains is None else tuple(gains)
    out = {"stiffness": 0.0 if stiffness is None else float(stiffness) * per,
           "damping": 0.0 if damping is None else float(damping) * per}
    force = effort if force is None else force
    if force is not None and math.isfinite(force) and force > 0:
        out["maxForce"] = float(force)
    return out


def principal_inertia(bm: BodyMass, body: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(centre of mass (3,), principal moments (3,), principal axes (3, 3)), in the frame of ``body``."""
    if bm.frame is not None and bm.diag is not None:
        R, w = bm.frame[:3, :3], np.asarray(bm.diag, dtype=float)
    else:
        w, R = np.linalg.eigh((bm.inertia + bm.inertia.T) / 2)
        if np.linalg.det(R) < 0:
            R[:, 0] = -R[:, 0]
    w = np.where(np.abs(w) <= 1e-15 * max(float(np.abs(w).max()), 1e-300), 0.0, w)  # eigh's rounding of 0
    inv = se3.inv(body)
    return inv[:3, :3] @ bm.com + inv[:3, 3], w, body[:3, :3].T @ R


def quatf(pxr: Any, R: np.ndarray) -> Any:
    w, x, y, z = quat_wxyz(R)
    return pxr.Gf.Quatf(w, x, y, z)


def write_mass(pxr: Any, prim: Any, bm: BodyMass, body: np.ndarray) -> bool:
    """``MassAPI`` on ``prim`` (a body at ``body``, base frame) with the mass properties ``bm``;
    returns whether the principal moments had to be repaired (a negative one, or one above the sum of
    the other two, as the MJCF export repairs them: ``io.mjcf.inertial.valid_moments``)."""
    from ..mjcf.inertial import valid_moments

    Gf = pxr.Gf
    com, w, R = principal_inertia(bm, body)
    w, changed = valid_moments(w)
    api = pxr.UsdPhysics.MassAPI.Apply(prim)
    api.CreateMassAttr(float(bm.mass))
    api.CreateCenterOfMassAttr(Gf.Vec3f(*map(float, com)))
    api.CreateDiagonalInertiaAttr(Gf.Vec3f(*map(float, w)))
    api.CreatePrincipalAxesAttr(quatf(pxr, R))
    return changed


def write_limits_and_drive(pxr: Any, joint: Any, j: JointPlan, gains: Mapping[str, Any] | None) -> None:
    """Limits (degrees or metres), the drive and robkin's exact joint attributes on a revolute or
    prismatic joint prim."""
    Sdf = pxr.Sdf
    revolute = not j.slide
    unit = DEG if revolute else 1.0
    if j.lower is not None:
        joint.CreateLowerLimitAttr(float(j.lower * unit))
    if j.upper is not None:
        joint.CreateUpperLimitAttr(float(j.upper * unit))
    prim = joint.GetPrim()
    if j.mimic is None:
        drive = pxr.UsdPhysics.DriveAPI.Apply(prim, "angular" if revolute else "linear")
        drive.CreateTypeAttr("force")
        for attr, value in drive_gains(revolute, None if gains is None else gains.get(j.name), j.effort).items():
            getattr(drive, f"Create{attr[0].upper()}{attr[1:]}Attr")(value)
        drive.CreateTargetPositionAttr(float(home_position(j.lower, j.upper) * unit))
    # PhysX's joint attributes (its schema is not in usd-core: applied by name): the velocity limit
    # (deg/s or m/s) and the rotor inertia; a URDF's friction is a torque, PhysX's jointFriction a
    # coefficient: not written there
    physx = [(name, value) for name, value in (("maxJointVelocity", None if j.velocity is None else j.velocity * unit),
                                               ("armature", j.armature)) if value is not None]
    if physx:
        prim.AddAppliedSchema("PhysxJointAPI")
        for name, value in physx:
            prim.CreateAttribute(f"physxJoint:{name}", Sdf.ValueTypeNames.Float, custom=False).Set(float(value))
    # robkin's own record, in double precision and SI units (radians, metres): what UsdPhysics has no
    # place for, and the limits exactly
    for name, value in (("lower", j.lower), ("upper", j.upper), ("effort", j.effort), ("velocity", j.velocity),
                        ("damping", j.damping), ("friction", j.friction), ("armature", j.armature)):
        if value is not None:
            prim.CreateAttribute(f"robkin:{name}", Sdf.ValueTypeNames.Double, custom=True).Set(float(value))
