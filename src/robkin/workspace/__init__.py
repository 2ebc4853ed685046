"""Workspace maps: where a robot's tool can go, with which approach directions, and how dexterously;
and where to stand a robot so that given task poses are reachable.

- ``maps``: ``reachability_map(robot, voxel, orientations, ...)`` -> ``WorkspaceMap`` (sampling
  configurations between the limits and binning their FK; ``reachable``, ``manipulability``, ``bins``);
- ``grid``: the voxel box in the base frame and the orientation bins (a Fibonacci sphere lattice of
  approach directions);
- ``sampling``: the chunks a map is sampled in, each with its own seed, and their order-free folding;
- ``distributed``: the same chunks on a Dask cluster (``dask=``), the same map;
- ``placement``: ``base_placement(map, poses, ...)``, the inverse-reachability query: base positions
  on a plane scored by how many task poses the map reaches from there;
- ``compare``: ``agreement(a, b)``, how far two maps of one voxel size agree;
- ``files``: ``save_map`` / ``load_map`` (.npz, read without pickles, bounded).

A capabilities package: it uses the hub (``Robot.fk``, ``Robot.manipulability``) and io's atomic
writes, never the front. Dask is imported only by the Dask path.
"""

from __future__ import annotations

from ..lazy_exports import lazy_exports

__all__ = ["WorkspaceMap", "reachability_map", "default_samples", "sphere_directions", "base_placement",
           "Placement", "agreement", "verify", "save_map", "load_map"]

__getattr__, __dir__ = lazy_exports(__name__, globals(), {
    "WorkspaceMap": ".maps", "reachability_map": ".maps", "default_samples": ".maps",
    "sphere_directions": ".grid", "base_placement": ".placement", "Placement": ".placement",
    "agreement": ".compare", "verify": ".placement", "save_map": ".files", "load_map": ".files"})
