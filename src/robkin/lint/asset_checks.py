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
                continue
            # a visual mesh beside collision shapes is only looked for (and its triangles counted when the
            # count is in a binary STL's header): parsing COLLADA visuals is most of a lint's time
            skim = g.role == "visual" and has_collision

            def add(sev, code, message, fix):
                f.append(Finding(sev, code, u.file, g.line, el, message, fix))

            r = meshes.found(g.filename or "") if skim else meshes.get(g.filename or "")
            if r.path is None:
                add(ERROR, "mesh-missing", f"{g.role} mesh '{g.filename}': {r.reason} (MuJoCo refuses the file; "
                    "pinocchio loads no geometry)", "put the mesh where the filename says, or fix the filename "
                    "(--package-path NAME=DIR tells where package:// is)")
                continue
            if skim:
                faces = _stl_faces(r.path)
                if faces is not None and faces > max_faces:
                    add(WARNING, "mesh-faces", f"{g.role} mesh '{g.filename}' has {faces} triangles, above the budget "
                        f"of {max_faces} (slow to load and draw)", "decimate it")
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


def _stl_faces(path) -> int | None:
    """The triangle count of a binary STL from its 84-byte header (None for any other file)."""
    try:
        if path.suffix.lower() != ".stl":
            return None
        size = path.stat().st_size
        with open(path, "rb") as fh:
            head = fh.read(84)
    except OSError:
        return None
    n = int.from_bytes(head[80:84], "little") if len(head) == 84 else -1
    return n if size == 84 + 50 * n else None
