# cython: language_level=3
"""Rigid transforms as twelve plain floats, for the robot-file readers' walks along a tree.

A pose is the tuple (r00, r01, r02, x, r10, r11, r12, y, r20, r21, r22, z): the top three rows of the
(4, 4) matrix [[R, p], [0, 0, 0, 1]], row by row. A reader composes one such pose per joint of a
chain; on (4, 4) arrays each product costs a numpy call and an array, and in Python bytecode the
unpacking of 24 floats per product was still a good share of a small URDF's load. Here each
operation is one call on C doubles, with the same operations in the same order as the formulas below
(so the same bits as plain Python floats would give: the extension is built without FMA contraction).
``matrices`` turns many poses into one (m, 4, 4) array at the end. ``from_quat``, ``from_axis_angle``
and ``from_euler`` make the orientations of MJCF and SDF elements (their callers check the directions
are not zero and say which attribute was; here a zero direction gives NaNs).
"""

cimport numpy as cnp
from cpython.tuple cimport PyTuple_New, PyTuple_SET_ITEM, PyTuple_GET_ITEM, PyTuple_GET_SIZE
from cpython.float cimport PyFloat_FromDouble, PyFloat_AsDouble
from cpython.ref cimport Py_INCREF
from libc.math cimport sin, cos, sqrt

from robkin.compiled.runtime.linalg cimport mat3_mul, rodrigues

import numpy as np

cnp.import_array()

__all__ = ["IDENTITY", "from_xyz_rpy", "from_quat", "from_axis_angle", "from_euler", "from_matrix", "compose",
           "inverse", "matrix", "matrices"]

#: (r00, r01, r02, x, r10, r11, r12, y, r20, r21, r22, z) of the identity
IDENTITY = (1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0)


cdef int _read(object pose, double* out) except -1:
    """The twelve numbers of a pose (a tuple, or any sequence of 12 numbers) into out."""
    cdef Py_ssize_t i
    if type(pose) is tuple and PyTuple_GET_SIZE(pose) == 12:
        for i in range(12):
            out[i] = PyFloat_AsDouble(<object>PyTuple_GET_ITEM(pose, i))
        return 0
    values = tuple(pose)
    if len(values) != 12:
        raise ValueError(f"a pose has 12 numbers, got {len(values)}")
    for i in range(12):
        out[i] = PyFloat_AsDouble(values[i])
    return 0


cdef tuple _tuple(const double* v):
    cdef tuple out = PyTuple_New(12)
    cdef Py_ssize_t i
    cdef object f
    for i in range(12):
        f = PyFloat_FromDouble(v[i])
        Py_INCREF(f)
        PyTuple_SET_ITEM(out, i, f)
    return out


def from_xyz_rpy(xyz, rpy):
    """A URDF origin: translation xyz (3,), rotation Rz(yaw) Ry(pitch) Rx(roll) for rpy (3,) in rad."""
    cdef double x, y, z, roll, pitch, yaw, cr, sr, cp, sp, cy, sy
    cdef double v[12]
    x, y, z = xyz
    roll, pitch, yaw = rpy
    if roll == 0 and pitch == 0 and yaw == 0:
        v[:] = [1.0, 0.0, 0.0, x, 0.0, 1.0, 0.0, y, 0.0, 0.0, 1.0, z]
        return _tuple(v)
    cr, sr = cos(roll), sin(roll)
    cp, sp = cos(pitch), sin(pitch)
    cy, sy = cos(yaw), sin(yaw)
    v[:] = [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr, x,
            sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr, y,
            -sp, cp * sr, cp * cr, z]
    return _tuple(v)


cdef tuple _placed(const double* R, pos):
    """The pose of rotation R (3x3 row-major) and translation pos (3,)."""
    cdef double v[12]
    cdef int i
    x, y, z = pos
    for i in range(3):
        v[4 * i] = R[3 * i]
        v[4 * i + 1] = R[3 * i + 1]
        v[4 * i + 2] = R[3 * i + 2]
    v[3], v[7], v[11] = x, y, z
    return _tuple(v)


def from_quat(pos, quat):
    """Translation pos (3,), rotation of the quaternion quat (4,) = (w, x, y, z) (MuJoCo's order)
    divided by its length first."""
    cdef double w, x, y, z, n
    cdef double R[9]
    w, x, y, z = quat
    n = sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    R[:] = [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
            2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
            2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]
    return _placed(R, pos)


def from_axis_angle(pos, axis, double angle):
    """Translation pos (3,), rotation by ``angle`` (rad) about axis (3,) divided by its length first."""
    cdef double a[3]
    cdef double R[9]
    cdef double n
    a[0], a[1], a[2] = axis
    n = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])
    a[0] /= n
    a[1] /= n
    a[2] /= n
    rodrigues(a, angle, R)
    return _placed(R, pos)


def from_euler(pos, angles, str seq):
    """Translation pos (3,), rotation of three angles (rad) about the axes named by ``seq``, three of
    x y z X Y Z: a lower-case letter turns about the rotated axis (R = R step), an upper-case one
    about the fixed axis (R = step R) (MuJoCo's ``eulerseq``; the caller checks the letters)."""
    cdef double R[9]
    cdef double step[9]
    cdef double tmp[9]
    cdef int k, i, u, v, w
    cdef double angle, c, s
    R[:] = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
    values = tuple(angles)
    for k in range(3):
        letter = seq[k]
        angle = values[k]
        c, s = cos(angle), sin(angle)
        # the rotation about coordinate axis u, its entries exactly 1, 0, +-c, +-s (orthonormal to the
        # rounding of c and s: a chain of a thousand such frames stays rigid to ~1e-13)
        u = "xyz".index(letter.lower())
        v, w = (u + 1) % 3, (u + 2) % 3
        step[:] = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
        step[3 * u + u] = 1.0
        step[3 * v + v] = c
        step[3 * w + w] = c
        step[3 * v + w] = -s
        step[3 * w + v] = s
        if letter.islower():
            mat3_mul(R, step, tmp)
        else:
            mat3_mul(step, R, tmp)
        for i in range(9):
            R[i] = tmp[i]
    return _placed(R, pos)


def from_matrix(T):
    """The pose of a (4, 4) rigid transform (its last row is not read)."""
    return tuple(np.asarray(T, dtype=float)[:3].ravel().tolist())


def compose(A, B):
    """A B: the pose B given in frame A."""
    cdef double a[12]
    cdef double b[12]
    cdef double v[12]
    cdef int i, j
    _read(A, a)
    _read(B, b)
    for i in range(3):
        for j in range(3):
            v[4 * i + j] = a[4 * i] * b[j] + a[4 * i + 1] * b[4 + j] + a[4 * i + 2] * b[8 + j]
        v[4 * i + 3] = a[4 * i] * b[3] + a[4 * i + 1] * b[7] + a[4 * i + 2] * b[11] + a[4 * i + 3]
    return _tuple(v)


def inverse(A):
    """A^-1 of a rigid transform: (R^T, -R^T p)."""
    cdef double a[12]
    cdef double v[12]
    cdef int i
    _read(A, a)
    for i in range(3):
        v[4 * i] = a[i]
        v[4 * i + 1] = a[4 + i]
        v[4 * i + 2] = a[8 + i]
        v[4 * i + 3] = -(a[i] * a[3] + a[4 + i] * a[7] + a[8 + i] * a[11])
    return _tuple(v)


def matrices(poses):
    """The poses as one array (m, 4, 4)."""
    cdef list items = list(poses)
    cdef Py_ssize_t m = len(items), k
    cdef cnp.ndarray out = np.empty((m, 4, 4))
    cdef double* o = <double*>cnp.PyArray_DATA(out)
    for k in range(m):
        _read(items[k], o + 16 * k)   # rows 0-2 land in entries 0-11 of the 4x4 block
        o[16 * k + 12] = 0.0
        o[16 * k + 13] = 0.0
        o[16 * k + 14] = 0.0
        o[16 * k + 15] = 1.0
    return out


def matrix(pose):
    """The pose as an array (4, 4)."""
    return matrices((pose,))[0]
