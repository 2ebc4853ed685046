"""Asset checks of a URDF: meshes missing or unreadable, flat, open (where a volume is taken from them),
too many faces, or in the wrong unit (much larger than the robot)."""

from __future__ import annotations

import numpy as np

from .findings import ERROR, INFO, WARNING, Finding
from .geometry import MeshCache
from .urdf_source import RawUrdf

__all__ = ["asset_findings", "MAX_FACES", "UNIT_FACTOR"]

#: a mesh with more triangles than this slows collision and loading for nothing (MuJoCo's convex hull of a
#: collision mesh, pinocchio's FCL BVH); --max-faces changes it
MAX_FACES = 200_000
#: a mesh this many times larger than the robot (the span of its joint origins) is in the wrong unit
UNIT_FACTOR = 50.0
#: a mesh thinner than this fraction of its size is flat: no volume (1e-9 is rounding of float32 STL)
FLAT = 1e-9


def robot_span(u: RawUrdf) -> float:
    """A length scale of the robot: the sum of its joint origins' distances (at least 0.1 m)."""
    return max(sum(float(np.linalg.norm(j.origin[:3, 3])) for j in u.joints), 0.1)


def asset_findings(u: RawUrdf, meshes: MeshCache, max_faces: int = MAX_FACES) -> list[Finding]:
    f: list[Finding] = []
    span = robot_span(u)
    for ln in u.links:
        el = f"{u.link_word} '{ln.name}'"
        has_collision = any(g.role == "collision" for g in ln.geometries)
        for g in ln.geometries:
            if g.kind != "mesh":
                bad = _bad_size(g)
                if bad:
                    f.append(Finding(ERROR if g.role == "collision" else WARNING, "geom-size", u.file, g.line, el,
                                     f"{g.role} {g.kind} {bad}: MuJoCo refuses it ('size 0 must be positive in geom'"
                                     + ("" if g.role == "collision" else "; its URDF import drops visuals, robkin "
                                        "convert --to mjcf writes them") + "); pinocchio's collision model gets a "
                                     "degenerate shape", "give the shape its real size, or remove it"))
                continue

            def add(sev, code, message, fix, g=g):
                f.append(Finding(sev, code, u.file, g.line, el, message, fix))

            # a visual mesh beside collision shapes carries no mass: its triangle count and size are enough
            # (mesh_summary: a COLLADA file summed up from its XML, 10-50x faster than parsing it whole)
            if g.role == "visual" and has_collision:
                _visual(add, g, *meshes.summary(g.filename or ""), span, max_faces)
                continue

            r = meshes.get(g.filename or "")
            if r.path is None:
                add(ERROR, "mesh-missing", *_missing(g, r))
                continue
            if r.V is None or r.F is None:
                add(ERROR, "mesh-unreadable", f"{g.role} mesh '{g.filename}': {r.reason}",
                    "re-export the mesh as binary STL or OBJ")
                continue
            V = r.V * np.asarray(g.scale)
            size = V.max(axis=0) - V.min(axis=0)
            diag = float(np.linalg.norm(size))
            if len(r.F) > max_faces:
                add(WARNING, "mesh-faces", f"{g.role} mesh '{g.filename}' has {len(r.F)} triangles, above the budget "
                    f"of {max_faces} (slow to load and collide)", "decimate it (robkin convert --to mjcf "
                    "--max-faces N does it for MuJoCo), or use primitives/hulls for collision")
            if diag > UNIT_FACTOR * span:
                add(WARNING, "mesh-unit", f"{g.role} mesh '{g.filename}' is {diag:.3g} m across, {diag / span:.0f}x "
                    f"the robot ({span:.3g} m): it looks written in millimetres", 'add scale="0.001 0.001 0.001" '
                    "to <mesh> (or re-export in metres)")
            if g.role != "collision":
                continue
            if size.min() <= FLAT * max(diag, 1e-300):
                add(WARNING, "mesh-flat", f"collision mesh '{g.filename}' is flat (zero volume): MuJoCo refuses it "
                    "where it must compute a volume, and it cannot carry mass", "give the link a solid collision shape")
            elif not r.closed:
                add(INFO, "mesh-open", f"collision mesh '{g.filename}' is not watertight: lint (and MuJoCo's inertia "
                    "from geometry) take its convex hull's volume", "close the mesh if its own volume matters")
    return f


def _missing(g, r) -> tuple[str, str]:
    return (f"{g.role} mesh '{g.filename}': {r.reason} (MuJoCo refuses the file; pinocchio loads no geometry)",
            "put the mesh where the filename says, or fix the filename (--package-path NAME=DIR tells where "
            "package:// is)")


def _visual(add, g, r, summary, span: float, max_faces: int) -> None:
    """The checks of a visual mesh: missing, unreadable (a warning: it carries nothing but its looks),
    too many triangles, in millimetres."""
    if r.path is None:
        add(ERROR, "mesh-missing", *_missing(g, r))
        return
    if summary is None:
        add(WARNING, "mesh-unreadable", f"visual mesh '{g.filename}': {r.reason} (viewers and pinocchio's "
            "visual model show nothing; robkin convert --to mjcf leaves it out)", "re-export the mesh as binary "
            "STL, OBJ or COLLADA")
        return
    if summary.faces > max_faces:
        add(WARNING, "mesh-faces", f"visual mesh '{g.filename}' has {summary.faces} triangles, above the budget "
            f"of {max_faces} (slow to load and draw)", "decimate it")
    diag = float(np.linalg.norm((summary.hi - summary.lo) * np.abs(np.asarray(g.scale))))
    if diag > UNIT_FACTOR * span:
        add(WARNING, "mesh-unit", f"visual mesh '{g.filename}' is {diag:.3g} m across, {diag / span:.0f}x the "
            f"robot ({span:.3g} m): it looks written in millimetres", 'add scale="0.001 0.001 0.001" to <mesh> '
            "(or re-export in metres)")


def _bad_size(g) -> str:
    """What is wrong with a primitive's size ("" when nothing): MuJoCo needs every size it reads positive."""
    if g.size is None:
        return "has a size that is not numbers"
    need = {"box": 3, "cylinder": 2, "sphere": 1, "capsule": 1}.get(g.kind, 0)
    if any(x <= 0 for x in g.size[:need]):
        return "has a size of zero or less (" + ", ".join(f"{x:g}" for x in g.size[:need]) + ", MJCF half sizes)"
    return ""
