"""Hypothesis strategies for random serial robots, reusable by any test module.

The robots are built axis by axis: each joint axis is drawn in a *chosen* relation to the previous one
(the robot base z axis for joint 1), so every case of the line geometry is exercised on purpose rather
than by luck: skew, parallel, anti-parallel, coincident, anti-coincident and intersecting. Joint types
(revolute/prismatic), ``flip`` flags, the world->base transform, the tool and the length unit
(mm, m, km) are drawn too.

Usage::

    from hypothesis import given
    from strategies import robots

    @given(robots(max_joints=6))
    def test_something(robot): ...

``robot_specs()`` gives the same robots with the recipe that built them (``RobotSpec``), for tests that
want to know which relation each axis was drawn with.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from hypothesis import strategies as st

from robkin import se3
from robkin.lines import AxisRelation
from robkin.robot import Joint, Robot

__all__ = ["RELATIONS", "TOOL_KINDS", "UNITS", "RobotSpec", "robot_specs", "robots", "unit_vectors",
           "poses", "dh_rows", "joint_lists", "angles"]

RELATIONS: tuple[str, ...] = tuple(r.value for r in AxisRelation)
#: How the tool frame relates to the last joint frame: anywhere, on the last axis (a rotation about
#: and slide along it, as for a flange), or reachable by one DH row (no residual tool needed).
TOOL_KINDS: tuple[str, ...] = ("random", "on-axis", "dh-row")
#: Length units the robot is expressed in (the same shapes in mm, m and km).
UNITS: tuple[float, ...] = (1e-3, 1.0, 1e3)

# Bounded, normal floats only: the robots are physical, and subnormals or 1e300 say nothing about
# the conversions (those are input-validation tests, elsewhere).
_coord = st.floats(-1.0, 1.0, allow_nan=False, allow_infinity=False, allow_subnormal=False)
angles = st.floats(-np.pi, np.pi, allow_nan=False, allow_infinity=False, allow_subnormal=False)
_length = st.floats(0.05, 1.0, allow_nan=False, allow_infinity=False)
_slide = st.floats(-1.0, 1.0, allow_nan=False, allow_infinity=False, allow_subnormal=False)
#: The same without the tiny nonzero values hypothesis likes (1e-9, 1e-12, ...): exactly 0, or at
#: least 1e-6 in size. Tiny offsets and angles land on the core's documented thresholds (TIE_TOL,
#: ANGLE_TOL, KEEP_TOL, LENGTH_TOL, all 1e-12..1.5e-8), where rounding noise decides a sign or a
#: relation: FK stays exact, but a table need not read back unchanged. Tests of table identity use
#: ``tiny=False``; FK tests keep the tiny values (they found real bugs there).
_clean = lambda hi: st.one_of(st.just(0.0), st.floats(1e-6 * hi, hi), st.floats(-hi, -1e-6 * hi))  # noqa: E731
_CLEAN = {"coord": _clean(1.0), "angle": _clean(np.pi), "slide": _clean(1.0)}
_TINY = {"coord": _coord, "angle": angles, "slide": _slide}
# Angle between a new, non-parallel axis and the previous one: well away from 0 and pi so that
# "skew" and "intersecting" really are those (nearly parallel axes are a conditioning question,
# covered by the rounded-input variant of the property tests), or exactly a right angle.
_tilt = st.one_of(st.just(np.pi / 2), st.floats(0.2, np.pi - 0.2))


@st.composite
def unit_vectors(draw) -> np.ndarray:
    """A unit 3-vector (the draw is rejected if its coordinates are nearly all zero)."""
    v = np.array([draw(_coord) for _ in range(3)])
    n = np.linalg.norm(v)
    if n < 0.1:
        # keep the strategy total instead of filtering: fall back to a coordinate axis
        v, n = np.eye(3)[draw(st.integers(0, 2))] * draw(st.sampled_from([-1.0, 1.0])), 1.0
    return v / n


@st.composite
def poses(draw, scale: float = 1.0, tiny: bool = True) -> np.ndarray:
    """A random rigid transform (4, 4); translation within +-scale per coordinate."""
    v = _TINY if tiny else _CLEAN
    rpy = [draw(v["angle"]) for _ in range(3)]
    p = [draw(v["coord"]) * scale for _ in range(3)]
    return se3.homogeneous(se3.matrix_from_rpy(rpy), p)


def _basis(u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors completing u to a right-handed orthonormal basis (e1, e2, u)."""
    e = np.eye(3)[int(np.argmin(np.abs(u)))]
    e1 = np.cross(u, e)
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(u, e1)


@st.composite
def _next_axis(draw, p: np.ndarray, u: np.ndarray, relation: str, unit: float, tiny: bool = True
               ) -> tuple[np.ndarray, np.ndarray]:
    """A line (point, unit direction) in the given relation to the line (p, u)."""
    v = _TINY if tiny else _CLEAN
    e1, e2 = _basis(u)
    phi = draw(v["angle"])
    radial = np.cos(phi) * e1 + np.sin(phi) * e2  # a unit direction perpendicular to u
    along = draw(v["slide"]) * unit
    if relation in ("coincident", "anti-coincident"):
        u_new = u if relation == "coincident" else -u
        return p + along * u, u_new
    if relation in ("parallel", "anti-parallel"):
        u_new = u if relation == "parallel" else -u
        return p + along * u + draw(_length) * unit * radial, u_new
    beta = draw(_tilt)
    u_new = np.cos(beta) * u + np.sin(beta) * radial
    u_new /= np.linalg.norm(u_new)
    if relation == "intersecting":
        return p + along * u, u_new
    # skew: step off line (p, u) along the common normal direction u x u_new, by a clear distance
    normal = np.cross(u, u_new)
    normal /= np.linalg.norm(normal)
    sign = draw(st.sampled_from([-1.0, 1.0]))
    return p + along * u + sign * draw(_length) * unit * normal, u_new


@dataclass(frozen=True)
class RobotSpec:
    """A drawn robot and the recipe behind it."""

    robot: Robot
    relations: tuple[str, ...]  # relation of axis i to axis i-1 (axis 0: to the robot base z axis)
    tool_kind: str
    unit: float


@st.composite
def joint_lists(draw, n: int) -> tuple[Joint, ...]:
    """n joints named joint1..jointN with random types and flip flags."""
    types = draw(st.lists(st.sampled_from(["revolute", "prismatic"]), min_size=n, max_size=n))
    flips = draw(st.lists(st.booleans(), min_size=n, max_size=n))
    return tuple(Joint(f"joint{i + 1}", t, flip=f) for i, (t, f) in enumerate(zip(types, flips)))


@st.composite
def robot_specs(draw, min_joints: int = 1, max_joints: int = 8, units: tuple[float, ...] = UNITS,
                world: bool = True, tiny: bool = True, relations: tuple[str, ...] = RELATIONS) -> RobotSpec:
    """A random robot built axis by axis with deliberately chosen axis relations (see module doc).

    ``tiny=False``: offsets and angles are exactly 0 or at least 1e-6 (see ``_CLEAN``).
    ``relations``: the axis relations to draw from (default: all of them).
    """
    v = _TINY if tiny else _CLEAN
    n = draw(st.integers(min_joints, max_joints))
    unit = draw(st.sampled_from(units))
    joints = draw(joint_lists(n))
    drawn = tuple(draw(st.sampled_from(relations)) for _ in range(n))
    p, u = np.zeros(3), np.array([0.0, 0.0, 1.0])  # the robot base z axis
    frames = np.empty((n + 1, 4, 4))
    for i, rel in enumerate(drawn):
        p, u = draw(_next_axis(p, u, rel, unit, tiny))
        e1, e2 = _basis(u)
        gamma = draw(v["angle"])
        x = np.cos(gamma) * e1 + np.sin(gamma) * e2
        # the frame origin is anywhere on the axis; p moves there so the next relation is drawn from it
        p = p + draw(v["slide"]) * unit * u
        frames[i] = se3.homogeneous(np.column_stack([x, np.cross(u, x), u]), p)
    tool_kind = draw(st.sampled_from(TOOL_KINDS))
    last = frames[n - 1]
    if tool_kind == "random":
        frames[n] = last @ draw(poses(unit, tiny))
    elif tool_kind == "on-axis":
        frames[n] = last @ se3.rot_z(draw(v["angle"])) @ se3.trans(0.0, 0.0, draw(v["slide"]) * unit)
    else:
        frames[n] = last @ se3.dh_matrix(draw(v["slide"]) * unit, draw(v["slide"]) * unit, draw(v["angle"]),
                                         draw(v["angle"]))
    world_pose = draw(poses(unit, tiny)) if world and draw(st.booleans()) else np.eye(4)
    robot = Robot(frames, joints, world=world_pose, name="drawn")
    return RobotSpec(robot, drawn, tool_kind, unit)


def robots(min_joints: int = 1, max_joints: int = 8, units: tuple[float, ...] = UNITS,
           world: bool = True, tiny: bool = True) -> st.SearchStrategy[Robot]:
    """Random robots (see ``robot_specs``)."""
    return robot_specs(min_joints, max_joints, units, world, tiny).map(lambda spec: spec.robot)


#: alpha values that make special axis cases in a DH table: parallel (0), anti-parallel (pi),
#: perpendicular (+-pi/2), and arbitrary.
_alpha = st.one_of(st.sampled_from([0.0, np.pi / 2, -np.pi / 2, np.pi]), angles)
#: a and d: often exactly 0 (intersecting / coincident axes), otherwise arbitrary.
_offset = st.one_of(st.just(0.0), _slide)


@st.composite
def dh_rows(draw, n: int, unit: float = 1.0, tiny: bool = True) -> np.ndarray:
    """A standard (or modified) DH table (n, 4) of (a, d, alpha, theta) with many special cases.

    ``tiny=False``: values are exactly 0 or at least 1e-6 in size (see ``_CLEAN``).
    """
    offset = _offset if tiny else _CLEAN["slide"]
    alpha = _alpha if tiny else st.one_of(st.sampled_from([0.0, np.pi / 2, -np.pi / 2, np.pi]), _CLEAN["angle"])
    theta = angles if tiny else _CLEAN["angle"]
    return np.array([[draw(offset) * unit, draw(offset) * unit, draw(alpha), draw(theta)] for _ in range(n)])
