"""MJCF placements: an element's ``pos`` and orientation as a pose, with MuJoCo's semantics.

Orientation forms: ``quat`` (w x y z, any length but zero), ``axisangle``, ``xyaxes``, ``zaxis``,
``euler`` (``<compiler eulerseq>`` and ``angle``), and a site's or geom's ``fromto`` (centre of the
segment, z from 'to' towards 'from'). One at most may be given.

Poses are twelve plain floats (``robkin.compiled.conversions.pose_rows``): a reader walks thousands of bodies,
and a (4, 4) array per body and per product cost more than the rest of the walk together.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Mapping

import numpy as np

from ...compiled.conversions import pose_rows
from ...compiled.scanners.attribute_numbers import numbers
from ...errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    from ...compiled.conversions.pose_rows import Pose  # twelve floats: the top three rows of a (4, 4) pose
    from .source import MjcfSource
else:
    Pose = tuple

__all__ = ["placement", "geom_placement", "geom_pose", "rotation_from_mjcf", "unit", "Pose", "ORIENTATIONS", "ZERO_VECTOR"]

ORIENTATIONS = ("quat", "axisangle", "xyaxes", "zaxis", "euler")
_ORIENTATION_SET = frozenset(ORIENTATIONS)
#: A direction (quaternion, axis, xyaxes, zaxis, fromto) shorter than this is no direction: MuJoCo
#: refuses such vectors too; typed directions have lengths ~1 (at least ~1e-6 with few decimals).
ZERO_VECTOR = 1e-10
_ORIGIN = (0.0, 0.0, 0.0)


def unit(v: tuple[float, ...], where: str) -> tuple[float, ...]:
    """``v`` divided by its length; InputError naming ``where`` when it is no direction."""
    n = math.hypot(*v)
    if n < ZERO_VECTOR:
        raise InputError(f"{where}: is a zero vector; a direction is needed")
    if len(v) == 3:
        return (v[0] / n, v[1] / n, v[2] / n)
    return tuple(x / n for x in v)


def _z_to(v: tuple[float, ...], pos: tuple[float, ...]) -> Pose:
    """Pose at ``pos`` turned minimally from +z onto the unit v (MuJoCo's rule; +z -> -z turns by pi about x)."""
    s = math.hypot(v[0], v[1])
    if s < ZERO_VECTOR:
        x, y, z = pos
        if v[2] > 0:
            return (1.0, 0.0, 0.0, x, 0.0, 1.0, 0.0, y, 0.0, 0.0, 1.0, z)
        return (1.0, 0.0, 0.0, x, 0.0, -1.0, 0.0, y, 0.0, 0.0, -1.0, z)
    return pose_rows.from_axis_angle(pos, (-v[1] / s, v[0] / s, 0.0), math.atan2(s, v[2]))


def placement(attrs: Mapping[str, str], src: MjcfSource, where: str) -> Pose:
    """Pose (twelve floats, see ``pose_rows``) of a body, site, geom or ``<frame>`` relative to its
    parent: ``fromto``, else ``pos`` and the one orientation given (identity when none)."""
    if attrs.get("fromto") is not None:
        return geom_placement(attrs, src, where)[0]
    return _oriented(attrs, src, where)


def _oriented(attrs: Mapping[str, str], src: MjcfSource, where: str) -> Pose:
    """Pose of ``pos`` and the one orientation given."""
    get = attrs.get
    pos = numbers(get("pos"), 3, where, "pos", _ORIGIN)
    if _ORIENTATION_SET.isdisjoint(attrs):
        x, y, z = pos
        return (1.0, 0.0, 0.0, x, 0.0, 1.0, 0.0, y, 0.0, 0.0, 1.0, z)
    given = [k for k in ORIENTATIONS if get(k) is not None]
    if not given:
        x, y, z = pos
        return (1.0, 0.0, 0.0, x, 0.0, 1.0, 0.0, y, 0.0, 0.0, 1.0, z)
    if len(given) > 1:
        raise InputError(f"{where}: has both {given[0]} and {given[1]}; give one orientation")
    kind = given[0]
    text, at = attrs[kind], f"{where}: {kind}"
    if kind == "quat":
        q = numbers(text, 4, at, None, ())
        unit(q, at)  # refuses a zero quaternion; from_quat divides by the length itself
        return pose_rows.from_quat(pos, q)
    if kind == "euler":
        a, b, c = numbers(text, 3, at, None, ())
        return pose_rows.from_euler(pos, (src.angle(a), src.angle(b), src.angle(c)), src.eulerseq)
    if kind == "axisangle":
        v = numbers(text, 4, at, None, ())
        unit(v[:3], at)
        return pose_rows.from_axis_angle(pos, v[:3], src.angle(v[3]))
    if kind == "zaxis":
        return _z_to(unit(numbers(text, 3, at, None, ()), at), pos)
    v = numbers(text, 6, at, None, ())  # xyaxes: x, and y made orthogonal to it; z = x cross y
    x = unit(v[:3], at)
    d = x[0] * v[3] + x[1] * v[4] + x[2] * v[5]
    y = unit((v[3] - x[0] * d, v[4] - x[1] * d, v[5] - x[2] * d), f"{at} (y is parallel to x)")
    z = (x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0])
    return (x[0], y[0], z[0], pos[0], x[1], y[1], z[1], pos[1], x[2], y[2], z[2], pos[2])


def geom_placement(attrs: Mapping[str, str], src: MjcfSource, where: str) -> tuple[Pose, float | None]:
    """(pose relative to the parent, length of the ``fromto`` segment or None) of a geom or site."""
    if attrs.get("fromto") is None:
        return _oriented(attrs, src, where), None
    v = numbers(attrs["fromto"], 6, where, "fromto", ())
    d = (v[0] - v[3], v[1] - v[4], v[2] - v[5])
    centre = ((v[0] + v[3]) / 2, (v[1] + v[4]) / 2, (v[2] + v[5]) / 2)
    return _z_to(unit(d, f"{where}: fromto"), centre), math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])


def geom_pose(attrs: Mapping[str, str], src: MjcfSource, where: str) -> tuple[np.ndarray, float | None]:
    """``geom_placement`` with the pose as an array (4, 4)."""
    pose, length = geom_placement(attrs, src, where)
    return pose_rows.matrix(pose), length


def rotation_from_mjcf(attrs: Mapping[str, str], src: MjcfSource, where: str) -> np.ndarray:
    """Rotation (3, 3) of an element's orientation attributes (identity when it has none)."""
    return pose_rows.matrix(_oriented({k: v for k, v in attrs.items() if k != "pos"}, src, where))[:3, :3]
