"""A joint's ``<axis>`` in an SDF model: its direction in the joint frame, limits and dynamics.

The axis ``<xyz>`` is in the joint frame from SDFormat 1.5 on, in the model frame in 1.4 or with
``use_parent_model_frame``, or in the frame named by ``expressed_in``; it is turned into the joint frame
through the reader's frame graph (``frame_graph.FrameGraph``). SDF's default limits (+-1e16) and its -1 effort and
velocity mean none.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from ...compiled.scanners.attribute_numbers import numbers
from ...errors import InputError
from ..trees.model import NO_LIMIT

if TYPE_CHECKING:  # pragma: no cover
    from ...compiled.conversions.pose_rows import Pose
    from .frame_graph import FrameGraph

__all__ = ["joint_axis", "axis_dynamics"]

Z_AXIS = (0.0, 0.0, 1.0)


def _rotate(T: Pose, v: tuple[float, ...]) -> tuple[float, float, float]:
    """The rotation of pose T applied to the vector v (3,)."""
    x, y, z = v
    return (T[0] * x + T[1] * y + T[2] * z, T[4] * x + T[5] * y + T[6] * z, T[8] * x + T[9] * y + T[10] * z)


def joint_axis(j: FrameGraph, axis_el: Any, name: str, where: str
               ) -> tuple[tuple[float, float, float], float | None, float | None]:
    """(unit axis in the joint frame, lower, upper) of a joint's ``<axis>`` element (None: absent);
    ``where`` is the joint as messages name it."""
    if axis_el is None:
        raise InputError(f"{where}: no <axis>; a moving joint needs <axis><xyz>0 0 1</xyz></axis>")
    xyz_el = axis_el.find("xyz")
    text = xyz_el.text if xyz_el is not None else None
    axis = numbers((text.strip() or None) if text else None, 3, where, "axis xyz", Z_AXIS)
    n = math.sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2])
    if n < 1e-9:  # SDF axes are unit vectors typed with a few decimals; this short is a zero or a typo
        raise InputError(f"{where}: axis xyz is zero; a moving joint needs a direction such as '0 0 1'")
    axis = (axis[0] / n, axis[1] / n, axis[2] / n)
    expressed = xyz_el.get("expressed_in") if xyz_el is not None else None
    if expressed or j.version < (1, 5) or (axis_el.findtext("use_parent_model_frame") or "").strip() in ("true", "1"):
        prefix = name[: name.rfind("::") + 2] if "::" in name else ""
        frame = j.scoped(expressed, prefix) if expressed else prefix + "__model__"
        axis = _rotate(j.relative(name, frame, where), axis)  # into the joint frame
    lower = upper = None
    lim = axis_el.find("limit")
    if lim is not None:
        lower = _limit(lim.findtext("lower"), where, "limit lower")
        upper = _limit(lim.findtext("upper"), where, "limit upper")
        if lower is not None and upper is not None and lower > upper:
            raise InputError(f"{where}: limit lower {lower} > upper {upper}")
    return axis, lower, upper


def axis_dynamics(axis: Any, where: str) -> tuple[float | None, float | None, float | None, float | None]:
    """(effort, velocity, damping, friction) of a joint's ``<axis>`` element (None: absent):
    ``<limit><effort><velocity>`` (SDF's default -1, no limit, read as None) and
    ``<dynamics><damping><friction>``; None where absent."""
    out: list[float | None] = []
    if axis is None:
        return None, None, None, None
    limit, dynamics = axis.find("limit"), axis.find("dynamics")  # a find per step: a path would go through ElementPath
    for sub, group, tag in ((limit, "limit", "effort"), (limit, "limit", "velocity"), (dynamics, "dynamics", "damping"),
                            (dynamics, "dynamics", "friction")):
        text = None if sub is None else sub.findtext(tag)
        v = None if text is None or not text.strip() else numbers(text.strip(), 1, where, f"axis/{group}/{tag}", ())[0]
        out.append(None if v is None or (v < 0 and group == "limit") else v)
    return out[0], out[1], out[2], out[3]


def _limit(text: str | None, where: str, what: str) -> float | None:
    if text is None or not text.strip():
        return None
    v = numbers(text.strip(), 1, where, what, ())[0]
    return v if abs(v) < NO_LIMIT else None  # SDF's default limits are +-1e16: no limit
