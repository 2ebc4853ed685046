"""MJCF joint equalities as mimic joints: ``<equality><joint joint1 joint2 polycoef>`` with a linear
polynomial is URDF's ``<mimic>`` (joint1 = multiplier * joint2 + offset).

MuJoCo's rule is y - y0 = a0 + a1 (x - x0) + a2 (x - x0)^2 + ... for y = qpos of joint1 and x = qpos of
joint2, y0 and x0 their ``ref`` (qpos0). robkin's q of an MJCF joint is its qpos, so the mimic is
multiplier a1 and offset y0 + a0 - a1 x0. Equalities with higher-order terms or switched off
(``active="false"``) are not mimics and are left out. One without ``joint2`` holds joint1 at
qpos y0 + a0: :func:`joint_locks` reads it as equal lower and upper limits (``robkin.io.trees.joint_limits``),
the form robkin's MJCF writer gives a locked joint.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Mapping

from ...compiled.scanners.attribute_numbers import numbers

if TYPE_CHECKING:  # pragma: no cover
    from ...body_parts import Mimic
    from .source import MjcfSource

__all__ = ["joint_mimics", "joint_locks"]

#: MuJoCo's default polycoef: joint1 = joint2
_POLYCOEF = (0.0, 1.0, 0.0, 0.0, 0.0)


def joint_mimics(src: MjcfSource, refs: Mapping[str, float]) -> dict[str, Mimic]:
    """joint1 name -> its Mimic, for every linear joint equality of the model (``refs``: joint name ->
    ref in qpos units, 0 where absent)."""
    from ...body_parts import Mimic

    out: dict[str, Mimic] = {}
    for eq in src.root.findall("equality"):
        for el in eq.findall("joint"):
            j1, j2 = el.get("joint1"), el.get("joint2")
            if not j1 or not j2 or el.get("active", "true") == "false":
                continue
            where = f"{src.source}: equality joint '{j1}'"
            a = numbers(el.get("polycoef"), 5, f"{where}: polycoef", None, _POLYCOEF)
            if any(a[2:]):
                continue
            y0, x0 = refs.get(j1, 0.0), refs.get(j2, 0.0)
            out[j1] = Mimic(j2, a[1], y0 + a[0] - a[1] * x0)
    return out


def joint_locks(src: MjcfSource, refs: Mapping[str, float]) -> dict[str, float]:
    """joint1 name -> the qpos it is held at, for every active joint equality without ``joint2`` whose
    polynomial is a constant (MuJoCo: y - y0 = a0, so qpos = y0 + a0)."""
    out: dict[str, float] = {}
    for eq in src.root.findall("equality"):
        for el in eq.findall("joint"):
            j1 = el.get("joint1")
            if not j1 or el.get("joint2") or el.get("active", "true") == "false":
                continue
            a = numbers(el.get("polycoef"), 5, f"{src.source}: equality joint '{j1}': polycoef", None, _POLYCOEF)
            out[j1] = refs.get(j1, 0.0) + a[0]  # MuJoCo uses only a0 when there is no joint2
    return out
