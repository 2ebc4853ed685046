"""The readers' twelve-float poses (``robkin.compiled.conversions.pose_rows``) against independent computations.

Oracles: scipy's ``Rotation.from_euler`` for URDF's roll-pitch-yaw (extrinsic x, y, z), numpy's matrix
products and ``np.linalg.inv`` for composition and inversion; and the lazily made arrays of a parsed
URDF joint against pinocchio's placement of the same joint.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from robkin.errors import InputError
from robkin.compiled.conversions import pose_rows
from robkin.io.urdf import UrdfJoint, parse_urdf_text

from strategies import poses

angles = st.floats(-2 * math.pi, 2 * math.pi, allow_nan=False)
lengths = st.floats(-10.0, 10.0, allow_nan=False)


@settings(max_examples=60, deadline=None)
@given(st.tuples(lengths, lengths, lengths), st.tuples(angles, angles, angles))
def test_from_xyz_rpy_matches_scipy_extrinsic_xyz(xyz, rpy):
    T = pose_rows.matrix(pose_rows.from_xyz_rpy(xyz, rpy))
    # URDF: R = Rz(yaw) Ry(pitch) Rx(roll), i.e. extrinsic rotations about x, then y, then z
    assert np.allclose(T[:3, :3], Rotation.from_euler("xyz", rpy).as_matrix(), atol=1e-14)
    assert np.array_equal(T[:3, 3], xyz) and np.array_equal(T[3], [0, 0, 0, 1])


@settings(max_examples=60, deadline=None)
@given(poses(), poses())
def test_compose_and_inverse_match_numpy(A, B):
    a, b = pose_rows.from_matrix(A), pose_rows.from_matrix(B)
    assert np.allclose(pose_rows.matrix(pose_rows.compose(a, b)), A @ B, atol=1e-12)
    assert np.allclose(pose_rows.matrix(pose_rows.inverse(a)), np.linalg.inv(A), atol=1e-12)
    assert np.allclose(pose_rows.matrices([a, b]), np.stack([A, B]), atol=0)


def test_zero_rpy_is_exact_and_identity_composes_exactly():
    p = pose_rows.from_xyz_rpy((0.1, -0.2, 0.3), (0.0, -0.0, 0.0))
    assert p == (1.0, 0.0, 0.0, 0.1, 0.0, 1.0, 0.0, -0.2, 0.0, 0.0, 1.0, 0.3)
    assert pose_rows.compose(pose_rows.IDENTITY, p) == p


URDF = """<robot name="r">
  <link name="a"/><link name="b"/><link name="c"/>
  <joint name="j1" type="revolute"><parent link="a"/><child link="b"/>
    <origin xyz="0.1 0.2 0.3" rpy="0.4 -0.5 0.6"/><axis xyz="0 0 2"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="j2" type="fixed"><parent link="b"/><child link="c"/></joint>
</robot>"""


def test_parsed_joint_arrays_are_made_on_first_use_and_match_pinocchio():
    pin = pytest.importorskip("pinocchio")
    j1, j2 = parse_urdf_text(URDF).joints
    assert j1._origin is None and not isinstance(j1._axis, np.ndarray)  # nothing made while parsing
    assert j1.xyz_rpy == (0.1, 0.2, 0.3, 0.4, -0.5, 0.6)
    assert j1.axis_xyz() == (0.0, 0.0, 2.0) and np.array_equal(j1.axis, [0.0, 0.0, 2.0])
    model = pin.buildModelFromXML(URDF)
    assert np.allclose(j1.origin, model.jointPlacements[model.getJointId("j1")].homogeneous, atol=1e-15)
    assert j1.origin is j1.origin  # made once
    assert np.array_equal(j2.origin, np.eye(4))


def test_joint_built_from_arrays_keeps_them():
    origin, axis = np.eye(4), np.array([0.0, 1.0, 0.0])
    j = UrdfJoint("j", "revolute", "a", "b", origin, axis, None, None)
    assert j.origin is origin and j.axis is axis and j.axis_xyz() == (0.0, 1.0, 0.0)
    assert j.pose() == pose_rows.IDENTITY
    with pytest.raises(TypeError):
        UrdfJoint("j", "revolute", "a", "b", None, axis, None, None)


@pytest.mark.parametrize("text, message", [
    ("1 2", "'1 2' has 2 numbers; expected 3 numbers"),
    ("1 x 2", "'1 x 2' is not 3 numbers"),
    ("1e200 nan 0", "'1e200 nan 0' has a number beyond +-1e+100"),  # the first bad number is named
    ("nan 1e200 0", "'nan 1e200 0' contains NaN or infinity"),
    ("0 0 inf", "'0 0 inf' contains NaN or infinity"),
])
def test_bad_origin_numbers_name_the_joint_and_attribute(text, message):
    bad = URDF.replace('xyz="0.1 0.2 0.3"', f'xyz="{text}"')
    with pytest.raises(InputError, match=r"^t\.urdf: joint 'j1': origin xyz: ") as err:
        parse_urdf_text(bad, "t.urdf")
    assert message in str(err.value)
