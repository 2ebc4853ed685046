"""MJCF (MuJoCo's XML) in and out.

- In: ``source`` (one XML tree, ``<include>`` resolved, ``<compiler>`` and ``<default>`` read), ``reader``
  (the body tree as a Robot: ``robot_from_mjcf``), with ``poses``, ``geoms`` and ``equality``; each body's
  mass as MuJoCo compiles it: ``geom_mass`` (the rules), ``geom_inertia`` (primitive and mesh formulas),
  ``mesh_data`` (a mesh's points from its file or attributes).
- Out: ``writer`` (``mjcf_from_robot``: a model MuJoCo simulates), ``tree`` (which link becomes which
  body, joint or site), ``geoms_write``, ``inertial``, ``actuators``, and the meshes beside the model
  (``files``: ``write_mjcf``, ``meshes``, ``mesh_parts``).
- ``format``: what both share (MuJoCo's quaternion order, placements, the noise written as zero).

The entry points are importable from this package and imported on first use (``robkin.lazy_exports``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ...lazy_exports import lazy_exports

__all__ = ["robot_from_mjcf", "model_from_mjcf", "mjcf_from_robot", "write_mjcf", "mjcf_with_meshes"]

__getattr__, __dir__ = lazy_exports(__name__, globals(), {
    **dict.fromkeys(("robot_from_mjcf", "model_from_mjcf"), ".reader"),
    "mjcf_from_robot": ".writer",
    **dict.fromkeys(("write_mjcf", "mjcf_with_meshes"), ".files")})

if TYPE_CHECKING:  # what static type checkers and IDEs see
    from .files import mjcf_with_meshes, write_mjcf
    from .reader import model_from_mjcf, robot_from_mjcf
    from .writer import mjcf_from_robot
