"""The shapes of a USD link as robkin shapes: the geometry prims below the link's prim (see ``reader``)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Iterator

import numpy as np

from ... import se3
from ...errors import InputError
from .format import NAME_ATTR, authored as _get, matrix_of_gf as _matrix, without_scale as _rigid

if TYPE_CHECKING:  # pragma: no cover
    from ...body_parts import Shape

__all__ = ["link_shapes", "MAX_PRIMS"]

#: Prims looked at below the links, instance proxies included: nested instances multiply (each level of
#: instances of instances), a robot has a few hundred.
MAX_PRIMS = 200_000

#: Rotations taking z onto a primitive's X or Y axis (a robkin cylinder or capsule runs along z).
_ALONG = {"X": np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]),
          "Y": np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])}


def _value(prim: Any, name: str, default: Any) -> Any:
    attr = prim.GetAttribute(name)
    v = attr.Get() if attr else None
    return default if v is None else v


def link_shapes(reader: Any, link: str, prim: Any) -> Iterator[Shape]:
    """The shapes below ``prim`` (not those of links inside it), poses relative to the link."""
    from ...body_parts import Geometry, Material, Shape

    pxr = reader.pxr
    UsdGeom, UsdPhysics, Usd = pxr.UsdGeom, pxr.UsdPhysics, pxr.Usd
    inv = se3.inv(reader.poses[link])
    it = iter(Usd.PrimRange(prim, Usd.TraverseInstanceProxies()))  # instanced shapes too (Isaac's importer)
    next(it)  # the link itself
    for p in it:
        reader.visited += 1
        if reader.visited > MAX_PRIMS:
            raise InputError(f"{reader.path}: more than {MAX_PRIMS} prims below the links (instances of instances "
                             f"of instances?); a robot has a few hundred")
        if p.GetPath() in reader.links:
            it.PruneChildren()  # another link (a frame inside this one): its own shapes
            continue
        kind = p.GetTypeName()
        if kind not in ("Cube", "Sphere", "Cylinder", "Capsule", "Mesh"):
            continue
        T, s = _rigid(inv @ reader.finite(_matrix(reader.cache.GetLocalToWorldTransform(p)), p, "transform"))
        if kind == "Cube":
            size = float(_value(p, "size", 2.0))
            geometry = Geometry("box", tuple(float(size * v) for v in s))
        elif kind == "Sphere":
            geometry = Geometry("sphere", (float(_value(p, "radius", 1.0)) * float(s.max()),))
        elif kind in ("Cylinder", "Capsule"):
            axis = str(_value(p, "axis", "Z"))
            if axis in _ALONG:
                T[:3, :3] = T[:3, :3] @ _ALONG[axis]
            k = {"X": 0, "Y": 1}.get(axis, 2)
            radial = max(float(s[m]) for m in range(3) if m != k)
            geometry = Geometry("cylinder" if kind == "Cylinder" else "capsule",
                                (float(_value(p, "radius", 1.0)) * radial, float(_value(p, "height", 2.0)) * float(s[k])))
        else:
            file = _get(p, "robkin:file")
            geometry = Geometry("mesh", tuple(float(v) for v in s),
                                str(file) if isinstance(file, str) and file else f"usd:{p.GetPath()}")
        reader.finite(geometry.size, p, "size")
        role = "collision" if p.HasAPI(UsdPhysics.CollisionAPI) else "visual"
        material = None
        colour = _get(p, "primvars:displayColor")
        if role == "visual" and colour is not None and len(colour) > 0:
            opacity = _get(p, "primvars:displayOpacity")
            a = float(opacity[0]) if opacity is not None and len(opacity) > 0 else 1.0
            material = Material(None, (float(colour[0][0]), float(colour[0][1]), float(colour[0][2]), a))
        name = _get(p, NAME_ATTR)
        yield Shape(link, 0, role, T, geometry, material, name if isinstance(name, str) else None)
