# cython: language_level=3
"""Which of many 4x4 matrices are exact rigid transforms (``rigid.pxd``'s ``exact_pose``), in one call.

A Robot checks its n + 2 poses (frames and world) at construction and IK checks its targets; in numpy
the same test took ~8 array calls (~20 us for a 6-joint robot), here ~1 us.

``frame_stacks``: the two quantities every Robot derives from its frames (``robkin.frame_stacks``: its
size and the FK's fixed transforms), here because a Robot needs them without loading the kinematics.
"""

cimport numpy as cnp
from robkin.compiled.runtime.numpy_order cimport frames_scale, frames_local

import numpy as np

cnp.import_array()


def exact_poses(A):
    """(N,) bool: which poses A (N, 4, 4) are finite, have the last row exactly [0, 0, 0, 1] and a
    rotation block orthonormal to 1e-12 with det > 0 (``exact_pose``).

    Parameters
    ----------
    A : (N, 4, 4) array_like of float
        Poses; read only.
    """
    cdef cnp.ndarray Aa = np.ascontiguousarray(A, dtype=np.float64)
    if cnp.PyArray_NDIM(Aa) != 3 or cnp.PyArray_DIM(Aa, 1) != 4 or cnp.PyArray_DIM(Aa, 2) != 4:
        raise ValueError(f"poses: expected shape (N, 4, 4), got {np.shape(Aa)}")
    cdef Py_ssize_t N = cnp.PyArray_DIM(Aa, 0), k
    cdef const double* T0 = <const double*>cnp.PyArray_DATA(Aa)
    cdef cnp.npy_intp dims[1]
    dims[0] = N
    cdef cnp.ndarray ok_arr = cnp.PyArray_ZEROS(1, dims, cnp.NPY_BOOL, 0)
    cdef unsigned char* ok = <unsigned char*>cnp.PyArray_DATA(ok_arr)
    with nogil:
        for k in range(N):
            ok[k] = exact_pose(T0 + 16 * k)
    return ok_arr


def frame_stacks(frames, bint want_scale, bint want_local):
    """``Robot.scale`` (B,) and the fixed transforms L (B, n + 1, 4, 4) of B robots' GJD frames
    (B, n + 1, 4, 4) (``robkin.frame_stacks``, which documents them); None for what is not wanted."""
    cdef cnp.ndarray Fa = np.ascontiguousarray(frames, dtype=np.float64)
    if Fa.ndim != 4 or Fa.shape[1] < 2 or Fa.shape[2] != 4 or Fa.shape[3] != 4:
        raise ValueError("expected frames (B, n + 1, 4, 4)")
    cdef Py_ssize_t B = Fa.shape[0], n = Fa.shape[1] - 1, k
    scale = np.empty(B) if want_scale else None
    local = np.empty((B, n + 1, 4, 4)) if want_local else None
    cdef double* f = <double*>cnp.PyArray_DATA(Fa)
    cdef double* s = <double*>cnp.PyArray_DATA(<cnp.ndarray>scale) if want_scale else NULL
    cdef double* l = <double*>cnp.PyArray_DATA(<cnp.ndarray>local) if want_local else NULL
    with nogil:
        for k in range(B):
            if want_scale:
                s[k] = frames_scale(f + 16 * (n + 1) * k, n)
            if want_local:
                frames_local(f + 16 * (n + 1) * k, n, l + 16 * (n + 1) * k)
    return scale, local
