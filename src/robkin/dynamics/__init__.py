"""Rigid-body dynamics of the chain: mass properties per body, inverse dynamics, gravity, mass matrix.

- ``mass_properties``: ``link_masses(robot)`` merges every inertial on a body (fixed links, the tool,
  links off the chain held at 0) exactly; ``LinkMasses.in_frames`` re-expresses them in a table's link
  frames and ``inertials_from_frames`` goes back.
- ``rigid_body``: recursive Newton-Euler and the composite-rigid-body mass matrix on the compiled chain
  (``robkin.compiled.chain.dynamics``), behind ``Robot.inverse_dynamics``, ``Robot.gravity`` and
  ``Robot.mass_matrix``.

Units: kg, metres, seconds, radians; torques in N m (revolute) or forces in N (prismatic).
"""

from __future__ import annotations

from ..mass_properties import LinkMasses, check_inertia, inertials_from_frames, link_masses, merge_masses

__all__ = ["LinkMasses", "link_masses", "merge_masses", "inertials_from_frames", "check_inertia"]
