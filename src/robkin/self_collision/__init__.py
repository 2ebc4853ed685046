"""Self-collision: conservative capsules per link, the allowed-collision matrix, collision-aware IK.

- ``geometry``: each link's collision shapes (meshes read, primitives kept), base frame at q = 0;
- ``capsules``: one least-volume capsule per link enclosing every vertex (conservative);
- ``model``: ``SelfCollisionModel``: the capsules, the pairs checked, the compiled batch check
  (``robkin.compiled.collision.capsules``) and distances, the convex parts' level
  (``robkin.compiled.collision.parts``);
- ``pairmaps``: pairs one or two joints move against each other, tabulated (cells proven apart);
  ``revolve``: a link turned about a joint's axis, the polytope around its solid of revolution (a map
  over fewer joints);
- ``acm``: the allowed-collision matrix (Adjacent, Default, Always, Never) from sampled configurations;
- ``exact``: the exact check of the links' own geometry (coal), the capsules' reference;
- ``build``: ``self_collision_model(robot, source)``, and what ``Robot.self_collision`` and
  ``Robot.self_collision_distances`` call;
- ``ik``: collision-aware IK (``Robot.ik(T, avoid_self_collision=True)``).

The SRDF file (``<disable_collisions>``) is read and written by ``robkin.io.srdf``. A capabilities
package: it uses the hub, io and the compiled core, never the front.
"""

from __future__ import annotations

from ..lazy_exports import lazy_exports

__all__ = ["SelfCollisionModel", "DisabledPair", "self_collision_model", "allowed_collisions", "Capsule",
           "ExactChecker", "collision_free_ik"]

__getattr__, __dir__ = lazy_exports(__name__, globals(), {
    "SelfCollisionModel": ".model", "DisabledPair": ".model", "self_collision_model": ".build",
    "allowed_collisions": ".acm", "Capsule": ".capsules", "ExactChecker": ".exact", "collision_free_ik": ".ik"})
