"""robkin.bodies: body motions and shape poses agree with forward kinematics and survive frame changes."""

from __future__ import annotations

import numpy as np

import robkin
from robkin import se3
from robkin.bodies import Bodies, Geometry, Shape, body_motions, shape_poses


def _robot():
    return robkin.load(robkin.__path__[0] + "/examples/rrpr.yaml")


def test_last_body_carries_the_tool_and_every_frame():
    robot = _robot()
    Q = robot.random_q(20, rng=1)
    M = body_motions(robot, Q)
    assert M.shape == (20, robot.n + 1, 4, 4)
    np.testing.assert_allclose(M[:, 0], np.broadcast_to(np.eye(4), (20, 4, 4)), atol=0)
    # the tool sits on the last body: motion_n @ tool(0) = fk(q)
    np.testing.assert_allclose(M[:, -1] @ robot.tool, robot.fk(Q), atol=1e-12)
    # joint frame i sits on body i (it turns about its own z): motion_i @ J_i(0) = J_i(q)
    np.testing.assert_allclose(M[:, 1:] @ robot.frames[:-1], robot.frames_at(Q)[:, :-1], atol=1e-12)


def test_shape_poses_do_not_depend_on_the_choice_of_gjd_frames():
    robot = _robot()
    shapes = tuple(Shape("l", b, "visual", se3.homogeneous(se3.matrix_from_rpy([0.1 * b, 0.2, 0.3]), [b, 1, 2]),
                         Geometry("box", (1, 1, 1))) for b in range(robot.n + 1))
    a = robot.replace(bodies=Bodies(shapes=shapes))
    # the same robot with other GJD frames: each origin slid along its axis and x turned about it
    rng = np.random.default_rng(2)
    moved = np.array([F @ se3.homogeneous(se3.matrix_from_rpy([0, 0, rng.uniform(-3, 3)]), [0, 0, rng.uniform(-1, 1)])
                      for F in robot.frames[:-1]] + [robot.tool])
    b = robot.replace(frames=moved, bodies=a.bodies)
    np.testing.assert_allclose(b.fk(robot.random_q(5, rng=4)), robot.fk(robot.random_q(5, rng=4)), atol=1e-12)
    q = robot.random_q(rng=3)
    np.testing.assert_allclose(shape_poses(a, q), shape_poses(b, q), atol=1e-12)
    assert shape_poses(robot, q).shape == (0, 4, 4)


def test_empty_bodies_by_default():
    assert not _robot().bodies


def test_shapes_without_link_names_are_written_on_their_body(tmp_path):
    from robkin.bodies import Inertial
    from robkin.io.urdf import robot_from_urdf, urdf_from_robot

    robot = _robot()
    shapes = tuple(Shape(f"b{b}", b, "visual", se3.homogeneous(se3.matrix_from_rpy([0.3, -0.2, 0.1 * b]), [b, 0.5, 0.1]),
                         Geometry("cylinder", (0.05, 0.3)), name=f"s{b}") for b in range(robot.n + 1))
    inertial = Inertial("b2", 2, se3.trans(0.1, 0.2, 0.3), 2.5, np.diag([0.1, 0.2, 0.3]))
    a = robot.replace(bodies=Bodies(shapes=shapes, inertials=(inertial,)))
    back = robot_from_urdf(urdf_from_robot(a))
    q = robot.random_q(4, rng=5)
    np.testing.assert_allclose(back.fk(q), a.fk(q), atol=1e-12)
    assert [s.name for s in back.bodies.shapes] == [s.name for s in shapes]
    np.testing.assert_allclose(shape_poses(back, q), shape_poses(a, q), atol=1e-12)
    (m,) = back.bodies.inertials
    assert m.body == 2 and m.mass == 2.5
    np.testing.assert_allclose(body_motions(back, q)[:, 2] @ m.pose, body_motions(a, q)[:, 2] @ inertial.pose,
                               atol=1e-12)
    np.testing.assert_array_equal(m.inertia, inertial.inertia)


def test_a_robot_read_from_a_urdf_pickles_and_copies():
    import copy
    import pickle

    from test_urdf import robot_file
    from robkin.io.urdf import robot_from_urdf

    robot = robot_from_urdf(robot_file("panda_description/urdf/panda.urdf"), tip_link="panda_hand_tcp")
    for again in (pickle.loads(pickle.dumps(robot)), copy.deepcopy(robot)):
        assert [s.geometry for s in again.bodies.shapes] == [s.geometry for s in robot.bodies.shapes]
        assert [k.name for k in again.bodies.links] == [k.name for k in robot.bodies.links]
        q = robot.random_q(rng=1)
        np.testing.assert_array_equal(shape_poses(again, q), shape_poses(robot, q))
