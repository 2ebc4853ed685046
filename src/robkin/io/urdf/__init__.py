"""URDF in and out.

- ``model``: the file parsed (``parse_urdf``, ``parse_urdf_text``): links, joints and the lazily parsed
  link contents (``content``), the compiled scan doing the kinematic part;
- ``chain``: a serial chain out of the tree as a ``Robot`` (``robot_from_urdf``, ``robot_from_model``);
- ``writer``: a ``Robot`` as URDF text (``urdf_from_robot``), the source file again where there is one.

The entry points are importable from this package and imported on first use (``robkin.lazy_exports``):
loading a URDF for its kinematics does not pay for the writer.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ...lazy_exports import lazy_exports

__all__ = ["parse_urdf", "parse_urdf_text", "UrdfModel", "UrdfJoint", "LinkContent", "origin_matrix",
           "robot_from_urdf", "robot_from_model", "axis_frame", "urdf_from_robot"]

__getattr__, __dir__ = lazy_exports(__name__, globals(), {
    **dict.fromkeys(("parse_urdf", "parse_urdf_text", "UrdfModel", "UrdfJoint", "LinkContent", "origin_matrix"),
                    ".model"),
    **dict.fromkeys(("axis_frame", "robot_from_model", "robot_from_urdf"), ".chain"),
    "urdf_from_robot": ".writer"})

if TYPE_CHECKING:  # what static type checkers and IDEs see
    from .chain import axis_frame, robot_from_model, robot_from_urdf
    from .model import LinkContent, UrdfJoint, UrdfModel, origin_matrix, parse_urdf, parse_urdf_text
    from .writer import urdf_from_robot
