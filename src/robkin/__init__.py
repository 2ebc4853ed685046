"""robkin: exact conversion between serial-robot kinematic representations, and kinematics on top.

Conventions (used everywhere in the package):

- Angles in radians, lengths in metres (or any consistent unit).
- Hub: the Global Joint Description (GJD), n + 1 poses (4, 4) in the robot base frame at q = 0:
  J_1..J_n with z along joint i's axis in its positive direction, and the tool J_{n+1}.
  One joint vector q means the same configuration in every representation.
- Standard DH row (a, d, alpha, theta): A_i = Rz(theta) Tz(d) Tx(a) Rx(alpha); joint i moves about/along
  z_{i-1}; theta (revolute) or d (prismatic) is the value at q = 0 and the joint adds q_i.
- Modified (Craig) DH row (a, d, alpha, theta) = (a_{i-1}, d_i, alpha_{i-1}, theta_i):
  A_i = Rx(alpha) Tx(a) Rz(theta) Tz(d).
- Hayati row (a, d, alpha, theta, beta): A_i = Rz(theta) Tz(d) Tx(a) Rx(alpha) Ry(beta), joint i as in
  standard DH; beta is used (and d = 0) only where axes i and i+1 are nearly parallel.
- PoE screws (w, v): revolute (w, -w x p), prismatic (0, v). Space: T = exp([S1]q1)...exp([Sn]qn) M;
  body: T = M exp([B1]q1)...exp([Bn]qn).
- RPY is URDF's: R = Rz(yaw) Ry(pitch) Rx(roll); a row is (roll, pitch, yaw, x, y, z); an RPY-XYZ table
  has n + 2 rows (world->base, one per joint, joint n->tool).
- FK is the tool pose in the robot base frame; a world->base transform is kept but not part of FK.
- A joint with ``flip`` moves opposite to its frame's z axis in DH, modified DH and RPY-XYZ tables.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

from .errors import ConditioningWarning, InputError, ProjectionWarning, RobkinError
from .lazy_exports import lazy_exports
from .robot import Joint, Robot
from .version import __version__


#: the representations' classes and converters, imported on first use (robkin.DHTable, robkin.dh_from_robot,
#: ...; see robkin.lazy_exports): ``import robkin`` itself costs only the hub (Robot) and the errors
_REPRESENTATIONS = (
    "DHTable", "MDHTable", "HayatiTable", "PoE", "RPYTable",
    "dh_from_robot", "dh_from_robots", "mdh_from_robot", "mdh_from_robots", "hayati_from_robot",
    "hayati_from_robots", "poe_from_robot", "rpy_from_robot",
    "robot_from_dh", "robot_from_mdh", "robot_from_hayati", "robot_from_poe", "robot_from_rpy",
    "robot_from_gjd",
)

__all__ = [
    "Joint", "Robot", *_REPRESENTATIONS,
    "RobkinError", "InputError", "ProjectionWarning", "ConditioningWarning", "load", "__version__",
    "set_threads", "get_threads", "calibrate",
]

__getattr__, __dir__ = lazy_exports(__name__, globals(), {**dict.fromkeys(_REPRESENTATIONS, ".representations"),
                                                        "set_threads": ".threads", "get_threads": ".threads",
                                                        "calibrate": ".calibration"})

if TYPE_CHECKING:  # what static type checkers and IDEs see
    from .representations import (DHTable, HayatiTable, MDHTable, PoE, RPYTable, dh_from_robot,
                                  dh_from_robots, hayati_from_robot, hayati_from_robots, mdh_from_robot, mdh_from_robots,
                                  poe_from_robot, robot_from_dh, robot_from_gjd, robot_from_hayati,
                                  robot_from_mdh, robot_from_poe, robot_from_rpy, rpy_from_robot)
    from .calibration import calibrate
    from .threads import get_threads, set_threads


def load(path: str | os.PathLike[str], base_link: str | None = None, tip_link: str | None = None, *,
         allow_xacro: bool = False, representation: str | None = None) -> Robot:
    """Load a robot from a robot document (.yaml/.yml/.json), a URDF (.urdf), MJCF (.xml/.mjcf), SDF (.sdf) or USD
    (.usda/.usd/.usdc, with usd-core) file, or a table file (.csv/.tsv/.txt: what ``robkin convert --format csv`` writes, or bare rows).

    ``representation`` ('dh', 'mdh', 'hayati', 'poe', 'poe-body', 'rpy-xyz', 'gjd') says which table a
    table file holds where the file does not say (bare rows ``a d alpha theta``; a PoE's frame).

    ``base_link``/``tip_link`` pick a serial chain from a robot file: URDF/SDF links, MJCF bodies or sites.
    A .xacro file is expanded only with ``allow_xacro=True`` (xacro runs code from the file).

    ``path``: the file to read (str or path-like); its suffix picks the reader.
    """
    from .io import load as _load

    return _load(path, base_link=base_link, tip_link=tip_link, allow_xacro=allow_xacro,
                 representation=representation)
