# cython: language_level=3
"""Rigid transforms as twelve plain floats, for the robot-file readers' walks along a tree.

A pose is the tuple (r00, r01, r02, x, r10, r11, r12, y, r20, r21, r22, z): the top three rows of the
(4, 4) matrix [[R, p], [0, 0, 0, 1]], row by row. A reader composes one such pose per joint of a
chain; on (4, 4) arrays each product costs a numpy call and an array, and in Python bytecode the
unpacking of 24 floats per product was still a good share of a small URDF's load. Here each
operation is one call on C doubles, with the same operations in the same order as the formulas below
(so the same bits as plain Python floats would give: the extension is built without FMA contraction).
``matrices`` turns many poses into one (m, 4, 4) array at the end.
"""

cimport numpy as cnp
from cpython.tuple cimport PyTuple_New, PyTuple_SET_ITEM, PyTuple_GET_ITEM, PyTuple_GET_SIZE
from cpython.float cimport PyFloat_FromDouble, PyFloat_AsDouble
from cpython.ref cimport Py_INCREF
from libc.math cimport sin, cos

import numpy as np

cnp.import_array()

__all__ = ["IDENTITY", "from_xyz_rpy", "from_matrix", "compose", "inverse", "matrix", "matrices"]

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
