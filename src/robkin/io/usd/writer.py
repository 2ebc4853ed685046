"""A Robot as a USD stage: a UsdPhysics articulation Isaac Sim, Isaac Lab and Newton load.

What is written (``usd_stage``)
    Stage metadata: ``defaultPrim`` (the robot), Z up, metres and kilograms. The robot's prim (an
    ``Xform`` named as the robot) carries ``ArticulationRootAPI``. Under it, every link of the source
    that moves or has mass is a rigid body (``RigidBodyAPI``, ``MassAPI``: ``physics``), side by side
    as PhysX wants them (rigid bodies are not nested), placed at its pose at q = 0 (the source's
    ``world`` in front) in double precision; a link fixed to its parent without mass (UR's ``tool0``, a
    ``flange``) is an ``Xform`` inside its parent's prim, marked ``robkin:frame``, so that no simulator
    gives it a default mass. The links' shapes are under them (``shapes``). The joints are prims under
    ``<robot>/joints``: ``RevoluteJoint``/``PrismaticJoint`` with limits and a drive, ``FixedJoint`` for
    the welded links, and a ``FixedJoint`` from the world (no ``body0``) to the chain's base, which makes
    the articulation fixed-base. Links above a base chosen mid-tree (a humanoid's pelvis when the chain
    starts at its torso) hang from the base through fixed joints (their source joints held at 0, as
    robkin reads them), so that the articulation is one tree rooted at the base.
    Mimic joints: a revolute one gets PhysX's ``PhysxMimicJointAPI:<axis>`` (``referenceJoint``,
    ``gearing`` = -multiplier, ``offset`` = -offset in radians: PhysX's q + gearing q_ref + offset = 0)
    and no drive; every mimic also ``robkin:mimic:*`` attributes (robkin's reader uses those). A massless
    link that only carries a joint for the body below it (the MJCF reader's ``BODY/JOINT`` link of a
    joint off its body's origin) gets no rigid body: its joint attaches that body, its frame off the
    body's origin, and robkin's reader makes the link again.

Which link becomes which prim is the MJCF writer's plan (``io.mjcf.tree.body_tree``): the same links,
joints and home pose; q = 0 is the pose every body is drawn at.
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping, Sequence

import numpy as np

from ... import se3
from .format import NAME_ATTR, identifier, pxr as _pxr, unique_identifier

if TYPE_CHECKING:  # pragma: no cover
    from ...robot import Robot
    from ..mjcf.tree import BodyPlan
    from .meshes import MeshData

__all__ = ["usd_stage", "usd_from_robot", "usd_bytes", "write_usd", "DriveGains"]

#: joint name -> (stiffness, damping, largest force), SI units (N m/rad, N m s/rad, N m; N/m, N s/m, N)
DriveGains = Mapping[str, Sequence["float | None"]]


def _is_frame(bp: BodyPlan) -> bool:
    """A plan body written as an Xform inside its parent: welded to it and massless (or the world link)."""
    massless = not any(m.mass > 0 for m in bp.inertials)
    if bp.parent is None:
        return bp.name == "world" and massless and not bp.shapes
    return bp.joint is None and massless


def _set_name(pxr: Any, prim: Any, name: str, prim_name: str) -> None:
    if name != prim_name:
        prim.CreateAttribute(NAME_ATTR, pxr.Sdf.ValueTypeNames.String, custom=True).Set(name)


def _set_string(pxr: Any, prim: Any, attr: str, value: str) -> None:
    prim.CreateAttribute(attr, pxr.Sdf.ValueTypeNames.String, custom=True).Set(value)


def _local_pose(pxr: Any, joint: Any, k: int, T: np.ndarray) -> None:
    from .physics import quatf

    pos = getattr(joint, f"CreateLocalPos{k}Attr")
    pos(pxr.Gf.Vec3f(*map(float, T[:3, 3])))
    getattr(joint, f"CreateLocalRot{k}Attr")(quatf(pxr, T[:3, :3]))


class _Writer:
    def __init__(self, robot: Robot, meshes: Mapping[str, MeshData], drives: DriveGains | None,
                 gravity_off: bool = False) -> None:
        from ..mjcf.tree import body_tree

        self.pxr = _pxr()
        self.robot, self.meshes, self.drives, self.gravity_off = robot, meshes, drives, gravity_off
        self.plan, _ = body_tree(robot)
        self.world = np.asarray(robot.world, dtype=float)
        self.scale = max(robot.scale, 1.0)
        self.links = {link.name: link for link in robot.bodies.links}
        # a link above a base chosen mid-tree -> the link below it on the way down to the base: welded to
        # that one (its source joint held at 0, as the reader held it), so the articulation is one tree
        self.above: dict[str, str] = {}
        if robot.bodies.chain and robot.bodies.chain[0] in self.links:
            lk = self.links[robot.bodies.chain[0]]
            while lk.parent is not None and lk.parent in self.links:
                self.above[lk.parent] = lk.name
                lk = self.links[lk.parent]
        self.stage = self.pxr.Usd.Stage.CreateInMemory("robot.usda")
        self.paths: list[Any] = []       # plan index -> prim path
        self.rigid: list[int] = []       # plan index -> plan index of the rigid body it is part of (-1: none)
        self.massless: list[str] = []
        # body -> the massless moving link that carries its joint (MJCF's BODY/JOINT link for a joint off
        # the body's origin): no prim of its own, its joint written to the body (frames off its origin)
        self.carrier = self.carriers()
        self.mimic_left: list[str] = []
        self.repaired: list[str] = []

    def carriers(self) -> dict[int, int]:
        out: dict[int, int] = {}
        for x, bp in enumerate(self.plan):
            if (bp.joint is None or bp.parent is None or bp.shapes or bp.sites or len(bp.children) != 1
                    or any(m.mass > 0 for m in bp.inertials) or bp.name == self.robot.bodies.tip):
                continue
            c = bp.children[0]
            if self.plan[c].joint is None and not _is_frame(self.plan[c]):
                out[c] = x
        return out

    def source_joint_name(self, link: str, default: str) -> str:
        lk = self.links.get(link)
        return lk.joint.name if lk is not None and lk.joint is not None else default

    def build(self) -> Any:
        from .physics import write_mass
        from .shapes import set_pose, write_shapes
        from ..mjcf.inertial import body_mass

        pxr, stage = self.pxr, self.stage
        Sdf, UsdGeom, UsdPhysics = pxr.Sdf, pxr.UsdGeom, pxr.UsdPhysics
        from ...version import __version__

        root_name = identifier(self.robot.name or "robot")
        root = UsdGeom.Xform.Define(stage, Sdf.Path.absoluteRootPath.AppendChild(root_name))
        _set_name(pxr, root.GetPrim(), self.robot.name or "robot", root_name)
        stage.SetDefaultPrim(root.GetPrim())
        UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
        UsdGeom.SetStageMetersPerUnit(stage, 1.0)
        UsdPhysics.SetStageKilogramsPerUnit(stage, 1.0)
        stage.GetRootLayer().documentation = f"written by robkin {__version__}"
        UsdPhysics.ArticulationRootAPI.Apply(root.GetPrim())
        taken: dict[Any, set[str]] = {root.GetPath(): {"joints"}}
        carriers = set(self.carrier.values())
        for i, bp in enumerate(self.plan):
            if i in carriers:  # its joint goes to the body it carries
                self.paths.append(None)
                self.rigid.append(-2)
                continue
            frame = _is_frame(bp)
            parent_path = root.GetPath() if bp.parent is None or not frame else self.paths[bp.parent]
            name = unique_identifier(bp.name, taken.setdefault(parent_path, set()))
            path = parent_path.AppendChild(name)
            prim = UsdGeom.Xform.Define(stage, path)
            self.paths.append(path)
            _set_name(pxr, prim.GetPrim(), bp.name, name)
            abs_frame = self.world @ bp.frame
            parent_abs = self.world @ self.plan[bp.parent].frame if frame and bp.parent is not None else np.eye(4)
            set_pose(pxr, prim, se3.inv(parent_abs) @ abs_frame)
            if frame:
                self.rigid.append(-1 if bp.parent is None else self.rigid[bp.parent])
                prim.GetPrim().CreateAttribute("robkin:frame", Sdf.ValueTypeNames.Bool, custom=True).Set(True)
                if bp.parent is not None:
                    _set_string(pxr, prim.GetPrim(), "robkin:joint", self.source_joint_name(bp.name, f"{bp.name}_fixed"))
            else:
                self.rigid.append(i)
                UsdPhysics.RigidBodyAPI.Apply(prim.GetPrim())
                if self.gravity_off:  # gravity compensated as Isaac Lab's disable_gravity does it (module doc)
                    prim.GetPrim().AddAppliedSchema("PhysxRigidBodyAPI")
                    prim.GetPrim().CreateAttribute("physxRigidBody:disableGravity", Sdf.ValueTypeNames.Bool,
                                                   custom=False).Set(True)
                bm = body_mass(bp.inertials)
                if bm is not None and bm.mass > 0:
                    if write_mass(pxr, prim.GetPrim(), bm, bp.frame):
                        self.repaired.append(bp.name)
                elif bp.joint is not None:
                    self.massless.append(bp.name)
            write_shapes(pxr, stage, path, bp.frame, bp.shapes, self.meshes)
            for site, P in bp.sites:
                if site == bp.name:
                    continue  # the tip's own frame: the body itself
                sname = unique_identifier(site, taken.setdefault(path, set()))
                sprim = UsdGeom.Xform.Define(stage, path.AppendChild(sname))
                _set_name(pxr, sprim.GetPrim(), site, sname)
                set_pose(pxr, sprim, se3.inv(bp.frame) @ P)
                sprim.GetPrim().CreateAttribute("robkin:frame", Sdf.ValueTypeNames.Bool, custom=True).Set(True)
                _set_string(pxr, sprim.GetPrim(), "robkin:joint", self.source_joint_name(site, f"{site}_fixed"))
        self.joints(root.GetPath())
        self.warn()
        return stage

    def joints(self, root: Any) -> None:
        from .physics import joint_frames, write_limits_and_drive

        pxr, stage = self.pxr, self.stage
        Sdf, UsdGeom, UsdPhysics = pxr.Sdf, pxr.UsdGeom, pxr.UsdPhysics
        scope = root.AppendChild("joints")
        UsdGeom.Scope.Define(stage, scope)
        taken: set[str] = set()
        prims: dict[str, Any] = {}
        mimics = []
        top = {bp.name: i for i, bp in enumerate(self.plan) if bp.parent is None and self.rigid[i] == i}
        for i, bp in enumerate(self.plan):
            if self.rigid[i] != i:
                continue  # a frame (inside its parent's prim), or a link carrying its child's joint
            jp = self.plan[self.carrier.get(i, i)]  # the plan entry whose joint attaches this body
            j = jp.joint
            below = top.get(self.above.get(bp.name, ""))
            if bp.parent is None and below is not None:  # above the base: welded to the link below it
                name = self.source_joint_name(self.plan[below].name, f"{bp.name}_fixed")
                path = scope.AppendChild(unique_identifier(name, taken))
                joint = UsdPhysics.FixedJoint.Define(stage, path)
                joint.CreateBody0Rel().SetTargets([self.paths[below]])
                joint.CreateBody1Rel().SetTargets([self.paths[i]])
                _local_pose(pxr, joint, 0, se3.inv(self.plan[below].frame) @ bp.frame)
                _local_pose(pxr, joint, 1, np.eye(4))
                _set_name(pxr, joint.GetPrim(), name, path.name)
                continue
            if bp.parent is None:
                name = self.source_joint_name(bp.name, f"{bp.name}_world")
                J = self.world @ bp.frame
                path = scope.AppendChild(unique_identifier(name, taken))
                joint = UsdPhysics.FixedJoint.Define(stage, path)
                joint.CreateBody1Rel().SetTargets([self.paths[i]])
                _local_pose(pxr, joint, 0, J)
                _local_pose(pxr, joint, 1, np.eye(4))
                _set_name(pxr, joint.GetPrim(), name, path.name)
                continue
            owner = self.rigid[jp.parent]  # type: ignore[index]  # not at the top: see above
            parent_frame = self.plan[owner].frame if owner >= 0 else se3.inv(self.world)
            name = j.name if j is not None else self.source_joint_name(bp.name, f"{bp.name}_fixed")
            path = scope.AppendChild(unique_identifier(name, taken))
            if j is None:
                joint = UsdPhysics.FixedJoint.Define(stage, path)
                J0, J1 = se3.inv(parent_frame) @ bp.frame, np.eye(4)
            else:
                kind = UsdPhysics.PrismaticJoint if j.slide else UsdPhysics.RevoluteJoint
                joint = kind.Define(stage, path)
                token, J0, J1 = joint_frames(j, parent_frame, jp.frame, self.scale)
                J1 = se3.inv(bp.frame) @ jp.frame @ J1  # in the body's frame (the carrier's is gone)
                joint.CreateAxisAttr(token)
                write_limits_and_drive(pxr, joint, j, self.drives)
                prims[j.name] = (joint, token)
                if j.mimic is not None:
                    mimics.append(j)
            if owner >= 0:
                joint.CreateBody0Rel().SetTargets([self.paths[owner]])
            joint.CreateBody1Rel().SetTargets([self.paths[i]])
            _local_pose(pxr, joint, 0, J0)
            _local_pose(pxr, joint, 1, J1)
            _set_name(pxr, joint.GetPrim(), name, path.name)
            if owner != jp.parent:  # hangs from a frame: say which, for the reader
                _set_string(pxr, joint.GetPrim(), "robkin:parent", self.plan[jp.parent].name)  # type: ignore[index]
        for j in mimics:
            self.mimic(j, prims)

    def mimic(self, j: Any, prims: Mapping[str, Any]) -> None:
        pxr = self.pxr
        Sdf = pxr.Sdf
        joint, token = prims[j.name]
        prim = joint.GetPrim()
        ref = prims.get(j.mimic.joint)
        if ref is None:
            self.mimic_left.append(j.name)
            return
        _set_string(pxr, prim, "robkin:mimic:joint", j.mimic.joint)
        for attr, value in (("multiplier", j.mimic.multiplier), ("offset", j.mimic.offset)):
            prim.CreateAttribute(f"robkin:mimic:{attr}", Sdf.ValueTypeNames.Double, custom=True).Set(float(value))
        if j.slide:
            return  # PhysX's mimic joints are rotational (rotX, rotY, rotZ): the coupling stays robkin's
        instance = f"rot{token}"
        prim.AddAppliedSchema(f"PhysxMimicJointAPI:{instance}")
        prim.CreateRelationship(f"physxMimicJoint:{instance}:referenceJoint", custom=False).SetTargets(
            [ref[0].GetPath()])
        prim.CreateAttribute(f"physxMimicJoint:{instance}:referenceJointAxis", Sdf.ValueTypeNames.Token,
                             custom=False).Set(f"rot{ref[1]}")
        prim.CreateAttribute(f"physxMimicJoint:{instance}:gearing", Sdf.ValueTypeNames.Float,
                             custom=False).Set(float(-j.mimic.multiplier))
        prim.CreateAttribute(f"physxMimicJoint:{instance}:offset", Sdf.ValueTypeNames.Float,
                             custom=False).Set(float(-j.mimic.offset))

    def warn(self) -> None:
        if self.massless:
            warnings.warn(f"link(s) {', '.join(self.massless[:6])}{', ...' if len(self.massless) > 6 else ''} move "
                          f"without mass: written without MassAPI values (a simulator derives them from the "
                          f"colliders or its defaults)", UserWarning, stacklevel=4)
        if self.repaired:
            warnings.warn(f"link(s) {', '.join(self.repaired[:6])}{', ...' if len(self.repaired) > 6 else ''}: inertia "
                          f"not physical (a negative principal moment, or one above the sum of the other two): "
                          f"clipped to the nearest valid moments", UserWarning, stacklevel=4)
        if self.mimic_left:
            warnings.warn(f"joint(s) {', '.join(self.mimic_left[:6])} mimic a joint that is not in the model: "
                          f"written as free joints", UserWarning, stacklevel=4)
        slides = [bp.joint.name for bp in self.plan if bp.joint is not None and bp.joint.mimic is not None
                  and bp.joint.slide and bp.joint.name not in self.mimic_left]
        if slides:
            warnings.warn(f"prismatic mimic joint(s) {', '.join(slides[:6])}: PhysX couples rotations only; "
                          f"written as free joints, the coupling kept as robkin:mimic attributes",
                          UserWarning, stacklevel=4)


def usd_stage(robot: Robot, *, meshes: Mapping[str, MeshData] | None = None,
              drives: DriveGains | None = None, gravity_off: bool = False) -> Any:
    """The robot as an in-memory USD stage (``pxr.Usd.Stage``; see the module doc): its root layer
    is the file (keep the stage while using the layer: the stage owns it).

    Parameters
    ----------
    robot : Robot
    meshes : mapping, optional
        Mesh file name as the source wrote it -> its points and triangles (``meshes.read_meshes``);
        mesh shapes not in it are left out.
    drives : mapping, optional
        Joint name -> (stiffness, damping, largest force) in SI units (N m/rad, N m s/rad, N m; N/m,
        N s/m, N), any of them None; written per degree for revolute joints. Joints not in it (and
        every joint when None) get effort-only drives: stiffness and damping 0, ``maxForce`` = effort.
        ``robkin convert --to usd`` gives the servo gains of ``robkin.simulation.servo_plan``.
    gravity_off : bool
        Gravity compensated: every rigid body gets PhysX's ``physxRigidBody:disableGravity`` (what
        Isaac Lab's articulation configurations set for a fixed-base arm held by its drives; UsdPhysics
        itself has no gravity compensation). ``robkin convert --to usd`` sets it where the servo plan
        compensates gravity, as the MJCF's ``gravcomp`` does.
    """
    return _Writer(robot, meshes or {}, drives, gravity_off).build()


def usd_from_robot(robot: Robot, **options: Any) -> str:
    """The ``.usda`` text of the robot (``usd_stage``'s options)."""
    stage = usd_stage(robot, **options)  # held while its layer is used: the stage owns the layer
    return stage.GetRootLayer().ExportToString()


def _source_meshes(robot: Robot, source: str | os.PathLike[str] | None,
                   package_paths: Mapping[str, Path] | None,
                   premade: Mapping[str, Path] | None = None) -> dict[str, MeshData]:
    """The robot file's meshes, read (one warning line for those left out); ``premade``: mesh names ->
    files made for this export (``robkin.collision``'s hulls, parts, decimated meshes), read from there."""
    if premade:
        from dataclasses import replace

        from .meshes import read_meshes

        made, left = read_meshes(dict(premade))
        if left:
            warnings.warn(f"{len(left)} collision mesh file(s) cannot be read, left out of the USD: "
                          f"{'; '.join(left[:3])}", UserWarning, stacklevel=3)
        rest = robot.replace(bodies=replace(robot.bodies, shapes=tuple(
            s for s in robot.bodies.shapes if s.geometry.filename not in premade)))
        return {**_source_meshes(rest, source, package_paths), **made}
    if source is None or not any(s.geometry.kind == "mesh" for s in robot.bodies.shapes):
        if any(s.geometry.kind == "mesh" for s in robot.bodies.shapes):
            warnings.warn("the robot's mesh files are not known without its source file: its mesh shapes are "
                          "left out of the USD", UserWarning, stacklevel=3)
        return {}
    from ..meshes.files import missing_line, resolve_meshes
    from .meshes import read_meshes

    resolved = resolve_meshes(robot, source, package_paths)
    missing = missing_line(resolved, source)
    if missing:
        warnings.warn(missing.replace("drawn without them", "left out of the USD"), UserWarning, stacklevel=3)
    data, left = read_meshes({k: m.path for k, m in resolved.items() if m.path is not None})
    if left:
        warnings.warn(f"{len(left)} mesh file(s) cannot be read, left out of the USD: {'; '.join(left[:3])}",
                      UserWarning, stacklevel=3)
    return data


def usd_bytes(robot: Robot, suffix: str, *, source: str | os.PathLike[str] | None = None,
              package_paths: Mapping[str, Path] | None = None, drives: DriveGains | None = None,
              gravity_off: bool = False, premade: Mapping[str, Path] | None = None) -> bytes:
    """The file's bytes for ``suffix`` ``.usda`` (text) or ``.usd``/``.usdc`` (binary crate), the meshes
    of the robot file ``source`` inline (those named in ``premade`` read from the file it gives)."""
    import tempfile

    stage = usd_stage(robot, meshes=_source_meshes(robot, source, package_paths, premade), drives=drives,
                      gravity_off=gravity_off)
    layer = stage.GetRootLayer()
    if suffix == ".usda":
        return layer.ExportToString().encode("utf-8")
    with tempfile.TemporaryDirectory(prefix="robkin-usd-") as folder:
        tmp = os.path.join(folder, "robot.usdc")
        if not layer.Export(tmp):
            raise OSError("usd-core could not write the crate file")
        return Path(tmp).read_bytes()


def write_usd(robot: Robot, path: str | os.PathLike[str], *, source: str | os.PathLike[str] | None = None,
              package_paths: Mapping[str, Path] | None = None, drives: DriveGains | None = None,
              gravity_off: bool = False) -> Path:
    """Write ``robot`` as ``path`` (``.usda`` text, ``.usd``/``.usdc`` binary), atomically, its meshes
    (from the robot file ``source``) inline; returns the path.

    ``source``: the robot file its meshes are found from (None: none); ``package_paths``: package name -> folder
    for ``package://`` meshes (``--package-path``); ``drives``, ``gravity_off``: as for ``usd_stage`` (joint
    name -> drive gains, default effort-only drives; every rigid body with gravity disabled, i.e.
    compensated).
    """
    from ...errors import InputError
    from ..files.atomic import atomic_file
    from .format import USD_EXTENSIONS

    out = Path(path)
    suffix = out.suffix.lower()
    if suffix not in USD_EXTENSIONS:
        raise InputError(f"{out}: a USD file is named {', '.join(USD_EXTENSIONS)}")
    data = usd_bytes(robot, suffix, source=source, package_paths=package_paths, drives=drives,
                     gravity_off=gravity_off)
    with atomic_file(out, binary=True) as fh:
        fh.write(data)
    return out
