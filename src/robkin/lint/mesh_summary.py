"""What lint needs of a visual mesh, cheaply: its triangle count and the box of its vertices, in metres.

A visual mesh carries no mass, so lint needs no triangles of it, only their number (the face budget) and
its size (a unit mistake). STL and OBJ are read whole (``collision.mesh_data.read_mesh``: fast); a COLLADA
file (``.dae``, the usual visual mesh, which trimesh parses in ~0.1 s each) is summed up from its XML: the
``count`` of each ``<triangles>``, ``<polylist>`` (its ``<vcount>``: a polygon of k corners is k - 2
triangles) and ``<polygons>``, the box of the ``POSITION`` arrays of each geometry's ``<vertices>``, moved
by the node transforms (``matrix``, ``translate``, ``rotate``, ``scale``) of each ``<instance_geometry>`` in
the visual scene (exporters scale millimetre geometry there), and ``<asset><unit meter>``. The box of a
geometry's box corners bounds the mesh (it may be larger than the mesh's own under a rotation: a unit
mistake is a factor of 1000).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["MeshSummary", "dae_summary"]

#: largest COLLADA file summed up (bytes); a larger one is "unreadable" (as read_mesh refuses huge meshes)
MAX_DAE_BYTES = 256 * 1024 * 1024


@dataclass
class MeshSummary:
    """Triangle count and vertex box (lo, hi: (3,), metres, before the ``<mesh scale>``)."""

    faces: int
    lo: np.ndarray
    hi: np.ndarray


def _local(tag) -> str:
    return tag.rsplit("}", 1)[-1] if isinstance(tag, str) else ""


def dae_summary(path: Path) -> MeshSummary:
    """The summary of a COLLADA file; ValueError naming why when it cannot be read."""
    from lxml import etree  # type: ignore[import-untyped, unused-ignore]

    if path.stat().st_size > MAX_DAE_BYTES:
        raise ValueError(f"larger than {MAX_DAE_BYTES} bytes")
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False, huge_tree=True,
                             remove_comments=True, remove_pis=True)
    try:
        root = etree.parse(str(path), parser).getroot()
    except (etree.XMLSyntaxError, OSError) as exc:
        raise ValueError(f"not valid COLLADA XML ({exc})") from None
    meter = 1.0
    for el in root.iter():
        if _local(el.tag) == "unit" and el.get("meter"):
            try:
                meter = float(el.get("meter"))
            except ValueError:
                pass
            break
    geoms = {}   # geometry id -> (faces, lo, hi)
    for g in root.iter():
        if _local(g.tag) == "geometry":
            got = _geometry(g)
            if got is not None:
                geoms[g.get("id") or f"#{len(geoms)}"] = got
    if not geoms:
        raise ValueError("no triangles")
    faces, lo, hi = 0, np.full(3, np.inf), np.full(3, -np.inf)
    instances = list(_instances(root))
    for gid, T in instances or [(k, np.eye(4)) for k in geoms]:
        if gid not in geoms:
            continue
        n, a, b = geoms[gid]
        corners = np.array([[x, y, z, 1.0] for x in (a[0], b[0]) for y in (a[1], b[1]) for z in (a[2], b[2])]) @ T.T
        faces += n
        lo, hi = np.minimum(lo, corners[:, :3].min(axis=0)), np.maximum(hi, corners[:, :3].max(axis=0))
    if faces == 0 or not np.isfinite(lo).all():
        raise ValueError("no triangles")
    return MeshSummary(faces, lo * meter, hi * meter)


def _geometry(g) -> tuple[int, np.ndarray, np.ndarray] | None:
    """(triangles, lo, hi) of one ``<geometry>``'s mesh, from its own POSITION arrays."""
    faces, sources, positions = 0, {}, []
    for el in g.iter():
        tag = _local(el.tag)
        if tag in ("triangles", "polygons"):
            faces += int(el.get("count") or 0)
        elif tag == "polylist":
            vc = next((c for c in el if _local(c.tag) == "vcount"), None)
            counts = np.array((vc.text or "").split(), dtype=np.int64) if vc is not None else np.zeros(0, np.int64)
            faces += int(np.maximum(counts - 2, 0).sum())
        elif tag == "source" and el.get("id"):
            sources[el.get("id")] = el
        elif tag == "vertices":
            positions += [(i.get("source") or "").lstrip("#") for i in el
                          if _local(i.tag) == "input" and i.get("semantic") == "POSITION"]
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    for sid in positions:
        src = sources.get(sid)
        fa = next((c for c in src.iter() if _local(c.tag) == "float_array"), None) if src is not None else None
        if fa is None or not fa.text:
            continue
        try:
            v = np.array(fa.text.split(), dtype=float)
        except ValueError:
            raise ValueError(f"a POSITION array of source '{sid}' is not numbers") from None
        v = v[: len(v) // 3 * 3].reshape(-1, 3)
        if len(v) and np.isfinite(v).all():
            lo, hi = np.minimum(lo, v.min(axis=0)), np.maximum(hi, v.max(axis=0))
    return (faces, lo, hi) if faces and np.isfinite(lo).all() else None


def _transform(node) -> np.ndarray:
    """A ``<node>``'s own transform (4, 4): its ``matrix``, ``translate``, ``rotate``, ``scale`` in order."""
    T = np.eye(4)
    for el in node:
        tag = _local(el.tag)
        try:
            v = np.array((el.text or "").split(), dtype=float)
        except ValueError:
            continue
        M = np.eye(4)
        if tag == "matrix" and v.size == 16:
            M = v.reshape(4, 4)
        elif tag == "translate" and v.size == 3:
            M[:3, 3] = v
        elif tag == "scale" and v.size == 3:
            M[:3, :3] = np.diag(v)
        elif tag == "rotate" and v.size == 4 and np.linalg.norm(v[:3]) > 0:
            from scipy.spatial.transform import Rotation

            M[:3, :3] = Rotation.from_rotvec(v[:3] / np.linalg.norm(v[:3]) * np.radians(v[3])).as_matrix()
        else:
            continue
        T = T @ M
    return T


def _instances(root):
    """(geometry id, transform (4, 4)) of each ``<instance_geometry>`` of the visual scenes' node trees."""
    for scene in root.iter():
        if _local(scene.tag) != "visual_scene":
            continue
        todo = [(n, np.eye(4)) for n in scene if _local(n.tag) == "node"]
        while todo:
            node, parent = todo.pop()
            T = parent @ _transform(node)
            for c in node:
                tag = _local(c.tag)
                if tag == "node":
                    todo.append((c, T))
                elif tag == "instance_geometry":
                    yield (c.get("url") or "").lstrip("#"), T
