"""The OPW parameters of an industrial arm as a document (``robkin convert --to opw``): the keys of
moveit_opw_kinematics_plugin's kinematics.yaml. The parameters themselves are found by
``robkin.representations.opw``."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ...representations.opw import GEOMETRY, opw_from_robot

if TYPE_CHECKING:  # pragma: no cover
    from ...robot import Robot

__all__ = ["opw_document"]


def opw_document(robot: "Robot") -> dict[str, Any]:
    """The OPW parameters as a document (the keys of moveit_opw_kinematics_plugin's kinematics.yaml, plus
    the joint names and, in robkin's words, the base and tool transforms)."""
    p = opw_from_robot(robot)
    return {
        "name": robot.name or "robot",
        "joint_names": [j.name for j in robot.joints],
        "opw_kinematics_geometric_parameters": {k: float(getattr(p, k)) for k in GEOMETRY},
        "opw_kinematics_joint_offsets": [float(o) for o in p.offsets],
        "opw_kinematics_joint_sign_corrections": [int(s) for s in p.sign_corrections],
        "convention": "q_model = sign_correction * q - offset (opw_kinematics); robot FK(q) = "
                      "base @ opw_forward(q_model) @ tool; lengths in metres, angles in radians",
        "base": p.base.tolist(),
        "tool": p.tool.tolist(),
    }
