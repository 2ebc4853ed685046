"""USD (OpenUSD with UsdPhysics) in and out, through ``usd-core`` (``pip install 'robkin[usd]'``).

- Out: ``writer`` (``usd_stage``: the robot as a UsdPhysics articulation; ``usd_from_robot``: its
  ``.usda`` text; ``write_usd``: a ``.usda``/``.usd``/``.usdc`` file), ``physics`` (joints, drives, mass
  properties), ``shapes`` (visual and collision prims), ``meshes`` (mesh files read into points and
  faces, written inline).
- In: ``layer`` (one file opened as one layer, with nothing it names followed), ``reader``
  (``model_from_usd``: the articulation as the ``UrdfModel`` every tree reader builds;
  ``robot_from_usd``: a serial chain of it).
- ``format``: what both share (the pxr import, names as USD identifiers, units, quaternions).

The entry points are importable from this package and imported on first use (``robkin.lazy_exports``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ...lazy_exports import lazy_exports

__all__ = ["robot_from_usd", "model_from_usd", "usd_from_robot", "usd_stage", "write_usd"]

__getattr__, __dir__ = lazy_exports(__name__, globals(), {
    **dict.fromkeys(("robot_from_usd", "model_from_usd"), ".reader"),
    **dict.fromkeys(("usd_from_robot", "usd_stage", "write_usd"), ".writer")})

if TYPE_CHECKING:  # what static type checkers and IDEs see
    from .reader import model_from_usd, robot_from_usd
    from .writer import usd_from_robot, usd_stage, write_usd
