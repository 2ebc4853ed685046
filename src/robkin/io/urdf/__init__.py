"""URDF in and out: a serial chain of a URDF file as a Robot, and a Robot as a URDF.

- ``parser``: the file parsed into a ``UrdfModel`` (``io.trees.model``: the tree of links and joints, read
  by one compiled pass of expat, ``compiled.scanners.urdf_scan``, that builds no XML tree; the contents of links,
  visuals, collisions and inertials, parsed from the text only when asked for, by ``content`` on
  ``io.trees.xml_parse``'s tree; a joint is an ``io.trees.tree_joint.UrdfJoint`` whose numbers stay plain
  floats, composed as ``pose_rows``);
- ``chain``: a serial chain out of the tree as a Robot (``robot_from_urdf``, ``robot_from_model``);
- ``writer``: a Robot as URDF text (``urdf_from_robot``), the source file again where there is one.

The entry points are importable from this package and imported on first use (``robkin.lazy_exports``):
loading a URDF for its kinematics does not pay for the writer.

Import (``robot_from_urdf``)
    revolute, continuous (revolute without limits), prismatic and fixed joints; any joint axis (a
    non-unit axis is normalised with a ``ProjectionWarning``) and any ``rpy`` origin. Fixed joints are
    folded into the neighbouring transforms. A serial chain is picked from a tree with
    ``base_link``/``tip_link``; either may be any link rigidly attached (through fixed joints, in
    either direction) to the chain's ends. Everything else the file says (link names, visuals,
    collisions, inertials, the links off the chain, joint effort/velocity/dynamics/mimic) is kept in
    ``Robot.bodies`` and ``Joint``; mesh files are never opened, so ``package://`` references need not
    resolve. The XML must have no DTD (so no entities of any kind); transmissions, ``<gazebo>`` and
    other extensions are ignored.

    The GJD: joint i's frame is its child link's frame at q = 0, turned so that its z axis is the
    (normalised) joint axis; the URDF joint position then *is* robkin's q_i (same sign, same zero).
    When the axis points against its link frame's z (negative z component), the joint gets ``flip``
    and the frame turned minimally onto -axis is used for frame-based tables, so an axis ``0 0 -1``
    gives RPY-XYZ rows equal to the URDF origins. The tool is the tip link frame; the links above the
    base link (typically a fixed ``world`` link) become ``Robot.world``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ...lazy_exports import lazy_exports

__all__ = ["parse_urdf", "parse_urdf_text", "UrdfModel", "UrdfJoint", "LinkContent", "origin_matrix",
           "robot_from_urdf", "robot_from_model", "axis_frame", "urdf_from_robot"]

__getattr__, __dir__ = lazy_exports(__name__, globals(), {
    **dict.fromkeys(("parse_urdf", "parse_urdf_text"), ".parser"),
    **dict.fromkeys(("UrdfModel", "UrdfJoint", "LinkContent", "origin_matrix"), "..trees.model"),
    **dict.fromkeys(("axis_frame", "robot_from_model", "robot_from_urdf"), ".chain"),
    "urdf_from_robot": ".writer"})

if TYPE_CHECKING:  # what static type checkers and IDEs see
    from .chain import axis_frame, robot_from_model, robot_from_urdf
    from ..trees.model import LinkContent, UrdfJoint, UrdfModel, origin_matrix
    from .parser import parse_urdf, parse_urdf_text
    from .writer import urdf_from_robot
