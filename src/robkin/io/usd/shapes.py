"""Visual and collision shapes as USD prims under a link: ``visuals`` and ``collisions`` scopes.

Primitives: a box is a ``Cube`` of size 1 scaled to its sides, a sphere a ``Sphere``, a cylinder a
``Cylinder`` and a capsule a ``Capsule`` along Z (a capsule's ``height`` is the distance between its
caps' centres, robkin's length); a mesh a ``Mesh`` of the file's triangles (``meshes``), scaled as the
source scales it. A shape's colour is its ``displayColor`` (and ``displayOpacity``).

Collision shapes carry ``CollisionAPI`` and ``purpose = guide`` (hidden in a render, as Isaac Sim's
importer leaves them); a collision mesh also ``MeshCollisionAPI`` with ``approximation = convexHull``,
what PhysX makes of a mesh on a moving body anyway (shapes the source gives as several convex parts
stay several prims). Each shape keeps the source's name (``robkin:name``) and mesh file name
(``robkin:file``) for the reader.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Mapping

import numpy as np

from ... import se3
from .format import NAME_ATTR, quat_wxyz, unique_identifier

if TYPE_CHECKING:  # pragma: no cover
    from ...body_parts import Shape
    from .meshes import MeshData

__all__ = ["write_shapes", "set_pose"]


def set_pose(pxr: Any, xformable: Any, T: np.ndarray, scale: tuple[float, float, float] | None = None) -> None:
    """``xformOp:translate`` (double3) and ``xformOp:orient`` (quatd) of the pose ``T`` (4, 4), then a
    scale where one is given and not 1: the transform in double precision."""
    Gf, UsdGeom = pxr.Gf, pxr.UsdGeom
    prec = UsdGeom.XformOp.PrecisionDouble
    t = T[:3, 3]
    ops = []
    if np.any(t != 0):
        op = xformable.AddTranslateOp(prec)
        op.Set(Gf.Vec3d(*map(float, t)))
        ops.append(op)
    w, x, y, z = quat_wxyz(T[:3, :3])
    if (x, y, z) != (0.0, 0.0, 0.0):
        op = xformable.AddOrientOp(prec)
        op.Set(Gf.Quatd(w, x, y, z))
        ops.append(op)
    if scale is not None and tuple(scale) != (1.0, 1.0, 1.0):
        op = xformable.AddScaleOp(prec)
        op.Set(Gf.Vec3d(*map(float, scale)))
        ops.append(op)


def _geometry(pxr: Any, stage: Any, path: Any, shape: Shape, meshes: Mapping[str, MeshData]
              ) -> tuple[Any, tuple[float, float, float] | None] | None:
    """(the geometry prim of ``shape`` at ``path``, the scale to put on it), or None (a mesh not read)."""
    UsdGeom, Vt = pxr.UsdGeom, pxr.Vt
    g = shape.geometry
    size = tuple(float(v) for v in g.size)
    if g.kind == "box":
        prim = UsdGeom.Cube.Define(stage, path)
        prim.CreateSizeAttr(1.0)
        return prim, (size[0], size[1], size[2])
    if g.kind == "sphere":
        prim = UsdGeom.Sphere.Define(stage, path)
        prim.CreateRadiusAttr(size[0])
        return prim, None
    if g.kind in ("cylinder", "capsule"):
        prim = (UsdGeom.Cylinder if g.kind == "cylinder" else UsdGeom.Capsule).Define(stage, path)
        prim.CreateRadiusAttr(size[0])
        prim.CreateHeightAttr(size[1])
        prim.CreateAxisAttr("Z")
        return prim, None
    data = meshes.get(g.filename or "")
    if data is None:
        return None
    prim = UsdGeom.Mesh.Define(stage, path)
    prim.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(np.ascontiguousarray(data.points, dtype=np.float32)))
    prim.CreateFaceVertexCountsAttr(Vt.IntArray.FromNumpy(np.full(len(data.triangles), 3, dtype=np.int32)))
    prim.CreateFaceVertexIndicesAttr(Vt.IntArray.FromNumpy(np.ascontiguousarray(data.triangles.ravel(), dtype=np.int32)))
    prim.CreateSubdivisionSchemeAttr("none")
    prim.GetPrim().CreateAttribute("robkin:file", pxr.Sdf.ValueTypeNames.String, custom=True).Set(g.filename)
    sx, sy, sz = size[:3] if len(size) >= 3 else (1.0, 1.0, 1.0)
    return prim, (sx, sy, sz)


def write_shapes(pxr: Any, stage: Any, link_path: Any, frame: np.ndarray, shapes: list[Shape],
                 meshes: Mapping[str, MeshData]) -> int:
    """The shapes of one link (poses in the base frame; the link at ``frame``) under ``link_path``;
    returns how many were written."""
    UsdGeom, UsdPhysics, Sdf, Gf = pxr.UsdGeom, pxr.UsdPhysics, pxr.Sdf, pxr.Gf
    inv = se3.inv(frame)
    written = 0
    taken: dict[str, set[str]] = {"visual": set(), "collision": set()}
    for s in shapes:
        scope = link_path.AppendChild("visuals" if s.role == "visual" else "collisions")
        if not stage.GetPrimAtPath(scope):
            UsdGeom.Scope.Define(stage, scope)
        label = s.name or (s.geometry.kind if s.geometry.kind != "mesh" else "mesh")
        path = scope.AppendChild(unique_identifier(label, taken[s.role]))
        made = _geometry(pxr, stage, path, s, meshes)
        if made is None:
            continue
        prim, scale = made
        set_pose(pxr, prim, inv @ s.pose, scale)
        if s.name:
            prim.GetPrim().CreateAttribute(NAME_ATTR, Sdf.ValueTypeNames.String, custom=True).Set(s.name)
        if s.role == "collision":
            UsdPhysics.CollisionAPI.Apply(prim.GetPrim())
            prim.CreatePurposeAttr("guide")
            if s.geometry.kind == "mesh":
                UsdPhysics.MeshCollisionAPI.Apply(prim.GetPrim()).CreateApproximationAttr("convexHull")
        elif s.material is not None and s.material.rgba is not None:
            r, g, b, a = (float(v) for v in s.material.rgba)
            prim.CreateDisplayColorAttr([Gf.Vec3f(r, g, b)])
            if a < 1.0:
                prim.CreateDisplayOpacityAttr([a])
        written += 1
    return written
