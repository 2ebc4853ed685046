"""Converters between the GJD hub and each representation: ``<out>_from_robot`` / ``robot_from_<in>``.

Each name is imported from its module on first use (see ``robkin.lazy_exports``): a command that
writes a DH table does not pay for importing the PoE, Hayati or RPY-XYZ modules.

``registry`` declares each representation once (CLI name, document section, columns, layout,
converters by name); documents, table files, the CLI, the GUI and the plots iterate it.
``presentation`` is this layer's facade to io (a table's ``str()`` and ``to_dict()``).
"""

from typing import TYPE_CHECKING

from ..lazy_exports import lazy_exports

_WHERE = {
    **dict.fromkeys(("DHTable", "dh_from_robot", "dh_from_robots", "robot_from_dh"), ".dh"),
    **dict.fromkeys(("gjd_from_robot", "robot_from_gjd"), ".gjd"),
    **dict.fromkeys(("HayatiTable", "hayati_from_robot", "hayati_from_robots", "robot_from_hayati"), ".hayati"),
    **dict.fromkeys(("MDHTable", "mdh_from_robot", "mdh_from_robots", "robot_from_mdh"), ".mdh"),
    **dict.fromkeys(("PoE", "poe_from_robot", "robot_from_poe"), ".poe"),
    **dict.fromkeys(("RPYTable", "robot_from_rpy", "rpy_from_robot"), ".rpy_xyz"),
}

__all__ = [
    "DHTable", "MDHTable", "HayatiTable", "PoE", "RPYTable",
    "dh_from_robot", "dh_from_robots", "robot_from_dh", "mdh_from_robot", "mdh_from_robots",
    "robot_from_mdh",
    "poe_from_robot", "robot_from_poe", "rpy_from_robot", "robot_from_rpy",
    "gjd_from_robot", "robot_from_gjd", "hayati_from_robot", "hayati_from_robots",
    "robot_from_hayati",
]

__getattr__, __dir__ = lazy_exports(__name__, globals(), _WHERE)

if TYPE_CHECKING:  # what static type checkers and IDEs see
    from .dh import DHTable, dh_from_robot, dh_from_robots, robot_from_dh
    from .gjd import gjd_from_robot, robot_from_gjd
    from .hayati import HayatiTable, hayati_from_robot, hayati_from_robots, robot_from_hayati
    from .mdh import MDHTable, mdh_from_robot, mdh_from_robots, robot_from_mdh
    from .poe import PoE, poe_from_robot, robot_from_poe
    from .rpy_xyz import RPYTable, robot_from_rpy, rpy_from_robot
