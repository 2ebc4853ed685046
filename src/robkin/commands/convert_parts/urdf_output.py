"""``convert --to urdf -o OUT``: the URDF text, with the mesh files it names taken along.

``package://`` names are written as the source wrote them (ROS, pinocchio and MuJoCo find packages
themselves). Every other mesh (a path relative to an MJCF or SDF, ``model://``, an absolute path) is
copied into ``meshes/`` beside the output, in its own format (URDF readers take COLLADA), and named
relative to it, so that the folder loads from anywhere. One warning line for meshes not found (their
names are written as the source gave them). ``--collision`` (``collision_output``) replaces the
collision shapes first; the mesh files it makes are named relative to the output.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # pragma: no cover
    from ...robot import Robot

__all__ = ["render_urdf"]


def render_urdf(robot: "Robot", args: argparse.Namespace, source: str | None, out_dir: Path | None,
                mesh_dir: str = "meshes") -> str:
    """The URDF text of ``robot`` read from ``source``; with ``out_dir``, its non-package meshes copied
    into ``out_dir/mesh_dir`` and named relative to ``out_dir``."""
    from ...io.urdf import urdf_from_robot
    from .collision_output import collision_stage

    with collision_stage(robot, args, source, out_dir, mesh_dir, fmt="urdf") as stage:  # --collision
        robot, premade = stage.robot, stage.premade
        if source is None or out_dir is None or not any(s.geometry.kind == "mesh" for s in robot.bodies.shapes):
            return urdf_from_robot(robot)
        import warnings
        from dataclasses import replace

        from ...io.meshes.files import copy_meshes, missing_line, resolve_meshes, with_mesh_names
        from ..support.common import package_paths

        found_in = robot.replace(bodies=replace(robot.bodies, shapes=tuple(
            s for s in robot.bodies.shapes if s.geometry.filename not in premade)))
        resolved = resolve_meshes(found_in, source, package_paths(args))
        travel = {k: m for k, m in resolved.items() if not k.lower().startswith("package://")}
        missing = missing_line(travel, source)
        if missing:
            warnings.warn(missing.replace("drawn without them", "written as the source names them"), UserWarning,
                          stacklevel=2)
        copies = copy_meshes(travel, out_dir, mesh_dir, readable=None) if travel else {}
        return urdf_from_robot(with_mesh_names(robot, {**copies, **premade}))
