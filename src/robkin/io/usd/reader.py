"""USD input: a UsdPhysics articulation as the robot tree every reader builds (``UrdfModel``).

The file is opened as one self-contained layer (``layer``: nothing it names is followed). Then:

Links
    Every prim with ``RigidBodyAPI``, and every prim robkin marked ``robkin:frame`` (a massless link
    welded to its parent, written inside its prim). A link's name is its ``robkin:name`` where given,
    else its prim name. A link's pose is its world transform (double precision, scale removed).
Joints
    ``RevoluteJoint`` (``continuous`` without limits), ``PrismaticJoint`` and ``FixedJoint`` prims,
    from the link owning ``body0`` (its prim or an ancestor) to the one owning ``body1``; other joint
    types are read as ``floating`` (a chain through one is refused). The kinematics is the joints'
    own frames, as a simulator reads it: the child sits at ``localPose0 @ localPose1^-1`` from its parent
    at q = 0 and turns about (slides along) the frame's X, Y or Z axis; a revolute axis that misses
    the child's origin gets an intermediate link ``CHILD/JOINT`` (as the MJCF reader does). These are
    float32 numbers: see ``format``. Limits are in degrees (revolute) or metres; robkin's own
    ``robkin:lower``/``upper``/``effort`` (double) are preferred where they agree with them to float32
    rounding (else the UsdPhysics values, edited since, win). A joint from the world (no ``body0``)
    hangs its link from a link ``world`` (which ``Robot.world`` then measures from). Mimic: robkin's
    ``robkin:mimic:*`` attributes, else PhysX's ``PhysxMimicJointAPI``.
What links hold
    ``MassAPI`` (mass, ``centerOfMass``, ``diagonalInertia``, ``principalAxes``) as the link's
    inertial (a link without an authored mass has none: unknown, not zero; ``density`` is not used);
    ``Cube``, ``Sphere``, ``Cylinder``, ``Capsule`` and ``Mesh`` prims below it as shapes (collision
    where they carry ``CollisionAPI``, else visual), a mesh named by ``robkin:file`` where robkin wrote
    it, else by its prim path (``usd:/robot/link/visuals/mesh``): the triangles stay in the USD file.

The chain is then picked by ``io.urdf.chain.robot_from_model``: ``base_link``/``tip_link`` name links.
"""

from __future__ import annotations

import math
import os
import warnings
from typing import TYPE_CHECKING, Any

import numpy as np

from ... import se3
from ...errors import InputError, quote
from ...names import check_name
from .format import DEG, NAME_ATTR, api_schemas, authored as _get, matrix_of_quat, matrix_of_gf as _matrix, pxr as _pxr,\
    without_scale as _rigid

if TYPE_CHECKING:  # pragma: no cover
    from ...robot import Robot
    from ..trees.model import UrdfModel

__all__ = ["model_from_usd", "robot_from_usd"]

#: A joint frame's origin this far (relative to its distance from the child's origin, float32 rounding
#: and then some) from the child's axis line still lies on it.
OFF_AXIS = 1e-6
#: robkin's double-precision record of a value agrees with the float32 UsdPhysics one within this.
FLOAT32_AGREE = 1e-6
_UNIT_AXES = {"X": np.array([1.0, 0.0, 0.0]), "Y": np.array([0.0, 1.0, 0.0]), "Z": np.array([0.0, 0.0, 1.0])}


def _attach(parent_of: dict[str, str], child: str, parent: str) -> bool:
    """Record ``parent`` as ``child``'s parent, unless the child has one already or it would close a loop."""
    if child in parent_of:
        return False
    link: str | None = parent
    while link is not None:  # up from the parent: every step is a recorded link, so this ends
        if link == child:
            return False
        link = parent_of.get(link)
    parent_of[child] = parent
    return True


class _Reader:
    def __init__(self, path: str) -> None:
        from .layer import open_stage

        self.pxr = _pxr()
        self.path = path
        self.stage = open_stage(path)
        self.cache = self.pxr.UsdGeom.XformCache()
        self.links: dict[Any, str] = {}      # prim path -> link name
        self.poses: dict[str, np.ndarray] = {}
        self.prims: dict[str, Any] = {}
        self.extra_links: list[str] = []  # the intermediate links CHILD/JOINT
        self.visited = 0  # prims looked at for shapes (bounded: see shapes_read)

    def where(self, prim: Any) -> str:
        return f"{self.path}: prim {quote(str(prim.GetPath()))}"

    def finite(self, values: Any, prim: Any, field: str) -> np.ndarray:
        a = np.array(values, dtype=float)
        if not np.all(np.isfinite(a)) or np.any(np.abs(a) > 1e100):
            raise InputError(f"{self.where(prim)}: {field} is not finite ({quote(list(a.ravel()))})")
        return a

    def name_of(self, prim: Any, taken: set[str]) -> str:
        name = _get(prim, NAME_ATTR)
        name = str(name) if isinstance(name, str) and name else prim.GetName()
        if name in taken:
            name = str(prim.GetPath())
        check_name(name, f"{self.where(prim)}: name")
        taken.add(name)
        return name

    def pose(self, prim: Any) -> np.ndarray:
        T = _matrix(self.cache.GetLocalToWorldTransform(prim))
        return _rigid(self.finite(T, prim, "transform"))[0]

    def owner(self, prim: Any) -> str | None:
        """The link a prim belongs to (itself or its nearest link ancestor), None for none."""
        while prim and prim.GetPath() != self.pxr.Sdf.Path.absoluteRootPath:
            if prim.GetPath() in self.links:
                return self.links[prim.GetPath()]
            prim = prim.GetParent()
        return None

    def local(self, prim: Any, k: int) -> np.ndarray:
        """Joint frame k (0 or 1) of a joint prim in its body's prim frame."""
        pos = _get(prim, f"physics:localPos{k}")
        rot = _get(prim, f"physics:localRot{k}")
        T = np.eye(4)
        if pos is not None:
            T[:3, 3] = self.finite(list(pos), prim, f"physics:localPos{k}")
        if rot is not None:
            w = self.finite([rot.GetReal(), *rot.GetImaginary()], prim, f"physics:localRot{k}")
            try:
                T[:3, :3] = matrix_of_quat(*w)
            except InputError:
                raise InputError(f"{self.where(prim)}: physics:localRot{k} is not a rotation") from None
        return T

    def body_frame(self, joint: Any, k: int) -> tuple[str | None, np.ndarray]:
        """(link of body k, the joint frame in that link's frame; None: the world, frame in the world)."""
        rel = joint.GetRelationship(f"physics:body{k}")
        targets = rel.GetTargets() if rel else []
        T = self.local(joint, k)
        if not targets:
            return None, T
        target = self.stage.GetPrimAtPath(targets[0])
        if not target:
            raise InputError(f"{self.where(joint)}: physics:body{k} names {quote(str(targets[0]))}, which is not in the file")
        link = self.owner(target)
        if link is None:
            raise InputError(f"{self.where(joint)}: physics:body{k} {quote(str(targets[0]))} is not a rigid body "
                             f"or inside one")
        if target.GetPath() != self.prims[link].GetPath():
            T = se3.inv(self.poses[link]) @ self.pose(target) @ T
        return link, T

    def model(self) -> UrdfModel:
        from ..trees.model import UrdfModel

        UsdPhysics = self.pxr.UsdPhysics
        prims = [p for p in self.stage.Traverse()]
        taken: set[str] = set()
        order: list[str] = []
        for prim in prims:
            if prim.HasAPI(UsdPhysics.RigidBodyAPI) or _get(prim, "robkin:frame") is True:
                name = self.name_of(prim, taken)
                self.links[prim.GetPath()] = name
                self.prims[name] = prim
                self.poses[name] = self.pose(prim)
                order.append(name)
        if not order:
            raise InputError(f"{self.path}: no rigid body (RigidBodyAPI) in the file; robkin reads a UsdPhysics "
                             f"articulation")
        world = next((n for n in order if n == "world" and _get(self.prims[n], "robkin:frame") is True
                      and self.owner(self.prims[n].GetParent()) is None), None)
        world_name = world or ("world" if "world" not in taken else "world_usd")
        joints, parent_of = self.joints(prims, world_name)
        for name in order:  # robkin's frames: welded to the link whose prim holds them
            prim = self.prims[name]
            if _get(prim, "robkin:frame") is not True or name in parent_of:
                continue
            parent = self.owner(prim.GetParent())
            if parent is None or not _attach(parent_of, name, parent):
                continue
            jname = _get(prim, "robkin:joint")
            joints.append(self.joint(str(jname) if isinstance(jname, str) else f"{name}_fixed", "fixed", parent, name,
                                     se3.inv(self.poses[parent]) @ self.poses[name]))
        links = order if world is not None or not any(j.parent == world_name for j in joints) else [world_name] + order
        content = {name: self.content(name) for name in order}
        name = _get(self.stage.GetDefaultPrim(), NAME_ATTR) if self.stage.GetDefaultPrim() else None
        robot_name = name if isinstance(name, str) else (self.stage.GetDefaultPrim().GetName()
                                                         if self.stage.GetDefaultPrim() else None)
        return UrdfModel(robot_name, tuple(links) + tuple(self.extra_links), tuple(joints), self.path, content)

    def joint(self, name: str, kind: str, parent: str, child: str, origin: np.ndarray, axis: Any = (1.0, 0.0, 0.0),
              lower: float | None = None, upper: float | None = None, **extra: Any) -> Any:
        from ..trees.model import UrdfJoint

        return UrdfJoint(name, kind, parent, child, origin, tuple(float(v) for v in axis), lower, upper, **extra)

    def joints(self, prims: list[Any], world: str) -> tuple[list[Any], dict[str, str]]:
        UsdPhysics = self.pxr.UsdPhysics
        out: list[Any] = []
        parent_of: dict[str, str] = {}
        loops: list[str] = []
        taken: set[str] = set()
        for prim in prims:
            if not prim.IsA(UsdPhysics.Joint):
                continue
            name = self.name_of(prim, taken)
            link0, J0 = self.body_frame(prim, 0)
            link1, J1 = self.body_frame(prim, 1)
            if link1 is None:
                if link0 is None:
                    continue  # a joint between nothing and nothing
                link0, J0, link1, J1 = None, J1, link0, J0
            named_parent = _get(prim, "robkin:parent")
            if isinstance(named_parent, str) and named_parent in self.poses and link0 is not None:
                J0 = se3.inv(self.poses[named_parent]) @ self.poses[link0] @ J0
                link0 = named_parent
            parent = world if link0 is None else link0
            if not _attach(parent_of, link1, parent):
                loops.append(name)
                continue
            out += self.moving(prim, name, parent, link1, J0, J1)
        if loops:
            warnings.warn(f"{self.path}: joint(s) {', '.join(loops[:6])} close a loop or attach a link twice: "
                          f"ignored (robkin reads a tree)", UserWarning, stacklevel=5)
        return out, parent_of

    def limit(self, prim: Any, attr: str, own: str, unit: float) -> float | None:
        v = _get(prim, attr)
        mine = _get(prim, own)
        if v is not None and math.isnan(v):
            raise InputError(f"{self.where(prim)}: {attr} is NaN")
        if v is None or not math.isfinite(v) or abs(v) >= 1e30:  # UsdPhysics' -inf/inf: no limit
            return None
        value = float(self.finite(v, prim, attr)) / unit
        if isinstance(mine, float) and math.isfinite(mine) and abs(mine - value) <= FLOAT32_AGREE * max(1.0, abs(mine)):
            return mine
        return value

    def moving(self, prim: Any, name: str, parent: str, child: str, J0: np.ndarray, J1: np.ndarray) -> list[Any]:
        UsdPhysics = self.pxr.UsdPhysics
        if prim.IsA(UsdPhysics.FixedJoint):
            return [self.joint(name, "fixed", parent, child, J0 @ se3.inv(J1))]
        revolute = prim.IsA(UsdPhysics.RevoluteJoint)
        if not (revolute or prim.IsA(UsdPhysics.PrismaticJoint)):
            return [self.joint(name, "floating", parent, child, J0 @ se3.inv(J1))]
        token = str(_get(prim, "physics:axis") or "X")
        if token not in _UNIT_AXES:
            raise InputError(f"{self.where(prim)}: physics:axis {quote(token)} is not X, Y or Z")
        unit = DEG if revolute else 1.0
        lower = self.limit(prim, "physics:lowerLimit", "robkin:lower", unit)
        upper = self.limit(prim, "physics:upperLimit", "robkin:upper", unit)
        if lower is not None and upper is not None and lower > upper:
            raise InputError(f"{self.where(prim)}: physics:lowerLimit is above physics:upperLimit")
        kind = "prismatic" if not revolute else ("revolute" if lower is not None or upper is not None else "continuous")
        extra = self.dynamics(prim, revolute)
        e = _UNIT_AXES[token]
        axis = J1[:3, :3] @ e
        p = J1[:3, 3]
        if revolute and np.linalg.norm(np.cross(p, axis)) > OFF_AXIS * max(float(np.linalg.norm(p)), 1.0):
            mid = f"{child}/{name}"
            self.poses.setdefault(mid, self.poses[parent] @ J0 if parent in self.poses else J0)
            self.extra_links.append(mid)
            return [self.joint(name, kind, parent, mid, J0, e, lower, upper, **extra),
                    self.joint(f"{name}:fixed", "fixed", mid, child, se3.inv(J1))]
        return [self.joint(name, kind, parent, child, J0 @ se3.inv(J1), axis, lower, upper, **extra)]

    def dynamics(self, prim: Any, revolute: bool) -> dict[str, Any]:
        from ...body_parts import Mimic

        unit = DEG if revolute else 1.0
        drive = "angular" if revolute else "linear"
        out: dict[str, Any] = {}
        force = _get(prim, f"drive:{drive}:physics:maxForce")
        mine = _get(prim, "robkin:effort")
        if force is not None and math.isfinite(force) and abs(force) < 1e30:
            out["effort"] = mine if isinstance(mine, float) and abs(mine - force) <= FLOAT32_AGREE * max(1.0, abs(mine)) \
                else float(force)
        velocity = _get(prim, "robkin:velocity")
        if velocity is None and _get(prim, "physxJoint:maxJointVelocity") is not None:
            velocity = float(_get(prim, "physxJoint:maxJointVelocity")) / unit
        armature = _get(prim, "robkin:armature")
        if armature is None:
            armature = _get(prim, "physxJoint:armature")
        for key, value in (("velocity", velocity), ("damping", _get(prim, "robkin:damping")),
                           ("friction", _get(prim, "robkin:friction")), ("armature", armature)):
            if value is not None:
                out[key] = float(self.finite(value, prim, key))
        ref = _get(prim, "robkin:mimic:joint")
        if isinstance(ref, str):
            out["mimic"] = Mimic(ref, float(_get(prim, "robkin:mimic:multiplier") or 1.0),
                                 float(_get(prim, "robkin:mimic:offset") or 0.0))
        else:
            for api in api_schemas(prim):
                if api.startswith("PhysxMimicJointAPI:"):
                    axis = api.split(":", 1)[1]
                    rel = prim.GetRelationship(f"physxMimicJoint:{axis}:referenceJoint")
                    targets = rel.GetTargets() if rel else []
                    if targets:
                        target = self.stage.GetPrimAtPath(targets[0])
                        tname = _get(target, NAME_ATTR) if target else None
                        gearing = _get(prim, f"physxMimicJoint:{axis}:gearing")
                        offset = _get(prim, f"physxMimicJoint:{axis}:offset")
                        out["mimic"] = Mimic(tname if isinstance(tname, str) else targets[0].name,
                                             -float(1.0 if gearing is None else gearing), -float(offset or 0.0))
        return out

    def content(self, link: str) -> Any:
        from ..trees.model import LinkContent
        from .shapes_read import link_shapes

        prim = self.prims[link]
        return LinkContent(tuple(link_shapes(self, link, prim)), self.inertial(link, prim))

    def inertial(self, link: str, prim: Any) -> Any:
        from ...body_parts import Inertial

        if not prim.HasAPI(self.pxr.UsdPhysics.MassAPI):
            return None
        mass = _get(prim, "physics:mass")
        if mass is None or not mass > 0:
            return None
        mass = float(self.finite(mass, prim, "physics:mass"))
        com = _get(prim, "physics:centerOfMass")
        com = np.zeros(3) if com is None or not np.all(np.isfinite(list(com))) else self.finite(list(com), prim,
                                                                                                 "physics:centerOfMass")
        diag = _get(prim, "physics:diagonalInertia")
        diag = np.zeros(3) if diag is None else self.finite(list(diag), prim, "physics:diagonalInertia")
        axes = _get(prim, "physics:principalAxes")
        T = np.eye(4)
        T[:3, 3] = com
        if axes is not None:
            q = [axes.GetReal(), *axes.GetImaginary()]
            if any(q):
                T[:3, :3] = matrix_of_quat(*self.finite(q, prim, "physics:principalAxes"))
        return Inertial(link, 0, T, mass, np.diag(diag))


def model_from_usd(source: str | os.PathLike[str]) -> UrdfModel:
    """The robot tree of a USD file (see the module doc)."""
    return _Reader(os.fspath(source)).model()


def robot_from_usd(source: str | os.PathLike[str], base_link: str | None = None, tip_link: str | None = None,
                   *, name: str | None = None) -> Robot:
    """The serial chain base_link -> tip_link of a USD articulation as a Robot.

    Parameters
    ----------
    source : path
        A ``.usda``, ``.usd`` or ``.usdc`` file (one self-contained layer: see ``robkin.io.usd.layer``).
    base_link, tip_link : str, optional
        Links (rigid bodies, or frames robkin wrote) at the chain's ends; by default the link fixed to
        the world and the only leaf below it.
    name : str, optional
        The robot's name (default: the articulation's).

    Returns
    -------
    Robot
        GJD frames in the base link's frame, one joint per revolute/prismatic joint of the chain (q in
        radians and metres), ``world`` = world -> base link.
    """
    from ..urdf.chain import robot_from_model

    return robot_from_model(model_from_usd(source), base_link, tip_link, name=name)
