"""The exact check: the links' own collision geometry (meshes as triangle sets, primitives as
themselves) collided by coal (the collision library pinocchio installs: ``pip install coal``).

``ExactChecker(robot, links)`` builds one coal object per shape; ``pair_collides(q, u, v)`` says whether
links u and v (indices into ``links``) touch at configuration q, ``colliding_pairs(q)`` which of the
given pairs do. It is the reference the capsule model is measured against (no false "free") and what
the allowed-collision matrix (``acm``) refines the capsules' verdicts with. Triangle meshes collide by
their surfaces (as MoveIt's FCL does): a link wholly inside another's closed mesh without touching its
surface does not count.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Iterable

import numpy as np

from ..errors import InputError
from .geometry import LinkGeometry

if TYPE_CHECKING:  # pragma: no cover
    from ..robot import Robot

__all__ = ["ExactChecker", "exact_available"]


def exact_available() -> bool:
    """Whether coal can be imported (the exact check needs it)."""
    try:
        import coal  # noqa: F401
    except ImportError:
        return False
    return True


def _coal_geometry(shape: Any) -> object:
    import coal

    if shape.kind == "mesh":
        m = coal.BVHModelOBBRSS()
        m.beginModel(len(shape.faces), len(shape.vertices))
        m.addVertices(np.ascontiguousarray(shape.vertices, dtype=np.float64))
        m.addTriangles(np.ascontiguousarray(shape.faces, dtype=np.int64))
        m.endModel()
        return m
    s = shape.size
    if shape.kind == "box":
        return coal.Box(float(s[0]), float(s[1]), float(s[2]))
    if shape.kind == "sphere":
        return coal.Sphere(float(s[0]))
    if shape.kind == "cylinder":
        return coal.Cylinder(float(s[0]), float(s[1]))
    return coal.Capsule(float(s[0]), float(s[1]))


class ExactChecker:
    """coal objects of each link's shapes, placed in their body's GJD frame (see the module doc)."""

    def __init__(self, robot: Robot, links: list[LinkGeometry]) -> None:
        try:
            import coal
        except ImportError:
            raise InputError("the exact collision check needs coal: pip install coal (or pinocchio)") from None
        self.coal = coal
        self.robot = robot
        self.links = links
        J = robot.frames
        self.objects: list[list[tuple[object, np.ndarray]]] = []
        for g in links:
            inv = np.linalg.inv(J[g.body - 1]) if g.body > 0 else np.eye(4)
            self.objects.append([(_coal_geometry(s), inv @ s.pose) for s in g.shapes])
        self.request = coal.CollisionRequest()

    def _placed(self, F: np.ndarray, u: int) -> list[tuple[object, object]]:
        body = self.links[u].body
        B = F[body - 1] if body > 0 else np.eye(4)
        out = []
        for geom, local in self.objects[u]:
            T = B @ local
            out.append((geom, self.coal.Transform3s(np.ascontiguousarray(T[:3, :3]), np.ascontiguousarray(T[:3, 3]))))
        return out

    def colliding_pairs(self, q: np.ndarray, pairs: Iterable[tuple[int, int]],
                        first: bool = False) -> list[tuple[int, int]]:
        """The pairs (u, v) of link indices whose shapes touch at the configuration q (n,); ``first``: stop
        at the first one."""
        F = self.robot.frames_at(np.asarray(q, dtype=float))
        placed: dict[int, list[tuple[object, object]]] = {}
        out = []
        collide, Result = self.coal.collide, self.coal.CollisionResult
        for u, v in pairs:
            if u not in placed:
                placed[u] = self._placed(F, u)
            if v not in placed:
                placed[v] = self._placed(F, v)
            if any(collide(g1, t1, g2, t2, self.request, Result()) for g1, t1 in placed[u] for g2, t2 in placed[v]):
                out.append((u, v))
                if first:
                    break
        return out

    def pair_collides(self, q: np.ndarray, u: int, v: int) -> bool:
        """Whether links u and v touch at q (n,)."""
        return bool(self.colliding_pairs(q, [(u, v)]))
