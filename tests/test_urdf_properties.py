"""Property tests of URDF output: any robot, with shapes on any body, survives URDF -> robkin exactly.

Random robots (``strategies.robots``: 1-8 joints, every axis relation, flips, mm/m/km, a world pose)
carry random shapes on random bodies. Written as URDF and read back: the same joints (names, types,
limits, flips), FK and world -> base to rounding, and every shape at the same pose at random q. Then
written again from what was read (now with the file's link names): the second file repeats the first.
"""

from __future__ import annotations

import warnings

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from robkin.bodies import Bodies, Geometry, Shape, shape_poses
from robkin.errors import ProjectionWarning
from robkin.io.urdf import robot_from_urdf, urdf_from_robot

from strategies import poses, robots

#: relative to robot size: a URDF stores each joint as an rpy + xyz origin, whose round trip costs a
#: few float64 roundings per joint (~1e-16 each), compounded along at most 8 joints and 1e3 units.
REL_TOL = 1e-11


@st.composite
def robots_with_shapes(draw):
    robot = draw(robots())
    k = draw(st.integers(0, 4))
    shapes = tuple(Shape(f"s{i}", draw(st.integers(0, robot.n)), draw(st.sampled_from(["visual", "collision"])),
                         draw(poses(robot.scale, tiny=False)), Geometry("box", (0.1, 0.2, 0.3)), name=f"s{i}")
                   for i in range(k))
    return robot.replace(bodies=Bodies(shapes=shapes))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(robots_with_shapes(), st.integers(0, 2**32 - 1))
def test_urdf_round_trip_of_any_robot_with_shapes(robot, seed):
    text = urdf_from_robot(robot)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ProjectionWarning)
        back = robot_from_urdf(text)
    assert [(j.name, j.type, j.lower, j.upper, j.flip) for j in back.joints] == \
        [(j.name, j.type, j.lower, j.upper, j.flip) for j in robot.joints]
    scale = max(robot.scale, 1.0)
    Q = robot.random_q(5, rng=seed)
    assert np.abs(back.fk(Q) - robot.fk(Q)).max() <= REL_TOL * scale
    assert np.abs(back.world - robot.world).max() <= REL_TOL * max(scale, np.abs(robot.world[:3, 3]).max())
    assert sorted(s.name for s in back.bodies.shapes) == sorted(s.name for s in robot.bodies.shapes)
    order = {s.name: i for i, s in enumerate(back.bodies.shapes)}
    mine = shape_poses(robot, Q)
    theirs = shape_poses(back, Q)[:, [order[s.name] for s in robot.bodies.shapes]]
    assert np.abs(theirs - mine).max(initial=0) <= REL_TOL * scale
    # written again from the file's own links: the same file
    assert urdf_from_robot(back) == urdf_from_robot(robot_from_urdf(urdf_from_robot(back)))
