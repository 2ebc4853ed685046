"""Collision geometry for simulators: what ``robkin convert --collision`` makes of a robot's collision shapes.

- ``pipeline``: ``collision_geometry(robot, mode, ...)``, the shapes of each mode (source, hull,
  decompose, primitives, none) and the mesh files written beside the output;
- ``mesh_data``: mesh files read as arrays (untrusted input, bounded), written as binary STL;
- ``hull``: convex hulls (SciPy's Qhull), flat meshes as thin boxes;
- ``decimate``: the face budget (``fast-simplification``);
- ``decompose``: convex decomposition by CoACD, cached by content;
- ``primitives``: a fitted box, sphere, cylinder or capsule per link, and its fit (volume error,
  one-sided Hausdorff distance);
- ``tessellate``: primitives as triangles, exact point-to-triangle distances;
- ``exclusions``: the body pairs an MJCF excludes from contact (parent-child, touching at home).

A capabilities package: it uses io (mesh files, the writers' drafts) and the hub, never the front.
"""

from __future__ import annotations

from ..lazy_exports import lazy_exports

__all__ = ["MODES", "Collision", "collision_geometry", "contact_excludes", "fit_primitive", "FitReport"]

__getattr__, __dir__ = lazy_exports(__name__, globals(), {
    "MODES": ".pipeline", "Collision": ".pipeline", "collision_geometry": ".pipeline",
    "contact_excludes": ".exclusions", "fit_primitive": ".primitives", "FitReport": ".primitives"})
