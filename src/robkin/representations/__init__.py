"""Converters between the GJD hub and each representation: ``<out>_from_robot`` / ``robot_from_<in>``."""

from .dh import DHTable, dh_from_robot, dh_from_robots, robot_from_dh
from .gjd import gjd_from_robot, robot_from_gjd
from .hayati import HayatiTable, hayati_from_robot, robot_from_hayati
from .mdh import MDHTable, mdh_from_robot, mdh_from_robots, robot_from_mdh
from .poe import PoE, poe_from_robot, robot_from_poe
from .rpy_xyz import RPYTable, robot_from_rpy, rpy_from_robot

__all__ = [
    "DHTable", "MDHTable", "HayatiTable", "PoE", "RPYTable",
    "dh_from_robot", "dh_from_robots", "robot_from_dh", "mdh_from_robot", "mdh_from_robots",
    "robot_from_mdh",
    "poe_from_robot", "robot_from_poe", "rpy_from_robot", "robot_from_rpy",
    "gjd_from_robot", "robot_from_gjd", "hayati_from_robot", "robot_from_hayati",
]
